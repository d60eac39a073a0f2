/*
 * test_hostclock.c -- the Linux port's clock through the time-stamp counter
 * (firmware/port/linux/fcc_hostclock.h): its arithmetic driven with chosen counter and
 * clock values (a counter of 2,500 ticks per microsecond, as on the build machine), and
 * the real clock bracketed by clock_gettime.
 */
#define _DEFAULT_SOURCE 1 /* clock_gettime under -std=c99 */

#include "fcc_test.h"

#include <time.h>

#include "fcc_hostclock.h"

#define TICKS_PER_US 2500u
#define OFFSET 123456789u /* the counter's value at clock 0 */

static uint64_t tick_at(uint64_t us)
{
    return OFFSET + us * TICKS_PER_US;
}

/* A real read at us with a bracket of half_us either side. */
static uint64_t sample_at(fcc_hostclock_t *c, uint64_t us, uint64_t half_us)
{
    return fcc_hostclock_sample(c, tick_at(us) - half_us * TICKS_PER_US, us,
                                tick_at(us) + half_us * TICKS_PER_US);
}

/* Samples 2 us wide, 30 ms apart: the anchor good for FCC_HOSTCLOCK_ANCHOR_US. */
static void calibrate(fcc_hostclock_t *c)
{
    fcc_hostclock_init(c, true);
    (void)sample_at(c, 1000000u, 1u);
    (void)sample_at(c, 1030000u, 1u);
}

static void test_without_counter_every_read_is_real(void **state)
{
    (void)state;
    fcc_hostclock_t c;
    fcc_hostclock_init(&c, false);
    assert_int_equal(sample_at(&c, 1000000u, 1u), 1000000u);
    assert_int_equal(sample_at(&c, 2000000u, 1u), 2000000u);
    uint64_t us = 0u;
    assert_false(fcc_hostclock_extrapolate(&c, tick_at(2000010u), &us));
}

static void test_anchor_age_from_the_rate_error(void **state)
{
    (void)state;
    fcc_hostclock_t c;
    fcc_hostclock_init(&c, true);
    uint64_t us = 0u;
    (void)sample_at(&c, 1000000u, 1u);
    assert_false(fcc_hostclock_extrapolate(&c, tick_at(1000100u), &us)); /* one sample */
    /* 1 ms apart, 2 us of brackets and 1 us of the readings' truncation: the rate to
     * 3e-3, the anchor good for 1 us / 3e-3 */
    (void)sample_at(&c, 1001000u, 1u);
    assert_true(fcc_hostclock_extrapolate(&c, tick_at(1001333u), &us));
    assert_int_equal(us, 1001333u);
    assert_false(fcc_hostclock_extrapolate(&c, tick_at(1001334u), &us));
    /* 30 ms: 1e-4, FCC_HOSTCLOCK_ANCHOR_US */
    (void)sample_at(&c, 1030000u, 1u);
    assert_true(fcc_hostclock_extrapolate(&c, tick_at(1030000u + FCC_HOSTCLOCK_ANCHOR_US), &us));
    assert_int_equal(us, 1030000u + FCC_HOSTCLOCK_ANCHOR_US);
}

static void test_base_is_the_narrowest_bracket_until_the_rate_is_known(void **state)
{
    (void)state;
    fcc_hostclock_t c;
    fcc_hostclock_init(&c, true);
    uint64_t us = 0u;
    (void)sample_at(&c, 1000000u, 500u);  /* preempted: a wide bracket */
    (void)sample_at(&c, 1001000u, 1u);    /* the base from here */
    (void)sample_at(&c, 1031000u, 1u);    /* 30 ms from the narrow one: trusted */
    assert_true(fcc_hostclock_extrapolate(&c, tick_at(1031500u), &us));
    assert_int_equal(us, 1031500u);
}

static void test_extrapolates_within_the_anchor_age_only(void **state)
{
    (void)state;
    fcc_hostclock_t c;
    calibrate(&c);
    uint64_t us = 0u;
    assert_true(fcc_hostclock_extrapolate(&c, tick_at(1030000u + FCC_HOSTCLOCK_ANCHOR_US), &us));
    assert_int_equal(us, 1030000u + FCC_HOSTCLOCK_ANCHOR_US);
    assert_false(fcc_hostclock_extrapolate(&c, tick_at(1030001u + FCC_HOSTCLOCK_ANCHOR_US), &us));
    /* a real read renews the anchor */
    assert_int_equal(sample_at(&c, 1040000u, 1u), 1040000u);
    assert_true(fcc_hostclock_extrapolate(&c, tick_at(1043000u), &us));
    assert_int_equal(us, 1043000u);
    /* a counter value before the anchor's (another core's, out of step): a real read */
    assert_false(fcc_hostclock_extrapolate(&c, tick_at(1039000u), &us));
}

static void test_wide_bracket_is_no_anchor(void **state)
{
    (void)state;
    fcc_hostclock_t c;
    calibrate(&c);
    uint64_t us = 0u;
    /* 2 x 15 us > FCC_HOSTCLOCK_BRACKET_US: the old anchor stays, and it is too old */
    assert_int_equal(sample_at(&c, 1040000u, 15u), 1040000u);
    assert_false(fcc_hostclock_extrapolate(&c, tick_at(1040100u), &us));
    assert_int_equal(sample_at(&c, 1040200u, 5u), 1040200u);
    assert_true(fcc_hostclock_extrapolate(&c, tick_at(1040300u), &us));
    assert_int_equal(us, 1040300u);
}

static void test_never_backwards(void **state)
{
    (void)state;
    fcc_hostclock_t c;
    calibrate(&c);
    uint64_t us = 0u;
    assert_true(fcc_hostclock_extrapolate(&c, tick_at(1034010u), &us));
    assert_int_equal(us, 1034010u);
    /* the clock says 3 us less than the counter did: the time stands until it passes */
    assert_int_equal(fcc_hostclock_sample(&c, tick_at(1034010u), 1034007u, tick_at(1034012u)),
                     1034010u);
    assert_true(fcc_hostclock_extrapolate(&c, tick_at(1034012u), &us));
    assert_int_equal(us, 1034010u);
    assert_true(fcc_hostclock_extrapolate(&c, tick_at(1034020u), &us));
    assert_int_equal(us, 1034016u);
}

static void test_rate_follows_the_clock_after_the_base_moves(void **state)
{
    (void)state;
    fcc_hostclock_t c;
    calibrate(&c);
    /* samples every 4 ms for the base's span: the base moves on at its end */
    uint64_t t = 1030000u;
    while (t < 1000000u + FCC_HOSTCLOCK_BASE_US + 8000u) {
        t += 4000u;
        (void)sample_at(&c, t, 1u);
    }
    assert_true(c.base.us > 1000000u);
    /* from here the clock runs 200 ppm slower than the counter (NTP slewing it) */
    const uint64_t t0 = t;
    for (int i = 0; i < 75; ++i) { /* 300 ms: the new rate measured to 1e-5 */
        t += 4000u;
        const uint64_t clock = t0 + (t - t0) - (t - t0) / 5000u;
        (void)fcc_hostclock_sample(&c, tick_at(t) - TICKS_PER_US, clock, tick_at(t) + TICKS_PER_US);
    }
    uint64_t us = 0u;
    assert_true(fcc_hostclock_extrapolate(&c, tick_at(t + 5000u), &us));
    const uint64_t want = t0 + (t + 5000u - t0) - (t + 5000u - t0) / 5000u;
    assert_true(us + 1u >= want && us <= want + 1u);
}

/* A real read at ns nanoseconds, as on a host whose clock_gettime takes 20 ns: a bracket
 * of 50 ticks and the clock in whole microseconds. */
static void sample_at_ns(fcc_hostclock_t *c, uint64_t ns)
{
    const uint64_t tick = OFFSET + ns * TICKS_PER_US / 1000u;
    (void)fcc_hostclock_sample(c, tick - 25u, ns / 1000u, tick + 25u);
}

/* Reads 1.7 us apart for 20 ms, each followed by extrapolations as far as the anchor
 * allows: within the drift, the truncation and rounding of the true time.  (With the
 * truncation left out of the rate's error, 1 us over the first microseconds' span passed
 * for 2e-5 and the time ran up to 14 us ahead.) */
static void test_whole_microsecond_readings_bound_the_rate(void **state)
{
    (void)state;
    fcc_hostclock_t c;
    fcc_hostclock_init(&c, true);
    for (uint64_t ns = 1000000000u; ns < 1020000000u; ns += 1700u) {
        sample_at_ns(&c, ns);
        for (uint64_t ahead = 0u; ahead <= 1000u * FCC_HOSTCLOCK_ANCHOR_US; ahead += 50000u) {
            fcc_hostclock_t probe = c; /* extrapolating moves the last time handed out */
            const uint64_t t = ns + ahead;
            uint64_t us = 0u;
            if (!fcc_hostclock_extrapolate(&probe, OFFSET + t * TICKS_PER_US / 1000u, &us)) {
                break;
            }
            assert_true(us + FCC_HOSTCLOCK_DRIFT_US + 2u >= t / 1000u);
            assert_true(us <= t / 1000u + FCC_HOSTCLOCK_DRIFT_US + 2u);
        }
    }
}

static uint64_t clock_us(void)
{
    struct timespec ts;
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000u + (uint64_t)ts.tv_nsec / 1000u;
}

/* The real clock: never backwards, and between two clock_gettime around it (give or take
 * the extrapolation's bound: an anchor's half bracket and the rate's error). */
static void test_real_clock_within_clock_gettime(void **state)
{
    (void)state;
    fcc_hostclock_t c;
    fcc_hostclock_init(&c, fcc_hostclock_has_counter());
    uint64_t last = 0u;
    for (int i = 0; i < 200000; ++i) {
        const uint64_t before = clock_us();
        const uint64_t now = fcc_hostclock_now(&c);
        const uint64_t after = clock_us();
        assert_true(now >= last);
        assert_true(now + FCC_HOSTCLOCK_BRACKET_US >= before);
        assert_true(now <= after + FCC_HOSTCLOCK_BRACKET_US);
        last = now;
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_without_counter_every_read_is_real),
        cmocka_unit_test(test_anchor_age_from_the_rate_error),
        cmocka_unit_test(test_base_is_the_narrowest_bracket_until_the_rate_is_known),
        cmocka_unit_test(test_extrapolates_within_the_anchor_age_only),
        cmocka_unit_test(test_wide_bracket_is_no_anchor),
        cmocka_unit_test(test_never_backwards),
        cmocka_unit_test(test_rate_follows_the_clock_after_the_base_moves),
        cmocka_unit_test(test_whole_microsecond_readings_bound_the_rate),
        cmocka_unit_test(test_real_clock_within_clock_gettime),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
