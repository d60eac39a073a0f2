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

#include "fcc_socketcan.h"
#include "tool_args.h"

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

/* The command line's words: the error line's, and the help after its usage line. */
static const tool_args_t can_echo_args = {
    .prog = "can_echo",
    .usage = "can_echo [-i IFACE] [-r ID] [-n COUNT] [-t IDLE_S] [-q]",
    .help =
        "Echo CAN frames: receive on ID, send the same bytes back on ID + 1 (the rig's\n"
        "round-trip baseline, through the fcc's own SocketCAN port).\n"
        "  -i IFACE    the CAN interface (default vcan0)\n"
        "  -r ID       the standard identifier to echo, 0..0x7FE (default 0x7F0, RIG_PING)\n"
        "  -n COUNT    stop after COUNT echoes (default 0: never)\n"
        "  -t IDLE_S   stop after IDLE_S seconds without a frame, 0..86400 (default 0: never)\n"
        "  -q          no ready line, no summary line\n"
        "  -h, --help  this text\n"
        "Stops also on SIGINT/SIGTERM. Exit 0, 1 on an I/O error, 2 on bad arguments.\n"};

/* The options from the command line: run, or the help or a usage error printed (exit 0 or
 * 2). */
static tool_args_result_t parse_args(int argc, char **argv, options_t *o)
{
    o->iface = "vcan0";
    o->rx_id = 0x7F0u;
    o->count = 0u;
    o->idle_s = 0u;
    o->quiet = 0;
    const tool_args_opt_t opts[] = {
        {.letter = 'i', .text = &o->iface},
        {.letter = 'r', .number = &o->rx_id, .min = 0u, .max = 0x7FEu,
         .what = "-r needs a standard identifier 0..0x7FE, not"},
        {.letter = 'n', .number = &o->count, .min = 0u, .max = 0xFFFFFFFFu,
         .what = "-n needs a count, not"},
        {.letter = 't', .number = &o->idle_s, .min = 0u, .max = 86400u,
         .what = "-t needs seconds 0..86400, not"},
        {.letter = 'q', .flag = &o->quiet},
    };
    return tool_args_parse(&can_echo_args, opts, sizeof opts / sizeof opts[0], argc, argv);
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
    const tool_args_result_t parsed = parse_args(argc, argv, &o);
    if (parsed != TOOL_ARGS_RUN) {
        return parsed == TOOL_ARGS_HELP ? 0 : 2;
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
