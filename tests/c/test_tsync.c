/*
 * test_tsync.c -- the time synchronisation slave (firmware/timesync): the PI
 * servo follows a master with an offset and a rate, and every bad input of
 * fcc_tsync.h is refused, counted and survived: a sync from the past or the
 * future, a jump of the master clock, a missing or orphan follow-up, a
 * repeated sequence, a second time master, a loss of sync and its recovery.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include "fcc_test.h"
#include "fcc_tsync.h"

#define INTERVAL_US 100000u

/* A master clock: m(l) = offset + l (1 + ppm 1e-6). */
typedef struct {
    double offset_us;
    double ppm;
    uint8_t id;
    uint8_t seq;
} master_t;

static uint64_t master_at(const master_t *m, uint64_t local_us)
{
    return (uint64_t)(m->offset_us + (double)local_us * (1.0 + m->ppm * 1e-6));
}

/* One SYNC + FOLLOW_UP pair whose SYNC is received at local time l and left the
 * master at master time mt; returns the follow-up's status. */
static fcc_status_t pair(fcc_tsync_t *ts, master_t *m, uint64_t l, uint64_t mt)
{
    const uint32_t sec = (uint32_t)(mt / 1000000u);
    const uint32_t ns = (uint32_t)(mt % 1000000u) * 1000u;
    const uint8_t seq = m->seq++;
    (void)fcc_tsync_on_sync(ts, m->id, seq, (uint8_t)(INTERVAL_US / 1000u), sec, l);
    return fcc_tsync_on_follow_up(ts, m->id, seq, false, ns);
}

static fcc_tsync_t g_ts;

static void start(fcc_tsync_t *ts)
{
    fcc_tsync_config_t cfg;
    fcc_assert_ok(fcc_tsync_config_default(&cfg));
    fcc_assert_ok(fcc_tsync_init(ts, &cfg));
}

/* n intervals of good pairs from local time *l on. */
static void run(fcc_tsync_t *ts, master_t *m, uint64_t *l, int n)
{
    for (int i = 0; i < n; ++i) {
        *l += INTERVAL_US;
        fcc_assert_ok(pair(ts, m, *l, master_at(m, *l)));
        (void)fcc_tsync_poll(ts, *l + 10u);
    }
}

static int64_t error_at(const fcc_tsync_t *ts, const master_t *m, uint64_t l)
{
    uint64_t est = 0u;
    fcc_assert_ok(fcc_tsync_to_master(ts, l, &est));
    return (int64_t)est - (int64_t)master_at(m, l);
}

/* The estimate of the master's time at local time l is within +-tol us. */
static void assert_error_within(const fcc_tsync_t *ts, const master_t *m, uint64_t l, int64_t tol)
{
    const int64_t e = error_at(ts, m, l);
    if (e > tol || e < -tol) {
        fail_msg("estimate off by %lld us at local %llu us (bound %lld)", (long long)e,
                 (unsigned long long)l, (long long)tol);
    }
}

/* n intervals without any sync from local time *l on, polled at each. */
static void quiet(fcc_tsync_t *ts, uint64_t *l, int n)
{
    for (int i = 0; i < n; ++i) {
        *l += INTERVAL_US;
        (void)fcc_tsync_poll(ts, *l);
    }
}

static void config_is_checked(void **state)
{
    (void)state;
    fcc_tsync_config_t cfg;
    fcc_assert_ok(fcc_tsync_config_default(&cfg));
    cfg.lock_us = cfg.step_us + 1u;
    assert_int_equal(fcc_tsync_init(&g_ts, &cfg), FCC_ERR_RANGE);
    fcc_assert_ok(fcc_tsync_config_default(&cfg));
    cfg.release_intervals = cfg.loss_intervals;
    assert_int_equal(fcc_tsync_init(&g_ts, &cfg), FCC_ERR_RANGE);
    assert_int_equal(fcc_tsync_init(NULL, &cfg), FCC_ERR_ARG);
    assert_int_equal(fcc_tsync_config_default(NULL), FCC_ERR_ARG);
    start(&g_ts);
    uint64_t out = 0u;
    assert_int_equal(fcc_tsync_to_master(&g_ts, 5u, &out), FCC_ERR_AGAIN);
    assert_int_equal(fcc_tsync_to_local(&g_ts, 5u, &out), FCC_ERR_AGAIN);
    assert_false(fcc_tsync_has_time(&g_ts));
    assert_int_equal(g_ts.state, FCC_TSYNC_FREE_RUN);
}

/* Offset 12.3 s and a master 100 ppm fast: locked within a few samples, then
 * the offset to a few microseconds and the rate to a few ppm. */
static void servo_follows_offset_and_rate(void **state)
{
    (void)state;
    start(&g_ts);
    master_t m = {12345678.0, 100.0, 3u, 200u};
    uint64_t l = 5000000u;
    run(&g_ts, &m, &l, 3);
    assert_true(fcc_tsync_has_time(&g_ts));
    run(&g_ts, &m, &l, 150);
    assert_int_equal(g_ts.state, FCC_TSYNC_LOCKED);
    assert_int_equal(g_ts.master, 3u);
    /* residuals are whole microseconds: at 0.1 s per sample the rate estimate moves in
     * steps of 10 ppm / 16 and settles within a few ppm (0.4 us per interval) */
    assert_true(g_ts.rate_ppb > 95000 && g_ts.rate_ppb < 105000);
    /* between two syncs and one interval ahead the estimate holds */
    assert_error_within(&g_ts, &m, l + INTERVAL_US / 2u, 3);
    uint64_t master = 0u;
    uint64_t back = 0u;
    fcc_assert_ok(fcc_tsync_to_master(&g_ts, l + 777u, &master));
    fcc_assert_ok(fcc_tsync_to_local(&g_ts, master, &back));
    assert_true(back + 1u >= l + 777u && back <= l + 778u);
    assert_int_equal(fcc_tsync_rejected(&g_ts), 0u);
    assert_int_equal(g_ts.cnt.samples, 153u);
}

/* Receive-stamp jitter of +-50 us: stays locked, error well under the jitter. */
static void servo_filters_jitter(void **state)
{
    (void)state;
    start(&g_ts);
    master_t m = {1000.0, -40.0, 1u, 0u};
    uint64_t l = 1000000u;
    uint32_t lcg = 12345u;
    for (int i = 0; i < 200; ++i) {
        l += INTERVAL_US;
        lcg = lcg * 1103515245u + 12345u;
        const int64_t jitter = (int64_t)((lcg >> 16) % 101u) - 50;
        fcc_assert_ok(pair(&g_ts, &m, (uint64_t)((int64_t)l + jitter), master_at(&m, l)));
    }
    assert_int_equal(g_ts.state, FCC_TSYNC_LOCKED);
    assert_error_within(&g_ts, &m, l, 39);
    assert_int_equal(fcc_tsync_rejected(&g_ts), 0u);
}

/* A single sync from the past or the future is refused and counted; the
 * estimate is untouched and the node stays locked. */
static void outliers_are_refused(void **state)
{
    (void)state;
    start(&g_ts);
    master_t m = {500000.0, 0.0, 2u, 0u};
    uint64_t l = 0u;
    run(&g_ts, &m, &l, 10);
    l += INTERVAL_US;
    assert_int_equal(pair(&g_ts, &m, l, master_at(&m, l) - 5000u), FCC_ERR_AGAIN);
    assert_int_equal(g_ts.cnt.past, 1u);
    l += INTERVAL_US;
    assert_int_equal(pair(&g_ts, &m, l, master_at(&m, l) + 2000000u), FCC_ERR_AGAIN);
    assert_int_equal(g_ts.cnt.future, 1u);
    assert_int_equal(g_ts.state, FCC_TSYNC_LOCKED);
    assert_error_within(&g_ts, &m, l, 1);
    run(&g_ts, &m, &l, 3);
    assert_int_equal(g_ts.cnt.jumps, 0u);
    assert_int_equal(fcc_tsync_rejected(&g_ts), 2u);
}

/* The master clock jumps by +3 s (or is set back): three agreeing outliers in
 * a row are a jump; the estimate re-steps and locks to the new time base. */
static void master_clock_jump_is_followed(void **state)
{
    (void)state;
    for (int dir = 0; dir < 2; ++dir) {
        start(&g_ts);
        master_t m = {10000000.0, 20.0, 4u, 0u};
        uint64_t l = 0u;
        run(&g_ts, &m, &l, 10);
        m.offset_us += (dir == 0) ? 3000000.0 : -3000000.0;
        for (int i = 0; i < 2; ++i) {
            l += INTERVAL_US;
            assert_int_equal(pair(&g_ts, &m, l, master_at(&m, l)), FCC_ERR_AGAIN);
        }
        l += INTERVAL_US;
        fcc_assert_ok(pair(&g_ts, &m, l, master_at(&m, l)));
        assert_int_equal(g_ts.cnt.jumps, 1u);
        assert_int_equal(g_ts.state, FCC_TSYNC_LOCKING);
        run(&g_ts, &m, &l, 5);
        assert_int_equal(g_ts.state, FCC_TSYNC_LOCKED);
        assert_error_within(&g_ts, &m, l, 2);
        if (dir == 1) {
            assert_true(g_ts.cnt.backwards >= 1u && g_ts.cnt.past == 3u);
        } else {
            assert_int_equal(g_ts.cnt.future, 3u);
        }
    }
}

/* Follow-ups: missing (next SYNC first, or the poll timeout), orphan (wrong
 * sequence, none pending), and a repeated SYNC sequence (a replay). */
static void follow_up_faults_are_counted(void **state)
{
    (void)state;
    start(&g_ts);
    master_t m = {0.0, 0.0, 5u, 10u};
    uint64_t l = 1000000u;
    run(&g_ts, &m, &l, 5);
    l += INTERVAL_US;
    fcc_assert_ok(fcc_tsync_on_sync(&g_ts, 5u, 50u, 100u, 1u, l));
    l += INTERVAL_US;
    fcc_assert_ok(fcc_tsync_on_sync(&g_ts, 5u, 51u, 100u, 1u, l)); /* 50 never followed */
    assert_int_equal(g_ts.cnt.missing_fup, 1u);
    (void)fcc_tsync_poll(&g_ts, l + 2u * INTERVAL_US);                /* 51 neither */
    assert_int_equal(g_ts.cnt.missing_fup, 2u);
    assert_int_equal(fcc_tsync_on_follow_up(&g_ts, 5u, 51u, false, 0u), FCC_ERR_AGAIN);
    assert_int_equal(g_ts.cnt.orphan_fup, 1u);
    fcc_assert_ok(fcc_tsync_on_sync(&g_ts, 5u, 52u, 100u, 1u, l + 2u * INTERVAL_US));
    assert_int_equal(fcc_tsync_on_follow_up(&g_ts, 5u, 53u, false, 0u), FCC_ERR_AGAIN);
    assert_int_equal(g_ts.cnt.orphan_fup, 2u);
    assert_int_equal(fcc_tsync_on_sync(&g_ts, 5u, 52u, 100u, 1u, l + 3u * INTERVAL_US),
                     FCC_ERR_AGAIN);
    assert_int_equal(g_ts.cnt.repeated_seq, 1u);
    assert_int_equal(g_ts.cnt.missing_fup, 3u); /* 52's follow-up never came either */
    m.seq = 60u;
    l += 4u * INTERVAL_US;
    run(&g_ts, &m, &l, 2);
    assert_true(fcc_tsync_has_time(&g_ts));
    assert_int_equal(fcc_tsync_rejected(&g_ts), 6u);
}

/* A second time master on the bus is counted and never followed while the
 * first one is alive; after the first is gone for good it is accepted. */
static void second_master_is_ignored(void **state)
{
    (void)state;
    start(&g_ts);
    master_t a = {0.0, 0.0, 1u, 0u};
    master_t b = {7000000.0, 0.0, 2u, 0u};
    uint64_t l = 0u;
    for (int i = 0; i < 20; ++i) {
        l += INTERVAL_US;
        fcc_assert_ok(pair(&g_ts, &a, l, master_at(&a, l)));
        assert_int_equal(pair(&g_ts, &b, l + 300u, master_at(&b, l + 300u)), FCC_ERR_AGAIN);
    }
    assert_int_equal(g_ts.cnt.foreign, 40u);
    assert_int_equal(g_ts.master, 1u);
    assert_int_equal(g_ts.state, FCC_TSYNC_LOCKED);
    assert_error_within(&g_ts, &a, l, 1);
    /* master 1 disappears: holdover, then release, then master 2 is followed */
    quiet(&g_ts, &l, 60);
    assert_int_equal(g_ts.state, FCC_TSYNC_FREE_RUN);
    assert_int_equal(g_ts.cnt.releases, 1u);
    run(&g_ts, &b, &l, 5);
    assert_int_equal(g_ts.master, 2u);
    assert_int_equal(g_ts.state, FCC_TSYNC_LOCKED);
}

/* Loss of sync: holdover after 3 quiet intervals (the estimate goes on),
 * recovery on the next good pair, counted both ways. */
static void loss_and_recovery(void **state)
{
    (void)state;
    start(&g_ts);
    master_t m = {250000.0, 30.0, 6u, 0u};
    uint64_t l = 0u;
    run(&g_ts, &m, &l, 30);
    assert_int_equal(g_ts.state, FCC_TSYNC_LOCKED);
    quiet(&g_ts, &l, 10);
    assert_int_equal(g_ts.state, FCC_TSYNC_HOLDOVER);
    assert_int_equal(g_ts.cnt.losses, 1u);
    assert_true(fcc_tsync_has_time(&g_ts)); /* free-runs on the last estimate */
    assert_error_within(&g_ts, &m, l, 20); /* 1 s at a well-estimated rate */
    run(&g_ts, &m, &l, 1);
    assert_int_equal(g_ts.cnt.recoveries, 1u);
    run(&g_ts, &m, &l, 4);
    assert_int_equal(g_ts.state, FCC_TSYNC_LOCKED);
    assert_int_equal(fcc_tsync_poll(NULL, 0u), FCC_TSYNC_FREE_RUN);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(config_is_checked),
        cmocka_unit_test(servo_follows_offset_and_rate),
        cmocka_unit_test(servo_filters_jitter),
        cmocka_unit_test(outliers_are_refused),
        cmocka_unit_test(master_clock_jump_is_followed),
        cmocka_unit_test(follow_up_faults_are_counted),
        cmocka_unit_test(second_master_is_ignored),
        cmocka_unit_test(loss_and_recovery),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
