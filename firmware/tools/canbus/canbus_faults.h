/*
 * canbus_faults.h -- bus faults for the model: error frames on chosen frames,
 * fault confinement per node (ISO 11898-1 clause 12, SPEC §8), a babbling
 * node.  OS-free, no clock: times are the core's nanoseconds.
 *
 * An error frame.  A fault hits a frame that starts (wins arbitration) in
 * its window, of its identifiers and sender: the bus is disturbed at bit
 * `bit` of the frame (counted from SOF = 0 on the wire, stuff bits
 * included) and every node detects it there (the transmitter a bit error,
 * the receivers a stuff or form error).  From there the bus carries:
 *
 *   the error flag            6 bits (dominant from an error-active node)
 *   superposed flags          0..6 bits (`superposed`: 0 when every node
 *                             detects the error at the same bit, as here; up
 *                             to 6 when some see it only as the flag's stuff
 *                             violation, ISO 11898-1 10.4.4.2)
 *   the error delimiter       8 recessive bits
 *   the interframe space      3 bits
 *
 * so a corrupted frame that started at s leaves the bus idle at
 *   s + (bit + 1 + 6 + superposed + 8 + 3) tau_bit
 * and its sender retransmits it automatically: it stays in its queue with
 * its queued time and takes part in that arbitration like any frame (a node
 * that is error-passive waits 8 more bits, "suspend transmission", after
 * each frame it transmitted, ISO 11898-1 10.4.6.4).  The default position is
 * the CRC delimiter (a form error: bit = the frame's stuffed length, its
 * bits less 13).
 *
 * Fault confinement, per node: the transmitter's TEC +8 for each error of
 * its frame, every receiver's REC +1; a successful transmission TEC -1, a
 * successful reception REC -1 (a REC above 127 goes back to 127).  The
 * state: warning at 96 (as Linux reports it), error-passive at 128 (TEC or
 * REC), bus-off when TEC exceeds 255 (the 32nd consecutive error of its
 * frames).  A bus-off node sends nothing; it leaves bus-off after 128
 * occurrences of 11 consecutive recessive bits on the bus (every 11 bits of
 * a recessive run count once; a run begins after an error flag or at a
 * frame's ACK delimiter and ends at the next SOF), with TEC = REC = 0.
 *
 * Its queue is dropped at bus-off, and frames it queues while bus-off are
 * refused: what a Linux SocketCAN node does.  can_bus_off() turns the
 * carrier off (the link watch resets the interface's qdisc, dropping what
 * waits there, and it drops what is sent until the carrier is back);
 * can_restart() (restart-ms, or the controller's own recovery) flushes the
 * frame in the controller's transmit buffer (can_flush_echo_skb) and sends
 * CAN_ERR_RESTARTED (drivers/net/can/dev/dev.c).
 */
#ifndef CANBUS_FAULTS_H
#define CANBUS_FAULTS_H

#include <stdbool.h>
#include <stdint.h>

#include "canbus_frame.h"

#define CANBUS_FAULTS_MAX 16u
#define CANBUS_ANY_NODE 0xFFFFFFFFu
/* Error position: the frame's CRC delimiter. */
#define CANBUS_BIT_CRC_DELIM 0xFFFFFFFFu
/* An explicit position must lie inside every frame: before the shortest frame's last EOF
 * bit (an 11-bit frame of no data and no stuff bits: SOF..EOF = 44 bits). */
#define CANBUS_BIT_MAX 42u
#define CANBUS_FLAG_BITS 6u
#define CANBUS_SUPERPOSED_MAX 6u
#define CANBUS_DELIM_BITS 8u
/* A frame's recessive tail from its ACK delimiter: 1 + EOF 7 (+ IFS 3 = 11). */
#define CANBUS_ACK_DELIM_EOF_BITS 8u
#define CANBUS_SUSPEND_BITS 8u
#define CANBUS_WARNING_LIMIT 96u
#define CANBUS_PASSIVE_LIMIT 128u
#define CANBUS_BUSOFF_LIMIT 255u
#define CANBUS_RECOVERY_RUNS 128u
#define CANBUS_RECOVERY_RUN_BITS 11u

typedef enum {
    CANBUS_ERROR_ACTIVE = 0,
    CANBUS_ERROR_WARNING = 1,
    CANBUS_ERROR_PASSIVE = 2,
    CANBUS_BUS_OFF = 3
} canbus_state_t;

/* A fault that corrupts frames. */
typedef struct {
    uint32_t id_min, id_max;  /* identifiers hit, inclusive (11 or 29 bits alike) */
    uint32_t node;            /* only this sender's frames, or CANBUS_ANY_NODE */
    uint64_t t_from, t_to;    /* frames starting in [t_from, t_to) ns */
    uint32_t every;           /* every n-th frame matching (1: each attempt, retransmissions
                                 too; n > 1: frames, a retransmission is not hit again) */
    uint32_t count;           /* at most this many errors (0: no limit) */
    uint32_t bit;             /* 0..CANBUS_BIT_MAX or CANBUS_BIT_CRC_DELIM */
    uint32_t superposed;      /* 0..CANBUS_SUPERPOSED_MAX */
    bool until_bus_off;       /* stop once its node is bus-off (a forced bus-off) */
} canbus_fault_t;

/* A babbling node: frame queued at node every period_ns from t_from until t_to
 * (period 0: back to back, the next one queued as the previous one starts). */
typedef struct {
    uint32_t node;
    canbus_frame_t frame;
    uint64_t period_ns;
    uint64_t t_from, t_to;
} canbus_babble_t;

/* One node's fault confinement, and what it went through. */
typedef struct {
    uint32_t tec, rec;
    uint32_t tec_max, rec_max;
    canbus_state_t state;
    uint64_t tx_errors, rx_errors;
    uint64_t passive_episodes, bus_off_episodes;
    uint64_t bus_off_at;       /* the latest bus-off */
    uint64_t recovery_ns_max;  /* the longest bus-off, to its recovery */
    uint64_t dropped;          /* frames dropped by bus-off */
    uint64_t suspend_until;    /* error-passive after its own frame: no SOF before */
    uint64_t run_start;        /* bus-off: the recessive run counted since then */
    uint32_t runs;             /* bus-off: occurrences of 11 recessive bits so far */
} canbus_confine_t;

/* 1 when the fault's fields are in range. */
bool canbus_fault_valid(const canbus_fault_t *f);

/* The state TEC and REC give (not bus-off, which only a TEC above 255 starts). */
canbus_state_t canbus_confine_state(uint32_t tec, uint32_t rec);

/* The counters after a transmit / receive error, a transmission / reception. */
void canbus_confine_tx_error(canbus_confine_t *n);
void canbus_confine_rx_error(canbus_confine_t *n);
void canbus_confine_tx_ok(canbus_confine_t *n);
void canbus_confine_rx_ok(canbus_confine_t *n);

/* The bit position of an error of fault f in a frame of `bits` bits (canbus_frame_bits). */
uint32_t canbus_fault_bit(const canbus_fault_t *f, uint32_t bits);

#endif /* CANBUS_FAULTS_H */
