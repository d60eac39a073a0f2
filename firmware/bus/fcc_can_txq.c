/*
 * fcc_can_txq.c -- frames queued for a port's send_many.  See fcc_can_txq.h.
 */
#include "fcc_can_txq.h"

#include <stddef.h>

fcc_status_t fcc_can_txq_init(fcc_can_txq_t *q)
{
    if (q == NULL) {
        return FCC_ERR_ARG;
    }
    q->n = 0u;
    return FCC_OK;
}

fcc_status_t fcc_can_txq_flush(fcc_can_txq_t *q, const fcc_can_port_t *port,
                               fcc_can_txq_done_fn done, void *ctx)
{
    if (q == NULL || port == NULL || done == NULL || (q->n > 0u && port->send_many == NULL)) {
        return FCC_ERR_ARG;
    }
    const uint32_t n = (q->n <= FCC_CAN_TXQ_LEN) ? q->n : FCC_CAN_TXQ_LEN;
    q->n = 0u; /* empty before done(): a report that sends again starts a new batch */
    if (n == 0u) {
        return FCC_OK;
    }
    fcc_status_t st[FCC_CAN_TXQ_LEN];
    for (uint32_t i = 0u; i < n; ++i) {
        st[i] = FCC_ERR_IO; /* a frame the port did not report on was not sent */
    }
    /* its return value is the first failure of st[]: each frame is reported below */
    (void)port->send_many(port->ctx, q->frame, n, st);
    fcc_status_t first = FCC_OK;
    for (uint32_t i = 0u; i < n; ++i) {
        first = (first == FCC_OK) ? st[i] : first;
        done(ctx, &q->frame[i], q->tag[i], st[i]);
    }
    return first;
}

fcc_status_t fcc_can_txq_send(fcc_can_txq_t *q, const fcc_can_port_t *port,
                              const fcc_can_frame_t *frame, uint8_t tag,
                              fcc_can_txq_done_fn done, void *ctx)
{
    if (q == NULL || port == NULL || frame == NULL || done == NULL || port->send == NULL) {
        return FCC_ERR_ARG;
    }
    if (port->send_many == NULL) { /* this port sends each frame as it is made */
        const fcc_status_t st = port->send(port->ctx, frame);
        done(ctx, frame, tag, st);
        return st;
    }
    fcc_status_t st = FCC_OK;
    if (q->n >= FCC_CAN_TXQ_LEN) {
        st = fcc_can_txq_flush(q, port, done, ctx);
    }
    q->frame[q->n] = *frame;
    q->tag[q->n] = tag;
    ++q->n;
    return st;
}
