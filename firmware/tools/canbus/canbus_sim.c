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
    char err[128];
    return canbus_sim_setup(s, bitrate, nodes, policy, name, load, loads, NULL, 0u, err,
                            sizeof err);
}

/* Node i's name in the statistics: the caller's, a load's, a babbling node's. */
static const char *node_name(const canbus_sim_t *s, uint32_t i, const char *const *name,
                             uint32_t loads)
{
    if (i < s->nodes) {
        return name[i];
    }
    const uint32_t babbler = i - s->nodes - loads;
    return i >= s->nodes + loads && babbler < s->faults.babbles ? canbus_babble_names[babbler]
                                                                 : "load";
}

/* The caller's names for canbus_fault_opts_resolve(); FCC_ERR_ARG: NULL. */
static fcc_status_t copy_names(canbus_sim_t *s, const char *const *name, uint32_t nodes)
{
    for (uint32_t i = 0u; i < nodes; ++i) {
        if (name[i] == NULL) {
            return FCC_ERR_ARG;
        }
        (void)snprintf(s->names[i], sizeof s->names[i], "%s", name[i]);
    }
    return FCC_OK;
}

fcc_status_t canbus_sim_setup(canbus_sim_t *s, uint32_t bitrate, uint32_t nodes,
                              const canbus_policy_t *policy, const char *const *name,
                              const canbus_load_cfg_t *load, uint32_t loads,
                              const char *const *opt, uint32_t opts, char *err, size_t len)
{
    if (s == NULL || policy == NULL || name == NULL || (load == NULL && loads > 0u) ||
        (opt == NULL && opts > 0u) || err == NULL) {
        return FCC_ERR_ARG;
    }
    memset(s, 0, sizeof *s);
    if (canbus_fault_opts_pairs(&s->faults, opt, opts, err, len) != FCC_OPT_DONE) {
        return FCC_ERR_ARG;
    }
    const uint32_t extra = s->faults.babbles + s->faults.loads;
    if (loads + s->faults.loads > CANBUS_SIM_LOADS_MAX || nodes > CANBUS_NODES_MAX ||
        loads + extra > CANBUS_NODES_MAX - nodes) {
        (void)snprintf(err, len, "at most %u loads and %u nodes in all", CANBUS_SIM_LOADS_MAX,
                       CANBUS_NODES_MAX);
        return FCC_ERR_SIZE;
    }
    const uint32_t all = nodes + loads + extra;
    for (uint32_t i = 0u; i < all; ++i) {
        s->policy[i] = i < nodes ? policy[i] : CANBUS_PRIO;
    }
    fcc_status_t st = copy_names(s, name, nodes);
    if (st == FCC_OK) {
        st = canbus_core_init(&s->core, bitrate, all, s->policy);
    }
    if (st != FCC_OK) {
        return st;
    }
    canbus_stats_init(&s->stats, bitrate);
    s->nodes = nodes;
    s->stats.nodes = all;
    for (uint32_t i = 0u; i < all; ++i) {
        s->stats.node[i].iface = node_name(s, i, name, loads);
        s->stats.node[i].policy = s->policy[i];
    }
    for (uint32_t l = 0u; l < loads && st == FCC_OK; ++l) {
        st = canbus_load_init(&s->load[l], &load[l], s->core.bit_ns);
        s->load_node[l] = nodes + l;
    }
    if (st == FCC_OK &&
        canbus_fault_opts_resolve(&s->faults, s->names, nodes, err, len) != FCC_OPT_DONE) {
        st = FCC_ERR_ARG;
    }
    if (st == FCC_OK) {
        st = canbus_fault_opts_arm(&s->faults, &s->core, nodes + loads, 0u, s->load + loads,
                                   s->load_node + loads);
    }
    s->loads = loads + s->faults.loads;
    s->stats.load = s->load;
    s->stats.loads = s->loads;
    return st;
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
        const fcc_status_t st = canbus_core_queue(&s->core, node, &f[i], t);
        if (st == FCC_ERR_IO) {
            continue; /* bus-off: dropped (the core counts it) */
        }
        if (st != FCC_OK) {
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
        if (!canbus_load_feed_one(s->load, s->loads, s->load_node, &s->core, next,
                                  &s->stats.load_dropped)) {
            return;
        }
    }
}

/* Fault confinement's events: the recoveries into the statistics (nobody else listens). */
static void drain_events(canbus_sim_t *s)
{
    canbus_event_t e;
    while (canbus_core_event(&s->core, &e)) {
        canbus_stats_event(&s->stats, &s->core, &e);
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
        const bool ended = canbus_core_advance(&s->core, ev, &d);
        drain_events(s);
        if (ended) {
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
    drain_events(s);
    canbus_stats_core(&s->stats, &s->core);
    s->stats.wall_s = (double)s->core.now / NS_PER_S;
    s->stats.cpu_s = 0.0;
    fcc_status_t st = canbus_stats_json(&s->stats, out);
    if (fclose(out) != 0) {
        st = FCC_ERR_IO;
    }
    return st;
}
