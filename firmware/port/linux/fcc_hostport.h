/*
 * fcc_hostport.h -- the Linux implementation of fcc_port.h: SocketCAN
 * (fcc_port_linux), CLOCK_MONOTONIC, and an interface watchdog.
 *
 * Why a watchdog: when the interface goes down the raw socket reports
 * ENETDOWN once and every send fails; when it is deleted and created again
 * the socket stays bound to an index that no longer exists.  The flight
 * computer must keep running (on prediction) and come back on its own, so
 * on an I/O error the socket is closed and the interface probed every
 * FCC_HOSTPORT_PROBE_US; when it is up again the socket is reopened.
 * Counters of closed sockets are carried over, so the heartbeat never goes
 * backwards.
 *
 * It sends a batch of frames (a step's outputs, the node's queue) with one
 * sendmmsg (fcc_socketcan_send_many).  A batch that carries an MSL_ELEV_CMD is
 * stamped by a clock read just before it is handed to the kernel (cmd_sent_us):
 * CLOCK_MONOTONIC, the clock of the receive time stamps (the kernel's SO_TIMESTAMPNS,
 * moved to CLOCK_MONOTONIC by fcc_socketcan), for the data age sensor frame
 * received -> command sent.  At the send, not later: whatever the loop does after
 * it (the other application's step in the same wake, event lines, a preemption)
 * is not the command's age; stamped by the loop's next clock read the figure was
 * 120 us and more above the kernel's own stamps of the same frames.  The read is
 * the time-stamp counter's (no system call); the kernel stamps the command a few
 * microseconds later, inside the send.
 *
 * Its clock (now_us, and the loop's reads through fcc_hostport_now) is CLOCK_MONOTONIC
 * read through the CPU's time-stamp counter where it is invariant (fcc_hostclock.h): the
 * node reads it twice a step (its execution time), and a system call each would lie on
 * the path from a lockstep tick to its command.
 */
#ifndef FCC_HOSTPORT_H
#define FCC_HOSTPORT_H

#include <stdbool.h>
#include <stdint.h>

#include "fcc_hostclock.h"
#include "fcc_port.h"
#include "fcc_socketcan.h"

#define FCC_HOSTPORT_PROBE_US 500000u

typedef struct {
    fcc_socketcan_t sc;
    fcc_hostclock_t clock;            /* the port's clock (fcc_hostclock.h) */
    uint64_t clock_reads;             /* its reads (clock.samples: those a system call served) */
    char ifname[32];
    bool up;                          /* socket open and working */
    uint64_t next_probe_us;           /* while down */
    fcc_can_port_counters_t carried;  /* counters of sockets closed so far */
    uint32_t downs;                   /* times the interface was lost */
    uint32_t reopens;                 /* times it came back */
    uint32_t cmd_id;                  /* identifier whose send is stamped */
    bool cmd_untaken;                 /* one has left since fcc_hostport_take_command */
    uint64_t cmd_sent_us;             /* CLOCK_MONOTONIC: the last one handed to the kernel */
    uint32_t cmd_sends;               /* sends taken so far */
    void (*event)(void *ctx, const fcc_event_t *ev);
    void *event_ctx;
} fcc_hostport_t;

/* The port's clock: CLOCK_MONOTONIC in microseconds, through the time-stamp counter where
 * it serves (fcc_hostclock.h: no system call per read); the node's now_us. */
uint64_t fcc_hostport_now(fcc_hostport_t *hp);

/* Prepares hp for interface ifname without opening it (sends fail, receive
 * is empty until fcc_hostport_open).  event/event_ctx receive interface
 * down/up reports. */
fcc_status_t fcc_hostport_init(fcc_hostport_t *hp, const char *ifname,
                               void (*event)(void *ctx, const fcc_event_t *ev), void *event_ctx);

/* Opens the interface: FCC_ERR_IO when it is missing or down (nothing kept
 * open). */
fcc_status_t fcc_hostport_open(fcc_hostport_t *hp);

/* The port table for the core (ctx = hp). */
fcc_port_t fcc_hostport_port(fcc_hostport_t *hp);

/* The descriptor to wait on, -1 while the interface is down. */
int fcc_hostport_fd(const fcc_hostport_t *hp);

/* Frames already read from the descriptor (read ahead) wait for the node's
 * receive: do not block on the descriptor while this is true. */
bool fcc_hostport_pending(const fcc_hostport_t *hp);

/* The loop's poll() found the descriptor readable (fcc_socketcan_readable). */
void fcc_hostport_readable(fcc_hostport_t *hp);

/* The loop takes the commands that left since the last call (cmd_untaken): one more
 * cmd_sends, cmd_sent_us the last one's send time. */
void fcc_hostport_take_command(fcc_hostport_t *hp);

/* An I/O error was seen: close the socket and start probing. */
void fcc_hostport_lost(fcc_hostport_t *hp);

/* While down: when due, probe the interface and reopen it if it is up.
 * Returns the next time (monotonic us) it wants to be called, or UINT64_MAX. */
uint64_t fcc_hostport_service(fcc_hostport_t *hp, uint64_t now_us);

void fcc_hostport_close(fcc_hostport_t *hp);

#endif /* FCC_HOSTPORT_H */
