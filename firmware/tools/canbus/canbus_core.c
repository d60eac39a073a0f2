/*
 * canbus_core.c -- the bus in time (see canbus_core.h), with its faults
 * (canbus_faults.h): error frames and retransmission, fault confinement,
 * bus-off and its recovery, babbling nodes.
 */
#include "canbus_core.h"

#include <stddef.h>
#include <string.h>

#define NS_PER_S 1000000000ul
#define NEVER UINT64_MAX

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

unsigned long canbus_core_size(void)
{
    return (unsigned long)sizeof(canbus_core_t);
}

static void emit(canbus_core_t *c, uint64_t t, uint32_t node, canbus_event_kind_t kind,
                 uint32_t bit, uint32_t id)
{
    if (c->events == CANBUS_EVENTS_MAX) {
        ++c->events_lost;
        return;
    }
    const canbus_confine_t *n = &c->confine[node];
    canbus_event_t *e = &c->event[(c->event_first + c->events) % CANBUS_EVENTS_MAX];
    ++c->events;
    e->t = t;
    e->node = node;
    e->kind = kind;
    e->state = n->state;
    e->tec = n->tec;
    e->rec = n->rec;
    e->bit = bit;
    e->id = id;
    e->frame_bits = kind == CANBUS_EV_TX_ERROR || kind == CANBUS_EV_RX_ERROR ? c->cur.bits : 0u;
}

bool canbus_core_event(canbus_core_t *c, canbus_event_t *out)
{
    if (c == NULL || out == NULL || c->events == 0u) {
        return false;
    }
    *out = c->event[c->event_first];
    c->event_first = (c->event_first + 1u) % CANBUS_EVENTS_MAX;
    --c->events;
    return true;
}

const canbus_confine_t *canbus_core_confine(const canbus_core_t *c, uint32_t node)
{
    return c != NULL && node < c->nodes ? &c->confine[node] : NULL;
}

static void push(canbus_core_t *c, uint32_t node, const canbus_frame_t *f, uint64_t t,
                 uint32_t babble)
{
    canbus_node_t *n = &c->node[node];
    canbus_entry_t *e = &n->entry[n->n++];
    e->frame = *f;
    e->t_queued = t;
    e->arbitration = canbus_frame_arbitration(f);
    e->bits = canbus_frame_bits(f);
    e->babble = babble;
    e->errors = 0u;
}

fcc_status_t canbus_core_queue(canbus_core_t *c, uint32_t node, const canbus_frame_t *f,
                               uint64_t t)
{
    if (c == NULL || node >= c->nodes || !canbus_frame_valid(f)) {
        return FCC_ERR_ARG;
    }
    if (c->confine[node].state == CANBUS_BUS_OFF) {
        ++c->confine[node].dropped;
        return FCC_ERR_IO;
    }
    if (c->node[node].n == CANBUS_QUEUE_LEN) {
        return FCC_ERR_AGAIN;
    }
    if (c->started && t < c->last_sof) {
        ++c->late;
    }
    push(c, node, f, t, 0u);
    return FCC_OK;
}

uint32_t canbus_core_pending(const canbus_core_t *c, uint32_t node)
{
    return c != NULL && node < c->nodes ? c->node[node].n : 0u;
}

fcc_status_t canbus_core_add_fault(canbus_core_t *c, const canbus_fault_t *f)
{
    if (c == NULL || !canbus_fault_valid(f) || (f->node != CANBUS_ANY_NODE && f->node >= c->nodes)) {
        return FCC_ERR_ARG;
    }
    if (c->faults == CANBUS_FAULTS_MAX) {
        return FCC_ERR_SIZE;
    }
    c->fault[c->faults++] = *f;
    return FCC_OK;
}

fcc_status_t canbus_core_add_babble(canbus_core_t *c, const canbus_babble_t *b)
{
    if (c == NULL || b == NULL || b->node >= c->nodes || !canbus_frame_valid(&b->frame) ||
        b->t_from > b->t_to) {
        return FCC_ERR_ARG;
    }
    if (c->babbles == CANBUS_BABBLE_MAX) {
        return FCC_ERR_SIZE;
    }
    c->babble_next[c->babbles] = b->t_from;
    c->babble[c->babbles++] = *b;
    return FCC_OK;
}

/* ---- arbitration ------------------------------------------------------------------------- */

/* The entry node i offers to an arbitration at time s, or -1: a FIFO its head once queued,
 * priority mailboxes the lowest arbitration field queued by then (the first queued of equals);
 * none while it suspends transmission (error-passive, after its own frame). */
static int offered(const canbus_core_t *c, uint32_t i, uint64_t s)
{
    const canbus_node_t *n = &c->node[i];
    if (s < c->confine[i].suspend_until) {
        return -1;
    }
    if (n->policy == CANBUS_FIFO) {
        return n->n > 0u && n->entry[0].t_queued <= s ? 0 : -1;
    }
    int best = -1;
    for (uint32_t k = 0u; k < n->n; ++k) {
        const canbus_entry_t *e = &n->entry[k];
        if (e->t_queued <= s && (best < 0 || e->arbitration < n->entry[best].arbitration)) {
            best = (int)k;
        }
    }
    return best;
}

/* When node i first has a frame to offer: false when its queue is empty. */
static bool ready_at(const canbus_core_t *c, uint32_t i, uint64_t *t)
{
    const canbus_node_t *n = &c->node[i];
    if (n->n == 0u) {
        return false;
    }
    uint64_t first = n->entry[0].t_queued;
    for (uint32_t k = 1u; n->policy == CANBUS_PRIO && k < n->n; ++k) {
        if (n->entry[k].t_queued < first) {
            first = n->entry[k].t_queued;
        }
    }
    *t = first > c->confine[i].suspend_until ? first : c->confine[i].suspend_until;
    return true;
}

/* The next arbitration on the idle bus: when it is idle and some node has a frame to offer. */
static bool next_arbitration(const canbus_core_t *c, uint64_t *s)
{
    bool any = false;
    uint64_t first = 0u;
    for (uint32_t i = 0u; i < c->nodes; ++i) {
        uint64_t t;
        if (ready_at(c, i, &t) && (!any || t < first)) {
            first = t;
            any = true;
        }
    }
    if (any) {
        *s = first > c->idle_at ? first : c->idle_at;
    }
    return any;
}

/* ---- faults ------------------------------------------------------------------------------ */

/* The fault that corrupts frame e of node at its start s, or -1 (each fault counts the
 * frames it matches, the first one hitting wins).  A retransmission is not a new frame: only
 * a fault hitting each attempt (every 1) hits it again. */
static int fault_hit(canbus_core_t *c, uint32_t node, const canbus_entry_t *e, uint64_t s)
{
    for (uint32_t i = 0u; i < c->faults; ++i) {
        const canbus_fault_t *f = &c->fault[i];
        if (c->fault_spent[i] || (f->node != CANBUS_ANY_NODE && f->node != node) ||
            e->frame.id < f->id_min || e->frame.id > f->id_max || s < f->t_from ||
            s >= f->t_to || (f->count != 0u && c->fault_hits[i] >= f->count) ||
            (e->errors > 0u && f->every > 1u)) {
            continue;
        }
        if (++c->fault_seen[i] % f->every == 0u) {
            ++c->fault_hits[i];
            return (int)i;
        }
    }
    return -1;
}

/* Node i's state from its counters, an event when it changed (bus-off is set apart). */
static void settle(canbus_core_t *c, uint32_t i, uint64_t t)
{
    canbus_confine_t *n = &c->confine[i];
    const canbus_state_t now = canbus_confine_state(n->tec, n->rec);
    if (now != n->state) {
        n->passive_episodes += now == CANBUS_ERROR_PASSIVE ? 1u : 0u;
        n->state = now;
        emit(c, t, i, CANBUS_EV_STATE, 0u, 0u);
    }
}

/* Node i goes bus-off at t (its error's bit); the recessive run it counts starts at run. */
static void bus_off(canbus_core_t *c, uint32_t i, uint64_t t, uint64_t run)
{
    canbus_confine_t *n = &c->confine[i];
    n->state = CANBUS_BUS_OFF;
    ++n->bus_off_episodes;
    n->bus_off_at = t;
    n->run_start = run;
    n->runs = 0u;
    n->dropped += c->node[i].n;
    c->node[i].n = 0u;
    for (uint32_t k = 0u; k < c->faults; ++k) {
        c->fault_spent[k] |= c->fault[k].until_bus_off && c->fault[k].node == i;
    }
    for (uint32_t k = 0u; k < c->babbles; ++k) {
        if (c->babble[k].node == i && c->babble[k].period_ns == 0u) {
            c->babble_next[k] = NEVER; /* back to back again once it recovers */
        }
    }
    emit(c, t, i, CANBUS_EV_STATE, 0u, 0u);
}

/* The corrupted frame on the bus has ended (its error delimiter): the counters of every
 * node that is not bus-off, the transmitter's frame left in its queue to be sent again. */
static void end_error(canbus_core_t *c)
{
    const uint64_t t_bit = c->cur.t_sof + (uint64_t)(c->cur_bit + 1u) * c->bit_ns;
    const uint32_t tx = c->cur.node;
    ++c->error_frames;
    for (uint32_t i = 0u; i < c->nodes; ++i) {
        canbus_confine_t *n = &c->confine[i];
        if (n->state == CANBUS_BUS_OFF) {
            continue;
        }
        if (i == tx) {
            canbus_confine_tx_error(n);
        } else {
            canbus_confine_rx_error(n);
        }
        emit(c, t_bit, i, i == tx ? CANBUS_EV_TX_ERROR : CANBUS_EV_RX_ERROR, c->cur_bit,
             c->cur.frame.id);
        if (n->tec > CANBUS_BUSOFF_LIMIT) {
            bus_off(c, i, t_bit, c->cur_flag_end);
        } else {
            settle(c, i, t_bit);
        }
    }
}

/* A frame ended well: the sender's and receivers' counters. */
static void end_ok(canbus_core_t *c)
{
    for (uint32_t i = 0u; i < c->nodes; ++i) {
        canbus_confine_t *n = &c->confine[i];
        if (n->state == CANBUS_BUS_OFF) {
            continue;
        }
        if (i == c->cur.node) {
            canbus_confine_tx_ok(n);
        } else {
            canbus_confine_rx_ok(n);
        }
        settle(c, i, c->cur.t_eof);
    }
}

/* The bus after the frame on it ended (well or in error): idle after the interframe space; an
 * error-passive transmitter suspends; bus-off nodes count from the new recessive run (after
 * the error flags, or from the ACK delimiter: the frame's last 11 bits, 1 + EOF + IFS). */
static void end_frame(canbus_core_t *c)
{
    const uint64_t run = c->cur_error ? c->cur_flag_end
                                      : c->cur.t_eof - CANBUS_ACK_DELIM_EOF_BITS * c->bit_ns;
    if (c->cur_error) {
        end_error(c);
    } else {
        end_ok(c);
    }
    c->busy = false;
    c->idle_at = c->cur.t_eof + CANBUS_IFS_BITS * c->bit_ns;
    c->now = c->cur.t_eof > c->now ? c->cur.t_eof : c->now;
    canbus_confine_t *tx = &c->confine[c->cur.node];
    if (tx->state == CANBUS_ERROR_PASSIVE) {
        tx->suspend_until = c->idle_at + CANBUS_SUSPEND_BITS * c->bit_ns;
    }
    for (uint32_t i = 0u; i < c->nodes; ++i) {
        if (c->confine[i].state == CANBUS_BUS_OFF && c->confine[i].bus_off_at < c->cur.t_sof) {
            c->confine[i].run_start = run; /* (a node that went bus-off now has its own) */
        }
    }
}

/* The earliest recovery of a bus-off node on the idle bus: its run's 11-bit counts reach 128. */
static bool next_recovery(const canbus_core_t *c, uint32_t *node, uint64_t *t)
{
    bool any = false;
    for (uint32_t i = 0u; i < c->nodes; ++i) {
        const canbus_confine_t *n = &c->confine[i];
        if (n->state != CANBUS_BUS_OFF) {
            continue;
        }
        const uint64_t r = n->run_start + (uint64_t)(CANBUS_RECOVERY_RUNS - n->runs) *
                                              CANBUS_RECOVERY_RUN_BITS * c->bit_ns;
        if (!any || r < *t) {
            *t = r;
            *node = i;
            any = true;
        }
    }
    return any;
}

static void recover(canbus_core_t *c, uint32_t i, uint64_t r)
{
    canbus_confine_t *n = &c->confine[i];
    n->state = CANBUS_ERROR_ACTIVE;
    n->tec = 0u;
    n->rec = 0u;
    n->suspend_until = 0u;
    n->recovery_ns_max = r - n->bus_off_at > n->recovery_ns_max ? r - n->bus_off_at
                                                                 : n->recovery_ns_max;
    for (uint32_t k = 0u; k < c->babbles; ++k) {
        if (c->babble[k].node == i && c->babble_next[k] == NEVER) {
            c->babble_next[k] = r > c->babble[k].t_from ? r : c->babble[k].t_from;
        }
    }
    emit(c, r, i, CANBUS_EV_RESTARTED, 0u, 0u);
}

/* A SOF at s ends every bus-off node's recessive run: its whole 11-bit counts are kept. */
static void count_runs(canbus_core_t *c, uint64_t s)
{
    const uint64_t run_ns = CANBUS_RECOVERY_RUN_BITS * c->bit_ns;
    for (uint32_t i = 0u; i < c->nodes; ++i) {
        canbus_confine_t *n = &c->confine[i];
        if (n->state == CANBUS_BUS_OFF && s > n->run_start) {
            n->runs += (uint32_t)((s - n->run_start) / run_ns);
        }
    }
}

/* The earliest babbling frame due (not later than its window's end). */
static bool next_babble(const canbus_core_t *c, uint32_t *k, uint64_t *t)
{
    bool any = false;
    for (uint32_t i = 0u; i < c->babbles; ++i) {
        const uint64_t due = c->babble_next[i];
        if (due != NEVER && due < c->babble[i].t_to && (!any || due < *t)) {
            *t = due;
            *k = i;
            any = true;
        }
    }
    return any;
}

static void babble_frame(canbus_core_t *c, uint32_t k)
{
    const canbus_babble_t *b = &c->babble[k];
    const uint64_t due = c->babble_next[k];
    if (c->confine[b->node].state == CANBUS_BUS_OFF) {
        ++c->confine[b->node].dropped;
    } else if (c->node[b->node].n == CANBUS_QUEUE_LEN) {
        ++c->babble_dropped;
    } else {
        push(c, b->node, &b->frame, due, k + 1u);
    }
    /* back to back: the next one when this one starts (start_frame) */
    c->babble_next[k] = b->period_ns == 0u ? NEVER : due + b->period_ns;
}

/* ---- the bus ----------------------------------------------------------------------------- */

/* Arbitration at s (a node offers a frame then): the winner's frame goes on the bus; it
 * leaves its queue unless a fault corrupts it (then it stays to be sent again). */
static void start_frame(canbus_core_t *c, uint64_t s)
{
    uint32_t winner = 0u;
    int slot = -1;
    for (uint32_t i = 0u; i < c->nodes; ++i) {
        const int k = offered(c, i, s);
        if (k >= 0 && (slot < 0 || c->node[i].entry[k].arbitration <
                                       c->node[winner].entry[slot].arbitration)) {
            winner = i;
            slot = k;
        }
    }
    count_runs(c, s);
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
    const int f = fault_hit(c, winner, e, s);
    c->cur_error = f >= 0;
    if (!c->cur_error && e->babble != 0u && c->babble[e->babble - 1u].period_ns == 0u) {
        c->babble_next[e->babble - 1u] = s; /* its one mailbox is free for the next one */
    }
    if (c->cur_error) {
        ++n->entry[slot].errors;
        /* the error's bit, the flags, then the delimiter: the bus's end of this frame */
        c->cur_bit = canbus_fault_bit(&c->fault[f], e->bits);
        c->cur_flag_end = s + (uint64_t)(c->cur_bit + 1u + CANBUS_FLAG_BITS +
                                         c->fault[f].superposed) * c->bit_ns;
        c->cur.t_eof = c->cur_flag_end + CANBUS_DELIM_BITS * c->bit_ns;
        return;
    }
    memmove(&n->entry[slot], &n->entry[slot + 1], (n->n - (uint32_t)slot - 1u) * sizeof *e);
    --n->n;
}

/* What the idle bus does next, by t: a recovery, a babbling frame, an arbitration (in this
 * order at one instant: a frame queued at s takes part in the arbitration at s).  false:
 * nothing by t. */
static bool idle_step(canbus_core_t *c, uint64_t t)
{
    uint64_t s = NEVER, r = NEVER, g = NEVER;
    uint32_t node = 0u, k = 0u;
    const bool arb = next_arbitration(c, &s);
    const bool rec = next_recovery(c, &node, &r);
    const bool bab = next_babble(c, &k, &g);
    if (rec && r <= s && r <= g && r <= t) {
        recover(c, node, r);
    } else if (bab && g <= s && g <= t) {
        babble_frame(c, k);
    } else if (arb && s <= t) {
        start_frame(c, s);
    } else {
        return false;
    }
    return true;
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
            const bool ok = !c->cur_error;
            end_frame(c);
            if (ok) {
                *out = c->cur;
                return true;
            }
        } else if (!idle_step(c, t)) {
            break;
        }
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
        *is_eof = !c->cur_error;
        return true;
    }
    *is_eof = false;
    uint64_t s = NEVER, r = NEVER, g = NEVER;
    uint32_t node = 0u, k = 0u;
    /* each of the three fills its time (NEVER when it has none): all three must run */
    const bool arbitration = next_arbitration(c, &s);
    const bool recovery = next_recovery(c, &node, &r);
    const bool babble = next_babble(c, &k, &g);
    const bool any = arbitration || recovery || babble;
    *t = s < r ? (s < g ? s : g) : (r < g ? r : g);
    return any;
}
