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

/* SocketCAN frame r queued at node at t: false when it was not (the caller counts it lost). */
static bool queue_one_raw(canbus_sim_t *s, uint32_t node, const uint8_t *r, uint64_t t)
{
    uint32_t can_id;
    memcpy(&can_id, r, sizeof can_id);
    if ((can_id & RAW_ERR) != 0u) {
        return false; /* an error frame is no classic controller's frame */
    }
    canbus_frame_t f;
    memset(&f, 0, sizeof f);
    f.ext = (can_id & RAW_EFF) != 0u;
    f.rtr = (can_id & RAW_RTR) != 0u;
    f.id = can_id & (f.ext ? CANBUS_EXT_ID_MAX : CANBUS_STD_ID_MAX);
    f.dlc = r[4];
    memcpy(f.data, r + 8, CANBUS_DLC_MAX);
    const fcc_status_t st = canbus_core_queue(&s->core, node, &f, t);
    if (st == FCC_ERR_IO) {
        return true; /* bus-off: dropped (the core counts it), as canbus_sim_queue() */
    }
    if (st != FCC_OK) {
        return false;
    }
    if (worst(s, &f)) {
        /* the entry just queued is the node's last */
        canbus_node_t *q = &s->core.node[node];
        q->entry[q->n - 1u].bits = worst_bits(&f);
    }
    return true;
}

uint32_t canbus_sim_queue_raw(canbus_sim_t *s, uint32_t node, const uint8_t *raw, uint32_t n,
                              uint64_t t)
{
    if (s == NULL || raw == NULL || node >= s->nodes) {
        return 0u;
    }
    for (uint32_t i = 0u; i < n; ++i) {
        if (!queue_one_raw(s, node, raw + (size_t)i * CANBUS_SIM_RAW_LEN, t)) {
            s->stats.node[node].lost += (uint64_t)(n - i); /* it and what follows */
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

#define REPORT_ALL UINT32_MAX

/* One run of the bus: which frames it hands out, and the node's frames it stops at. */
typedef struct {
    canbus_done_t *out; /* NULL: none handed out */
    uint32_t max;
    bool stop_full;     /* stop when out is full (else count past it) */
    uint32_t report;    /* the node whose frames are handed out; REPORT_ALL: the caller's */
    uint32_t n;         /* frames handed out (or that would have been) */
    uint32_t node;      /* with count > 0: stop at the count-th frame of node queued at tq */
    uint64_t tq;
    uint32_t count;
    uint32_t seen;
    uint64_t seen_eof;  /* the end of frame of the last of them */
} run_t;

static void run_to(canbus_sim_t *s, uint64_t t, run_t *r)
{
    while ((!r->stop_full || r->n < r->max) && (r->count == 0u || r->seen < r->count)) {
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
            if (d.node < s->nodes && (r->report == REPORT_ALL || d.node == r->report)) {
                if (r->out != NULL && r->n < r->max) {
                    r->out[r->n] = d;
                }
                ++r->n;
            }
            if (r->count > 0u && d.node == r->node && d.t_queued == r->tq) {
                ++r->seen;
                r->seen_eof = d.t_eof;
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
}

uint32_t canbus_sim_run(canbus_sim_t *s, uint64_t t, canbus_done_t *out, uint32_t max,
                        uint32_t node, uint64_t tq, uint32_t count, uint32_t *seen)
{
    if (s == NULL || out == NULL || (count > 0u && seen == NULL)) {
        return 0u;
    }
    run_t r = {out, max, true, REPORT_ALL, 0u, node, tq, count, count > 0u ? *seen : 0u, 0u};
    run_to(s, t, &r);
    if (count > 0u) {
        *seen = r.seen;
    }
    return r.n;
}

fcc_status_t canbus_sim_roles(canbus_sim_t *s, uint32_t sim, uint32_t fcc, uint32_t last_id,
                              uint64_t compute_ns)
{
    if (s == NULL || sim >= s->nodes || fcc >= s->nodes) {
        return FCC_ERR_ARG;
    }
    s->sim_node = sim;
    s->fcc_node = fcc;
    s->last_id = last_id;
    s->compute_ns = compute_ns;
    return FCC_OK;
}

/* The frames raw[at .. at + n - 1] whose can_id is last_id (last) or is not (!last) queued at
 * node at t, as canbus_sim_queue_raw() would queue them alone: how many were. */
static uint32_t queue_some(canbus_sim_t *s, const uint8_t *raw, uint32_t at, uint32_t n,
                           uint64_t t, bool last)
{
    const uint32_t node = s->sim_node;
    uint32_t queued = 0u;
    uint32_t lost = 0u;
    for (uint32_t i = at; i < at + n; ++i) {
        const uint8_t *r = raw + (size_t)i * CANBUS_SIM_RAW_LEN;
        uint32_t can_id;
        memcpy(&can_id, r, sizeof can_id);
        if ((can_id == s->last_id) != last) {
            continue;
        }
        if (lost > 0u || !queue_one_raw(s, node, r, t)) {
            ++lost; /* it and the others after it */
        } else {
            ++queued;
        }
    }
    s->stats.node[node].lost += lost;
    return queued;
}

static bool step_fits(const canbus_sim_step_t *x, uint32_t raws)
{
    return x->inputs <= raws && x->inputs_at <= raws - x->inputs && x->answer <= raws &&
           x->answer_at <= raws - x->answer;
}

fcc_status_t canbus_sim_steps(canbus_sim_t *s, canbus_sim_step_t *step, uint32_t n,
                              const uint8_t *raw, uint32_t raws, canbus_done_t *out,
                              uint32_t max, uint32_t *reported)
{
    if (s == NULL || step == NULL || (raw == NULL && raws > 0u) || reported == NULL) {
        return FCC_ERR_ARG;
    }
    for (uint32_t k = 0u; k < n; ++k) {
        if (!step_fits(&step[k], raws)) {
            return FCC_ERR_ARG;
        }
    }
    run_t r = {out, max, false, s->fcc_node, 0u, s->sim_node, 0u, 0u, 0u, 0u};
    for (uint32_t k = 0u; k < n; ++k) {
        canbus_sim_step_t *x = &step[k];
        r.count = 0u;
        run_to(s, x->t, &r);
        x->queued = queue_some(s, raw, x->inputs_at, x->inputs, x->t, false);
        (void)queue_some(s, raw, x->inputs_at, x->inputs, x->t, true);
        r.tq = x->t;
        r.count = x->queued;
        r.seen = 0u;
        run_to(s, x->horizon, &r);
        x->t_in = x->queued == 0u ? x->t : r.seen >= x->queued ? r.seen_eof : x->horizon;
        x->answered = x->answer == 0u ? 0u
                                      : canbus_sim_queue_raw(s, s->fcc_node,
                                                             raw + (size_t)x->answer_at *
                                                                       CANBUS_SIM_RAW_LEN,
                                                             x->answer, x->t_in + s->compute_ns);
    }
    *reported = out == NULL ? 0u : (r.n < max ? r.n : max);
    return out != NULL && r.n > max ? FCC_ERR_SIZE : FCC_OK;
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
