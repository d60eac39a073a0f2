/*
 * test_app_port.h -- an in-memory port for the tests of firmware/app (static inline: a
 * program uses what it needs of it): frames
 * queued for the node to receive, every frame it sends captured in order, a
 * clock the test moves, every event recorded.  No bus, no OS: the node under
 * test is the real one, only the wires are replaced.
 *
 * The simulator side encodes with the real frame layer (its own fcc_bus_t
 * that produces the simulator's and the sensors' messages), so frames carry
 * real E2E protection.
 */
#ifndef TEST_APP_PORT_H
#define TEST_APP_PORT_H

#include <string.h>

#include "fcc_node.h"

#define MEM_RX_MAX 1024u
#define MEM_TRIP 0x7E57u /* the node's trip in these tests */
static const uint8_t k_mem_key[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
#define MEM_TX_MAX 8192u

typedef struct {
    fcc_can_frame_t rx[MEM_RX_MAX];
    size_t rx_head;
    size_t rx_n;
    fcc_can_frame_t tx[MEM_TX_MAX];
    size_t tx_n;
    uint64_t now_us;
    uint64_t step_us;      /* the clock advances this much per reading */
    bool fail_send;        /* the "interface" refuses every frame */
    uint32_t refuse_id;    /* with refuse_st != FCC_OK: frames with this id are refused */
    fcc_status_t refuse_st;
    uint32_t batches;      /* send_many calls (a batched port: mem_batched) */
    uint32_t batch_len[64]; /* frames in each of the first 64 */
    uint32_t ev_count[FCC_EV_COUNT];
    fcc_event_t last_ev[FCC_EV_COUNT];
    fcc_bus_t sim;         /* the simulator's frame layer */
    fcc_secoc_t sec;       /* the simulator's authenticators (test key, MEM_TRIP) */
} mem_port_t;

static inline fcc_status_t mem_send(void *ctx, const fcc_can_frame_t *f)
{
    mem_port_t *p = ctx;
    if (p->fail_send) {
        return FCC_ERR_IO;
    }
    if (p->refuse_st != FCC_OK && f->id == p->refuse_id) {
        return p->refuse_st;
    }
    if (p->tx_n < MEM_TX_MAX) {
        p->tx[p->tx_n++] = *f;
    }
    return FCC_OK;
}

/* send_many as fcc_can.h defines it: frame by frame, an I/O error ends the batch. */
static inline fcc_status_t mem_send_many(void *ctx, const fcc_can_frame_t *f, uint32_t n,
                                  fcc_status_t *st)
{
    mem_port_t *p = ctx;
    if (p->batches < 64u) {
        p->batch_len[p->batches] = n;
    }
    ++p->batches;
    fcc_status_t first = FCC_OK;
    bool io_error = false;
    for (uint32_t i = 0u; i < n; ++i) {
        st[i] = io_error ? FCC_ERR_IO : mem_send(ctx, &f[i]);
        io_error = io_error || st[i] == FCC_ERR_IO;
        first = (first == FCC_OK) ? st[i] : first;
    }
    return first;
}

/* The port hands whole batches to send_many (as the Linux port does). */
static inline void mem_batched(fcc_port_t *port)
{
    port->can.send_many = mem_send_many;
}

static inline fcc_status_t mem_recv(void *ctx, fcc_can_frame_t *f)
{
    mem_port_t *p = ctx;
    if (p->rx_head == p->rx_n) {
        p->rx_head = p->rx_n = 0u;
        return FCC_ERR_AGAIN;
    }
    *f = p->rx[p->rx_head++];
    return FCC_OK;
}

static inline fcc_status_t mem_counters(void *ctx, fcc_can_port_counters_t *out)
{
    (void)ctx;
    memset(out, 0, sizeof *out);
    out->bus_errors = 7u; /* a recognisable value for the heartbeat test */
    return FCC_OK;
}

static inline uint64_t mem_now(void *ctx)
{
    mem_port_t *p = ctx;
    p->now_us += p->step_us;
    return p->now_us;
}

static inline void mem_event(void *ctx, const fcc_event_t *ev)
{
    mem_port_t *p = ctx;
    if ((unsigned int)ev->cls < (unsigned int)FCC_EV_COUNT) {
        ++p->ev_count[ev->cls];
        p->last_ev[ev->cls] = *ev;
    }
}

static inline void mem_init(mem_port_t *p, fcc_port_t *port)
{
    memset(p, 0, sizeof *p);
    p->step_us = 10u;
    memset(port, 0, sizeof *port);
    port->can.ctx = p;
    port->can.send = mem_send;
    port->can.recv = mem_recv;
    port->can.counters = mem_counters;
    port->now_us = mem_now;
    port->clock_ctx = p;
    port->event = mem_event;
    port->event_ctx = p;
    uint64_t produces = 0u;
    uint64_t consumes = 0u;
    for (unsigned int i = 0u; i < (unsigned int)FCC_MSG_COUNT; ++i) {
        const fcc_bus_msg_desc_t *d = fcc_bus_desc((fcc_msg_t)i);
        if ((d->senders & (1u << FCC_BUS_NODE_FCC)) != 0u) {
            consumes |= (uint64_t)1u << i;
        } else {
            produces |= (uint64_t)1u << i;
        }
    }
    (void)fcc_bus_init_masks(&p->sim, consumes, produces);
    (void)fcc_secoc_init(&p->sec, k_mem_key, MEM_TRIP);
}

/* A node configuration with the test key and trip. */
static inline void mem_secure(fcc_node_config_t *cfg)
{
    memcpy(cfg->security.key, k_mem_key, sizeof k_mem_key);
    cfg->security.trip = MEM_TRIP;
}

/* Queue raw bytes as they are (fault injection). */
static inline void mem_push_raw(mem_port_t *p, uint32_t id, const uint8_t *data, uint8_t dlc)
{
    fcc_can_frame_t *f = &p->rx[p->rx_n++];
    memset(f, 0, sizeof *f);
    f->id = id;
    f->dlc = dlc;
    memcpy(f->data, data, dlc);
    f->t_us = p->now_us;
}

/* Encode (E2E-protected) and queue; returns the encode status. */
static inline fcc_status_t mem_push(mem_port_t *p, fcc_msg_t msg, const fcc_msg_data_t *d)
{
    fcc_can_frame_t f;
    const fcc_status_t st = fcc_bus_encode(&p->sim, msg, d, &f);
    uint32_t a;
    if (st == FCC_OK) {
        mem_push_raw(p, f.id, f.data, f.dlc);
        if (fcc_secoc_secured_index(msg, &a)) { /* its authenticator right after it */
            fcc_can_frame_t auth;
            if (fcc_secoc_protect(&p->sec, a, f.data, 8u, &auth) == FCC_OK) {
                mem_push_raw(p, auth.id, auth.data, auth.dlc);
            }
        }
    }
    return st;
}

static inline void mem_push_tick(mem_port_t *p, uint32_t app, uint32_t k)
{
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    d.sim_tick.app = (uint8_t)app;
    d.sim_tick.step = k;
    (void)mem_push(p, FCC_MSG_SIM_TICK, &d);
}

static inline void mem_push_cdrw(mem_port_t *p, uint32_t k, double alpha, double q, double de)
{
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    d.cdrw_aoa.step = (uint16_t)k;
    d.cdrw_aoa.alpha = (fcc_real_t)alpha;
    (void)mem_push(p, FCC_MSG_CDRW_AOA, &d);
    memset(&d, 0, sizeof d);
    d.cdrw_pitch_rate.step = (uint16_t)k;
    d.cdrw_pitch_rate.q = (fcc_real_t)q;
    (void)mem_push(p, FCC_MSG_CDRW_PITCH_RATE, &d);
    memset(&d, 0, sizeof d);
    d.cdrw_elevator.step = (uint16_t)k;
    d.cdrw_elevator.delta_e = (fcc_real_t)de;
    (void)mem_push(p, FCC_MSG_CDRW_ELEVATOR, &d);
}

static inline void mem_push_gyro(mem_port_t *p, uint32_t k, double q_g)
{
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    d.msl_rate_gyro.step = (uint16_t)k;
    d.msl_rate_gyro.q_g = (fcc_real_t)q_g;
    (void)mem_push(p, FCC_MSG_MSL_RATE_GYRO, &d);
}

static inline void mem_push_accel(mem_port_t *p, uint32_t k, double n_a)
{
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    d.msl_accelerometer.step = (uint16_t)k;
    d.msl_accelerometer.n_a = (fcc_real_t)n_a;
    (void)mem_push(p, FCC_MSG_MSL_ACCELEROMETER, &d);
}

static inline void mem_push_control(mem_port_t *p, uint8_t command, double period, uint8_t bits)
{
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    d.sim_control.command = command;
    d.sim_control.lqg_period = (fcc_real_t)period;
    d.sim_control.da_bits = bits;
    (void)mem_push(p, FCC_MSG_SIM_CONTROL, &d);
}

/* One master SYNC (received at local l) + FOLLOW_UP for master time mt, E2E
 * headers from `from` (the simulator's, or a forger's pre-empting counters);
 * with its TSYNC_AUTH when `auth`; the clock set to l. */
static inline void mem_push_sync_pair(mem_port_t *p, fcc_bus_t *from, uint8_t seq, uint64_t l,
                                      uint64_t mt, bool auth)
{
    fcc_msg_data_t d;
    fcc_can_frame_t s, f;
    memset(&d, 0, sizeof d);
    d.tsync_sync.master = 1u;
    d.tsync_sync.seq = seq;
    d.tsync_sync.interval_ms = 100u;
    d.tsync_sync.sec = (uint32_t)(mt / 1000000u);
    fcc_assert_ok(fcc_bus_encode(from, FCC_MSG_TSYNC_SYNC, &d, &s));
    memset(&d, 0, sizeof d);
    d.tsync_follow_up.master = 1u;
    d.tsync_follow_up.seq = seq;
    d.tsync_follow_up.ns = (uint32_t)(mt % 1000000u) * 1000u;
    fcc_assert_ok(fcc_bus_encode(from, FCC_MSG_TSYNC_FOLLOW_UP, &d, &f));
    p->now_us = l;
    mem_push_raw(p, s.id, s.data, 8u);
    mem_push_raw(p, f.id, f.data, 8u);
    if (auth) {
        uint32_t a = 0u;
        assert_true(fcc_secoc_auth_index(FCC_MSG_TSYNC_AUTH, &a));
        uint8_t pdu[16];
        memcpy(pdu, s.data, 8u);
        memcpy(&pdu[8], f.data, 8u);
        fcc_can_frame_t af;
        fcc_assert_ok(fcc_secoc_protect(&p->sec, a, pdu, 16u, &af));
        mem_push_raw(p, af.id, af.data, 8u);
    }
}

/* Index of the n-th (0-based) sent frame with identifier id at or after
 * index from, or -1. */
static inline long mem_find_tx(const mem_port_t *p, size_t from, uint32_t id, unsigned int n)
{
    for (size_t i = from; i < p->tx_n; ++i) {
        if (p->tx[i].id == id) {
            if (n == 0u) {
                return (long)i;
            }
            --n;
        }
    }
    return -1;
}

/* Decode sent frame i (no E2E check: the checks of the receiving side are
 * tested elsewhere); fails the test if it does not decode in range. */
static inline fcc_msg_data_t mem_decode_tx(const mem_port_t *p, long i)
{
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    fcc_msg_t m;
    if (i < 0 || fcc_bus_find(p->tx[i].id, &m) != FCC_OK ||
        fcc_bus_decode(m, p->tx[i].data, &d) != FCC_OK) {
        fail_msg("sent frame %ld does not decode", i);
    }
    return d;
}

#endif /* TEST_APP_PORT_H */
