/*
 * fcc_aes.h -- AES-128 block encryption (FIPS-197), for the CMAC of the
 * SecOC-style authentication (fcc_cmac.h).  Encryption only: CMAC never
 * decrypts.
 *
 *     fcc_aes128_t aes;                         caller-owned, 176 bytes of round keys
 *     fcc_aes128_init(&aes, key);               key schedule, once per key
 *     fcc_aes128_encrypt(&aes, in, out);        one 16-byte block (in may equal out)
 *
 * Side channels: the S-box is a 256-byte table indexed by secret bytes.  On the
 * Cortex-M4F (no data cache, flash/SRAM accesses of uniform latency) a lookup
 * takes the same time for every index; on a cached host CPU it does not, and
 * a co-resident process could in principle learn key bits from cache timing.
 * The host build is the test rig, not the aircraft.  fcc_cmac_verify compares
 * tags in constant time everywhere.
 */
#ifndef FCC_AES_H
#define FCC_AES_H

#include <stdint.h>

#include "fcc_types.h"

#define FCC_AES_BLOCK 16u
#define FCC_AES128_KEY 16u
#define FCC_AES128_ROUNDS 10u

typedef struct {
    uint8_t rk[(FCC_AES128_ROUNDS + 1u) * FCC_AES_BLOCK]; /* round keys 0..10 */
} fcc_aes128_t;

/* Key expansion.  FCC_ERR_ARG on NULL. */
fcc_status_t fcc_aes128_init(fcc_aes128_t *aes, const uint8_t key[FCC_AES128_KEY]);

/* out = AES-128(key, in).  in and out may be the same buffer.  FCC_ERR_ARG on NULL. */
fcc_status_t fcc_aes128_encrypt(const fcc_aes128_t *aes, const uint8_t in[FCC_AES_BLOCK],
                                uint8_t out[FCC_AES_BLOCK]);

/* Overwrite the round keys (call when a key is retired). */
void fcc_aes128_wipe(fcc_aes128_t *aes);

#endif /* FCC_AES_H */
