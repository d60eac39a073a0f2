/*
 * canrec_opts.c -- command line of canrec (see canrec_opts.h).
 */
#include "canrec_opts.h"

#include <net/if.h>
#include <string.h>

#include "fcc_opt.h"

/* The largest -r: the kernel takes an int (and doubles it). */
#define RCVBUF_MAX 0x3FFFFFFFul

void canrec_opts_usage(FILE *out)
{
    fprintf(out,
            "usage: canrec [options] IFACE\n"
            "Records every frame on the SocketCAN interface IFACE in the candump log format,\n"
            "one line a frame: (SECONDS.MICROSECONDS) IFACE ID#DATA, the kernel's receive time\n"
            "(SO_TIMESTAMP) -- the lines candump -l writes.  Frames are taken from a packet\n"
            "socket's receive ring (AF_PACKET, PACKET_RX_RING: no system call per batch, one\n"
            "copy a frame; needs CAP_NET_RAW), else read in batches from a CAN_RAW socket\n"
            "(recvmmsg), and written in blocks; stops on SIGINT or SIGTERM, after reading what\n"
            "is queued and writing everything out.\n"
            "options:\n"
            "  -o, --output FILE   write the log to FILE (default: stdout, written once per batch)\n"
            "  -R, --ring BYTES    the receive ring's size, 4096..%lu (default %lu)\n"
            "  -r, --rcvbuf BYTES  the CAN_RAW socket's receive buffer, where no ring can be\n"
            "                      had (as candump -r; default: the system's)\n"
            "  -b, --batch N       frames per read, 1..%u (default %u)\n"
            "  -n, --count N       stop after N frames (default: never)\n"
            "  -w, --wait MS       after a read that emptied the queue, let frames gather for\n"
            "                      MS ms, 0..%u (default 0: read as they come); the times\n"
            "                      are the kernel's all the same; the ring (-R) or the\n"
            "                      queue (-r) must hold MS ms of the bus\n"
            "  -h, --help          this text\n"
            "Frames the kernel drops because the ring or the receive queue is full are counted\n"
            "(PACKET_STATISTICS, SO_RXQ_OVFL): one line on stderr as they happen, and exit 3.\n"
            "Exit: 0 recorded; 1 socket or file error (one line); 2 bad command line;\n"
            "3 frames were lost (the log is incomplete).\n",
            CANREC_RING_MAX, CANREC_RING_DEFAULT, CANREC_BATCH_MAX, CANREC_BATCH_DEFAULT,
            CANREC_WAIT_MAX_MS);
}

static int is(const char *name, const char *short_name, const char *long_name)
{
    return strcmp(name, short_name) == 0 || strcmp(name, long_name) == 0;
}

static fcc_opt_result_t apply(void *ctx, const char *name, const char *val, char *err,
                              size_t len)
{
    canrec_opts_t *o = ctx;
    if (is(name, "-o", "--output")) {
        if (val == NULL) {
            return FCC_OPT_NEED_VALUE;
        }
        if (val[0] == '\0') {
            return fcc_opt_fail(err, len, "%s: an empty file name", name);
        }
        o->output = val;
        return FCC_OPT_DONE;
    }
    if (is(name, "-r", "--rcvbuf")) {
        return fcc_opt_uint(name, val, 1u, RCVBUF_MAX, &o->rcvbuf, err, len);
    }
    if (is(name, "-R", "--ring")) {
        return fcc_opt_uint(name, val, 4096u, CANREC_RING_MAX, &o->ring, err, len);
    }
    if (is(name, "-b", "--batch")) {
        return fcc_opt_uint(name, val, 1u, CANREC_BATCH_MAX, &o->batch, err, len);
    }
    if (is(name, "-w", "--wait")) {
        return fcc_opt_uint(name, val, 0u, CANREC_WAIT_MAX_MS, &o->wait_ms, err, len);
    }
    if (is(name, "-n", "--count")) {
        return fcc_opt_uint(name, val, 1u, 0xFFFFFFFFul, &o->count, err, len);
    }
    return FCC_OPT_NOT_MINE;
}

int canrec_opts_parse(int argc, char **argv, canrec_opts_t *o, FILE *out, char *err,
                      size_t err_len)
{
    memset(o, 0, sizeof *o);
    o->batch = CANREC_BATCH_DEFAULT;
    o->ring = CANREC_RING_DEFAULT;
    for (int i = 1; i < argc; ++i) {
        const char *arg = argv[i];
        if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
            canrec_opts_usage(out);
            return 1;
        }
        if (arg[0] != '-') {
            if (o->iface != NULL) {
                return fcc_opt_fail(err, err_len, "records one interface, not '%s' and '%s' "
                                    "(run one canrec per interface)", o->iface, arg);
            }
            if (strlen(arg) >= IF_NAMESIZE) {
                return fcc_opt_fail(err, err_len, "interface name '%s' is longer than %d "
                                    "characters", arg, IF_NAMESIZE - 1);
            }
            o->iface = arg;
            continue;
        }
        if (fcc_opt_take(argc, argv, &i, apply, o, "see --help", err, err_len) != FCC_OPT_DONE) {
            return -1;
        }
    }
    if (o->iface == NULL) {
        return fcc_opt_fail(err, err_len, "no interface given (usage: canrec [options] IFACE; "
                            "see --help)");
    }
    return 0;
}
