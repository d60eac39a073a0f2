/*
 * canbus_hist.c -- log-linear histogram (see canbus_hist.h).
 *
 * Index of v >= 128: with shift = msb(v) - 6, v >> shift is in 64..127 and
 * the index 64 * shift + (v >> shift), contiguous with the exact 0..127.
 */
#include "canbus_hist.h"

#include <string.h>

static uint32_t msb(uint64_t v)
{
    uint32_t m = 0u;
    while (v >>= 1) {
        ++m;
    }
    return m;
}

static uint32_t bucket(uint64_t v)
{
    if (v < 2u * CANBUS_HIST_SUB) {
        return (uint32_t)v;
    }
    uint32_t shift = msb(v) - 6u;
    if (shift > CANBUS_HIST_SHIFT_MAX) {
        return CANBUS_HIST_BUCKETS - 1u;
    }
    return CANBUS_HIST_SUB * shift + (uint32_t)(v >> shift);
}

static uint64_t upper_edge(uint32_t i)
{
    if (i < 2u * CANBUS_HIST_SUB) {
        return i;
    }
    const uint32_t shift = i / CANBUS_HIST_SUB - 1u;
    const uint64_t m = i - CANBUS_HIST_SUB * shift;
    return ((m + 1u) << shift) - 1u;
}

void canbus_hist_init(canbus_hist_t *h)
{
    memset(h, 0, sizeof *h);
}

void canbus_hist_add(canbus_hist_t *h, uint64_t v)
{
    ++h->count[bucket(v)];
    h->min = h->n == 0u || v < h->min ? v : h->min;
    h->max = v > h->max ? v : h->max;
    ++h->n;
}

uint64_t canbus_hist_quantile(const canbus_hist_t *h, uint64_t num, uint64_t den)
{
    if (h->n == 0u || den == 0u) {
        return 0u;
    }
    uint64_t rank = (h->n * num + den - 1u) / den; /* the ceil(n q)-th smallest */
    rank = rank == 0u ? 1u : rank;
    uint64_t seen = 0u;
    for (uint32_t i = 0u; i < CANBUS_HIST_BUCKETS; ++i) {
        seen += h->count[i];
        if (seen >= rank && i + 1u < CANBUS_HIST_BUCKETS) {
            const uint64_t edge = upper_edge(i);
            return edge < h->max ? edge : h->max;
        }
    }
    return h->max;
}
