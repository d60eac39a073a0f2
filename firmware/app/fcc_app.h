/*
 * fcc_app.h -- the one interface of every application of the node: a const table of
 * function pointers per application (as a CMSIS driver's access struct), so that the node
 * (fcc_node.c) runs any application the same way and has no path of its own for any.
 *
 * An application is a module with its instance type and, for the node, one const
 * fcc_app_ops_t: its inputs (the DBC's FccApp frames, generated), how a frame reaches it,
 * its step, its output frames and the authenticator they go under, its period.  The node
 * keeps each instance in its own storage (fcc_node.h: no heap) and calls the ops with it.
 *
 * Per step k the node: closes the E2E period of each input, calls step(), then encode()
 * and sends the frames under out_auth (all or none), then reports the inputs' health and
 * the step (FCC_ACK in lockstep).  The optional hooks (NULL: none) take a run-time
 * configuration from SIM_CONTROL and do its work in the background (the missile's LQG
 * redesign).
 */
#ifndef FCC_APP_H
#define FCC_APP_H

#include <stdbool.h>
#include <stdint.h>

#include "fcc_bus.h"
#include "fcc_sensor.h"
#include "fcc_types.h"

/* What the node gives a step. */
typedef struct {
    uint32_t k;           /* step index */
    bool check_step;      /* lockstep: the frames must carry k mod 2^16 */
    uint16_t stale_limit; /* missing frames tolerated before a sensor is STALE */
    bool oracle_fault;    /* the simulator's fault truth (SIM_EVENT), for who uses it */
} fcc_app_tick_t;

/* What a step tells the node (its outputs stay in the instance until encode()). */
typedef struct {
    bool degraded;     /* inputs unusable or a part of the step failed */
    bool reconfigured; /* a new configuration was switched in at this step */
} fcc_app_step_t;

typedef struct {
    const char *name;        /* its name on fcc's command line (--apps) and in logs */
    const fcc_msg_t *inputs; /* its input frames, the order of its slots (NULL: none) */
    uint32_t n_inputs;
    fcc_msg_t out_auth;      /* the authenticator of its outputs (FCC_MSG_COUNT: not secured) */
    /* the release window of a synchronised realtime step after its sampling instant
     * (fcc_node.h; 0: half its period) */
    uint32_t rt_window_us;

    fcc_status_t (*config_default)(void *cfg); /* NULL for one that takes no configuration */
    fcc_status_t (*init)(void *app, const void *cfg);
    fcc_status_t (*reset)(void *app); /* fresh state, same configuration */
    fcc_sensor_t *(*sensor)(void *app, fcc_msg_t msg); /* the slot of an input, or NULL */
    const fcc_sensor_t *(*input)(const void *app, uint32_t slot); /* slot i, read only */
    fcc_status_t (*offer)(void *app, fcc_msg_t msg, const fcc_msg_data_t *data, uint64_t t_us);
    fcc_status_t (*step)(void *app, const fcc_app_tick_t *tick, fcc_app_step_t *out);
    /* the last step's output frames into frames[0..FCC_SECOC_MAX_PDUS), their count in *n */
    fcc_status_t (*encode)(const void *app, fcc_bus_t *bus, fcc_can_frame_t *frames, uint32_t *n);
    uint32_t (*period_us)(const void *app);

    /* optional: a design request of SIM_CONTROL (lqg_period, da_bits), its background work
     * (FCC_OK after a slice, FCC_ERR_AGAIN with nothing to do) and whether some is waiting */
    fcc_status_t (*request)(void *app, fcc_real_t period, uint8_t bits);
    fcc_status_t (*background)(void *app);
    bool (*wants_background)(const void *app);
} fcc_app_ops_t;

#endif /* FCC_APP_H */
