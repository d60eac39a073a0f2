/*
 * SecOC (firmware/bus/fcc_secoc.c) at its edges: every refusal of a bad
 * argument, one at a time and uncounted (a caller's error is no attack);
 * the PDU table look-ups; the authenticator's frame; a counter that would
 * pass 2^32; the same genuine frame held twice; the multi-frame verifier's
 * candidates.  The vectors, replay, window and eviction are in test_secoc.c.
 */
#include "fcc_test.h"

#include <string.h>

#include "fcc_secoc.h"

static const uint8_t k_key[FCC_SECOC_KEY_BYTES] = {0x2b, 0x7e, 0x15, 0x16, 0x28, 0xae, 0xd2, 0xa6,
                                                   0xab, 0xf7, 0x15, 0x88, 0x09, 0xcf, 0x4f, 0x3c};

static fcc_secoc_t g_tx;
static fcc_secoc_t g_rx;

static void setup_pair(uint32_t trip)
{
    fcc_assert_ok(fcc_secoc_init(&g_tx, k_key, trip));
    fcc_assert_ok(fcc_secoc_init(&g_rx, k_key, trip));
}

static void fill(uint8_t *p, size_t len, uint8_t seed)
{
    for (size_t b = 0u; b < len; ++b) {
        p[b] = (uint8_t)(seed + 13u * b);
    }
}

static void assert_no_counts(const fcc_secoc_t *sec)
{
    assert_int_equal(sec->cnt.verified, 0u);
    assert_int_equal(sec->cnt.mac_failed, 0u);
    assert_int_equal(sec->cnt.freshness_failed, 0u);
    assert_int_equal(sec->cnt.unpaired, 0u);
}

static void init_refuses_null(void **state)
{
    (void)state;
    assert_int_equal(fcc_secoc_init(NULL, k_key, 1u), FCC_ERR_ARG);
    assert_int_equal(fcc_secoc_init(&g_tx, NULL, 1u), FCC_ERR_ARG);
    fcc_assert_ok(fcc_secoc_init(&g_tx, k_key, 0xABCDu));
    assert_int_equal(g_tx.trip, 0xABCDu);
    fcc_secoc_wipe(&g_tx);
    fcc_secoc_wipe(NULL); /* nothing to forget: no fault */
}

static void table_lookups(void **state)
{
    (void)state;
    for (uint32_t i = 0u; i < FCC_SECOC_N_AUTH; ++i) {
        uint32_t index = FCC_SECOC_N_AUTH;
        assert_true(fcc_secoc_auth_index(fcc_secoc_table[i].auth, &index));
        assert_int_equal(index, i);
        assert_true(fcc_secoc_auth_index(fcc_secoc_table[i].auth, NULL));
        /* only a single-frame PDU's frame leads to its authenticator */
        index = FCC_SECOC_N_AUTH;
        const bool single = fcc_secoc_table[i].n_pdus == 1u;
        assert_int_equal(fcc_secoc_secured_index(fcc_secoc_table[i].pdus[0], &index), single);
        assert_int_equal(index, single ? i : FCC_SECOC_N_AUTH);
    }
    assert_true(fcc_secoc_secured_index(FCC_MSG_SIM_TICK, NULL));
    /* frames that are neither */
    uint32_t index = 99u;
    assert_false(fcc_secoc_auth_index(FCC_MSG_SIM_TICK, &index));
    assert_false(fcc_secoc_secured_index(FCC_MSG_RIG_PING, &index));
    assert_false(fcc_secoc_secured_index(FCC_MSG_TSYNC_AUTH, &index));
    assert_int_equal(index, 99u);
}

static void mac_refuses_bad_arguments(void **state)
{
    (void)state;
    setup_pair(1u);
    uint8_t pdu[FCC_SECOC_PDU_BYTES + 1u];
    fill(pdu, sizeof pdu, 3u);
    uint8_t tag[FCC_SECOC_MAC_BYTES];
    uint8_t tag2[FCC_SECOC_MAC_BYTES];
    assert_int_equal(fcc_secoc_mac(NULL, 1u, pdu, 8u, 0u, tag), FCC_ERR_ARG);
    assert_int_equal(fcc_secoc_mac(&g_tx.cmac, 1u, NULL, 8u, 0u, tag), FCC_ERR_ARG);
    assert_int_equal(fcc_secoc_mac(&g_tx.cmac, 1u, pdu, 8u, 0u, NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_secoc_mac(&g_tx.cmac, 1u, pdu, FCC_SECOC_PDU_BYTES + 1u, 0u, tag),
                     FCC_ERR_ARG);
    /* the largest PDU is accepted; data id, PDU and freshness each change the tag */
    fcc_assert_ok(fcc_secoc_mac(&g_tx.cmac, 1u, pdu, FCC_SECOC_PDU_BYTES, 0u, tag));
    fcc_assert_ok(fcc_secoc_mac(&g_tx.cmac, 1u, pdu, 8u, 5u, tag));
    fcc_assert_ok(fcc_secoc_mac(&g_tx.cmac, 1u, pdu, 8u, 5u, tag2));
    assert_memory_equal(tag, tag2, sizeof tag);
    fcc_assert_ok(fcc_secoc_mac(&g_tx.cmac, 2u, pdu, 8u, 5u, tag2));
    assert_memory_not_equal(tag, tag2, sizeof tag);
    fcc_assert_ok(fcc_secoc_mac(&g_tx.cmac, 1u, pdu, 8u, 6u, tag2));
    assert_memory_not_equal(tag, tag2, sizeof tag);
    pdu[7] ^= 1u;
    fcc_assert_ok(fcc_secoc_mac(&g_tx.cmac, 1u, pdu, 8u, 5u, tag2));
    assert_memory_not_equal(tag, tag2, sizeof tag);
}

static void protect_builds_the_authenticator(void **state)
{
    (void)state;
    setup_pair(0x1234u);
    uint32_t i = 0u;
    assert_true(fcc_secoc_secured_index(FCC_MSG_SIM_TICK, &i));
    uint8_t pdu[8];
    fill(pdu, 8u, 1u);
    fcc_can_frame_t auth;
    assert_int_equal(fcc_secoc_protect(NULL, i, pdu, 8u, &auth), FCC_ERR_ARG);
    assert_int_equal(fcc_secoc_protect(&g_tx, i, NULL, 8u, &auth), FCC_ERR_ARG);
    assert_int_equal(fcc_secoc_protect(&g_tx, i, pdu, 8u, NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_secoc_protect(&g_tx, FCC_SECOC_N_AUTH, pdu, 8u, &auth), FCC_ERR_ARG);
    assert_int_equal(fcc_secoc_protect(&g_tx, i, pdu, 16u, &auth), FCC_ERR_ARG);
    assert_int_equal(g_tx.chan[i].counter, 0u); /* no refusal used up a freshness value */
    g_tx.chan[i].counter = 0x1FFFFu;
    fcc_assert_ok(fcc_secoc_protect(&g_tx, i, pdu, 8u, &auth));
    assert_int_equal(g_tx.chan[i].counter, 0x20000u);
    assert_int_equal(auth.id, fcc_bus_msg_table[FCC_MSG_SIM_TICK_AUTH].id);
    assert_int_equal(auth.dlc, 8u);
    assert_int_equal(auth.data[0], 0x00u); /* the counter's 16 low bits, little-endian */
    assert_int_equal(auth.data[1], 0x00u);
    uint8_t tag[FCC_SECOC_MAC_BYTES];
    fcc_assert_ok(fcc_secoc_mac(&g_tx.cmac, fcc_secoc_table[i].data_id, pdu, 8u,
                                ((uint64_t)0x1234u << 32) | 0x20000u, tag));
    assert_memory_equal(&auth.data[2], tag, FCC_SECOC_MAC_BYTES);
}

static void hold_and_verify_refuse_bad_arguments(void **state)
{
    (void)state;
    setup_pair(2u);
    uint8_t pdu[8];
    uint8_t auth[8] = {1, 0, 0, 0, 0, 0, 0, 0};
    uint8_t out[8];
    fill(pdu, 8u, 2u);
    assert_int_equal(fcc_secoc_hold(NULL, 1u, pdu), FCC_ERR_ARG);
    assert_int_equal(fcc_secoc_hold(&g_rx, 1u, NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_secoc_hold(&g_rx, FCC_SECOC_N_AUTH, pdu), FCC_ERR_ARG);
    fcc_assert_ok(fcc_secoc_hold(&g_rx, 1u, pdu));
    assert_int_equal(fcc_secoc_verify(NULL, 1u, auth, out), FCC_SECOC_NO_PDU);
    assert_int_equal(fcc_secoc_verify(&g_rx, 1u, NULL, out), FCC_SECOC_NO_PDU);
    assert_int_equal(fcc_secoc_verify(&g_rx, 1u, auth, NULL), FCC_SECOC_NO_PDU);
    assert_int_equal(fcc_secoc_verify(&g_rx, FCC_SECOC_N_AUTH, auth, out), FCC_SECOC_NO_PDU);
    assert_no_counts(&g_rx);
    assert_int_equal(g_rx.chan[1].n_held, 1u); /* the held frame is still there */
}

/* The receive counter cannot pass 2^32 - 1: an authenticator that would take it there is stale,
 * however close it is. */
static void counter_never_wraps(void **state)
{
    (void)state;
    setup_pair(3u);
    uint32_t i = 0u;
    assert_true(fcc_secoc_secured_index(FCC_MSG_SIM_CONTROL, &i));
    uint8_t pdu[8];
    uint8_t out[8];
    fcc_can_frame_t auth;
    fill(pdu, 8u, 4u);
    g_tx.chan[i].counter = 0xFFFFFFFEu;
    g_rx.chan[i].counter = 0xFFFFFFF0u;
    fcc_assert_ok(fcc_secoc_protect(&g_tx, i, pdu, 8u, &auth)); /* counter 0xFFFFFFFF */
    fcc_assert_ok(fcc_secoc_hold(&g_rx, i, pdu));
    assert_int_equal(fcc_secoc_verify(&g_rx, i, auth.data, out), FCC_SECOC_VERIFIED);
    assert_int_equal(g_rx.chan[i].counter, 0xFFFFFFFFu);
    /* the sender's counter wraps to 0: 16 low bits 0x0000 stand for 2^32 here, beyond the range */
    fcc_assert_ok(fcc_secoc_protect(&g_tx, i, pdu, 8u, &auth));
    fcc_assert_ok(fcc_secoc_hold(&g_rx, i, pdu));
    assert_int_equal(fcc_secoc_verify(&g_rx, i, auth.data, out), FCC_SECOC_FRESHNESS_FAILED);
    assert_int_equal(g_rx.cnt.freshness_failed, 1u);
    assert_int_equal(g_rx.chan[i].counter, 0xFFFFFFFFu);
}

/* A genuine frame held twice (a duplicate on the bus): the first copy is the one authenticated,
 * the second stays held, nothing is counted unpaired. */
static void duplicate_held_frame(void **state)
{
    (void)state;
    setup_pair(4u);
    uint32_t i = 0u;
    assert_true(fcc_secoc_secured_index(FCC_MSG_SIM_TICK, &i));
    uint8_t pdu[8];
    uint8_t out[8];
    fcc_can_frame_t auth;
    fill(pdu, 8u, 5u);
    fcc_assert_ok(fcc_secoc_protect(&g_tx, i, pdu, 8u, &auth));
    fcc_assert_ok(fcc_secoc_hold(&g_rx, i, pdu));
    fcc_assert_ok(fcc_secoc_hold(&g_rx, i, pdu));
    assert_int_equal(fcc_secoc_verify(&g_rx, i, auth.data, out), FCC_SECOC_VERIFIED);
    assert_memory_equal(out, pdu, 8u);
    assert_int_equal(g_rx.chan[i].n_held, 1u);
    assert_int_equal(g_rx.cnt.unpaired, 0u);
    assert_int_equal(g_rx.cnt.verified, 1u);
    /* the copy left behind cannot be authenticated again by the same authenticator */
    assert_int_equal(fcc_secoc_verify(&g_rx, i, auth.data, out), FCC_SECOC_FRESHNESS_FAILED);
}

/* The time master's two-frame PDU, verified against candidates the caller holds. */
static void verify_pdus_candidates(void **state)
{
    (void)state;
    setup_pair(5u);
    uint32_t i = 0u;
    assert_true(fcc_secoc_auth_index(FCC_MSG_TSYNC_AUTH, &i));
    const size_t len = 8u * fcc_secoc_table[i].n_pdus;
    assert_int_equal(len, 16u);
    uint8_t cand[FCC_SECOC_CANDIDATES][16];
    for (uint8_t k = 0u; k < FCC_SECOC_CANDIDATES; ++k) {
        fill(cand[k], len, (uint8_t)(10u * k));
    }
    fcc_can_frame_t auth;
    fcc_assert_ok(fcc_secoc_protect(&g_tx, i, cand[2], len, &auth));
    uint32_t match = 77u;
    /* refusals: uncounted, match untouched */
    assert_int_equal(fcc_secoc_verify_pdus(NULL, i, auth.data, cand[0], 4u, len, &match), FCC_SECOC_NO_PDU);
    assert_int_equal(fcc_secoc_verify_pdus(&g_rx, i, NULL, cand[0], 4u, len, &match), FCC_SECOC_NO_PDU);
    assert_int_equal(fcc_secoc_verify_pdus(&g_rx, i, auth.data, cand[0], 4u, len, NULL), FCC_SECOC_NO_PDU);
    assert_int_equal(fcc_secoc_verify_pdus(&g_rx, FCC_SECOC_N_AUTH, auth.data, cand[0], 4u, len, &match),
                     FCC_SECOC_NO_PDU);
    assert_int_equal(fcc_secoc_verify_pdus(&g_rx, i, auth.data, cand[0], FCC_SECOC_CANDIDATES + 1u, len, &match),
                     FCC_SECOC_NO_PDU);
    assert_int_equal(fcc_secoc_verify_pdus(&g_rx, i, auth.data, NULL, 1u, len, &match), FCC_SECOC_NO_PDU);
    assert_int_equal(fcc_secoc_verify_pdus(&g_rx, i, auth.data, cand[0], 4u, 8u, &match), FCC_SECOC_NO_PDU);
    assert_int_equal(match, 77u);
    assert_no_counts(&g_rx);
    /* no candidate at all (none needed with n = 0): a counted MAC failure */
    assert_int_equal(fcc_secoc_verify_pdus(&g_rx, i, auth.data, NULL, 0u, len, &match), FCC_SECOC_NO_PDU);
    assert_int_equal(g_rx.cnt.mac_failed, 1u);
    /* candidates 0 and 1 are not it: a MAC failure, the counter stays */
    assert_int_equal(fcc_secoc_verify_pdus(&g_rx, i, auth.data, cand[0], 2u, len, &match),
                     FCC_SECOC_MAC_FAILED);
    assert_int_equal(g_rx.cnt.mac_failed, 2u);
    assert_int_equal(g_rx.chan[i].counter, 0u);
    /* all four: the third verifies, the counter moves on */
    assert_int_equal(fcc_secoc_verify_pdus(&g_rx, i, auth.data, cand[0], 4u, len, &match),
                     FCC_SECOC_VERIFIED);
    assert_int_equal(match, 2u);
    assert_int_equal(g_rx.chan[i].counter, 1u);
    assert_int_equal(g_rx.cnt.verified, 1u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(init_refuses_null),
        cmocka_unit_test(table_lookups),
        cmocka_unit_test(mac_refuses_bad_arguments),
        cmocka_unit_test(protect_builds_the_authenticator),
        cmocka_unit_test(hold_and_verify_refuse_bad_arguments),
        cmocka_unit_test(counter_never_wraps),
        cmocka_unit_test(duplicate_held_frame),
        cmocka_unit_test(verify_pdus_candidates),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
