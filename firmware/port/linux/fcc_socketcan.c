/*
 * fcc_socketcan.c -- SocketCAN raw-socket port.  See fcc_socketcan.h.
 */
#define _GNU_SOURCE 1 /* sendmmsg, recvmmsg, CMSG_*, clock_gettime under -std=c99 */

#include "fcc_socketcan.h"

#include "fcc_hostclock.h"

#include <errno.h>
#include <net/if.h>
#include <poll.h>
#include <stdbool.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>

#ifndef SO_RXQ_OVFL
#define SO_RXQ_OVFL 40
#endif
#ifndef SO_RCVBUFFORCE
#define SO_RCVBUFFORCE 33
#endif

static uint64_t timespec_us(const struct timespec *ts)
{
    return (uint64_t)ts->tv_sec * 1000000u + (uint64_t)ts->tv_nsec / 1000u;
}

/* The kernel stamps frames with CLOCK_REALTIME; the port's clock (now_us, the
 * schedule, the time sync) is CLOCK_MONOTONIC.  The difference of the two is
 * read as the tightest of 5 monotonic-realtime-monotonic brackets (a reading
 * interrupted between two clock reads would add its delay to every stamp),
 * renewed when the stamps have moved on by more than a second (to follow NTP
 * slewing; a step of the realtime clock either way renews it too).  Judged by
 * the stamps themselves, not by a clock read per frame: under User-Mode Linux
 * every clock read is a system call. */
static uint64_t realtime_to_monotonic(fcc_socketcan_t *s, uint64_t rt_us)
{
    const uint64_t since = (rt_us > s->rt_offset_at_us) ? rt_us - s->rt_offset_at_us
                                                        : s->rt_offset_at_us - rt_us;
    if (s->rt_offset_at_us == 0u || since > 1000000u) {
        uint64_t best = UINT64_MAX;
        for (int i = 0; i < 5; ++i) {
            struct timespec rt;
            const uint64_t m0 = fcc_hostclock_monotonic_us();
            (void)clock_gettime(CLOCK_REALTIME, &rt);
            const uint64_t m1 = fcc_hostclock_monotonic_us();
            if (m1 - m0 < best) {
                best = m1 - m0;
                s->rt_minus_mono_us = (int64_t)timespec_us(&rt) - (int64_t)(m0 + (m1 - m0) / 2u);
            }
        }
        s->rt_offset_at_us = (rt_us != 0u) ? rt_us : 1u;
    }
    const int64_t mono = (int64_t)rt_us - s->rt_minus_mono_us;
    return (mono > 0) ? (uint64_t)mono : 1u;
}

static fcc_status_t set_opt(int fd, int level, int name, const void *val, socklen_t len)
{
    return (setsockopt(fd, level, name, val, len) == 0) ? FCC_OK : FCC_ERR_IO;
}

static fcc_status_t configure(int fd)
{
    const int one = 1;
    const can_err_mask_t err_mask = CAN_ERR_MASK; /* every error class */
    fcc_status_t st = set_opt(fd, SOL_SOCKET, SO_TIMESTAMPNS, &one, sizeof one);
    if (st == FCC_OK) {
        st = set_opt(fd, SOL_SOCKET, SO_RXQ_OVFL, &one, sizeof one);
    }
    if (st == FCC_OK) {
        st = set_opt(fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &err_mask, sizeof err_mask);
    }
    return st;
}

fcc_status_t fcc_socketcan_open(fcc_socketcan_t *s, const char *ifname)
{
    if (s == NULL) {
        return FCC_ERR_ARG;
    }
    memset(s, 0, sizeof *s);
    s->fd = -1;
    s->send_budget_us = FCC_SOCKETCAN_DEFAULT_SEND_BUDGET_US;
    if (ifname == NULL || ifname[0] == '\0' || strlen(ifname) >= IFNAMSIZ) {
        return FCC_ERR_ARG;
    }
    const int fd = socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
    if (fd < 0) {
        return FCC_ERR_IO;
    }
    struct ifreq ifr;
    memset(&ifr, 0, sizeof ifr);
    memcpy(ifr.ifr_name, ifname, strlen(ifname));
    struct sockaddr_can addr;
    memset(&addr, 0, sizeof addr);
    addr.can_family = AF_CAN;
    fcc_status_t st = (ioctl(fd, SIOCGIFINDEX, &ifr) == 0) ? FCC_OK : FCC_ERR_IO;
    if (st == FCC_OK) {
        addr.can_ifindex = ifr.ifr_ifindex;
        st = configure(fd);
    }
    if (st == FCC_OK && bind(fd, (struct sockaddr *)&addr, sizeof addr) != 0) {
        st = FCC_ERR_IO;
    }
    if (st != FCC_OK) {
        (void)close(fd);
        return st;
    }
    s->fd = fd;
    return FCC_OK;
}

fcc_status_t fcc_socketcan_set_rcvbuf(fcc_socketcan_t *s, int bytes)
{
    if (s == NULL || s->fd < 0 || bytes <= 0) {
        return FCC_ERR_ARG;
    }
    /* FORCE needs CAP_NET_ADMIN; without it the plain option is capped by rmem_max */
    if (set_opt(s->fd, SOL_SOCKET, SO_RCVBUFFORCE, &bytes, sizeof bytes) == FCC_OK) {
        return FCC_OK;
    }
    return set_opt(s->fd, SOL_SOCKET, SO_RCVBUF, &bytes, sizeof bytes);
}

fcc_status_t fcc_socketcan_set_filters(fcc_socketcan_t *s, const uint32_t *ids, size_t n)
{
    if (s == NULL || s->fd < 0 || n > FCC_SOCKETCAN_MAX_FILTERS || (n > 0u && ids == NULL)) {
        return FCC_ERR_ARG;
    }
    struct can_filter f[FCC_SOCKETCAN_MAX_FILTERS];
    for (size_t i = 0u; i < n; ++i) {
        if (ids[i] > CAN_SFF_MASK) {
            return FCC_ERR_ARG;
        }
        f[i].can_id = ids[i];
        /* exact identifier, standard frame, data frame */
        f[i].can_mask = CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG;
    }
    if (n == 0u) { /* one filter that passes everything */
        f[0].can_id = 0u;
        f[0].can_mask = 0u;
        n = 1u;
    }
    return set_opt(s->fd, SOL_CAN_RAW, CAN_RAW_FILTER, f, (socklen_t)(n * sizeof f[0]));
}

/* Read the control messages: kernel time stamp and receive-queue drop count. */
static void read_cmsgs(fcc_socketcan_t *s, struct msghdr *mh, uint64_t *t_us)
{
    *t_us = 0u;
    for (struct cmsghdr *c = CMSG_FIRSTHDR(mh); c != NULL; c = CMSG_NXTHDR(mh, c)) {
        if (c->cmsg_level != SOL_SOCKET) {
            continue;
        }
        if (c->cmsg_type == SO_TIMESTAMPNS) {
            struct timespec ts;
            memcpy(&ts, CMSG_DATA(c), sizeof ts);
            *t_us = realtime_to_monotonic(s, timespec_us(&ts));
        } else if (c->cmsg_type == SO_RXQ_OVFL) {
            uint32_t drops;
            memcpy(&drops, CMSG_DATA(c), sizeof drops);
            s->cnt.rx_overflows += drops - s->kernel_drops; /* wraps like the kernel's */
            s->kernel_drops = drops;
        }
    }
}

/* The state a CAN_ERR_CRTL frame's data[1] says (can_change_state(): the side(s) at it). */
static fcc_ctrl_state_t crtl_state(uint8_t bits, fcc_ctrl_state_t was)
{
    if ((bits & (CAN_ERR_CRTL_TX_PASSIVE | CAN_ERR_CRTL_RX_PASSIVE)) != 0u) {
        return FCC_CTRL_PASSIVE;
    }
    if ((bits & (CAN_ERR_CRTL_TX_WARNING | CAN_ERR_CRTL_RX_WARNING)) != 0u) {
        return FCC_CTRL_WARNING;
    }
    return (bits & CAN_ERR_CRTL_ACTIVE) != 0u ? FCC_CTRL_ACTIVE : was; /* overflows: no change */
}

void fcc_socketcan_ctrl_update(fcc_socketcan_ctrl_t *c, uint32_t can_id, const uint8_t *data)
{
    if (c == NULL || data == NULL) {
        return;
    }
    const fcc_ctrl_state_t was = c->state;
    fcc_ctrl_state_t now = was;
    if ((can_id & CAN_ERR_PROT) != 0u) {
        ++c->protocol_errors;
    }
    if ((can_id & CAN_ERR_CRTL) != 0u) {
        now = crtl_state(data[1], was);
    }
    if ((can_id & CAN_ERR_BUSOFF) != 0u) {
        now = FCC_CTRL_BUS_OFF;
    }
    if ((can_id & CAN_ERR_RESTARTED) != 0u) {
        ++c->restarts;
        now = FCC_CTRL_ACTIVE;
    }
    if ((can_id & CAN_ERR_CNT) != 0u) {
        c->tec_max = data[6] > c->tec_max ? data[6] : c->tec_max;
        c->rec_max = data[7] > c->rec_max ? data[7] : c->rec_max;
    }
    if (now != was) {
        c->warnings += now == FCC_CTRL_WARNING ? 1u : 0u;
        c->passive += now == FCC_CTRL_PASSIVE ? 1u : 0u;
        c->bus_off += now == FCC_CTRL_BUS_OFF ? 1u : 0u;
        c->state = now;
    }
}

const char *fcc_socketcan_ctrl_state_name(fcc_ctrl_state_t state)
{
    static const char *const names[] = {"active", "warning", "passive", "bus-off"};
    return (unsigned)state < sizeof names / sizeof names[0] ? names[state] : "?";
}

/* One received message: a frame for the application into the read-ahead
 * buffer, or an error frame / a frame the port cannot represent counted. */
static void take_message(fcc_socketcan_t *s, const struct can_frame *cf, size_t len,
                         struct msghdr *mh)
{
    uint64_t t_us;
    read_cmsgs(s, mh, &t_us);
    if ((cf->can_id & CAN_ERR_FLAG) != 0u) {
        ++s->cnt.bus_errors;
        fcc_socketcan_ctrl_update(&s->ctrl, cf->can_id, cf->data);
        return;
    }
    if (len != sizeof *cf || (cf->can_id & (CAN_EFF_FLAG | CAN_RTR_FLAG)) != 0u ||
        cf->len > CAN_MAX_DLEN) {
        ++s->cnt.rx_ignored;
        return;
    }
    fcc_can_frame_t *frame = &s->rx[s->rx_n++];
    frame->id = cf->can_id & CAN_SFF_MASK;
    frame->dlc = cf->len;
    memset(frame->data, 0, sizeof frame->data);
    memcpy(frame->data, cf->data, cf->len);
    frame->t_us = t_us;
}

/* Reads the waiting messages, up to FCC_SOCKETCAN_RX_BATCH, with one recvmmsg into
 * the (empty) read-ahead buffer.  FCC_ERR_AGAIN when none is waiting.  Fewer than
 * asked for: the kernel's queue is empty now (drained), so the next read waits for
 * the caller's wait to see the descriptor readable -- under User-Mode Linux a system
 * call costs about as much as a whole step's arithmetic. */
static fcc_status_t read_ahead(fcc_socketcan_t *s)
{
    struct can_frame cf[FCC_SOCKETCAN_RX_BATCH];
    struct iovec iov[FCC_SOCKETCAN_RX_BATCH];
    union { /* control messages are aligned like size_t (cmsghdr's cmsg_len) */
        char buf[CMSG_SPACE(sizeof(struct timespec)) + CMSG_SPACE(sizeof(uint32_t))];
        size_t align;
    } ctrl[FCC_SOCKETCAN_RX_BATCH];
    struct mmsghdr mm[FCC_SOCKETCAN_RX_BATCH];
    memset(mm, 0, sizeof mm);
    for (uint32_t i = 0u; i < FCC_SOCKETCAN_RX_BATCH; ++i) {
        iov[i].iov_base = &cf[i];
        iov[i].iov_len = sizeof cf[i];
        mm[i].msg_hdr.msg_iov = &iov[i];
        mm[i].msg_hdr.msg_iovlen = 1;
        mm[i].msg_hdr.msg_control = ctrl[i].buf;
        mm[i].msg_hdr.msg_controllen = sizeof ctrl[i].buf;
    }
    const int n = recvmmsg(s->fd, mm, FCC_SOCKETCAN_RX_BATCH, MSG_DONTWAIT, NULL);
    if (n < 0) {
        if (errno == EAGAIN || errno == EWOULDBLOCK) {
            s->drained = true;
            return FCC_ERR_AGAIN;
        }
        return (errno == EINTR) ? FCC_ERR_AGAIN : FCC_ERR_IO;
    }
    s->drained = (uint32_t)n < FCC_SOCKETCAN_RX_BATCH;
    s->rx_head = 0u;
    s->rx_n = 0u;
    for (int i = 0; i < n; ++i) {
        take_message(s, &cf[i], mm[i].msg_len, &mm[i].msg_hdr);
    }
    return FCC_OK;
}

fcc_status_t fcc_socketcan_recv(fcc_socketcan_t *s, fcc_can_frame_t *frame)
{
    if (s == NULL || s->fd < 0 || frame == NULL) {
        return FCC_ERR_ARG;
    }
    while (s->rx_head == s->rx_n) { /* error and foreign frames skipped; the queue is finite */
        if (s->drained) {
            return FCC_ERR_AGAIN;
        }
        const fcc_status_t st = read_ahead(s);
        if (st != FCC_OK) {
            return st;
        }
    }
    *frame = s->rx[s->rx_head++];
    ++s->cnt.rx_frames;
    return FCC_OK;
}

bool fcc_socketcan_pending(const fcc_socketcan_t *s)
{
    return s != NULL && s->fd >= 0 && s->rx_head < s->rx_n;
}

fcc_status_t fcc_socketcan_wait(fcc_socketcan_t *s, int timeout_ms)
{
    if (s == NULL || s->fd < 0) {
        return FCC_ERR_ARG;
    }
    if (s->rx_head < s->rx_n) { /* read ahead, not yet handed out */
        return FCC_OK;
    }
    struct pollfd p = {s->fd, POLLIN, 0};
    const int r = poll(&p, 1, timeout_ms);
    if (r < 0) {
        return (errno == EINTR) ? FCC_ERR_AGAIN : FCC_ERR_IO;
    }
    if (r == 0) {
        return FCC_ERR_AGAIN;
    }
    s->drained = false;
    return FCC_OK;
}

void fcc_socketcan_readable(fcc_socketcan_t *s)
{
    if (s != NULL) {
        s->drained = false;
    }
}

static bool frame_sendable(const fcc_can_frame_t *frame)
{
    return frame->id <= CAN_SFF_MASK && frame->dlc <= CAN_MAX_DLEN;
}

/* The messages of one sendmmsg: the kernel's frames and their headers, and the
 * index of each in the caller's array (frames it refused are not in it). */
typedef struct {
    struct can_frame cf[FCC_SOCKETCAN_MAX_BATCH];
    struct iovec iov[FCC_SOCKETCAN_MAX_BATCH];
    struct mmsghdr mm[FCC_SOCKETCAN_MAX_BATCH];
    uint32_t index[FCC_SOCKETCAN_MAX_BATCH];
    uint32_t n;
} batch_t;

static void batch_fill(batch_t *b, const fcc_can_frame_t *frames, uint32_t n, fcc_status_t *st)
{
    b->n = 0u;
    for (uint32_t i = 0u; i < n; ++i) {
        if (!frame_sendable(&frames[i])) {
            st[i] = FCC_ERR_ARG;
            continue;
        }
        const uint32_t m = b->n++;
        memset(&b->cf[m], 0, sizeof b->cf[m]);
        b->cf[m].can_id = frames[i].id;
        b->cf[m].len = frames[i].dlc;
        memcpy(b->cf[m].data, frames[i].data, frames[i].dlc);
        b->iov[m].iov_base = &b->cf[m];
        b->iov[m].iov_len = sizeof b->cf[m];
        memset(&b->mm[m], 0, sizeof b->mm[m]);
        b->mm[m].msg_hdr.msg_iov = &b->iov[m];
        b->mm[m].msg_hdr.msg_iovlen = 1;
        b->index[m] = i;
    }
}

/* Sends a batch's messages in order, each with the bounded retry of a single
 * send: a message refused with a full queue (ENOBUFS/EAGAIN/EINTR) is tried again
 * (counted in tx_retries) until send_budget_us after its first refusal, then
 * dropped (tx_dropped, FCC_ERR_AGAIN) and the next one goes.  The deadline is
 * read only once a send failed: a clock read is a system call under User-Mode
 * Linux, and most sends succeed.  False after an I/O error (that message and
 * the later ones FCC_ERR_IO). */
static bool batch_send(fcc_socketcan_t *s, batch_t *b, fcc_status_t *st)
{
    uint32_t next = 0u;
    uint64_t deadline = 0u;
    /* A send leaves the receive side as it is: an answer that came meanwhile makes the
     * descriptor readable, and the caller's wait returns at once for it (in lockstep the
     * peers run as SCHED_BATCH, so the answer comes only once this process waits: a read
     * after each send found nothing, a system call per step). */
    while (next < b->n) {
        const int sent = sendmmsg(s->fd, &b->mm[next], b->n - next, 0);
        const int err = (sent < 0) ? errno : 0;
        uint32_t whole = 0u; /* messages the kernel took whole (a raw CAN socket: all it took) */
        while ((int)whole < sent && b->mm[next + whole].msg_len == sizeof b->cf[0]) {
            st[b->index[next + whole]] = FCC_OK;
            ++s->cnt.tx_frames;
            ++whole;
        }
        next += whole;
        if (sent > 0 && (int)whole == sent) {
            deadline = 0u; /* the next message has a budget of its own */
            continue;
        }
        if (sent >= 0 || (err != ENOBUFS && err != EAGAIN && err != EINTR)) {
            for (uint32_t j = next; j < b->n; ++j) {
                st[b->index[j]] = FCC_ERR_IO;
            }
            return false;
        }
        const uint64_t now = fcc_hostclock_monotonic_us();
        if (deadline == 0u) {
            deadline = now + s->send_budget_us;
        }
        if (now >= deadline) {
            ++s->cnt.tx_dropped;
            st[b->index[next]] = FCC_ERR_AGAIN;
            ++next;
            deadline = 0u;
            continue;
        }
        ++s->cnt.tx_retries;
        /* ENOBUFS does not wake poll(): wait a short, bounded time either way. */
        struct pollfd p = {s->fd, POLLOUT, 0};
        (void)poll(&p, 1, 1);
    }
    return true;
}

fcc_status_t fcc_socketcan_send_many(fcc_socketcan_t *s, const fcc_can_frame_t *frames,
                                     uint32_t n, fcc_status_t *st)
{
    if (s == NULL || (n > 0u && (frames == NULL || st == NULL))) {
        return FCC_ERR_ARG;
    }
    batch_t b;
    bool io_ok = true;
    for (uint32_t done = 0u; done < n;) {
        const uint32_t chunk = (n - done < FCC_SOCKETCAN_MAX_BATCH) ? n - done
                                                                    : FCC_SOCKETCAN_MAX_BATCH;
        if (s->fd < 0 || !io_ok) { /* closed, or the interface failed earlier in this batch */
            for (uint32_t i = done; i < done + chunk; ++i) {
                st[i] = (s->fd < 0) ? FCC_ERR_ARG : FCC_ERR_IO;
            }
        } else {
            batch_fill(&b, &frames[done], chunk, &st[done]);
            io_ok = batch_send(s, &b, &st[done]);
        }
        done += chunk;
    }
    fcc_status_t first = FCC_OK;
    for (uint32_t i = 0u; i < n && first == FCC_OK; ++i) {
        first = st[i];
    }
    return first;
}

fcc_status_t fcc_socketcan_send(fcc_socketcan_t *s, const fcc_can_frame_t *frame)
{
    fcc_status_t st;
    return fcc_socketcan_send_many(s, frame, 1u, &st);
}

fcc_status_t fcc_socketcan_counters(const fcc_socketcan_t *s, fcc_can_port_counters_t *out)
{
    if (s == NULL || out == NULL) {
        return FCC_ERR_ARG;
    }
    *out = s->cnt;
    return FCC_OK;
}

void fcc_socketcan_close(fcc_socketcan_t *s)
{
    if (s != NULL && s->fd >= 0) {
        (void)close(s->fd);
        s->fd = -1;
        s->rx_head = 0u; /* frames read ahead from a closed socket are gone with it */
        s->rx_n = 0u;
    }
}

static fcc_status_t port_send(void *ctx, const fcc_can_frame_t *frame)
{
    return fcc_socketcan_send(ctx, frame);
}

static fcc_status_t port_send_many(void *ctx, const fcc_can_frame_t *frames, uint32_t n,
                                   fcc_status_t *st)
{
    return fcc_socketcan_send_many(ctx, frames, n, st);
}

static fcc_status_t port_recv(void *ctx, fcc_can_frame_t *frame)
{
    return fcc_socketcan_recv(ctx, frame);
}

static fcc_status_t port_counters(void *ctx, fcc_can_port_counters_t *out)
{
    return fcc_socketcan_counters(ctx, out);
}

fcc_can_port_t fcc_socketcan_port(fcc_socketcan_t *s)
{
    fcc_can_port_t port = {s, port_send, port_recv, port_counters, port_send_many};
    return port;
}
