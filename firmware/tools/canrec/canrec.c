/*
 * canrec -- record a SocketCAN interface in the candump log format, a batch
 * of frames per system call or none.
 *
 *   canrec [-o FILE] [-R BYTES] [-r BYTES] [-b N] [-n N] [-w MS] IFACE
 *
 * The lines are candump -l's (canrec_log.h): the kernel's receive time of
 * every frame (SO_TIMESTAMP), the interface, the frame.  Where candump makes
 * two system calls and one wake-up per frame (select, recvmsg), canrec takes
 * the frames from a packet socket's receive ring (canrec_ring.h: the kernel
 * copies each frame into memory canrec reads, no system call while frames
 * are there) or, without CAP_NET_RAW, from a CAN_RAW socket in
 * recvmmsg(MSG_WAITFORONE), everything queued up to -b frames in that one
 * call; the log goes out once per batch (one write of at most -b frames, or of
 * what one -w wait gathered), so a recorder killed with its guest has lost at
 * most the batch in hand: a campaign keeps every flight whose end the
 * recorder read.  On a User-Mode Linux guest, where a system call costs
 * microseconds and each socket a frame is queued to as much again, that is
 * the recorder's whole cost (docs/performance.md).
 *
 * -w MS: after a read that emptied the queue, canrec lets frames gather for MS
 * milliseconds before it reads again (the kernel stamps them on arrival, so the
 * log is the same): in lockstep one wake-up for many steps instead of one or two
 * a step.  The ring or queue (-r) must then hold MS of the bus.
 *
 * The kernel's drop counter (PACKET_STATISTICS for the ring; SO_RXQ_OVFL, and
 * SO_MEMINFO at the end, for the socket) tells whether a frame was lost because
 * the ring or queue was full: one line on stderr when it happens, exit 3 at the
 * end.  SIGINT/SIGTERM: the frames queued at that moment are read too (a stop
 * during a -w wait must not lose the rig's end marker), everything is written,
 * the file closed, exit 0 (or 3).  A receive error (the interface went down) is
 * reported after the frames queued before it are written, exit 1.
 *
 * Exit: 0 recorded; 1 socket or file error; 2 bad command line; 3 frames lost.
 * Host tool (Linux), static storage only (the ring is the kernel's, mapped).
 */
#define _GNU_SOURCE

#include <errno.h>
#include <fcntl.h>
#include <net/if.h>
#include <poll.h>
#include <signal.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>

#include <linux/can.h>
#include <linux/can/raw.h>
#include <linux/sock_diag.h>

#include "canrec_log.h"
#include "canrec_opts.h"
#include "canrec_ring.h"

#define EXIT_IO 1
#define EXIT_USAGE 2
#define EXIT_LOST 3

/* Output block: written when the next line might not fit. */
#define OUT_BLOCK (64u * 1024u)
/* A blocked receive returns this often to look at the stop flag (a signal
 * between the look and the call would otherwise wait for the next frame). */
#define RCV_TIMEOUT_US 200000

typedef union {
    char buf[CMSG_SPACE(sizeof(struct timeval)) + CMSG_SPACE(sizeof(uint32_t))];
    size_t align; /* a cmsghdr's alignment (its first member is a size_t) */
} control_t;

/* The recorder's state: one instance, owned by main(). */
typedef struct {
    const canrec_opts_t *o;
    canrec_ring_t ring;       /* the packet socket's ring, when use_ring */
    bool use_ring;
    int sock;                 /* else: the CAN_RAW socket */
    int out_fd;
    uint64_t frames;
    uint32_t drops_seen;      /* the kernel's counter as last read */
    uint64_t drops;           /* frames lost since the start */
    int rx_errno;             /* a receive error not yet reported (0: none) */
    size_t out_len;
    char out[OUT_BLOCK];
    struct mmsghdr msgs[CANREC_BATCH_MAX];
    struct iovec iov[CANREC_BATCH_MAX];
    struct canfd_frame frames_in[CANREC_BATCH_MAX];
    control_t control[CANREC_BATCH_MAX];
} recorder_t;

static recorder_t g_rec;
static volatile sig_atomic_t g_stop = 0;

static void on_signal(int sig)
{
    (void)sig;
    g_stop = 1;
}

static int fail(const char *what, const char *iface, int err)
{
    fprintf(stderr, "canrec: %s%s%s: %s\n", what, iface ? " " : "", iface ? iface : "",
            strerror(err));
    return EXIT_IO;
}

static int write_all(int fd, const char *p, size_t n)
{
    while (n > 0u) {
        const ssize_t w = write(fd, p, n);
        if (w < 0) {
            if (errno == EINTR) {
                continue;
            }
            return -1;
        }
        p += w;
        n -= (size_t)w;
    }
    return 0;
}

static int flush_out(recorder_t *r)
{
    if (r->out_len == 0u) {
        return 0;
    }
    const int rc = write_all(r->out_fd, r->out, r->out_len);
    r->out_len = 0u;
    return rc;
}

/* The CAN_RAW socket (where no packet ring can be had): every frame of the interface (CAN FD
 * too, when it has them), receive timestamps, the drop counter, the receive buffer asked for. */
static int open_socket(recorder_t *r, unsigned idx)
{
    const canrec_opts_t *o = r->o;
    r->sock = socket(PF_CAN, SOCK_RAW, CAN_RAW);
    if (r->sock < 0) {
        return fail("cannot open a CAN socket for", o->iface, errno);
    }
    const int on = 1;
    /* as candump: FD frames when the interface has them, classic otherwise */
    (void)setsockopt(r->sock, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &on, sizeof on);
    if (setsockopt(r->sock, SOL_SOCKET, SO_TIMESTAMP, &on, sizeof on) < 0) {
        return fail("cannot have receive timestamps (SO_TIMESTAMP) on", o->iface, errno);
    }
    if (setsockopt(r->sock, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof on) < 0) {
        return fail("cannot count dropped frames (SO_RXQ_OVFL) on", o->iface, errno);
    }
    const struct timeval tmo = {0, RCV_TIMEOUT_US};
    if (setsockopt(r->sock, SOL_SOCKET, SO_RCVTIMEO, &tmo, sizeof tmo) < 0) {
        return fail("cannot set the receive timeout on", o->iface, errno);
    }
    if (o->rcvbuf != 0u) {
        const int want = (int)o->rcvbuf;
        /* beyond net.core.rmem_max with CAP_NET_ADMIN, else up to it */
        if (setsockopt(r->sock, SOL_SOCKET, SO_RCVBUFFORCE, &want, sizeof want) < 0 &&
            setsockopt(r->sock, SOL_SOCKET, SO_RCVBUF, &want, sizeof want) < 0) {
            return fail("cannot set the receive buffer on", o->iface, errno);
        }
        int got = 0;
        socklen_t got_len = sizeof got;
        if (getsockopt(r->sock, SOL_SOCKET, SO_RCVBUF, &got, &got_len) == 0 && got / 2 < want) {
            fprintf(stderr, "canrec: note: the receive buffer of %s is %d bytes, not the %d "
                    "asked (net.core.rmem_max)\n", o->iface, got / 2, want);
        }
    }
    struct sockaddr_can addr;
    memset(&addr, 0, sizeof addr);
    addr.can_family = AF_CAN;
    addr.can_ifindex = (int)idx;
    if (bind(r->sock, (struct sockaddr *)&addr, sizeof addr) < 0) {
        return fail("cannot bind to", o->iface, errno);
    }
    for (unsigned i = 0u; i < CANREC_BATCH_MAX; ++i) {
        r->iov[i].iov_base = &r->frames_in[i];
        r->iov[i].iov_len = sizeof r->frames_in[i];
        r->msgs[i].msg_hdr.msg_iov = &r->iov[i];
        r->msgs[i].msg_hdr.msg_iovlen = 1;
        r->msgs[i].msg_hdr.msg_control = r->control[i].buf;
    }
    return 0;
}

/* The ring where a packet socket may be had (CAP_NET_RAW), else the CAN_RAW socket.  The ring
 * records any interface, so it is opened only on a CAN one (as binding CAN_RAW checks). */
static int open_receiver(recorder_t *r)
{
    const canrec_opts_t *o = r->o;
    const unsigned idx = if_nametoindex(o->iface);
    if (idx == 0u) {
        return fail("no CAN interface", o->iface, errno);
    }
    if (!canrec_ring_is_can(o->iface)) {
        return fail("cannot bind to", o->iface, ENODEV);
    }
    const char *what = "";
    int err = 0;
    switch (canrec_ring_open(&r->ring, idx, o->ring, &what, &err)) {
    case CANREC_RING_OK:
        r->use_ring = true;
        return 0;
    case CANREC_RING_UNAVAILABLE:
        return open_socket(r, idx);
    default:
        return fail(what, o->iface, err);
    }
}

/* The frames the kernel dropped since the last count: counted, and said. */
static void count_losses(recorder_t *r, uint32_t lost)
{
    if (lost == 0u) {
        return;
    }
    r->drops += lost;
    fprintf(stderr, "canrec: %s: %lu frame%s lost (receive queue full), %llu in all\n",
            r->o->iface, (unsigned long)lost, lost == 1u ? "" : "s",
            (unsigned long long)r->drops);
}

/* The CAN_RAW socket's drop counter went from r->drops_seen to now. */
static void note_drops(recorder_t *r, uint32_t now)
{
    count_losses(r, canrec_drops_since(r->drops_seen, now));
    r->drops_seen = now;
}

/* One frame received at sec.usec: its line into the output block. */
static int record_line(recorder_t *r, int64_t sec, int64_t usec, const struct canfd_frame *f,
                       bool fd)
{
    if (OUT_BLOCK - r->out_len < CANREC_LINE_MAX && flush_out(r) != 0) {
        return fail("cannot write the log of", r->o->iface, errno);
    }
    const size_t n = canrec_log_line(r->out + r->out_len, OUT_BLOCK - r->out_len, sec, usec,
                                     r->o->iface, f, fd);
    if (n == 0u) {
        fprintf(stderr, "canrec: %s: a frame with the receive time %lld.%06lld cannot be "
                "written\n", r->o->iface, (long long)sec, (long long)usec);
        return EXIT_IO;
    }
    r->out_len += n;
    ++r->frames;
    return 0;
}

static int not_a_frame(const recorder_t *r, unsigned len)
{
    fprintf(stderr, "canrec: %s: a message of %u bytes is not a CAN frame\n", r->o->iface, len);
    return EXIT_IO;
}

/* One message of the CAN_RAW socket: its line into the output block. */
static int record(recorder_t *r, struct mmsghdr *m, const struct canfd_frame *f)
{
    bool fd;
    if (m->msg_len == CANFD_MTU) {
        fd = true;
    } else if (m->msg_len == CAN_MTU) {
        fd = false;
    } else {
        return not_a_frame(r, m->msg_len);
    }
    if ((m->msg_hdr.msg_flags & MSG_CTRUNC) != 0) {
        fprintf(stderr, "canrec: %s: receive timestamp truncated\n", r->o->iface);
        return EXIT_IO;
    }
    struct timeval tv = {0, 0};
    for (struct cmsghdr *c = CMSG_FIRSTHDR(&m->msg_hdr); c != NULL;
         c = CMSG_NXTHDR(&m->msg_hdr, c)) {
        if (c->cmsg_level != SOL_SOCKET) {
            continue;
        }
        if (c->cmsg_type == SO_TIMESTAMP) {
            memcpy(&tv, CMSG_DATA(c), sizeof tv);
        } else if (c->cmsg_type == SO_RXQ_OVFL) {
            uint32_t now;
            memcpy(&now, CMSG_DATA(c), sizeof now);
            note_drops(r, now);
        }
    }
    return record_line(r, (int64_t)tv.tv_sec, (int64_t)tv.tv_usec, f, fd);
}

/* One receive call (flags: MSG_WAITFORONE to wait for the first frame, MSG_DONTWAIT not
 * to wait) and its frames into the output block.  0, with *drained when the call returned
 * fewer frames than it asked for (the queue is empty: a signal or the receive timeout
 * returns none), or the exit status of an error. */
static unsigned batch_size(const recorder_t *r)
{
    unsigned want = (unsigned)r->o->batch;
    if (r->o->count != 0u && r->o->count - r->frames < want) {
        want = (unsigned)(r->o->count - r->frames);
    }
    return want;
}

static int read_batch(recorder_t *r, int flags, bool *drained)
{
    const unsigned want = batch_size(r);
    for (unsigned i = 0u; i < want; ++i) {
        r->msgs[i].msg_hdr.msg_name = NULL;
        r->msgs[i].msg_hdr.msg_namelen = 0;
        r->msgs[i].msg_hdr.msg_controllen = sizeof r->control[i].buf;
        r->msgs[i].msg_hdr.msg_flags = 0;
    }
    const int n = recvmmsg(r->sock, r->msgs, want, flags, NULL);
    if (n < 0 && errno != EINTR && errno != EAGAIN && errno != EWOULDBLOCK) {
        r->rx_errno = errno;
    }
    *drained = n < (int)want;
    for (int i = 0; i < n; ++i) {
        const int rc = record(r, &r->msgs[i], &r->frames_in[i]);
        if (rc != 0) {
            return rc;
        }
    }
    if (n > 0 && flush_out(r) != 0) {
        return fail("cannot write the log of", r->o->iface, errno);
    }
    return 0;
}

/* The ring's counterpart of read_batch: what the ring holds, up to -b frames; with wait, first
 * up to RCV_TIMEOUT_US for one (a socket error -- the interface went down -- ends the wait and
 * is kept for after the frames still in the ring). */
static int read_ring(recorder_t *r, bool wait, bool *drained)
{
    canrec_ring_frame_t f;
    bool ready = canrec_ring_peek(&r->ring, &f);
    if (!ready && wait) {
        struct pollfd p = {r->ring.fd, POLLIN, 0};
        if (poll(&p, 1, RCV_TIMEOUT_US / 1000) > 0 && (p.revents & POLLERR) != 0) {
            r->rx_errno = canrec_ring_error(&r->ring);
        }
        ready = canrec_ring_peek(&r->ring, &f);
    }
    const unsigned want = batch_size(r);
    unsigned n = 0u;
    bool losses = false;
    for (; ready && n < want; ready = n < want && canrec_ring_peek(&r->ring, &f)) {
        if (!f.is_can) {
            return not_a_frame(r, f.len);
        }
        const int rc = record_line(r, f.sec, f.usec, f.frame, f.fd);
        if (rc != 0) {
            return rc;
        }
        losses = losses || f.after_losses;
        canrec_ring_release(&r->ring);
        ++n;
    }
    *drained = n < want;
    uint32_t lost = 0u;
    if (losses && canrec_ring_losses(&r->ring, &lost) == 0) {
        count_losses(r, lost);
    }
    if (n > 0u && flush_out(r) != 0) {
        return fail("cannot write the log of", r->o->iface, errno);
    }
    return 0;
}

/* One read from the ring or the socket (wait: for the first frame). */
static int read_some(recorder_t *r, bool wait, bool *drained)
{
    return r->use_ring ? read_ring(r, wait, drained)
                       : read_batch(r, wait ? MSG_WAITFORONE : MSG_DONTWAIT, drained);
}

/* -w: after a read that emptied the queue, let frames gather for wait_ms (the kernel
 * stamps them as they come, so the log is the same) -- one wake-up for many lockstep
 * steps instead of one or two each.  A signal ends the wait. */
static void let_frames_gather(const recorder_t *r)
{
    const struct timespec gap = {(time_t)(r->o->wait_ms / 1000u),
                                 (long)(r->o->wait_ms % 1000u) * 1000000L};
    (void)nanosleep(&gap, NULL);
}

static bool count_reached(const recorder_t *r)
{
    return r->o->count != 0u && r->frames >= r->o->count;
}

/* What is queued now was on the bus before a stop or a receive error (the rig's end
 * marker among it, when a stop came during a -w wait), so it is read and written too --
 * up to DRAIN_MAX frames, in case the bus never goes quiet. */
#define DRAIN_MAX 65536u

static int drain(recorder_t *r)
{
    const uint64_t limit = r->frames + DRAIN_MAX;
    bool drained = false;
    while (!drained && !count_reached(r) && r->frames < limit) {
        const int rc = read_some(r, false, &drained);
        if (rc != 0) {
            return rc;
        }
    }
    return 0;
}

/* The kernel reports a socket error (ENETDOWN: the interface went down) before the
 * frames still queued -- and clears it -- so those frames are drained first, then
 * the error is reported. */
static int receive_failed(recorder_t *r)
{
    const int err = r->rx_errno;
    r->rx_errno = 0;
    const int rc = drain(r);
    return rc != 0 ? rc : fail("cannot receive from", r->o->iface, err);
}

/* Until a signal, -n frames, or an error. */
static int record_loop(recorder_t *r)
{
    while (!g_stop && !count_reached(r)) {
        bool drained = false;
        const int rc = read_some(r, true, &drained);
        if (rc != 0) {
            return rc;
        }
        if (r->rx_errno != 0) {
            return receive_failed(r);
        }
        if (drained && r->o->wait_ms != 0u && !g_stop) {
            let_frames_gather(r);
        }
    }
    return 0;
}

/* The drop counter as the kernel has it now (frames dropped after the last
 * frame read carry no SO_RXQ_OVFL message); 0 when it cannot say. */
static void final_drops(recorder_t *r)
{
    if (r->use_ring) {
        uint32_t lost = 0u;
        if (canrec_ring_losses(&r->ring, &lost) == 0) {
            count_losses(r, lost);
        }
        return;
    }
#if defined(SO_MEMINFO)
    uint32_t mem[SK_MEMINFO_VARS];
    socklen_t len = sizeof mem;
    memset(mem, 0, sizeof mem);
    if (getsockopt(r->sock, SOL_SOCKET, SO_MEMINFO, mem, &len) == 0 &&
        len > SK_MEMINFO_DROPS * sizeof mem[0]) {
        note_drops(r, mem[SK_MEMINFO_DROPS]);
    }
#else
    (void)r;
#endif
}

int main(int argc, char **argv)
{
    canrec_opts_t o;
    char err[256];
    const int parsed = canrec_opts_parse(argc, argv, &o, stdout, err, sizeof err);
    if (parsed != 0) {
        if (parsed < 0) {
            fprintf(stderr, "canrec: %s\n", err);
            return EXIT_USAGE;
        }
        return 0;
    }
    recorder_t *r = &g_rec;
    r->o = &o;
    r->sock = -1;
    r->out_fd = STDOUT_FILENO;
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;  /* no SA_RESTART: a blocked receive returns EINTR */
    (void)sigemptyset(&sa.sa_mask);
    (void)sigaction(SIGINT, &sa, NULL);
    (void)sigaction(SIGTERM, &sa, NULL);
    r->ring.fd = -1;
    int rc = open_receiver(r);
    if (rc == 0 && o.output != NULL) {
        r->out_fd = open(o.output, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
        if (r->out_fd < 0) {
            rc = fail("cannot write", o.output, errno);
        }
    }
    if (rc == 0) {
        rc = record_loop(r);
    }
    if (rc == 0 && g_stop) {
        rc = drain(r);
    }
    if (rc == 0 && r->rx_errno != 0) {
        rc = fail("cannot receive from", o.iface, r->rx_errno);
    }
    if (r->sock >= 0 || r->use_ring) {
        final_drops(r);
    }
    if (flush_out(r) != 0 && rc == 0) {
        rc = fail("cannot write the log of", o.iface, errno);
    }
    if (r->out_fd != STDOUT_FILENO && r->out_fd >= 0 && close(r->out_fd) != 0 && rc == 0) {
        rc = fail("cannot write", o.output, errno);
    }
    if (r->sock >= 0) {
        (void)close(r->sock);
    }
    canrec_ring_close(&r->ring);
    if (rc == 0 && r->drops > 0u) {
        fprintf(stderr, "canrec: %s: %llu frame%s lost in all: the log is incomplete (a larger "
                "-r, or a recorder that keeps up)\n", o.iface, (unsigned long long)r->drops,
                r->drops == 1u ? "" : "s");
        rc = EXIT_LOST;
    }
    return rc;
}
