/*
 * canrec_ring.h -- the receive ring of a packet socket on one CAN interface
 * (AF_PACKET, TPACKET_V2, PACKET_RX_RING).
 *
 * The kernel writes every frame the interface receives (the frames the local
 * sockets send come back on the receive path: CAN loopback) into a ring of
 * slots shared with canrec, stamped as SO_TIMESTAMP stamps them.  canrec takes
 * them without a system call per batch, and the kernel delivers each frame with
 * a copy into the ring instead of a socket buffer queued and copied out again.
 * In a User-Mode Linux guest (docs/performance.md): an 18-frame send costs its
 * sender 7.5 us more with a ring on the interface, 15 us more with a CAN_RAW
 * socket; canrec reads a frame in ~0.1 us where the socket took ~2 us, once
 * the ring's page has been used (its first use costs ~35 us there).
 *
 * A packet socket needs CAP_NET_RAW; without it (or on a kernel without
 * PACKET_IGNORE_OUTGOING, before Linux 4.20) canrec_ring_open() says
 * CANREC_RING_UNAVAILABLE and canrec reads a CAN_RAW socket as before.
 *
 * Host only (Linux); the ring is the kernel's memory, mapped once.
 */
#ifndef CANREC_RING_H
#define CANREC_RING_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <linux/can.h>

/* A slot: the kernel's header, the link-layer address, the frame (CAN FD at most). */
#define CANREC_RING_SLOT 160u

typedef enum {
    CANREC_RING_OK = 0,
    CANREC_RING_UNAVAILABLE, /* no packet socket here: read a CAN_RAW socket instead */
    CANREC_RING_FAILED       /* a step failed: what and errno say which */
} canrec_ring_status_t;

typedef struct {
    int fd;
    unsigned char *base;  /* the mapped ring */
    size_t len;
    unsigned slots;
    unsigned per_block;   /* slots in one block (a page) */
    unsigned head;        /* the next slot to read */
} canrec_ring_t;

/* One received frame, read in place (valid until canrec_ring_release). */
typedef struct {
    int64_t sec;
    int64_t usec;
    const struct canfd_frame *frame;
    unsigned len;        /* its length in bytes */
    bool is_can;         /* a whole classic (CAN_MTU) or CAN FD (CANFD_MTU) frame, not CAN XL */
    bool fd;             /* a CAN FD frame */
    bool after_losses;   /* the kernel dropped frames (ring full) since its count was read */
} canrec_ring_frame_t;

/* Whether the interface named is a CAN one (a packet socket would record any). */
bool canrec_ring_is_can(const char *iface);

/*
 * The ring of about `bytes` bytes (at least a page) on interface ifindex.
 * On CANREC_RING_FAILED, *what names the step and *err is its errno.
 */
canrec_ring_status_t canrec_ring_open(canrec_ring_t *ring, unsigned ifindex, size_t bytes,
                                      const char **what, int *err);

/* The frame in the next slot, if the kernel has filled it. */
bool canrec_ring_peek(const canrec_ring_t *ring, canrec_ring_frame_t *out);

/* Hands the slot just read back to the kernel. */
void canrec_ring_release(canrec_ring_t *ring);

/* Frames the kernel dropped since the last call (the ring was full): 0 and *lost, or -1. */
int canrec_ring_losses(const canrec_ring_t *ring, uint32_t *lost);

/* A pending socket error (ENETDOWN: the interface went down), cleared; 0: none. */
int canrec_ring_error(const canrec_ring_t *ring);

void canrec_ring_close(canrec_ring_t *ring);

#endif /* CANREC_RING_H */
