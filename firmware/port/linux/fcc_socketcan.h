/*
 * fcc_socketcan.h -- the Linux SocketCAN port (host only, never in fcc_core).
 *
 * Implements the port interface of firmware/bus/fcc_can.h on a raw CAN socket:
 *  - open an interface by name, non-blocking;
 *  - receive filters: exact match on the standard identifiers a node consumes;
 *  - receive without blocking, with the kernel's time stamp (SO_TIMESTAMPNS, moved to CLOCK_MONOTONIC):
 *    the waiting frames are read ahead, up to FCC_SOCKETCAN_RX_BATCH with one
 *    recvmmsg(), and handed out one by one in arrival order (a caller that waits
 *    on the descriptor asks fcc_socketcan_pending() first).  A read that returned
 *    fewer than it asked for emptied the kernel's queue: the port does not ask the
 *    kernel again (no system call that would say "nothing") until the caller's wait
 *    says the descriptor is readable (fcc_socketcan_wait, or fcc_socketcan_readable
 *    for a caller that polls the descriptor itself; a send changes nothing here);
 *  - send: a full queue (ENOBUFS/EAGAIN) is retried for a bounded time, then
 *    the frame is dropped and counted -- the program never stops on it;
 *  - send many: the same, frames in order, up to FCC_SOCKETCAN_MAX_BATCH per
 *    sendmmsg() (one system call for a whole step's outputs);
 *  - error frames (CAN_RAW_ERR_FILTER) and kernel receive-queue overflows
 *    (SO_RXQ_OVFL) are counted, not passed to the application.
 * The state is a caller-owned struct; no heap.
 */
#ifndef FCC_SOCKETCAN_H
#define FCC_SOCKETCAN_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fcc_can.h"
#include "fcc_types.h"

#define FCC_SOCKETCAN_MAX_FILTERS 64u
#define FCC_SOCKETCAN_DEFAULT_SEND_BUDGET_US 5000u
#define FCC_SOCKETCAN_MAX_BATCH 32u /* frames per sendmmsg (larger batches: several) */
#define FCC_SOCKETCAN_RX_BATCH 16u  /* frames read ahead per recvmmsg */

/* The controller's fault confinement as its driver reports it to a socket that asked for
 * error frames (CAN_RAW_ERR_FILTER; linux/can/error.h): what fcc counts of a bus in error. */
typedef enum {
    FCC_CTRL_ACTIVE = 0,
    FCC_CTRL_WARNING = 1,
    FCC_CTRL_PASSIVE = 2,
    FCC_CTRL_BUS_OFF = 3
} fcc_ctrl_state_t;

typedef struct {
    fcc_ctrl_state_t state;      /* as the latest error frame says */
    uint32_t protocol_errors;    /* CAN_ERR_PROT: an error frame on the bus */
    uint32_t warnings;           /* times it entered error-warning (CAN_ERR_CRTL_*_WARNING) */
    uint32_t passive;            /* times it entered error-passive (CAN_ERR_CRTL_*_PASSIVE) */
    uint32_t bus_off;            /* CAN_ERR_BUSOFF */
    uint32_t restarts;           /* CAN_ERR_RESTARTED: back from bus-off */
    uint32_t tec_max, rec_max;   /* CAN_ERR_CNT: the counters in data[6], data[7] */
} fcc_socketcan_ctrl_t;

/* One error frame (can_id with CAN_ERR_FLAG, its 8 data bytes) into c. */
void fcc_socketcan_ctrl_update(fcc_socketcan_ctrl_t *c, uint32_t can_id, const uint8_t *data);

/* "active", "warning", "passive", "bus-off". */
const char *fcc_socketcan_ctrl_state_name(fcc_ctrl_state_t state);

typedef struct {
    int fd;                       /* -1 when closed */
    uint32_t send_budget_us;      /* bounded retry time of one send */
    uint32_t kernel_drops;        /* last SO_RXQ_OVFL value seen (cumulative in the kernel) */
    fcc_can_port_counters_t cnt;
    fcc_socketcan_ctrl_t ctrl;    /* from the error frames received */
    /* CLOCK_REALTIME - CLOCK_MONOTONIC (us), to move the kernel's stamps to the port's clock:
     * the tightest of a few bracketed readings, renewed every second (0: not yet) */
    int64_t rt_minus_mono_us;
    uint64_t rt_offset_at_us;     /* the realtime stamp it was read at (0: not yet) */
    fcc_can_frame_t rx[FCC_SOCKETCAN_RX_BATCH]; /* frames read ahead, in arrival order */
    uint32_t rx_head;             /* the next one to hand out */
    uint32_t rx_n;                /* how many were read */
    bool drained;                 /* the last read emptied the kernel's queue */
} fcc_socketcan_t;

/* Open interface ifname (e.g. "vcan0"): FCC_ERR_IO when it does not exist or
 * the kernel has no CAN; s->fd stays -1 then.  Receives every standard data
 * frame until fcc_socketcan_set_filters() narrows it. */
fcc_status_t fcc_socketcan_open(fcc_socketcan_t *s, const char *ifname);

/* Receive only these standard identifiers (n <= FCC_SOCKETCAN_MAX_FILTERS;
 * n == 0 receives every frame again). */
fcc_status_t fcc_socketcan_set_filters(fcc_socketcan_t *s, const uint32_t *ids, size_t n);

/* Asks for a receive buffer of `bytes` (SO_RCVBUFFORCE, else SO_RCVBUF, which the kernel
 * caps at rmem_max); FCC_ERR_IO when neither is accepted. */
fcc_status_t fcc_socketcan_set_rcvbuf(fcc_socketcan_t *s, int bytes);

/* One frame if one is waiting (FCC_OK), FCC_ERR_AGAIN if none, FCC_ERR_IO on a
 * socket error.  Error frames and frames the port cannot represent (extended,
 * remote) are counted and skipped.  Frames are read ahead (one recvmmsg for all
 * that wait, up to FCC_SOCKETCAN_RX_BATCH) and handed out one per call; rx_frames
 * counts them as they are handed out.  After a read that emptied the kernel's
 * queue, FCC_ERR_AGAIN without a system call until fcc_socketcan_wait() or
 * fcc_socketcan_readable() (frames that came since wait on the descriptor). */
fcc_status_t fcc_socketcan_recv(fcc_socketcan_t *s, fcc_can_frame_t *frame);

/* Frames read ahead and not yet handed out: the descriptor may not be readable
 * although fcc_socketcan_recv() has a frame, so a caller about to wait on it
 * must not block while this is true. */
bool fcc_socketcan_pending(const fcc_socketcan_t *s);

/* Wait up to timeout_ms for a frame to read (at once when one is read ahead):
 * FCC_OK readable, FCC_ERR_AGAIN timeout. */
fcc_status_t fcc_socketcan_wait(fcc_socketcan_t *s, int timeout_ms);

/* The caller's own poll() found the descriptor readable: the next
 * fcc_socketcan_recv() asks the kernel again. */
void fcc_socketcan_readable(fcc_socketcan_t *s);

/* Send one standard data frame (dlc <= 8).  FCC_ERR_AGAIN: dropped after the
 * bounded retry (counted in tx_dropped). */
fcc_status_t fcc_socketcan_send(fcc_socketcan_t *s, const fcc_can_frame_t *frame);

/* Send frames[0..n) in order, each exactly as fcc_socketcan_send would (its own
 * bounded retry, the same counters), FCC_SOCKETCAN_MAX_BATCH per sendmmsg; the
 * status of frame i in st[i] (FCC_ERR_ARG: not a sendable frame, or the port is
 * closed).  An I/O error ends the batch: that frame and every later one
 * FCC_ERR_IO, not attempted.  Returns the first status that is not FCC_OK, else
 * FCC_OK; FCC_ERR_ARG with st[] untouched when s, or frames/st with n > 0, is NULL. */
fcc_status_t fcc_socketcan_send_many(fcc_socketcan_t *s, const fcc_can_frame_t *frames,
                                     uint32_t n, fcc_status_t *st);

fcc_status_t fcc_socketcan_counters(const fcc_socketcan_t *s, fcc_can_port_counters_t *out);

void fcc_socketcan_close(fcc_socketcan_t *s);

/* The port interface of fcc_can.h bound to s. */
fcc_can_port_t fcc_socketcan_port(fcc_socketcan_t *s);

#endif /* FCC_SOCKETCAN_H */
