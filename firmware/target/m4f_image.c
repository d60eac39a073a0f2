/*
 * m4f_image.c -- a bare-metal Cortex-M4F program that links the whole flight
 * computer: both applications, the lockstep/realtime node, the frame layer,
 * the LQG design and the identification, through a dummy port.
 *
 * It is never flashed.  It exists so that the cross build measures the flash
 * and static RAM of the real image (arm-none-eabi-size after the link), and
 * so that a link error proves the core needs no OS and no heap: newlib-nano
 * with nosys would resolve malloc, but nothing here may reference it (the
 * test tests/python/test_fcc_noheap.py checks the linked symbols).
 *
 * On a real board the port would wrap the CAN peripheral's FIFOs and a
 * microsecond timer; here receive always says "empty", transmit discards, and
 * the clock is a counter, which is enough to keep every code path reachable
 * (the linker's --gc-sections keeps only what main can reach).
 */
#include <stdint.h>

#include "fcc_node.h"

static fcc_node_t g_node;          /* the whole flight computer, static RAM */
static volatile uint32_t g_tx;      /* frames "sent" */
static volatile uint64_t g_clock;   /* stands in for a 1 MHz timer */

static fcc_status_t port_send(void *ctx, const fcc_can_frame_t *frame)
{
    (void)ctx;
    g_tx = g_tx + 1u + (uint32_t)frame->data[0];
    return FCC_OK;
}

static fcc_status_t port_recv(void *ctx, fcc_can_frame_t *frame)
{
    (void)ctx;
    (void)frame;
    return FCC_ERR_AGAIN;
}

static fcc_status_t port_counters(void *ctx, fcc_can_port_counters_t *out)
{
    (void)ctx;
    *out = (fcc_can_port_counters_t){0};
    out->tx_frames = g_tx;
    return FCC_OK;
}

static uint64_t port_now(void *ctx)
{
    (void)ctx;
    g_clock = g_clock + 7u;
    return g_clock;
}

int main(void);

int main(void)
{
    static fcc_node_config_t cfg;
    fcc_port_t port = {{NULL, port_send, port_recv, port_counters}, port_now, NULL, NULL, NULL};
    if (fcc_node_config_default(&cfg) != FCC_OK) {
        for (;;) {
        }
    }
    cfg.mode = FCC_MODE_REALTIME;
    if (fcc_node_init(&g_node, &cfg, &port) != FCC_OK) {
        for (;;) {
        }
    }
    (void)fcc_node_send_status(&g_node);
    uint64_t next[FCC_N_APPS] = {0u, 0u};
    uint32_t k[FCC_N_APPS] = {0u, 0u};
    uint64_t next_status = 100000u;
    for (;;) {
        (void)fcc_node_poll(&g_node, 16u, NULL);
        const uint64_t now = port_now(NULL);
        for (uint32_t a = 0u; a < FCC_N_APPS; ++a) {
            if (now >= next[a]) {
                (void)fcc_node_run_step(&g_node, a, k[a]++);
                next[a] += fcc_node_app_period_us(&g_node, a);
            }
        }
        if (now >= next_status) {
            (void)fcc_node_send_status(&g_node);
            next_status += 100000u;
        }
        (void)fcc_node_background(&g_node);
    }
}
