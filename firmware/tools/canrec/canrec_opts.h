/*
 * canrec_opts.h -- command line of canrec (options as candump's where they
 * mean the same: -r, -n).
 */
#ifndef CANREC_OPTS_H
#define CANREC_OPTS_H

#include <stddef.h>
#include <stdio.h>

/* Frames one read (a recvmmsg() or a pass over the ring) may take: the largest -b. */
#define CANREC_BATCH_MAX 256u
#define CANREC_BATCH_DEFAULT 64u
/* The receive ring (-R): its default and largest size.  The default holds 6,500 frames, 20 ms
 * of the busiest bus a User-Mode Linux guest makes (~330,000 frames/s: a 20 kHz flood in
 * lockstep); larger is dearer there, where each page's first use costs ~35 us. */
#define CANREC_RING_DEFAULT (1024ul * 1024ul)
#define CANREC_RING_MAX (16ul * 1024ul * 1024ul)
/* The longest -w: a gathering wait is a bounded batching interval, not a sleep. */
#define CANREC_WAIT_MAX_MS 100u

typedef struct {
    const char *iface;        /* the CAN interface (one) */
    const char *output;       /* -o FILE, or NULL: stdout */
    unsigned long rcvbuf;     /* -r BYTES: the CAN_RAW socket's receive buffer, 0: the system's */
    unsigned long ring;       /* -R BYTES: the receive ring's size */
    unsigned long batch;      /* -b N: frames per read, 1..CANREC_BATCH_MAX */
    unsigned long count;      /* -n N: stop after N frames, 0: never */
    unsigned long wait_ms;    /* -w MS: after a read that emptied the queue, wait MS; 0: never */
} canrec_opts_t;

/* 0: parsed; 1: --help printed on out; -1: one line (no newline) in err. */
int canrec_opts_parse(int argc, char **argv, canrec_opts_t *opts, FILE *out, char *err,
                      size_t err_len);

void canrec_opts_usage(FILE *out);

#endif /* CANREC_OPTS_H */
