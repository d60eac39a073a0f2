/*
 * canbus_opts.h -- command line of canbus.
 */
#ifndef CANBUS_OPTS_H
#define CANBUS_OPTS_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "canbus_core.h"
#include "canbus_fault_opts.h"

#define CANBUS_BITRATE_DEFAULT 500000u

typedef struct {
    const char *iface;        /* canbus's end of the node's pair (NUL-terminated copy) */
    canbus_policy_t policy;
} canbus_node_opt_t;

typedef struct {
    uint32_t bitrate;                         /* --bitrate */
    canbus_node_opt_t node[CANBUS_NODES_MAX]; /* --node, in the order given */
    uint32_t nodes;
    char names[CANBUS_NODES_MAX][16];         /* the interface names (IF_NAMESIZE) */
    canbus_fault_opts_t faults;               /* --error, --bus-off, --babble */
} canbus_opts_t;

/* 0: parsed; 1: --help printed on out; -1: one line (no newline) in err. */
int canbus_opts_parse(int argc, char **argv, canbus_opts_t *opts, FILE *out, char *err,
                      size_t err_len);

void canbus_opts_usage(FILE *out);

#endif /* CANBUS_OPTS_H */
