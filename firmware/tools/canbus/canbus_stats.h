/*
 * canbus_stats.h -- what canbus measures, and its one JSON line.
 *
 * Per frame that ended on the bus: its response time, from being queued at
 * its sender to its end of frame (the model's times), per identifier; and in
 * wall time how late the process delivered it after the model's end of
 * frame.  Per node: frames sent, received and lost.  Fixed storage: the
 * first CANBUS_IDS_MAX identifiers seen get a histogram each, later ones are
 * counted in ids_untracked.
 */
#ifndef CANBUS_STATS_H
#define CANBUS_STATS_H

#include <stdint.h>
#include <stdio.h>

#include "canbus_core.h"
#include "canbus_hist.h"
#include "canbus_load.h"
#include "fcc_types.h"

#define CANBUS_IDS_MAX 256u
/* Bus-off episodes whose recovery time a node keeps (later ones: counted, the longest kept). */
#define CANBUS_RECOVERIES_MAX 8u

typedef struct {
    uint32_t id;
    bool ext;
    canbus_hist_t response;
} canbus_id_stats_t;

typedef struct {
    const char *iface;
    canbus_policy_t policy;
    uint64_t sent;      /* its frames that ended on the bus */
    uint64_t received;  /* frames delivered to it */
    uint64_t lost;      /* its frames lost before the bus (its queue full) or deliveries to it
                           that failed */
    canbus_confine_t confine;   /* its fault confinement (the core's, copied at a report) */
    uint64_t error_frames;      /* SocketCAN error frames written to it */
    uint64_t recovery_ns[CANBUS_RECOVERIES_MAX]; /* bus-off to recovery, the first ones */
    uint32_t recoveries;
} canbus_node_stats_t;

typedef struct {
    uint32_t bitrate;
    uint64_t frames;          /* ended on the bus */
    uint64_t busy_ns;         /* bus time they took, interframe spaces included */
    canbus_hist_t delivery;   /* wall-clock delivery after the model's end of frame (ns) */
    uint64_t early;           /* deliveries before it (a clock error: never by design) */
    uint64_t late_queued;     /* frames read after an arbitration they should have been in */
    uint64_t pending;         /* frames still queued at the end */
    double wall_s;            /* since the start */
    double cpu_s;             /* the process's user + system time */
    canbus_node_stats_t node[CANBUS_NODES_MAX];
    uint32_t nodes;
    canbus_id_stats_t id[CANBUS_IDS_MAX];
    uint32_t ids;
    uint64_t ids_untracked;   /* frames of identifiers beyond the first CANBUS_IDS_MAX */
    uint64_t error_frames;    /* error frames on the bus (corrupted frames) */
    uint64_t babble_dropped;  /* babbling frames that found their node's queue full */
    uint64_t events_lost;     /* fault-confinement events the core could not keep */
    const canbus_load_t *load; /* the background loads (their streams), NULL: none */
    uint32_t loads;
    uint64_t load_dropped;    /* load frames released while their node's queue was full */
} canbus_stats_t;

void canbus_stats_init(canbus_stats_t *s, uint32_t bitrate);

/* A frame that ended: its response time under its identifier, the sender's count. */
void canbus_stats_frame(canbus_stats_t *s, const canbus_done_t *d, uint64_t bit_ns);

/* Its delivery delivered_ns (wall) after the model's end of frame eof_ns. */
void canbus_stats_delivery(canbus_stats_t *s, uint64_t eof_ns, uint64_t delivered_ns);

/* A bus-off node recovered at recovered_ns, having gone bus-off at bus_off_ns. */
void canbus_stats_recovery(canbus_stats_t *s, uint32_t node, uint64_t bus_off_ns,
                           uint64_t recovered_ns);

/* What the core counts, copied: every node's fault confinement, the frames
 * pending (queued or on the bus), error frames, babbling frames dropped,
 * events lost, frames queued late. */
void canbus_stats_core(canbus_stats_t *s, const canbus_core_t *c);

/* A fault-confinement event of the core: a recovery is counted. */
void canbus_stats_event(canbus_stats_t *s, const canbus_core_t *c, const canbus_event_t *e);

/* Frames lost in all (every node). */
uint64_t canbus_stats_lost(const canbus_stats_t *s);

/* The statistics as one JSON line (docs/bus-timing.md "The wire-time bus").
 * FCC_ERR_IO when out cannot take it. */
fcc_status_t canbus_stats_json(const canbus_stats_t *s, FILE *out);

#endif /* CANBUS_STATS_H */
