/*
 * fcc_keyfile.c -- key file and trip (see fcc_keyfile.h).
 */
#define _DEFAULT_SOURCE
#include "fcc_keyfile.h"

#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/random.h>

static int hex_value(int c)
{
    if (c >= '0' && c <= '9') {
        return c - '0';
    }
    c = tolower(c);
    return (c >= 'a' && c <= 'f') ? c - 'a' + 10 : -1;
}

int fcc_keyfile_read(const char *path, uint8_t key[FCC_SECOC_KEY_BYTES], char *err, size_t len)
{
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        (void)snprintf(err, len, "--key-file: cannot read '%s': %s", path, strerror(errno));
        return -1;
    }
    char line[256];
    int keys = 0;
    bool bad = false;
    while (fgets(line, sizeof line, f) != NULL) {
        const char *s = line;
        while (isspace((unsigned char)*s)) {
            ++s;
        }
        if (*s == '#' || *s == '\0') {
            continue;
        }
        size_t n = 0u;
        while (hex_value((unsigned char)s[0]) >= 0 && hex_value((unsigned char)s[1]) >= 0 &&
               n < FCC_SECOC_KEY_BYTES) {
            key[n++] = (uint8_t)(16 * hex_value((unsigned char)s[0]) + hex_value((unsigned char)s[1]));
            s += 2;
        }
        while (isspace((unsigned char)*s)) {
            ++s;
        }
        bad = bad || n != FCC_SECOC_KEY_BYTES || *s != '\0';
        ++keys;
    }
    (void)fclose(f);
    if (keys != 1 || bad) {
        memset(key, 0, FCC_SECOC_KEY_BYTES);
        (void)snprintf(err, len, "--key-file: '%s' must hold one line of %u hex digits", path,
                       2u * FCC_SECOC_KEY_BYTES);
        return -1;
    }
    return 0;
}

bool fcc_keyfile_is_test_key(const uint8_t key[FCC_SECOC_KEY_BYTES])
{
    for (unsigned int i = 0u; i < FCC_SECOC_KEY_BYTES; ++i) {
        if (key[i] != i) {
            return false;
        }
    }
    return true;
}

uint32_t fcc_keyfile_random_trip(void)
{
    uint32_t trip = 0u;
    for (int tries = 0; tries < 8 && trip == 0u; ++tries) {
        if (getrandom(&trip, sizeof trip, 0) != (ssize_t)sizeof trip) {
            trip = 0u;
        }
    }
    return trip;
}
