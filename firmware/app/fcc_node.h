/*
 * fcc_node.h -- the flight computer as one bus node: its applications (fcc_app.h), the
 * lockstep protocol, run-time commands, health and the heartbeat.
 *
 * Portable: no OS, no heap, no clock except the port's.  The Linux main
 * (firmware/port/linux) and the Cortex-M4F image (firmware/port/mps2_an386)
 * drive it the same way:
 *
 *     static fcc_node_t node;                        ~100 kB: keep it static
 *     cfg.security = {key, trip};                    key file, random trip
 *     fcc_node_init(&node, &cfg, &port);             designs the LQG (start-up)
 *     fcc_node_send_status(&node);                   "I am listening"
 *     loop:
 *         fcc_node_poll(&node, 64);                  frames in; lockstep steps run on SIM_TICK
 *         realtime: at each deadline fcc_node_run_step(&node, app, k);
 *         idle:     fcc_node_background(&node);      run-time LQG redesign
 *         every 1/rate: fcc_node_send_status(&node);
 *         until fcc_node_shutdown_requested(&node)
 *
 * The protocol (ticks, ACK, SIM_CONTROL, SIM_EVENT, sensor health) is
 * written down in firmware/app/README.md.
 */
#ifndef FCC_NODE_H
#define FCC_NODE_H

#include <stdbool.h>
#include <stdint.h>

#include "fcc_app.h"
#include "fcc_app_msl.h"
#include "fcc_app_sid.h"
#if defined(FCC_APP_PROBE)
#include "fcc_app_probe.h" /* the test build's third application (cmake -DFCC_APP_PROBE=ON) */
#endif
#include "fcc_bus.h"
#include "fcc_can_txq.h"
#include "fcc_port.h"
#include "fcc_secoc.h"
#include "fcc_tsync.h"
#include "fcc_tsync_auth.h"
#include "fcc_types.h"

/* Application numbers: the values of SIM_TICK.app / FCC_ACK.app, generated from the DBC's
 * FccApp attribute (fcc_bus_msgs.h).  The node runs each through its fcc_app_ops_t
 * (fcc_app.h, fcc_node_app_ops); an id without one in this build is not flown (its ticks
 * are ignored, --apps refuses it). */
#define FCC_APP_CDRW FCC_BUS_APP_CDRW
#define FCC_APP_MSL FCC_BUS_APP_MISSILE
#define FCC_N_APPS FCC_BUS_N_APPS

/* Missing frames tolerated (last value held) before a sensor is STALE. */
#define FCC_NODE_DEFAULT_STALE_LIMIT 1u

typedef enum {
    FCC_MODE_LOCKSTEP = 0, /* steps on SIM_TICK (FCC_STATUS.mode 0) */
    FCC_MODE_REALTIME = 1  /* steps on the port's clock (FCC_STATUS.mode 1) */
} fcc_mode_t;

/* Operating modes (FCC_STATUS.op_mode; firmware/app/README.md, "Modes"). */
typedef enum {
    FCC_OP_GROUND = 0,      /* standby: applications idle; reset, design, shutdown allowed */
    FCC_OP_FLIGHT = 1,      /* applications run; only GROUND is accepted */
    FCC_OP_MAINTENANCE = 2  /* applications idle; reset, design, shutdown; leave via GROUND */
} fcc_op_mode_t;

/* Key and session of the SecOC-style authentication (fcc_secoc.h). */
typedef struct {
    uint8_t key[FCC_SECOC_KEY_BYTES];
    uint32_t trip; /* high half of every freshness value: drawn at start, never 0 */
} fcc_node_security_t;

typedef struct {
    fcc_mode_t mode;
    fcc_node_security_t security; /* required: fcc_node_init refuses trip 0 */
    bool app_enabled[FCC_N_APPS];
    uint16_t stale_limit;
    fcc_app_sid_config_t sid;
    fcc_app_msl_config_t msl;
} fcc_node_config_t;

/* Per application, since start (kept across SIM_CONTROL resets). */
typedef struct {
    uint32_t steps;
    uint32_t degraded_steps;
    uint32_t step_errors;
    uint32_t ticks_lost;     /* lockstep: steps skipped by the simulator */
    uint32_t ticks_repeated; /* lockstep: same tick again (ACK resent) */
    uint32_t ticks_behind;   /* lockstep: tick older than the last, ignored */
    uint32_t ticks_ignored;  /* realtime mode or disabled app */
    uint32_t overruns;       /* realtime: steps started a whole period late */
    uint32_t worst_exec_us;
    uint32_t last_exec_us;
    /* Lockstep history (cleared by a reset). */
    bool have_last;
    uint32_t last_step;
    bool last_degraded;
} fcc_node_app_t;

typedef struct {
    uint32_t rx_frames;        /* frames handed to fcc_node_handle_frame */
    uint32_t tx_frames;        /* frames the port accepted */
    uint32_t tx_failed;        /* frames the port did not send */
    uint32_t resets;
    uint32_t configs_accepted; /* SIM_CONTROL design requests accepted */
    uint32_t configs_applied;  /* designs switched in */
    uint32_t configs_rejected; /* requests refused or designs failed */
    uint32_t status_sent;      /* heartbeats */
    uint32_t oracle_events;    /* good SIM_EVENT frames */
    uint32_t mode_refused;     /* authenticated commands and ticks refused in the current mode */
    uint32_t mode_changes;
    uint32_t own_id;           /* frames received on an identifier fcc sends (impersonation) */
} fcc_node_counters_t;

typedef struct {
    fcc_node_config_t cfg;
    fcc_port_t port;
    /* Frames of the current call waiting for the port's send_many (fcc_can_txq.h):
     * flushed at the end of every call of this API that may send (handle_frame,
     * poll, run_step, send_status), so a step's outputs and its FCC_ACK leave
     * together and nothing waits in it between calls. */
    fcc_can_txq_t txq;
    fcc_bus_t bus;
    fcc_secoc_t sec;
    fcc_op_mode_t op_mode;
    /* the applications' instances (fcc_node.c's k_apps says which id each one is) */
    fcc_app_sid_t sid;
    fcc_app_msl_t msl;
#if defined(FCC_APP_PROBE)
    fcc_app_probe_t probe;
#endif
    fcc_node_app_t app[FCC_N_APPS];
    fcc_node_counters_t cnt;
    bool oracle_fault;     /* from the last good SIM_EVENT */
    bool shutdown;         /* SIM_CONTROL shutdown received */
    bool config_rejected;  /* the last request was refused (FCC_STATUS flag) */
    bool e2e_fault_flag;   /* ERROR / WRONG_SEQUENCE since the last heartbeat */
    bool overrun_flag;     /* overrun since the last heartbeat */
    fcc_tsync_t tsync;     /* time base of the bus's time master (TSYNC_*) */
    fcc_tsync_auth_t tsync_auth; /* its SYNC / FOLLOW_UP held until TSYNC_AUTH verifies them */
    fcc_tsync_state_t tsync_reported; /* last state reported as an event */
    uint32_t tsync_rejected_reported;
} fcc_node_t;

/* The interface of application app in this build, NULL when it has none (fcc_app.h). */
const fcc_app_ops_t *fcc_node_app_ops(uint32_t app);

/* The id of the application called name in this build (fcc's --apps), FCC_N_APPS: none. */
uint32_t fcc_node_app_named(const char *name, uint32_t len);

/* Lockstep, every application of this build, stale limit 1, the applications' defaults. */
fcc_status_t fcc_node_config_default(fcc_node_config_t *cfg);

/* Checks cfg, starts every application (the LQG design runs here) and the
 * bus node.  The port is copied; its send, recv and now_us must be set. */
fcc_status_t fcc_node_init(fcc_node_t *node, const fcc_node_config_t *cfg,
                           const fcc_port_t *port);

/* SIM_CONTROL reset: fresh applications, tick history and oracle flag
 * cleared, E2E receivers resynchronised; design and counters kept. */
fcc_status_t fcc_node_reset(fcc_node_t *node);

/* One received frame: checks (fcc_bus.h), then sensors are stored for the
 * next step, SIM_TICK runs a lockstep step, SIM_CONTROL and SIM_EVENT are
 * applied.  Never fails on bad input: it counts and reports it. */
void fcc_node_handle_frame(fcc_node_t *node, const fcc_can_frame_t *frame);

/* Receive and handle up to max_frames waiting frames: how many were handled
 * in *n (may be NULL).  FCC_OK when the port ran dry or the budget was used,
 * FCC_ERR_IO when the port reported an error (the caller decides what the
 * interface is doing). */
fcc_status_t fcc_node_poll(fcc_node_t *node, uint32_t max_frames, uint32_t *n);

/* Run step k of app now and send its outputs (then FCC_ACK in lockstep).
 * Realtime uses it at each deadline; lockstep calls it from the tick.
 * FCC_ERR_AGAIN (nothing run) outside FLIGHT. */
fcc_status_t fcc_node_run_step(fcc_node_t *node, uint32_t app, uint32_t k);

/* Idle-time work: one slice of an application's pending work (the missile's LQG redesign,
 * fcc_app_msl_background).
 * FCC_OK after a slice (call again while it returns FCC_OK, or between
 * control steps), FCC_ERR_AGAIN when there was nothing to do. */
fcc_status_t fcc_node_background(fcc_node_t *node);

/* The heartbeat: the frames of FCC_STATUS_AUTH's SecOC group in the DBC's order
 * (FCC_STATUS, FCC_E2E_COUNTS, FCC_E2E_FAULTS, FCC_REJECT_COUNTS, FCC_BUS_COUNTS,
 * FCC_SYNC_STATUS, FCC_SEC_COUNTS, FCC_SEC_SESSION, FCC_SYNC_REFUSALS), then that
 * authenticator;
 * clears the since-last-heartbeat flags. */
fcc_status_t fcc_node_send_status(fcc_node_t *node);

/* Time sync timeouts (missing follow-up, loss of sync, release) and state
 * events; call at least once per sync interval (the hosts call it every loop). */
fcc_tsync_state_t fcc_node_sync_poll(fcc_node_t *node);

/* Every time-sync input refused: the servo's classes, implausible pairs, and
 * frames refused by the authentication (FCC_SYNC_STATUS.rejected). */
uint32_t fcc_node_sync_rejected(const fcc_node_t *node);

/* True when fcc takes frames of msg: an input slot of its application (the DBC's FccApp),
 * a handler of the node's, or an authenticator.  Every frame the DBC sends to FCC must be
 * taken (tests/c check it against the generated table, so that a frame added to the DBC is
 * not ignored in silence). */
bool fcc_node_handles(fcc_msg_t msg);

/* Realtime, synchronised schedule: every input of app has a good frame
 * received at or after since_us (the port's clock) waiting for the next step. */
bool fcc_node_inputs_since(const fcc_node_t *node, uint32_t app, uint64_t since_us);

/* Realtime: `missed` periods of app were skipped because a step started late. */
void fcc_node_note_overrun(fcc_node_t *node, uint32_t app, uint32_t missed, uint32_t k);

/* Host-side events (interface, bus errors) through the same sink. */
void fcc_node_report(fcc_node_t *node, fcc_event_class_t cls, int32_t value);

bool fcc_node_shutdown_requested(const fcc_node_t *node);

fcc_op_mode_t fcc_node_op_mode(const fcc_node_t *node);

/* ---- realtime schedule (fcc_node_rt.c): the same for every main ---------------- */

/* One application's absolute deadlines t0 + k T on the port's clock (free-run),
 * or, while the time sync has the master's time (fcc_tsync_has_time), the
 * master's sampling instants t_n = n T: step n is released as soon as every
 * input has a frame stamped at or after t_n - FCC_NODE_RT_GUARD_US, at the
 * latest at t_n + the window (the application's rt_window_us, fcc_app.h: the
 * autopilot's command must leave before the actuation instant; 0, as the
 * identification's: T / 2). */
#define FCC_NODE_RT_GUARD_US 500u

typedef struct {
    uint64_t deadline;  /* next release, port microseconds */
    uint32_t period_us;
    uint32_t k;         /* step index of that release */
    bool synced;        /* following the master's sampling instants */
    uint64_t n;         /* synced: index of the next instant, t_n = n period (master us) */
    uint64_t instant;   /* synced: port time of t_n */
    uint64_t last_instant; /* synced: port time of the instant of the last step run */
    uint32_t aligns;    /* times the schedule (re)aligned to a master */
} fcc_node_rt_t;

/* First deadlines one period after start_us. */
void fcc_node_rt_start(const fcc_node_t *node, fcc_node_rt_t rt[FCC_N_APPS], uint64_t start_us);

/* Runs each enabled application whose deadline has come (synchronised: whose
 * inputs are in or whose window is over), the autopilot first.  A step that
 * starts a whole period late skips the missed periods (counted as overruns, no
 * catch-up burst); one that ends after its next deadline is an overrun; the
 * deadline then advances by the period, which a redesign may have changed.
 * jitter_us[a]: start - deadline (synchronised: start - sampling instant) of
 * each step run (UINT64_MAX: app a did not run).  Returns how many steps ran. */
uint32_t fcc_node_rt_run_due(fcc_node_t *node, fcc_node_rt_t rt[FCC_N_APPS],
                             uint64_t jitter_us[FCC_N_APPS]);

/* The earliest deadline of the enabled applications (UINT64_MAX: none). */
uint64_t fcc_node_rt_next(const fcc_node_t *node, const fcc_node_rt_t rt[FCC_N_APPS]);

/* Period of app in microseconds (the missile's follows run-time redesigns; 0: no such app). */
uint32_t fcc_node_app_period_us(const fcc_node_t *node, uint32_t app);

#endif /* FCC_NODE_H */
