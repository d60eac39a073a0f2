/*
 * can_echo -- echo CAN frames: receive on identifier ID, send the same bytes
 * back on ID + 1.  The rig's round-trip baseline (RIG_PING 0x7F0 -> RIG_PONG
 * 0x7F1 by default) for the bus tests and the latency benchmark: it is the
 * smallest C program that goes through the same SocketCAN port as the fcc.
 *
 *   can_echo [-i IFACE] [-r ID] [-n COUNT] [-t IDLE_S] [-q]
 *
 *   can_echo --help
 *
 * Stops after COUNT echoes (0: never), after IDLE_S seconds without a frame
 * (0: never) or on SIGINT/SIGTERM; prints one "ready" line when listening and
 * one summary line at exit.  Exit 0, 1 on an I/O error, 2 on bad arguments.
 */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fcc_socketcan.h"

static volatile sig_atomic_t g_stop = 0;

static void on_signal(int sig)
{
    (void)sig;
    g_stop = 1;
}

typedef struct {
    const char *iface;
    unsigned long rx_id;
    unsigned long count;
    unsigned long idle_s;
    int quiet;
} options_t;

/* What parse_args found: run, print the help (exit 0), or a usage error (exit 2). */
typedef enum { ARGS_RUN = 0, ARGS_HELP = 1, ARGS_BAD = 2 } args_t;

#define CAN_ECHO_USAGE "can_echo [-i IFACE] [-r ID] [-n COUNT] [-t IDLE_S] [-q]"

static void print_help(void)
{
    fputs("usage: " CAN_ECHO_USAGE "\n"
          "Echo CAN frames: receive on ID, send the same bytes back on ID + 1 (the rig's\n"
          "round-trip baseline, through the fcc's own SocketCAN port).\n"
          "  -i IFACE    the CAN interface (default vcan0)\n"
          "  -r ID       the standard identifier to echo, 0..0x7FE (default 0x7F0, RIG_PING)\n"
          "  -n COUNT    stop after COUNT echoes (default 0: never)\n"
          "  -t IDLE_S   stop after IDLE_S seconds without a frame, 0..86400 (default 0: never)\n"
          "  -q          no ready line, no summary line\n"
          "  -h, --help  this text\n"
          "Stops also on SIGINT/SIGTERM. Exit 0, 1 on an I/O error, 2 on bad arguments.\n",
          stdout);
}

static args_t usage_error(const char *what, const char *arg)
{
    fprintf(stderr, "can_echo: %s '%s' (usage: " CAN_ECHO_USAGE ")\n", what, arg);
    return ARGS_BAD;
}

static int parse_ulong(const char *s, unsigned long max, unsigned long *out)
{
    char *end = NULL;
    if (s == NULL || s[0] == '\0' || s[0] == '-') {
        return -1;
    }
    const unsigned long v = strtoul(s, &end, 0);
    if (*end != '\0' || v > max) {
        return -1;
    }
    *out = v;
    return 0;
}

static args_t parse_args(int argc, char **argv, options_t *o)
{
    o->iface = "vcan0";
    o->rx_id = 0x7F0u;
    o->count = 0u;
    o->idle_s = 0u;
    o->quiet = 0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        const char *v = (i + 1 < argc) ? argv[i + 1] : NULL;
        if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            print_help();
            return ARGS_HELP;
        }
        if (strcmp(a, "-q") == 0) {
            o->quiet = 1;
            continue;
        }
        const int takes_value = strcmp(a, "-i") == 0 || strcmp(a, "-r") == 0 ||
                                strcmp(a, "-n") == 0 || strcmp(a, "-t") == 0;
        if (!takes_value) {
            return usage_error("unknown option", a);
        }
        if (v == NULL) {
            return usage_error("a value is missing after", a);
        }
        ++i;
        if (strcmp(a, "-i") == 0) {
            o->iface = v;
        } else if (strcmp(a, "-r") == 0) {
            if (parse_ulong(v, 0x7FEu, &o->rx_id) != 0) {
                return usage_error("-r needs a standard identifier 0..0x7FE, not", v);
            }
        } else if (strcmp(a, "-n") == 0) {
            if (parse_ulong(v, 0xFFFFFFFFu, &o->count) != 0) {
                return usage_error("-n needs a count, not", v);
            }
        } else if (strcmp(a, "-t") == 0) {
            if (parse_ulong(v, 86400u, &o->idle_s) != 0) {
                return usage_error("-t needs seconds 0..86400, not", v);
            }
        } else {
            return usage_error("unknown option", a);
        }
    }
    return ARGS_RUN;
}

/* Echo until done; returns the exit status. */
static int echo_loop(fcc_socketcan_t *port, const options_t *o, unsigned long *echoed)
{
    unsigned long idle_ms = 0u;
    while (!g_stop && (o->count == 0u || *echoed < o->count)) {
        fcc_status_t st = fcc_socketcan_wait(port, 100);
        if (st == FCC_ERR_AGAIN) {
            idle_ms += 100u;
            if (o->idle_s != 0u && idle_ms >= o->idle_s * 1000u) {
                break;
            }
            continue;
        }
        fcc_can_frame_t f;
        while (st == FCC_OK && (st = fcc_socketcan_recv(port, &f)) == FCC_OK) {
            idle_ms = 0u;
            if (f.id != o->rx_id) {
                continue;
            }
            f.id = (uint32_t)o->rx_id + 1u;
            if (fcc_socketcan_send(port, &f) == FCC_OK) {
                ++*echoed;
            }
        }
        if (st != FCC_ERR_AGAIN) {
            fprintf(stderr, "can_echo: receive failed on %s: %s\n", o->iface, fcc_status_str(st));
            return 1;
        }
    }
    return 0;
}

int main(int argc, char **argv)
{
    options_t o;
    const args_t parsed = parse_args(argc, argv, &o);
    if (parsed != ARGS_RUN) {
        return parsed == ARGS_HELP ? 0 : 2;
    }
    fcc_socketcan_t port;
    if (fcc_socketcan_open(&port, o.iface) != FCC_OK) {
        fprintf(stderr, "can_echo: cannot open CAN interface '%s'\n", o.iface);
        return 1;
    }
    const uint32_t id = (uint32_t)o.rx_id;
    if (fcc_socketcan_set_filters(&port, &id, 1u) != FCC_OK) {
        fprintf(stderr, "can_echo: cannot set the receive filter on %s\n", o.iface);
        fcc_socketcan_close(&port);
        return 1;
    }
    (void)signal(SIGINT, on_signal);
    (void)signal(SIGTERM, on_signal);
    if (!o.quiet) {
        printf("can_echo: ready on %s, 0x%03lX -> 0x%03lX\n", o.iface, o.rx_id, o.rx_id + 1u);
        fflush(stdout);
    }
    unsigned long echoed = 0u;
    const int rc = echo_loop(&port, &o, &echoed);
    fcc_can_port_counters_t c;
    (void)fcc_socketcan_counters(&port, &c);
    if (!o.quiet) {
        printf("can_echo: echoed %lu; rx %lu, tx %lu, bus errors %lu, rx overflows %lu, "
               "tx retries %lu, tx dropped %lu\n", echoed, (unsigned long)c.rx_frames,
               (unsigned long)c.tx_frames, (unsigned long)c.bus_errors,
               (unsigned long)c.rx_overflows, (unsigned long)c.tx_retries,
               (unsigned long)c.tx_dropped);
    }
    fcc_socketcan_close(&port);
    return rc;
}
