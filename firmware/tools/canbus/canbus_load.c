/*
 * canbus_load.c -- background traffic on the bus (see canbus_load.h).
 */
#include "canbus_load.h"

#include <stddef.h>
#include <string.h>

/* SPEC §8: an 8-byte 11-bit frame is at most 135 bits, interframe space included. */
#define LOAD_FRAME_BITS 135u
#define LOAD_DLC 8u

/* xorshift64* (Vigna 2016): small, fast, and the same numbers on every platform. */
static uint64_t draw(uint64_t *s)
{
    uint64_t x = *s;
    x ^= x >> 12;
    x ^= x << 25;
    x ^= x >> 27;
    *s = x;
    return x * 0x2545F4914F6CDD1Dull;
}

fcc_status_t canbus_load_init(canbus_load_t *l, const canbus_load_cfg_t *cfg, uint64_t bit_ns)
{
    if (l == NULL || cfg == NULL) {
        return FCC_ERR_ARG;
    }
    if (cfg->id_lo > cfg->id_hi || cfg->id_hi > CANBUS_STD_ID_MAX || cfg->ppm == 0u ||
        cfg->ppm > CANBUS_LOAD_PPM_MAX || cfg->start_ns >= cfg->end_ns || bit_ns == 0u) {
        return FCC_ERR_RANGE;
    }
    memset(l, 0, sizeof *l);
    l->cfg = *cfg;
    const uint32_t span = cfg->id_hi - cfg->id_lo;
    l->streams = span + 1u < CANBUS_LOAD_STREAMS_MAX ? span + 1u : CANBUS_LOAD_STREAMS_MAX;
    /* period = streams * C / U, rounded up: the utilisation stays at most ppm */
    const uint64_t work = (uint64_t)l->streams * LOAD_FRAME_BITS * bit_ns * CANBUS_LOAD_PPM_MAX;
    l->period_ns = (work + cfg->ppm - 1u) / cfg->ppm;
    /* the seed 0 would stay 0 for ever: mix in a constant */
    l->rng = cfg->seed ^ 0x9E3779B97F4A7C15ull;
    for (uint32_t i = 0u; i < l->streams; ++i) {
        l->id[i] = cfg->id_lo + (l->streams > 1u ? i * span / (l->streams - 1u) : 0u);
        l->next[i] = cfg->start_ns + draw(&l->rng) % l->period_ns;
    }
    return FCC_OK;
}

/* The stream released first (the lowest index of equals). */
static uint32_t first_stream(const canbus_load_t *l)
{
    uint32_t best = 0u;
    for (uint32_t i = 1u; i < l->streams; ++i) {
        if (l->next[i] < l->next[best]) {
            best = i;
        }
    }
    return best;
}

bool canbus_load_next(const canbus_load_t *l, uint64_t *t)
{
    if (l == NULL || t == NULL || l->streams == 0u) {
        return false;
    }
    const uint64_t first = l->next[first_stream(l)];
    if (first >= l->cfg.end_ns) {
        return false;
    }
    *t = first;
    return true;
}

void canbus_load_take(canbus_load_t *l, canbus_frame_t *f)
{
    if (l == NULL || f == NULL || l->streams == 0u) {
        return;
    }
    const uint32_t i = first_stream(l);
    memset(f, 0, sizeof *f);
    f->id = l->id[i];
    f->dlc = (uint8_t)LOAD_DLC;
    uint64_t bytes = draw(&l->rng);
    for (uint32_t b = 0u; b < LOAD_DLC; ++b) {
        f->data[b] = (uint8_t)(bytes >> (8u * b));
    }
    l->next[i] += l->period_ns;
}

bool canbus_load_stream(const canbus_load_t *l, uint32_t i, uint32_t *id, uint64_t *period_ns)
{
    if (l == NULL || id == NULL || period_ns == NULL || i >= l->streams) {
        return false;
    }
    *id = l->id[i];
    *period_ns = l->period_ns;
    return true;
}

int canbus_load_first(const canbus_load_t *l, uint32_t n, uint64_t *t)
{
    int best = -1;
    for (uint32_t i = 0u; l != NULL && t != NULL && i < n; ++i) {
        uint64_t r;
        if (canbus_load_next(&l[i], &r) && (best < 0 || r < *t)) {
            best = (int)i;
            *t = r;
        }
    }
    return best;
}

bool canbus_load_feed_one(canbus_load_t *l, uint32_t n, const uint32_t *node, canbus_core_t *c,
                          uint64_t t, uint64_t *dropped)
{
    uint64_t when = 0u;
    const int i = canbus_load_first(l, n, &when);
    if (i < 0 || when > t || node == NULL || dropped == NULL) {
        return false;
    }
    canbus_frame_t f;
    canbus_load_take(&l[i], &f);
    if (canbus_core_queue(c, node[i], &f, when) != FCC_OK) {
        ++*dropped;
    }
    return true;
}
