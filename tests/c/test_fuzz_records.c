/*
 * test_fuzz_records.c -- the bus fuzz targets can reach every message of the
 * DBC (tests/fuzz/fuzz_bus_records.h): some selector byte names each one, and
 * some fuzz_bus_rx record sends each one's own identifier, E2E-protected when
 * the message is.  Runs in every unit build, so a harness that leaves
 * messages out fails here even where the fuzzers are not built.
 */
#include "fcc_test.h"

#include <stdbool.h>
#include <string.h>

#include "../fuzz/fuzz_bus_records.h"

static void test_every_message_has_a_selector(void **state)
{
    (void)state;
    bool seen[FCC_MSG_COUNT] = {false};
    for (unsigned int b = 0u; b < 256u; ++b) {
        const fcc_msg_t m = fuzz_bus_pick((uint8_t)b);
        assert_true((unsigned int)m < (unsigned int)FCC_MSG_COUNT);
        seen[m] = true;
    }
    for (unsigned int m = 0u; m < (unsigned int)FCC_MSG_COUNT; ++m) {
        if (!seen[m]) {
            fail_msg("message %u (%s) cannot be chosen", m, fcc_bus_msg_table[m].name);
        }
    }
}

/* Every flag combination and every second byte: each message is sent with its
 * own identifier, protected (a CRC the receiver accepts) when it has E2E, and
 * its period closed. */
static void test_every_message_is_sent_from_the_table(void **state)
{
    (void)state;
    bool sent[FCC_MSG_COUNT] = {false};
    bool protected_ok[FCC_MSG_COUNT] = {false};
    bool period_closed[FCC_MSG_COUNT] = {false};
    uint8_t r[FUZZ_RX_REC];
    memset(r, 0, sizeof r);
    r[2] = 8u;
    for (unsigned int flags = 0u; flags < 256u; ++flags) {
        for (unsigned int b = 0u; b < 256u; ++b) {
            r[0] = (uint8_t)flags;
            r[1] = (uint8_t)b;
            fcc_can_frame_t f;
            fcc_msg_t m;
            fuzz_rx_record(r, &f, &m);
            assert_true((unsigned int)m < (unsigned int)FCC_MSG_COUNT);
            if ((flags & FUZZ_RX_FROM_TABLE) == 0u) {
                continue;
            }
            assert_int_equal(f.id, fcc_bus_msg_table[m].id);
            sent[m] = true;
            period_closed[m] = period_closed[m] || (flags & FUZZ_RX_END_PERIOD) != 0u;
            if ((flags & FUZZ_RX_PROTECT) != 0u && fcc_bus_msg_table[m].data_id != 0u) {
                fcc_e2e_rx_t rx;
                fcc_assert_ok(fcc_e2e_rx_init(&rx, fcc_bus_msg_table[m].data_id,
                                              fcc_bus_msg_table[m].max_delta_counter));
                protected_ok[m] = protected_ok[m] ||
                                  fcc_e2e_usable(fcc_e2e_rx_check(&rx, f.data, f.dlc));
            }
        }
    }
    for (unsigned int m = 0u; m < (unsigned int)FCC_MSG_COUNT; ++m) {
        if (!sent[m] || !period_closed[m]) {
            fail_msg("message %u (%s) is never sent from the table", m, fcc_bus_msg_table[m].name);
        }
        if (fcc_bus_msg_table[m].data_id != 0u && !protected_ok[m]) {
            fail_msg("message %u (%s) is never sent with a good E2E protection", m,
                     fcc_bus_msg_table[m].name);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_message_has_a_selector),
        cmocka_unit_test(test_every_message_is_sent_from_the_table),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
