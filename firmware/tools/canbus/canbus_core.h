/*
 * canbus_core.h -- a classic CAN bus in time: the nodes' transmit queues,
 * arbitration, and each frame's exact time on the wire (SPEC §8).
 *
 * OS-free: no sockets, no clock.  Time is an input in nanoseconds, so the
 * same core runs in simulated time (deterministic: the same calls give the
 * same results) and in wall time (canbus.c feeds it the kernel's receive
 * times and sleeps until the next end of frame).
 *
 * The model.  Each node has a transmit queue (CANBUS_QUEUE_LEN frames) with
 * the policy of its controller: CANBUS_PRIO offers its highest-priority
 * queued frame to arbitration (priority-ordered mailboxes), CANBUS_FIFO its
 * oldest (then a low-priority frame at the head blocks the node's
 * higher-priority ones: priority inversion).  When the bus is idle and frames
 * are queued, arbitration at that instant picks the lowest arbitration field
 * among the frames the nodes offer (canbus_frame_arbitration(); two nodes
 * offering the same field, which a real bus signals as an error: the lower
 * node index).  The frame starts (SOF) then, ends (the last bit of EOF) after
 * its stuffed length less the interframe space, canbus_frame_bits() - 3 bit
 * times, when every other node receives it and the sender has its
 * confirmation; the bus is idle again 3 bit times later.  A frame queued
 * while the bus is idle and nothing else waits starts at once.
 *
 * Usage: canbus_core_queue() each frame with the time it was queued;
 * canbus_core_advance() to a time: 1 and each frame that ended by then, in
 * order, until 0 (the core is then at that time).  Frames must be queued
 * before the core is advanced past their time: a frame queued with a time
 * before an arbitration the core has already held without it keeps its time
 * (its response time counts the wait) and takes part in the next one; it is
 * counted in `late` (in wall time: the process read it too late).
 * canbus_core_next() says when the core next has something to do.
 */
#ifndef CANBUS_CORE_H
#define CANBUS_CORE_H

#include <stdbool.h>
#include <stdint.h>

#include "canbus_faults.h"
#include "canbus_frame.h"
#include "fcc_types.h"

#define CANBUS_NODES_MAX 16u
#define CANBUS_QUEUE_LEN 64u

typedef enum { CANBUS_PRIO = 0, CANBUS_FIFO = 1 } canbus_policy_t;

#define CANBUS_BABBLE_MAX 4u
#define CANBUS_EVENTS_MAX 1024u

/* What fault confinement did, in time order (canbus_core_event()). */
typedef enum {
    CANBUS_EV_TX_ERROR = 0,  /* node's frame was corrupted (an error frame, it transmitting) */
    CANBUS_EV_RX_ERROR = 1,  /* node received an error frame */
    CANBUS_EV_STATE = 2,     /* node's state changed to `state` (bus-off included) */
    CANBUS_EV_RESTARTED = 3  /* node left bus-off (128 x 11 recessive bits): error-active */
} canbus_event_kind_t;

typedef struct {
    uint64_t t;              /* the error's bit (errors, state changes), the recovery */
    uint32_t node;
    canbus_event_kind_t kind;
    canbus_state_t state;    /* after the event */
    uint32_t tec, rec;       /* after the event */
    uint32_t bit;            /* errors: the bit position in the frame */
    uint32_t id;             /* errors: the frame's identifier */
    uint32_t frame_bits;     /* errors: its length (canbus_frame_bits: CRC delimiter at - 13) */
} canbus_event_t;

/* A frame in a node's queue. */
typedef struct {
    canbus_frame_t frame;
    uint64_t t_queued;
    uint32_t arbitration;
    uint32_t bits;
    uint32_t babble;    /* queued by babbler babble - 1; 0: by the node */
    uint32_t errors;    /* its attempts corrupted so far (then it is retransmitted) */
} canbus_entry_t;

typedef struct {
    canbus_entry_t entry[CANBUS_QUEUE_LEN]; /* in the order queued */
    uint32_t n;
    canbus_policy_t policy;
} canbus_node_t;

/* A frame on the bus, and once it ended, what the nodes see. */
typedef struct {
    canbus_frame_t frame;
    uint32_t node;      /* the sender */
    uint32_t bits;      /* canbus_frame_bits() */
    uint64_t t_queued;  /* queued at the sender (ns) */
    uint64_t t_sof;     /* won arbitration: start of frame */
    uint64_t t_eof;     /* end of frame: received by the others, confirmed to the sender */
} canbus_done_t;

typedef struct {
    uint64_t bit_ns;
    canbus_node_t node[CANBUS_NODES_MAX];
    uint32_t nodes;
    bool busy;          /* a frame is on the bus, before its end of frame */
    canbus_done_t cur;  /* that frame */
    uint64_t idle_at;   /* when not busy: the bus is idle from then (end of interframe space) */
    uint64_t now;
    bool started;       /* some frame has won an arbitration, the latest at last_sof */
    uint64_t last_sof;
    uint64_t late;      /* frames queued with a time before an arbitration held without them */
    /* faults (canbus_faults.h) */
    canbus_confine_t confine[CANBUS_NODES_MAX];
    canbus_fault_t fault[CANBUS_FAULTS_MAX];
    uint32_t fault_seen[CANBUS_FAULTS_MAX];  /* frames it matched */
    uint32_t fault_hits[CANBUS_FAULTS_MAX];  /* errors it caused */
    bool fault_spent[CANBUS_FAULTS_MAX];     /* a forced bus-off done */
    uint32_t faults;
    canbus_babble_t babble[CANBUS_BABBLE_MAX];
    uint64_t babble_next[CANBUS_BABBLE_MAX]; /* its next frame's time; UINT64_MAX: none due */
    uint32_t babbles;
    uint64_t babble_dropped;                 /* its frames that found the node's queue full */
    bool cur_error;                          /* the frame on the bus is corrupted: cur.t_eof is
                                                then its error delimiter's end */
    uint32_t cur_bit;                        /* detected at this bit */
    uint64_t cur_flag_end;                   /* the error flags end (the delimiter starts) */
    uint64_t error_frames;
    canbus_event_t event[CANBUS_EVENTS_MAX]; /* a ring, the oldest at event_first */
    uint32_t event_first, events;
    uint64_t events_lost;                    /* events that found the ring full */
} canbus_core_t;

/* An idle bus at time 0 with nodes (1..CANBUS_NODES_MAX) of the given
 * policies.  bitrate in bit/s, 1e9 a whole multiple of it (a whole number of
 * nanoseconds a bit: 125k, 250k, 500k, 1M ...).  FCC_ERR_ARG: NULL;
 * FCC_ERR_RANGE: a node count, bitrate or policy out of range. */
fcc_status_t canbus_core_init(canbus_core_t *c, uint32_t bitrate, uint32_t nodes,
                              const canbus_policy_t *policy);

/* Frame f queued at node at time t (ns).  FCC_ERR_ARG: NULL, no such node,
 * an invalid frame; FCC_ERR_AGAIN: the node's queue is full (not queued);
 * FCC_ERR_IO: the node is bus-off (dropped, counted in its confine.dropped,
 * as SocketCAN drops it with the carrier off). */
fcc_status_t canbus_core_queue(canbus_core_t *c, uint32_t node, const canbus_frame_t *f,
                               uint64_t t);

/* Frames waiting in node's queue (0 for no such node). */
uint32_t canbus_core_pending(const canbus_core_t *c, uint32_t node);

/* Runs the bus up to time t.  true: a frame ended at or before t, in *out
 * (call again for the next one); false: none did, the core is now at t. */
bool canbus_core_advance(canbus_core_t *c, uint64_t t, canbus_done_t *out);

/* When the core next acts on its own: true with *t and *is_eof (the frame on
 * the bus ends then: advancing to *t needs no frame queued meanwhile), or
 * *is_eof false (arbitration then: the bus goes idle or a frame queued for
 * later becomes pending: queue what came before advancing; with faults also
 * a corrupted frame's error delimiter ending, a babbling node's next frame,
 * a bus-off node's recovery); false: nothing until a frame is queued. */
bool canbus_core_next(const canbus_core_t *c, uint64_t *t, bool *is_eof);

/* ---- faults (canbus_faults.h); without any, the bus above is unchanged ---- */

/* sizeof(canbus_core_t), for a caller that allocates it without this header (ctypes). */
unsigned long canbus_core_size(void);

/* A fault corrupting frames from now on.  FCC_ERR_ARG: NULL or invalid
 * (canbus_fault_valid), a node that does not exist; FCC_ERR_SIZE: CANBUS_FAULTS_MAX. */
fcc_status_t canbus_core_add_fault(canbus_core_t *c, const canbus_fault_t *f);

/* A babbling node (its frames queued by the core at their times).  FCC_ERR_ARG:
 * NULL, no such node, an invalid frame, t_from > t_to; FCC_ERR_SIZE: CANBUS_BABBLE_MAX. */
fcc_status_t canbus_core_add_babble(canbus_core_t *c, const canbus_babble_t *b);

/* The oldest fault-confinement event not taken yet: true with *out. */
bool canbus_core_event(canbus_core_t *c, canbus_event_t *out);

/* A node's counters and state (NULL for no such node). */
const canbus_confine_t *canbus_core_confine(const canbus_core_t *c, uint32_t node);

#endif /* CANBUS_CORE_H */
