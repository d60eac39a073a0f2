/*
 * canbus_frame.c -- a frame's bits on the wire (see canbus_frame.h).
 *
 * The stuffed region is built bit by bit into a small array (at most 54 + 64 +
 * 15 = 133 bits), its CRC-15 appended, and the runs counted as
 * hil.bus.busload does: after five equal bits one complement bit, which
 * starts the next run.
 */
#include "canbus_frame.h"

#include <stddef.h>

#define CRC15_POLY 0x4599u
#define REGION_MAX (54u + 8u * CANBUS_DLC_MAX + 15u)

typedef struct {
    uint8_t bit[REGION_MAX];
    size_t n;
} bits_t;

static void put(bits_t *b, uint32_t value, unsigned width)
{
    for (unsigned i = width; i-- > 0u;) {
        b->bit[b->n++] = (uint8_t)((value >> i) & 1u);
    }
}

static uint32_t crc15(const bits_t *b)
{
    uint32_t crc = 0u;
    for (size_t i = 0u; i < b->n; ++i) {
        const uint32_t next = b->bit[i] ^ ((crc >> 14) & 1u);
        crc = (crc << 1) & 0x7FFFu;
        if (next != 0u) {
            crc ^= CRC15_POLY;
        }
    }
    return crc;
}

static uint32_t stuff_bits(const bits_t *b)
{
    uint32_t count = 0u;
    unsigned run = 0u;
    int last = -1;
    for (size_t i = 0u; i < b->n; ++i) {
        const int bit = b->bit[i];
        run = bit == last ? run + 1u : 1u;
        last = bit;
        if (run == 5u) {
            ++count;
            last = 1 - bit; /* the stuff bit starts a run of its own */
            run = 1u;
        }
    }
    return count;
}

bool canbus_frame_valid(const canbus_frame_t *f)
{
    return f != NULL && f->dlc <= CANBUS_DLC_MAX &&
           f->id <= (f->ext ? CANBUS_EXT_ID_MAX : CANBUS_STD_ID_MAX);
}

uint32_t canbus_frame_bits(const canbus_frame_t *f)
{
    if (!canbus_frame_valid(f)) {
        return 0u;
    }
    bits_t b;
    b.n = 0u;
    put(&b, 0u, 1u); /* SOF */
    if (f->ext) {
        put(&b, f->id >> 18, 11u);
        put(&b, 3u, 2u); /* SRR, IDE */
        put(&b, f->id & 0x3FFFFu, 18u);
        put(&b, f->rtr ? 1u : 0u, 1u);
        put(&b, 0u, 2u); /* r1, r0 */
    } else {
        put(&b, f->id, 11u);
        put(&b, f->rtr ? 1u : 0u, 1u);
        put(&b, 0u, 2u); /* IDE, r0 */
    }
    put(&b, f->dlc, 4u);
    if (!f->rtr) {
        for (unsigned i = 0u; i < f->dlc; ++i) {
            put(&b, f->data[i], 8u);
        }
    }
    put(&b, crc15(&b), 15u);
    return (uint32_t)b.n + stuff_bits(&b) + CANBUS_TAIL_BITS;
}

uint32_t canbus_frame_arbitration(const canbus_frame_t *f)
{
    const uint32_t rtr = f->rtr ? 1u : 0u;
    if (f->ext) {
        /* base 11 | SRR 1 | IDE 1 | extension 18 | RTR */
        return ((f->id >> 18) << 21) | (1u << 20) | (1u << 19) | ((f->id & 0x3FFFFu) << 1) | rtr;
    }
    /* base 11 | RTR | IDE 0: then the arbitration field has ended */
    return (f->id << 21) | (rtr << 20);
}
