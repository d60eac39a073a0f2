/*
 * test_crypto.c -- AES-128 against FIPS-197 (Appendix B and C.1), AES-CMAC
 * against NIST SP 800-38B Appendix D.1 (subkeys and the four examples), and
 * both against Python's `cryptography` package on random inputs
 * (tests/vectors/crypto/, written by tests/gen_crypto_vectors.py).
 */
#include "fcc_test.h"

#include <stdlib.h>
#include <string.h>

#include "fcc_aes.h"
#include "fcc_cmac.h"

#define VEC_DIR FCC_SOURCE_DIR "/tests/vectors/crypto/"

static void assert_hex(const uint8_t *got, const char *want_hex)
{
    uint8_t want[64];
    const size_t n = fcc_test_hex(want_hex, want, sizeof want);
    assert_memory_equal(got, want, n);
}

static void test_aes_fips197(void **state)
{
    (void)state;
    uint8_t key[16], pt[16], ct[16];
    fcc_aes128_t aes;
    /* Appendix B: the cipher example. */
    fcc_test_hex("2b7e151628aed2a6abf7158809cf4f3c", key, 16);
    fcc_test_hex("3243f6a8885a308d313198a2e0370734", pt, 16);
    fcc_assert_ok(fcc_aes128_init(&aes, key));
    /* Appendix A.1: the last round key of the expansion. */
    assert_hex(&aes.rk[160], "d014f9a8c9ee2589e13f0cc8b6630ca6");
    fcc_assert_ok(fcc_aes128_encrypt(&aes, pt, ct));
    assert_hex(ct, "3925841d02dc09fbdc118597196a0b32");
    /* Appendix C.1: AES-128. */
    fcc_test_hex("000102030405060708090a0b0c0d0e0f", key, 16);
    fcc_test_hex("00112233445566778899aabbccddeeff", pt, 16);
    fcc_assert_ok(fcc_aes128_init(&aes, key));
    fcc_assert_ok(fcc_aes128_encrypt(&aes, pt, pt)); /* in place */
    assert_hex(pt, "69c4e0d86a7b0430d8cdb78070b4c55a");
    assert_int_equal(fcc_aes128_init(NULL, key), FCC_ERR_ARG);
    assert_int_equal(fcc_aes128_encrypt(&aes, NULL, ct), FCC_ERR_ARG);
    fcc_aes128_wipe(&aes);
    for (size_t i = 0; i < sizeof aes.rk; ++i) {
        assert_int_equal(aes.rk[i], 0);
    }
}

static void test_cmac_sp800_38b(void **state)
{
    (void)state;
    uint8_t key[16], msg[64], tag[16];
    fcc_test_hex("2b7e151628aed2a6abf7158809cf4f3c", key, 16);
    fcc_test_hex("6bc1bee22e409f96e93d7e117393172aae2d8a571e03ac9c9eb76fac45af8e51"
        "30c81c46a35ce411e5fbc1191a0a52eff69f2445df4f9b17ad2b417be66c3710", msg, 64);
    fcc_cmac_t c;
    fcc_assert_ok(fcc_cmac_init(&c, key));
    assert_hex(c.k1, "fbeed618357133667c85e08f7236a8de");
    assert_hex(c.k2, "f7ddac306ae266ccf90bc11ee46d513b");
    static const struct {
        size_t len;
        const char *tag;
    } ex[] = {{0u, "bb1d6929e95937287fa37d129b756746"},
              {16u, "070a16b46b4d4144f79bdd9dd04a287c"},
              {40u, "dfa66747de9ae63030ca32611497c827"},
              {64u, "51f0bebf7e3b9d92fc49741779363cfe"}};
    for (size_t i = 0; i < sizeof ex / sizeof ex[0]; ++i) {
        fcc_assert_ok(fcc_cmac_compute(&c, (ex[i].len > 0u) ? msg : NULL, ex[i].len, tag));
        assert_hex(tag, ex[i].tag);
        assert_true(fcc_cmac_verify(&c, msg, ex[i].len, tag, 16u));
        assert_true(fcc_cmac_verify(&c, msg, ex[i].len, tag, 6u));
        tag[5] ^= 0x01u;
        assert_false(fcc_cmac_verify(&c, msg, ex[i].len, tag, 6u));
        assert_true(fcc_cmac_verify(&c, msg, ex[i].len, tag, 5u));
    }
    assert_false(fcc_cmac_verify(&c, msg, 16u, tag, 0u));
    assert_false(fcc_cmac_verify(&c, msg, 16u, tag, 17u));
    assert_int_equal(fcc_cmac_compute(&c, NULL, 3u, tag), FCC_ERR_ARG);
}

/* A line "KEY INPUT EXPECTED" of cmac_random.txt or aes_random.txt (hex; an input
 * "-" is empty): the key and the input bytes, the expected value's hex in want; the
 * input's length. */
static size_t vector_fields(const char *line, uint8_t key[16], uint8_t *in, size_t in_max,
                            char want[40])
{
    char k[40], m[256];
    assert_int_equal(sscanf(line, "%39s %255s %39s", k, m, want), 3);
    fcc_test_hex(k, key, 16);
    return fcc_test_hex(m, in, in_max);
}

/* A line of cmac_random.txt: key, message, its AES-128-CMAC. */
static void cmac_line(const char *line, void *ctx)
{
    (void)ctx;
    uint8_t key[16], msg[128], tag[16];
    char want[40];
    const size_t len = vector_fields(line, key, msg, sizeof msg, want);
    fcc_cmac_t c;
    fcc_assert_ok(fcc_cmac_init(&c, key));
    fcc_assert_ok(fcc_cmac_compute(&c, msg, len, tag));
    assert_hex(tag, want);
}

/* A line of aes_random.txt: key, plaintext block, its AES-128 encryption. */
static void aes_line(const char *line, void *ctx)
{
    (void)ctx;
    uint8_t key[16], pt[16], ct[16];
    char want[40];
    assert_int_equal(vector_fields(line, key, pt, sizeof pt, want), 16u);
    fcc_aes128_t aes;
    fcc_assert_ok(fcc_aes128_init(&aes, key));
    fcc_assert_ok(fcc_aes128_encrypt(&aes, pt, ct));
    assert_hex(ct, want);
}

static void test_against_cryptography(void **state)
{
    (void)state;
    fcc_test_vector_file(VEC_DIR "cmac_random.txt", 200u, cmac_line, NULL);
    fcc_test_vector_file(VEC_DIR "aes_random.txt", 100u, aes_line, NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_aes_fips197),
        cmocka_unit_test(test_cmac_sp800_38b),
        cmocka_unit_test(test_against_cryptography),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
