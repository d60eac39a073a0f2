/*
 * canbus_load.h -- background traffic on the bus: another ECU's periodic
 * frames, at a chosen utilisation and identifier range (issue 35, item 3).
 *
 * The node sends `streams` periodic frames (one per identifier, the
 * identifiers spread evenly over [id_lo, id_hi], 11-bit, 8 data bytes), all
 * with the same period, chosen so that their worst-case frame times fill
 * `ppm` parts per million of the bus: period = streams * C / U, C the
 * 135-bit worst case of an 8-byte frame (SPEC §8), rounded up to a whole
 * nanosecond (so the utilisation is at most the one asked for; stuffing on
 * the actual bits makes the carried load a little lower still).  Periodic,
 * not random arrivals, so that the worst-case response time analysis covers
 * the load (hil.bus.wcrt takes the same streams).  Each stream's phase in
 * [0, period) and every frame's data bytes come from a xorshift64* generator
 * seeded with `seed`: the same configuration gives the same frames.  Frames
 * are released in [start_ns, end_ns) only.
 *
 * OS-free, no dynamic memory: canbus_sim.c feeds it to the core in
 * simulated time, the canbus process (--load) in wall time, both through
 * canbus_load_feed_one().
 */
#ifndef CANBUS_LOAD_H
#define CANBUS_LOAD_H

#include <stdbool.h>
#include <stdint.h>

#include "canbus_core.h"
#include "canbus_frame.h"
#include "fcc_types.h"

#define CANBUS_LOAD_STREAMS_MAX 16u
/* background nodes a bus may have */
#define CANBUS_LOADS_MAX 4u
/* 1e6: the whole bus */
#define CANBUS_LOAD_PPM_MAX 1000000u

typedef struct {
    uint32_t id_lo;     /* 11-bit identifiers, id_lo <= id_hi */
    uint32_t id_hi;
    uint32_t ppm;       /* utilisation, parts per million (1..CANBUS_LOAD_PPM_MAX) */
    uint64_t start_ns;  /* releases in [start_ns, end_ns) */
    uint64_t end_ns;
    uint64_t seed;
} canbus_load_cfg_t;

typedef struct {
    canbus_load_cfg_t cfg;
    uint32_t streams;
    uint32_t id[CANBUS_LOAD_STREAMS_MAX];
    uint64_t next[CANBUS_LOAD_STREAMS_MAX];  /* each stream's next release */
    uint64_t period_ns;
    uint64_t rng;
} canbus_load_t;

/* The generator for a bus of bit_ns nanoseconds a bit.  FCC_ERR_ARG: NULL;
 * FCC_ERR_RANGE: an identifier range or utilisation out of range, an empty
 * window, bit_ns 0. */
fcc_status_t canbus_load_init(canbus_load_t *l, const canbus_load_cfg_t *cfg, uint64_t bit_ns);

/* When the next frame is released: false when none is left in the window. */
bool canbus_load_next(const canbus_load_t *l, uint64_t *t);

/* The frame released then (call after canbus_load_next said true), and the
 * generator moves on to the next. */
void canbus_load_take(canbus_load_t *l, canbus_frame_t *f);

/* Stream i's identifier and the common period (false: no such stream). */
bool canbus_load_stream(const canbus_load_t *l, uint32_t i, uint32_t *id, uint64_t *period_ns);

/* The load of l[0..n-1] whose next frame is released first: its index, its
 * release in *t; -1 when none is left. */
int canbus_load_first(const canbus_load_t *l, uint32_t n, uint64_t *t);

/* The frame of l[0..n-1] released first, when at or before t: queued at c on
 * node[i] (the i-th load's node) at its release time, true; *dropped + 1
 * when the node refused it (its queue full).  false: none released by t. */
bool canbus_load_feed_one(canbus_load_t *l, uint32_t n, const uint32_t *node, canbus_core_t *c,
                          uint64_t t, uint64_t *dropped);

#endif /* CANBUS_LOAD_H */
