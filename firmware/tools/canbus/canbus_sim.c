/*
 * canbus_sim.c -- the bus model in simulated time (see canbus_sim.h).
 */
#include "canbus_sim.h"

#include <stdio.h>
#include <string.h>

#define NS_PER_S 1000000000.0

size_t canbus_sim_size(void)
{
    return sizeof(canbus_sim_t);
}

fcc_status_t canbus_sim_init(canbus_sim_t *s, uint32_t bitrate, uint32_t nodes,
                             const canbus_policy_t *policy, const char *const *name,
                             const canbus_load_cfg_t *load, uint32_t loads)
{
    if (s == NULL || policy == NULL || name == NULL || (load == NULL && loads > 0u)) {
        return FCC_ERR_ARG;
    }
    if (loads > CANBUS_SIM_LOADS_MAX || nodes > CANBUS_NODES_MAX - loads) {
        return FCC_ERR_SIZE;
    }
    memset(s, 0, sizeof *s);
    for (uint32_t i = 0u; i < nodes + loads; ++i) {
        s->policy[i] = i < nodes ? policy[i] : CANBUS_PRIO;
    }
    fcc_status_t st = canbus_core_init(&s->core, bitrate, nodes + loads, s->policy);
    if (st != FCC_OK) {
        return st;
    }
    canbus_stats_init(&s->stats, bitrate);
    s->nodes = nodes;
    s->stats.nodes = nodes + loads;
    for (uint32_t i = 0u; i < nodes + loads; ++i) {
        if (i < nodes && name[i] == NULL) {
            return FCC_ERR_ARG;
        }
        s->stats.node[i].iface = i < nodes ? name[i] : "load";
        s->stats.node[i].policy = s->policy[i];
    }
    for (uint32_t l = 0u; l < loads; ++l) {
        st = canbus_load_init(&s->load[l], &load[l], s->core.bit_ns);
        if (st != FCC_OK) {
            return st;
        }
        s->load_node[l] = nodes + l;
    }
    s->loads = loads;
    return FCC_OK;
}

/* SPEC §8: the worst-case length, interframe space included (a remote frame has no data). */
static uint32_t worst_bits(const canbus_frame_t *f)
{
    const uint32_t g = f->ext ? 54u : 34u;
    const uint32_t d = f->rtr ? 0u : 8u * f->dlc;
    return g + d + CANBUS_TAIL_BITS + (g + d - 1u) / 4u;
}

uint32_t canbus_sim_queue(canbus_sim_t *s, uint32_t node, const canbus_frame_t *f, uint32_t n,
                          uint64_t t, const uint8_t *worst)
{
    if (s == NULL || f == NULL || node >= s->nodes) {
        return 0u;
    }
    for (uint32_t i = 0u; i < n; ++i) {
        if (canbus_core_queue(&s->core, node, &f[i], t) != FCC_OK) {
            s->stats.node[node].lost += (uint64_t)(n - i);
            return i;
        }
        if (worst != NULL && worst[i] != 0u) {
            /* the entry just queued is the node's last */
            canbus_node_t *q = &s->core.node[node];
            q->entry[q->n - 1u].bits = worst_bits(&f[i]);
        }
    }
    return n;
}

fcc_status_t canbus_sim_worst(canbus_sim_t *s, const uint32_t *id, uint32_t n)
{
    if (s == NULL || (id == NULL && n > 0u)) {
        return FCC_ERR_ARG;
    }
    if (n > CANBUS_SIM_WORST_MAX) {
        return FCC_ERR_SIZE;
    }
    for (uint32_t i = 0u; i < n; ++i) {
        s->worst_id[i] = id[i];
    }
    s->worst_ids = n;
    return FCC_OK;
}

static bool worst(const canbus_sim_t *s, const canbus_frame_t *f)
{
    for (uint32_t i = 0u; i < s->worst_ids && !f->ext; ++i) {
        if (s->worst_id[i] == f->id) {
            return true;
        }
    }
    return false;
}

#define RAW_EFF 0x80000000ul
#define RAW_RTR 0x40000000ul
#define RAW_ERR 0x20000000ul

uint32_t canbus_sim_queue_raw(canbus_sim_t *s, uint32_t node, const uint8_t *raw, uint32_t n,
                              uint64_t t)
{
    if (s == NULL || raw == NULL || node >= s->nodes) {
        return 0u;
    }
    for (uint32_t i = 0u; i < n; ++i) {
        const uint8_t *r = raw + (size_t)i * CANBUS_SIM_RAW_LEN;
        uint32_t can_id;
        memcpy(&can_id, r, sizeof can_id);
        canbus_frame_t f;
        memset(&f, 0, sizeof f);
        f.ext = (can_id & RAW_EFF) != 0u;
        f.rtr = (can_id & RAW_RTR) != 0u;
        f.id = can_id & (f.ext ? CANBUS_EXT_ID_MAX : CANBUS_STD_ID_MAX);
        f.dlc = r[4];
        memcpy(f.data, r + 8, CANBUS_DLC_MAX);
        const uint8_t mark = (uint8_t)worst(s, &f);
        /* an error frame is no classic controller's frame: lost with what follows */
        if ((can_id & RAW_ERR) != 0u || canbus_sim_queue(s, node, &f, 1u, t, &mark) != 1u) {
            if ((can_id & RAW_ERR) != 0u) {
                s->stats.node[node].lost += (uint64_t)(n - i);
            } else {
                s->stats.node[node].lost += (uint64_t)(n - i - 1u);
            }
            return i;
        }
    }
    return n;
}

/* The load released first, at or before t: its index, or -1. */
static int due_load(const canbus_sim_t *s, uint64_t t, uint64_t *when)
{
    int best = -1;
    for (uint32_t i = 0u; i < s->loads; ++i) {
        uint64_t r;
        if (canbus_load_next(&s->load[i], &r) && r <= t && (best < 0 || r < *when)) {
            best = (int)i;
            *when = r;
        }
    }
    return best;
}

/* Queues every load frame released by the core's next event (or by t): the
 * core never passes a release it was not given. */
static void feed_loads(canbus_sim_t *s, uint64_t t)
{
    for (;;) {
        uint64_t next = t;
        bool is_eof;
        uint64_t ev;
        if (canbus_core_next(&s->core, &ev, &is_eof) && ev < next) {
            next = ev;
        }
        uint64_t when = 0u;
        const int i = due_load(s, next, &when);
        if (i < 0) {
            return;
        }
        canbus_frame_t f;
        canbus_load_take(&s->load[i], &f);
        if (canbus_core_queue(&s->core, s->load_node[i], &f, when) != FCC_OK) {
            ++s->load_dropped;
        }
    }
}

uint32_t canbus_sim_run(canbus_sim_t *s, uint64_t t, canbus_done_t *out, uint32_t max,
                        uint32_t node, uint64_t tq, uint32_t count, uint32_t *seen)
{
    if (s == NULL || out == NULL || (count > 0u && seen == NULL)) {
        return 0u;
    }
    uint32_t n = 0u;
    while (n < max && (count == 0u || *seen < count)) {
        feed_loads(s, t);
        /* one event at a time, so that the loads are fed before each */
        uint64_t ev = t;
        bool is_eof;
        if (!canbus_core_next(&s->core, &ev, &is_eof) || ev > t) {
            ev = t;
        }
        canbus_done_t d;
        if (canbus_core_advance(&s->core, ev, &d)) {
            canbus_stats_frame(&s->stats, &d, s->core.bit_ns);
            if (d.node < s->nodes) {
                out[n++] = d;
            }
            if (count > 0u && d.node == node && d.t_queued == tq) {
                ++*seen;
            }
            continue;
        }
        if (ev == t) {
            uint64_t again;
            bool eof_again;
            /* at t with nothing more to do at t itself */
            if (!canbus_core_next(&s->core, &again, &eof_again) || again > t) {
                break;
            }
        }
    }
    s->stats.late_queued = s->core.late;
    return n;
}

uint32_t canbus_sim_pending(const canbus_sim_t *s, uint32_t node)
{
    if (s == NULL) {
        return 0u;
    }
    const uint32_t on_bus = s->core.busy && s->core.cur.node == node ? 1u : 0u;
    return canbus_core_pending(&s->core, node) + on_bus;
}

fcc_status_t canbus_sim_json(canbus_sim_t *s, const char *path)
{
    if (s == NULL || path == NULL) {
        return FCC_ERR_ARG;
    }
    FILE *out = fopen(path, "w");
    if (out == NULL) {
        return FCC_ERR_IO;
    }
    s->stats.wall_s = (double)s->core.now / NS_PER_S;
    s->stats.cpu_s = 0.0;
    s->stats.late_queued = s->core.late;
    s->stats.pending = 0u;
    for (uint32_t i = 0u; i < s->core.nodes; ++i) {
        s->stats.pending += canbus_sim_pending(s, i);
    }
    fcc_status_t st = canbus_stats_json(&s->stats, out);
    fputs("{\"load_streams\": [", out);
    const char *sep = "";
    for (uint32_t l = 0u; l < s->loads; ++l) {
        uint32_t id;
        uint64_t period;
        for (uint32_t i = 0u; canbus_load_stream(&s->load[l], i, &id, &period); ++i) {
            fprintf(out, "%s{\"id\": %lu, \"period_ns\": %llu}", sep, (unsigned long)id,
                    (unsigned long long)period);
            sep = ", ";
        }
    }
    fprintf(out, "], \"load_dropped\": %llu}\n", (unsigned long long)s->load_dropped);
    if (fclose(out) != 0) {
        st = FCC_ERR_IO;
    }
    return st;
}
