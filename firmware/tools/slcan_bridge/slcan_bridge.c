/*
 * slcan_bridge -- a CAN interface and an SLCAN serial line on a Unix socket,
 * joined in user space: what slcand + the kernel's slcan + can-gw do for a
 * real serial line, for the Cortex-M4F image under QEMU (its UART0 as
 * `-chardev socket,path=SOCKET`; firmware/port/mps2_an386/README.md, "The
 * line in the rig").  A frame on IFACE is written to the line as its SLCAN
 * line at once, in the bridge's own thread (no kernel work item in between:
 * the slcan line discipline paced frames at 2.5-3.75 ms each); a frame line
 * from the image becomes a frame on IFACE (other sockets there, candump
 * included, see it as every node's frame).
 *
 *   slcan_bridge -i IFACE -u SOCKET [-n QUEUE] [-b BYTES] [-z]
 *
 *   slcan_bridge --help
 *
 * It listens on SOCKET (a new path: an existing file is refused, never
 * replaced), prints "slcan_bridge: ready" once listening, takes one
 * connection (QEMU's; "slcan_bridge: connected"), opens the channel as slcand -o -c -s6 does (C, S6,
 * O; with -z Z2 before O) and bridges until the line closes or SIGINT/SIGTERM.  With -z every
 * line to the image carries the frame's time on IFACE (the kernel's receive
 * stamp, CLOCK_MONOTONIC microseconds, modulo 2^32) as 8 hex digits after
 * its data, the time a CAN controller would stamp it with; the image turns
 * it into its own clock's (README, "Time sync over the line").
 *
 * No frame is lost silently: frames wait for the line in a queue of QUEUE
 * frames (default 256) behind the socket's send buffer of BYTES (default
 * 64 kB, as a pty's); a frame the queue cannot take, a frame the kernel dropped
 * from the bridge's receive queue, or a frame from the image the interface
 * refused ends the bridge with one line naming the loss, exit 3.  Exit 0
 * when the line or a signal ended it (a summary line), 1 on an I/O error
 * (the interface or the socket gone; one line), 2 on bad arguments.
 */
#define _GNU_SOURCE 1 /* accept4, SOCK_CLOEXEC, sigaction under -std=c99 */
#include <errno.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/uio.h>
#include <sys/un.h>
#include <unistd.h>

#include "fcc_slcan.h"
#include "fcc_socketcan.h"
#include "tool_args.h"

#define QUEUE_MAX 4096u
#define QUEUE_DEFAULT 256u
/* A line to the image: the frame's (FCC_SLCAN_FRAME_CHARS, CR included) and the stamp. */
#define LINE_CAP (FCC_SLCAN_FRAME_CHARS + FCC_SLCAN_STAMP_CHARS)
/* The kernel's buffer toward QEMU by default, as a pty's (64 kB): the line stalls for up to
 * seconds when QEMU is starved in a loaded guest, and the lines wait there and in the queue. */
#define LINE_SNDBUF_DEFAULT 65536u
#define LINE_SNDBUF_MAX (1u << 22)
/* Lines handed to the kernel in one sendmsg at most. */
#define FLUSH_LINES 64u
#define CAN_RCVBUF (1 << 20)
#define EXIT_IO 1
#define EXIT_USAGE 2
#define EXIT_LOST 3

/* The command line's words: the error line's, and the help after its usage line. */
static const tool_args_t bridge_args = {
    .prog = "slcan_bridge",
    .usage = "slcan_bridge -i IFACE -u SOCKET [-n QUEUE] [-b BYTES] [-z]",
    .help =
        "Join a CAN interface and an SLCAN line on a Unix socket (QEMU's UART0 as\n"
        "-chardev socket,path=SOCKET): frames on IFACE become SLCAN lines at once,\n"
        "frame lines from the line become frames on IFACE.\n"
        "  -i IFACE    the CAN interface (vcan0, or a vxcan end)\n"
        "  -u SOCKET   the Unix socket to listen on (a new path; one connection)\n"
        "  -n QUEUE    frames that may wait for the line, 1..4096 (default 256)\n"
        "  -b BYTES    the socket's send buffer toward the line (SO_SNDBUF, the kernel's\n"
        "              minimum..4 MiB, default 65536): lines wait there too\n"
        "  -z          each line to the line carries the frame's time on IFACE:\n"
        "              8 hex digits after the data, CLOCK_MONOTONIC us modulo 2^32\n"
        "  -h, --help  this text\n"
        "Exit 0 (the line closed, or SIGINT/SIGTERM), 1 on an I/O error, 2 on bad\n"
        "arguments, 3 when a frame was lost (the queue full, the kernel's receive queue\n"
        "overflowed, the interface refused a frame); one line on stderr names it.\n"};

static volatile sig_atomic_t g_stop = 0;

static void on_signal(int sig)
{
    (void)sig;
    g_stop = 1;
}

typedef struct {
    const char *iface;
    const char *socket_path;
    unsigned long queue;
    unsigned long sndbuf;
    int stamps;
} options_t;

/* The lines waiting for the image (a ring of fixed slots; head is being written). */
typedef struct {
    char line[QUEUE_MAX][LINE_CAP];
    uint8_t len[QUEUE_MAX];
    uint32_t head;
    uint32_t count;
    uint32_t cap;
    uint32_t head_done; /* bytes of the head line already written */
} line_queue_t;

/* What comes from the image: the line being assembled. */
typedef struct {
    char buf[FCC_SLCAN_LINE_MAX];
    size_t len;
    int overlong;
} line_in_t;

typedef struct {
    unsigned long to_image;
    unsigned long from_image;
    unsigned long answers_ok;
    unsigned long answers_error;
    unsigned long lines_bad;
    unsigned long queue_peak;
    unsigned long wakeups; /* poll() returns: a bridge that spins shows here */
} counts_t;

typedef struct {
    fcc_socketcan_t can;
    int listen_fd;
    int line_fd;
    line_queue_t out;
    line_in_t in;
    counts_t n;
    const options_t *opt;
} bridge_t;

/* The options from the command line: run, or the help or a usage error printed (exit 0 or
 * EXIT_USAGE). */
static tool_args_result_t parse_args(int argc, char **argv, options_t *o)
{
    o->iface = NULL;
    o->socket_path = NULL;
    o->queue = QUEUE_DEFAULT;
    o->sndbuf = LINE_SNDBUF_DEFAULT;
    o->stamps = 0;
    const tool_args_opt_t opts[] = {
        {.letter = 'i', .text = &o->iface},
        {.letter = 'u', .text = &o->socket_path},
        {.letter = 'n', .number = &o->queue, .min = 1u, .max = QUEUE_MAX,
         .what = "-n needs a queue length 1..4096, not"},
        {.letter = 'b', .number = &o->sndbuf, .min = 1u, .max = LINE_SNDBUF_MAX,
         .what = "-b needs a buffer size 1..4194304, not"},
        {.letter = 'z', .flag = &o->stamps},
    };
    const tool_args_result_t parsed =
        tool_args_parse(&bridge_args, opts, sizeof opts / sizeof opts[0], argc, argv);
    if (parsed != TOOL_ARGS_RUN) {
        return parsed;
    }
    if (o->iface == NULL) {
        tool_args_usage_error(&bridge_args, "-i IFACE is required", "");
        return TOOL_ARGS_BAD;
    }
    if (o->socket_path == NULL) {
        tool_args_usage_error(&bridge_args, "-u SOCKET is required", "");
        return TOOL_ARGS_BAD;
    }
    if (strlen(o->socket_path) >= sizeof(((struct sockaddr_un *)NULL)->sun_path)) {
        tool_args_usage_error(&bridge_args, "the socket path is too long", o->socket_path);
        return TOOL_ARGS_BAD;
    }
    return TOOL_ARGS_RUN;
}

/* ---- the line's socket -------------------------------------------------------- */

static int listen_on(const char *path)
{
    struct stat st;
    if (lstat(path, &st) == 0) {
        fprintf(stderr, "slcan_bridge: %s exists (the bridge replaces nothing)\n", path);
        return -1;
    }
    const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) {
        fprintf(stderr, "slcan_bridge: cannot make a Unix socket: %s\n", strerror(errno));
        return -1;
    }
    struct sockaddr_un addr;
    memset(&addr, 0, sizeof addr);
    addr.sun_family = AF_UNIX;
    memcpy(addr.sun_path, path, strlen(path));
    if (bind(fd, (struct sockaddr *)&addr, sizeof addr) != 0 || listen(fd, 1) != 0) {
        fprintf(stderr, "slcan_bridge: cannot listen on %s: %s\n", path, strerror(errno));
        (void)close(fd);
        return -1;
    }
    return fd;
}

/* Waits for QEMU's connection (or a signal): the connected descriptor, non-blocking. */
static int accept_line(int listen_fd, unsigned long sndbuf_bytes)
{
    while (!g_stop) {
        struct pollfd p = {listen_fd, POLLIN, 0};
        const int r = poll(&p, 1u, 200);
        if (r < 0 && errno != EINTR) {
            fprintf(stderr, "slcan_bridge: poll: %s\n", strerror(errno));
            return -1;
        }
        if (r <= 0) {
            continue;
        }
        const int fd = accept4(listen_fd, NULL, NULL, SOCK_NONBLOCK | SOCK_CLOEXEC);
        if (fd < 0) {
            fprintf(stderr, "slcan_bridge: accept: %s\n", strerror(errno));
            return -1;
        }
        const int sndbuf = (int)sndbuf_bytes;
        if (setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &sndbuf, sizeof sndbuf) != 0) {
            fprintf(stderr, "slcan_bridge: SO_SNDBUF: %s\n", strerror(errno));
            (void)close(fd);
            return -1;
        }
        return fd;
    }
    return -1;
}

/* ---- toward the image --------------------------------------------------------- */

/* Takes n written bytes off the queue's head. */
static void consume(line_queue_t *q, size_t n)
{
    while (n > 0u) {
        const size_t left = (size_t)q->len[q->head] - q->head_done;
        const size_t take = (n < left) ? n : left;
        q->head_done += (uint32_t)take;
        n -= take;
        if (q->head_done == q->len[q->head]) {
            q->head_done = 0u;
            q->head = (q->head + 1u) % q->cap;
            --q->count;
        }
    }
}

/* Writes the queued lines (up to FLUSH_LINES in one sendmsg) until the socket takes no more:
 * 0, or -1 (the line is gone). */
static int flush_queue(bridge_t *b)
{
    line_queue_t *q = &b->out;
    while (q->count > 0u) {
        struct iovec iov[FLUSH_LINES];
        size_t n = 0u;
        for (; n < FLUSH_LINES && n < q->count; ++n) {
            const uint32_t slot = (q->head + (uint32_t)n) % q->cap;
            const size_t done = (n == 0u) ? q->head_done : 0u;
            iov[n].iov_base = &q->line[slot][done];
            iov[n].iov_len = (size_t)q->len[slot] - done;
        }
        struct msghdr mh;
        memset(&mh, 0, sizeof mh);
        mh.msg_iov = iov;
        mh.msg_iovlen = n;
        const ssize_t w = sendmsg(b->line_fd, &mh, MSG_NOSIGNAL);
        if (w < 0) {
            if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) {
                return 0;
            }
            fprintf(stderr, "slcan_bridge: the line is gone (%s)\n", strerror(errno));
            return -1;
        }
        consume(q, (size_t)w);
    }
    return 0;
}

/* The Z2 stamp's FCC_SLCAN_STAMP_CHARS hex digits (fcc_slcan_parse reads them back). */
static void put_stamp(char *out, uint32_t v)
{
    static const char digits[] = "0123456789ABCDEF";
    for (size_t i = FCC_SLCAN_STAMP_CHARS; i > 0u; --i) {
        out[i - 1u] = digits[v & 0xFu];
        v >>= 4u;
    }
}

/* A line in the queue: 0, or -1 with the loss said (the queue full). */
static int queue_line(bridge_t *b, const char *line, size_t n)
{
    line_queue_t *q = &b->out;
    if (q->count == q->cap) {
        fprintf(stderr, "slcan_bridge: a frame dropped on its way to the image (the queue of %lu "
                        "frames toward the line was full: the line is slower than the bus)\n",
                b->opt->queue);
        return -1;
    }
    const uint32_t slot = (q->head + q->count) % q->cap;
    memcpy(q->line[slot], line, n);
    q->len[slot] = (uint8_t)n;
    ++q->count;
    b->n.queue_peak = (q->count > b->n.queue_peak) ? q->count : b->n.queue_peak;
    return 0;
}

/* One frame from IFACE as its line (stamped with -z): 0, or -1 (lost, said). */
static int frame_to_line(bridge_t *b, const fcc_can_frame_t *f)
{
    char line[LINE_CAP];
    size_t n = 0u;
    if (fcc_slcan_encode(f, false, line, sizeof line, &n) != FCC_OK || n == 0u) {
        fprintf(stderr, "slcan_bridge: cannot encode frame 0x%03lX\n", (unsigned long)f->id);
        return -1;
    }
    if (b->opt->stamps) { /* the stamp before the CR */
        put_stamp(&line[n - 1u], (uint32_t)f->t_us);
        line[n - 1u + FCC_SLCAN_STAMP_CHARS] = (char)FCC_SLCAN_CR;
        n += FCC_SLCAN_STAMP_CHARS;
    }
    ++b->n.to_image;
    return queue_line(b, line, n);
}

/* The frames waiting on IFACE into the queue: 0, or -1 (a loss or an error, said). */
static int from_bus(bridge_t *b)
{
    fcc_socketcan_readable(&b->can);
    fcc_can_frame_t f;
    fcc_status_t st;
    while ((st = fcc_socketcan_recv(&b->can, &f)) == FCC_OK) {
        if (frame_to_line(b, &f) != 0) {
            return -1;
        }
    }
    if (b->can.cnt.rx_overflows != 0u) {
        fprintf(stderr, "slcan_bridge: %lu frames dropped on their way to the image (the "
                        "bridge's receive queue on %s overflowed)\n",
                (unsigned long)b->can.cnt.rx_overflows, b->opt->iface);
        return -1;
    }
    if (st != FCC_ERR_AGAIN) {
        fprintf(stderr, "slcan_bridge: cannot read %s (is it gone?)\n", b->opt->iface);
        return -2;
    }
    return 0;
}

/* ---- from the image ----------------------------------------------------------- */

/* One complete line from the image: a frame goes to IFACE, answers are counted. */
static int line_from_image(bridge_t *b, uint8_t end)
{
    line_in_t *in = &b->in;
    if (end == FCC_SLCAN_BEL) {
        ++b->n.answers_error;
        return 0;
    }
    if (in->overlong) {
        ++b->n.lines_bad;
        return 0;
    }
    if (in->len == 0u) {
        ++b->n.answers_ok;
        return 0;
    }
    fcc_slcan_msg_t m;
    if (fcc_slcan_parse(in->buf, in->len, &m) != FCC_OK || m.cmd != FCC_SLCAN_CMD_FRAME ||
        m.extended) {
        ++b->n.lines_bad; /* an answer with text (V, F ...) or garbage: nothing for the bus */
        return 0;
    }
    ++b->n.from_image;
    if (fcc_socketcan_send(&b->can, &m.frame) != FCC_OK) {
        fprintf(stderr, "slcan_bridge: %s refused frame 0x%03lX from the image (%s)\n",
                b->opt->iface, (unsigned long)m.frame.id,
                b->can.cnt.tx_dropped != 0u ? "its queue stayed full" : "is it gone?");
        return (b->can.cnt.tx_dropped != 0u) ? -1 : -2;
    }
    return 0;
}

/* The bytes waiting on the line: 0, 1 (the line closed), -1 (a loss), -2 (an error). */
static int from_line(bridge_t *b)
{
    uint8_t buf[512];
    const ssize_t r = recv(b->line_fd, buf, sizeof buf, 0);
    if (r == 0) {
        return 1;
    }
    if (r < 0) {
        if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) {
            return 0;
        }
        fprintf(stderr, "slcan_bridge: the line is gone (%s)\n", strerror(errno));
        return -2;
    }
    line_in_t *in = &b->in;
    for (ssize_t i = 0; i < r; ++i) {
        const uint8_t c = buf[i];
        if (c == FCC_SLCAN_CR || c == FCC_SLCAN_BEL) {
            const int st = line_from_image(b, c);
            in->len = 0u;
            in->overlong = 0;
            if (st != 0) {
                return st;
            }
        } else if (c == (uint8_t)'\n' && in->len == 0u) {
            continue; /* an LF after a CR */
        } else if (in->len < sizeof in->buf) {
            in->buf[in->len++] = (char)c;
        } else {
            in->overlong = 1;
        }
    }
    return 0;
}

/* ---- the loop ----------------------------------------------------------------- */

static int open_channel(bridge_t *b)
{
    static const char open_cmds[] = "\r\r\rC\rS6\rO\r"; /* slcand -o -c -s6 */
    static const char open_stamped[] = "\r\r\rC\rS6\rZ2\rO\r";
    return b->opt->stamps ? queue_line(b, open_stamped, sizeof open_stamped - 1u)
                          : queue_line(b, open_cmds, sizeof open_cmds - 1u);
}

/* Bridges until the line closes or a signal: the exit status. */
static int bridge_loop(bridge_t *b)
{
    if (open_channel(b) != 0 || flush_queue(b) != 0) {
        return EXIT_IO;
    }
    while (!g_stop) {
        struct pollfd p[2] = {{b->can.fd, POLLIN, 0},
                              {b->line_fd, (short)(POLLIN | (b->out.count > 0u ? POLLOUT : 0)), 0}};
        const int r = poll(p, 2u, 500);
        ++b->n.wakeups;
        if (r < 0) {
            if (errno == EINTR) {
                continue;
            }
            fprintf(stderr, "slcan_bridge: poll: %s\n", strerror(errno));
            return EXIT_IO;
        }
        int st = 0;
        if ((p[1].revents & (POLLIN | POLLHUP | POLLERR)) != 0) {
            st = from_line(b);
            if (st == 1) {
                return 0; /* QEMU closed the line: the session is over */
            }
        }
        if (st == 0 && (p[0].revents & (POLLIN | POLLERR | POLLHUP | POLLNVAL)) != 0) {
            st = from_bus(b);
        }
        if (st == 0 && flush_queue(b) != 0) {
            st = -2;
        }
        if (st != 0) {
            return (st == -1) ? EXIT_LOST : EXIT_IO;
        }
    }
    return 0;
}

static void summary(const bridge_t *b, int status)
{
    struct rusage ru;
    memset(&ru, 0, sizeof ru);
    const unsigned long cpu_ms = (getrusage(RUSAGE_SELF, &ru) == 0)
        ? (unsigned long)(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) * 1000u +
              (unsigned long)(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec) / 1000u
        : 0u;
    fprintf(stderr, "slcan_bridge: summary to_image=%lu from_image=%lu answers_ok=%lu "
                    "answers_error=%lu lines_bad=%lu queue_peak=%lu rx_ignored=%lu wakeups=%lu "
                    "cpu_ms=%lu exit=%d\n",
            b->n.to_image, b->n.from_image, b->n.answers_ok, b->n.answers_error, b->n.lines_bad,
            b->n.queue_peak, (unsigned long)b->can.cnt.rx_ignored, b->n.wakeups, cpu_ms, status);
}

static int run(bridge_t *b)
{
    if (fcc_socketcan_open(&b->can, b->opt->iface) != FCC_OK) {
        fprintf(stderr, "slcan_bridge: cannot open CAN interface %s\n", b->opt->iface);
        return EXIT_IO;
    }
    if (fcc_socketcan_set_rcvbuf(&b->can, CAN_RCVBUF) != FCC_OK) {
        fprintf(stderr, "slcan_bridge: cannot size %s's receive queue\n", b->opt->iface);
        fcc_socketcan_close(&b->can);
        return EXIT_IO;
    }
    b->listen_fd = listen_on(b->opt->socket_path);
    int status = EXIT_IO;
    if (b->listen_fd >= 0) {
        fputs("slcan_bridge: ready\n", stdout);
        status = (fflush(stdout) == 0) ? 0 : EXIT_IO;
        b->line_fd = (status == 0) ? accept_line(b->listen_fd, b->opt->sndbuf) : -1;
        if (b->line_fd >= 0) {
            fputs("slcan_bridge: connected\n", stdout);
            status = (fflush(stdout) == 0) ? bridge_loop(b) : EXIT_IO;
            (void)close(b->line_fd);
        } else if (!g_stop) {
            status = EXIT_IO;
        }
        (void)close(b->listen_fd);
        (void)unlink(b->opt->socket_path);
    }
    fcc_socketcan_close(&b->can);
    return status;
}

int main(int argc, char **argv)
{
    options_t opt;
    const tool_args_result_t a = parse_args(argc, argv, &opt);
    if (a != TOOL_ARGS_RUN) {
        return (a == TOOL_ARGS_HELP) ? 0 : EXIT_USAGE;
    }
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    if (sigaction(SIGINT, &sa, NULL) != 0 || sigaction(SIGTERM, &sa, NULL) != 0) {
        fprintf(stderr, "slcan_bridge: cannot handle signals\n");
        return EXIT_IO;
    }
    static bridge_t bridge; /* ~150 kB of queue: main's one instance, off the stack */
    bridge_t *b = &bridge;
    memset(b, 0, sizeof *b);
    b->opt = &opt;
    b->line_fd = -1;
    b->listen_fd = -1;
    b->out.cap = (uint32_t)opt.queue;
    const int status = run(b);
    summary(b, status);
    return status;
}
