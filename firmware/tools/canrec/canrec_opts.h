/*
 * canrec_opts.h -- command line of canrec (options as candump's where they
 * mean the same: -r, -n).
 */
#ifndef CANREC_OPTS_H
#define CANREC_OPTS_H

#include <stddef.h>
#include <stdio.h>

/* Frames one recvmmsg() may return: the largest -b. */
#define CANREC_BATCH_MAX 256u
#define CANREC_BATCH_DEFAULT 64u
/* The longest -w: a gathering wait is a bounded batching interval, not a sleep. */
#define CANREC_WAIT_MAX_MS 100u

typedef struct {
    const char *iface;        /* the CAN interface (one) */
    const char *output;       /* -o FILE, or NULL: stdout */
    unsigned long rcvbuf;     /* -r BYTES: socket receive buffer, 0: the system's default */
    unsigned long batch;      /* -b N: frames per receive call, 1..CANREC_BATCH_MAX */
    unsigned long count;      /* -n N: stop after N frames, 0: never */
    unsigned long wait_ms;    /* -w MS: after a read that emptied the queue, wait MS; 0: never */
} canrec_opts_t;

/* 0: parsed; 1: --help printed on out; -1: one line (no newline) in err. */
int canrec_opts_parse(int argc, char **argv, canrec_opts_t *opts, FILE *out, char *err,
                      size_t err_len);

void canrec_opts_usage(FILE *out);

#endif /* CANREC_OPTS_H */
