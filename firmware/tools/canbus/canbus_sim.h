/*
 * canbus_sim.h -- the bus model in simulated time, for the lockstep rig
 * ("one model, two time bases", issue 35 item 2): the same core as the
 * realtime canbus process (canbus_core), its statistics (canbus_stats) and
 * background load nodes (canbus_load), driven by calls instead of sockets and
 * a clock.  hil.rig.simbus loads it as a shared library (ctypes).
 *
 * Usage: canbus_sim_init() with the nodes' policies and the background
 * nodes (they get the indices after the caller's), or canbus_sim_setup()
 * with canbus's fault options too (the realtime process's own builder,
 * canbus_fault_opts.c: error frames, bus-off, babbling nodes, loads); then, in time order,
 * canbus_sim_queue() a node's frames at the time it queues them and
 * canbus_sim_run() to a time: the frames of the other nodes (not the load's)
 * that ended by then, in order, each with its end of frame.  The load's
 * frames are queued as they are released, before the core passes their time,
 * so a call's result depends only on the calls before it (deterministic).
 * canbus_sim_json() writes the statistics as canbus's JSON line, with the
 * load's streams and drops added.  Simulated time in nanoseconds; no clock,
 * no sockets, no dynamic memory.
 */
#ifndef CANBUS_SIM_H
#define CANBUS_SIM_H

#include <stddef.h>
#include <stdint.h>

#include "canbus_core.h"
#include "canbus_fault_opts.h"
#include "canbus_load.h"
#include "canbus_stats.h"
#include "fcc_types.h"

#define CANBUS_SIM_LOADS_MAX CANBUS_LOADS_MAX
#define CANBUS_SIM_WORST_MAX 32u
/* sizeof (struct can_frame) of Linux SocketCAN: can_id (host order, flags in the top 3 bits),
 * len, 3 bytes of padding, 8 data bytes */
#define CANBUS_SIM_RAW_LEN 16u

typedef struct {
    canbus_core_t core;
    canbus_stats_t stats;
    canbus_load_t load[CANBUS_SIM_LOADS_MAX];
    uint32_t load_node[CANBUS_SIM_LOADS_MAX];
    uint32_t loads;
    uint32_t nodes;          /* the nodes the caller named (the loads come after them) */
    canbus_fault_opts_t faults;              /* canbus_sim_setup()'s options */
    char names[CANBUS_NODES_MAX][16];        /* the caller's nodes' names, for the options */
    canbus_policy_t policy[CANBUS_NODES_MAX];
    uint32_t worst_id[CANBUS_SIM_WORST_MAX];  /* canbus_sim_worst() */
    uint32_t worst_ids;
    uint32_t sim_node, fcc_node;  /* canbus_sim_roles() */
    uint32_t last_id;
    uint64_t compute_ns;
} canbus_sim_t;

/* One lockstep exchange of canbus_sim_steps(): in, where its frames are in the
 * raw buffer; out, what the model made of them. */
typedef struct {
    uint64_t t;           /* the step's instant (ns): the bus runs to it, then the inputs are queued */
    uint64_t horizon;     /* the inputs are complete at the latest then (an overloaded bus) */
    uint32_t inputs_at;   /* the simulator's frames: raw frames inputs_at .. + inputs - 1 */
    uint32_t inputs;
    uint32_t answer_at;   /* fcc's answer, queued at t_in + compute: answer_at .. + answer - 1 */
    uint32_t answer;
    uint64_t t_in;        /* out: when the inputs were complete (horizon: not by then; t: none) */
    uint32_t queued;      /* out: the inputs (last_id's frames not counted) that were queued */
    uint32_t answered;    /* out: the answer's frames that were queued */
} canbus_sim_step_t;

/* sizeof (canbus_sim_t): the caller allocates it (ctypes). */
size_t canbus_sim_size(void);

/* An idle bus at time 0 with `nodes` nodes of the given policies, named
 * (the statistics' "iface"; the strings must outlive the model), and after
 * them a priority-queued background node per load[0..loads-1], named
 * "load" (all nodes made by canbus_core_init(), so that everything the core
 * keeps per node starts as for the caller's).  The status of
 * canbus_core_init() or canbus_load_init(); FCC_ERR_ARG for a NULL name;
 * FCC_ERR_SIZE: more than CANBUS_SIM_LOADS_MAX loads or CANBUS_NODES_MAX
 * nodes in all. */
fcc_status_t canbus_sim_init(canbus_sim_t *s, uint32_t bitrate, uint32_t nodes,
                             const canbus_policy_t *policy, const char *const *name,
                             const canbus_load_cfg_t *load, uint32_t loads);

/* canbus_sim_init() and the bus faults of canbus's command line
 * (canbus_fault_opts.h: --error, --bus-off, --babble, --load), opts pairs of
 * option name and value in opt[0..2*opts-1], a node named as in `name`,
 * times from 0: the same builder as the realtime process's.  Their nodes
 * (babbling, then loads) come after the loads of `load`.  FCC_ERR_ARG with
 * one line in err (len bytes) for an option refused; FCC_ERR_SIZE also when
 * the loads in all exceed CANBUS_SIM_LOADS_MAX.  The core's fault
 * confinement is in the statistics (canbus_sim_json); nobody receives
 * SocketCAN error frames (the caller's nodes are not sockets). */
fcc_status_t canbus_sim_setup(canbus_sim_t *s, uint32_t bitrate, uint32_t nodes,
                              const canbus_policy_t *policy, const char *const *name,
                              const canbus_load_cfg_t *load, uint32_t loads,
                              const char *const *opt, uint32_t opts, char *err, size_t len);

/* n frames queued at node at time t: how many were (the first that does not
 * fit, a full queue or an invalid frame, and those after it are lost, counted
 * as the node's; frames of a bus-off node count as queued: the core drops them,
 * as SocketCAN does with the carrier off).  worst (NULL: none) marks the frames that take their
 * worst-case length, SPEC §8's g + 8n + 13 + floor((g + 8n - 1)/4) bits,
 * instead of their actual bits' (a frame whose bits the run does not
 * determine, e.g. an authenticator under a random session key: the model's
 * times then do not depend on them). */
uint32_t canbus_sim_queue(canbus_sim_t *s, uint32_t node, const canbus_frame_t *f, uint32_t n,
                          uint64_t t, const uint8_t *worst);

/* The same for n SocketCAN frames (struct can_frame, CANBUS_SIM_RAW_LEN bytes
 * each, back to back), each taking its worst-case length when its identifier
 * is one given to canbus_sim_worst(): one call for a node's frames of a step. */
uint32_t canbus_sim_queue_raw(canbus_sim_t *s, uint32_t node, const uint8_t *raw, uint32_t n,
                              uint64_t t);

/* The 11-bit identifiers whose frames canbus_sim_queue_raw() queues at their
 * worst-case length (replacing the earlier set).  FCC_ERR_SIZE: more than
 * CANBUS_SIM_WORST_MAX. */
fcc_status_t canbus_sim_worst(canbus_sim_t *s, const uint32_t *id, uint32_t n);

/* Runs the bus up to time t.  The frames of the caller's nodes that ended
 * then, at most max of them, in *out, in order: max returned means the core
 * stopped at the last one's end of frame (call again for more).  With
 * count > 0 it also stops at the end of frame of the count-th frame of node
 * queued at tq (*seen: how many of those ended; NULL when count is 0), so
 * that a node's reaction to them can be queued then. */
uint32_t canbus_sim_run(canbus_sim_t *s, uint64_t t, canbus_done_t *out, uint32_t max,
                        uint32_t node, uint64_t tq, uint32_t count, uint32_t *seen);

/* The nodes of canbus_sim_steps(): the simulator's (its frames with can_id
 * last_id, SocketCAN's 32 bits, are queued after the others and not waited
 * for: the lowest priority, nothing fcc steps on) and fcc's, which answers
 * compute_ns after its inputs.  FCC_ERR_ARG: no such node. */
fcc_status_t canbus_sim_roles(canbus_sim_t *s, uint32_t sim, uint32_t fcc, uint32_t last_id,
                              uint64_t compute_ns);

/* Lockstep exchanges, each as the rig makes it one call at a time: the bus
 * runs to step->t; the simulator's frames other than last_id's are queued at
 * t (canbus_sim_queue_raw(), what does not fit lost), then last_id's; the bus
 * runs until as many of the simulator's frames queued at t as were queued
 * ended (t_in: the last one's end of frame), or to the horizon (t_in then the
 * horizon; t when none was queued); fcc's answer is queued at t_in + compute.
 * raw: raws SocketCAN frames (CANBUS_SIM_RAW_LEN bytes each).  The frames of
 * fcc that ended meanwhile, in order, in out[0..*reported-1] (out NULL: none
 * handed out).  FCC_ERR_ARG: NULL or a step's frames outside raw (no step
 * run); FCC_ERR_SIZE: more than max of them ended (the steps all ran, the
 * rest not handed out). */
fcc_status_t canbus_sim_steps(canbus_sim_t *s, canbus_sim_step_t *step, uint32_t n,
                              const uint8_t *raw, uint32_t raws, canbus_done_t *out,
                              uint32_t max, uint32_t *reported);

/* Frames waiting at node, or on the bus from it. */
uint32_t canbus_sim_pending(const canbus_sim_t *s, uint32_t node);

/* The statistics as canbus_stats_json() writes them (the loads' streams
 * among them, "load_streams": [{"id", "period_ns"}...]).  wall_s is
 * the simulated time (so "load" is the bus's load over it), cpu_s 0.
 * FCC_ERR_IO: the file cannot be written. */
fcc_status_t canbus_sim_json(canbus_sim_t *s, const char *path);

#endif /* CANBUS_SIM_H */
