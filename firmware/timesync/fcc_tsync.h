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
 * Only authenticated pairs get here (the node verifies the time master's
 * TSYNC_AUTH over SYNC + FOLLOW_UP first: fcc_tsync_auth.h); an authenticated
 * master may still be wrong (a compromised or faulty master), so every pair
 * is first checked against the port's own clock.
 *
 * Plausibility, per sample, before the servo: the deviation d = M - L of the
 * master's time from the own clock is compared with a reference deviation
 * d_ref (set by the first sample) that follows the accepted samples at a
 * rate of at most max_rate_ppb: |d - d_ref| <= max_step_us + max_rate_ppb *
 * (L - L_ref), L_ref the last accepted sample.  A pair outside is refused
 * (never used), counted `step_refused` when the refusals began with a jump of
 * more than max_step_us from the previous authenticated pair, `rate_refused`
 * when they began with a gradual drift (every pair of one run of refusals is
 * counted under the cause of its first), and the state is REFUSED.  So
 * whatever an authenticated master sends, the time fcc follows never steps
 * by more than max_step_us and never runs away from the own clock faster
 * than max_rate_ppb.  fcc_tsync_rebase() (the node: an authenticated RESET
 * on the ground) forgets the reference while the master is not followed.
 *
 * Servo, per sample: residual e = M - estimate(L).
 *   |e| <= step_us: phase += e / 2, rate += e / (16 dt) (dt: time since the
 *       last sample), clamped to +-max_rate_ppb (the plausibility bound); lock_count residuals in a
 *       row under lock_us -> LOCKED.
 *   |e| >  step_us: an outlier, counted as `past` (e < 0) or `future` (e > 0)
 *       and not used -- unless jump_count outliers in a row agree with each
 *       other within step_us: then the master clock really jumped; the
 *       estimate is re-stepped to the new time (`jumps`), state LOCKING.
 *   A master time that does not advance (M <= the previous sample's) is
 *   `backwards`, never used.
 *
 * States (fcc_tsync_state_t, FCC_SYNC_STATUS.state):
 *   FREE_RUN  no master yet (or rebased): the node runs on its own clock;
 *   LOCKING   following a master, residuals not yet small;
 *   LOCKED    following, residuals small;
 *   HOLDOVER  no usable sample for loss_intervals sync intervals: the last
 *             estimate (offset + rate) goes on, flagged degraded, `losses`
 *             counted; the next good sample recovers (`recoveries`).
 *   LOST      release_intervals without an accepted sample (from HOLDOVER):
 *             the estimate is dropped (own clock, `releases`) and any master
 *             is accepted again -- within the plausibility reference, which
 *             is kept.
 *   REFUSED   the last authenticated pair failed the plausibility check: it
 *             is not followed; the last estimate, if any, goes on at the rate
 *             of the last quiet residual (it is the own clock, within the
 *             rate bound) for as long as the master is refused -- no release:
 *             a wrong master must not hand the schedule a new time base.  The
 *             next plausible pair recovers (`recoveries`); fcc_tsync_rebase()
 *             forgets the reference.
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
    FCC_TSYNC_HOLDOVER = 3,
    FCC_TSYNC_LOST = 4,
    FCC_TSYNC_REFUSED = 5
} fcc_tsync_state_t;

typedef struct {
    uint32_t step_us;           /* |residual| above: outlier (1000) */
    uint32_t lock_us;           /* |residual| below: counts towards LOCKED (200) */
    uint8_t lock_count;         /* good residuals in a row to lock (3) */
    uint8_t jump_count;         /* agreeing outliers in a row = a master clock jump (3) */
    uint8_t loss_intervals;     /* intervals without a usable sample -> HOLDOVER (3) */
    uint8_t release_intervals;  /* intervals in HOLDOVER -> FREE_RUN (50) */
    int32_t max_rate_ppb;       /* plausibility: rate bound, also the estimate's clamp
                                   (200 000 = 200 ppm) */
    uint32_t max_step_us;       /* plausibility: step bound (1000) */
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
    uint32_t releases;     /* estimate dropped (HOLDOVER -> LOST, or in REFUSED) */
    uint32_t step_refused; /* pairs refused: a step beyond max_step_us vs the own clock */
    uint32_t rate_refused; /* pairs refused: a drift beyond max_rate_ppb vs the own clock */
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
    int32_t quiet_rate_ppb;     /* the rate after the last residual under lock_us */
    uint64_t last_sample_local_us;
    uint64_t last_sample_master_us;
    uint64_t last_good_local_us;
    int32_t last_residual_us;   /* saturated to int32 */
    uint8_t good_run;
    uint8_t outlier_run;
    int64_t outlier_first_us;   /* M - estimate of the first outlier of the run */
    /* plausibility reference: d_ref = M - L, following the accepted samples at
     * most at max_rate_ppb; L_ref the last accepted sample */
    bool have_plaus;
    uint64_t plaus_local_us;
    int64_t plaus_dev_us;
    bool have_last_auth;        /* the previous authenticated pair's deviation */
    int64_t last_auth_dev_us;
    bool refusing;              /* in a run of refusals: its cause */
    bool refusing_step;
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

/* Forget the plausibility reference while no master is followed (REFUSED or
 * LOST): the next authenticated pair starts anew (FREE_RUN).  No effect while
 * following (the node calls it on an authenticated RESET on the ground).
 * FCC_OK when it did, FCC_ERR_AGAIN when there was nothing to forget. */
fcc_status_t fcc_tsync_rebase(fcc_tsync_t *ts);

/* An estimate exists (LOCKING, LOCKED, HOLDOVER, or REFUSED before its
 * release): the schedule may follow the master's time base. */
bool fcc_tsync_has_time(const fcc_tsync_t *ts);

/* Local time -> master time and back.  FCC_ERR_AGAIN without an estimate. */
fcc_status_t fcc_tsync_to_master(const fcc_tsync_t *ts, uint64_t local_us, uint64_t *master_us);
fcc_status_t fcc_tsync_to_local(const fcc_tsync_t *ts, uint64_t master_us, uint64_t *local_us);

/* Every refused input, all classes together (implausible pairs included). */
uint32_t fcc_tsync_rejected(const fcc_tsync_t *ts);

#endif /* FCC_TSYNC_H */
