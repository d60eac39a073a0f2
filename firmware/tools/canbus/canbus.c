/*
 * canbus -- a classic CAN bus with wire time between SocketCAN endpoints.
 *
 *   canbus [--bitrate BPS] --node IFACE[:prio|:fifo] --node IFACE[:...] ...
 *
 * Each node has an endpoint of its own: a vxcan pair, the node on one end,
 * canbus on the other (IFACE).  Whatever canbus reads on IFACE that node sent;
 * what canbus writes there, that node receives.  canbus_core.h is the bus:
 * every frame read is queued at its node with the kernel's receive time
 * (SO_TIMESTAMPNS: when the node sent it, vxcan being synchronous), wins
 * arbitration when the bus is idle, and ends after its exact length on the
 * wire; canbus sleeps until that end of frame (clock_nanosleep, absolute,
 * CLOCK_MONOTONIC) and writes the frame to every other endpoint.
 *
 * The loop: take the time, read every endpoint (what came before that time
 * is then queued), run the core up to it, then sleep until the core's next
 * event: an end of frame is delivered at once on waking (nothing queued
 * meanwhile can change it), an arbitration only after reading again.  With
 * nothing on the bus canbus waits in ppoll() for a frame.
 *
 * A node's frames stay in the kernel's receive queue of its endpoint while
 * its queue in the core is full (its controller's queue: backpressure as a
 * qdisc gives it); frames the kernel drops there (SO_RXQ_OVFL), frames a
 * pair drops on the way (its interfaces' drop counters, read with each
 * report) and deliveries that fail are counted: exit 3.
 *
 * Faults (canbus_faults.h, --error, --bus-off, --babble): the core corrupts
 * frames, counts each node's TEC and REC, puts a node bus-off and recovers it;
 * canbus writes each node's part of it to its endpoint as the node's own
 * controller driver would (SocketCAN error frames, CAN_ERR_*: the node sees
 * them on a raw socket with CAN_RAW_ERR_FILTER).  A babbling node is a node
 * of the core with no endpoint, and so is a background load (--load,
 * canbus_load.h: the generator of the lockstep rig's bus model, released in
 * wall time).  The faults' times count from the first frame
 * canbus carries, or from the instant in --epoch FILE, read on SIGUSR2 (a rig
 * writes its flight's start there).
 *
 * Measured (canbus_stats.h): each frame's response time per identifier, and
 * how long after the model's end of frame its last write returned (the
 * delivery error).  One JSON line on stdout on SIGUSR1 and at SIGINT/SIGTERM.
 *
 * Exit: 0 stopped by a signal; 1 socket error; 2 bad command line; 3 frames
 * lost.  Host tool (Linux), static storage only.
 */
#define _GNU_SOURCE

#include <errno.h>
#include <net/if.h>
#include <poll.h>
#include <signal.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>

#include "canbus_core.h"
#include "canbus_opts.h"
#include "canbus_stats.h"

#define EXIT_IO 1
#define EXIT_USAGE 2
#define EXIT_LOST 3

#define NS_PER_S 1000000000ull
/* Frames one read takes from an endpoint (at most the room in the node's queue). */
#define READ_BATCH 32u
/* An endpoint's receive queue: a node's backlog while its controller queue is full. */
#define RCVBUF_BYTES (4 * 1024 * 1024)
/* The realtime - monotonic offset (for the kernel's receive times) is taken again this often. */
#define OFFSET_EVERY_NS NS_PER_S

typedef union {
    char buf[CMSG_SPACE(sizeof(struct timespec)) + CMSG_SPACE(sizeof(uint32_t))];
    size_t align;
} control_t;

typedef struct {
    const canbus_opts_t *o;
    canbus_core_t core;
    canbus_stats_t stats;
    int sock[CANBUS_NODES_MAX];             /* the endpoints' (babbling nodes have none) */
    uint32_t endpoints;
    bool armed;                             /* the faults are in the core (first frame) */
    canbus_load_t load[CANBUS_LOADS_MAX];   /* the background loads, once armed */
    uint32_t load_node[CANBUS_LOADS_MAX];
    uint32_t loads;
    uint32_t drops_seen[CANBUS_NODES_MAX]; /* SO_RXQ_OVFL as last read */
    uint64_t link_drops[CANBUS_NODES_MAX];  /* the pair's drop counters at the start */
    struct pollfd pfd[CANBUS_NODES_MAX];
    int64_t rt_offset;                      /* CLOCK_REALTIME - CLOCK_MONOTONIC, ns */
    uint64_t offset_at;
    uint64_t t_start;
    struct mmsghdr msgs[READ_BATCH];
    struct iovec iov[READ_BATCH];
    struct canfd_frame in[READ_BATCH];
    control_t control[READ_BATCH];
} bus_t;

static bus_t g_bus;
static volatile sig_atomic_t g_stop = 0;
static volatile sig_atomic_t g_report = 0;
static volatile sig_atomic_t g_epoch = 0;

static void on_signal(int sig)
{
    if (sig == SIGUSR1) {
        g_report = 1;
    } else if (sig == SIGUSR2) {
        g_epoch = 1;
    } else {
        g_stop = 1;
    }
}

static int fail(const char *what, const char *iface, int err)
{
    fprintf(stderr, "canbus: %s%s%s: %s\n", what, iface ? " " : "", iface ? iface : "",
            strerror(err));
    return EXIT_IO;
}

static uint64_t ns_of(const struct timespec *ts)
{
    return (uint64_t)ts->tv_sec * NS_PER_S + (uint64_t)ts->tv_nsec;
}

static uint64_t mono_now(void)
{
    struct timespec ts;
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);
    return ns_of(&ts);
}

/* CLOCK_REALTIME - CLOCK_MONOTONIC, the realtime read between two monotonic ones. */
static void take_offset(bus_t *b, uint64_t now)
{
    struct timespec m1, rt, m2;
    (void)clock_gettime(CLOCK_MONOTONIC, &m1);
    (void)clock_gettime(CLOCK_REALTIME, &rt);
    (void)clock_gettime(CLOCK_MONOTONIC, &m2);
    b->rt_offset = (int64_t)ns_of(&rt) - (int64_t)((ns_of(&m1) + ns_of(&m2)) / 2u);
    b->offset_at = now;
}

/* One counter of /sys/class/net/IFACE/statistics (0 where it cannot be read). */
static uint64_t link_stat(const char *iface, const char *name)
{
    char path[96];
    unsigned long long v = 0u;
    (void)snprintf(path, sizeof path, "/sys/class/net/%s/statistics/%s", iface, name);
    FILE *f = fopen(path, "r");
    if (f != NULL) {
        if (fscanf(f, "%llu", &v) != 1) {
            v = 0u;
        }
        (void)fclose(f);
    }
    return (uint64_t)v;
}

/* Frames the pair of endpoint i dropped on the way from the node to canbus or back (vxcan
 * counts a frame the kernel's backlog refused as tx_dropped of the sending end, rx_dropped of
 * the receiving one): both ends' counters.  The peer is found by its index (iflink). */
static uint64_t link_drops(const char *iface)
{
    char path[96];
    char peer[IF_NAMESIZE] = "";
    unsigned idx = 0u;
    (void)snprintf(path, sizeof path, "/sys/class/net/%s/iflink", iface);
    FILE *f = fopen(path, "r");
    if (f != NULL) {
        if (fscanf(f, "%u", &idx) != 1 || if_indextoname(idx, peer) == NULL) {
            peer[0] = '\0';
        }
        (void)fclose(f);
    }
    uint64_t n = link_stat(iface, "rx_dropped") + link_stat(iface, "tx_dropped");
    if (peer[0] != '\0' && strcmp(peer, iface) != 0) {
        n += link_stat(peer, "rx_dropped") + link_stat(peer, "tx_dropped");
    }
    return n;
}

/* canbus's end of one node's pair: classic frames, receive times, the drop counter, a
 * large receive queue, non-blocking; its own writes not looped back to it. */
static int open_endpoint(bus_t *b, uint32_t i)
{
    const char *iface = b->o->node[i].iface;
    const unsigned idx = if_nametoindex(iface);
    if (idx == 0u) {
        return fail("no CAN interface", iface, errno);
    }
    const int s = socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
    if (s < 0) {
        return fail("cannot open a CAN socket for", iface, errno);
    }
    b->sock[i] = s;
    const int on = 1;
    const int off = 0;
    const int rcvbuf = RCVBUF_BYTES;
    if (setsockopt(s, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof on) < 0) {
        return fail("cannot have receive timestamps (SO_TIMESTAMPNS) on", iface, errno);
    }
    if (setsockopt(s, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof on) < 0) {
        return fail("cannot count dropped frames (SO_RXQ_OVFL) on", iface, errno);
    }
    /* a node's CAN FD frames reach canbus too, to be counted: a classic bus cannot carry them */
    if (setsockopt(s, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &on, sizeof on) < 0) {
        return fail("cannot receive CAN FD frames (to count them) on", iface, errno);
    }
    if (setsockopt(s, SOL_CAN_RAW, CAN_RAW_LOOPBACK, &off, sizeof off) < 0) {
        return fail("cannot turn loopback off on", iface, errno);
    }
    if (setsockopt(s, SOL_SOCKET, SO_RCVBUFFORCE, &rcvbuf, sizeof rcvbuf) < 0 &&
        setsockopt(s, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof rcvbuf) < 0) {
        return fail("cannot set the receive buffer on", iface, errno);
    }
    struct sockaddr_can addr;
    memset(&addr, 0, sizeof addr);
    addr.can_family = AF_CAN;
    addr.can_ifindex = (int)idx;
    if (bind(s, (struct sockaddr *)&addr, sizeof addr) < 0) {
        return fail("cannot bind to", iface, errno);
    }
    b->pfd[i].fd = s;
    b->pfd[i].events = POLLIN;
    b->link_drops[i] = link_drops(iface);
    return 0;
}

static void note_drops(bus_t *b, uint32_t i, uint32_t now)
{
    const uint32_t lost = now - b->drops_seen[i]; /* the kernel's counter wraps */
    b->drops_seen[i] = now;
    if (lost != 0u) {
        b->stats.node[i].lost += lost;
        fprintf(stderr, "canbus: %s: %lu frame%s lost (canbus's receive queue full)\n",
                b->o->node[i].iface, (unsigned long)lost, lost == 1u ? "" : "s");
    }
}

/* The faults of the command line into the core, their times from t0 (the first frame). */
static void arm_faults(bus_t *b, uint64_t t0)
{
    /* checked by the options: cannot fail */
    (void)canbus_fault_opts_arm(&b->o->faults, &b->core, b->endpoints, t0, b->load,
                                b->load_node);
    b->loads = b->o->faults.loads;
    b->stats.load = b->load;
    b->stats.loads = b->loads;
    b->armed = true;
}

/* SIGUSR2 with --epoch FILE: the faults from the instant FILE holds (read once). */
static int arm_at_epoch(bus_t *b)
{
    const char *path = b->o->faults.epoch_file;
    if (b->armed || path[0] == '\0') {
        return 0;
    }
    unsigned long long t0 = 0u;
    char extra = '\0';
    FILE *f = fopen(path, "r");
    const int got = f != NULL ? fscanf(f, "%llu %c", &t0, &extra) : -1;
    if (f != NULL) {
        (void)fclose(f);
    }
    if (got != 1) {
        fprintf(stderr, "canbus: --epoch %s: not one decimal number of CLOCK_MONOTONIC "
                "nanoseconds\n", path);
        return EXIT_USAGE;
    }
    arm_faults(b, (uint64_t)t0);
    return 0;
}

/* One frame read from node i: queued in the core at the time the kernel received it. */
static void queue_frame(bus_t *b, uint32_t i, struct mmsghdr *m, const struct canfd_frame *cf)
{
    uint64_t t = mono_now();
    for (struct cmsghdr *c = CMSG_FIRSTHDR(&m->msg_hdr); c != NULL;
         c = CMSG_NXTHDR(&m->msg_hdr, c)) {
        if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SO_TIMESTAMPNS) {
            struct timespec ts;
            memcpy(&ts, CMSG_DATA(c), sizeof ts);
            t = (uint64_t)((int64_t)ns_of(&ts) - b->rt_offset);
        } else if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SO_RXQ_OVFL) {
            uint32_t drops;
            memcpy(&drops, CMSG_DATA(c), sizeof drops);
            note_drops(b, i, drops);
        }
    }
    if (!b->armed && b->o->faults.epoch_file[0] == '\0') {
        arm_faults(b, t);
    }
    canbus_frame_t f;
    memset(&f, 0, sizeof f);
    f.ext = (cf->can_id & CAN_EFF_FLAG) != 0u;
    f.rtr = (cf->can_id & CAN_RTR_FLAG) != 0u;
    f.id = cf->can_id & (f.ext ? CAN_EFF_MASK : CAN_SFF_MASK);
    f.dlc = cf->len;
    memcpy(f.data, cf->data, sizeof f.data);
    /* CAN FD and error frames are not a classic controller's: counted as lost; a bus-off
     * node's frames are dropped as SocketCAN drops them (counted by the core) */
    if (m->msg_len != CAN_MTU || (cf->can_id & CAN_ERR_FLAG) != 0u) {
        ++b->stats.node[i].lost;
    } else {
        const fcc_status_t rc = canbus_core_queue(&b->core, i, &f, t);
        b->stats.node[i].lost += rc != FCC_OK && rc != FCC_ERR_IO ? 1u : 0u;
    }
}

/* What node i sent, as much as its queue in the core has room for. */
static int read_node(bus_t *b, uint32_t i)
{
    const uint32_t room = CANBUS_QUEUE_LEN - canbus_core_pending(&b->core, i);
    const unsigned want = room < READ_BATCH ? room : READ_BATCH;
    if (want == 0u) {
        return 0;
    }
    for (unsigned k = 0u; k < want; ++k) {
        b->msgs[k].msg_hdr.msg_controllen = sizeof b->control[k].buf;
        b->msgs[k].msg_hdr.msg_flags = 0;
    }
    const int n = recvmmsg(b->sock[i], b->msgs, want, MSG_DONTWAIT, NULL);
    if (n < 0) {
        return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR
                   ? 0 : fail("cannot receive from", b->o->node[i].iface, errno);
    }
    for (int k = 0; k < n; ++k) {
        queue_frame(b, i, &b->msgs[k], &b->in[k]);
    }
    return 0;
}

/* Every endpoint with frames waiting: one poll() says which (a system call costs several
 * microseconds in a User-Mode Linux guest; a read of an empty endpoint as much). */
static int read_all(bus_t *b)
{
    if (poll(b->pfd, b->endpoints, 0) <= 0) {
        return 0; /* none (or EINTR: the next round looks again) */
    }
    for (uint32_t i = 0u; i < b->endpoints; ++i) {
        if ((b->pfd[i].revents & (POLLIN | POLLERR)) == 0) {
            continue;
        }
        const int rc = read_node(b, i);
        if (rc != 0) {
            return rc;
        }
    }
    return 0;
}

/* A frame that ended: to every other endpoint, then measured. */
static int deliver(bus_t *b, const canbus_done_t *d)
{
    struct can_frame cf;
    memset(&cf, 0, sizeof cf);
    cf.can_id = d->frame.id | (d->frame.ext ? CAN_EFF_FLAG : 0u) |
                (d->frame.rtr ? CAN_RTR_FLAG : 0u);
    cf.can_dlc = d->frame.dlc;
    memcpy(cf.data, d->frame.data, sizeof cf.data);
    for (uint32_t i = 0u; i < b->endpoints; ++i) {
        if (i == d->node) {
            continue;
        }
        if (send(b->sock[i], &cf, sizeof cf, MSG_DONTWAIT) == (ssize_t)sizeof cf) {
            ++b->stats.node[i].received;
        } else if (errno == EAGAIN || errno == EWOULDBLOCK || errno == ENOBUFS) {
            ++b->stats.node[i].lost;
        } else {
            return fail("cannot deliver a frame to", b->o->node[i].iface, errno);
        }
    }
    canbus_stats_delivery(&b->stats, d->t_eof, mono_now());
    canbus_stats_frame(&b->stats, d, b->core.bit_ns);
    return 0;
}

/* data[1] of a state change as can_change_state() fills it: the side(s) whose counter is at
 * the new state (TX, RX or both). */
static uint8_t crtl_bits(const canbus_event_t *e)
{
    const canbus_state_t tx = canbus_confine_state(e->tec, 0u);
    const canbus_state_t rx = canbus_confine_state(0u, e->rec);
    if (e->state == CANBUS_ERROR_ACTIVE) {
        return CAN_ERR_CRTL_ACTIVE;
    }
    const bool passive = e->state == CANBUS_ERROR_PASSIVE;
    uint8_t bits = 0u;
    if (tx >= rx) {
        bits |= passive ? CAN_ERR_CRTL_TX_PASSIVE : CAN_ERR_CRTL_TX_WARNING;
    }
    if (rx >= tx) {
        bits |= passive ? CAN_ERR_CRTL_RX_PASSIVE : CAN_ERR_CRTL_RX_WARNING;
    }
    return bits;
}

/* The error frame a SocketCAN driver gives its sockets for event e (linux/can/error.h): a
 * bus error (CAN_ERR_PROT: the transmitter a bit error, a receiver a form error at the CRC
 * delimiter or a stuff error elsewhere), a state change (CAN_ERR_CRTL), bus-off, restart;
 * the counters in data[6] and data[7] (CAN_ERR_CNT). */
static void error_frame(const canbus_event_t *e, struct can_frame *cf)
{
    memset(cf, 0, sizeof *cf);
    cf->can_id = CAN_ERR_FLAG | CAN_ERR_CNT;
    cf->can_dlc = CAN_ERR_DLC;
    cf->data[6] = (uint8_t)(e->tec > 255u ? 255u : e->tec);
    cf->data[7] = (uint8_t)(e->rec > 255u ? 255u : e->rec);
    const bool at_delim = e->bit + CANBUS_TAIL_BITS == e->frame_bits;
    switch (e->kind) {
    case CANBUS_EV_TX_ERROR:
    case CANBUS_EV_RX_ERROR:
        cf->can_id |= CAN_ERR_PROT | CAN_ERR_BUSERROR;
        cf->data[2] = e->kind == CANBUS_EV_TX_ERROR
                          ? (uint8_t)(CAN_ERR_PROT_BIT | CAN_ERR_PROT_TX)
                          : (uint8_t)(at_delim ? CAN_ERR_PROT_FORM : CAN_ERR_PROT_STUFF);
        cf->data[3] = at_delim ? CAN_ERR_PROT_LOC_CRC_DEL : CAN_ERR_PROT_LOC_UNSPEC;
        break;
    case CANBUS_EV_STATE:
        if (e->state == CANBUS_BUS_OFF) {
            cf->can_id |= CAN_ERR_BUSOFF;
        } else {
            cf->can_id |= CAN_ERR_CRTL;
            cf->data[1] = crtl_bits(e);
        }
        break;
    case CANBUS_EV_RESTARTED:
    default:
        cf->can_id |= CAN_ERR_RESTARTED;
        break;
    }
}

/* The core's fault-confinement events: each to its node's endpoint as an error frame. */
static int deliver_events(bus_t *b)
{
    canbus_event_t e;
    while (canbus_core_event(&b->core, &e)) {
        canbus_stats_event(&b->stats, &b->core, &e);
        if (e.node >= b->endpoints) {
            continue; /* a babbling node or a load: nobody listens */
        }
        struct can_frame cf;
        error_frame(&e, &cf);
        if (send(b->sock[e.node], &cf, sizeof cf, MSG_DONTWAIT) == (ssize_t)sizeof cf) {
            ++b->stats.node[e.node].error_frames;
        } else if (errno == EAGAIN || errno == EWOULDBLOCK || errno == ENOBUFS) {
            ++b->stats.node[e.node].lost;
        } else {
            return fail("cannot deliver an error frame to", b->o->node[e.node].iface, errno);
        }
    }
    return 0;
}

/* Every frame that ended by t, and what fault confinement did meanwhile (the loads' frames
 * released by t queued first: the core takes frames queued for later). */
static int deliver_until(bus_t *b, uint64_t t)
{
    while (canbus_load_feed_one(b->load, b->loads, b->load_node, &b->core, t,
                                &b->stats.load_dropped)) {
    }
    canbus_done_t d;
    while (canbus_core_advance(&b->core, t, &d)) {
        const int rc = deliver_events(b);
        if (rc != 0) {
            return rc;
        }
        const int rc2 = deliver(b, &d);
        if (rc2 != 0) {
            return rc2;
        }
    }
    return deliver_events(b);
}

/* true: t has come; false: a signal came first (EINTR). */
static bool sleep_until(uint64_t t)
{
    const struct timespec ts = {(time_t)(t / NS_PER_S), (long)(t % NS_PER_S)};
    return clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == 0;
}

/* Nothing on the bus: wait for a frame or a signal (blocked between the look at the flags
 * and the wait, so that none is missed), or until a load's next release (NULL: none). */
static void wait_for_frames(bus_t *b, const uint64_t *release)
{
    struct timespec left = {0, 0};
    if (release != NULL) {
        const uint64_t now = mono_now();
        const uint64_t dt = *release > now ? *release - now : 0u;
        left.tv_sec = (time_t)(dt / NS_PER_S);
        left.tv_nsec = (long)(dt % NS_PER_S);
    }
    sigset_t block, old;
    (void)sigemptyset(&block);
    (void)sigaddset(&block, SIGINT);
    (void)sigaddset(&block, SIGTERM);
    (void)sigaddset(&block, SIGUSR1);
    (void)sigaddset(&block, SIGUSR2);
    (void)sigprocmask(SIG_BLOCK, &block, &old);
    if (!g_stop && !g_report && !g_epoch) {
        (void)ppoll(b->pfd, b->endpoints, release != NULL ? &left : NULL, &old);
    }
    (void)sigprocmask(SIG_SETMASK, &old, NULL);
}

/* What the pairs dropped since the start (on neither socket's counter): lost, and said. */
static void count_link_drops(bus_t *b)
{
    for (uint32_t i = 0u; i < b->endpoints; ++i) {
        const uint64_t now = link_drops(b->o->node[i].iface);
        if (now > b->link_drops[i]) {
            b->stats.node[i].lost += now - b->link_drops[i];
            fprintf(stderr, "canbus: %s: %llu frame%s dropped by the pair (ip -s link)\n",
                    b->o->node[i].iface, (unsigned long long)(now - b->link_drops[i]),
                    now - b->link_drops[i] == 1u ? "" : "s");
        }
        b->link_drops[i] = now;
    }
}

static void fill_stats(bus_t *b)
{
    canbus_stats_t *s = &b->stats;
    canbus_stats_core(s, &b->core);
    s->wall_s = (double)(mono_now() - b->t_start) * 1e-9;
    struct rusage ru;
    if (getrusage(RUSAGE_SELF, &ru) == 0) {
        s->cpu_s = (double)(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
                   (double)(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec) * 1e-6;
    }
}

static int report(bus_t *b)
{
    count_link_drops(b);
    fill_stats(b);
    if (canbus_stats_json(&b->stats, stdout) != FCC_OK) {
        return fail("cannot write the statistics to", "stdout", errno != 0 ? errno : EIO);
    }
    return 0;
}

static int run(bus_t *b)
{
    while (!g_stop) {
        const uint64_t now = mono_now();
        if (now - b->offset_at >= OFFSET_EVERY_NS) {
            take_offset(b, now);
        }
        int rc = 0;
        if (g_epoch) {
            g_epoch = 0;
            rc = arm_at_epoch(b);
        }
        if (rc == 0) {
            rc = read_all(b);
        }
        if (rc == 0) {
            rc = deliver_until(b, now);
        }
        /* after the read: a report counts every frame sent before its signal (a vxcan send
         * puts the frame in canbus's queue before it returns), so that `hil run` knows the
         * bus is drained when one reports nothing pending and the next no new frame */
        if (rc == 0 && g_report) {
            g_report = 0;
            rc = report(b);
        }
        if (rc != 0) {
            return rc;
        }
        uint64_t next = 0u;
        bool is_eof = false;
        uint64_t release = 0u;
        const bool core = canbus_core_next(&b->core, &next, &is_eof);
        const bool load = canbus_load_first(b->load, b->loads, &release) >= 0;
        /* a load's release first: read the nodes meanwhile (the loop queues it on waking) */
        if (!core || (load && release < next)) {
            wait_for_frames(b, load ? &release : NULL);
            continue;
        }
        /* woken early by a signal: nothing is due yet, the loop looks again */
        if (sleep_until(next) && is_eof && (rc = deliver_until(b, next)) != 0) {
            return rc;
        }
    }
    return 0;
}

static int start(bus_t *b, const canbus_opts_t *o)
{
    canbus_policy_t policy[CANBUS_NODES_MAX];
    b->o = o;
    b->endpoints = o->nodes;
    const uint32_t nodes = o->nodes + o->faults.babbles + o->faults.loads;
    canbus_stats_init(&b->stats, o->bitrate);
    b->stats.nodes = nodes;
    for (uint32_t i = 0u; i < nodes; ++i) {
        const bool babbler = i >= o->nodes && i < o->nodes + o->faults.babbles;
        const bool load = i >= o->nodes + o->faults.babbles;
        policy[i] = i >= o->nodes ? CANBUS_PRIO : o->node[i].policy;
        b->stats.node[i].iface = load      ? "load"
                                 : babbler ? canbus_babble_names[i - o->nodes]
                                           : o->node[i].iface;
        b->stats.node[i].policy = policy[i];
        b->sock[i] = -1;
    }
    if (canbus_core_init(&b->core, o->bitrate, nodes, policy) != FCC_OK) {
        fprintf(stderr, "canbus: cannot model a bus at %lu bit/s with %lu nodes\n",
                (unsigned long)o->bitrate, (unsigned long)nodes);
        return EXIT_USAGE;
    }
    for (unsigned k = 0u; k < READ_BATCH; ++k) {
        b->iov[k].iov_base = &b->in[k];
        b->iov[k].iov_len = sizeof b->in[k];
        b->msgs[k].msg_hdr.msg_iov = &b->iov[k];
        b->msgs[k].msg_hdr.msg_iovlen = 1;
        b->msgs[k].msg_hdr.msg_control = b->control[k].buf;
    }
    for (uint32_t i = 0u; i < o->nodes; ++i) {
        const int rc = open_endpoint(b, i);
        if (rc != 0) {
            return rc;
        }
    }
    b->t_start = mono_now();
    take_offset(b, b->t_start);
    fprintf(stderr, "canbus: ready: %lu nodes at %lu bit/s\n", (unsigned long)o->nodes,
            (unsigned long)o->bitrate);
    return 0;
}

int main(int argc, char **argv)
{
    canbus_opts_t o;
    char err[256];
    const int parsed = canbus_opts_parse(argc, argv, &o, stdout, err, sizeof err);
    if (parsed != 0) {
        if (parsed < 0) {
            fprintf(stderr, "canbus: %s\n", err);
            return EXIT_USAGE;
        }
        return 0;
    }
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal; /* no SA_RESTART: a sleep or wait returns EINTR */
    (void)sigemptyset(&sa.sa_mask);
    (void)sigaction(SIGINT, &sa, NULL);
    (void)sigaction(SIGTERM, &sa, NULL);
    (void)sigaction(SIGUSR1, &sa, NULL);
    (void)sigaction(SIGUSR2, &sa, NULL);
    bus_t *b = &g_bus;
    int rc = start(b, &o);
    const bool started = rc == 0;
    if (started) {
        rc = run(b);
    }
    if (started) {
        const int rc_report = report(b);
        rc = rc != 0 ? rc : rc_report;
    }
    for (uint32_t i = 0u; i < o.nodes; ++i) {
        if (b->sock[i] >= 0) {
            (void)close(b->sock[i]);
        }
    }
    const uint64_t lost = canbus_stats_lost(&b->stats);
    if (rc == 0 && lost > 0u) {
        fprintf(stderr, "canbus: %llu frame%s lost in all (see \"lost\" per node)\n",
                (unsigned long long)lost, lost == 1u ? "" : "s");
        rc = EXIT_LOST;
    }
    return rc;
}
