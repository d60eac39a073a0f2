/*
 * fcc_cmac.c -- AES-128-CMAC after NIST SP 800-38B (see fcc_cmac.h).
 */
#include "fcc_cmac.h"

#include <string.h>

/* out = in << 1 (as a 128-bit big-endian number), XOR Rb = 0x87 into the last
 * byte when the bit shifted out was 1 (SP 800-38B 6.1), branch-free. */
static void dbl(const uint8_t in[FCC_AES_BLOCK], uint8_t out[FCC_AES_BLOCK])
{
    const uint8_t msb = (uint8_t)(in[0] >> 7);
    for (unsigned int i = 0u; i + 1u < FCC_AES_BLOCK; ++i) {
        out[i] = (uint8_t)((uint8_t)(in[i] << 1) | (uint8_t)(in[i + 1u] >> 7));
    }
    out[FCC_AES_BLOCK - 1u] = (uint8_t)((uint8_t)(in[FCC_AES_BLOCK - 1u] << 1) ^ (uint8_t)(0x87u * msb));
}

fcc_status_t fcc_cmac_init(fcc_cmac_t *cmac, const uint8_t key[FCC_AES128_KEY])
{
    if (cmac == NULL || key == NULL) {
        return FCC_ERR_ARG;
    }
    fcc_status_t st = fcc_aes128_init(&cmac->aes, key);
    uint8_t l[FCC_AES_BLOCK];
    memset(l, 0, sizeof l);
    if (st == FCC_OK) {
        st = fcc_aes128_encrypt(&cmac->aes, l, l); /* L = AES(K, 0^128) */
    }
    dbl(l, cmac->k1);
    dbl(cmac->k1, cmac->k2);
    memset(l, 0, sizeof l);
    return st;
}

fcc_status_t fcc_cmac_compute(const fcc_cmac_t *cmac, const uint8_t *msg, size_t len,
                              uint8_t tag[FCC_CMAC_TAG])
{
    if (cmac == NULL || tag == NULL || (msg == NULL && len > 0u)) {
        return FCC_ERR_ARG;
    }
    /* n blocks, the last one complete or padded with 10...0. */
    const size_t n = (len == 0u) ? 1u : (len + FCC_AES_BLOCK - 1u) / FCC_AES_BLOCK;
    const bool complete = len > 0u && len % FCC_AES_BLOCK == 0u;
    uint8_t x[FCC_AES_BLOCK];
    memset(x, 0, sizeof x);
    fcc_status_t st = FCC_OK;
    for (size_t b = 0u; b + 1u < n && st == FCC_OK; ++b) {
        for (unsigned int i = 0u; i < FCC_AES_BLOCK; ++i) {
            x[i] = (uint8_t)(x[i] ^ msg[FCC_AES_BLOCK * b + i]);
        }
        st = fcc_aes128_encrypt(&cmac->aes, x, x);
    }
    const size_t off = FCC_AES_BLOCK * (n - 1u);
    const size_t rest = len - off;
    const uint8_t *k = complete ? cmac->k1 : cmac->k2;
    for (unsigned int i = 0u; i < FCC_AES_BLOCK; ++i) {
        uint8_t m = 0u;
        if (i < rest) {
            m = msg[off + i];
        } else if (i == rest) {
            m = 0x80u;
        } else {
            /* the padding's zeros: m stays 0 */
        }
        x[i] = (uint8_t)(x[i] ^ m ^ k[i]);
    }
    if (st == FCC_OK) {
        st = fcc_aes128_encrypt(&cmac->aes, x, tag);
    }
    memset(x, 0, sizeof x);
    return st;
}

bool fcc_cmac_verify(const fcc_cmac_t *cmac, const uint8_t *msg, size_t len,
                     const uint8_t *tag, size_t tag_len)
{
    if (tag == NULL || tag_len == 0u || tag_len > FCC_CMAC_TAG) {
        return false;
    }
    uint8_t full[FCC_CMAC_TAG];
    if (fcc_cmac_compute(cmac, msg, len, full) != FCC_OK) {
        return false;
    }
    uint8_t diff = 0u;
    for (size_t i = 0u; i < tag_len; ++i) {
        diff = (uint8_t)(diff | (full[i] ^ tag[i]));
    }
    memset(full, 0, sizeof full);
    return diff == 0u;
}

void fcc_cmac_wipe(fcc_cmac_t *cmac)
{
    if (cmac != NULL) {
        fcc_aes128_wipe(&cmac->aes);
        volatile uint8_t *p1 = cmac->k1;
        volatile uint8_t *p2 = cmac->k2;
        for (unsigned int i = 0u; i < FCC_AES_BLOCK; ++i) {
            p1[i] = 0u;
            p2[i] = 0u;
        }
    }
}
