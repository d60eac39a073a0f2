/*
 * fcc_port.h -- everything the portable flight-computer core needs from the
 * machine it runs on, as a table of function pointers.
 *
 * Why a table and not link-time functions: the same core runs on Linux
 * (SocketCAN, CLOCK_MONOTONIC, stderr), on a Cortex-M4F (CAN peripheral, a
 * hardware timer, a fault log) and inside the unit tests (frames in memory, a
 * fake clock), and all three can coexist in one test program.
 *
 * The core never blocks and never reads a clock except through now_us().
 */
#ifndef FCC_PORT_H
#define FCC_PORT_H

#include <stdint.h>

#include "fcc_can.h"
#include "fcc_event.h"
#include "fcc_types.h"

typedef struct {
    /* Frames in and out (fcc_can.h): recv never blocks (FCC_ERR_AGAIN when
     * empty); send may retry for a bounded time, FCC_ERR_AGAIN / FCC_ERR_IO
     * when the frame was not sent (the core counts it and goes on). */
    fcc_can_port_t can;
    /* Monotonic microseconds, for step execution times only. */
    uint64_t (*now_us)(void *ctx);
    void *clock_ctx;
    /* Optional (NULL = silent): one call per event; the port decides how to
     * report it (Linux: one rate-limited stderr line per class). */
    void (*event)(void *ctx, const fcc_event_t *event);
    void *event_ctx;
} fcc_port_t;

#endif /* FCC_PORT_H */
