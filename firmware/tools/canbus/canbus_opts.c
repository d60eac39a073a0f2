/*
 * canbus_opts.c -- command line of canbus (see canbus_opts.h).
 */
#include "canbus_opts.h"

#include <net/if.h>
#include <string.h>

#include "fcc_opt.h"

#define NS_PER_S 1000000000ul
#define BITRATE_MIN 10000ul
#define BITRATE_MAX 1000000ul

void canbus_opts_usage(FILE *out)
{
    fprintf(out,
            "usage: canbus [--bitrate BPS] --node IFACE[:prio|:fifo] --node IFACE[:...] ...\n"
            "              [--error FIELDS] [--bus-off IFACE[@S]] [--babble FIELDS]\n"
            "              [--load FIELDS] [--epoch first-frame|FILE]\n"
            "A classic CAN bus with wire time between SocketCAN endpoints, one a node: each\n"
            "IFACE is canbus's end of a node's pair (vxcan: the node uses the peer).  A frame a\n"
            "node sends waits in its controller's queue, wins arbitration when the bus is idle\n"
            "(lowest identifier first), takes its exact stuffed length on the wire, and reaches\n"
            "every other node at its end of frame (docs/bus-timing.md).\n"
            "options:\n"
            "  --bitrate BPS          125k, 250k, 500k, 1M, or bit/s in %lu..%lu with a whole\n"
            "                         number of nanoseconds a bit (default %u)\n"
            "  --node IFACE[:POLICY]  a node, 2..%u of them; POLICY its transmit queue: prio\n"
            "                         (priority-ordered mailboxes, the default) or fifo\n"
            "  --error FIELDS         error frames on the frames it hits (their senders\n"
            "                         retransmit): id=ID[-ID], node=IFACE (the sender),\n"
            "                         from=S, to=S, every=N (every n-th frame hit), count=N\n"
            "                         (at most), bit=N (0..%u, from SOF) or crc-delim (the\n"
            "                         default), superposed=N (0..6 flag bits; default 0)\n"
            "  --bus-off IFACE[@S]    the node's frames corrupted from S on until it is\n"
            "                         bus-off (TEC > 255); it recovers after 128 x 11\n"
            "                         recessive bits, its queue dropped as SocketCAN does\n"
            "  --babble FIELDS        a babbling node of its own: id=ID, dlc=N (8), period=S\n"
            "                         (0, the default: back to back), from=S, to=S\n"
            "  --load FIELDS          a background node of its own (canbus_load.h): periodic\n"
            "                         8-byte frames filling util=U of the bus (0.5) on\n"
            "                         identifiers spread over id=ID-ID (0x200-0x6FF), phases\n"
            "                         and data from seed=N (0), released from=S to=S\n"
            "  --epoch WHEN           the faults' times S count from the first frame canbus\n"
            "                         carries (first-frame, the default), or from the\n"
            "                         instant in FILE (CLOCK_MONOTONIC ns), read on SIGUSR2\n"
            "  -h, --help             this text\n"
            "Each node receives its controller's error frames as a SocketCAN driver presents\n"
            "them (CAN_ERR_*: bus errors, warning, passive, bus-off, restarted).\n"
            "Prints \"canbus: ready\" on stderr once every endpoint is open; the statistics as\n"
            "one JSON line on stdout on SIGUSR1 and at the end (SIGINT or SIGTERM).\n"
            "Exit: 0 stopped by a signal; 1 socket error (one line); 2 bad command line;\n"
            "3 frames were lost (a node's queue or canbus's receive queue was full, or a\n"
            "delivery failed).\n",
            BITRATE_MIN, BITRATE_MAX, CANBUS_BITRATE_DEFAULT, CANBUS_NODES_MAX, CANBUS_BIT_MAX);
}

static fcc_opt_result_t parse_bitrate(const char *name, const char *val, uint32_t *out,
                                      char *err, size_t len)
{
    static const char *const named[] = {"125k", "250k", "500k", "1M"};
    static const uint32_t rates[] = {125000u, 250000u, 500000u, 1000000u};
    if (val == NULL) {
        return FCC_OPT_NEED_VALUE;
    }
    for (size_t i = 0u; i < sizeof rates / sizeof rates[0]; ++i) {
        if (strcmp(val, named[i]) == 0) {
            *out = rates[i];
            return FCC_OPT_DONE;
        }
    }
    unsigned long bps = 0u;
    if (fcc_opt_uint(name, val, BITRATE_MIN, BITRATE_MAX, &bps, err, len) != FCC_OPT_DONE) {
        return FCC_OPT_ERROR;
    }
    if (NS_PER_S % bps != 0u) {
        return fcc_opt_fail(err, len, "%s: %lu bit/s is not a whole number of nanoseconds a "
                            "bit (125k, 250k, 500k, 1M ...)", name, bps);
    }
    *out = (uint32_t)bps;
    return FCC_OPT_DONE;
}

/* A name the JSON line can carry as it is, of an interface Linux could have. */
static bool plain_name(const char *s, size_t n)
{
    for (size_t i = 0u; i < n; ++i) {
        if (s[i] <= ' ' || s[i] == '"' || s[i] == '\\' || s[i] == '/' || s[i] == 0x7F) {
            return false;
        }
    }
    return n > 0u;
}

static fcc_opt_result_t parse_node(const char *name, const char *val, canbus_opts_t *o,
                                   char *err, size_t len)
{
    if (val == NULL) {
        return FCC_OPT_NEED_VALUE;
    }
    if (o->nodes == CANBUS_NODES_MAX) {
        return fcc_opt_fail(err, len, "%s: at most %u nodes", name, CANBUS_NODES_MAX);
    }
    const char *colon = strchr(val, ':');
    const size_t n = colon != NULL ? (size_t)(colon - val) : strlen(val);
    canbus_node_opt_t *node = &o->node[o->nodes];
    node->policy = CANBUS_PRIO;
    if (colon != NULL) {
        static const char *const policies[] = {"prio", "fifo"};
        int which = 0;
        if (fcc_opt_choice(name, colon + 1, policies, 2, &which, err, len) != FCC_OPT_DONE) {
            return FCC_OPT_ERROR;
        }
        node->policy = which == 1 ? CANBUS_FIFO : CANBUS_PRIO;
    }
    if (n >= IF_NAMESIZE || n >= sizeof o->names[0] || !plain_name(val, n)) {
        return fcc_opt_fail(err, len, "%s: '%.*s' is not an interface name (1..%d characters, "
                            "no spaces, quotes, backslashes or slashes)", name, (int)n, val,
                            IF_NAMESIZE - 1);
    }
    for (uint32_t i = 0u; i < o->nodes; ++i) {
        if (strlen(o->names[i]) == n && strncmp(o->names[i], val, n) == 0) {
            return fcc_opt_fail(err, len, "%s: %s is given twice (one endpoint a node)", name,
                                o->names[i]);
        }
    }
    memcpy(o->names[o->nodes], val, n);
    o->names[o->nodes][n] = '\0';
    node->iface = o->names[o->nodes];
    ++o->nodes;
    return FCC_OPT_DONE;
}

static fcc_opt_result_t apply(void *ctx, const char *name, const char *val, char *err,
                              size_t len)
{
    canbus_opts_t *o = ctx;
    const fcc_opt_result_t fault = canbus_fault_opt(&o->faults, name, val, err, len);
    if (fault != FCC_OPT_NOT_MINE) {
        return fault;
    }
    if (strcmp(name, "--bitrate") == 0) {
        return parse_bitrate(name, val, &o->bitrate, err, len);
    }
    if (strcmp(name, "--node") == 0) {
        return parse_node(name, val, o, err, len);
    }
    return FCC_OPT_NOT_MINE;
}

int canbus_opts_parse(int argc, char **argv, canbus_opts_t *o, FILE *out, char *err,
                      size_t err_len)
{
    memset(o, 0, sizeof *o);
    o->bitrate = CANBUS_BITRATE_DEFAULT;
    for (int i = 1; i < argc; ++i) {
        const char *arg = argv[i];
        if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
            canbus_opts_usage(out);
            return 1;
        }
        if (arg[0] != '-') {
            return fcc_opt_fail(err, err_len, "unexpected argument '%s' (nodes are given as "
                                "--node IFACE; see --help)", arg);
        }
        if (fcc_opt_take(argc, argv, &i, apply, o, "see --help", err, err_len) != FCC_OPT_DONE) {
            return -1;
        }
    }
    if (o->nodes < 2u) {
        return fcc_opt_fail(err, err_len, "a bus needs at least 2 nodes, %u given (--node "
                            "IFACE, repeated; see --help)", o->nodes);
    }
    if (o->nodes + o->faults.babbles + o->faults.loads > CANBUS_NODES_MAX) {
        return fcc_opt_fail(err, err_len, "at most %u nodes and babbling nodes in all",
                            CANBUS_NODES_MAX);
    }
    if (canbus_fault_opts_resolve(&o->faults, o->names, o->nodes, err, err_len) !=
        FCC_OPT_DONE) {
        return -1;
    }
    return 0;
}
