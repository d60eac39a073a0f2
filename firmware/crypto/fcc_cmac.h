/*
 * fcc_cmac.h -- AES-128-CMAC (NIST SP 800-38B, = RFC 4493), one-shot.
 *
 *     fcc_cmac_t cmac;                              caller-owned: round keys + K1, K2
 *     fcc_cmac_init(&cmac, key);                    key schedule and subkeys, once per key
 *     fcc_cmac_compute(&cmac, msg, len, tag);       full 16-byte tag
 *     fcc_cmac_verify(&cmac, msg, len, tag, 6);     truncated tag, compared in constant time
 *
 * Truncation keeps the most significant (first) bytes, as SP 800-38B section 6.2
 * and AUTOSAR SecOC do.
 */
#ifndef FCC_CMAC_H
#define FCC_CMAC_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fcc_aes.h"

#define FCC_CMAC_TAG 16u

typedef struct {
    fcc_aes128_t aes;
    uint8_t k1[FCC_AES_BLOCK]; /* subkey for a complete last block */
    uint8_t k2[FCC_AES_BLOCK]; /* subkey for a padded last block */
} fcc_cmac_t;

/* FCC_ERR_ARG on NULL. */
fcc_status_t fcc_cmac_init(fcc_cmac_t *cmac, const uint8_t key[FCC_AES128_KEY]);

/* tag = CMAC(key, msg[0..len)).  len may be 0 (msg may then be NULL). */
fcc_status_t fcc_cmac_compute(const fcc_cmac_t *cmac, const uint8_t *msg, size_t len,
                              uint8_t tag[FCC_CMAC_TAG]);

/* True when the first tag_len (1..16) bytes of CMAC(key, msg) equal tag; the
 * comparison takes the same time whatever the bytes are.  False on bad arguments. */
bool fcc_cmac_verify(const fcc_cmac_t *cmac, const uint8_t *msg, size_t len,
                     const uint8_t *tag, size_t tag_len);

/* Overwrite keys and subkeys. */
void fcc_cmac_wipe(fcc_cmac_t *cmac);

#endif /* FCC_CMAC_H */
