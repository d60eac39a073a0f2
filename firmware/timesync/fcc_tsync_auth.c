/*
 * fcc_tsync_auth.c -- authenticated receiver of the time master's frames
 * (see fcc_tsync_auth.h).
 */
#include "fcc_tsync_auth.h"

#include <string.h>

fcc_status_t fcc_tsync_auth_init(fcc_tsync_auth_t *ta)
{
    if (ta == NULL) {
        return FCC_ERR_ARG;
    }
    memset(ta, 0, sizeof *ta);
    return FCC_OK;
}

/* Take n held frames out of a list from index `at` on; the later ones move up
 * in order (the pairing reads the lists newest first).  at + n <= *n_held. */
static void take_out(fcc_tsync_held_t *list, uint8_t *n_held, uint32_t at, uint32_t n)
{
    memmove(&list[at], &list[at + n], (size_t)(*n_held - at - n) * sizeof list[0]);
    *n_held = (uint8_t)(*n_held - n);
}

/* How far a held frame's sequence number (byte 2) is from the one expected
 * next, either way, modulo 256 (0..128): 0 for the master's next frame, 1 for
 * the one after it when a pair was lost, ~10 for a replay a second late. */
static uint8_t apart(const fcc_tsync_auth_t *ta, const fcc_tsync_held_t *held)
{
    const uint8_t ahead = (uint8_t)(held->data[2] - ta->expected_seq);
    const uint8_t back = (uint8_t)(ta->expected_seq - held->data[2]);
    return (ahead < back) ? ahead : back;
}

/* The held frame to give up for a new one: once a pair has verified, the one
 * furthest from the expected sequence number, the oldest of equals -- a
 * burst of replayed old frames then pushes out its own kind, not the master's
 * frame awaiting its authenticator (fcc_tsync_auth.h); before, the oldest. */
static uint32_t evictee(const fcc_tsync_auth_t *ta, const fcc_tsync_held_t *list, uint8_t n_held)
{
    uint32_t worst = 0u;
    if (ta->seq_known) {
        for (uint32_t k = 1u; k < n_held; ++k) {
            if (apart(ta, &list[k]) > apart(ta, &list[worst])) {
                worst = k;
            }
        }
    }
    return worst;
}

static fcc_status_t hold(fcc_tsync_auth_t *ta, fcc_tsync_held_t *list, uint8_t *n_held,
                         const uint8_t data[8], uint64_t t_us)
{
    if (ta == NULL || data == NULL) {
        return FCC_ERR_ARG;
    }
    if (*n_held == FCC_TSYNC_AUTH_HELD) {
        take_out(list, n_held, evictee(ta, list, *n_held), 1u);
        ++ta->cnt.unauthenticated;
    }
    memcpy(list[*n_held].data, data, 8u);
    list[*n_held].t_us = t_us;
    ++*n_held;
    return FCC_OK;
}

fcc_status_t fcc_tsync_auth_hold_sync(fcc_tsync_auth_t *ta, const uint8_t data[8], uint64_t t_us)
{
    return (ta == NULL) ? FCC_ERR_ARG : hold(ta, ta->sync, &ta->n_sync, data, t_us);
}

fcc_status_t fcc_tsync_auth_hold_follow_up(fcc_tsync_auth_t *ta, const uint8_t data[8])
{
    return (ta == NULL) ? FCC_ERR_ARG : hold(ta, ta->fup, &ta->n_fup, data, 0u);
}

/* Same master (high nibble of byte 1) and sequence number (byte 2): the
 * DBC's layout of both frames, read before any check. */
static bool same_sync(const uint8_t a[8], const uint8_t b[8])
{
    return (a[1] & 0xF0u) == (b[1] & 0xF0u) && a[2] == b[2];
}

fcc_secoc_verdict_t fcc_tsync_auth_verify(fcc_tsync_auth_t *ta, fcc_secoc_t *sec, uint32_t index,
                                          const uint8_t auth[8], fcc_tsync_held_t *sync,
                                          uint8_t fup[8])
{
    if (ta == NULL || sec == NULL || auth == NULL || sync == NULL || fup == NULL) {
        return FCC_SECOC_NO_PDU;
    }
    uint8_t cand[FCC_SECOC_CANDIDATES][16];
    uint8_t ci[FCC_SECOC_CANDIDATES];
    uint8_t cj[FCC_SECOC_CANDIDATES];
    uint32_t n = 0u;
    for (uint32_t j = ta->n_fup; j-- > 0u && n < FCC_SECOC_CANDIDATES;) {
        for (uint32_t i = ta->n_sync; i-- > 0u && n < FCC_SECOC_CANDIDATES;) {
            if (same_sync(ta->sync[i].data, ta->fup[j].data)) {
                memcpy(&cand[n][0], ta->sync[i].data, 8u);
                memcpy(&cand[n][8], ta->fup[j].data, 8u);
                ci[n] = (uint8_t)i;
                cj[n] = (uint8_t)j;
                ++n;
            }
        }
    }
    uint32_t m = 0u;
    const fcc_secoc_verdict_t v = fcc_secoc_verify_pdus(sec, index, auth, &cand[0][0], n, 16u, &m);
    if (v == FCC_SECOC_FRESHNESS_FAILED) {
        ++ta->cnt.freshness_failed;
    } else if (v != FCC_SECOC_VERIFIED) {
        ++ta->cnt.mac_failed;
    } else {
        *sync = ta->sync[ci[m]];
        memcpy(fup, ta->fup[cj[m]].data, 8u);
        ta->expected_seq = (uint8_t)(sync->data[2] + 1u); /* the master's next pair */
        ta->seq_known = true;
        /* the pair and everything held before it goes; the others were never authenticated */
        ta->cnt.unauthenticated += (uint32_t)ci[m] + (uint32_t)cj[m];
        take_out(ta->sync, &ta->n_sync, 0u, (uint32_t)ci[m] + 1u);
        take_out(ta->fup, &ta->n_fup, 0u, (uint32_t)cj[m] + 1u);
    }
    return v;
}
