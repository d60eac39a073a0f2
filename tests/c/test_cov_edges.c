/*
 * Argument checks of the linear algebra's iterative parts and of the crypto
 * (firmware/linalg/fcc_mat_{svd,expm,eig}.c, firmware/crypto), each refusal
 * caused by one argument alone; a zero matrix's singular values; CMAC over a
 * zero-length message and tag lengths at their limits.  The numbers of these
 * modules are tested in test_linalg.c and test_crypto.c.
 */
#include "fcc_test.h"

#include <string.h>

#include "fcc_cmac.h"
#include "fcc_mat.h"

static fcc_mat_svd_ws_t g_svd;
static fcc_mat_expm_ws_t g_expm;
static fcc_mat_eig_ws_t g_eig;
static fcc_real_t g_big[(2 * FCC_MAT_MAX_DIM + 1) * (FCC_MAT_MAX_DIM + 1)];

static void svd_refusals_and_zero(void **state)
{
    (void)state;
    fcc_real_t d[6] = {0, 0, 0, 0, 0, 0};
    fcc_real_t s[3] = {9, 9, 9};
    const fcc_mat_t a = FCC_MAT(3, 2, d);
    const fcc_mat_t no_data = FCC_MAT(3, 2, NULL);
    assert_int_equal(fcc_mat_svd_values(&no_data, s, &g_svd), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_svd_values(&a, NULL, &g_svd), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_svd_values(&a, s, NULL), FCC_ERR_ARG);
    /* too many columns (either orientation), too many rows */
    const fcc_mat_t wide = FCC_MAT(FCC_MAT_MAX_DIM + 1, FCC_MAT_MAX_DIM + 1, g_big);
    const fcc_mat_t tall = FCC_MAT(2 * FCC_MAT_MAX_DIM + 1, 1, g_big);
    assert_int_equal(fcc_mat_svd_values(&wide, s, &g_svd), FCC_ERR_SIZE);
    assert_int_equal(fcc_mat_svd_values(&tall, s, &g_svd), FCC_ERR_SIZE);
    /* a zero matrix: zero singular values, no division by its zero scale */
    fcc_assert_ok(fcc_mat_svd_values(&a, s, &g_svd));
    assert_true(s[0] == 0 && s[1] == 0);
    assert_true(s[2] == 9); /* only min(rows, cols) values written */
}

static void expm_refusals(void **state)
{
    (void)state;
    fcc_real_t d[4] = {0, 1, 0, 0};
    fcc_real_t ed[9];
    const fcc_mat_t a = FCC_MAT(2, 2, d);
    fcc_mat_t e = FCC_MAT(2, 2, ed);
    const fcc_mat_t no_data = FCC_MAT(2, 2, NULL);
    fcc_mat_t e_no_data = FCC_MAT(2, 2, NULL);
    fcc_mat_t alias = FCC_MAT(2, 2, d);
    assert_int_equal(fcc_mat_expm(&no_data, &e, &g_expm), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_expm(&a, &e_no_data, &g_expm), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_expm(&a, &e, NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_expm(&a, &alias, &g_expm), FCC_ERR_ARG);
    const fcc_mat_t wide = FCC_MAT(2, 3, g_big);
    const fcc_mat_t huge = FCC_MAT(FCC_MAT_MAX_DIM + 1, FCC_MAT_MAX_DIM + 1, g_big);
    fcc_mat_t e3 = FCC_MAT(3, 3, ed);
    assert_int_equal(fcc_mat_expm(&wide, &e, &g_expm), FCC_ERR_SIZE);
    assert_int_equal(fcc_mat_expm(&huge, &e, &g_expm), FCC_ERR_SIZE);
    assert_int_equal(fcc_mat_expm(&a, &e3, &g_expm), FCC_ERR_SIZE);
    /* and the nilpotent a: e^a = I + a */
    fcc_assert_ok(fcc_mat_expm(&a, &e, &g_expm));
    const double want[4] = {1, 1, 0, 1};
    fcc_assert_reals_close(ed, want, 4, FCC_TEST_TOL(1e-15, 1e-6), "expm");
}

static void eig_refusals(void **state)
{
    (void)state;
    fcc_real_t d[4] = {2, 0, 0, 3};
    fcc_real_t vd[4];
    fcc_real_t wr[2], wi[2];
    const fcc_mat_t a = FCC_MAT(2, 2, d);
    const fcc_mat_t no_data = FCC_MAT(2, 2, NULL);
    assert_int_equal(fcc_mat_eig(&no_data, wr, wi, NULL, &g_eig), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_eig(&a, NULL, wi, NULL, &g_eig), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_eig(&a, wr, NULL, NULL, &g_eig), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_eig(&a, wr, wi, NULL, NULL), FCC_ERR_ARG);
    const fcc_mat_t wide = FCC_MAT(2, 3, g_big);
    assert_int_equal(fcc_mat_eig(&wide, wr, wi, NULL, &g_eig), FCC_ERR_SIZE);
    /* eigenvectors: into storage of their own */
    fcc_mat_t v_no_data = FCC_MAT(2, 2, NULL);
    fcc_mat_t v_alias = FCC_MAT(2, 2, d);
    assert_int_equal(fcc_mat_eig(&a, wr, wi, &v_no_data, &g_eig), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_eig(&a, wr, wi, &v_alias, &g_eig), FCC_ERR_ARG);
    fcc_mat_t v = FCC_MAT(2, 2, vd);
    fcc_assert_ok(fcc_mat_eig(&a, wr, wi, &v, &g_eig));
    assert_true((wr[0] == 2 && wr[1] == 3) || (wr[0] == 3 && wr[1] == 2));
    assert_true(wi[0] == 0 && wi[1] == 0);
}

static const uint8_t k_key[16] = {0x2b, 0x7e, 0x15, 0x16, 0x28, 0xae, 0xd2, 0xa6,
                                  0xab, 0xf7, 0x15, 0x88, 0x09, 0xcf, 0x4f, 0x3c};

static void crypto_refusals(void **state)
{
    (void)state;
    fcc_aes128_t aes;
    uint8_t in[FCC_AES_BLOCK] = {0};
    uint8_t out[FCC_AES_BLOCK];
    assert_int_equal(fcc_aes128_init(NULL, k_key), FCC_ERR_ARG);
    assert_int_equal(fcc_aes128_init(&aes, NULL), FCC_ERR_ARG);
    fcc_assert_ok(fcc_aes128_init(&aes, k_key));
    assert_int_equal(fcc_aes128_encrypt(NULL, in, out), FCC_ERR_ARG);
    assert_int_equal(fcc_aes128_encrypt(&aes, NULL, out), FCC_ERR_ARG);
    assert_int_equal(fcc_aes128_encrypt(&aes, in, NULL), FCC_ERR_ARG);
    fcc_cmac_t cmac;
    uint8_t tag[FCC_CMAC_TAG];
    assert_int_equal(fcc_cmac_init(NULL, k_key), FCC_ERR_ARG);
    assert_int_equal(fcc_cmac_init(&cmac, NULL), FCC_ERR_ARG);
    fcc_assert_ok(fcc_cmac_init(&cmac, k_key));
    assert_int_equal(fcc_cmac_compute(NULL, in, 1u, tag), FCC_ERR_ARG);
    assert_int_equal(fcc_cmac_compute(&cmac, in, 1u, NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_cmac_compute(&cmac, NULL, 1u, tag), FCC_ERR_ARG);
    /* an empty message may have no buffer: RFC 4493's example 1 */
    static const uint8_t empty_tag[FCC_CMAC_TAG] = {0xbb, 0x1d, 0x69, 0x29, 0xe9, 0x59, 0x37, 0x28,
                                                    0x7f, 0xa3, 0x7d, 0x12, 0x9b, 0x75, 0x67, 0x46};
    fcc_assert_ok(fcc_cmac_compute(&cmac, NULL, 0u, tag));
    assert_memory_equal(tag, empty_tag, FCC_CMAC_TAG);
    /* verify: a tag of 1..16 bytes; a missing, empty or too long tag is never "verified" */
    assert_true(fcc_cmac_verify(&cmac, NULL, 0u, empty_tag, FCC_CMAC_TAG));
    assert_true(fcc_cmac_verify(&cmac, NULL, 0u, empty_tag, 1u));
    assert_false(fcc_cmac_verify(&cmac, NULL, 0u, NULL, FCC_CMAC_TAG));
    assert_false(fcc_cmac_verify(&cmac, NULL, 0u, empty_tag, 0u));
    assert_false(fcc_cmac_verify(&cmac, NULL, 0u, empty_tag, FCC_CMAC_TAG + 1u));
    assert_false(fcc_cmac_verify(NULL, NULL, 0u, empty_tag, FCC_CMAC_TAG));
    fcc_cmac_wipe(&cmac);
    fcc_cmac_wipe(NULL);
    fcc_aes128_wipe(NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(svd_refusals_and_zero),
        cmocka_unit_test(expm_refusals),
        cmocka_unit_test(eig_refusals),
        cmocka_unit_test(crypto_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
