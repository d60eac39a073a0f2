/*
 * fuzz_tsync_auth.c -- libFuzzer: the time-sync authenticator (fcc_tsync_auth.h), which
 * holds the master's SYNC and FOLLOW_UP frames until its TSYNC_AUTH verifies a pair,
 * against a master with the same key (fcc_secoc_protect over SYNC | FOLLOW_UP).
 *
 * Input: records of FUZZ_TSYNC_REC bytes: [0] the operation, [1..2] the receive stamp's
 * step, [3..10] a frame or an authenticator, [11] a SYNC's master and sequence bits:
 *   SYNC, FOLLOW_UP  a frame held (any bytes; the receiver pairs by master and sequence);
 *   GENUINE          a pair of the input's bytes (the FOLLOW_UP with the SYNC's master and
 *                    sequence) held, then the master's authenticator of it verified;
 *   FORGED           the input's bytes as the authenticator;
 *   REPLAY           the last genuine pair held again, and its authenticator again.
 * Properties (abort on violation): a genuine authenticator verifies and hands out exactly
 * its pair, with the SYNC's own receive stamp; the input's bytes never verify; a replay is
 * refused for its freshness; each verification moves exactly one verdict counter by one;
 * never more than FCC_TSYNC_AUTH_HELD frames of a kind held.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fcc_tsync_auth.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define FUZZ_TSYNC_REC 12u
#define TRIP 0x7E57u

enum { OP_SYNC, OP_FOLLOW_UP, OP_GENUINE, OP_FORGED, OP_REPLAY, OP_COUNT };

static const uint8_t k_key[FCC_SECOC_KEY_BYTES] = {0, 1, 2, 3, 4, 5, 6, 7,
                                                   8, 9, 10, 11, 12, 13, 14, 15};

typedef struct {
    fcc_tsync_auth_t ta;
    fcc_secoc_t master, rx;
    uint32_t index; /* TSYNC_AUTH's PDU */
    uint64_t now_us;
    bool have_last;
    uint8_t last_pair[16];
    uint8_t last_auth[8];
} harness_t;

static void check(bool ok)
{
    if (!ok) {
        abort();
    }
}

static uint32_t verdicts(const harness_t *h)
{
    return h->rx.cnt.verified + h->ta.cnt.mac_failed + h->ta.cnt.freshness_failed;
}

static void held_bounded(const harness_t *h)
{
    check(h->ta.n_sync <= FCC_TSYNC_AUTH_HELD && h->ta.n_fup <= FCC_TSYNC_AUTH_HELD);
}

/* Hold the pair (SYNC stamped now), verify auth: the verdict, checked. */
static fcc_secoc_verdict_t receive(harness_t *h, const uint8_t pair[16], const uint8_t auth[8])
{
    check(fcc_tsync_auth_hold_sync(&h->ta, &pair[0], h->now_us) == FCC_OK);
    check(fcc_tsync_auth_hold_follow_up(&h->ta, &pair[8]) == FCC_OK);
    held_bounded(h);
    const uint32_t before = verdicts(h);
    fcc_tsync_held_t sync;
    uint8_t fup[8];
    const fcc_secoc_verdict_t v = fcc_tsync_auth_verify(&h->ta, &h->rx, h->index, auth, &sync, fup);
    check(verdicts(h) == before + 1u);
    check(v != FCC_SECOC_VERIFIED || (memcmp(sync.data, &pair[0], 8u) == 0 &&
                                      memcmp(fup, &pair[8], 8u) == 0 && sync.t_us == h->now_us));
    held_bounded(h);
    return v;
}

static void run(harness_t *h, const uint8_t *r)
{
    h->now_us += 1u + ((uint32_t)r[1] | (uint32_t)r[2] << 8);
    uint8_t pair[16];
    memcpy(&pair[0], r + 3, 8u);
    memcpy(&pair[8], r + 3, 8u);
    pair[8] = (uint8_t)~pair[8];
    pair[9] = (uint8_t)((pair[1] & 0xF0u) | (r[11] & 0x0Fu)); /* the SYNC's master */
    pair[10] = pair[2];                                        /* and sequence */
    switch (r[0] % OP_COUNT) {
    case OP_SYNC:
        check(fcc_tsync_auth_hold_sync(&h->ta, r + 3, h->now_us) == FCC_OK);
        break;
    case OP_FOLLOW_UP:
        check(fcc_tsync_auth_hold_follow_up(&h->ta, r + 3) == FCC_OK);
        break;
    case OP_GENUINE: {
        fcc_can_frame_t auth;
        check(fcc_secoc_protect(&h->master, h->index, pair, sizeof pair, &auth) == FCC_OK);
        check(receive(h, pair, auth.data) == FCC_SECOC_VERIFIED);
        h->have_last = true;
        memcpy(h->last_pair, pair, sizeof pair);
        memcpy(h->last_auth, auth.data, 8u);
        break;
    }
    case OP_FORGED:
        check(receive(h, pair, r + 3) != FCC_SECOC_VERIFIED);
        break;
    default:
        if (h->have_last) {
            check(receive(h, h->last_pair, h->last_auth) == FCC_SECOC_FRESHNESS_FAILED);
        }
        break;
    }
    held_bounded(h);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static harness_t h; /* static: not on the fuzzer's stack */
    memset(&h, 0, sizeof h);
    check(fcc_tsync_auth_init(&h.ta) == FCC_OK);
    check(fcc_secoc_init(&h.master, k_key, TRIP) == FCC_OK);
    check(fcc_secoc_init(&h.rx, k_key, TRIP) == FCC_OK);
    check(fcc_secoc_auth_index(FCC_MSG_TSYNC_AUTH, &h.index));
    check(fcc_secoc_table[h.index].n_pdus == 2u);
    for (size_t off = 0u; off + FUZZ_TSYNC_REC <= size; off += FUZZ_TSYNC_REC) {
        run(&h, data + off);
    }
    return 0;
}
