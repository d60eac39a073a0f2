/*
 * fcc_hostport.c -- Linux port: SocketCAN + clock + interface watchdog.
 */
#define _DEFAULT_SOURCE 1 /* ioctl flags under -std=c99 */

#include "fcc_hostport.h"

#include <net/if.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include "fcc_bus_msgs.h"

uint64_t fcc_hostport_now(fcc_hostport_t *hp)
{
    ++hp->clock_reads;
    return fcc_hostclock_now(&hp->clock);
}

static void report(const fcc_hostport_t *hp, fcc_event_class_t cls, int32_t value)
{
    if (hp->event != NULL) {
        fcc_event_t ev = {cls, 0xFFu, FCC_EV_NO_MSG, 0u, value};
        hp->event(hp->event_ctx, &ev);
    }
}

/* The interface exists and is administratively up. */
static bool iface_up(const char *ifname)
{
    const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd < 0) {
        return false;
    }
    struct ifreq ifr;
    memset(&ifr, 0, sizeof ifr);
    memcpy(ifr.ifr_name, ifname, strnlen(ifname, IFNAMSIZ - 1u));
    const bool up = ioctl(fd, SIOCGIFFLAGS, &ifr) == 0 && (ifr.ifr_flags & IFF_UP) != 0;
    (void)close(fd);
    return up;
}

static void add_counters(fcc_can_port_counters_t *acc, const fcc_can_port_counters_t *c)
{
    acc->rx_frames += c->rx_frames;
    acc->tx_frames += c->tx_frames;
    acc->bus_errors += c->bus_errors;
    acc->rx_overflows += c->rx_overflows;
    acc->tx_retries += c->tx_retries;
    acc->tx_dropped += c->tx_dropped;
    acc->rx_ignored += c->rx_ignored;
}

fcc_status_t fcc_hostport_init(fcc_hostport_t *hp, const char *ifname,
                               void (*event)(void *ctx, const fcc_event_t *ev), void *event_ctx)
{
    if (hp == NULL || ifname == NULL || strlen(ifname) >= sizeof hp->ifname) {
        return FCC_ERR_ARG;
    }
    memset(hp, 0, sizeof *hp);
    hp->sc.fd = -1;
    fcc_hostclock_init(&hp->clock, fcc_hostclock_has_counter());
    strcpy(hp->ifname, ifname);
    hp->cmd_id = FCC_MSG_MSL_ELEV_CMD_ID;
    hp->event = event;
    hp->event_ctx = event_ctx;
    return FCC_OK;
}

/* fcc's receive buffer: a burst (a flood before a lockstep tick) must not overflow the
 * default ~200 kB (~300 frames) and lose the tick; 4 MiB hold ~5000 frames. */
#define FCC_HOSTPORT_RCVBUF_BYTES (4 << 20)

static void size_rcvbuf(fcc_socketcan_t *sc)
{
    /* best effort: refused without privilege, the default buffer still works */
    const fcc_status_t st = fcc_socketcan_set_rcvbuf(sc, FCC_HOSTPORT_RCVBUF_BYTES);
    (void)st;
}

fcc_status_t fcc_hostport_open(fcc_hostport_t *hp)
{
    if (hp == NULL || hp->up) {
        return FCC_ERR_ARG;
    }
    if (!iface_up(hp->ifname)) {
        return FCC_ERR_IO;
    }
    const fcc_status_t st = fcc_socketcan_open(&hp->sc, hp->ifname);
    hp->up = (st == FCC_OK);
    if (hp->up) {
        size_rcvbuf(&hp->sc);
    }
    return st;
}

int fcc_hostport_fd(const fcc_hostport_t *hp)
{
    return (hp != NULL && hp->up) ? hp->sc.fd : -1;
}

bool fcc_hostport_pending(const fcc_hostport_t *hp)
{
    return hp != NULL && hp->up && fcc_socketcan_pending(&hp->sc);
}

void fcc_hostport_readable(fcc_hostport_t *hp)
{
    if (hp != NULL && hp->up) {
        fcc_socketcan_readable(&hp->sc);
    }
}

void fcc_hostport_take_command(fcc_hostport_t *hp)
{
    if (hp != NULL && hp->cmd_untaken) {
        hp->cmd_untaken = false;
        ++hp->cmd_sends;
    }
}

void fcc_hostport_lost(fcc_hostport_t *hp)
{
    if (hp == NULL || !hp->up) {
        return;
    }
    fcc_can_port_counters_t c;
    if (fcc_socketcan_counters(&hp->sc, &c) == FCC_OK) {
        add_counters(&hp->carried, &c);
    }
    fcc_socketcan_close(&hp->sc);
    hp->up = false;
    ++hp->downs;
    hp->next_probe_us = fcc_hostport_now(hp) + FCC_HOSTPORT_PROBE_US;
    report(hp, FCC_EV_IFACE_DOWN, (int32_t)hp->downs);
}

uint64_t fcc_hostport_service(fcc_hostport_t *hp, uint64_t now_us)
{
    if (hp == NULL || hp->up) {
        return UINT64_MAX;
    }
    if (now_us < hp->next_probe_us) {
        return hp->next_probe_us;
    }
    hp->next_probe_us = now_us + FCC_HOSTPORT_PROBE_US;
    if (!iface_up(hp->ifname)) {
        return hp->next_probe_us;
    }
    fcc_socketcan_t fresh;
    if (fcc_socketcan_open(&fresh, hp->ifname) != FCC_OK) {
        return hp->next_probe_us;
    }
    size_rcvbuf(&fresh);
    fresh.ctrl = hp->sc.ctrl; /* the controller's story goes on over a reopen */
    hp->sc = fresh;
    hp->up = true;
    ++hp->reopens;
    report(hp, FCC_EV_IFACE_UP, (int32_t)hp->reopens);
    return UINT64_MAX;
}

void fcc_hostport_close(fcc_hostport_t *hp)
{
    if (hp != NULL && hp->up) {
        fcc_socketcan_close(&hp->sc);
        hp->up = false;
    }
}

/* ---- the port table ------------------------------------------------------------ */

static fcc_status_t port_send_many(void *ctx, const fcc_can_frame_t *frames, uint32_t n,
                                   fcc_status_t *st)
{
    fcc_hostport_t *hp = ctx;
    if (frames == NULL || st == NULL) {
        return FCC_ERR_ARG;
    }
    if (!hp->up) {
        for (uint32_t i = 0u; i < n; ++i) {
            st[i] = FCC_ERR_IO;
        }
        return (n > 0u) ? FCC_ERR_IO : FCC_OK;
    }
    bool has_cmd = false;
    for (uint32_t i = 0u; i < n; ++i) {
        has_cmd = has_cmd || frames[i].id == hp->cmd_id;
    }
    /* the command's send time: handed to the kernel now (fcc_hostport.h) */
    const uint64_t handed_us = has_cmd ? fcc_hostport_now(hp) : 0u;
    const fcc_status_t first = fcc_socketcan_send_many(&hp->sc, frames, n, st);
    bool cmd_sent = false;
    bool io_error = false;
    for (uint32_t i = 0u; i < n; ++i) {
        cmd_sent = cmd_sent || (st[i] == FCC_OK && frames[i].id == hp->cmd_id);
        io_error = io_error || st[i] == FCC_ERR_IO;
    }
    if (cmd_sent) { /* on the bus */
        hp->cmd_sent_us = handed_us;
        hp->cmd_untaken = true;
    }
    if (io_error) {
        fcc_hostport_lost(hp);
    }
    return first;
}

static fcc_status_t port_send(void *ctx, const fcc_can_frame_t *frame)
{
    fcc_status_t st;
    return port_send_many(ctx, frame, 1u, &st);
}

static fcc_status_t port_recv(void *ctx, fcc_can_frame_t *frame)
{
    fcc_hostport_t *hp = ctx;
    if (!hp->up) {
        return FCC_ERR_AGAIN;
    }
    const fcc_status_t st = fcc_socketcan_recv(&hp->sc, frame);
    if (st == FCC_ERR_IO) {
        fcc_hostport_lost(hp);
    }
    return st;
}

static fcc_status_t port_counters(void *ctx, fcc_can_port_counters_t *out)
{
    const fcc_hostport_t *hp = ctx;
    *out = hp->carried;
    fcc_can_port_counters_t c;
    if (hp->up && fcc_socketcan_counters(&hp->sc, &c) == FCC_OK) {
        add_counters(out, &c);
    }
    return FCC_OK;
}

static uint64_t port_now(void *ctx)
{
    return fcc_hostport_now(ctx);
}

fcc_port_t fcc_hostport_port(fcc_hostport_t *hp)
{
    const fcc_port_t p = {
        .clock_ctx = hp,
        .can = {.ctx = hp, .send = port_send, .recv = port_recv, .counters = port_counters,
                .send_many = port_send_many},
        .now_us = port_now,
        .event = hp->event,
        .event_ctx = hp->event_ctx,
    };
    return p;
}
