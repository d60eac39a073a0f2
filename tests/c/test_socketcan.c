/*
 * test_socketcan.c -- the SocketCAN port's bad-input paths, which need no CAN
 * interface: a missing interface, bad names, bad filters, a closed port -- and
 * the batched send (sendmmsg) and receive (recvmmsg) on a datagram socket pair,
 * the same system calls as on a CAN socket: order and bytes, a full queue
 * retried then dropped, an I/O error ending the batch, frames read ahead, a drained
 * queue not asked again until the descriptor is readable; the kernel's receive stamps on
 * the monotonic clock, a command's send stamp taken at its send.  The port's traffic is tested over vcan0 by
 * tests/python/bus/test_bus_vcan.py (can_echo) and every vcan test of fcc.
 */
#include "fcc_test.h"

#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include <linux/can.h>
#include <linux/can/error.h>

#include "fcc_bus_msgs.h"
#include "fcc_hostclock.h"
#include "fcc_hostport.h"
#include "fcc_socketcan.h"

static void test_open_bad_names(void **state)
{
    (void)state;
    fcc_socketcan_t s;
    assert_int_equal(fcc_socketcan_open(NULL, "vcan0"), FCC_ERR_ARG);
    assert_int_equal(fcc_socketcan_open(&s, NULL), FCC_ERR_ARG);
    assert_int_equal(s.fd, -1);
    assert_int_equal(fcc_socketcan_open(&s, ""), FCC_ERR_ARG);
    assert_int_equal(fcc_socketcan_open(&s, "a_name_longer_than_ifnamsiz"), FCC_ERR_ARG);
    /* No such interface (or no CAN in this kernel at all): an I/O error, no crash. */
    assert_int_equal(fcc_socketcan_open(&s, "nocan7"), FCC_ERR_IO);
    assert_int_equal(s.fd, -1);
}

static void test_closed_port_refuses_everything(void **state)
{
    (void)state;
    fcc_socketcan_t s;
    assert_int_equal(fcc_socketcan_open(&s, "nocan7"), FCC_ERR_IO);
    fcc_can_frame_t f;
    memset(&f, 0, sizeof f);
    const uint32_t ids[1] = {0x50u};
    assert_int_equal(fcc_socketcan_recv(&s, &f), FCC_ERR_ARG);
    assert_int_equal(fcc_socketcan_send(&s, &f), FCC_ERR_ARG);
    assert_int_equal(fcc_socketcan_wait(&s, 0), FCC_ERR_ARG);
    assert_int_equal(fcc_socketcan_set_filters(&s, ids, 1u), FCC_ERR_ARG);
    fcc_can_port_counters_t c;
    fcc_assert_ok(fcc_socketcan_counters(&s, &c));
    assert_int_equal(c.tx_frames, 0u);
    assert_int_equal(fcc_socketcan_counters(NULL, &c), FCC_ERR_ARG);
    fcc_socketcan_close(&s);
    fcc_socketcan_close(&s); /* twice is harmless */
    fcc_socketcan_close(NULL);

    /* The port interface forwards to the same functions. */
    fcc_can_port_t port = fcc_socketcan_port(&s);
    assert_ptr_equal(port.ctx, &s);
    assert_int_equal(port.send(port.ctx, &f), FCC_ERR_ARG);
    assert_int_equal(port.recv(port.ctx, &f), FCC_ERR_ARG);
    fcc_assert_ok(port.counters(port.ctx, &c));
}

static void test_send_many_bad_arguments(void **state)
{
    (void)state;
    fcc_socketcan_t s;
    assert_int_equal(fcc_socketcan_open(&s, "nocan7"), FCC_ERR_IO);
    fcc_can_frame_t f[2];
    memset(f, 0, sizeof f);
    fcc_status_t st[2] = {FCC_OK, FCC_OK};
    assert_int_equal(fcc_socketcan_send_many(NULL, f, 2u, st), FCC_ERR_ARG);
    assert_int_equal(fcc_socketcan_send_many(&s, NULL, 2u, st), FCC_ERR_ARG);
    assert_int_equal(fcc_socketcan_send_many(&s, f, 2u, NULL), FCC_ERR_ARG);
    assert_int_equal(st[0], FCC_OK); /* untouched */
    fcc_assert_ok(fcc_socketcan_send_many(&s, NULL, 0u, NULL)); /* nothing to send */
    /* a closed port: every frame refused */
    assert_int_equal(fcc_socketcan_send_many(&s, f, 2u, st), FCC_ERR_ARG);
    assert_int_equal(st[0], FCC_ERR_ARG);
    assert_int_equal(st[1], FCC_ERR_ARG);
    fcc_can_port_t port = fcc_socketcan_port(&s);
    assert_int_equal(port.send_many(port.ctx, f, 2u, st), FCC_ERR_ARG);
}

/* A port whose socket is one end of a datagram socket pair; *peer: the other end. */
static void pair_port(fcc_socketcan_t *s, int *peer, uint32_t budget_us)
{
    int sv[2];
    assert_int_equal(socketpair(AF_UNIX, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0, sv), 0);
    memset(s, 0, sizeof *s);
    s->fd = sv[0];
    s->send_budget_us = budget_us;
    *peer = sv[1];
}

static fcc_can_frame_t frame(uint32_t id, uint8_t dlc)
{
    fcc_can_frame_t f;
    memset(&f, 0, sizeof f);
    f.id = id;
    f.dlc = dlc;
    for (uint8_t i = 0u; i < dlc; ++i) {
        f.data[i] = (uint8_t)(0xA0u + id + i);
    }
    return f;
}

static void test_send_many_in_order_as_can_frames(void **state)
{
    (void)state;
    fcc_socketcan_t s;
    int peer;
    pair_port(&s, &peer, 5000u);
    fcc_can_frame_t f[8];
    fcc_status_t st[8];
    for (uint32_t i = 0u; i < 8u; ++i) {
        f[i] = frame(0x100u + i, (uint8_t)(i % 9u));
    }
    f[3].id = 0x800u; /* not a standard identifier: refused, the others go */
    assert_int_equal(fcc_socketcan_send_many(&s, f, 8u, st), FCC_ERR_ARG);
    for (uint32_t i = 0u; i < 8u; ++i) {
        assert_int_equal(st[i], (i == 3u) ? FCC_ERR_ARG : FCC_OK);
    }
    fcc_can_port_counters_t c;
    fcc_assert_ok(fcc_socketcan_counters(&s, &c));
    assert_int_equal(c.tx_frames, 7u);
    assert_int_equal(c.tx_retries, 0u);
    for (uint32_t i = 0u; i < 8u; ++i) {
        if (i == 3u) {
            continue;
        }
        struct can_frame cf;
        assert_int_equal(read(peer, &cf, sizeof cf), (ssize_t)sizeof cf);
        assert_int_equal(cf.can_id, f[i].id);
        assert_int_equal(cf.len, f[i].dlc);
        assert_memory_equal(cf.data, f[i].data, f[i].dlc);
    }
    struct can_frame extra;
    assert_true(read(peer, &extra, sizeof extra) < 0); /* nothing else */
    /* the single send is the same path */
    fcc_assert_ok(fcc_socketcan_send(&s, &f[0]));
    fcc_assert_ok(fcc_socketcan_counters(&s, &c));
    assert_int_equal(c.tx_frames, 8u);
    (void)close(peer);
    fcc_socketcan_close(&s);
}

static void test_send_many_full_queue_retried_then_dropped(void **state)
{
    (void)state;
    fcc_socketcan_t s;
    int peer;
    pair_port(&s, &peer, 1000u);
    const int small = 1; /* the kernel's minimum send buffer: a few frames */
    assert_int_equal(setsockopt(s.fd, SOL_SOCKET, SO_SNDBUF, &small, sizeof small), 0);
    /* the peer never reads: the queue fills, then every frame is retried for 1 ms and dropped */
    enum { N = 40 };
    fcc_can_frame_t f[N];
    fcc_status_t st[N];
    for (uint32_t i = 0u; i < N; ++i) {
        f[i] = frame(i, 8u);
    }
    assert_int_equal(fcc_socketcan_send_many(&s, f, N, st), FCC_ERR_AGAIN);
    uint32_t sent = 0u;
    while (sent < N && st[sent] == FCC_OK) {
        ++sent;
    }
    assert_true(sent > 0u && sent < N);
    for (uint32_t i = sent; i < N; ++i) {
        assert_int_equal(st[i], FCC_ERR_AGAIN);
    }
    fcc_can_port_counters_t c;
    fcc_assert_ok(fcc_socketcan_counters(&s, &c));
    assert_int_equal(c.tx_frames, sent);
    assert_int_equal(c.tx_dropped, N - sent);
    assert_true(c.tx_retries >= N - sent);
    for (uint32_t i = 0u; i < sent; ++i) { /* what went out, went out in order */
        struct can_frame cf;
        assert_int_equal(read(peer, &cf, sizeof cf), (ssize_t)sizeof cf);
        assert_int_equal(cf.can_id, i);
    }
    /* room again: the next batch goes whole */
    fcc_assert_ok(fcc_socketcan_send_many(&s, f, 2u, st));
    (void)close(peer);
    fcc_socketcan_close(&s);
}

static void test_send_many_io_error_ends_the_batch(void **state)
{
    (void)state;
    fcc_socketcan_t s;
    int peer;
    pair_port(&s, &peer, 1000u);
    (void)close(peer); /* the other end is gone: not a full queue, an error */
    fcc_can_frame_t f[3] = {frame(1u, 8u), frame(2u, 8u), frame(3u, 8u)};
    fcc_status_t st[3];
    assert_int_equal(fcc_socketcan_send_many(&s, f, 3u, st), FCC_ERR_IO);
    for (uint32_t i = 0u; i < 3u; ++i) {
        assert_int_equal(st[i], FCC_ERR_IO);
    }
    fcc_can_port_counters_t c;
    fcc_assert_ok(fcc_socketcan_counters(&s, &c));
    assert_int_equal(c.tx_frames, 0u);
    assert_int_equal(c.tx_dropped, 0u);
    assert_int_equal(c.tx_retries, 0u);
    fcc_socketcan_close(&s);
}

static void test_recv_reads_ahead_in_arrival_order(void **state)
{
    (void)state;
    fcc_socketcan_t s;
    int peer;
    pair_port(&s, &peer, 1000u);
    /* more than one recvmmsg's worth, with an error frame, an extended frame and a short
     * message among them: counted and skipped, the others in order */
    enum { N = FCC_SOCKETCAN_RX_BATCH + 5 };
    for (uint32_t i = 0u; i < N; ++i) {
        struct can_frame cf;
        memset(&cf, 0, sizeof cf);
        cf.can_id = 0x100u + i;
        cf.len = 8u;
        cf.data[0] = (uint8_t)i;
        if (i == 3u) {
            cf.can_id |= CAN_ERR_FLAG;
        } else if (i == 7u) {
            cf.can_id |= CAN_EFF_FLAG;
        }
        const size_t len = (i == 11u) ? 8u : sizeof cf;
        assert_int_equal(write(peer, &cf, len), (ssize_t)len);
    }
    assert_false(fcc_socketcan_pending(&s));
    fcc_can_frame_t f;
    uint32_t got = 0u;
    for (uint32_t i = 0u; i < N; ++i) {
        if (i == 3u || i == 7u || i == 11u) {
            continue;
        }
        fcc_assert_ok(fcc_socketcan_recv(&s, &f));
        assert_int_equal(f.id, 0x100u + i);
        assert_int_equal(f.dlc, 8u);
        assert_int_equal(f.data[0], i);
        ++got;
        if (got == 1u) { /* the rest of the first batch waits in the port, not the socket */
            assert_true(fcc_socketcan_pending(&s));
            fcc_assert_ok(fcc_socketcan_wait(&s, 0));
        }
    }
    assert_int_equal(fcc_socketcan_recv(&s, &f), FCC_ERR_AGAIN);
    assert_false(fcc_socketcan_pending(&s));
    fcc_can_port_counters_t c;
    fcc_assert_ok(fcc_socketcan_counters(&s, &c));
    assert_int_equal(c.rx_frames, N - 3u);
    assert_int_equal(c.bus_errors, 1u);
    assert_int_equal(c.rx_ignored, 2u);
    /* frames read ahead go with a closed socket */
    struct can_frame cf;
    memset(&cf, 0, sizeof cf);
    assert_int_equal(write(peer, &cf, sizeof cf), (ssize_t)sizeof cf);
    assert_int_equal(write(peer, &cf, sizeof cf), (ssize_t)sizeof cf);
    fcc_assert_ok(fcc_socketcan_wait(&s, 0));
    fcc_assert_ok(fcc_socketcan_recv(&s, &f));
    assert_true(fcc_socketcan_pending(&s));
    fcc_socketcan_close(&s);
    assert_false(fcc_socketcan_pending(&s));
    assert_int_equal(fcc_socketcan_recv(&s, &f), FCC_ERR_ARG);
    (void)close(peer);
}

/* A short read emptied the kernel's queue: no system call asks it again until the
 * caller's wait (or its own poll, told with fcc_socketcan_readable) saw more -- not
 * after a send either (its answer, if queued, makes the descriptor readable). */
static void test_drained_queue_not_asked_again_until_readable(void **state)
{
    (void)state;
    fcc_socketcan_t s;
    int peer;
    pair_port(&s, &peer, 1000u);
    struct can_frame cf;
    memset(&cf, 0, sizeof cf);
    cf.can_id = 0x123u;
    cf.len = 1u;
    fcc_can_frame_t f;
    assert_int_equal(fcc_socketcan_recv(&s, &f), FCC_ERR_AGAIN); /* nothing: drained */
    assert_int_equal(write(peer, &cf, sizeof cf), (ssize_t)sizeof cf);
    assert_int_equal(fcc_socketcan_recv(&s, &f), FCC_ERR_AGAIN); /* not asked again */
    fcc_assert_ok(fcc_socketcan_wait(&s, 0));
    fcc_assert_ok(fcc_socketcan_recv(&s, &f));
    assert_int_equal(f.id, 0x123u);
    assert_int_equal(fcc_socketcan_recv(&s, &f), FCC_ERR_AGAIN); /* the read was short */
    cf.can_id = 0x124u;
    assert_int_equal(write(peer, &cf, sizeof cf), (ssize_t)sizeof cf);
    assert_int_equal(fcc_socketcan_recv(&s, &f), FCC_ERR_AGAIN);
    fcc_socketcan_readable(&s); /* the caller's own poll saw it */
    fcc_assert_ok(fcc_socketcan_recv(&s, &f));
    assert_int_equal(f.id, 0x124u);
    /* a send: the receive side as it was; the wait finds the answer */
    assert_int_equal(fcc_socketcan_recv(&s, &f), FCC_ERR_AGAIN);
    cf.can_id = 0x125u;
    assert_int_equal(write(peer, &cf, sizeof cf), (ssize_t)sizeof cf);
    fcc_can_frame_t out;
    memset(&out, 0, sizeof out);
    out.id = 0x321u;
    fcc_assert_ok(fcc_socketcan_send(&s, &out));
    assert_int_equal(fcc_socketcan_recv(&s, &f), FCC_ERR_AGAIN);
    fcc_assert_ok(fcc_socketcan_wait(&s, 0));
    fcc_assert_ok(fcc_socketcan_recv(&s, &f));
    assert_int_equal(f.id, 0x125u);
    struct can_frame echoed;
    assert_int_equal(read(peer, &echoed, sizeof echoed), (ssize_t)sizeof echoed);
    /* a full read (as many as asked for) may have left more: the next call asks */
    for (uint32_t i = 0u; i < FCC_SOCKETCAN_RX_BATCH + 1u; ++i) {
        cf.can_id = 0x200u + i;
        assert_int_equal(write(peer, &cf, sizeof cf), (ssize_t)sizeof cf);
    }
    fcc_assert_ok(fcc_socketcan_wait(&s, 0));
    for (uint32_t i = 0u; i < FCC_SOCKETCAN_RX_BATCH + 1u; ++i) {
        fcc_assert_ok(fcc_socketcan_recv(&s, &f));
        assert_int_equal(f.id, 0x200u + i);
    }
    assert_int_equal(fcc_socketcan_recv(&s, &f), FCC_ERR_AGAIN);
    fcc_can_port_counters_t c;
    fcc_assert_ok(fcc_socketcan_counters(&s, &c));
    assert_int_equal(c.rx_frames, FCC_SOCKETCAN_RX_BATCH + 4u);
    fcc_socketcan_close(&s);
    (void)close(peer);
}

/* Generous against the conversions' own errors (the realtime-monotonic offset's half
 * bracket, the counter's extrapolation: microseconds), small against the work after a send. */
#define AGREE_US 100u
#define LATER_WORK_US 2000u

static void enable_kernel_stamps(int fd)
{
    const int one = 1;
    assert_int_equal(setsockopt(fd, SOL_SOCKET, SO_TIMESTAMPNS, &one, sizeof one), 0);
}

/* The kernel's receive stamp of a frame, as the port hands it out (CLOCK_REALTIME moved to
 * CLOCK_MONOTONIC), lies between the monotonic clock read before and after its send. */
static void test_kernel_stamp_moved_to_the_monotonic_clock(void **state)
{
    (void)state;
    fcc_socketcan_t s;
    int peer;
    pair_port(&s, &peer, 1000u);
    enable_kernel_stamps(s.fd);
    struct can_frame cf;
    memset(&cf, 0, sizeof cf);
    cf.can_id = 0x040u;
    cf.len = 8u;
    for (int i = 0; i < 3; ++i) { /* the first one also measures the offset */
        const uint64_t before = fcc_hostclock_monotonic_us();
        assert_int_equal(write(peer, &cf, sizeof cf), (ssize_t)sizeof cf);
        const uint64_t after = fcc_hostclock_monotonic_us();
        fcc_assert_ok(fcc_socketcan_wait(&s, 1000));
        fcc_can_frame_t f;
        fcc_assert_ok(fcc_socketcan_recv(&s, &f));
        assert_true(f.t_us + AGREE_US >= before);
        assert_true(f.t_us <= after + AGREE_US);
    }
    fcc_socketcan_close(&s);
    (void)close(peer);
}

/* A command's send time is taken when its batch is handed to the kernel: not after the
 * kernel's own stamp of it (as the bus's port converts it), and not moved by whatever the
 * loop does before it takes the command (the old stamp, the loop's next clock read, put
 * that work into the data age).  Bracketed by clock reads around the send, not held within
 * a fixed time of the kernel's stamp: a preemption between the read and the system call
 * (101+ us in the UML guest, CI 2026-12-02) is the machine's, not the stamp's. */
static void test_command_stamped_at_its_send(void **state)
{
    (void)state;
    fcc_hostport_t hp;
    fcc_assert_ok(fcc_hostport_init(&hp, "vcan0", NULL, NULL));
    int peer;
    pair_port(&hp.sc, &peer, 1000u);
    hp.up = true;
    fcc_socketcan_t bus; /* the other end, as an observer on the bus would stamp it */
    memset(&bus, 0, sizeof bus);
    bus.fd = peer;
    enable_kernel_stamps(peer);
    const fcc_port_t port = fcc_hostport_port(&hp);
    const fcc_can_frame_t out[2] = {frame(FCC_MSG_MSL_ELEV_CMD_ID, 8u), frame(0x31u, 8u)};
    fcc_status_t st[2];
    for (int i = 0; i < 3; ++i) {
        const uint64_t before = fcc_hostport_now(&hp);
        fcc_assert_ok(port.can.send_many(port.can.ctx, out, 2u, st));
        const uint64_t handed = fcc_hostport_now(&hp);
        assert_true(hp.cmd_untaken);
        const uint64_t sent_us = hp.cmd_sent_us;
        assert_true(sent_us >= before && sent_us <= handed); /* the send's time, not the loop's */
        /* the rest of the wake: another send, work */
        fcc_assert_ok(port.can.send_many(port.can.ctx, &out[1], 1u, st));
        const uint64_t until = fcc_hostclock_monotonic_us() + LATER_WORK_US;
        while (fcc_hostclock_monotonic_us() < until) {
        }
        fcc_hostport_take_command(&hp);
        assert_false(hp.cmd_untaken);
        assert_int_equal(hp.cmd_sends, (uint32_t)i + 1u);
        assert_int_equal(hp.cmd_sent_us, sent_us);
        fcc_can_frame_t f;
        fcc_assert_ok(fcc_socketcan_wait(&bus, 1000));
        fcc_assert_ok(fcc_socketcan_recv(&bus, &f));
        assert_int_equal(f.id, FCC_MSG_MSL_ELEV_CMD_ID);
        assert_true(sent_us <= f.t_us + AGREE_US); /* not after the kernel's own stamp */
        fcc_assert_ok(fcc_socketcan_recv(&bus, &f));
        fcc_assert_ok(fcc_socketcan_recv(&bus, &f));
    }
    /* a batch without the command leaves its stamp alone */
    fcc_assert_ok(port.can.send_many(port.can.ctx, &out[1], 1u, st));
    assert_false(hp.cmd_untaken);
    fcc_socketcan_close(&bus);
    fcc_hostport_close(&hp);
}

/* The error frames a driver (or canbus) gives a node whose frames fail until bus-off: bus
 * errors with the counters, warning, passive, bus-off, restarted. */
static void test_controller_state_from_error_frames(void **state)
{
    (void)state;
    fcc_socketcan_ctrl_t c;
    memset(&c, 0, sizeof c);
    uint8_t d[8] = {0};
    const uint32_t prot = CAN_ERR_FLAG | CAN_ERR_PROT | CAN_ERR_BUSERROR | CAN_ERR_CNT;
    const uint32_t crtl = CAN_ERR_FLAG | CAN_ERR_CRTL | CAN_ERR_CNT;
    for (uint32_t k = 1u; k <= 31u; ++k) {
        d[6] = (uint8_t)(8u * k);
        fcc_socketcan_ctrl_update(&c, prot, d);
        if (k == 12u) {
            d[1] = CAN_ERR_CRTL_TX_WARNING;
            fcc_socketcan_ctrl_update(&c, crtl, d);
        } else if (k == 16u) {
            d[1] = CAN_ERR_CRTL_TX_PASSIVE;
            fcc_socketcan_ctrl_update(&c, crtl, d);
            assert_int_equal(c.state, FCC_CTRL_PASSIVE);
        }
    }
    d[6] = 255u; /* the 32nd: TEC 256, as much as data[6] holds */
    fcc_socketcan_ctrl_update(&c, prot, d);
    fcc_socketcan_ctrl_update(&c, CAN_ERR_FLAG | CAN_ERR_BUSOFF | CAN_ERR_CNT, d);
    assert_int_equal(c.state, FCC_CTRL_BUS_OFF);
    assert_string_equal(fcc_socketcan_ctrl_state_name(c.state), "bus-off");
    memset(d, 0, sizeof d);
    fcc_socketcan_ctrl_update(&c, CAN_ERR_FLAG | CAN_ERR_RESTARTED | CAN_ERR_CNT, d);
    assert_int_equal(c.state, FCC_CTRL_ACTIVE);
    assert_int_equal(c.protocol_errors, 32u);
    assert_int_equal(c.warnings, 1u);
    assert_int_equal(c.passive, 1u);
    assert_int_equal(c.bus_off, 1u);
    assert_int_equal(c.restarts, 1u);
    assert_int_equal(c.tec_max, 255u);
    assert_int_equal(c.rec_max, 0u);
    /* an overflow report changes no state; back to active by CAN_ERR_CRTL_ACTIVE */
    d[1] = CAN_ERR_CRTL_RX_OVERFLOW;
    fcc_socketcan_ctrl_update(&c, crtl, d);
    assert_int_equal(c.state, FCC_CTRL_ACTIVE);
    d[1] = CAN_ERR_CRTL_RX_WARNING;
    fcc_socketcan_ctrl_update(&c, crtl, d);
    d[1] = CAN_ERR_CRTL_ACTIVE;
    fcc_socketcan_ctrl_update(&c, crtl, d);
    assert_int_equal(c.state, FCC_CTRL_ACTIVE);
    assert_int_equal(c.warnings, 2u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_open_bad_names),
        cmocka_unit_test(test_closed_port_refuses_everything),
        cmocka_unit_test(test_send_many_bad_arguments),
        cmocka_unit_test(test_send_many_in_order_as_can_frames),
        cmocka_unit_test(test_send_many_full_queue_retried_then_dropped),
        cmocka_unit_test(test_send_many_io_error_ends_the_batch),
        cmocka_unit_test(test_recv_reads_ahead_in_arrival_order),
        cmocka_unit_test(test_drained_queue_not_asked_again_until_readable),
        cmocka_unit_test(test_kernel_stamp_moved_to_the_monotonic_clock),
        cmocka_unit_test(test_command_stamped_at_its_send),
        cmocka_unit_test(test_controller_state_from_error_frames),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
