/*
 * fcc_cli.h -- the command line of the fcc executable.
 *
 * Every option turns into a field of fcc_node_config_t (the portable
 * configuration) or of the host loop; nothing else reads argv.  The
 * identification options (and their usage text) are fcc_opt_sid.h's, the
 * very code sid_replay uses, with the same meaning and defaults (the
 * firmware's), so a replayed flight and a bus flight can be compared option
 * for option.
 */
#ifndef FCC_CLI_H
#define FCC_CLI_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "fcc_node.h"

typedef struct {
    const char *iface;        /* --iface (vcan0) */
    fcc_node_config_t node;   /* mode, apps, stale limit, both applications */
    double duration_s;        /* --duration: 0 = until a signal or a shutdown frame */
    double status_rate_hz;    /* --status-rate (10); 0 = only at start and exit */
    int rt_priority;          /* --rt-priority: SCHED_FIFO priority, 0 = normal scheduling */
    const char *key_file;     /* --key-file (required): read into node.security.key */
    uint32_t trip;            /* --trip: the session's trip from the launcher; 0 = draw one */
    bool lqg_delay_auto;      /* --lqg-delay auto (the default): node.msl.delay set by the mode */
    bool check_only;          /* --check-args: parse and check, then exit (nothing opened) */
} fcc_cli_t;

/* 0: parsed and checked; 1: nothing to run: --help was asked (usage printed to
 * out) or --check-args found the options valid; -1: one line in err (without
 * the "fcc: " prefix). */
int fcc_cli_parse(int argc, char **argv, fcc_cli_t *cli, char *err, size_t err_len, FILE *out);

void fcc_cli_usage(FILE *out);

#endif /* FCC_CLI_H */
