/*
 * fcc_sensor.h -- health of one periodic sensor signal, judged once per step.
 *
 * The frame layer (fcc_bus.h) says whether a single frame is good.  An
 * application needs more: was there a good sample FOR THIS STEP, and if not,
 * may it still use the last one?  Between steps the node offers every good
 * frame (fcc_sensor_offer) and reports every rejected one
 * (fcc_sensor_reject); at the step, fcc_sensor_close() decides:
 *
 *   OK          a usable frame came since the last step (lockstep: one whose
 *               step field is this step): the newest one is used;
 *   HELD        nothing came (or only E2E REPEATED copies), for at most
 *               stale_limit steps in a row: the last good value is reused;
 *               one late or lost frame must not throw a filter off;
 *   STALE       nothing new for more than stale_limit steps, or never
 *               anything: no value;
 *   REJECTED    only rejected frames (E2E ERROR / WRONG_SEQUENCE, wrong DLC,
 *               out of range): no value -- a corrupted sample is worse than
 *               none, and the last one is not reused;
 *   MISALIGNED  lockstep: good frames, but all for other steps: no value.
 *
 * OK and HELD are usable; the three others make the step degraded.  The
 * sensor recovers with the next OK.
 */
#ifndef FCC_SENSOR_H
#define FCC_SENSOR_H

#include <stdbool.h>
#include <stdint.h>

#include "fcc_types.h"

/* Good frames remembered per step (a duplicate or a delayed frame adds one). */
#define FCC_SENSOR_MAX_PENDING 4u

typedef enum {
    FCC_SENSOR_OK = 0,
    FCC_SENSOR_HELD = 1,
    FCC_SENSOR_STALE = 2,
    FCC_SENSOR_REJECTED = 3,
    FCC_SENSOR_MISALIGNED = 4,
    FCC_SENSOR_N_STATES = 5
} fcc_sensor_state_t;

typedef struct {
    fcc_real_t value;
    uint16_t step;  /* the frame's step field (low 16 bits of k) */
    uint64_t t_us;  /* receive time stamp */
} fcc_sensor_sample_t;

typedef struct {
    uint32_t can_id;                                      /* for reports */
    fcc_sensor_sample_t pending[FCC_SENSOR_MAX_PENDING];  /* good frames of this period, oldest first */
    uint8_t n_pending;
    uint8_t n_rejected;          /* rejected frames this period (saturates) */
    bool have_value;             /* a good value was ever used */
    fcc_sensor_sample_t last;    /* the last value used (OK) */
    uint16_t missing_run;        /* consecutive steps without OK */
    fcc_sensor_state_t state;    /* verdict of the last step */
    uint32_t count[FCC_SENSOR_N_STATES]; /* steps per verdict */
} fcc_sensor_t;

/* Fresh sensor, state STALE (nothing seen yet). */
void fcc_sensor_init(fcc_sensor_t *s, uint32_t can_id);

/* Forget every value and the pending frames; the counts are kept. */
void fcc_sensor_reset(fcc_sensor_t *s);

/* A frame passed every check: remember it for the current step.  Beyond
 * FCC_SENSOR_MAX_PENDING the oldest is dropped.  Non-finite values are
 * refused (FCC_ERR_NOT_FINITE) and counted as a rejection. */
fcc_status_t fcc_sensor_offer(fcc_sensor_t *s, fcc_real_t value, uint16_t step, uint64_t t_us);

/* A frame of this sensor was rejected (E2E, DLC or range). */
void fcc_sensor_reject(fcc_sensor_t *s);

/*
 * Close the step: the verdict (see the file comment), and in *sample the
 * value to use when usable (OK or HELD; untouched otherwise).  check_step:
 * only frames whose step field equals `step` count (lockstep); otherwise the
 * newest good frame is used (realtime).
 */
fcc_sensor_state_t fcc_sensor_close(fcc_sensor_t *s, bool check_step, uint16_t step,
                                    uint16_t stale_limit, fcc_sensor_sample_t *sample);

/* OK or HELD. */
bool fcc_sensor_usable(fcc_sensor_state_t state);

/* "OK", "HELD", ... (never NULL). */
const char *fcc_sensor_state_str(fcc_sensor_state_t state);

#endif /* FCC_SENSOR_H */
