/*
 * fcc_app_sid.h -- the identification application (firmware/sid/README.md):
 * MLS-KF, MLS-ZKF and MLS-AZKF side by side on the CDRW's sensor frames, at
 * 50 Hz.
 *
 * The maths is fcc_sid.h's; this module only decides what each loop gets:
 *  - the sensors alpha, q (measurements) and de (the input) are judged per
 *    step by fcc_sensor.h;
 *  - the step is a normal predict-correct step when all three are usable
 *    (OK or HELD), otherwise a prediction with measurement_valid = false, so
 *    the filters coast on their model and the MLS learns nothing from it;
 *    de is then the last good value (0 before any);
 *  - the three loops get the same sample and the same oracle fault flag.
 * The outputs of a step are in fcc_app_sid_result_t; fcc_app_sid_encode()
 * turns them into the 12 DBC frames (AZKF, ZKF, KF; STATE, BOUNDS, MODEL_A,
 * MODEL_B each).
 */
#ifndef FCC_APP_SID_H
#define FCC_APP_SID_H

#include <stdbool.h>
#include <stdint.h>

#include "fcc_app.h"
#include "fcc_bus.h"
#include "fcc_sensor.h"
#include "fcc_sid.h"
#include "fcc_types.h"

#define FCC_APP_SID_PERIOD_US 20000u
#define FCC_APP_SID_N_FILTERS 3u
#define FCC_APP_SID_N_FRAMES 12u

typedef enum {
    FCC_APP_SID_IN_ALPHA = 0,
    FCC_APP_SID_IN_Q = 1,
    FCC_APP_SID_IN_DE = 2,
    FCC_APP_SID_N_INPUTS = 3
} fcc_app_sid_input_t;

/* One configuration for the three loops: each loop takes it with its own
 * filter type (fcc_sid_config_default() values, then the user's options). */
typedef struct {
    fcc_sid_config_t base;
} fcc_app_sid_config_t;

/* What one step produced, indexed by fcc_sid_filter_t (KF, ZKF, AZKF). */
typedef struct {
    uint32_t k;
    fcc_sid_out_t out[FCC_APP_SID_N_FILTERS];
    fcc_sensor_state_t input_state[FCC_APP_SID_N_INPUTS];
    bool measurement_valid; /* alpha, q and de were usable */
    bool degraded;          /* inputs degraded or a loop reported an error */
    fcc_status_t status;    /* first error of the three loops */
    uint64_t newest_rx_us;  /* receive stamp of the newest sample used (0: none) */
} fcc_app_sid_result_t;

typedef struct {
    fcc_app_sid_config_t cfg;
    fcc_sid_t loop[FCC_APP_SID_N_FILTERS];
    fcc_sensor_t in[FCC_APP_SID_N_INPUTS];
    fcc_real_t de_last; /* last good elevator, used while it is unusable */
    fcc_app_sid_result_t last;
    uint32_t steps;
    uint32_t degraded_steps;
} fcc_app_sid_t;

/* Paper values and the sid module's documented defaults. */
void fcc_app_sid_config_default(fcc_app_sid_config_t *cfg);

/* Checks the configuration and starts the three loops (initial estimate,
 * priors).  app is ~3 x sizeof(fcc_sid_t): keep it static. */
fcc_status_t fcc_app_sid_init(fcc_app_sid_t *app, const fcc_app_sid_config_t *cfg);

/* Fresh loops and sensors with the same configuration; step counters kept. */
fcc_status_t fcc_app_sid_reset(fcc_app_sid_t *app);

/* The sensor slot fed by message msg (CDRW_AOA, CDRW_PITCH_RATE,
 * CDRW_ELEVATOR), or NULL. */
fcc_sensor_t *fcc_app_sid_sensor(fcc_app_sid_t *app, fcc_msg_t msg);

/* Offer a decoded good frame of one of its sensors (value and step field). */
fcc_status_t fcc_app_sid_offer(fcc_app_sid_t *app, fcc_msg_t msg, const fcc_msg_data_t *data,
                               uint64_t t_us);

/*
 * Step k: judge the sensors (check_step: the frames must carry k mod 2^16),
 * run the three loops, fill *res.  Returns res->status; the loops never see a
 * NaN and keep their last good state on error.
 */
fcc_status_t fcc_app_sid_step(fcc_app_sid_t *app, uint32_t k, bool check_step,
                              uint16_t stale_limit, bool oracle_fault,
                              fcc_app_sid_result_t *res);

/* The 12 output frames of a result, in sending order (AZKF, ZKF, KF).
 * Diagnostic values are clamped to the DBC ranges (fcc_bus_encode_sat);
 * *n_frames receives how many were encoded (a refused one is skipped and
 * counted by the bus).  Returns the first refusal, FCC_OK if none. */
fcc_status_t fcc_app_sid_encode(const fcc_app_sid_result_t *res, fcc_bus_t *bus,
                                fcc_can_frame_t frames[FCC_APP_SID_N_FRAMES], uint32_t *n_frames);

/* The application to the node (fcc_app.h): its config is an fcc_app_sid_config_t. */
extern const fcc_app_ops_t fcc_app_sid_ops;

#endif /* FCC_APP_SID_H */
