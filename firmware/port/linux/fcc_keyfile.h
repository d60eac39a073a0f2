/*
 * fcc_keyfile.h -- the bus-authentication key from a file, and a random trip
 * (host only).  Format (dbc/README.md, "Authentication"): one line of 32 hex
 * digits; lines starting with '#' are comments.
 *
 * The file is taken only if it is a regular file of at most FCC_KEYFILE_MAX_BYTES:
 * opened without blocking and without becoming a controlling terminal
 * (O_NONBLOCK | O_NOCTTY), checked with fstat before a byte is read.  A FIFO (which
 * would block, or hang until a writer came), a device (/dev/zero never ends), a
 * directory or a larger file is refused in one line -- never waited on, never read
 * to its end.
 */
#ifndef FCC_KEYFILE_H
#define FCC_KEYFILE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fcc_secoc.h"

/* A key file is one line of 32 hex digits and a few comment lines (the published test
 * key's file has 354 bytes): anything larger is not one. */
#define FCC_KEYFILE_MAX_BYTES 1024u

/* The key in text[0..len) (any bytes; a NUL is just a byte that is no hex digit):
 * 0 and key filled, or -1 with key untouched when the text is not exactly one key line
 * (and comment or blank lines). */
int fcc_keyfile_parse(const char *text, size_t len, uint8_t key[FCC_SECOC_KEY_BYTES]);

/* 0 and key filled, or -1 with key zeroed and one line in err. */
int fcc_keyfile_read(const char *path, uint8_t key[FCC_SECOC_KEY_BYTES], char *err, size_t len);

/* True when key is the published test key (tests/keys/secoc_test.key). */
bool fcc_keyfile_is_test_key(const uint8_t key[FCC_SECOC_KEY_BYTES]);

/* A random non-zero 32-bit trip from getrandom(2); 0 on failure. */
uint32_t fcc_keyfile_random_trip(void);

#endif /* FCC_KEYFILE_H */
