/*
 * fcc_secoc.h -- SecOC-style authentication of CAN frames (in the manner of
 * AUTOSAR SecOC, profile-like: AES-128-CMAC truncated to 48 bits, a 64-bit
 * freshness value of which 16 bits travel).  The specification is in
 * dbc/README.md ("Authentication"); hil/src/hil/bus/secoc.py is the same in
 * Python.  In short:
 *
 *   - a secured frame (SIM_CONTROL, SIM_TICK), or group (the heartbeat; the time
 *     master's SYNC + FOLLOW_UP; fcc's outputs of one step: the 12 identification
 *     frames, the missile's command + estimate) is followed by its authenticator
 *     frame from the same sender (the DBC's SecOC_Pdus / SecOC_DataID attributes,
 *     fcc_secoc_table);
 *   - freshness value FV = trip << 32 | message counter; the counter counts the
 *     authenticator frames of one secured PDU, from 1; trip is drawn by fcc at
 *     start and published in FCC_SEC_SESSION;
 *   - authenticator = FV mod 2^16 (bytes 0-1, little-endian) | the first 6 bytes
 *     of AES-128-CMAC(key, data ID (big-endian) | secured bytes | FV (big-endian));
 *   - the receiver rebuilds FV as the smallest value above the last accepted one
 *     with those 16 low bits; more than FCC_SECOC_WINDOW ahead is a freshness
 *     failure (a replay, or too many frames lost); otherwise the MAC decides.
 *
 * The receiver holds up to FCC_SECOC_CANDIDATES secured frames per PDU until an
 * authenticator arrives, and accepts the one whose MAC verifies: a forged frame
 * squeezed between a genuine frame and its authenticator is dropped without
 * taking the genuine one with it.  Only the verified frame goes on to the E2E
 * and range checks (fcc_bus_receive), so forgeries never disturb E2E state.
 *
 *     fcc_secoc_t sec;                                 caller-owned
 *     fcc_secoc_init(&sec, key, trip);
 *     sender:   fcc_secoc_protect(&sec, a, pdu_bytes, 8 * n_pdus, &auth_frame);
 *     receiver: fcc_secoc_hold(&sec, a, frame.data);   a secured frame came
 *               if (fcc_secoc_verify(&sec, a, auth.data, out) == FCC_SECOC_VERIFIED) use(out);
 */
#ifndef FCC_SECOC_H
#define FCC_SECOC_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fcc_bus_msgs.h"
#include "fcc_can.h"
#include "fcc_cmac.h"
#include "fcc_types.h"

#define FCC_SECOC_KEY_BYTES 16u
#define FCC_SECOC_MAC_BYTES 6u       /* 48-bit truncated MAC */
#define FCC_SECOC_FV_TRUNC_BITS 16u  /* freshness bits in the authenticator */
#define FCC_SECOC_WINDOW 1024u       /* acceptance window of the message counter */
#define FCC_SECOC_CANDIDATES 4u      /* secured frames held per PDU awaiting an authenticator */
#define FCC_SECOC_PDU_BYTES (8u * FCC_SECOC_MAX_PDUS)

typedef enum {
    FCC_SECOC_VERIFIED = 0,          /* out holds the authentic frame */
    FCC_SECOC_FRESHNESS_FAILED = 1,  /* not newer than the last accepted, or beyond the window */
    FCC_SECOC_MAC_FAILED = 2,        /* no held frame matches the MAC */
    FCC_SECOC_NO_PDU = 3             /* nothing held for this authenticator */
} fcc_secoc_verdict_t;

typedef struct {
    uint32_t verified;         /* secured frames authenticated */
    uint32_t mac_failed;       /* authenticators whose MAC matched nothing held (incl. NO_PDU) */
    uint32_t freshness_failed; /* authenticators replayed or out of the window */
    uint32_t unpaired;         /* held frames dropped without authentication */
} fcc_secoc_counters_t;

/* One secured PDU: tx counter (last sent) or rx counter (last accepted) and
 * the frames held for its next authenticator (receiver, single-frame PDUs). */
typedef struct {
    uint32_t counter;
    uint8_t n_held;
    uint8_t held[FCC_SECOC_CANDIDATES][8];
} fcc_secoc_chan_t;

typedef struct {
    fcc_cmac_t cmac;
    uint32_t trip;
    fcc_secoc_chan_t chan[FCC_SECOC_N_AUTH];
    fcc_secoc_counters_t cnt;
} fcc_secoc_t;

/* key: 16 bytes; trip: the high half of every freshness value (the fcc's
 * session).  FCC_ERR_ARG on NULL. */
fcc_status_t fcc_secoc_init(fcc_secoc_t *sec, const uint8_t key[FCC_SECOC_KEY_BYTES], uint32_t trip);

/* Index into fcc_secoc_table of the authenticator msg is (true), or of the
 * authenticator of the single-frame PDU msg (true); false otherwise. */
bool fcc_secoc_auth_index(fcc_msg_t msg, uint32_t *index);
bool fcc_secoc_secured_index(fcc_msg_t msg, uint32_t *index);

/* Sender: the next freshness value of PDU `index` and the authenticator frame
 * (identifier, 8 bytes) for pdu[0..len), len = 8 * n_pdus. */
fcc_status_t fcc_secoc_protect(fcc_secoc_t *sec, uint32_t index, const uint8_t *pdu, size_t len,
                               fcc_can_frame_t *auth);

/* Receiver: a secured frame of PDU `index` arrived (8 bytes); the oldest held
 * frame is dropped (unpaired) when FCC_SECOC_CANDIDATES are already held. */
fcc_status_t fcc_secoc_hold(fcc_secoc_t *sec, uint32_t index, const uint8_t data[8]);

/* Receiver: the authenticator of PDU `index` arrived.  VERIFIED: out = the
 * authenticated frame, the held frames older than it are dropped (unpaired).
 * Otherwise the held frames stay (a forged authenticator does not discard a
 * genuine frame).  Counted in sec->cnt. */
fcc_secoc_verdict_t fcc_secoc_verify(fcc_secoc_t *sec, uint32_t index, const uint8_t auth[8],
                                     uint8_t out[8]);

/* Receiver, a PDU of several frames that the caller holds itself (the time
 * master's SYNC + FOLLOW_UP, which the time sync pairs with their receive
 * stamps): the authenticator of PDU `index` is tried against each of the n
 * candidate PDUs cand[i * len .. (i + 1) * len), n <= FCC_SECOC_CANDIDATES,
 * len = 8 * n_pdus of the PDU -- every one tried (the time does not tell which
 * matched).  VERIFIED: *match = the first candidate that verified and the
 * counter moves on; otherwise nothing changes.  Counted in sec->cnt as by
 * fcc_secoc_verify (NO_PDU for n = 0 counts as a MAC failure). */
fcc_secoc_verdict_t fcc_secoc_verify_pdus(fcc_secoc_t *sec, uint32_t index, const uint8_t auth[8],
                                          const uint8_t *cand, uint32_t n, size_t len,
                                          uint32_t *match);

/* The MAC input and tag, for tests and tools: tag = first 6 bytes of the CMAC
 * over data_id | pdu | fv. */
fcc_status_t fcc_secoc_mac(const fcc_cmac_t *cmac, uint16_t data_id, const uint8_t *pdu,
                           size_t len, uint64_t fv, uint8_t tag[FCC_SECOC_MAC_BYTES]);

/* Forget the key. */
void fcc_secoc_wipe(fcc_secoc_t *sec);

#endif /* FCC_SECOC_H */
