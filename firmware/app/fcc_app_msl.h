/*
 * fcc_app_msl.h -- the missile autopilot application (firmware/lqg/fcc_lqg.h):
 * the sampled-data LQG of fcc_lqg.h on the gyro and accelerometer frames,
 * its command through the N-bit D/A converter into MSL_ELEV_CMD.
 *
 * Per step k (period T):
 *   1. switch in a new design if one is ready (see below);
 *   2. judge the gyro and the accelerometer (fcc_sensor.h);
 *   3. both usable: x^ = xbar + L (y - H xbar); otherwise a prediction-only
 *      step x^ = xbar (degraded) -- a steady-state gain for two outputs
 *      cannot be applied to one;
 *   4. u = sat(-K x^) -> D/A code, u_applied = code LSB;
 *   5. xbar+ = Phi x^ + Gamma u_applied (the command actually applied).
 *
 * Run-time redesign (SIM_CONTROL: new T and/or N) is double-buffered: a
 * request is checked at once (fcc_app_msl_request), computed later into the
 * spare slot by fcc_app_msl_background() -- off the control path -- and
 * switched in atomically at the start of the next step.  The estimate xbar
 * carries over (it is a physical state); only the gains, Phi, Gamma and the
 * converter change.  A design that fails keeps the old one.
 */
#ifndef FCC_APP_MSL_H
#define FCC_APP_MSL_H

#include <stdbool.h>
#include <stdint.h>

#include "fcc_app.h"
#include "fcc_bus.h"
#include "fcc_lqg.h"
#include "fcc_sensor.h"
#include "fcc_types.h"

/* Sampling periods accepted at run time (s): the paper's study range and the
 * DBC range of SIM_CONTROL.lqg_period. */
#define FCC_APP_MSL_T_MIN FCC_R(0.02)
#define FCC_APP_MSL_T_MAX FCC_R(0.3)
#define FCC_APP_MSL_DEFAULT_T FCC_R(0.05)
#define FCC_APP_MSL_DEFAULT_BITS 8u
/* `--lqg-delay auto` in realtime: the command of the sample at t_k acts at the
 * actuation instant t_k + 5 ms of the time-triggered schedule (README.md,
 * "Real time"); in lockstep auto is 0 (the command acts at the sample). */
#define FCC_APP_MSL_RT_DELAY FCC_R(0.005)
/* Realtime, synchronised: a step is released at the latest this long after its sampling
 * instant (its command must leave before the actuation instant, fcc_node.h). */
#define FCC_APP_MSL_RT_WINDOW_US 3500u

typedef enum {
    FCC_APP_MSL_IN_GYRO = 0,
    FCC_APP_MSL_IN_ACCEL = 1,
    FCC_APP_MSL_N_INPUTS = 2
} fcc_app_msl_input_t;

typedef struct {
    fcc_lqg_plant_t plant;   /* the paper's missile, weights and noise by default */
    fcc_lqg_solver_t solver; /* which Riccati solution is used (both are checked) */
    fcc_real_t period;       /* T, s */
    uint8_t bits;            /* N */
    fcc_real_t delay;        /* known input delay d the LQG is designed for, 0 <= d < T */
} fcc_app_msl_config_t;

/* One half of the double buffer. */
typedef struct {
    fcc_real_t period;
    uint8_t bits;
    fcc_lqg_design_t design;
} fcc_app_msl_slot_t;

typedef enum {
    FCC_APP_MSL_SPARE_FREE = 0,  /* nothing requested */
    FCC_APP_MSL_SPARE_WANTED,    /* request accepted, design not computed yet */
    FCC_APP_MSL_SPARE_READY      /* design computed, switched in at the next step */
} fcc_app_msl_spare_t;

typedef struct {
    uint32_t k;
    fcc_lqg_output_t out;   /* estimate, command, D/A code */
    uint8_t bits;           /* N of the code */
    fcc_real_t period;      /* T of this step */
    fcc_sensor_state_t input_state[FCC_APP_MSL_N_INPUTS];
    bool measured;          /* the measurement update ran */
    bool degraded;
    bool switched;          /* a new design was switched in at this step */
    fcc_status_t status;
    uint64_t newest_rx_us;  /* receive stamp of the newest sample used (0: none) */
} fcc_app_msl_result_t;

typedef struct {
    fcc_app_msl_config_t cfg;
    fcc_app_msl_slot_t slot[2];
    uint8_t active;                 /* slot in use */
    fcc_app_msl_spare_t spare;      /* state of the other slot */
    fcc_real_t want_period;         /* request waiting for the spare slot */
    uint8_t want_bits;
    fcc_lqg_ws_t ws;                /* design scratch */
    fcc_lqg_ctrl_t ctrl;
    fcc_sensor_t in[FCC_APP_MSL_N_INPUTS];
    fcc_app_msl_result_t last;
    uint32_t steps;
    uint32_t degraded_steps;
    uint32_t designs_applied;       /* run-time designs switched in */
    uint32_t designs_failed;        /* run-time designs that failed (old one kept) */
    fcc_status_t last_design_status;
    bool designing;                 /* the wanted design is under way in ws (sliced) */
} fcc_app_msl_t;

/* The paper's plant, T = 0.05 s, 8 bits, Hamiltonian solver. */
fcc_status_t fcc_app_msl_config_default(fcc_app_msl_config_t *cfg);

/* True for 0.02 <= T <= 0.3 and 2 <= bits <= 16 (the delay is checked
 * against T by the design: 0 <= d < T). */
bool fcc_app_msl_valid(fcc_real_t period, uint8_t bits);

/* Designs the initial LQG (blocking: this is start-up) and starts the
 * estimator from zero.  FCC_ERR_RANGE for T or bits out of range, else the
 * design's status. */
fcc_status_t fcc_app_msl_init(fcc_app_msl_t *app, const fcc_app_msl_config_t *cfg);

/* Estimator from zero, sensors cleared; the design in use is kept. */
fcc_status_t fcc_app_msl_reset(fcc_app_msl_t *app);

/* Request a new design: period 0 / bits 0 keep the value of the newest
 * request (or of the design in use).  FCC_ERR_RANGE when the result is out of
 * range (nothing changes).  A newer request replaces one not switched in yet. */
fcc_status_t fcc_app_msl_request(fcc_app_msl_t *app, fcc_real_t period, uint8_t bits);

/* Compute a wanted design into the spare slot, one slice per call (the
 * design is sliced so that a realtime loop can run it between control steps:
 * FCC_LQG_DESIGN_SLICES calls, each bounded; bench pil measures them).
 * FCC_ERR_AGAIN when there was nothing to do, FCC_OK after a slice of work
 * (the design is ready, and switched in at the next step, once
 * fcc_app_msl_wants_design() is false), the design's error when it failed
 * (the request is dropped, the old design stays).  A newer request restarts
 * the design. */
fcc_status_t fcc_app_msl_background(fcc_app_msl_t *app);

/* True while a request is waiting for (more) fcc_app_msl_background(). */
bool fcc_app_msl_wants_design(const fcc_app_msl_t *app);

/* The design in use: period (s) and bits. */
fcc_real_t fcc_app_msl_period(const fcc_app_msl_t *app);
uint8_t fcc_app_msl_bits(const fcc_app_msl_t *app);

/* The sensor slot fed by message msg (MSL_RATE_GYRO, MSL_ACCELEROMETER), or NULL. */
fcc_sensor_t *fcc_app_msl_sensor(fcc_app_msl_t *app, fcc_msg_t msg);

/* Offer a decoded good frame of one of its sensors. */
fcc_status_t fcc_app_msl_offer(fcc_app_msl_t *app, fcc_msg_t msg, const fcc_msg_data_t *data,
                               uint64_t t_us);

/* Step k (see the file comment).  Returns res->status (FCC_OK unless the
 * controller refused its input, in which case a prediction step ran). */
fcc_status_t fcc_app_msl_step(fcc_app_msl_t *app, uint32_t k, bool check_step,
                              uint16_t stale_limit, fcc_app_msl_result_t *res);

/* MSL_ELEV_CMD (E2E-protected, strict: a code out of range is refused, never
 * clamped) then MSL_STATE_EST (clamped to the DBC range).  *n_frames gets
 * how many were encoded; returns the first refusal. */
fcc_status_t fcc_app_msl_encode(const fcc_app_msl_result_t *res, fcc_bus_t *bus,
                                fcc_can_frame_t frames[2], uint32_t *n_frames);

/* The application to the node (fcc_app.h): its config is an fcc_app_msl_config_t. */
extern const fcc_app_ops_t fcc_app_msl_ops;

#endif /* FCC_APP_MSL_H */
