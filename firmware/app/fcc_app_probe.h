/*
 * fcc_app_probe.h -- the third application of a test build (cmake -DFCC_APP_PROBE=ON):
 * the smallest application behind the node's one interface (fcc_app.h), so that a third
 * aircraft is flown on the host fcc in a real lockstep flight (tests/python/apps) and is
 * seen to take its own path, neither the missile's nor the identification's.
 *
 * It has no sensor frames and no output frames of its own (the DBC gives it SIM_TICK.app
 * PROBE and nothing else): every step is answered by the node's FCC_ACK, degraded on odd
 * steps -- a pattern neither shipped application answers with, so that the rig sees which
 * step function ran.
 */
#ifndef FCC_APP_PROBE_H
#define FCC_APP_PROBE_H

#include <stdint.h>

#include "fcc_app.h"
#include "fcc_types.h"

#define FCC_APP_PROBE_PERIOD_US 50000u

typedef struct {
    uint32_t steps;
    uint32_t last_k;
} fcc_app_probe_t;

/* The application to the node (fcc_app.h); it takes no configuration (cfg may be NULL). */
extern const fcc_app_ops_t fcc_app_probe_ops;

#endif /* FCC_APP_PROBE_H */
