/*
 * fuzz_bus_tx.c -- libFuzzer: arbitrary values (NaN, Inf, huge, denormal,
 * out-of-range integers) asked to be encoded.  Properties (abort on
 * violation): the encoder either refuses with a status and counts it, or
 * produces a frame that the receiver accepts with every real within half an
 * LSB of what was asked (or clamped to the range with encode_sat).
 *
 * Input: [0] the message (fuzz_bus_pick: any of the DBC), [1] bit 0 = saturating encode, then for each
 * signal 8 bytes: the real (bit pattern of fcc_real_t) or the integer.
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fcc_bus.h"
#include "fuzz_bus_records.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void check_value(const fcc_bus_signal_desc_t *s, fcc_real_t asked, fcc_real_t got,
                        bool saturate)
{
    const double lsb = 1.0 / (double)s->inv_scale;
    const double lo = (double)s->raw_min * lsb;
    const double hi = (double)s->raw_max * lsb;
    double want = (double)asked;
    if (saturate) {
        want = (want < lo) ? lo : (want > hi) ? hi : want;
    }
    /* half an LSB, plus the float build's own rounding of the value */
    if (fabs((double)got - want) > 0.5 * lsb + 4.0 * (double)FCC_EPS * fabs(want)) {
        abort();
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 2u) {
        return 0;
    }
    const fcc_msg_t msg = fuzz_bus_pick(data[0]);
    const bool saturate = (data[1] & 1u) != 0u;
    const fcc_bus_msg_desc_t *d = fcc_bus_desc(msg);
    fcc_msg_data_t in;
    memset(&in, 0, sizeof in);
    size_t off = 2u;
    for (uint32_t i = 0u; i < d->n_signals && off + 8u <= size; ++i, off += 8u) {
        fcc_real_t real;
        int64_t integer;
        memcpy(&real, data + off, sizeof real);
        memcpy(&integer, data + off, sizeof integer);
        (void)fcc_bus_signal_set(msg, i, &in, real, integer % 70000);
    }
    static fcc_bus_t tx, rx;
    const uint64_t all = (uint64_t)((1uLL << FCC_MSG_COUNT) - 1u);
    if (fcc_bus_init_masks(&tx, 0u, all) != FCC_OK || fcc_bus_init_masks(&rx, all, 0u) != FCC_OK) {
        abort();
    }
    fcc_can_frame_t f;
    const fcc_status_t st = saturate ? fcc_bus_encode_sat(&tx, msg, &in, &f)
                                     : fcc_bus_encode(&tx, msg, &in, &f);
    if (st != FCC_OK) {
        if (tx.tx_refused != 1u) {
            abort();
        }
        return 0;
    }
    fcc_bus_rx_msg_t m;
    if (fcc_bus_receive(&rx, &f, &m) != FCC_OK) {
        abort(); /* what we encode, we accept */
    }
    for (uint32_t i = 0u; i < d->n_signals; ++i) {
        fcc_real_t a, b;
        int64_t ia, ib;
        (void)fcc_bus_signal_get(msg, i, &in, &a, &ia);
        (void)fcc_bus_signal_get(msg, i, &m.data, &b, &ib);
        if (d->signals[i].phys_type == FCC_FIELD_REAL) {
            check_value(&d->signals[i], a, b, saturate);
        } else if (!saturate && ia != ib) {
            abort();
        }
    }
    return 0;
}
