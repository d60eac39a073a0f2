/*
 * canrec_ring.c -- the packet socket's receive ring (canrec_ring.h).
 */
#define _GNU_SOURCE

#include "canrec_ring.h"

#include <arpa/inet.h>
#include <errno.h>
#include <net/if.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <unistd.h>

#include <linux/if_arp.h>
#include <linux/if_ether.h>
#include <linux/if_packet.h>

#ifndef PACKET_IGNORE_OUTGOING
#define PACKET_IGNORE_OUTGOING 23
#endif

/* A block is a page: the kernel allocates the ring a page at a time (no large
 * contiguous allocation that could fail on a busy machine). */
#define BLOCK_BYTES 4096u
/* The most blocks a ring has (16 MiB, -R's largest). */
#define BLOCKS_MAX 4096u

/* Each page used once before recording, while the kernel writes nothing yet (the socket is not
 * bound): a page's first use is a fault, and on a User-Mode Linux guest a host mapping (~35 us
 * a page there, 9 ms for 1 MiB) -- paid here, at the start, rather than while recording, as a
 * real-time program locks its memory in before its loop. */
static void map_every_page(const canrec_ring_t *ring)
{
    for (size_t at = 0u; at < ring->len; at += BLOCK_BYTES) {
        struct tpacket2_hdr *first = (struct tpacket2_hdr *)(void *)(ring->base + at);
        __atomic_store_n(&first->tp_status, (uint32_t)TP_STATUS_KERNEL, __ATOMIC_RELAXED);
    }
}

bool canrec_ring_is_can(const char *iface)
{
    const int fd = socket(AF_UNIX, SOCK_DGRAM, 0);
    if (fd < 0) {
        return false;
    }
    struct ifreq ifr;
    memset(&ifr, 0, sizeof ifr);
    (void)strncpy(ifr.ifr_name, iface, IF_NAMESIZE - 1);
    const bool can = ioctl(fd, SIOCGIFHWADDR, &ifr) == 0 && ifr.ifr_hwaddr.sa_family == ARPHRD_CAN;
    (void)close(fd);
    return can;
}

static canrec_ring_status_t failed(canrec_ring_t *ring, const char *step, const char **what,
                                   int *err)
{
    *what = step;
    *err = errno;
    canrec_ring_close(ring);
    return CANREC_RING_FAILED;
}

static canrec_ring_status_t unavailable(canrec_ring_t *ring)
{
    canrec_ring_close(ring);
    return CANREC_RING_UNAVAILABLE;
}

canrec_ring_status_t canrec_ring_open(canrec_ring_t *ring, unsigned ifindex, size_t bytes,
                                      const char **what, int *err)
{
    memset(ring, 0, sizeof *ring);
    ring->fd = socket(AF_PACKET, SOCK_RAW, htons(ETH_P_ALL));
    if (ring->fd < 0) {
        if (errno == EPERM || errno == EACCES || errno == EAFNOSUPPORT) {
            return unavailable(ring);
        }
        return failed(ring, "cannot open a packet socket for", what, err);
    }
    const int on = 1;
    const int version = TPACKET_V2;
    /* The frames this host sends are seen once, as the CAN loopback brings them back on the
     * receive path; without this the transmit path's copy would be recorded too. */
    if (setsockopt(ring->fd, SOL_PACKET, PACKET_IGNORE_OUTGOING, &on, sizeof on) < 0) {
        return unavailable(ring);
    }
    if (setsockopt(ring->fd, SOL_PACKET, PACKET_VERSION, &version, sizeof version) < 0) {
        return failed(ring, "cannot have a TPACKET_V2 ring on", what, err);
    }
    /* Asking for receive timestamps turns on the stamp every frame gets as it arrives (the
     * one SO_TIMESTAMP gives a CAN_RAW socket): the ring copies it, candump's lines equal. */
    if (setsockopt(ring->fd, SOL_SOCKET, SO_TIMESTAMP, &on, sizeof on) < 0) {
        return failed(ring, "cannot have receive timestamps (SO_TIMESTAMP) on", what, err);
    }
    size_t blocks = (bytes + BLOCK_BYTES - 1u) / BLOCK_BYTES;
    blocks = blocks == 0u ? 1u : (blocks > BLOCKS_MAX ? BLOCKS_MAX : blocks);
    ring->per_block = BLOCK_BYTES / CANREC_RING_SLOT;
    ring->slots = (unsigned)blocks * ring->per_block;
    struct tpacket_req req;
    memset(&req, 0, sizeof req);
    req.tp_block_size = BLOCK_BYTES;
    req.tp_block_nr = (unsigned)blocks;
    req.tp_frame_size = CANREC_RING_SLOT;
    req.tp_frame_nr = ring->slots;
    if (setsockopt(ring->fd, SOL_PACKET, PACKET_RX_RING, &req, sizeof req) < 0) {
        return failed(ring, "cannot have a receive ring (PACKET_RX_RING) on", what, err);
    }
    ring->len = blocks * BLOCK_BYTES;
    void *base = mmap(NULL, ring->len, PROT_READ | PROT_WRITE, MAP_SHARED, ring->fd, 0);
    if (base == MAP_FAILED) {
        ring->len = 0u;
        return failed(ring, "cannot map the receive ring of", what, err);
    }
    ring->base = base;
    map_every_page(ring);
    struct sockaddr_ll addr;
    memset(&addr, 0, sizeof addr);
    addr.sll_family = AF_PACKET;
    addr.sll_protocol = htons(ETH_P_ALL);
    addr.sll_ifindex = (int)ifindex;
    if (bind(ring->fd, (struct sockaddr *)&addr, sizeof addr) < 0) {
        return failed(ring, "cannot bind to", what, err);
    }
    return CANREC_RING_OK;
}

static struct tpacket2_hdr *slot(const canrec_ring_t *ring, unsigned i)
{
    const size_t block = i / ring->per_block;
    const size_t within = i % ring->per_block;
    return (struct tpacket2_hdr *)(void *)(ring->base + block * BLOCK_BYTES +
                                           within * CANREC_RING_SLOT);
}

bool canrec_ring_peek(const canrec_ring_t *ring, canrec_ring_frame_t *out)
{
    const struct tpacket2_hdr *h = slot(ring, ring->head);
    /* acquire: the frame's bytes are read only after the kernel's "yours" is seen */
    const uint32_t status = __atomic_load_n(&h->tp_status, __ATOMIC_ACQUIRE);
    if ((status & TP_STATUS_USER) == 0u) {
        return false;
    }
    out->sec = (int64_t)h->tp_sec;
    out->usec = (int64_t)(h->tp_nsec / 1000u);
    const unsigned char *at = (const unsigned char *)h;
    const struct sockaddr_ll *from =
        (const struct sockaddr_ll *)(const void *)(at + ((sizeof *h + TPACKET_ALIGNMENT - 1u) & ~(size_t)(TPACKET_ALIGNMENT - 1u)));
    const unsigned protocol = ntohs(from->sll_protocol);
    out->frame = (const struct canfd_frame *)(const void *)(at + h->tp_mac);
    out->len = h->tp_len;
    out->fd = protocol == ETH_P_CANFD;
    out->is_can = h->tp_snaplen == h->tp_len &&
                  ((protocol == ETH_P_CAN && h->tp_len == CAN_MTU) ||
                   (protocol == ETH_P_CANFD && h->tp_len == CANFD_MTU));
    out->after_losses = (status & TP_STATUS_LOSING) != 0u;
    return true;
}

void canrec_ring_release(canrec_ring_t *ring)
{
    /* release: the kernel may reuse the slot only after it has been read */
    __atomic_store_n(&slot(ring, ring->head)->tp_status, (uint32_t)TP_STATUS_KERNEL,
                     __ATOMIC_RELEASE);
    ring->head = ring->head + 1u == ring->slots ? 0u : ring->head + 1u;
}

int canrec_ring_losses(const canrec_ring_t *ring, uint32_t *lost)
{
    struct tpacket_stats st;  /* reading the counts resets them */
    socklen_t len = sizeof st;
    if (getsockopt(ring->fd, SOL_PACKET, PACKET_STATISTICS, &st, &len) < 0) {
        return -1;
    }
    *lost = st.tp_drops;
    return 0;
}

int canrec_ring_error(const canrec_ring_t *ring)
{
    int e = 0;
    socklen_t len = sizeof e;
    return getsockopt(ring->fd, SOL_SOCKET, SO_ERROR, &e, &len) == 0 ? e : errno;
}

void canrec_ring_close(canrec_ring_t *ring)
{
    if (ring->base != NULL) {
        (void)munmap(ring->base, ring->len);
    }
    if (ring->fd >= 0) {
        (void)close(ring->fd);
    }
    ring->base = NULL;
    ring->len = 0u;
    ring->fd = -1;
}
