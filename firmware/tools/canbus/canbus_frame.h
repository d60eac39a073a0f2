/*
 * canbus_frame.h -- a classic CAN frame as the bus model sees it: its exact
 * length on the wire and its place in arbitration (ISO 11898-1, SPEC §8).
 *
 * OS-free (no SocketCAN types): the core and its tests use it alike.
 */
#ifndef CANBUS_FRAME_H
#define CANBUS_FRAME_H

#include <stdbool.h>
#include <stdint.h>

#define CANBUS_DLC_MAX 8u
#define CANBUS_STD_ID_MAX 0x7FFul
#define CANBUS_EXT_ID_MAX 0x1FFFFFFFul
/* After the stuffed region: CRC delimiter, ACK slot and delimiter, EOF (7), IFS (3). */
#define CANBUS_TAIL_BITS 13u
/* The interframe space: the bus is idle again this many bits after the end of frame. */
#define CANBUS_IFS_BITS 3u

typedef struct {
    uint32_t id;      /* 11 or 29 bits */
    bool ext;         /* a 29-bit identifier */
    bool rtr;         /* a remote frame: dlc is sent, no data */
    uint8_t dlc;      /* 0..8 */
    uint8_t data[CANBUS_DLC_MAX];
} canbus_frame_t;

/* 1 when f is a classic frame the bus can carry (identifier and DLC in range). */
bool canbus_frame_valid(const canbus_frame_t *f);

/* Its length in bits from SOF to the end of the interframe space, stuff bits
 * counted on its actual bits (CRC-15 0x4599 included): what
 * hil.bus.busload.frame_bits() computes.  0 for an invalid frame. */
uint32_t canbus_frame_bits(const canbus_frame_t *f);

/* Its arbitration field as one number, the bits in the order they are sent
 * (base identifier, RTR or SRR, IDE, identifier extension, RTR): the lower
 * number wins, so an 11-bit frame beats a 29-bit one with the same base and a
 * data frame a remote one. */
uint32_t canbus_frame_arbitration(const canbus_frame_t *f);

#endif /* CANBUS_FRAME_H */
