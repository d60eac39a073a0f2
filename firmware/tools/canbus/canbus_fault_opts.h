/*
 * canbus_fault_opts.h -- canbus's fault options (--error, --bus-off, --babble):
 * what a scenario's bus faults become on canbus's command line.
 *
 *   --error  [id=ID[-ID]][,node=IFACE][,from=S][,to=S][,every=N][,count=N]
 *            [,bit=N|crc-delim][,superposed=N]
 *   --bus-off IFACE[@S]
 *   --babble id=ID[,dlc=N][,period=S][,from=S][,to=S]
 *
 *   --epoch first-frame|FILE
 *
 * Times S are seconds after the epoch: the first frame canbus carries (the
 * default), or the instant a rig writes to FILE and signals with SIGUSR2
 * (CLOCK_MONOTONIC nanoseconds, one decimal number: its flight's start, so
 * that a scenario's times mean the same whatever the setup took and whatever
 * the nodes sent before).  Faults wait for the epoch.
 */
#ifndef CANBUS_FAULT_OPTS_H
#define CANBUS_FAULT_OPTS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "canbus_core.h"
#include "fcc_opt.h"

#define CANBUS_IFACE_LEN 16u

typedef struct {
    canbus_fault_t fault;           /* times from the first frame; node resolved later */
    char node[CANBUS_IFACE_LEN];    /* the sender's interface, "" any */
} canbus_error_opt_t;

typedef struct {
    canbus_error_opt_t error[CANBUS_FAULTS_MAX];
    uint32_t errors;
    canbus_babble_t babble[CANBUS_BABBLE_MAX]; /* times from the first frame; node: its index
                                                  among the babblers */
    uint32_t babbles;
    char epoch_file[256];                      /* --epoch FILE ("": the first frame) */
} canbus_fault_opts_t;

/* --error / --bus-off / --babble / --epoch VAL into o: FCC_OPT_NOT_MINE for another option. */
fcc_opt_result_t canbus_fault_opt(canbus_fault_opts_t *o, const char *name, const char *val,
                                  char *err, size_t len);

/* The fault's node from its interface name among names[0..n-1]: false (err set) when none. */
fcc_opt_result_t canbus_fault_opts_resolve(canbus_fault_opts_t *o, char (*names)[16],
                                           uint32_t n, char *err, size_t len);

#endif /* CANBUS_FAULT_OPTS_H */
