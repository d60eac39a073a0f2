/*
 * canrec_log.h -- the candump log line of one received frame, and the
 * arithmetic of the kernel's drop counter (SO_RXQ_OVFL).
 *
 * Line format (candump -l / -L of can-utils 2020.11, the Debian package the
 * rig runs, and what hil.bus.candump reads):
 *
 *   (SSSSSSSSSS.UUUUUU) IFACE ID#DATA\n
 *
 *   seconds zero-padded to at least 10 digits, microseconds to 6;
 *   ID: 3 hex digits (standard), 8 (extended, or an error frame with
 *   CAN_ERR_FLAG kept in the identifier); DATA: two upper-case hex digits a
 *   byte, no separators; a remote frame "R" plus its DLC when 1..8; a CAN FD
 *   frame "##" plus its flags (one hex digit) before the data.  A classic
 *   frame's raw DLC 9..15 (len8_dlc) is not written, as that candump does not.
 *
 * Host only (Linux headers); no I/O, no allocation: unit-tested in
 * tests/c/test_canrec.c.
 */
#ifndef CANREC_LOG_H
#define CANREC_LOG_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <linux/can.h>

/* Longest line canrec_log_line() writes, newline and NUL included: 20-digit
 * seconds, a 15-character interface name, an FD frame of 64 bytes. */
#define CANREC_LINE_MAX 256u

/*
 * One log line for frame f (fd: it was read as a CAN FD frame, CANFD_MTU
 * bytes) received at sec.usec on iface, newline-terminated, into buf.
 * Returns its length without the NUL, or 0 when it does not fit in cap or
 * usec is not 0..999999.
 */
size_t canrec_log_line(char *buf, size_t cap, int64_t sec, int64_t usec, const char *iface,
                       const struct canfd_frame *f, bool fd);

/* Frames the kernel dropped between two readings of its 32-bit counter
 * (wraps around). */
uint32_t canrec_drops_since(uint32_t before, uint32_t now);

#endif /* CANREC_LOG_H */
