/*
 * sid_replay_opts.h -- command line of sid_replay, turned into firmware
 * configurations (fcc_sid_config_t) with the firmware's own defaults.  The
 * identification options are fcc_opt_sid.h's (the same as fcc's); only the
 * replay's own options (--filter, --mls-only, --fixed-model, the input file)
 * are parsed here.
 */
#ifndef SID_REPLAY_OPTS_H
#define SID_REPLAY_OPTS_H

#include <stdbool.h>
#include <stddef.h>

#include "fcc_sid.h"

typedef struct {
    bool run[3];             /* KF, ZKF, AZKF selected by --filter */
    bool mls_only;           /* --mls-only */
    bool fixed_model;        /* --fixed-model given */
    bool all_rows;           /* --all-rows: every row mode in one pass */
    bool estimates_only;     /* --estimates: t, filter and the estimates only */
    bool binary;             /* --binary: the --estimates rows as binary64 records */
    const char *input;       /* file name, or NULL / "-" for stdin */
    fcc_sid_config_t cfg;    /* shared by the three loops (filter set per loop) */
} sid_opts_t;

/* 0: options parsed; 1: --help printed; -1: one line in err. */
int sid_opts_parse(int argc, char **argv, sid_opts_t *opts, char *err, size_t err_len);

void sid_opts_usage(const char *prog);

#endif /* SID_REPLAY_OPTS_H */
