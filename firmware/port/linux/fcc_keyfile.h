/*
 * fcc_keyfile.h -- the bus-authentication key from a file, and a random trip
 * (host only).  Format (dbc/README.md, "Authentication"): one line of 32 hex
 * digits; lines starting with '#' are comments.
 */
#ifndef FCC_KEYFILE_H
#define FCC_KEYFILE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fcc_secoc.h"

/* 0 and key filled, or -1 with one line in err. */
int fcc_keyfile_read(const char *path, uint8_t key[FCC_SECOC_KEY_BYTES], char *err, size_t len);

/* True when key is the published test key (tests/keys/secoc_test.key). */
bool fcc_keyfile_is_test_key(const uint8_t key[FCC_SECOC_KEY_BYTES]);

/* A random non-zero 32-bit trip from getrandom(2); 0 on failure. */
uint32_t fcc_keyfile_random_trip(void);

#endif /* FCC_KEYFILE_H */
