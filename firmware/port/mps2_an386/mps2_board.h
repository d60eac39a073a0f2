/*
 * mps2_board.h -- the board under the Cortex-M4F image: QEMU's mps2-an386
 * (Arm MPS2 FPGA board with the AN386 Cortex-M4 image, FPv4-SP FPU).
 *
 *   UART0 (0x40004000)  the CAN link (SLCAN): receive and transmit by
 *                       interrupt through fixed rings, never blocks
 *   UART1 (0x40005000)  the log: polled, bounded wait, drops when stuck
 *   dual timer 1        free-running 32-bit counter at 25 MHz, extended to a
 *                       64-bit tick count and microsecond clock
 *   SysTick             one-shot alarm: ends the idle loop's WFI at its deadline
 *   semihosting         only to end QEMU with an exit status
 *
 * No heap, no OS; the only mutable state is this module's (one board).
 */
#ifndef MPS2_BOARD_H
#define MPS2_BOARD_H

#include <stddef.h>
#include <stdint.h>

#include "fcc_types.h"

#define MPS2_CPU_HZ 25000000u
#define MPS2_LINK_RX_RING 4096u
#define MPS2_LINK_TX_RING 4096u
/* Receive stamps of lines not yet read (a power of two; an SLCAN frame line
 * is 5-27 bytes: 128 lines cover 3.5 kB of frames in the receive ring). */
#define MPS2_LINK_LINE_STAMPS 128u

typedef struct {
    uint32_t rx_bytes;
    uint32_t rx_overflows;  /* bytes lost: the receive ring was full (or the UART overran) */
    uint32_t tx_bytes;
    uint32_t tx_refused;    /* writes refused: no room in the transmit ring */
    uint32_t log_dropped;   /* log bytes dropped: UART1 did not drain */
    uint32_t sleeps;        /* times the idle loop slept (WFI) */
    uint32_t lines;         /* lines received (CR or LF ended) */
    uint32_t line_us_sum;   /* their time on the line: first byte to terminator, us */
    uint32_t line_us_worst;
    uint32_t stamps_lost;   /* lines without a receive stamp: the stamp ring was full */
} mps2_counters_t;

/* Clock, both UARTs, interrupts; the FPU is on from reset (mps2_startup.c). */
void mps2_board_init(void);

/* Microseconds since mps2_board_init(); 25 MHz ticks (40 ns) since then. */
uint64_t mps2_now_us(void);
uint64_t mps2_ticks(void);

/* Next received byte of the link: 1, *byte and *line_rx_us, the time (us,
 * the mps2_now_us() clock) when the receive interrupt took the first byte of
 * the line the byte belongs to (a line ends with CR or LF); or 0 when none is
 * waiting.  So a frame's receive stamp is its line's arrival on the wire, not
 * the time the main loop came to parse it. */
int mps2_link_getc(uint8_t *byte, uint64_t *line_rx_us);

/* When the receive interrupt took the terminator of the last line
 * mps2_link_getc() returned to its end (us, as above): the line's arrival
 * complete, as a CAN controller's receive interrupt at the end of a frame. */
uint64_t mps2_link_line_end_us(void);

/* n bytes to the link, all or nothing: FCC_ERR_AGAIN when the ring has no
 * room for them (nothing queued).  Matches fcc_slcan_write_fn. */
fcc_status_t mps2_link_write(void *ctx, const uint8_t *bytes, size_t n);

/* Text to the log UART (no newline added). */
void mps2_log(const char *text);
void mps2_log_u64(uint64_t v);

/* Sleeps (WFI) until an interrupt, unless a received byte is already
 * waiting; returns at once when until_us is already reached.  The SysTick,
 * armed here, wakes it at until_us or after 0.67 s, whichever is first. */
void mps2_idle(uint64_t until_us);

/* Deepest stack use since reset, bytes (the stack is painted at reset). */
uint32_t mps2_stack_used(void);

void mps2_counters(mps2_counters_t *out);

/* Ends QEMU with this status (semihosting SYS_EXIT_EXTENDED); on a board
 * without a debugger it would stop in a fault, so only call it last. */
void mps2_exit(int status) __attribute__((noreturn));

/* The boot configuration sector (README.md here), 64 bytes. */
const volatile uint8_t *mps2_bootcfg(void);

#endif /* MPS2_BOARD_H */
