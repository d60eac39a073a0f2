/*
 * fcc_can.h -- a classic CAN frame and the port interface the core talks to.
 *
 * The core never sees an OS: it gets frames from, and hands frames to, a port
 * through this small table of functions.  firmware/port/linux implements it on
 * SocketCAN; a microcontroller port would implement it on its CAN peripheral.
 */
#ifndef FCC_CAN_H
#define FCC_CAN_H

#include <stdint.h>

#include "fcc_types.h"

#define FCC_CAN_MAX_DLC 8u
#define FCC_CAN_STD_ID_MAX 0x7FFu

/* One classic CAN data frame with an 11-bit identifier.  t_us is the receive
 * time stamp (the port's clock, microseconds; 0 when the port has none). */
typedef struct {
    uint32_t id;
    uint8_t dlc;
    uint8_t data[FCC_CAN_MAX_DLC];
    uint64_t t_us;
} fcc_can_frame_t;

/* Port counters, kept by the port and published in FCC_BUS_COUNTS. */
typedef struct {
    uint32_t rx_frames;
    uint32_t tx_frames;
    uint32_t bus_errors;   /* error frames received (CAN_ERR_FLAG) */
    uint32_t rx_overflows; /* frames the kernel dropped from the receive queue */
    uint32_t tx_retries;   /* send attempts repeated after ENOBUFS/EAGAIN */
    uint32_t tx_dropped;   /* frames given up after the bounded retry */
    uint32_t rx_ignored;   /* remote, extended-ID or oversize frames the port discards */
} fcc_can_port_counters_t;

/*
 * The port interface.  recv() never blocks: FCC_ERR_AGAIN when no frame is
 * waiting.  send() may retry for a bounded time; a frame it gives up on is
 * counted in tx_dropped and reported as FCC_ERR_AGAIN, never a crash.
 *
 * send_many() is optional (NULL: the core sends frame by frame).  It sends
 * frames[0..n) in this order exactly as n calls of send() would -- the same
 * bytes, the same bounded retry of each frame, the same counters -- in as few
 * operating-system calls as it can (Linux: one sendmmsg), and writes the
 * status send() would have returned for frame i to st[i].  An I/O error ends
 * the batch: that frame and every later one get FCC_ERR_IO, not attempted.
 * Returns FCC_OK when every st[i] is FCC_OK, else the first failing status;
 * FCC_ERR_ARG (st[] untouched) for NULL arguments.  A port gives it when a
 * system call costs more than the frames: the core then queues a step's
 * frames (fcc_node.h) and hands them over at the end of the step.
 */
typedef struct {
    void *ctx;
    fcc_status_t (*send)(void *ctx, const fcc_can_frame_t *frame);
    fcc_status_t (*recv)(void *ctx, fcc_can_frame_t *frame);
    fcc_status_t (*counters)(void *ctx, fcc_can_port_counters_t *out);
    fcc_status_t (*send_many)(void *ctx, const fcc_can_frame_t *frames, uint32_t n,
                              fcc_status_t *st);
} fcc_can_port_t;

#endif /* FCC_CAN_H */
