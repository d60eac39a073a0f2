/*
 * fuzz_node_rx.c -- libFuzzer: the node's frame dispatch (fcc_node_poll ->
 * fcc_node_handle_frame: the bus checks, the authentication, the sensors, the ticks, the
 * commands, the time sync) through the public API of fcc_node.h only, with the node's
 * housekeeping (heartbeat, time-sync poll, background design, realtime schedule) between
 * frames.  The port is the harness: it hands the input's frames to the node and checks
 * every frame the node sends.
 *
 * Input: a byte choosing lockstep or realtime, then records as fuzz_bus_rx's
 * (fuzz_bus_records.h: any identifier, any DLC, E2E-protected on request) with two more
 * flags: FUZZ_NODE_AUTH follows a secured message with its genuine authenticator (the test
 * key and trip: what a fuzzer cannot forge), FUZZ_NODE_HOUSEKEEPING runs the housekeeping
 * after it; [11] also moves the clock.
 * Properties (abort on violation): the node takes every frame (no error but the port's);
 * every frame it sends is a standard data frame of at most 8 bytes; it leaves the ground
 * mode, asks to shut down or sends a control command only after a SIM_CONTROL that was
 * genuinely authenticated -- forged frames never fly it.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fcc_node.h"
#include "fuzz_bus_records.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define FUZZ_NODE_AUTH 0x10u
#define FUZZ_NODE_HOUSEKEEPING 0x08u
#define TRIP 0x7E57u
#define BACKGROUND_SLICES 64u /* per housekeeping: a redesign goes on in later ones */

static const uint8_t k_key[FCC_SECOC_KEY_BYTES] = {0, 1, 2, 3, 4, 5, 6, 7,
                                                   8, 9, 10, 11, 12, 13, 14, 15};

typedef struct {
    fcc_can_frame_t rx[2]; /* a record's frame and its authenticator */
    uint32_t rx_head, rx_n;
    uint64_t now_us;
    uint32_t commands;     /* MSL_ELEV_CMD frames sent */
    bool genuine_control;  /* an authenticated SIM_CONTROL was handed to the node */
    fcc_secoc_t sim;       /* the simulator's authenticators */
} harness_t;

static harness_t g_h;
static fcc_node_t g_node;
static fcc_node_t g_fresh[2]; /* the node just initialised, per mode (a design is slow) */
static bool g_have_fresh[2];

static void check(bool ok)
{
    if (!ok) {
        abort();
    }
}

static fcc_status_t port_send(void *ctx, const fcc_can_frame_t *f)
{
    harness_t *h = ctx;
    check(f->id <= 0x7FFu && f->dlc <= 8u);
    h->commands += (f->id == FCC_MSG_MSL_ELEV_CMD_ID) ? 1u : 0u;
    return FCC_OK;
}

static fcc_status_t port_send_many(void *ctx, const fcc_can_frame_t *f, uint32_t n,
                                   fcc_status_t *st)
{
    for (uint32_t i = 0u; i < n; ++i) {
        st[i] = port_send(ctx, &f[i]);
    }
    return FCC_OK;
}

static fcc_status_t port_recv(void *ctx, fcc_can_frame_t *f)
{
    harness_t *h = ctx;
    if (h->rx_head == h->rx_n) {
        return FCC_ERR_AGAIN;
    }
    *f = h->rx[h->rx_head++];
    return FCC_OK;
}

static fcc_status_t port_counters(void *ctx, fcc_can_port_counters_t *out)
{
    (void)ctx;
    memset(out, 0, sizeof *out);
    return FCC_OK;
}

static uint64_t port_now(void *ctx)
{
    harness_t *h = ctx;
    h->now_us += 10u;
    return h->now_us;
}

/* The node of this mode as fcc_node_init leaves it: initialised once (the LQG design takes
 * milliseconds), then copied back -- always to g_node, where it was initialised, so
 * whatever it points to is where it was; its port points at the one harness. */
static void fresh_node(uint32_t mode)
{
    if (!g_have_fresh[mode]) {
        fcc_node_config_t cfg;
        check(fcc_node_config_default(&cfg) == FCC_OK);
        cfg.mode = (mode == 0u) ? FCC_MODE_LOCKSTEP : FCC_MODE_REALTIME;
        memcpy(cfg.security.key, k_key, sizeof k_key);
        cfg.security.trip = TRIP;
        fcc_port_t port;
        memset(&port, 0, sizeof port);
        port.can.ctx = &g_h;
        port.can.send = port_send;
        port.can.send_many = port_send_many;
        port.can.recv = port_recv;
        port.can.counters = port_counters;
        port.now_us = port_now;
        port.clock_ctx = &g_h;
        check(fcc_node_init(&g_node, &cfg, &port) == FCC_OK);
        g_fresh[mode] = g_node;
        g_have_fresh[mode] = true;
    }
    g_node = g_fresh[mode];
}

/* A record's frame, and its genuine authenticator when asked for and secured. */
static void queue(harness_t *h, const uint8_t *r)
{
    fcc_msg_t msg;
    h->rx_head = 0u;
    h->rx_n = 0u;
    fuzz_rx_record(r, &h->rx[0], &msg);
    h->rx[0].t_us = h->now_us;
    h->rx_n = 1u;
    uint32_t a;
    const bool from_table = (r[0] & FUZZ_RX_FROM_TABLE) != 0u;
    if (from_table && (r[0] & FUZZ_NODE_AUTH) != 0u && fcc_secoc_secured_index(msg, &a)) {
        check(fcc_secoc_protect(&h->sim, a, h->rx[0].data, 8u, &h->rx[1]) == FCC_OK);
        h->rx[1].t_us = h->now_us;
        h->rx_n = 2u;
        h->genuine_control = h->genuine_control || msg == FCC_MSG_SIM_CONTROL;
    }
}

static void housekeeping(fcc_node_rt_t rt[FCC_N_APPS])
{
    (void)fcc_node_send_status(&g_node);
    (void)fcc_node_sync_poll(&g_node);
    for (uint32_t i = 0u; i < BACKGROUND_SLICES && fcc_node_background(&g_node) == FCC_OK; ++i) {
    }
    if (g_node.cfg.mode == FCC_MODE_REALTIME) {
        uint64_t jitter[FCC_N_APPS];
        (void)fcc_node_rt_run_due(&g_node, rt, jitter);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1u) {
        return 0;
    }
    harness_t *h = &g_h;
    memset(h, 0, sizeof *h);
    h->now_us = 1000000u;
    check(fcc_secoc_init(&h->sim, k_key, TRIP) == FCC_OK);
    fresh_node(data[0] & 1u);
    fcc_node_rt_t rt[FCC_N_APPS];
    fcc_node_rt_start(&g_node, rt, h->now_us);
    for (size_t off = 1u; off + FUZZ_RX_REC <= size; off += FUZZ_RX_REC) {
        const uint8_t *r = data + off;
        queue(h, r);
        const uint32_t before = g_node.cnt.rx_frames;
        uint32_t n = 0u;
        check(fcc_node_poll(&g_node, 4u, &n) == FCC_OK);
        check(n == h->rx_n && g_node.cnt.rx_frames == before + n);
        h->now_us += (uint64_t)r[11] * 100u;
        if ((r[0] & FUZZ_NODE_HOUSEKEEPING) != 0u) {
            housekeeping(rt);
        }
        if (!h->genuine_control) {
            check(fcc_node_op_mode(&g_node) == FCC_OP_GROUND);
            check(!fcc_node_shutdown_requested(&g_node));
            check(h->commands == 0u);
        }
    }
    return 0;
}
