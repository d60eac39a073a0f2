/*
 * fcc_hist.c -- log-linear histogram (see fcc_hist.h).
 */
#include "fcc_hist.h"

#include <string.h>

void fcc_hist_init(fcc_hist_t *h)
{
    memset(h, 0, sizeof *h);
}

static unsigned int top_bit(uint64_t v)
{
    unsigned int e = 0u;
    while ((v >> 1) != 0u) {
        v >>= 1;
        ++e;
    }
    return e;
}

static uint32_t index_of(uint64_t v)
{
    if (v < FCC_HIST_LINEAR) {
        return (uint32_t)v;
    }
    unsigned int e = top_bit(v); /* >= 7 */
    if (e > 31u) {
        return FCC_HIST_BUCKETS - 1u;
    }
    const uint32_t sub = (uint32_t)((v >> (e - 6u)) & (FCC_HIST_SUB - 1u));
    return FCC_HIST_LINEAR + (e - 7u) * FCC_HIST_SUB + sub;
}

static uint64_t lower_edge(uint32_t i)
{
    if (i < FCC_HIST_LINEAR) {
        return i;
    }
    const uint32_t e = 7u + (i - FCC_HIST_LINEAR) / FCC_HIST_SUB;
    const uint64_t sub = (i - FCC_HIST_LINEAR) % FCC_HIST_SUB;
    return ((uint64_t)1u << e) + (sub << (e - 6u));
}

void fcc_hist_add(fcc_hist_t *h, uint64_t value_us)
{
    ++h->bucket[index_of(value_us)];
    ++h->n;
    h->sum += value_us;
    if (value_us > h->max) {
        h->max = value_us;
    }
}

uint64_t fcc_hist_quantile(const fcc_hist_t *h, double p)
{
    if (h->n == 0u) {
        return 0u;
    }
    if (p >= 1.0) {
        return h->max;
    }
    /* smallest value with at least ceil(p n) samples at or below it */
    uint64_t rank = (uint64_t)(p * (double)h->n);
    if ((double)rank < p * (double)h->n) {
        ++rank;
    }
    if (rank == 0u) {
        rank = 1u;
    }
    uint64_t seen = 0u;
    for (uint32_t i = 0u; i < FCC_HIST_BUCKETS; ++i) {
        seen += h->bucket[i];
        if (seen >= rank) {
            const uint64_t edge = lower_edge(i);
            return (edge > h->max) ? h->max : edge;
        }
    }
    return h->max;
}
