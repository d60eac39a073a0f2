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

uint32_t fcc_node_rt_run_due(fcc_node_t *node, fcc_node_rt_t rt[FCC_N_APPS],
                             uint64_t jitter_us[FCC_N_APPS])
{
    /* When both are due the autopilot goes first: its command closes a loop,
     * the identification only observes. */
    static const uint32_t k_order[FCC_N_APPS] = {FCC_APP_MSL, FCC_APP_CDRW};
    uint32_t ran = 0u;
    for (uint32_t i = 0u; i < FCC_N_APPS; ++i) {
        const uint32_t a = k_order[i];
        jitter_us[a] = UINT64_MAX;
        const uint64_t now = node->port.now_us(node->port.clock_ctx);
        if (!node->cfg.app_enabled[a] || now < rt[a].deadline) {
            continue;
        }
        if (node->op_mode != FCC_OP_FLIGHT) {
            /* On the ground the grid goes on and nothing steps: no overrun, no jitter. */
            const uint64_t periods = (now - rt[a].deadline) / rt[a].period_us + 1u;
            rt[a].k += (uint32_t)periods;
            rt[a].deadline += periods * rt[a].period_us;
            continue;
        }
        jitter_us[a] = release(node, &rt[a], a, now);
        ++ran;
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
