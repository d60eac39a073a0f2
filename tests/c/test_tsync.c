/*
 * test_tsync.c -- the time synchronisation slave (firmware/timesync): the PI
 * servo follows a master with an offset and a rate, and every bad input of
 * fcc_tsync.h is refused, counted and survived: a sync from the past or the
 * future, a jump of the master clock, a drag of its rate, a missing or orphan
 * follow-up, a repeated sequence, a second time master, a loss of sync and its
 * recovery; and the authenticated receiver (fcc_tsync_auth.h): only a pair
 * whose TSYNC_AUTH verifies gets through, forged, pre-empting and replayed
 * frames are refused and counted.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <string.h>

#include "fcc_test.h"
#include "fcc_tsync.h"
#include "fcc_tsync_auth.h"

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

/* A single sync from the past or the future is refused and counted: beyond
 * the step bound against the own clock (which is the servo's outlier gate too),
 * the state is REFUSED for that pair; the estimate is untouched and the next
 * good pair recovers. */
static void outliers_are_refused(void **state)
{
    (void)state;
    start(&g_ts);
    master_t m = {500000.0, 0.0, 2u, 0u};
    uint64_t l = 0u;
    run(&g_ts, &m, &l, 10);
    l += INTERVAL_US;
    assert_int_equal(pair(&g_ts, &m, l, master_at(&m, l) - 5000u), FCC_ERR_AGAIN);
    assert_int_equal(g_ts.cnt.step_refused, 1u);
    assert_int_equal(g_ts.state, FCC_TSYNC_REFUSED);
    assert_true(fcc_tsync_has_time(&g_ts)); /* the estimate goes on */
    run(&g_ts, &m, &l, 1);
    assert_int_equal(g_ts.cnt.recoveries, 1u);
    l += INTERVAL_US;
    assert_int_equal(pair(&g_ts, &m, l, master_at(&m, l) + 2000000u), FCC_ERR_AGAIN);
    assert_int_equal(g_ts.cnt.step_refused, 2u);
    assert_error_within(&g_ts, &m, l, 1);
    run(&g_ts, &m, &l, 3);
    assert_int_equal(g_ts.state, FCC_TSYNC_LOCKED);
    assert_int_equal(g_ts.cnt.jumps, 0u);
    assert_int_equal(fcc_tsync_rejected(&g_ts), 2u);
}

/* The master clock jumps by +-3 s (an authenticated master that steps): every
 * pair of the new time base is refused (step), the estimate goes on on the old
 * one, for as long as it lasts; only a rebase (an authenticated RESET on the
 * ground) lets fcc follow the new time base. */
static void master_clock_jump_is_refused(void **state)
{
    (void)state;
    for (int dir = 0; dir < 2; ++dir) {
        start(&g_ts);
        master_t m = {10000000.0, 20.0, 4u, 0u};
        uint64_t l = 0u;
        run(&g_ts, &m, &l, 10);
        assert_int_equal(g_ts.state, FCC_TSYNC_LOCKED);
        assert_int_equal(fcc_tsync_rebase(&g_ts), FCC_ERR_AGAIN); /* followed: nothing to do */
        master_t old = m;
        m.offset_us += (dir == 0) ? 3000000.0 : -3000000.0;
        for (int i = 0; i < 100; ++i) {
            l += INTERVAL_US;
            assert_int_equal(pair(&g_ts, &m, l, master_at(&m, l)), FCC_ERR_AGAIN);
            (void)fcc_tsync_poll(&g_ts, l + 10u);
        }
        assert_int_equal(g_ts.cnt.step_refused, 100u);
        assert_int_equal(g_ts.cnt.rate_refused + g_ts.cnt.jumps + g_ts.cnt.losses, 0u);
        assert_int_equal(g_ts.state, FCC_TSYNC_REFUSED);
        assert_true(fcc_tsync_has_time(&g_ts));
        assert_error_within(&g_ts, &old, l, 25); /* 10 s on the old base at 20 ppm */
        fcc_assert_ok(fcc_tsync_rebase(&g_ts));
        assert_int_equal(g_ts.state, FCC_TSYNC_FREE_RUN);
        run(&g_ts, &m, &l, 5);
        assert_int_equal(g_ts.state, FCC_TSYNC_LOCKED);
        assert_error_within(&g_ts, &m, l, 2);
    }
}

/* With a step bound above the servo's gate, a jump inside it is still the
 * servo's: three agreeing outliers re-step the estimate. */
static void jump_within_the_bound_is_followed(void **state)
{
    (void)state;
    fcc_tsync_config_t cfg;
    fcc_assert_ok(fcc_tsync_config_default(&cfg));
    cfg.max_step_us = 5000u;
    fcc_assert_ok(fcc_tsync_init(&g_ts, &cfg));
    master_t m = {10000000.0, 0.0, 4u, 0u};
    uint64_t l = 0u;
    run(&g_ts, &m, &l, 10);
    m.offset_us -= 3000.0;
    for (int i = 0; i < 2; ++i) {
        l += INTERVAL_US;
        assert_int_equal(pair(&g_ts, &m, l, master_at(&m, l)), FCC_ERR_AGAIN);
    }
    l += INTERVAL_US;
    fcc_assert_ok(pair(&g_ts, &m, l, master_at(&m, l)));
    assert_int_equal(g_ts.cnt.jumps, 1u);
    assert_int_equal(g_ts.cnt.past, 3u);
    run(&g_ts, &m, &l, 5);
    assert_int_equal(g_ts.state, FCC_TSYNC_LOCKED);
    assert_error_within(&g_ts, &m, l, 2);
}

/* A master dragged at 4 ms/s (4000 ppm) from a locked state: the first pairs
 * stay inside the step bound, then it leaves the rate bound and every pair is
 * refused (rate); what it imposed on the estimate stays under the step bound.
 * A master 150 ppm off (inside the 200 ppm bound) is followed throughout, one
 * 300 ppm off is refused within a few seconds. */
static void drag_is_bounded(void **state)
{
    (void)state;
    start(&g_ts);
    master_t m = {2000000.0, 0.0, 7u, 0u};
    uint64_t l = 0u;
    run(&g_ts, &m, &l, 20);
    master_t drag = m;
    drag.offset_us += 4000.0 * 1e-6 * (double)l; /* same time now, 4000 ppm slower from here */
    drag.ppm = -4000.0;
    int used = 0;
    for (int i = 0; i < 100; ++i) {
        l += INTERVAL_US;
        used += pair(&g_ts, &drag, l, master_at(&drag, l)) == FCC_OK;
        (void)fcc_tsync_poll(&g_ts, l + 10u);
    }
    assert_true(used <= 3);
    assert_int_equal(g_ts.cnt.rate_refused, (uint32_t)(100 - used));
    assert_int_equal(g_ts.cnt.step_refused, 0u);
    assert_int_equal(g_ts.state, FCC_TSYNC_REFUSED);
    assert_error_within(&g_ts, &m, l, (int64_t)g_ts.cfg.max_step_us);
    for (int k = 0; k < 2; ++k) {
        start(&g_ts);
        master_t r = {1000.0, (k == 0) ? 150.0 : -300.0, 8u, 0u};
        l = 0u;
        for (int i = 0; i < 300; ++i) { /* 30 s */
            l += INTERVAL_US;
            (void)pair(&g_ts, &r, l, master_at(&r, l));
            (void)fcc_tsync_poll(&g_ts, l + 10u);
        }
        if (k == 0) {
            assert_int_equal(g_ts.state, FCC_TSYNC_LOCKED);
            assert_int_equal(fcc_tsync_rejected(&g_ts), 0u);
        } else {
            /* 100 ppm beyond the bound: out of the 1 ms step bound after 10 s */
            assert_int_equal(g_ts.state, FCC_TSYNC_REFUSED);
            assert_true(g_ts.cnt.rate_refused >= 150u && g_ts.cnt.step_refused == 0u);
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
    /* master 1 disappears: holdover, then lost (released); master 2's pairs are
     * authentic but 7 s off the own clock's time base: refused, until a rebase */
    quiet(&g_ts, &l, 60);
    assert_int_equal(g_ts.state, FCC_TSYNC_LOST);
    assert_false(fcc_tsync_has_time(&g_ts));
    assert_int_equal(g_ts.cnt.releases, 1u);
    l += INTERVAL_US;
    assert_int_equal(pair(&g_ts, &b, l, master_at(&b, l)), FCC_ERR_AGAIN);
    assert_int_equal(g_ts.state, FCC_TSYNC_REFUSED);
    assert_false(fcc_tsync_has_time(&g_ts));
    fcc_assert_ok(fcc_tsync_rebase(&g_ts));
    run(&g_ts, &b, &l, 5);
    assert_int_equal(g_ts.master, 2u);
    assert_int_equal(g_ts.state, FCC_TSYNC_LOCKED);
    /* master 1 back within its time base after a loss: followed again without a rebase */
    start(&g_ts);
    l = 0u;
    run(&g_ts, &a, &l, 10);
    quiet(&g_ts, &l, 60);
    assert_int_equal(g_ts.state, FCC_TSYNC_LOST);
    run(&g_ts, &a, &l, 5);
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

/* ---- the authenticated receiver ------------------------------------------------ */

static const uint8_t k_key[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};

/* A SYNC / FOLLOW_UP as the DBC lays them out where the receiver looks (byte 1
 * high nibble: master, byte 2: seq); the rest stands for the payload. */
static void tsync_frame(uint8_t master, uint8_t seq, uint8_t salt, uint8_t out[8])
{
    for (unsigned int b = 0u; b < 8u; ++b) {
        out[b] = (uint8_t)(salt * 13u + b);
    }
    out[1] = (uint8_t)((master << 4) | (salt & 0x0Fu));
    out[2] = seq;
}

typedef struct {
    fcc_secoc_t tx, rx;
    uint32_t i;
    fcc_tsync_auth_t ta;
} tsauth_t;

static tsauth_t g_a;

static void tsauth_start(void)
{
    fcc_assert_ok(fcc_secoc_init(&g_a.tx, k_key, 0x5EEDu));
    fcc_assert_ok(fcc_secoc_init(&g_a.rx, k_key, 0x5EEDu));
    assert_true(fcc_secoc_auth_index(FCC_MSG_TSYNC_AUTH, &g_a.i));
    fcc_assert_ok(fcc_tsync_auth_init(&g_a.ta));
}

/* The master's authenticator of sync | fup. */
static void master_auth(fcc_secoc_t *tx, const uint8_t sync[8], const uint8_t fup[8],
                        uint8_t auth[8])
{
    uint8_t pdu[16];
    memcpy(pdu, sync, 8u);
    memcpy(&pdu[8], fup, 8u);
    fcc_can_frame_t f;
    fcc_assert_ok(fcc_secoc_protect(tx, g_a.i, pdu, 16u, &f));
    assert_int_equal(f.id, FCC_MSG_TSYNC_AUTH_ID);
    memcpy(auth, f.data, 8u);
}

static fcc_secoc_verdict_t verify(uint8_t sync_out[8], uint64_t *t_out, uint8_t fup_out[8],
                                  const uint8_t auth[8])
{
    fcc_tsync_held_t h;
    const fcc_secoc_verdict_t v = fcc_tsync_auth_verify(&g_a.ta, &g_a.rx, g_a.i, auth, &h, fup_out);
    if (v == FCC_SECOC_VERIFIED) {
        memcpy(sync_out, h.data, 8u);
        *t_out = h.t_us;
    }
    return v;
}

/* The red team's attack: forged SYNC + FOLLOW_UP of the same master and
 * sequence number ahead of the master's (pre-empting its E2E counters), with
 * and without a forged authenticator; a replayed authenticator; a forged pair
 * squeezed in after the master's.  Only the master's pair, with its own
 * receive stamp, comes out; each refusal is counted. */
static void authenticated_pairs_only(void **state)
{
    (void)state;
    tsauth_start();
    uint8_t sync[8], fup[8], auth[8], fs[8], ff[8], out_s[8], out_f[8];
    uint64_t t = 0u;
    /* the genuine triple */
    tsync_frame(1u, 10u, 1u, sync);
    tsync_frame(1u, 10u, 2u, fup);
    master_auth(&g_a.tx, sync, fup, auth);
    fcc_assert_ok(fcc_tsync_auth_hold_sync(&g_a.ta, sync, 1000u));
    fcc_assert_ok(fcc_tsync_auth_hold_follow_up(&g_a.ta, fup));
    assert_int_equal(verify(out_s, &t, out_f, auth), FCC_SECOC_VERIFIED);
    assert_memory_equal(out_s, sync, 8u);
    assert_memory_equal(out_f, fup, 8u);
    assert_int_equal(t, 1000u);
    uint8_t old_auth[8];
    memcpy(old_auth, auth, 8u);
    /* forged pair first (same master and seq, other bytes), then the genuine one */
    tsync_frame(1u, 11u, 7u, fs);
    tsync_frame(1u, 11u, 8u, ff);
    tsync_frame(1u, 11u, 3u, sync);
    tsync_frame(1u, 11u, 4u, fup);
    fcc_assert_ok(fcc_tsync_auth_hold_sync(&g_a.ta, fs, 1990u));
    fcc_assert_ok(fcc_tsync_auth_hold_follow_up(&g_a.ta, ff));
    uint8_t forged_auth[8] = {2u, 0u, 1u, 2u, 3u, 4u, 5u, 6u};
    assert_int_equal(verify(out_s, &t, out_f, forged_auth), FCC_SECOC_MAC_FAILED);
    assert_int_equal(verify(out_s, &t, out_f, old_auth), FCC_SECOC_FRESHNESS_FAILED);
    fcc_assert_ok(fcc_tsync_auth_hold_sync(&g_a.ta, sync, 2000u));
    fcc_assert_ok(fcc_tsync_auth_hold_follow_up(&g_a.ta, fup));
    tsync_frame(1u, 11u, 9u, ff); /* another forged FOLLOW_UP, just before the authenticator */
    fcc_assert_ok(fcc_tsync_auth_hold_follow_up(&g_a.ta, ff));
    master_auth(&g_a.tx, sync, fup, auth);
    assert_int_equal(verify(out_s, &t, out_f, auth), FCC_SECOC_VERIFIED);
    assert_memory_equal(out_s, sync, 8u);
    assert_memory_equal(out_f, fup, 8u);
    assert_int_equal(t, 2000u);
    /* the forged pair held before it is dropped; the later forged FOLLOW_UP waits */
    assert_int_equal(g_a.ta.cnt.unauthenticated, 2u);
    assert_int_equal(g_a.ta.n_sync, 0u);
    assert_int_equal(g_a.ta.n_fup, 1u);
    assert_int_equal(g_a.ta.cnt.mac_failed, 1u);
    assert_int_equal(g_a.ta.cnt.freshness_failed, 1u);
    assert_int_equal(g_a.rx.cnt.verified, 2u);
    /* a forged pair alone never verifies, whatever authenticator comes */
    tsync_frame(1u, 12u, 5u, fs);
    fcc_assert_ok(fcc_tsync_auth_hold_sync(&g_a.ta, fs, 3000u));
    tsync_frame(1u, 12u, 6u, ff);
    fcc_assert_ok(fcc_tsync_auth_hold_follow_up(&g_a.ta, ff));
    master_auth(&g_a.tx, sync, fup, auth); /* a genuine authenticator of other frames */
    assert_int_equal(verify(out_s, &t, out_f, auth), FCC_SECOC_MAC_FAILED);
    forged_auth[0] = 5u; /* a fresh counter, a guessed MAC */
    assert_int_equal(verify(out_s, &t, out_f, forged_auth), FCC_SECOC_MAC_FAILED);
    /* an authenticator with no pair to match (other seq): NO_PDU, a MAC failure */
    fcc_tsync_auth_t empty;
    fcc_assert_ok(fcc_tsync_auth_init(&empty));
    fcc_tsync_held_t h;
    assert_int_equal(fcc_tsync_auth_verify(&empty, &g_a.rx, g_a.i, auth, &h, out_f),
                     FCC_SECOC_NO_PDU);
    assert_int_equal(empty.cnt.mac_failed, 1u);
    assert_int_equal(fcc_tsync_auth_verify(NULL, &g_a.rx, g_a.i, auth, &h, out_f),
                     FCC_SECOC_NO_PDU);
}

/* A flood of SYNCs and FOLLOW_UPs of one sequence number: at most
 * FCC_SECOC_CANDIDATES MACs per authenticator, the oldest held frames go
 * (counted); the newest genuine pair still verifies. */
static void candidates_are_bounded(void **state)
{
    (void)state;
    tsauth_start();
    uint8_t sync[8], fup[8], auth[8], x[8], out_s[8], out_f[8];
    uint64_t t = 0u;
    for (uint8_t k = 0u; k < 10u; ++k) {
        tsync_frame(1u, 20u, (uint8_t)(100u + k), x);
        fcc_assert_ok(fcc_tsync_auth_hold_sync(&g_a.ta, x, k));
        fcc_assert_ok(fcc_tsync_auth_hold_follow_up(&g_a.ta, x));
    }
    assert_int_equal(g_a.ta.cnt.unauthenticated, 12u); /* 6 of each pushed out */
    tsync_frame(1u, 20u, 1u, sync);
    tsync_frame(1u, 20u, 2u, fup);
    fcc_assert_ok(fcc_tsync_auth_hold_sync(&g_a.ta, sync, 77u));
    fcc_assert_ok(fcc_tsync_auth_hold_follow_up(&g_a.ta, fup));
    master_auth(&g_a.tx, sync, fup, auth);
    assert_int_equal(verify(out_s, &t, out_f, auth), FCC_SECOC_VERIFIED);
    assert_int_equal(t, 77u);
    assert_int_equal(g_a.ta.cnt.unauthenticated, 12u + 2u + 6u); /* 2 more pushed out, 6 older */
    /* the genuine pair behind 3 newer forged FOLLOW_UPs: 4 candidates x 4 SYNCs, beyond the
     * bound of 4 MACs -- refused (a denial, counted), never a forgery accepted */
    tsync_frame(1u, 21u, 1u, sync);
    tsync_frame(1u, 21u, 2u, fup);
    fcc_assert_ok(fcc_tsync_auth_hold_sync(&g_a.ta, sync, 88u));
    fcc_assert_ok(fcc_tsync_auth_hold_follow_up(&g_a.ta, fup));
    for (uint8_t k = 0u; k < 3u; ++k) {
        tsync_frame(1u, 21u, (uint8_t)(50u + k), x);
        fcc_assert_ok(fcc_tsync_auth_hold_sync(&g_a.ta, x, 90u + k));
        fcc_assert_ok(fcc_tsync_auth_hold_follow_up(&g_a.ta, x));
    }
    master_auth(&g_a.tx, sync, fup, auth);
    assert_int_equal(verify(out_s, &t, out_f, auth), FCC_SECOC_MAC_FAILED);
}

/* ---- each condition deciding on its own (MC/DC, scripts/test coverage) ---------------- */

/* Each of fcc_tsync_init's limits refuses a configuration by itself; the lock bound may equal
 * the step bound. */
static void each_config_limit_alone(void **state)
{
    (void)state;
    fcc_tsync_config_t ok;
    fcc_assert_ok(fcc_tsync_config_default(&ok));
    fcc_tsync_config_t c = ok;
    c.step_us = 0u;
    assert_int_equal(fcc_tsync_init(&g_ts, &c), FCC_ERR_RANGE);
    c = ok;
    c.lock_count = 0u;
    assert_int_equal(fcc_tsync_init(&g_ts, &c), FCC_ERR_RANGE);
    c = ok;
    c.jump_count = 0u;
    assert_int_equal(fcc_tsync_init(&g_ts, &c), FCC_ERR_RANGE);
    c = ok;
    c.loss_intervals = 0u;
    assert_int_equal(fcc_tsync_init(&g_ts, &c), FCC_ERR_RANGE);
    c = ok;
    c.max_rate_ppb = 0;
    assert_int_equal(fcc_tsync_init(&g_ts, &c), FCC_ERR_RANGE);
    c.max_rate_ppb = -1;
    assert_int_equal(fcc_tsync_init(&g_ts, &c), FCC_ERR_RANGE);
    c = ok;
    c.max_step_us = 0u;
    assert_int_equal(fcc_tsync_init(&g_ts, &c), FCC_ERR_RANGE);
    assert_int_equal(fcc_tsync_init(&g_ts, NULL), FCC_ERR_ARG);
    c = ok;
    c.lock_us = c.step_us;
    fcc_assert_ok(fcc_tsync_init(&g_ts, &c));
}

/* Time is told only from a reference, in a state that keeps one; to_local undoes to_master. */
static void time_needs_a_reference(void **state)
{
    (void)state;
    uint64_t out = 0u;
    assert_false(fcc_tsync_has_time(NULL));
    start(&g_ts);
    assert_int_equal(fcc_tsync_to_master(NULL, 0u, &out), FCC_ERR_ARG);
    assert_int_equal(fcc_tsync_to_master(&g_ts, 0u, NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_tsync_to_local(NULL, 0u, &out), FCC_ERR_ARG);
    assert_int_equal(fcc_tsync_to_local(&g_ts, 0u, NULL), FCC_ERR_ARG);
    master_t m = {3000000.0, 50.0, 1u, 0u};
    uint64_t l = 1000000u;
    run(&g_ts, &m, &l, 40);
    assert_int_equal(g_ts.state, FCC_TSYNC_LOCKED);
    uint64_t master = 0u;
    uint64_t local = 0u;
    fcc_assert_ok(fcc_tsync_to_master(&g_ts, l + 12345u, &master));
    fcc_assert_ok(fcc_tsync_to_local(&g_ts, master, &local));
    assert_true(local + 1u >= l + 12345u && local <= l + 12345u + 1u);
    /* every state that keeps the reference tells time; a state that does not, never (even
     * with a reference left in memory) */
    const fcc_tsync_state_t with_time[] = {FCC_TSYNC_LOCKING, FCC_TSYNC_LOCKED, FCC_TSYNC_HOLDOVER,
                                           FCC_TSYNC_REFUSED};
    for (size_t i = 0; i < sizeof with_time / sizeof with_time[0]; ++i) {
        g_ts.state = with_time[i];
        assert_true(fcc_tsync_has_time(&g_ts));
    }
    g_ts.state = FCC_TSYNC_FREE_RUN;
    assert_false(fcc_tsync_has_time(&g_ts));
    g_ts.state = FCC_TSYNC_LOST;
    assert_false(fcc_tsync_has_time(&g_ts));
    assert_int_equal(fcc_tsync_to_master(&g_ts, l, &out), FCC_ERR_AGAIN);
}

/* A follow-up is refused for each of its faults alone: nothing pending, another sequence
 * number, nanoseconds out of range; the one that matches is then taken. */
static void follow_up_faults_alone(void **state)
{
    (void)state;
    start(&g_ts);
    assert_int_equal(fcc_tsync_on_sync(NULL, 1u, 0u, 100u, 0u, 0u), FCC_ERR_ARG);
    assert_int_equal(fcc_tsync_on_follow_up(NULL, 1u, 0u, false, 0u), FCC_ERR_ARG);
    assert_int_equal(fcc_tsync_rebase(NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_tsync_rejected(NULL), 0u);
    assert_int_equal(fcc_tsync_on_follow_up(&g_ts, 1u, 7u, false, 0u), FCC_ERR_AGAIN);
    fcc_assert_ok(fcc_tsync_on_sync(&g_ts, 1u, 7u, 100u, 5u, 1000000u));
    assert_int_equal(fcc_tsync_on_follow_up(&g_ts, 1u, 8u, false, 0u), FCC_ERR_AGAIN);
    assert_int_equal(fcc_tsync_on_follow_up(&g_ts, 1u, 7u, false, 1000000000u), FCC_ERR_AGAIN);
    assert_int_equal(g_ts.cnt.orphan_fup, 3u);
    fcc_assert_ok(fcc_tsync_on_follow_up(&g_ts, 1u, 7u, true, 999999999u)); /* 6.999999 s */
    uint64_t master = 0u;
    fcc_assert_ok(fcc_tsync_to_master(&g_ts, 1000000u, &master));
    assert_int_equal(master, 6999999u);
    /* a rebase is only for a refused or lost master */
    assert_int_equal(fcc_tsync_rebase(&g_ts), FCC_ERR_AGAIN);
}

/* Residuals: two outliers on opposite sides start the outlier run again (no jump from two
 * different errors); a pair whose local time is not after the last one's is not "backwards"
 * (the master did not go back in the own clock's time) and not used; a pair at the same local
 * time as the last moves the phase but not the rate; a pair 2^40 us later neither. */
static void residual_edges(void **state)
{
    (void)state;
    start(&g_ts);
    master_t m = {0.0, 0.0, 1u, 0u};
    uint64_t l = 1000000u;
    run(&g_ts, &m, &l, 10);
    assert_int_equal(g_ts.state, FCC_TSYNC_LOCKED);
    l += INTERVAL_US;
    /* 1010 us: beyond the servo's step bound (1000 us), within the plausibility bound (1000 us
     * and 200 ppm of the 0.1 s since the last accepted pair) */
    assert_int_equal(pair(&g_ts, &m, l, l - 1010u), FCC_ERR_AGAIN); /* in the past */
    l += INTERVAL_US;
    assert_int_equal(pair(&g_ts, &m, l, l + 1010u), FCC_ERR_AGAIN); /* in the future */
    l += INTERVAL_US;
    assert_int_equal(pair(&g_ts, &m, l, l - 1010u), FCC_ERR_AGAIN);
    assert_int_equal(g_ts.cnt.jumps, 0u); /* never 3 alike in a row */
    assert_int_equal(g_ts.outlier_run, 1u);
    assert_int_equal(g_ts.cnt.past, 2u);
    assert_int_equal(g_ts.cnt.future, 1u);
    run(&g_ts, &m, &l, 5);
    /* 0.5 ms later on the own clock, the master's time not moved on: backwards, not used */
    const uint64_t last_master = g_ts.last_sample_master_us;
    assert_int_equal(pair(&g_ts, &m, l + 500u, last_master), FCC_ERR_AGAIN);
    assert_int_equal(g_ts.cnt.backwards, 1u);
    const uint32_t backwards = g_ts.cnt.backwards;
    assert_int_equal(pair(&g_ts, &m, l, l - 10u), FCC_ERR_AGAIN); /* same local, earlier master */
    assert_int_equal(g_ts.cnt.backwards, backwards);
    const int32_t rate = g_ts.rate_ppb;
    fcc_assert_ok(pair(&g_ts, &m, l, l + 20u)); /* same local time, 20 us later */
    assert_int_equal(g_ts.rate_ppb, rate);
    l += (1ull << 40);
    fcc_assert_ok(pair(&g_ts, &m, l, l + 20u));
    assert_int_equal(g_ts.rate_ppb, rate);
}

/* Holdover and release need the quiet time to have passed on the own clock: a poll at a time
 * before the last good pair (a clock read out of order) changes nothing; a lost master may be
 * rebased. */
static void poll_out_of_order(void **state)
{
    (void)state;
    start(&g_ts);
    master_t m = {0.0, 0.0, 1u, 0u};
    uint64_t l = 1000000u;
    run(&g_ts, &m, &l, 1);
    assert_int_equal(g_ts.state, FCC_TSYNC_LOCKING);
    assert_int_equal(fcc_tsync_poll(&g_ts, l - 1u), FCC_TSYNC_LOCKING);
    assert_int_equal(fcc_tsync_poll(&g_ts, l + 10u * INTERVAL_US), FCC_TSYNC_HOLDOVER);
    assert_int_equal(fcc_tsync_poll(&g_ts, l - 1u), FCC_TSYNC_HOLDOVER);
    assert_int_equal(fcc_tsync_poll(&g_ts, l + 100u * INTERVAL_US), FCC_TSYNC_LOST);
    fcc_assert_ok(fcc_tsync_rebase(&g_ts));
    assert_int_equal(g_ts.state, FCC_TSYNC_FREE_RUN);
}

/* The authenticated receiver's refusals, each alone: nothing to hold into, nothing to verify
 * with; a FOLLOW_UP of another master or sequence number is no candidate. */
static void auth_refusals_alone(void **state)
{
    (void)state;
    tsauth_start();
    uint8_t sync[8], fup[8], auth[8], other[8], out_f[8];
    fcc_tsync_held_t h;
    assert_int_equal(fcc_tsync_auth_init(NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_tsync_auth_hold_sync(NULL, sync, 0u), FCC_ERR_ARG);
    assert_int_equal(fcc_tsync_auth_hold_sync(&g_a.ta, NULL, 0u), FCC_ERR_ARG);
    assert_int_equal(fcc_tsync_auth_hold_follow_up(NULL, fup), FCC_ERR_ARG);
    assert_int_equal(fcc_tsync_auth_hold_follow_up(&g_a.ta, NULL), FCC_ERR_ARG);
    tsync_frame(1u, 30u, 1u, sync);
    tsync_frame(1u, 30u, 2u, fup);
    master_auth(&g_a.tx, sync, fup, auth);
    assert_int_equal(fcc_tsync_auth_verify(NULL, &g_a.rx, g_a.i, auth, &h, out_f), FCC_SECOC_NO_PDU);
    assert_int_equal(fcc_tsync_auth_verify(&g_a.ta, NULL, g_a.i, auth, &h, out_f), FCC_SECOC_NO_PDU);
    assert_int_equal(fcc_tsync_auth_verify(&g_a.ta, &g_a.rx, g_a.i, NULL, &h, out_f), FCC_SECOC_NO_PDU);
    assert_int_equal(fcc_tsync_auth_verify(&g_a.ta, &g_a.rx, g_a.i, auth, NULL, out_f), FCC_SECOC_NO_PDU);
    assert_int_equal(fcc_tsync_auth_verify(&g_a.ta, &g_a.rx, g_a.i, auth, &h, NULL), FCC_SECOC_NO_PDU);
    fcc_assert_ok(fcc_tsync_auth_hold_sync(&g_a.ta, sync, 5u));
    tsync_frame(2u, 30u, 2u, other); /* another master, same sequence number */
    fcc_assert_ok(fcc_tsync_auth_hold_follow_up(&g_a.ta, other));
    tsync_frame(1u, 31u, 2u, other); /* same master, another sequence number */
    fcc_assert_ok(fcc_tsync_auth_hold_follow_up(&g_a.ta, other));
    assert_int_equal(fcc_tsync_auth_verify(&g_a.ta, &g_a.rx, g_a.i, auth, &h, out_f), FCC_SECOC_NO_PDU);
    assert_int_equal(g_a.ta.cnt.mac_failed, 1u);
    fcc_assert_ok(fcc_tsync_auth_hold_follow_up(&g_a.ta, fup));
    assert_int_equal(fcc_tsync_auth_verify(&g_a.ta, &g_a.rx, g_a.i, auth, &h, out_f), FCC_SECOC_VERIFIED);
    assert_int_equal(h.t_us, 5u);
    assert_memory_equal(out_f, fup, 8u);
}

/* The candidate pairs stop at FCC_SECOC_CANDIDATES inside a FOLLOW_UP's row too: SYNCs
 * [A41 B40 C40 D40], FOLLOW_UPs [F40 G41]: G41-A41, then F40 with D40, C40, B40 -- the fourth
 * pair ends the search before the last SYNC of F40's row would be looked at. */
static void candidates_stop_inside_a_row(void **state)
{
    (void)state;
    tsauth_start();
    uint8_t s41[8], s40[3][8], f40[8], g41[8], auth[8], out_f[8];
    fcc_tsync_held_t h;
    tsync_frame(1u, 41u, 1u, s41);
    fcc_assert_ok(fcc_tsync_auth_hold_sync(&g_a.ta, s41, 10u));
    for (uint8_t k = 0u; k < 3u; ++k) {
        tsync_frame(1u, 40u, (uint8_t)(2u + k), s40[k]);
        fcc_assert_ok(fcc_tsync_auth_hold_sync(&g_a.ta, s40[k], 11u + k));
    }
    tsync_frame(1u, 40u, 7u, f40);
    tsync_frame(1u, 41u, 8u, g41);
    fcc_assert_ok(fcc_tsync_auth_hold_follow_up(&g_a.ta, f40));
    fcc_assert_ok(fcc_tsync_auth_hold_follow_up(&g_a.ta, g41));
    master_auth(&g_a.tx, s40[1], f40, auth); /* C40 + F40: the third candidate */
    assert_int_equal(fcc_tsync_auth_verify(&g_a.ta, &g_a.rx, g_a.i, auth, &h, out_f), FCC_SECOC_VERIFIED);
    assert_memory_equal(h.data, s40[1], 8u);
    assert_int_equal(h.t_us, 12u);
    assert_int_equal(g_a.ta.cnt.unauthenticated, 2u); /* A41 and B40, held before C40 */
}

/* ---- eviction from a full hold (fcc_tsync_auth.h "Eviction") -------------------------- */

/* The master's SYNC and FOLLOW_UP of sequence number seq (SYNC received at t_us), held. */
static void hold_master_pair(uint8_t seq, uint64_t t_us, uint8_t sync[8], uint8_t fup[8])
{
    tsync_frame(1u, seq, 1u, sync);
    tsync_frame(1u, seq, 2u, fup);
    fcc_assert_ok(fcc_tsync_auth_hold_sync(&g_a.ta, sync, t_us));
    fcc_assert_ok(fcc_tsync_auth_hold_follow_up(&g_a.ta, fup));
}

/* A replayed burst: the master's old pairs first..last (another payload than its current ones). */
static void hold_replays(uint8_t first, uint8_t last, uint64_t t0_us)
{
    uint8_t x[8];
    for (uint8_t seq = first; seq <= last; ++seq) {
        tsync_frame(1u, seq, 3u, x);
        fcc_assert_ok(fcc_tsync_auth_hold_sync(&g_a.ta, x, t0_us + seq));
        fcc_assert_ok(fcc_tsync_auth_hold_follow_up(&g_a.ta, x));
    }
}

/* The master's authenticator of sync | fup verifies that very pair. */
static void master_pair_verifies(const uint8_t sync[8], const uint8_t fup[8], uint64_t t_us)
{
    uint8_t auth[8], out_f[8];
    fcc_tsync_held_t h;
    master_auth(&g_a.tx, sync, fup, auth);
    assert_int_equal(fcc_tsync_auth_verify(&g_a.ta, &g_a.rx, g_a.i, auth, &h, out_f),
                     FCC_SECOC_VERIFIED);
    assert_memory_equal(h.data, sync, 8u);
    assert_int_equal(h.t_us, t_us);
    assert_memory_equal(out_f, fup, 8u);
}

/* A fresh receiver that has verified the master's pair 50 (expected next: 51). */
static void start_after_pair_50(uint8_t sync[8], uint8_t fup[8])
{
    tsauth_start();
    hold_master_pair(50u, 100u, sync, fup);
    master_pair_verifies(sync, fup, 100u);
}

/* The sequence numbers held of one kind, oldest first. */
static void assert_held_seqs(const fcc_tsync_held_t *list, uint8_t n_held, const uint8_t seqs[4])
{
    assert_int_equal(n_held, FCC_TSYNC_AUTH_HELD);
    for (unsigned int k = 0u; k < FCC_TSYNC_AUTH_HELD; ++k) {
        assert_int_equal(list[k].data[2], seqs[k]);
    }
}

/* `hil verify time-sync --case replayed-master`: after the pair of seq 50 verified, the master's
 * SYNC and FOLLOW_UP 51 are held when a burst of 7 replayed pairs 41..47 (9..3 behind 50) lands
 * before the master's authenticator.  The replays push out each other (the furthest behind 51
 * first), the master's frames stay at the head, the others in order, and its authenticator
 * verifies.  Oldest-first, the fourth replay pushed SYNC 51 out: held 44..47, the authenticator
 * matched no pair (MAC_FAILED) and the pair was lost. */
static void replayed_burst_leaves_the_masters_pair(void **state)
{
    (void)state;
    uint8_t sync[8], fup[8];
    start_after_pair_50(sync, fup);
    hold_master_pair(51u, 200u, sync, fup);
    hold_replays(41u, 47u, 150u);
    assert_int_equal(g_a.ta.cnt.unauthenticated, 8u); /* 41..44 of each pushed out */
    const uint8_t kept[4] = {51u, 45u, 46u, 47u};
    assert_held_seqs(g_a.ta.sync, g_a.ta.n_sync, kept);
    assert_held_seqs(g_a.ta.fup, g_a.ta.n_fup, kept);
    master_pair_verifies(sync, fup, 200u);
    assert_int_equal(g_a.ta.cnt.mac_failed, 0u);
    /* the replays held after it wait; the master's next pair, held after them, drops them */
    assert_int_equal(g_a.ta.n_sync, 3u);
    hold_master_pair(52u, 300u, sync, fup);
    master_pair_verifies(sync, fup, 300u);
    assert_int_equal(g_a.ta.cnt.unauthenticated, 8u + 6u);
    assert_int_equal(g_a.ta.n_sync + g_a.ta.n_fup, 0u);
}

/* A pair lost (51's authenticator never came): the master's next, 52, is one ahead of the
 * expected 51 -- near, kept -- while the replays 41..47 push out each other; 52 verifies. */
static void after_a_lost_pair_the_masters_next_stays(void **state)
{
    (void)state;
    uint8_t sync[8], fup[8];
    start_after_pair_50(sync, fup);
    hold_master_pair(51u, 200u, sync, fup);
    hold_master_pair(52u, 300u, sync, fup);
    hold_replays(41u, 47u, 250u);
    const uint8_t kept[4] = {51u, 52u, 46u, 47u};
    assert_held_seqs(g_a.ta.sync, g_a.ta.n_sync, kept);
    assert_held_seqs(g_a.ta.fup, g_a.ta.n_fup, kept);
    master_pair_verifies(sync, fup, 300u);
    assert_int_equal(g_a.ta.cnt.mac_failed, 0u);
    assert_int_equal(g_a.ta.cnt.unauthenticated, 10u + 2u); /* 41..45 pushed out, 51 dropped */
}

/* Before any pair has verified there is no expected sequence number: a full hold drops its
 * oldest, whatever the sequence numbers (SYNC 200 goes, not 1, which is further behind the
 * zero a verified pair would have left); a forged authenticator does not change that. */
static void before_a_verified_pair_the_oldest_goes(void **state)
{
    (void)state;
    tsauth_start();
    uint8_t x[8], out_f[8];
    fcc_tsync_held_t h;
    const uint8_t seqs[5] = {200u, 1u, 2u, 3u, 4u};
    const uint8_t forged_auth[8] = {1u, 0u, 1u, 2u, 3u, 4u, 5u, 6u};
    for (unsigned int k = 0u; k < 5u; ++k) {
        if (k == 4u) {
            assert_int_equal(fcc_tsync_auth_verify(&g_a.ta, &g_a.rx, g_a.i, forged_auth, &h, out_f),
                             FCC_SECOC_MAC_FAILED);
        }
        tsync_frame(1u, seqs[k], 4u, x);
        fcc_assert_ok(fcc_tsync_auth_hold_sync(&g_a.ta, x, k));
        fcc_assert_ok(fcc_tsync_auth_hold_follow_up(&g_a.ta, x));
    }
    assert_held_seqs(g_a.ta.sync, g_a.ta.n_sync, &seqs[1]);
    assert_held_seqs(g_a.ta.fup, g_a.ta.n_fup, &seqs[1]);
    assert_int_equal(g_a.ta.cnt.unauthenticated, 2u);
}

/* Equally far, the oldest goes; the distance wraps modulo 256.  After the pair of seq 255
 * (expected: 0), SYNCs [250a 0 250b 251] and 252 arriving: 250a and 250b are both 6 behind,
 * 250a goes; then 253 pushes out 250b. */
static void equally_far_the_oldest_goes(void **state)
{
    (void)state;
    tsauth_start();
    uint8_t sync[8], fup[8], a250[8], b250[8], x[8];
    hold_master_pair(255u, 10u, sync, fup);
    master_pair_verifies(sync, fup, 10u);
    tsync_frame(1u, 0u, 1u, sync); /* the master's next */
    tsync_frame(1u, 250u, 5u, a250);
    tsync_frame(1u, 250u, 6u, b250);
    fcc_assert_ok(fcc_tsync_auth_hold_sync(&g_a.ta, a250, 20u));
    fcc_assert_ok(fcc_tsync_auth_hold_sync(&g_a.ta, sync, 21u));
    fcc_assert_ok(fcc_tsync_auth_hold_sync(&g_a.ta, b250, 22u));
    tsync_frame(1u, 251u, 7u, x);
    fcc_assert_ok(fcc_tsync_auth_hold_sync(&g_a.ta, x, 23u));
    tsync_frame(1u, 252u, 7u, x);
    fcc_assert_ok(fcc_tsync_auth_hold_sync(&g_a.ta, x, 24u));
    assert_memory_equal(g_a.ta.sync[1].data, b250, 8u);
    assert_int_equal(g_a.ta.sync[1].t_us, 22u);
    tsync_frame(1u, 253u, 7u, x);
    fcc_assert_ok(fcc_tsync_auth_hold_sync(&g_a.ta, x, 25u));
    const uint8_t kept[4] = {0u, 251u, 252u, 253u};
    assert_held_seqs(g_a.ta.sync, g_a.ta.n_sync, kept);
    assert_int_equal(g_a.ta.cnt.unauthenticated, 2u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(config_is_checked),
        cmocka_unit_test(servo_follows_offset_and_rate),
        cmocka_unit_test(servo_filters_jitter),
        cmocka_unit_test(outliers_are_refused),
        cmocka_unit_test(master_clock_jump_is_refused),
        cmocka_unit_test(jump_within_the_bound_is_followed),
        cmocka_unit_test(drag_is_bounded),
        cmocka_unit_test(authenticated_pairs_only),
        cmocka_unit_test(candidates_are_bounded),
        cmocka_unit_test(follow_up_faults_are_counted),
        cmocka_unit_test(second_master_is_ignored),
        cmocka_unit_test(loss_and_recovery),
        cmocka_unit_test(each_config_limit_alone),
        cmocka_unit_test(time_needs_a_reference),
        cmocka_unit_test(follow_up_faults_alone),
        cmocka_unit_test(residual_edges),
        cmocka_unit_test(poll_out_of_order),
        cmocka_unit_test(auth_refusals_alone),
        cmocka_unit_test(candidates_stop_inside_a_row),
        cmocka_unit_test(replayed_burst_leaves_the_masters_pair),
        cmocka_unit_test(after_a_lost_pair_the_masters_next_stays),
        cmocka_unit_test(before_a_verified_pair_the_oldest_goes),
        cmocka_unit_test(equally_far_the_oldest_goes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
