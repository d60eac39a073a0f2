/*
 * fuzz_keyfile.c -- libFuzzer: fcc's key-file parser (fcc_keyfile_parse, what
 * fcc_keyfile_read hands the bytes of a regular file of at most FCC_KEYFILE_MAX_BYTES to).
 *
 * Input: the file's bytes, any of them (NULs, no final newline, CR, very long lines).
 * Properties (abort on violation): a refused text leaves the key untouched; an accepted one
 * holds the key as 32 hex digits on a line of its own, so that line alone parses to the same
 * key, and the text with a comment line added still does (comments are ignored).
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fcc_keyfile.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void check(bool ok)
{
    if (!ok) {
        abort();
    }
}

static void hex_line(const uint8_t key[FCC_SECOC_KEY_BYTES], char line[2u * FCC_SECOC_KEY_BYTES + 1u])
{
    static const char digits[] = "0123456789abcdef";
    for (unsigned int i = 0u; i < FCC_SECOC_KEY_BYTES; ++i) {
        line[2u * i] = digits[key[i] >> 4];
        line[2u * i + 1u] = digits[key[i] & 0x0Fu];
    }
    line[2u * FCC_SECOC_KEY_BYTES] = '\n';
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static char text[FCC_KEYFILE_MAX_BYTES + 16u];
    uint8_t key[FCC_SECOC_KEY_BYTES];
    memset(key, 0xA5, sizeof key);
    const char *bytes = (const char *)data;
    if (fcc_keyfile_parse(bytes, size, key) != 0) {
        for (unsigned int i = 0u; i < FCC_SECOC_KEY_BYTES; ++i) {
            check(key[i] == 0xA5u);
        }
        return 0;
    }
    char line[2u * FCC_SECOC_KEY_BYTES + 1u];
    hex_line(key, line);
    uint8_t again[FCC_SECOC_KEY_BYTES];
    check(fcc_keyfile_parse(line, sizeof line, again) == 0 && memcmp(again, key, sizeof key) == 0);
    if (size + 3u <= sizeof text) {
        memcpy(text, "#\n", 2u);
        memcpy(text + 2u, bytes, size);
        check(fcc_keyfile_parse(text, size + 2u, again) == 0 && memcmp(again, key, sizeof key) == 0);
    }
    return 0;
}
