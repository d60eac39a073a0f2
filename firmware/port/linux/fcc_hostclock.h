/*
 * fcc_hostclock.h -- CLOCK_MONOTONIC in microseconds without a system call per read,
 * through the CPU's time-stamp counter where it is invariant (x86-64).
 *
 * Why: under User-Mode Linux every clock_gettime is a system call (5.7 us in a quiet
 * guest, several times that on a loaded host), and the node reads the clock on the
 * path from a lockstep tick to its command (the step's execution time, FCC_ACK's
 * exec_us) and several times a realtime step (release, overrun check).  Reading the
 * counter takes ~30 ns, also in the guest.
 *
 * How: a real clock_gettime bracketed by two counter reads is a sample (the clock's
 * value at the bracket's middle; half the bracket is its uncertainty).  The counter's
 * rate is measured between an early sample (the base) and the latest, with the bound of
 * error (half bracket + half bracket + 1 us, the clock's readings being whole
 * microseconds) / span.  A read is the last sample (the anchor)
 * plus the counter's ticks since, scaled, as long as the anchor is young enough that the
 * rate's error adds at most FCC_HOSTCLOCK_DRIFT_US (and at most FCC_HOSTCLOCK_ANCHOR_US
 * old); an older one is renewed by a real read.  In the guest (brackets of ~6 us) the
 * anchor may be 1 ms old after a 12 ms span, 5 ms old after 60 ms.  So a time is off
 * by at most FCC_HOSTCLOCK_DRIFT_US plus the anchor's half bracket (at most
 * FCC_HOSTCLOCK_BRACKET_US / 2: a sample whose bracket is wider, the process preempted
 * between the reads, is no anchor), and a duration by the rate's error (0.1 us in 100 us
 * at worst).  The base moves on every FCC_HOSTCLOCK_BASE_US, so the rate follows NTP's
 * slewing of CLOCK_MONOTONIC.  Reads never go backwards (a real read that lands behind
 * the last extrapolated time returns that time).  Without an invariant counter (another
 * CPU, or the CPU says it is not) every read is a clock_gettime, as before.
 *
 * The arithmetic (fcc_hostclock_sample, fcc_hostclock_extrapolate) takes the counter
 * and the clock as arguments: tests/c/test_hostclock.c drives it with chosen values.
 */
#ifndef FCC_HOSTCLOCK_H
#define FCC_HOSTCLOCK_H

#include <stdbool.h>
#include <stdint.h>

#define FCC_HOSTCLOCK_ANCHOR_US 5000u   /* an anchor older than this: a real read */
#define FCC_HOSTCLOCK_DRIFT_US 1u       /* what the rate's error may add since the anchor */
#define FCC_HOSTCLOCK_BRACKET_US 20u    /* a wider bracket (preempted between the reads): no anchor */
#define FCC_HOSTCLOCK_BASE_US 10000000u /* the rate's base moves on after this span */
#define FCC_HOSTCLOCK_RATE_FLOOR 1e-5   /* a rate measured this well replaces the one in use */

/* One bracketed clock reading: the counter before and after, the clock in between. */
typedef struct {
    uint64_t tick;    /* the bracket's middle */
    uint64_t half;    /* half the bracket, in ticks */
    uint64_t us;      /* CLOCK_MONOTONIC */
} fcc_hostclock_sample_t;

typedef struct {
    bool counter;                  /* an invariant counter: extrapolate between anchors */
    bool have_base;
    bool have_anchor;
    double us_per_tick;            /* 0: not measured yet */
    double rate_err;               /* its bound of relative error */
    fcc_hostclock_sample_t base;   /* the rate's start */
    fcc_hostclock_sample_t anchor; /* the latest sample with a narrow bracket */
    uint64_t anchor_ticks;         /* how old (ticks) an anchor may be */
    uint64_t last_us;              /* the last time handed out */
    uint32_t samples;              /* real reads so far */
} fcc_hostclock_t;

/* counter: the CPU's counter is invariant and may be used (fcc_hostclock_has_counter()). */
void fcc_hostclock_init(fcc_hostclock_t *c, bool counter);

/* The counter may be used here: x86-64 with an invariant time-stamp counter. */
bool fcc_hostclock_has_counter(void);

/* A real reading us taken between counter values before and after: kept as a sample
 * (base, rate, anchor).  Returns the time to hand out (us, or the last time handed out
 * when us is behind it). */
uint64_t fcc_hostclock_sample(fcc_hostclock_t *c, uint64_t before, uint64_t us, uint64_t after);

/* The time at counter value tick from the anchor: true with *us (never behind the last
 * time handed out); false when a real read is due (no rate yet, no anchor, or the
 * anchor too old). */
bool fcc_hostclock_extrapolate(fcc_hostclock_t *c, uint64_t tick, uint64_t *us);

/* CLOCK_MONOTONIC now, in microseconds: always a real read (a system call under UML). */
uint64_t fcc_hostclock_monotonic_us(void);

/* CLOCK_MONOTONIC now, in microseconds: extrapolated, or a real (bracketed) read. */
uint64_t fcc_hostclock_now(fcc_hostclock_t *c);

#endif /* FCC_HOSTCLOCK_H */
