/*
 * fcc_node_rt.c -- the realtime schedule of the node's applications: absolute
 * deadlines t0 + k T on the port's clock, shared by the Linux main and the
 * Cortex-M4F image (see fcc_node.h).
 */
#include "fcc_node.h"

void fcc_node_rt_start(const fcc_node_t *node, fcc_node_rt_t rt[FCC_N_APPS], uint64_t start_us)
{
    for (uint32_t a = 0u; a < FCC_N_APPS; ++a) {
        rt[a].period_us = fcc_node_app_period_us(node, a);
        rt[a].deadline = start_us + rt[a].period_us;
        rt[a].k = 0u;
        rt[a].synced = false;
        rt[a].n = 0u;
        rt[a].instant = 0u;
        rt[a].last_instant = 0u;
        rt[a].aligns = 0u;
    }
}

static uint64_t release(fcc_node_t *node, fcc_node_rt_t *r, uint32_t a, uint64_t now)
{
    if (now >= r->deadline + r->period_us) { /* a whole period late: skip, no burst */
        const uint64_t missed = (now - r->deadline) / r->period_us;
        r->deadline += missed * r->period_us;
        r->k += (uint32_t)missed;
        fcc_node_note_overrun(node, a, (uint32_t)missed, r->k);
    }
    const uint64_t jitter = now - r->deadline;
    (void)fcc_node_run_step(node, a, r->k);
    if (node->port.now_us(node->port.clock_ctx) > r->deadline + r->period_us) {
        fcc_node_note_overrun(node, a, 1u, r->k);
    }
    ++r->k;
    r->period_us = fcc_node_app_period_us(node, a); /* a redesign re-bases here */
    r->deadline += r->period_us;
    return jitter;
}

/* Synchronised: place app a's next instant in master time (the first one after
 * now when not aligned yet) and its deadline; false without the master's time. */
static bool align(const fcc_node_t *node, fcc_node_rt_t *r, uint32_t a, uint64_t now)
{
    const fcc_tsync_t *ts = &node->tsync;
    uint64_t m_now = 0u;
    if (fcc_tsync_to_master(ts, now, &m_now) != FCC_OK || r->period_us == 0u) {
        return false;
    }
    if (!r->synced) {
        r->n = m_now / r->period_us + 1u;
        r->synced = true;
        ++r->aligns;
    }
    const fcc_app_ops_t *ops = fcc_node_app_ops(a);
    const uint64_t window = (ops != NULL && ops->rt_window_us != 0u) ? ops->rt_window_us
                                                                     : r->period_us / 2u;
    uint64_t instant = 0u;
    uint64_t deadline = 0u;
    if (fcc_tsync_to_local(ts, r->n * r->period_us, &instant) != FCC_OK ||
        fcc_tsync_to_local(ts, r->n * r->period_us + window, &deadline) != FCC_OK) {
        return false;
    }
    r->instant = instant;
    r->deadline = deadline;
    return true;
}

/* Synchronised release of app a: inputs complete, or the window is over. */
static uint64_t release_synced(fcc_node_t *node, fcc_node_rt_t *r, uint32_t a, uint64_t now)
{
    const uint64_t guard = (r->instant > FCC_NODE_RT_GUARD_US) ? r->instant - FCC_NODE_RT_GUARD_US
                                                               : 0u;
    /* every input is in and the instant, less the guard, has come (named apart: clang
     * measures no MC/DC of a decision that negates a nested one) */
    const bool ready =
        fcc_node_inputs_since(node, a, guard) && now + FCC_NODE_RT_GUARD_US >= r->instant;
    if (now < r->deadline && !ready) {
        return UINT64_MAX;
    }
    if (now >= r->instant + r->period_us + (r->deadline - r->instant)) {
        const uint64_t missed = (now - r->instant) / r->period_us; /* skip, no burst */
        r->n += missed;
        fcc_node_note_overrun(node, a, (uint32_t)missed, (uint32_t)r->n);
        (void)align(node, r, a, now);
    }
    const uint64_t jitter = (now > r->instant) ? now - r->instant : 0u;
    r->last_instant = r->instant;
    r->k = (uint32_t)r->n;
    (void)fcc_node_run_step(node, a, r->k);
    const uint32_t period = fcc_node_app_period_us(node, a);
    ++r->n;
    if (period != r->period_us) { /* a redesign: the new period's instants */
        r->period_us = period;
        r->synced = false;
    }
    (void)align(node, r, a, node->port.now_us(node->port.clock_ctx));
    return jitter;
}

/* When several are due, those whose command has a deadline (a release window, fcc_app.h)
 * go first: the autopilot's command closes a loop, the identification only observes. */
static void release_order(uint32_t order[FCC_N_APPS])
{
    uint32_t n = 0u;
    for (uint32_t pass = 0u; pass < 2u; ++pass) {
        for (uint32_t a = 0u; a < FCC_N_APPS; ++a) {
            const fcc_app_ops_t *ops = fcc_node_app_ops(a);
            const bool windowed = ops != NULL && ops->rt_window_us != 0u;
            if ((pass == 0u) ? windowed : !windowed) {
                order[n] = a;
                ++n;
            }
        }
    }
}

uint32_t fcc_node_rt_run_due(fcc_node_t *node, fcc_node_rt_t rt[FCC_N_APPS],
                             uint64_t jitter_us[FCC_N_APPS])
{
    uint32_t k_order[FCC_N_APPS];
    release_order(k_order);
    uint32_t ran = 0u;
    const bool master = fcc_tsync_has_time(&node->tsync);
    for (uint32_t i = 0u; i < FCC_N_APPS; ++i) {
        const uint32_t a = k_order[i];
        fcc_node_rt_t *r = &rt[a];
        jitter_us[a] = UINT64_MAX;
        const uint64_t now = node->port.now_us(node->port.clock_ctx);
        if (!node->cfg.app_enabled[a]) {
            continue;
        }
        if (node->op_mode != FCC_OP_FLIGHT) {
            /* On the ground the grid goes on and nothing steps: no overrun, no jitter. */
            if (now >= r->deadline && r->period_us > 0u) {
                const uint64_t periods = (now - r->deadline) / r->period_us + 1u;
                r->k += (uint32_t)periods;
                r->n += periods;
                r->deadline += periods * r->period_us;
            }
            continue;
        }
        if (master && align(node, r, a, now)) {
            jitter_us[a] = release_synced(node, r, a, now);
            ran += (jitter_us[a] != UINT64_MAX) ? 1u : 0u;
            continue;
        }
        if (r->synced) { /* the master is gone: free-run on the own clock from here */
            r->synced = false;
            r->deadline = now + r->period_us;
        }
        /* a schedule never started (fcc_node_rt_start) has no period and so no grid */
        if ((now >= r->deadline) && (r->period_us > 0u)) {
            jitter_us[a] = release(node, r, a, now);
            ++ran;
        }
    }
    return ran;
}

uint64_t fcc_node_rt_next(const fcc_node_t *node, const fcc_node_rt_t rt[FCC_N_APPS])
{
    uint64_t next = UINT64_MAX;
    for (uint32_t a = 0u; a < FCC_N_APPS; ++a) {
        if (node->cfg.app_enabled[a] && rt[a].deadline < next) {
            next = rt[a].deadline;
        }
    }
    return next;
}
