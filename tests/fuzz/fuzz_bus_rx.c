/*
 * fuzz_bus_rx.c -- libFuzzer: random frames through the receive path
 * (identifier lookup, DLC check, E2E check, unpack, range check) of two
 * receivers (the FCC's and one that consumes every message), plus period ends.
 *
 * Input: a sequence of records, fuzz_bus_records.h (any message of the DBC,
 * by one byte).
 * Properties checked (abort on violation): a frame passed on decodes again to
 * the same values after re-encoding; every rejection moved exactly one counter.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fcc_bus.h"
#include "fuzz_bus_records.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static uint32_t rejections(const fcc_bus_t *bus)
{
    fcc_bus_counters_t c;
    if (fcc_bus_get_counters(bus, &c) != FCC_OK) {
        abort();
    }
    return c.unknown_id + c.wrong_dlc + c.out_of_range + c.e2e[FCC_E2E_ERROR] +
           c.e2e[FCC_E2E_REPEATED] + c.e2e[FCC_E2E_WRONG_SEQUENCE];
}

static void check_reencode(const fcc_bus_rx_msg_t *m)
{
    uint8_t bytes[8];
    fcc_msg_data_t again;
    if (fcc_bus_pack(m->msg, &m->data, bytes) != FCC_OK ||
        fcc_bus_decode(m->msg, bytes, &again) != FCC_OK) {
        abort(); /* a value that was good on receive must encode */
    }
    uint8_t bytes2[8];
    if (fcc_bus_pack(m->msg, &again, bytes2) != FCC_OK || memcmp(bytes, bytes2, 8) != 0) {
        abort(); /* decode/encode must be a fixed point */
    }
}

static void feed(fcc_bus_t *bus, const fcc_can_frame_t *f)
{
    const uint32_t before = rejections(bus);
    fcc_bus_rx_msg_t m;
    const fcc_status_t st = fcc_bus_receive(bus, f, &m);
    const uint32_t moved = rejections(bus) - before;
    if (st == FCC_OK) {
        if (m.verdict != FCC_BUS_PASS || moved != 0u || !fcc_e2e_usable(m.e2e)) {
            abort();
        }
        check_reencode(&m);
    } else if (m.verdict == FCC_BUS_PASS || moved != 1u) {
        abort();
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static fcc_bus_t fcc, all; /* static: 2.6 kB, not on the fuzzer's stack */
    if (fcc_bus_init(&fcc, FCC_BUS_NODE_FCC) != FCC_OK ||
        fcc_bus_init_masks(&all, (uint64_t)((1uLL << FCC_MSG_COUNT) - 1u), 0u) != FCC_OK) {
        abort();
    }
    for (size_t off = 0u; off + FUZZ_RX_REC <= size; off += FUZZ_RX_REC) {
        const uint8_t *r = data + off;
        fcc_can_frame_t f;
        fcc_msg_t msg;
        fuzz_rx_record(r, &f, &msg);
        feed(&fcc, &f);
        feed(&all, &f);
        if ((r[0] & FUZZ_RX_END_PERIOD) != 0u) {
            (void)fcc_bus_end_period(&fcc, msg);
            (void)fcc_bus_end_period(&all, msg);
        }
    }
    return 0;
}
