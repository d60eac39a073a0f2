/*
 * canbus_core.c -- the bus in time (see canbus_core.h).
 */
#include "canbus_core.h"

#include <stddef.h>
#include <string.h>

#define NS_PER_S 1000000000ul

fcc_status_t canbus_core_init(canbus_core_t *c, uint32_t bitrate, uint32_t nodes,
                              const canbus_policy_t *policy)
{
    if (c == NULL || policy == NULL) {
        return FCC_ERR_ARG;
    }
    if (nodes == 0u || nodes > CANBUS_NODES_MAX || bitrate == 0u || bitrate > NS_PER_S ||
        NS_PER_S % bitrate != 0u) {
        return FCC_ERR_RANGE;
    }
    memset(c, 0, sizeof *c);
    for (uint32_t i = 0u; i < nodes; ++i) {
        if (policy[i] != CANBUS_PRIO && policy[i] != CANBUS_FIFO) {
            return FCC_ERR_RANGE;
        }
        c->node[i].policy = policy[i];
    }
    c->bit_ns = NS_PER_S / bitrate;
    c->nodes = nodes;
    return FCC_OK;
}

fcc_status_t canbus_core_queue(canbus_core_t *c, uint32_t node, const canbus_frame_t *f,
                               uint64_t t)
{
    if (c == NULL || node >= c->nodes || !canbus_frame_valid(f)) {
        return FCC_ERR_ARG;
    }
    canbus_node_t *n = &c->node[node];
    if (n->n == CANBUS_QUEUE_LEN) {
        return FCC_ERR_AGAIN;
    }
    canbus_entry_t *e = &n->entry[n->n++];
    e->frame = *f;
    e->t_queued = t;
    if (c->started && t < c->last_sof) {
        ++c->late;
    }
    e->arbitration = canbus_frame_arbitration(f);
    e->bits = canbus_frame_bits(f);
    return FCC_OK;
}

uint32_t canbus_core_pending(const canbus_core_t *c, uint32_t node)
{
    return c != NULL && node < c->nodes ? c->node[node].n : 0u;
}

/* The entry node offers to an arbitration at time s, or -1: a FIFO its head once queued,
 * priority mailboxes the lowest arbitration field queued by then (the first queued of equals). */
static int offered(const canbus_node_t *n, uint64_t s)
{
    if (n->policy == CANBUS_FIFO) {
        return n->n > 0u && n->entry[0].t_queued <= s ? 0 : -1;
    }
    int best = -1;
    for (uint32_t i = 0u; i < n->n; ++i) {
        const canbus_entry_t *e = &n->entry[i];
        if (e->t_queued <= s && (best < 0 || e->arbitration < n->entry[best].arbitration)) {
            best = (int)i;
        }
    }
    return best;
}

/* When node first has a frame to offer: false when its queue is empty. */
static bool ready_at(const canbus_node_t *n, uint64_t *t)
{
    if (n->n == 0u) {
        return false;
    }
    uint64_t first = n->entry[0].t_queued;
    for (uint32_t i = 1u; n->policy == CANBUS_PRIO && i < n->n; ++i) {
        if (n->entry[i].t_queued < first) {
            first = n->entry[i].t_queued;
        }
    }
    *t = first;
    return true;
}

/* The next arbitration on the idle bus: when it is idle and some node has a frame to offer. */
static bool next_arbitration(const canbus_core_t *c, uint64_t *s)
{
    bool any = false;
    uint64_t first = 0u;
    for (uint32_t i = 0u; i < c->nodes; ++i) {
        uint64_t t;
        if (ready_at(&c->node[i], &t) && (!any || t < first)) {
            first = t;
            any = true;
        }
    }
    if (any) {
        *s = first > c->idle_at ? first : c->idle_at;
    }
    return any;
}

/* Arbitration at s (a node offers a frame then): the winner leaves its queue for the bus. */
static void start_frame(canbus_core_t *c, uint64_t s)
{
    uint32_t winner = 0u;
    int slot = -1;
    for (uint32_t i = 0u; i < c->nodes; ++i) {
        const int k = offered(&c->node[i], s);
        if (k >= 0 && (slot < 0 || c->node[i].entry[k].arbitration <
                                       c->node[winner].entry[slot].arbitration)) {
            winner = i;
            slot = k;
        }
    }
    canbus_node_t *n = &c->node[winner];
    const canbus_entry_t *e = &n->entry[slot];
    c->cur.frame = e->frame;
    c->cur.node = winner;
    c->cur.bits = e->bits;
    c->cur.t_queued = e->t_queued;
    c->cur.t_sof = s;
    c->cur.t_eof = s + (uint64_t)(e->bits - CANBUS_IFS_BITS) * c->bit_ns;
    c->busy = true;
    c->started = true;
    c->last_sof = s;
    memmove(&n->entry[slot], &n->entry[slot + 1], (n->n - (uint32_t)slot - 1u) * sizeof *e);
    --n->n;
}

bool canbus_core_advance(canbus_core_t *c, uint64_t t, canbus_done_t *out)
{
    if (c == NULL || out == NULL) {
        return false;
    }
    for (;;) {
        if (c->busy) {
            if (c->cur.t_eof > t) {
                break;
            }
            *out = c->cur;
            c->busy = false;
            c->idle_at = c->cur.t_eof + CANBUS_IFS_BITS * c->bit_ns;
            c->now = c->cur.t_eof > c->now ? c->cur.t_eof : c->now;
            return true;
        }
        uint64_t s;
        if (!next_arbitration(c, &s) || s > t) {
            break;
        }
        start_frame(c, s);
    }
    c->now = t > c->now ? t : c->now;
    return false;
}

bool canbus_core_next(const canbus_core_t *c, uint64_t *t, bool *is_eof)
{
    if (c == NULL || t == NULL || is_eof == NULL) {
        return false;
    }
    if (c->busy) {
        *t = c->cur.t_eof;
        *is_eof = true;
        return true;
    }
    *is_eof = false;
    return next_arbitration(c, t);
}
