/*
 * fcc_secoc.c -- SecOC-style frame authentication (see fcc_secoc.h).
 */
#include "fcc_secoc.h"

#include <string.h>

#define MAC_INPUT_MAX (2u + FCC_SECOC_PDU_BYTES + 8u)
#define TRUNC_MASK ((1uL << FCC_SECOC_FV_TRUNC_BITS) - 1u)

fcc_status_t fcc_secoc_init(fcc_secoc_t *sec, const uint8_t key[FCC_SECOC_KEY_BYTES], uint32_t trip)
{
    if (sec == NULL || key == NULL) {
        return FCC_ERR_ARG;
    }
    memset(sec, 0, sizeof *sec);
    sec->trip = trip;
    return fcc_cmac_init(&sec->cmac, key);
}

bool fcc_secoc_auth_index(fcc_msg_t msg, uint32_t *index)
{
    for (uint32_t i = 0u; i < FCC_SECOC_N_AUTH; ++i) {
        if (fcc_secoc_table[i].auth == msg) {
            if (index != NULL) {
                *index = i;
            }
            return true;
        }
    }
    return false;
}

bool fcc_secoc_secured_index(fcc_msg_t msg, uint32_t *index)
{
    for (uint32_t i = 0u; i < FCC_SECOC_N_AUTH; ++i) {
        if (fcc_secoc_table[i].n_pdus == 1u && fcc_secoc_table[i].pdus[0] == msg) {
            if (index != NULL) {
                *index = i;
            }
            return true;
        }
    }
    return false;
}

fcc_status_t fcc_secoc_mac(const fcc_cmac_t *cmac, uint16_t data_id, const uint8_t *pdu,
                           size_t len, uint64_t fv, uint8_t tag[FCC_SECOC_MAC_BYTES])
{
    if (cmac == NULL || pdu == NULL || tag == NULL || len > FCC_SECOC_PDU_BYTES) {
        return FCC_ERR_ARG;
    }
    uint8_t in[MAC_INPUT_MAX];
    in[0] = (uint8_t)(data_id >> 8);
    in[1] = (uint8_t)(data_id & 0xFFu);
    memcpy(&in[2], pdu, len);
    for (unsigned int i = 0u; i < 8u; ++i) {
        in[2u + len + i] = (uint8_t)(fv >> (56u - 8u * i));
    }
    uint8_t full[FCC_CMAC_TAG];
    const fcc_status_t st = fcc_cmac_compute(cmac, in, 2u + len + 8u, full);
    memcpy(tag, full, FCC_SECOC_MAC_BYTES);
    return st;
}

static uint64_t full_fv(uint32_t trip, uint32_t counter)
{
    return ((uint64_t)trip << 32) | counter;
}

fcc_status_t fcc_secoc_protect(fcc_secoc_t *sec, uint32_t index, const uint8_t *pdu, size_t len,
                               fcc_can_frame_t *auth)
{
    if (sec == NULL || pdu == NULL || auth == NULL || index >= FCC_SECOC_N_AUTH ||
        len != 8u * fcc_secoc_table[index].n_pdus) {
        return FCC_ERR_ARG;
    }
    const fcc_secoc_desc_t *d = &fcc_secoc_table[index];
    fcc_secoc_chan_t *c = &sec->chan[index];
    const uint32_t counter = c->counter + 1u;
    uint8_t tag[FCC_SECOC_MAC_BYTES];
    const fcc_status_t st = fcc_secoc_mac(&sec->cmac, d->data_id, pdu, len,
                                          full_fv(sec->trip, counter), tag);
    if (st != FCC_OK) {
        return st;
    }
    c->counter = counter;
    memset(auth, 0, sizeof *auth);
    auth->id = fcc_bus_msg_table[d->auth].id;
    auth->dlc = 8u;
    auth->data[0] = (uint8_t)(counter & 0xFFu);
    auth->data[1] = (uint8_t)((counter >> 8) & 0xFFu);
    memcpy(&auth->data[2], tag, FCC_SECOC_MAC_BYTES);
    return FCC_OK;
}

/* Drop the held frames 0..n-1 (the oldest n). */
static void drop_oldest(fcc_secoc_chan_t *c, uint32_t n)
{
    if (n >= c->n_held) {
        c->n_held = 0u;
        return;
    }
    memmove(c->held[0], c->held[n], (size_t)(c->n_held - n) * sizeof c->held[0]);
    c->n_held = (uint8_t)(c->n_held - n);
}

fcc_status_t fcc_secoc_hold(fcc_secoc_t *sec, uint32_t index, const uint8_t data[8])
{
    if (sec == NULL || data == NULL || index >= FCC_SECOC_N_AUTH) {
        return FCC_ERR_ARG;
    }
    fcc_secoc_chan_t *c = &sec->chan[index];
    if (c->n_held == FCC_SECOC_CANDIDATES) {
        drop_oldest(c, 1u);
        ++sec->cnt.unpaired;
    }
    memcpy(c->held[c->n_held], data, 8u);
    ++c->n_held;
    return FCC_OK;
}

/* The freshness value an authenticator stands for: the smallest counter above
 * the last accepted one with its 16 low bits, within the window. */
static bool fresh_counter(const fcc_secoc_chan_t *c, const uint8_t auth[8], uint32_t *counter)
{
    const uint32_t trunc = (uint32_t)auth[0] | ((uint32_t)auth[1] << 8);
    uint64_t cand = ((uint64_t)c->counter & ~(uint64_t)TRUNC_MASK) | trunc;
    if (cand <= c->counter) {
        cand += (uint64_t)TRUNC_MASK + 1u;
    }
    if (cand - c->counter > FCC_SECOC_WINDOW || cand > UINT32_MAX) {
        return false;
    }
    *counter = (uint32_t)cand;
    return true;
}

/* Try every candidate (no early exit); the index of the first that matched, or n. */
static uint32_t find_match(const fcc_secoc_t *sec, uint32_t index, const uint8_t auth[8],
                           const uint8_t *cand, uint32_t n, size_t len, uint32_t counter)
{
    const uint64_t fv = full_fv(sec->trip, counter);
    const uint16_t data_id = fcc_secoc_table[index].data_id;
    uint32_t match = n;
    for (uint32_t i = 0u; i < n; ++i) {
        uint8_t tag[FCC_SECOC_MAC_BYTES];
        if (fcc_secoc_mac(&sec->cmac, data_id, &cand[i * len], len, fv, tag) != FCC_OK) {
            continue;
        }
        uint8_t diff = 0u;
        for (unsigned int b = 0u; b < FCC_SECOC_MAC_BYTES; ++b) {
            diff = (uint8_t)(diff | (tag[b] ^ auth[2u + b]));
        }
        if (diff == 0u && match == n) {
            match = i;
        }
    }
    return match;
}

/* The verdict on n candidates (each len bytes) for one authenticator: a fresh counter, then
 * the first candidate whose MAC matches (*match); the channel's counter moves on only then.
 * Every refusal is counted. */
static fcc_secoc_verdict_t authenticate(fcc_secoc_t *sec, uint32_t index, const uint8_t auth[8],
                                        const uint8_t *cand, uint32_t n, size_t len, uint32_t *match)
{
    fcc_secoc_chan_t *c = &sec->chan[index];
    uint32_t counter = 0u;
    if (!fresh_counter(c, auth, &counter)) {
        ++sec->cnt.freshness_failed;
        return FCC_SECOC_FRESHNESS_FAILED;
    }
    if (n == 0u) {
        ++sec->cnt.mac_failed;
        return FCC_SECOC_NO_PDU;
    }
    const uint32_t m = find_match(sec, index, auth, cand, n, len, counter);
    if (m == n) {
        ++sec->cnt.mac_failed;
        return FCC_SECOC_MAC_FAILED;
    }
    *match = m;
    c->counter = counter;
    ++sec->cnt.verified;
    return FCC_SECOC_VERIFIED;
}

fcc_secoc_verdict_t fcc_secoc_verify(fcc_secoc_t *sec, uint32_t index, const uint8_t auth[8],
                                     uint8_t out[8])
{
    if (sec == NULL || auth == NULL || out == NULL || index >= FCC_SECOC_N_AUTH) {
        return FCC_SECOC_NO_PDU;
    }
    fcc_secoc_chan_t *c = &sec->chan[index];
    uint32_t match = 0u;
    const fcc_secoc_verdict_t v = authenticate(sec, index, auth, &c->held[0][0], c->n_held, 8u, &match);
    if (v == FCC_SECOC_VERIFIED) {
        memcpy(out, c->held[match], 8u);
        sec->cnt.unpaired += match; /* older held frames: never authenticated */
        drop_oldest(c, match + 1u);
    }
    return v;
}

fcc_secoc_verdict_t fcc_secoc_verify_pdus(fcc_secoc_t *sec, uint32_t index, const uint8_t auth[8],
                                          const uint8_t *cand, uint32_t n, size_t len,
                                          uint32_t *match)
{
    if (sec == NULL || auth == NULL || match == NULL || index >= FCC_SECOC_N_AUTH ||
        n > FCC_SECOC_CANDIDATES || (n > 0u && cand == NULL) ||
        len != 8u * fcc_secoc_table[index].n_pdus) {
        return FCC_SECOC_NO_PDU;
    }
    return authenticate(sec, index, auth, cand, n, len, match);
}

void fcc_secoc_wipe(fcc_secoc_t *sec)
{
    if (sec != NULL) {
        fcc_cmac_wipe(&sec->cmac);
    }
}
