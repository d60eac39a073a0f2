/*
 * fcc_tsync_auth.h -- the authenticated receiver of the time master's frames:
 * TSYNC_SYNC and TSYNC_FOLLOW_UP are held (the SYNC with its receive stamp)
 * until the master's TSYNC_AUTH, the SecOC authenticator of the pair (the
 * DBC's SecOC_Pdus "TSYNC_SYNC TSYNC_FOLLOW_UP"; fcc_secoc.h, dbc/README.md
 * "Authentication"), verifies one SYNC + FOLLOW_UP pair; only that pair goes
 * on to the E2E and range checks and then to the servo (fcc_tsync.h).  So a
 * forged SYNC or FOLLOW_UP -- even one with a valid E2E header that pre-empts
 * the master's alive counter -- never reaches the E2E state or the servo, and
 * the SYNC's receive stamp is taken when it arrives, not when it verifies.
 *
 * Pairing: on an authenticator, the held FOLLOW_UPs (newest first) are paired
 * with the held SYNCs of the same master and sequence number (newest first),
 * and at most FCC_SECOC_CANDIDATES pairs are tried (a bounded cost per
 * authenticator, whatever is held).  On success the verified frames and every
 * frame held before them are dropped, the others counted `unauthenticated`;
 * frames that came after stay for the next authenticator.  A forged
 * authenticator drops nothing.
 *
 * Eviction: when FCC_TSYNC_AUTH_HELD frames of a kind are held, a new one
 * pushes out the held frame least likely to be the master's next: the one
 * whose sequence number is furthest from the expected one, either way (the
 * last verified pair's + 1, modulo 256: the master's frame after a lost pair
 * is 1 away, a replay a second late ~10), the oldest of equals; before any
 * pair has verified, the oldest.  Why: replayed bursts of
 * the master's own old frames (~7 SYNCs and 7 FOLLOW_UPs, sequence numbers
 * ~10 behind, `hil verify time-sync --case replayed-master --target
 * qemu-m4f`) landing between the master's SYNC and its TSYNC_AUTH pushed the
 * master's SYNC out of the oldest-first hold, so its authenticator matched no
 * pair and the pair was lost (repeated: HOLDOVER).  Now the replays push out
 * each other.  A forged frame with the expected sequence number fares no
 * better than before: it still needs an authenticator.  Portable, no heap.
 */
#ifndef FCC_TSYNC_AUTH_H
#define FCC_TSYNC_AUTH_H

#include <stdint.h>

#include "fcc_secoc.h"
#include "fcc_types.h"

#define FCC_TSYNC_AUTH_HELD 4u /* SYNCs and FOLLOW_UPs held each */

typedef struct {
    uint8_t data[8];
    uint64_t t_us; /* receive stamp (SYNC), port clock */
} fcc_tsync_held_t;

typedef struct {
    uint32_t mac_failed;       /* TSYNC_AUTH whose MAC matched no held pair (forged) */
    uint32_t freshness_failed; /* TSYNC_AUTH replayed, or beyond the acceptance window */
    uint32_t unauthenticated;  /* SYNC / FOLLOW_UP frames dropped without a valid authenticator */
} fcc_tsync_auth_counters_t;

typedef struct {
    fcc_tsync_held_t sync[FCC_TSYNC_AUTH_HELD];
    uint8_t n_sync;
    fcc_tsync_held_t fup[FCC_TSYNC_AUTH_HELD];
    uint8_t n_fup;
    bool seq_known;       /* a pair has verified: expected_seq is the master's next */
    uint8_t expected_seq; /* sequence number of the last verified pair + 1 (mod 256) */
    fcc_tsync_auth_counters_t cnt;
} fcc_tsync_auth_t;

/* Nothing held, counters zero. */
fcc_status_t fcc_tsync_auth_init(fcc_tsync_auth_t *ta);

/* A SYNC (8 bytes, received at t_us) or a FOLLOW_UP arrived: held; when
 * FCC_TSYNC_AUTH_HELD of its kind are held, one is dropped (unauthenticated)
 * first, as "Eviction" above says. */
fcc_status_t fcc_tsync_auth_hold_sync(fcc_tsync_auth_t *ta, const uint8_t data[8], uint64_t t_us);
fcc_status_t fcc_tsync_auth_hold_follow_up(fcc_tsync_auth_t *ta, const uint8_t data[8]);

/* The authenticator (8 bytes) of SecOC PDU `index` (TSYNC_AUTH's).  VERIFIED:
 * *sync (bytes and receive stamp) and fup[8] are the authentic pair.  The
 * verdict is counted here and in sec->cnt. */
fcc_secoc_verdict_t fcc_tsync_auth_verify(fcc_tsync_auth_t *ta, fcc_secoc_t *sec, uint32_t index,
                                          const uint8_t auth[8], fcc_tsync_held_t *sync,
                                          uint8_t fup[8]);

#endif /* FCC_TSYNC_AUTH_H */
