/*
 * fcc_keyfile.c -- key file and trip (see fcc_keyfile.h).
 */
#define _DEFAULT_SOURCE
#include "fcc_keyfile.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

static int hex_value(char ch)
{
    const int c = (unsigned char)ch;
    if (c >= '0' && c <= '9') {
        return c - '0';
    }
    if (c >= 'a' && c <= 'f') {
        return c - 'a' + 10;
    }
    return (c >= 'A' && c <= 'F') ? c - 'A' + 10 : -1;
}

/* White space within a line (a line ends at '\n'). */
static bool is_blank(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/* The line [s, e): 1 a key line (into key), 0 a blank or comment line, -1 anything else. */
static int parse_line(const char *s, const char *e, uint8_t key[FCC_SECOC_KEY_BYTES])
{
    while (s < e && is_blank(*s)) {
        ++s;
    }
    if (s == e || *s == '#') {
        return 0;
    }
    size_t n = 0u;
    while (n < FCC_SECOC_KEY_BYTES && e - s >= 2 && hex_value(s[0]) >= 0 && hex_value(s[1]) >= 0) {
        key[n++] = (uint8_t)(16 * hex_value(s[0]) + hex_value(s[1]));
        s += 2;
    }
    while (s < e && is_blank(*s)) {
        ++s;
    }
    return (n == FCC_SECOC_KEY_BYTES && s == e) ? 1 : -1;
}

int fcc_keyfile_parse(const char *text, size_t len, uint8_t key[FCC_SECOC_KEY_BYTES])
{
    if (text == NULL || key == NULL) {
        return -1;
    }
    uint8_t found[FCC_SECOC_KEY_BYTES];
    int keys = 0;
    bool bad = false;
    const char *end = text + len;
    for (const char *s = text; s < end && !bad;) {
        const char *nl = memchr(s, '\n', (size_t)(end - s));
        const char *e = (nl != NULL) ? nl : end;
        const int r = parse_line(s, e, found);
        bad = r < 0;
        keys += (r > 0) ? 1 : 0;
        s = (nl != NULL) ? nl + 1 : end;
    }
    const int rc = (!bad && keys == 1) ? 0 : -1;
    if (rc == 0) {
        memcpy(key, found, sizeof found);
    }
    memset(found, 0, sizeof found);
    return rc;
}

/* What a file that is not a regular one is, for the refusal. */
static const char *file_kind(mode_t mode)
{
    if (S_ISDIR(mode)) {
        return "a directory";
    }
    if (S_ISFIFO(mode)) {
        return "a FIFO";
    }
    if (S_ISCHR(mode) || S_ISBLK(mode)) {
        return "a device";
    }
    return S_ISSOCK(mode) ? "a socket" : "not a regular file";
}

/* At most FCC_KEYFILE_MAX_BYTES + 1 bytes of an open regular file into buf: how many,
 * or -1 (errno) on a read error. */
static ssize_t read_bounded(int fd, char *buf, size_t size)
{
    size_t got = 0u;
    while (got < size) {
        const ssize_t r = read(fd, buf + got, size - got);
        if (r < 0 && errno == EINTR) {
            continue;
        }
        if (r < 0) {
            return -1;
        }
        if (r == 0) {
            break;
        }
        got += (size_t)r;
    }
    return (ssize_t)got;
}

/* The file's bytes into buf[0..*n): 0, or -1 with one line in err. */
static int load(const char *path, char *buf, size_t size, size_t *n, char *err, size_t len)
{
    const int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
    if (fd < 0) {
        (void)snprintf(err, len, "--key-file: cannot read '%s': %s", path, strerror(errno));
        return -1;
    }
    struct stat st;
    int rc = -1;
    if (fstat(fd, &st) != 0) {
        (void)snprintf(err, len, "--key-file: cannot read '%s': %s", path, strerror(errno));
    } else if (!S_ISREG(st.st_mode)) {
        (void)snprintf(err, len, "--key-file: '%s' is %s, not a regular file: refused", path,
                       file_kind(st.st_mode));
    } else if (st.st_size > (off_t)FCC_KEYFILE_MAX_BYTES) {
        (void)snprintf(err, len, "--key-file: '%s' has %lld bytes: a key file has at most %u "
                       "(one line of %u hex digits)", path, (long long)st.st_size,
                       FCC_KEYFILE_MAX_BYTES, 2u * FCC_SECOC_KEY_BYTES);
    } else {
        const ssize_t got = read_bounded(fd, buf, size);
        if (got < 0) {
            (void)snprintf(err, len, "--key-file: cannot read '%s': %s", path, strerror(errno));
        } else if ((size_t)got > FCC_KEYFILE_MAX_BYTES) { /* it grew since fstat */
            (void)snprintf(err, len, "--key-file: '%s' has more than %u bytes: not a key file",
                           path, FCC_KEYFILE_MAX_BYTES);
        } else {
            *n = (size_t)got;
            rc = 0;
        }
    }
    (void)close(fd);
    return rc;
}

int fcc_keyfile_read(const char *path, uint8_t key[FCC_SECOC_KEY_BYTES], char *err, size_t len)
{
    char buf[FCC_KEYFILE_MAX_BYTES + 1u];
    size_t n = 0u;
    memset(key, 0, FCC_SECOC_KEY_BYTES);
    int rc = load(path, buf, sizeof buf, &n, err, len);
    if (rc == 0 && fcc_keyfile_parse(buf, n, key) != 0) {
        (void)snprintf(err, len, "--key-file: '%s' must hold one line of %u hex digits", path,
                       2u * FCC_SECOC_KEY_BYTES);
        rc = -1;
    }
    memset(buf, 0, sizeof buf);
    return rc;
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
