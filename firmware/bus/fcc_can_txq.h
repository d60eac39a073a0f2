/*
 * fcc_can_txq.h -- frames queued for a port's send_many (fcc_can.h), so that a
 * step's outputs leave in one system call instead of one per frame.
 *
 * The queue is caller-owned fixed storage (FCC_CAN_TXQ_LEN frames).  The
 * caller sends every frame through fcc_can_txq_send() and calls
 * fcc_can_txq_flush() at the end of the work that produced them (a control
 * step, a heartbeat) -- and before anything that must see them out first: a
 * wait, a sleep, a receive that may depend on them.  Frames leave in the order
 * they were sent, as the same bytes; a full queue is flushed before the next
 * frame goes in.
 *
 * The port reports on every frame (send_many's per-frame status); done() gets
 * each report, in order, with the caller's tag of the frame, so the caller
 * counts and reports frames exactly as it would have frame by frame.  A port
 * without send_many (the Cortex-M4F image: a UART) gets each frame at once
 * from fcc_can_txq_send(), as before; flush then has nothing to do.
 */
#ifndef FCC_CAN_TXQ_H
#define FCC_CAN_TXQ_H

#include <stdint.h>

#include "fcc_can.h"
#include "fcc_types.h"

/* A CDRW step's 12 outputs and its FCC_ACK, or a heartbeat's 9 frames, fit. */
#define FCC_CAN_TXQ_LEN 16u

typedef struct {
    fcc_can_frame_t frame[FCC_CAN_TXQ_LEN];
    uint8_t tag[FCC_CAN_TXQ_LEN]; /* the caller's label of each frame (the node: its app) */
    uint32_t n;                   /* frames waiting */
} fcc_can_txq_t;

/* What the port did with one frame (st: what send() would have returned). */
typedef void (*fcc_can_txq_done_fn)(void *ctx, const fcc_can_frame_t *frame, uint8_t tag,
                                    fcc_status_t st);

/* An empty queue.  FCC_ERR_ARG for NULL. */
fcc_status_t fcc_can_txq_init(fcc_can_txq_t *q);

/* One frame to the port: queued when the port has send_many (after a flush if
 * the queue is full), else sent now and reported.  Returns FCC_OK when the
 * frame was queued or sent; else the status of the frame (or of the flush
 * that made room) that failed, which done() has been told as well.
 * FCC_ERR_ARG (nothing done) for NULL arguments or a port without send(). */
fcc_status_t fcc_can_txq_send(fcc_can_txq_t *q, const fcc_can_port_t *port,
                              const fcc_can_frame_t *frame, uint8_t tag,
                              fcc_can_txq_done_fn done, void *ctx);

/* Every waiting frame to the port in one send_many, then done() for each in
 * order; the queue is empty afterwards.  FCC_OK when all were sent (or none
 * waited), else the first failing frame's status; FCC_ERR_ARG (nothing done)
 * for NULL arguments. */
fcc_status_t fcc_can_txq_flush(fcc_can_txq_t *q, const fcc_can_port_t *port,
                               fcc_can_txq_done_fn done, void *ctx);

#endif /* FCC_CAN_TXQ_H */
