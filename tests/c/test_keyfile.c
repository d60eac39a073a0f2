/*
 * test_keyfile.c -- fcc's key file (fcc_keyfile.h): the format, and every file that is
 * not a key file refused without waiting on it or reading it to its end -- a FIFO
 * without a writer, /dev/zero, a directory, a file larger than a key file can be (a
 * sparse gigabyte: refused by its size, not read).
 */
#define _DEFAULT_SOURCE 1 /* mkdtemp, ftruncate */

#include "fcc_test.h"

#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "fcc_keyfile.h"

static const char k_key_line[] = "000102030405060708090a0B0c0D0e0F";

typedef struct {
    char dir[64];
    char path[128];
} scratch_t;

static int scratch_setup(void **state)
{
    static scratch_t sc;
    strcpy(sc.dir, "/tmp/fcc_keyfile_XXXXXX");
    assert_non_null(mkdtemp(sc.dir));
    (void)snprintf(sc.path, sizeof sc.path, "%s/key", sc.dir);
    *state = &sc;
    return 0;
}

static int scratch_teardown(void **state)
{
    scratch_t *sc = *state;
    (void)unlink(sc->path);
    (void)rmdir(sc->path);
    (void)rmdir(sc->dir);
    return 0;
}

static void write_file(const char *path, const char *text, size_t len)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(text, 1u, len, f), len);
    assert_int_equal(fclose(f), 0);
}

static void assert_key_zero(const uint8_t key[FCC_SECOC_KEY_BYTES])
{
    for (unsigned int i = 0u; i < FCC_SECOC_KEY_BYTES; ++i) {
        assert_int_equal(key[i], 0u);
    }
}

/* Refused, key zeroed, one line naming the file and the reason. */
static void assert_refused(const char *path, const char *words)
{
    uint8_t key[FCC_SECOC_KEY_BYTES];
    memset(key, 0xAA, sizeof key);
    char err[256] = "";
    assert_int_equal(fcc_keyfile_read(path, key, err, sizeof err), -1);
    assert_key_zero(key);
    assert_non_null(strstr(err, path));
    assert_non_null(strstr(err, words));
    assert_null(strchr(err, '\n'));
}

static void test_parse_the_format(void **state)
{
    (void)state;
    uint8_t key[FCC_SECOC_KEY_BYTES];
    const char good[] = "# the bus key\n\n  000102030405060708090a0B0c0D0e0F \r\n# end";
    assert_int_equal(fcc_keyfile_parse(good, strlen(good), key), 0);
    assert_true(fcc_keyfile_is_test_key(key));
    assert_int_equal(fcc_keyfile_parse(k_key_line, strlen(k_key_line), key), 0);
    static const char *const bad[] = {
        "",                                                                   /* no key */
        "# only a comment\n",
        "000102030405060708090a0b0c0d0e0\n",                                  /* 31 digits */
        "000102030405060708090a0b0c0d0e0f0\n",                                /* 33 */
        "000102030405060708090a0b0c0d0e0f00\n",                               /* 34 */
        "000102030405060708090a0b0c0d0e0g\n",                                 /* not hex */
        "00 0102030405060708090a0b0c0d0e0f\n",                                /* split */
        "000102030405060708090a0b0c0d0e0f # key\n",                           /* trailing */
        "000102030405060708090a0b0c0d0e0f\n000102030405060708090a0b0c0d0e0f", /* two */
    };
    for (size_t i = 0u; i < sizeof bad / sizeof bad[0]; ++i) {
        memset(key, 0x55, sizeof key);
        assert_int_equal(fcc_keyfile_parse(bad[i], strlen(bad[i]), key), -1);
        assert_int_equal(key[0], 0x55u); /* untouched */
    }
    /* a NUL is a byte like any other: no hex digit, not the end of the text */
    const char nul[] = "000102030405060708090a0b0c0d0e0f\n\0";
    assert_int_equal(fcc_keyfile_parse(nul, sizeof nul - 1u, key), -1);
    assert_int_equal(fcc_keyfile_parse(NULL, 0u, key), -1);
}

static void test_read_a_key_file(void **state)
{
    scratch_t *sc = *state;
    write_file(sc->path, k_key_line, strlen(k_key_line));
    uint8_t key[FCC_SECOC_KEY_BYTES];
    char err[256] = "";
    assert_int_equal(fcc_keyfile_read(sc->path, key, err, sizeof err), 0);
    assert_true(fcc_keyfile_is_test_key(key));
    assert_int_equal(fcc_keyfile_read("tests/keys/secoc_test.key", key, err, sizeof err), 0);
    assert_true(fcc_keyfile_is_test_key(key));
    /* malformed, missing */
    write_file(sc->path, "not a key\n", 10u);
    assert_refused(sc->path, "must hold one line of 32 hex digits");
    (void)unlink(sc->path);
    assert_refused(sc->path, "cannot read");
}

static void test_fifo_refused_without_waiting(void **state)
{
    scratch_t *sc = *state;
    assert_int_equal(mkfifo(sc->path, 0600), 0); /* no writer: a blocking open would hang */
    assert_refused(sc->path, "is a FIFO, not a regular file");
}

static void test_device_refused_unread(void **state)
{
    (void)state;
    assert_refused("/dev/zero", "is a device, not a regular file");
    assert_refused("/dev/null", "is a device, not a regular file");
}

static void test_directory_refused(void **state)
{
    scratch_t *sc = *state;
    assert_int_equal(mkdir(sc->path, 0700), 0);
    assert_refused(sc->path, "is a directory, not a regular file");
}

static void test_oversized_file_refused_by_its_size(void **state)
{
    scratch_t *sc = *state;
    /* one byte too many: a valid key line padded with comment */
    char text[FCC_KEYFILE_MAX_BYTES + 1u];
    memset(text, '#', sizeof text);
    memcpy(text, k_key_line, strlen(k_key_line));
    text[strlen(k_key_line)] = '\n';
    write_file(sc->path, text, FCC_KEYFILE_MAX_BYTES);
    uint8_t key[FCC_SECOC_KEY_BYTES];
    char err[256] = "";
    assert_int_equal(fcc_keyfile_read(sc->path, key, err, sizeof err), 0); /* the limit: fine */
    write_file(sc->path, text, sizeof text);
    assert_refused(sc->path, "has 1025 bytes: a key file has at most 1024");
    /* a sparse gigabyte: its size says so, nothing of it is read */
    FILE *f = fopen(sc->path, "wb");
    assert_non_null(f);
    assert_int_equal(ftruncate(fileno(f), (off_t)1 << 30), 0);
    assert_int_equal(fclose(f), 0);
    assert_refused(sc->path, "has 1073741824 bytes");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parse_the_format),
        cmocka_unit_test_setup_teardown(test_read_a_key_file, scratch_setup, scratch_teardown),
        cmocka_unit_test_setup_teardown(test_fifo_refused_without_waiting, scratch_setup,
                                        scratch_teardown),
        cmocka_unit_test(test_device_refused_unread),
        cmocka_unit_test_setup_teardown(test_directory_refused, scratch_setup, scratch_teardown),
        cmocka_unit_test_setup_teardown(test_oversized_file_refused_by_its_size, scratch_setup,
                                        scratch_teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
