/*
 * fcc_hostclock.c -- CLOCK_MONOTONIC through the time-stamp counter.  See fcc_hostclock.h.
 */
#define _DEFAULT_SOURCE 1 /* clock_gettime under -std=c99 */

#include "fcc_hostclock.h"

#include <time.h>

#if defined(__x86_64__) && defined(__GNUC__)
#include <cpuid.h>
#include <x86intrin.h>
#define FCC_HOSTCLOCK_X86 1
#endif

uint64_t fcc_hostclock_monotonic_us(void)
{
    struct timespec ts;
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000u + (uint64_t)ts.tv_nsec / 1000u;
}

static uint64_t counter_now(void)
{
#ifdef FCC_HOSTCLOCK_X86
    return (uint64_t)__rdtsc();
#else
    return 0u; /* never called: fcc_hostclock_has_counter() is false */
#endif
}

bool fcc_hostclock_has_counter(void)
{
#ifdef FCC_HOSTCLOCK_X86
    unsigned int eax = 0u;
    unsigned int ebx = 0u;
    unsigned int ecx = 0u;
    unsigned int edx = 0u;
    /* CPUID 0x80000007, EDX bit 8: the counter runs at a constant rate in every
     * power state (and, with it, in step on every core) */
    return __get_cpuid(0x80000007u, &eax, &ebx, &ecx, &edx) != 0 && (edx & (1u << 8)) != 0u;
#else
    return false;
#endif
}

void fcc_hostclock_init(fcc_hostclock_t *c, bool counter)
{
    const fcc_hostclock_t zero = {0};
    *c = zero;
    c->counter = counter;
}

/* Never behind the last time handed out. */
static uint64_t hand_out(fcc_hostclock_t *c, uint64_t us)
{
    if (us < c->last_us) {
        return c->last_us;
    }
    c->last_us = us;
    return us;
}

/* The rate from the base to s, when its bound of error is at most that of the rate in
 * use (or FCC_HOSTCLOCK_RATE_FLOOR: after the base moved on, the new rate takes over once
 * measured that well); the anchor's age from it. */
static void measure_rate(fcc_hostclock_t *c, const fcc_hostclock_sample_t *s)
{
    const fcc_hostclock_sample_t *b = &c->base;
    if (s->tick <= b->tick || s->us <= b->us) {
        return;
    }
    const double span = (double)(s->tick - b->tick);
    const double us_per_tick = (double)(s->us - b->us) / span;
    /* the brackets' halves, and the clock's whole microseconds: a difference of two
     * truncated readings is off by up to 1 us (on a host whose clock_gettime takes
     * 20 ns that is most of the error, and leaving it out let reads run 14 us ahead) */
    const double err = ((double)(b->half + s->half) * us_per_tick + 1.0) / (double)(s->us - b->us);
    const double good_enough = (c->rate_err > FCC_HOSTCLOCK_RATE_FLOOR) ? c->rate_err
                                                                          : FCC_HOSTCLOCK_RATE_FLOOR;
    if (c->us_per_tick > 0.0 && err > good_enough) {
        return;
    }
    c->us_per_tick = us_per_tick;
    c->rate_err = err;
    double age_us = (double)FCC_HOSTCLOCK_DRIFT_US / err;
    if (age_us > (double)FCC_HOSTCLOCK_ANCHOR_US) {
        age_us = (double)FCC_HOSTCLOCK_ANCHOR_US;
    }
    c->anchor_ticks = (uint64_t)(age_us / c->us_per_tick);
}

uint64_t fcc_hostclock_sample(fcc_hostclock_t *c, uint64_t before, uint64_t us, uint64_t after)
{
    ++c->samples;
    if (!c->counter || after < before) {
        return hand_out(c, us);
    }
    fcc_hostclock_sample_t s;
    s.half = (after - before + 1u) / 2u;
    s.tick = before + (after - before) / 2u;
    s.us = us;
    /* until the rate is known, the base is the narrowest bracket seen */
    if (!c->have_base || (c->us_per_tick == 0.0 && s.half < c->base.half)) {
        c->base = s;
        c->have_base = true;
        return hand_out(c, us);
    }
    measure_rate(c, &s);
    if (c->us_per_tick > 0.0 &&
        (double)(2u * s.half) * c->us_per_tick <= (double)FCC_HOSTCLOCK_BRACKET_US) {
        c->anchor = s;
        c->have_anchor = true;
        if (s.us - c->base.us >= FCC_HOSTCLOCK_BASE_US) {
            c->base = s; /* the next rate from here: it follows NTP's slewing */
        }
    }
    return hand_out(c, us);
}

bool fcc_hostclock_extrapolate(fcc_hostclock_t *c, uint64_t tick, uint64_t *us)
{
    if (!c->counter || !c->have_anchor || tick < c->anchor.tick ||
        tick - c->anchor.tick > c->anchor_ticks) {
        return false;
    }
    const double since = (double)(tick - c->anchor.tick) * c->us_per_tick;
    *us = hand_out(c, c->anchor.us + (uint64_t)(since + 0.5)); /* to the nearest */
    return true;
}

uint64_t fcc_hostclock_now(fcc_hostclock_t *c)
{
    if (!c->counter) {
        return fcc_hostclock_monotonic_us();
    }
    const uint64_t before = counter_now();
    uint64_t us;
    if (fcc_hostclock_extrapolate(c, before, &us)) {
        return us;
    }
    us = fcc_hostclock_monotonic_us();
    return fcc_hostclock_sample(c, before, us, counter_now());
}
