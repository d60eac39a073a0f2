/*
 * canbus_fault_opts.h -- canbus's fault options (--error, --bus-off, --babble):
 * what a scenario's bus faults become on canbus's command line.
 *
 *   --error  [id=ID[-ID]][,node=IFACE][,from=S][,to=S][,every=N][,count=N]
 *            [,bit=N|crc-delim][,superposed=N]
 *   --bus-off IFACE[@S]
 *   --babble id=ID[,dlc=N][,period=S][,from=S][,to=S]
 *   --load   util=U[,id=ID-ID][,seed=N][,from=S][,to=S]
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
#include "canbus_load.h"
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
    canbus_load_cfg_t load[CANBUS_LOADS_MAX];  /* times from the epoch */
    uint32_t loads;
    char epoch_file[256];                      /* --epoch FILE ("": the first frame) */
} canbus_fault_opts_t;

/* A babbling node's name in the statistics (a load's is "load"). */
extern const char *const canbus_babble_names[CANBUS_BABBLE_MAX];

/* --error / --bus-off / --babble / --load / --epoch VAL into o: FCC_OPT_NOT_MINE for another option. */
fcc_opt_result_t canbus_fault_opt(canbus_fault_opts_t *o, const char *name, const char *val,
                                  char *err, size_t len);

/* The fault's node from its interface name among names[0..n-1]: false (err set) when none. */
fcc_opt_result_t canbus_fault_opts_resolve(canbus_fault_opts_t *o, char (*names)[16],
                                           uint32_t n, char *err, size_t len);

/* n options as name, value pairs (arg[2k], arg[2k+1]) into o, each as
 * canbus_fault_opt() takes it (another option is an error). */
fcc_opt_result_t canbus_fault_opts_pairs(canbus_fault_opts_t *o, const char *const *arg,
                                         uint32_t n, char *err, size_t len);

/* The faults into c (resolved first), their times from t0: the babbling nodes
 * on nodes first_extra.., then the background loads: load[k] made for c's
 * bit time, on node load_node[k] = first_extra + o->babbles + k.  c must
 * have these nodes.  The status of canbus_core_add_fault/add_babble or
 * canbus_load_init (checked by the options: FCC_OK). */
fcc_status_t canbus_fault_opts_arm(const canbus_fault_opts_t *o, canbus_core_t *c,
                                   uint32_t first_extra, uint64_t t0, canbus_load_t *load,
                                   uint32_t *load_node);

#endif /* CANBUS_FAULT_OPTS_H */
