/*
 * test_e2e.c -- E2E protection: CRC-8 SAE J1850 against its published check
 * value and the AUTOSAR table, the hand-worked frames of dbc/README.md, the
 * receiver state machine by hand, and the shared sequences that the Python
 * implementation generated (tests/vectors/bus/e2e_seq.txt, crc.txt).
 */
#include "fcc_test.h"

#include <stdlib.h>
#include <string.h>

#include "fcc_e2e.h"

#define VEC_DIR FCC_SOURCE_DIR "/tests/vectors/bus/"

static size_t parse_hex(const char *hex, uint8_t *out, size_t max)
{
    size_t n = 0u;
    if (strcmp(hex, "-") == 0) {
        return 0u;
    }
    while (hex[0] != '\0' && hex[1] != '\0' && n < max) {
        char byte[3] = {hex[0], hex[1], '\0'};
        out[n++] = (uint8_t)strtoul(byte, NULL, 16);
        hex += 2;
    }
    return n;
}

static void test_crc_check_value(void **state)
{
    (void)state;
    const uint8_t check[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
    assert_int_equal(fcc_e2e_crc8(check, sizeof check), 0x4B);
    const uint8_t zeros[] = {0, 0, 0, 0};
    assert_int_equal(fcc_e2e_crc8(zeros, sizeof zeros), 0x59); /* AUTOSAR CRC table */
    const uint8_t ff[] = {0xFF, 0xFF, 0xFF, 0xFF};
    assert_int_equal(fcc_e2e_crc8(ff, sizeof ff), 0x74);
    assert_int_equal(fcc_e2e_crc8(NULL, 0u), 0x00);
}

static void test_crc_vectors(void **state)
{
    (void)state;
    FILE *f = fopen(VEC_DIR "crc.txt", "r");
    assert_non_null(f);
    char line[256];
    int n = 0;
    while (fgets(line, sizeof line, f) != NULL) {
        char hex[128];
        unsigned int crc;
        if (line[0] == '#' || sscanf(line, "%127s %x", hex, &crc) != 2) {
            continue;
        }
        uint8_t data[64];
        const size_t len = parse_hex(hex, data, sizeof data);
        assert_int_equal(fcc_e2e_crc8(data, len), crc);
        ++n;
    }
    fclose(f);
    assert_true(n >= 9);
}

/* dbc/README.md: SIM_TICK (data ID 0x1020), app 0, step 1, counter 0. */
static void test_hand_worked_frames(void **state)
{
    (void)state;
    uint8_t tick[8] = {0, 0x00, 0x01, 0, 0, 0, 0, 0};
    fcc_assert_ok(fcc_e2e_protect(0x1020u, 0u, tick));
    const uint8_t tick_expected[8] = {0x9F, 0x00, 0x01, 0, 0, 0, 0, 0};
    assert_memory_equal(tick, tick_expected, 8);
    /* The CRC over the 9 bytes written out by hand gives the same value. */
    const uint8_t crc_input[9] = {0x20, 0x10, 0x00, 0x01, 0, 0, 0, 0, 0};
    assert_int_equal(fcc_e2e_crc8(crc_input, sizeof crc_input), 0x9F);

    /* CDRW_AOA (0x1050), step 7, alpha raw 157000 = 0x00026548, counter 5. */
    uint8_t aoa[8] = {0, 0, 0x07, 0x00, 0x48, 0x65, 0x02, 0x00};
    fcc_assert_ok(fcc_e2e_protect(0x1050u, 5u, aoa));
    const uint8_t aoa_expected[8] = {0x31, 0x05, 0x07, 0x00, 0x48, 0x65, 0x02, 0x00};
    assert_memory_equal(aoa, aoa_expected, 8);
}

static void test_protect_keeps_high_nibble_and_refuses_bad_counter(void **state)
{
    (void)state;
    uint8_t f[8] = {0, 0xA7, 1, 2, 3, 4, 5, 6};
    fcc_assert_ok(fcc_e2e_protect(0x1234u, 0x0Cu, f));
    assert_int_equal(f[1], 0xAC);
    assert_int_equal(f[0], fcc_e2e_frame_crc(0x1234u, f));
    const uint8_t before[8] = {f[0], f[1], f[2], f[3], f[4], f[5], f[6], f[7]};
    assert_int_equal(fcc_e2e_protect(0x1234u, 16u, f), FCC_ERR_ARG);
    assert_memory_equal(f, before, 8);
    assert_int_equal(fcc_e2e_protect(0x1234u, 0u, NULL), FCC_ERR_ARG);
    /* The data ID is part of the CRC: another ID, another CRC. */
    assert_int_not_equal(fcc_e2e_frame_crc(0x1234u, f), fcc_e2e_frame_crc(0x1235u, f));
    assert_int_not_equal(fcc_e2e_frame_crc(0x1234u, f), fcc_e2e_frame_crc(0x3412u, f));
}

static void make(uint8_t f[8], uint8_t counter)
{
    memset(f, 0, 8);
    f[2] = 0x42;
    (void)fcc_e2e_protect(0x1050u, counter, f);
}

static fcc_e2e_status_t feed(fcc_e2e_rx_t *rx, uint8_t counter)
{
    uint8_t f[8];
    make(f, counter);
    return fcc_e2e_rx_check(rx, f, 8u);
}

static void test_receiver_by_hand(void **state)
{
    (void)state;
    fcc_e2e_rx_t rx;
    fcc_assert_ok(fcc_e2e_rx_init(&rx, 0x1050u, 0u));
    assert_int_equal(rx.max_delta, 3);
    assert_int_equal(feed(&rx, 14u), FCC_E2E_OK);            /* first frame: sync */
    assert_int_equal(feed(&rx, 14u), FCC_E2E_REPEATED);
    assert_int_equal(feed(&rx, 15u), FCC_E2E_OK);
    assert_int_equal(feed(&rx, 0u), FCC_E2E_OK);             /* wraps 15 -> 0 */
    assert_int_equal(feed(&rx, 2u), FCC_E2E_OK_SOME_LOST);   /* one lost */
    assert_int_equal(feed(&rx, 5u), FCC_E2E_OK_SOME_LOST);   /* two lost: delta 3 */
    assert_int_equal(rx.lost_frames, 3u);
    assert_int_equal(feed(&rx, 9u), FCC_E2E_WRONG_SEQUENCE); /* delta 4 > 3 */
    assert_int_equal(feed(&rx, 10u), FCC_E2E_OK);            /* resynchronised */
    assert_int_equal(feed(&rx, 8u), FCC_E2E_WRONG_SEQUENCE); /* went back */
    assert_int_equal(feed(&rx, 9u), FCC_E2E_OK);

    uint8_t f[8];
    make(f, 10u);
    f[0] ^= 0x01u;
    assert_int_equal(fcc_e2e_rx_check(&rx, f, 8u), FCC_E2E_ERROR);
    make(f, 10u);
    f[7] ^= 0x80u; /* one payload bit */
    assert_int_equal(fcc_e2e_rx_check(&rx, f, 8u), FCC_E2E_ERROR);
    make(f, 10u);
    assert_int_equal(fcc_e2e_rx_check(&rx, f, 7u), FCC_E2E_ERROR); /* wrong length */
    assert_int_equal(fcc_e2e_rx_check(&rx, NULL, 8u), FCC_E2E_ERROR);
    assert_int_equal(feed(&rx, 10u), FCC_E2E_OK); /* errors did not move the counter */

    /* A frame of another message (other data ID) is an ERROR here. */
    memset(f, 0, 8);
    (void)fcc_e2e_protect(0x1051u, 11u, f);
    assert_int_equal(fcc_e2e_rx_check(&rx, f, 8u), FCC_E2E_ERROR);

    assert_int_equal(rx.count[FCC_E2E_OK], 6u); /* 14, 15, 0, 10, 9, 10 */
    assert_int_equal(rx.count[FCC_E2E_REPEATED], 1u);
    assert_int_equal(rx.count[FCC_E2E_OK_SOME_LOST], 2u);
    assert_int_equal(rx.count[FCC_E2E_WRONG_SEQUENCE], 2u);
    assert_int_equal(rx.count[FCC_E2E_ERROR], 5u);
    assert_int_equal(rx.count[FCC_E2E_NO_NEW_DATA], 0u);
}

static void test_no_new_data_and_resync(void **state)
{
    (void)state;
    fcc_e2e_rx_t rx;
    fcc_assert_ok(fcc_e2e_rx_init(&rx, 0x1050u, 2u));
    assert_true(fcc_e2e_rx_end_period(&rx)); /* nothing yet */
    assert_true(rx.stale);
    assert_int_equal(feed(&rx, 3u), FCC_E2E_OK);
    assert_false(fcc_e2e_rx_end_period(&rx));
    assert_false(rx.stale);
    assert_true(fcc_e2e_rx_end_period(&rx));
    assert_int_equal(rx.count[FCC_E2E_NO_NEW_DATA], 2u);
    assert_int_equal(rx.last_status, FCC_E2E_NO_NEW_DATA);
    /* Even a rejected frame is a frame: the period is not NO_NEW_DATA. */
    uint8_t f[8];
    make(f, 4u);
    f[0] ^= 0xFFu;
    assert_int_equal(fcc_e2e_rx_check(&rx, f, 8u), FCC_E2E_ERROR);
    assert_false(fcc_e2e_rx_end_period(&rx));
    /* max delta 2: delta 3 is a wrong sequence. */
    assert_int_equal(feed(&rx, 6u), FCC_E2E_WRONG_SEQUENCE);
    fcc_e2e_rx_resync(&rx);
    assert_int_equal(feed(&rx, 0u), FCC_E2E_OK);
    assert_false(fcc_e2e_rx_end_period(NULL));
    fcc_e2e_rx_resync(NULL);
}

static void test_init_and_sender(void **state)
{
    (void)state;
    fcc_e2e_rx_t rx;
    assert_int_equal(fcc_e2e_rx_init(&rx, 1u, 15u), FCC_ERR_ARG);
    assert_int_equal(fcc_e2e_rx_init(NULL, 1u, 3u), FCC_ERR_ARG);
    fcc_assert_ok(fcc_e2e_rx_init(&rx, 1u, 14u));
    assert_int_equal(fcc_e2e_rx_check(NULL, NULL, 8u), FCC_E2E_ERROR);

    fcc_e2e_tx_t tx;
    fcc_assert_ok(fcc_e2e_tx_init(&tx, 0x1050u));
    fcc_assert_ok(fcc_e2e_rx_init(&rx, 0x1050u, 0u));
    for (unsigned int i = 0u; i < 40u; ++i) {
        uint8_t f[8] = {0, 0, (uint8_t)i, 0, 0, 0, 0, 0};
        fcc_assert_ok(fcc_e2e_tx_protect(&tx, f));
        assert_int_equal(f[1] & 0x0Fu, i % 16u);
        assert_int_equal(fcc_e2e_rx_check(&rx, f, 8u), FCC_E2E_OK);
    }
    assert_int_equal(fcc_e2e_tx_protect(NULL, NULL), FCC_ERR_ARG);
    assert_true(fcc_e2e_usable(FCC_E2E_OK));
    assert_true(fcc_e2e_usable(FCC_E2E_OK_SOME_LOST));
    assert_false(fcc_e2e_usable(FCC_E2E_REPEATED));
    assert_false(fcc_e2e_usable(FCC_E2E_WRONG_SEQUENCE));
    assert_false(fcc_e2e_usable(FCC_E2E_ERROR));
    assert_false(fcc_e2e_usable(FCC_E2E_NO_NEW_DATA));
    assert_string_equal(fcc_e2e_status_str(FCC_E2E_OK_SOME_LOST), "OK_SOME_LOST");
    assert_string_equal(fcc_e2e_status_str(FCC_E2E_N_STATUS), "UNKNOWN");
}

static int status_of(const char *name)
{
    for (int s = 0; s < (int)FCC_E2E_N_STATUS; ++s) {
        if (strcmp(name, fcc_e2e_status_str((fcc_e2e_status_t)s)) == 0) {
            return s;
        }
    }
    fail_msg("unknown E2E class %s", name);
    return -1;
}

/* Data IDs of the protected messages, as in the DBC: 0x1000 | CAN ID. */
static void test_shared_sequences(void **state)
{
    (void)state;
    FILE *f = fopen(VEC_DIR "e2e_seq.txt", "r");
    assert_non_null(f);
    char line[256];
    fcc_e2e_rx_t rx;
    int sequences = 0;
    int frames = 0;
    while (fgets(line, sizeof line, f) != NULL) {
        char a[64], b[64], c[64];
        unsigned int id, v[6];
        if (line[0] == '#') {
            continue;
        }
        if (sscanf(line, "RESET %x", &id) == 1) {
            fcc_assert_ok(fcc_e2e_rx_init(&rx, (uint16_t)(0x1000u | id), 0u));
            ++sequences;
        } else if (sscanf(line, "PERIOD %x %u", &id, &v[0]) == 2) {
            assert_int_equal(fcc_e2e_rx_end_period(&rx), v[0] != 0u);
        } else if (sscanf(line, "COUNTS %x %u %u %u %u %u %u", &id, &v[0], &v[1], &v[2], &v[3],
                          &v[4], &v[5]) == 7) {
            for (unsigned int s = 0u; s < 6u; ++s) {
                assert_int_equal(rx.count[s], v[s]);
            }
        } else if (sscanf(line, "%63s %63s %63s", a, b, c) == 3) {
            uint8_t data[8];
            assert_int_equal(parse_hex(b, data, 8u), 8u);
            assert_int_equal(fcc_e2e_rx_check(&rx, data, 8u), status_of(c));
            ++frames;
        }
    }
    fclose(f);
    assert_true(sequences >= 4);
    assert_true(frames >= 100);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_crc_check_value),
        cmocka_unit_test(test_crc_vectors),
        cmocka_unit_test(test_hand_worked_frames),
        cmocka_unit_test(test_protect_keeps_high_nibble_and_refuses_bad_counter),
        cmocka_unit_test(test_receiver_by_hand),
        cmocka_unit_test(test_no_new_data_and_resync),
        cmocka_unit_test(test_init_and_sender),
        cmocka_unit_test(test_shared_sequences),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
