/*
 * fcc_tsync.h -- time synchronisation slave: follows one time master on the
 * bus (SYNC + FOLLOW_UP, in the manner of CANopen SYNC and AUTOSAR CAN time
 * synchronisation) and estimates the master's time as a function of the
 * port's own clock, offset and rate, with a PI servo.
 *
 * Portable: integers only (microseconds in 64 bits, rate in parts per
 * billion), no clock of its own -- every call is given the local time (the
 * port's now_us() or a frame's receive stamp on that clock), no heap.
 *
 * Protocol (dbc/fcc_hil.dbc TSYNC_SYNC / TSYNC_FOLLOW_UP):
 *   SYNC(master, seq, interval_ms, sec)  received at local time L;
 *   FOLLOW_UP(master, seq, sec_carry, ns): the master time M at which that
 *   SYNC actually left = (sec + sec_carry) s + ns.  The pair is one sample
 *   (L, M): transmission time on the wire is common to every sample and
 *   shows as a constant offset (one frame, ~0.25 ms at 500 kbit/s on a real
 *   bus; 0 on vcan).
 *
 * Servo, per sample: residual e = M - estimate(L).
 *   |e| <= step_us: phase += e / 2, rate += e / (16 dt) (dt: time since the
 *       last sample), clamped to +-max_rate_ppb; lock_count residuals in a
 *       row under lock_us -> LOCKED.
 *   |e| >  step_us: an outlier, counted as `past` (e < 0) or `future` (e > 0)
 *       and not used -- unless jump_count outliers in a row agree with each
 *       other within step_us: then the master clock really jumped; the
 *       estimate is re-stepped to the new time (`jumps`), state LOCKING.
 *   A master time that does not advance (M <= the previous sample's) is
 *   `backwards`, never used.
 *
 * States (fcc_tsync_state_t, FCC_SYNC_STATUS.state):
 *   FREE_RUN  no master yet (or released): the node runs on its own clock;
 *   LOCKING   following a master, residuals not yet small;
 *   LOCKED    following, residuals small;
 *   HOLDOVER  no usable sample for loss_intervals sync intervals: the last
 *             estimate (offset + rate) goes on, flagged degraded, `losses`
 *             counted; the next good sample recovers (`recoveries`).  After
 *             release_intervals in holdover the master is released
 *             (FREE_RUN, `releases`) and any master is accepted again.
 * Bad input (each counted, never fatal): a SYNC from another master than the
 * one followed (`foreign`: a second time master), a SYNC whose FOLLOW_UP never
 * came (`missing_fup`: the next SYNC or one interval passed), a FOLLOW_UP
 * without its SYNC (`orphan_fup`), a SYNC repeating the previous sequence
 * number (`repeated_seq`: a replay), and the outliers above.
 */
#ifndef FCC_TSYNC_H
#define FCC_TSYNC_H

#include <stdbool.h>
#include <stdint.h>

#include "fcc_types.h"

typedef enum {
    FCC_TSYNC_FREE_RUN = 0,
    FCC_TSYNC_LOCKING = 1,
    FCC_TSYNC_LOCKED = 2,
    FCC_TSYNC_HOLDOVER = 3
} fcc_tsync_state_t;

typedef struct {
    uint32_t step_us;           /* |residual| above: outlier (1000) */
    uint32_t lock_us;           /* |residual| below: counts towards LOCKED (200) */
    uint8_t lock_count;         /* good residuals in a row to lock (3) */
    uint8_t jump_count;         /* agreeing outliers in a row = a master clock jump (3) */
    uint8_t loss_intervals;     /* intervals without a usable sample -> HOLDOVER (3) */
    uint8_t release_intervals;  /* intervals in HOLDOVER -> FREE_RUN (50) */
    int32_t max_rate_ppb;       /* rate estimate clamp (500 000 = 500 ppm) */
} fcc_tsync_config_t;

typedef struct {
    uint32_t syncs;        /* SYNC frames of the master followed */
    uint32_t samples;      /* SYNC + FOLLOW_UP pairs used by the servo */
    uint32_t missing_fup;  /* SYNC never followed up */
    uint32_t orphan_fup;   /* FOLLOW_UP without its SYNC */
    uint32_t repeated_seq; /* SYNC with the previous sequence number */
    uint32_t past;         /* outlier: master time behind the estimate by > step_us */
    uint32_t future;       /* outlier: ahead by > step_us */
    uint32_t backwards;    /* master time not after the previous sample's */
    uint32_t jumps;        /* master clock jumps accepted (estimate re-stepped) */
    uint32_t foreign;      /* frames of another time master */
    uint32_t losses;       /* LOCKING/LOCKED -> HOLDOVER */
    uint32_t recoveries;   /* HOLDOVER -> LOCKING/LOCKED */
    uint32_t releases;     /* HOLDOVER -> FREE_RUN */
} fcc_tsync_counters_t;

typedef struct {
    fcc_tsync_config_t cfg;
    fcc_tsync_state_t state;
    bool have_master;
    uint8_t master;
    uint32_t interval_us;
    /* the SYNC waiting for its FOLLOW_UP */
    bool pending;
    uint8_t pend_seq;
    uint32_t pend_sec;
    uint64_t pend_local_us;
    bool have_seq;
    uint8_t last_seq;
    /* the estimate: master(L) = ref_master + (L - ref_local) (1 + rate_ppb 1e-9) */
    bool have_ref;
    uint64_t ref_local_us;
    uint64_t ref_master_us;
    int32_t rate_ppb;
    uint64_t last_sample_local_us;
    uint64_t last_sample_master_us;
    uint64_t last_good_local_us;
    int32_t last_residual_us;   /* saturated to int32 */
    uint8_t good_run;
    uint8_t outlier_run;
    int64_t outlier_first_us;   /* M - estimate of the first outlier of the run */
    fcc_tsync_counters_t cnt;
} fcc_tsync_t;

/* The defaults above. */
fcc_status_t fcc_tsync_config_default(fcc_tsync_config_t *cfg);

/* FREE_RUN, no master, counters zero.  FCC_ERR_RANGE for a config that cannot
 * work (zero counts, lock_us > step_us, rate clamp <= 0). */
fcc_status_t fcc_tsync_init(fcc_tsync_t *ts, const fcc_tsync_config_t *cfg);

/* A SYNC received at local_us.  FCC_OK when it was taken (waits for its
 * FOLLOW_UP), FCC_ERR_AGAIN when it was refused and counted. */
fcc_status_t fcc_tsync_on_sync(fcc_tsync_t *ts, uint8_t master, uint8_t seq, uint8_t interval_ms,
                               uint32_t sec, uint64_t local_us);

/* A FOLLOW_UP.  FCC_OK when the pair was used by the servo, FCC_ERR_AGAIN when
 * it was refused and counted (orphan, foreign, outlier, backwards). */
fcc_status_t fcc_tsync_on_follow_up(fcc_tsync_t *ts, uint8_t master, uint8_t seq,
                                    bool sec_carry, uint32_t ns);

/* Timeouts (missing FOLLOW_UP, loss of sync, release); call at least once per
 * sync interval.  Returns the state. */
fcc_tsync_state_t fcc_tsync_poll(fcc_tsync_t *ts, uint64_t now_us);

/* An estimate exists (LOCKING, LOCKED or HOLDOVER): the schedule may follow the
 * master's time base. */
bool fcc_tsync_has_time(const fcc_tsync_t *ts);

/* Local time -> master time and back.  FCC_ERR_AGAIN without an estimate. */
fcc_status_t fcc_tsync_to_master(const fcc_tsync_t *ts, uint64_t local_us, uint64_t *master_us);
fcc_status_t fcc_tsync_to_local(const fcc_tsync_t *ts, uint64_t master_us, uint64_t *local_us);

/* Every refused input, all classes together. */
uint32_t fcc_tsync_rejected(const fcc_tsync_t *ts);

#endif /* FCC_TSYNC_H */
