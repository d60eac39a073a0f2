/*
 * fuzz_secoc.c -- libFuzzer: the SecOC receiver (fcc_secoc_hold, fcc_secoc_verify,
 * fcc_secoc_verify_pdus) against a sender with the same key (fcc_secoc_protect).
 *
 * Input: records of FUZZ_SECOC_REC bytes: [0] the operation, [1] the secured PDU
 * (modulo the table; raw for the bad-argument operation), [2..3] parameters, [4..11]
 * bytes (a frame, an authenticator, the seed of a PDU of several frames):
 *   HOLD     a frame held for the PDU's next authenticator;
 *   GENUINE  the sender authenticates a PDU of the input's bytes and the receiver
 *            verifies it -- a single frame held first, or several frames among up to
 *            FCC_SECOC_CANDIDATES candidates of the input (verify_pdus);
 *   FORGED   the input's bytes as the authenticator;
 *   REPLAY   the last genuine authenticator again, its PDU held again;
 *   BADARGS  an index, a candidate count and a length as they come.
 * Properties (abort on violation): a genuine authenticator verifies and yields exactly
 * the bytes it was computed over; the input's own bytes never verify (a 48-bit MAC); a
 * replayed authenticator is refused for its freshness; each verification moves exactly one
 * counter by one, a refused call none; never more than FCC_SECOC_CANDIDATES frames held.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fcc_secoc.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define FUZZ_SECOC_REC 12u
#define TRIP 0x7E57u

enum { OP_HOLD, OP_GENUINE, OP_FORGED, OP_REPLAY, OP_BADARGS, OP_COUNT };

static const uint8_t k_key[FCC_SECOC_KEY_BYTES] = {0, 1, 2, 3, 4, 5, 6, 7,
                                                   8, 9, 10, 11, 12, 13, 14, 15};

typedef struct {
    fcc_secoc_t tx, rx;
    bool have_last;                       /* a genuine authenticator verified */
    uint32_t last_index;
    uint8_t last_auth[8];
    uint8_t last_pdu[FCC_SECOC_PDU_BYTES];
} harness_t;

static void check(bool ok)
{
    if (!ok) {
        abort();
    }
}

static uint32_t verdicts(const fcc_secoc_t *s)
{
    return s->cnt.verified + s->cnt.mac_failed + s->cnt.freshness_failed;
}

static size_t pdu_len(uint32_t index)
{
    return 8u * fcc_secoc_table[index].n_pdus;
}

/* A PDU of index's length from 8 seed bytes (every frame different). */
static void fill_pdu(uint8_t *pdu, size_t len, const uint8_t seed[8], uint8_t salt)
{
    for (size_t i = 0u; i < len; ++i) {
        pdu[i] = (uint8_t)(seed[i % 8u] ^ (uint8_t)(i / 8u) ^ salt);
    }
}

/* The receiver's verdict on auth for the PDU pdu (held first when it is one frame, else
 * among n candidates at position pos, the others derived from the seed). */
static fcc_secoc_verdict_t receive(harness_t *h, uint32_t index, const uint8_t auth[8],
                                   const uint8_t *pdu, uint32_t n, uint32_t pos,
                                   const uint8_t seed[8])
{
    const size_t len = pdu_len(index);
    const uint32_t before = verdicts(&h->rx);
    fcc_secoc_verdict_t v;
    if (len == 8u) {
        check(fcc_secoc_hold(&h->rx, index, pdu) == FCC_OK);
        check(h->rx.chan[index].n_held <= FCC_SECOC_CANDIDATES);
        uint8_t out[8];
        v = fcc_secoc_verify(&h->rx, index, auth, out);
        check(v != FCC_SECOC_VERIFIED || memcmp(out, pdu, 8u) == 0);
    } else {
        uint8_t cand[FCC_SECOC_CANDIDATES * FCC_SECOC_PDU_BYTES];
        for (uint32_t i = 0u; i < n; ++i) {
            fill_pdu(&cand[i * len], len, seed, (uint8_t)(i + 1u));
        }
        memcpy(&cand[pos * len], pdu, len);
        uint32_t match = n;
        v = fcc_secoc_verify_pdus(&h->rx, index, auth, cand, n, len, &match);
        check(v != FCC_SECOC_VERIFIED ||
              (match <= pos && memcmp(&cand[match * len], pdu, len) == 0));
    }
    check(verdicts(&h->rx) == before + 1u);
    return v;
}

static void genuine(harness_t *h, uint32_t index, const uint8_t *r)
{
    const size_t len = pdu_len(index);
    const uint32_t n = 1u + r[2] % FCC_SECOC_CANDIDATES;
    uint8_t pdu[FCC_SECOC_PDU_BYTES];
    fill_pdu(pdu, len, r + 4, 0u);
    fcc_can_frame_t auth;
    check(fcc_secoc_protect(&h->tx, index, pdu, len, &auth) == FCC_OK && auth.dlc == 8u);
    const fcc_secoc_verdict_t v = receive(h, index, auth.data, pdu, n, r[3] % n, r + 4);
    check(v == FCC_SECOC_VERIFIED);
    h->have_last = true;
    h->last_index = index;
    memcpy(h->last_auth, auth.data, 8u);
    memcpy(h->last_pdu, pdu, len);
}

static void bad_args(harness_t *h, const uint8_t *r)
{
    const uint32_t index = r[1];
    const uint32_t n = r[2];
    const size_t len = r[3];
    if (index < FCC_SECOC_N_AUTH && n <= FCC_SECOC_CANDIDATES && len == pdu_len(index)) {
        return; /* valid: the other operations cover it */
    }
    /* refused before a candidate is read, whatever n and len claim */
    uint8_t cand[FCC_SECOC_CANDIDATES * FCC_SECOC_PDU_BYTES] = {0};
    uint32_t match = 0u;
    const uint32_t before = verdicts(&h->rx);
    check(fcc_secoc_verify_pdus(&h->rx, index, r + 4, cand, n, len, &match) == FCC_SECOC_NO_PDU);
    check(verdicts(&h->rx) == before);
    if (index >= FCC_SECOC_N_AUTH) {
        uint8_t out[8];
        check(fcc_secoc_verify(&h->rx, index, r + 4, out) == FCC_SECOC_NO_PDU);
        check(fcc_secoc_hold(&h->rx, index, r + 4) != FCC_OK);
        check(verdicts(&h->rx) == before);
    }
}

static void run(harness_t *h, const uint8_t *r)
{
    const uint32_t index = r[1] % FCC_SECOC_N_AUTH;
    const size_t len = pdu_len(index);
    uint8_t pdu[FCC_SECOC_PDU_BYTES];
    switch (r[0] % OP_COUNT) {
    case OP_HOLD:
        if (len == 8u) {
            check(fcc_secoc_hold(&h->rx, index, r + 4) == FCC_OK);
            check(h->rx.chan[index].n_held <= FCC_SECOC_CANDIDATES);
        }
        break;
    case OP_GENUINE:
        genuine(h, index, r);
        break;
    case OP_FORGED: {
        const uint32_t n = 1u + r[2] % FCC_SECOC_CANDIDATES;
        fill_pdu(pdu, len, r + 4, 0x5Au);
        check(receive(h, index, r + 4, pdu, n, r[3] % n, r + 4) != FCC_SECOC_VERIFIED);
        break;
    }
    case OP_REPLAY:
        if (h->have_last) {
            check(receive(h, h->last_index, h->last_auth, h->last_pdu, 1u, 0u, r + 4) ==
                  FCC_SECOC_FRESHNESS_FAILED);
        }
        break;
    default:
        bad_args(h, r);
        break;
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static harness_t h; /* static: not on the fuzzer's stack */
    memset(&h, 0, sizeof h);
    check(fcc_secoc_init(&h.tx, k_key, TRIP) == FCC_OK);
    check(fcc_secoc_init(&h.rx, k_key, TRIP) == FCC_OK);
    for (size_t off = 0u; off + FUZZ_SECOC_REC <= size; off += FUZZ_SECOC_REC) {
        run(&h, data + off);
    }
    return 0;
}
