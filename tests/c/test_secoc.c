/*
 * test_secoc.c -- SecOC-style authentication: authenticator frames equal the
 * Python reference (`cryptography`, tests/vectors/crypto/secoc.txt), and the
 * receiver's freshness window, replay refusal and held-frame pairing.
 */
#include "fcc_test.h"

#include <stdlib.h>
#include <string.h>

#include "fcc_secoc.h"

#define VEC_DIR FCC_SOURCE_DIR "/tests/vectors/crypto/"

static const uint8_t k_key[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};

static uint32_t index_of(uint16_t data_id)
{
    for (uint32_t i = 0u; i < FCC_SECOC_N_AUTH; ++i) {
        if (fcc_secoc_table[i].data_id == data_id) {
            return i;
        }
    }
    fail_msg("no SecOC data ID 0x%04x in the DBC", data_id);
    return 0u;
}

/* One line of secoc.txt: key, data ID, secured bytes, trip, message counter and the
 * authenticator frame's 8 bytes, in hex. */
static void vector_line(const char *line, void *ctx)
{
    (void)ctx;
    char k[40], p[200], a[40];
    unsigned int data_id, trip, counter;
    assert_int_equal(sscanf(line, "%39s %x %199s %x %x %39s", k, &data_id, p, &trip, &counter, a), 6);
    uint8_t key[16], pdu[FCC_SECOC_PDU_BYTES], want[8];
    fcc_test_hex(k, key, 16);
    const size_t len = fcc_test_hex(p, pdu, sizeof pdu);
    fcc_test_hex(a, want, 8);
    static fcc_secoc_t sec;
    fcc_assert_ok(fcc_secoc_init(&sec, key, trip));
    const uint32_t i = index_of((uint16_t)data_id);
    sec.chan[i].counter = counter - 1u;
    fcc_can_frame_t auth;
    fcc_assert_ok(fcc_secoc_protect(&sec, i, pdu, len, &auth));
    assert_int_equal(auth.id, fcc_bus_msg_table[fcc_secoc_table[i].auth].id);
    assert_int_equal(auth.dlc, 8);
    assert_memory_equal(auth.data, want, 8);
    assert_int_equal(sec.chan[i].counter, counter);
}

static void test_vectors(void **state)
{
    (void)state;
    fcc_test_vector_file(VEC_DIR "secoc.txt", 60u, vector_line, NULL);
}

static void test_table_matches_dbc(void **state)
{
    (void)state;
    uint32_t i;
    assert_true(fcc_secoc_secured_index(FCC_MSG_SIM_TICK, &i));
    assert_int_equal(fcc_secoc_table[i].auth, FCC_MSG_SIM_TICK_AUTH);
    assert_true(fcc_secoc_secured_index(FCC_MSG_SIM_CONTROL, &i));
    /* fcc's outputs of a step: groups under one authenticator each */
    assert_false(fcc_secoc_secured_index(FCC_MSG_MSL_ELEV_CMD, &i));
    assert_true(fcc_secoc_auth_index(FCC_MSG_MSL_ELEV_CMD_AUTH, &i));
    assert_int_equal(fcc_secoc_table[i].n_pdus, 2u);
    assert_int_equal(fcc_secoc_table[i].pdus[0], FCC_MSG_MSL_ELEV_CMD);
    assert_int_equal(fcc_secoc_table[i].pdus[1], FCC_MSG_MSL_STATE_EST);
    assert_true(fcc_secoc_auth_index(FCC_MSG_SID_OUT_AUTH, &i));
    assert_int_equal(fcc_secoc_table[i].n_pdus, 12u);
    assert_int_equal(fcc_secoc_table[i].pdus[0], FCC_MSG_SID_AZKF_STATE);
    assert_int_equal(fcc_secoc_table[i].pdus[11], FCC_MSG_SID_KF_MODEL_B);
    assert_false(fcc_secoc_secured_index(FCC_MSG_CDRW_AOA, &i));
    assert_false(fcc_secoc_secured_index(FCC_MSG_FCC_STATUS, &i)); /* a group, not single */
    assert_true(fcc_secoc_auth_index(FCC_MSG_FCC_STATUS_AUTH, &i));
    assert_int_equal(fcc_secoc_table[i].n_pdus, 9u);
    assert_int_equal(fcc_secoc_table[i].pdus[0], FCC_MSG_FCC_STATUS);
    assert_int_equal(fcc_secoc_table[i].pdus[5], FCC_MSG_FCC_SYNC_STATUS); /* the time sync status too */
    assert_int_equal(fcc_secoc_table[i].pdus[8], FCC_MSG_FCC_SYNC_REFUSALS);
    /* the time master's SYNC + FOLLOW_UP: one group, held by the time sync (not single frames) */
    assert_false(fcc_secoc_secured_index(FCC_MSG_TSYNC_SYNC, &i));
    assert_true(fcc_secoc_auth_index(FCC_MSG_TSYNC_AUTH, &i));
    assert_int_equal(fcc_secoc_table[i].n_pdus, 2u);
    assert_int_equal(fcc_secoc_table[i].pdus[0], FCC_MSG_TSYNC_SYNC);
    assert_int_equal(fcc_secoc_table[i].pdus[1], FCC_MSG_TSYNC_FOLLOW_UP);
}

/* Sender and receiver with one key and trip: a tick and its authenticator. */
typedef struct {
    fcc_secoc_t tx, rx;
    uint32_t i;
} pair_t;

static pair_t g_p;

static void setup_pair(uint32_t trip)
{
    fcc_assert_ok(fcc_secoc_init(&g_p.tx, k_key, trip));
    fcc_assert_ok(fcc_secoc_init(&g_p.rx, k_key, trip));
    assert_true(fcc_secoc_secured_index(FCC_MSG_SIM_TICK, &g_p.i));
}

static void frame(uint8_t seq, uint8_t out[8])
{
    for (unsigned int b = 0u; b < 8u; ++b) {
        out[b] = (uint8_t)(seq * 7u + b);
    }
}

static void test_accept_and_replay(void **state)
{
    (void)state;
    setup_pair(0xC0FFEEu);
    uint8_t pdu[8], out[8], old_pdu[8];
    fcc_can_frame_t auth, old_auth;
    for (uint8_t s = 0u; s < 5u; ++s) {
        frame(s, pdu);
        fcc_assert_ok(fcc_secoc_protect(&g_p.tx, g_p.i, pdu, 8u, &auth));
        if (s == 1u) {
            memcpy(old_pdu, pdu, 8u);
            old_auth = auth;
        }
        fcc_assert_ok(fcc_secoc_hold(&g_p.rx, g_p.i, pdu));
        assert_int_equal(fcc_secoc_verify(&g_p.rx, g_p.i, auth.data, out), FCC_SECOC_VERIFIED);
        assert_memory_equal(out, pdu, 8u);
    }
    /* The same frames again: a replay fails freshness (no MAC computed). */
    fcc_assert_ok(fcc_secoc_hold(&g_p.rx, g_p.i, old_pdu));
    assert_int_equal(fcc_secoc_verify(&g_p.rx, g_p.i, old_auth.data, out), FCC_SECOC_FRESHNESS_FAILED);
    fcc_assert_ok(fcc_secoc_hold(&g_p.rx, g_p.i, pdu));
    assert_int_equal(fcc_secoc_verify(&g_p.rx, g_p.i, auth.data, out), FCC_SECOC_FRESHNESS_FAILED);
    assert_int_equal(g_p.rx.cnt.verified, 5u);
    assert_int_equal(g_p.rx.cnt.freshness_failed, 2u);
    /* A tampered byte fails the MAC; the genuine frame held beside it still verifies. */
    frame(9u, pdu);
    fcc_assert_ok(fcc_secoc_protect(&g_p.tx, g_p.i, pdu, 8u, &auth));
    uint8_t forged[8];
    memcpy(forged, pdu, 8u);
    forged[3] ^= 0x40u;
    fcc_secoc_t rx2 = g_p.rx;
    fcc_assert_ok(fcc_secoc_hold(&rx2, g_p.i, forged));
    assert_int_equal(fcc_secoc_verify(&rx2, g_p.i, auth.data, out), FCC_SECOC_MAC_FAILED);
    g_p.rx.chan[g_p.i].n_held = 0u;
    fcc_assert_ok(fcc_secoc_hold(&g_p.rx, g_p.i, pdu));    /* genuine */
    fcc_assert_ok(fcc_secoc_hold(&g_p.rx, g_p.i, forged)); /* squeezed in before the authenticator */
    assert_int_equal(fcc_secoc_verify(&g_p.rx, g_p.i, auth.data, out), FCC_SECOC_VERIFIED);
    assert_memory_equal(out, pdu, 8u);
    /* A forged authenticator does not discard the genuine frame held. */
    frame(10u, pdu);
    fcc_assert_ok(fcc_secoc_protect(&g_p.tx, g_p.i, pdu, 8u, &auth));
    g_p.rx.chan[g_p.i].n_held = 0u;
    fcc_assert_ok(fcc_secoc_hold(&g_p.rx, g_p.i, pdu));
    uint8_t bad[8];
    memcpy(bad, auth.data, 8u);
    bad[7] ^= 0x01u;
    assert_int_equal(fcc_secoc_verify(&g_p.rx, g_p.i, bad, out), FCC_SECOC_MAC_FAILED);
    assert_int_equal(fcc_secoc_verify(&g_p.rx, g_p.i, auth.data, out), FCC_SECOC_VERIFIED);
    /* An authenticator with nothing held. */
    assert_int_equal(fcc_secoc_verify(&g_p.rx, g_p.i, auth.data, out), FCC_SECOC_FRESHNESS_FAILED);
}

/* pdu through the pair: authenticated by the sender (with `from`'s counter and trip),
 * held by the receiver, its authenticator verified; the receiver's verdict. */
static fcc_secoc_verdict_t deliver(fcc_secoc_t *from, const uint8_t pdu[8])
{
    fcc_can_frame_t auth;
    uint8_t out[8];
    fcc_assert_ok(fcc_secoc_protect(from, g_p.i, pdu, 8u, &auth));
    fcc_assert_ok(fcc_secoc_hold(&g_p.rx, g_p.i, pdu));
    return fcc_secoc_verify(&g_p.rx, g_p.i, auth.data, out);
}

static void test_window_and_other_trip(void **state)
{
    (void)state;
    setup_pair(7u);
    uint8_t pdu[8];
    frame(1u, pdu);
    /* FCC_SECOC_WINDOW lost frames are still accepted ... */
    g_p.tx.chan[g_p.i].counter = FCC_SECOC_WINDOW - 1u;
    assert_int_equal(deliver(&g_p.tx, pdu), FCC_SECOC_VERIFIED);
    /* ... one more is not; across the 16-bit wrap of the truncated value it works. */
    g_p.tx.chan[g_p.i].counter += FCC_SECOC_WINDOW;
    assert_int_equal(deliver(&g_p.tx, pdu), FCC_SECOC_FRESHNESS_FAILED);
    g_p.tx.chan[g_p.i].counter = 0xFFFEu;
    g_p.rx.chan[g_p.i].counter = 0xFFF0u;
    g_p.rx.chan[g_p.i].n_held = 0u;
    for (int s = 0; s < 3; ++s) { /* 0xFFFF, 0x10000, 0x10001 */
        assert_int_equal(deliver(&g_p.tx, pdu), FCC_SECOC_VERIFIED);
    }
    assert_int_equal(g_p.rx.chan[g_p.i].counter, 0x10001u);
    /* The same key in another session (trip) authenticates nothing. */
    fcc_secoc_t other;
    fcc_assert_ok(fcc_secoc_init(&other, k_key, 8u));
    other.chan[g_p.i].counter = 0x10001u;
    assert_int_equal(deliver(&other, pdu), FCC_SECOC_MAC_FAILED);
}

static void test_hold_eviction(void **state)
{
    (void)state;
    setup_pair(1u);
    uint8_t pdu[8], out[8];
    fcc_can_frame_t auth;
    frame(1u, pdu);
    fcc_assert_ok(fcc_secoc_protect(&g_p.tx, g_p.i, pdu, 8u, &auth));
    fcc_assert_ok(fcc_secoc_hold(&g_p.rx, g_p.i, pdu));
    for (uint8_t s = 0u; s < FCC_SECOC_CANDIDATES; ++s) { /* a flood of forgeries evicts it */
        uint8_t junk[8];
        frame((uint8_t)(100u + s), junk);
        fcc_assert_ok(fcc_secoc_hold(&g_p.rx, g_p.i, junk));
    }
    assert_int_equal(g_p.rx.cnt.unpaired, 1u);
    assert_int_equal(fcc_secoc_verify(&g_p.rx, g_p.i, auth.data, out), FCC_SECOC_MAC_FAILED);
    assert_int_equal(fcc_secoc_protect(&g_p.tx, g_p.i, pdu, 7u, &auth), FCC_ERR_ARG);
    assert_int_equal(fcc_secoc_hold(&g_p.rx, FCC_SECOC_N_AUTH, pdu), FCC_ERR_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vectors),
        cmocka_unit_test(test_table_matches_dbc),
        cmocka_unit_test(test_accept_and_replay),
        cmocka_unit_test(test_window_and_other_trip),
        cmocka_unit_test(test_hold_eviction),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
