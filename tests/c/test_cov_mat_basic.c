/*
 * The matrix basics (firmware/linalg/fcc_mat_basic.c) at their edges: each
 * way a descriptor is unusable, each size mismatch and each forbidden alias,
 * one at a time, for every operation; the norms' degenerate inputs.  The
 * values of the operations are in test_linalg.c; here a few by hand.
 */
#include "fcc_test.h"

#include <math.h>
#include <string.h>

#include "fcc_mat.h"

static fcc_real_t g_a[16];
static fcc_real_t g_b[16];
static fcc_real_t g_c[16];

/* The three ways a descriptor over real storage is unusable. */
static void unusable(fcc_mat_t out[3], uint16_t rows, uint16_t cols, fcc_real_t *data)
{
    out[0] = FCC_MAT(rows, cols, NULL);
    out[1] = FCC_MAT(0, cols, data);
    out[2] = FCC_MAT(rows, 0, data);
}

static void init_and_unusable_descriptors(void **state)
{
    (void)state;
    fcc_mat_t m;
    assert_int_equal(fcc_mat_init(NULL, 2, 2, g_a), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_init(&m, 2, 2, NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_init(&m, 0, 2, g_a), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_init(&m, 2, 0, g_a), FCC_ERR_ARG);
    fcc_assert_ok(fcc_mat_init(&m, 2, 3, g_a));
    assert_int_equal(m.rows, 2);
    assert_int_equal(m.cols, 3);
    fcc_mat_t bad[3];
    unusable(bad, 2, 2, g_a);
    fcc_real_t v = 0;
    assert_int_equal(fcc_mat_zero(NULL), FCC_ERR_ARG);
    for (int i = 0; i < 3; ++i) {
        assert_int_equal(fcc_mat_zero(&bad[i]), FCC_ERR_ARG);
        assert_int_equal(fcc_mat_identity(&bad[i]), FCC_ERR_ARG);
        assert_int_equal(fcc_mat_symmetrize(&bad[i]), FCC_ERR_ARG);
        assert_int_equal(fcc_mat_check_finite(&bad[i]), FCC_ERR_ARG);
        assert_int_equal(fcc_mat_norm_1(&bad[i], &v), FCC_ERR_ARG);
        assert_int_equal(fcc_mat_norm_inf(&bad[i], &v), FCC_ERR_ARG);
        assert_int_equal(fcc_mat_norm_max(&bad[i], &v), FCC_ERR_ARG);
        assert_int_equal(fcc_mat_norm_fro(&bad[i], &v), FCC_ERR_ARG);
    }
    const fcc_mat_t a = FCC_MAT(2, 2, g_a);
    assert_int_equal(fcc_mat_norm_1(&a, NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_norm_inf(&a, NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_norm_max(&a, NULL), FCC_ERR_ARG);
    fcc_mat_t wide = FCC_MAT(2, 3, g_a);
    assert_int_equal(fcc_mat_identity(&wide), FCC_ERR_SIZE);
    assert_int_equal(fcc_mat_symmetrize(&wide), FCC_ERR_SIZE);
}

/* f(x, y, z) for every one of x, y, z unusable (the others fine), and for each size mismatch. */
static void binary_operations_refuse(void **state)
{
    (void)state;
    const fcc_mat_t a = FCC_MAT(2, 2, g_a);
    const fcc_mat_t b = FCC_MAT(2, 2, g_b);
    fcc_mat_t c = FCC_MAT(2, 2, g_c);
    fcc_mat_t bad[3];
    unusable(bad, 2, 2, g_c);
    for (int i = 0; i < 3; ++i) {
        assert_int_equal(fcc_mat_copy(&bad[i], &c), FCC_ERR_ARG);
        assert_int_equal(fcc_mat_copy(&a, &bad[i]), FCC_ERR_ARG);
        assert_int_equal(fcc_mat_add(&bad[i], &b, &c), FCC_ERR_ARG);
        assert_int_equal(fcc_mat_add(&a, &bad[i], &c), FCC_ERR_ARG);
        assert_int_equal(fcc_mat_sub(&a, &b, &bad[i]), FCC_ERR_ARG);
        assert_int_equal(fcc_mat_scale(&bad[i], 2, &c), FCC_ERR_ARG);
        assert_int_equal(fcc_mat_scale(&a, 2, &bad[i]), FCC_ERR_ARG);
        assert_int_equal(fcc_mat_trans(&bad[i], &c), FCC_ERR_ARG);
        assert_int_equal(fcc_mat_trans(&a, &bad[i]), FCC_ERR_ARG);
        assert_int_equal(fcc_mat_mul(&bad[i], &b, &c), FCC_ERR_ARG);
        assert_int_equal(fcc_mat_mul(&a, &bad[i], &c), FCC_ERR_ARG);
        assert_int_equal(fcc_mat_mul(&a, &b, &bad[i]), FCC_ERR_ARG);
        assert_int_equal(fcc_mat_get_block(&bad[i], 0, 0, &c), FCC_ERR_ARG);
        assert_int_equal(fcc_mat_get_block(&a, 0, 0, &bad[i]), FCC_ERR_ARG);
        assert_int_equal(fcc_mat_set_block(&bad[i], 0, 0, &a), FCC_ERR_ARG);
        assert_int_equal(fcc_mat_set_block(&c, 0, 0, &bad[i]), FCC_ERR_ARG);
        fcc_real_t v = 0;
        assert_int_equal(fcc_mat_rel_diff(&bad[i], &b, &v), FCC_ERR_ARG);
        assert_int_equal(fcc_mat_rel_diff(&a, &bad[i], &v), FCC_ERR_ARG);
    }
    fcc_real_t v = 0;
    assert_int_equal(fcc_mat_rel_diff(&a, &b, NULL), FCC_ERR_ARG);
    /* size mismatches: rows only, then columns only */
    fcc_mat_t tall = FCC_MAT(3, 2, g_c);
    fcc_mat_t wide = FCC_MAT(2, 3, g_c);
    const fcc_mat_t tall_b = FCC_MAT(3, 2, g_b);
    const fcc_mat_t wide_b = FCC_MAT(2, 3, g_b);
    assert_int_equal(fcc_mat_copy(&a, &tall), FCC_ERR_SIZE);
    assert_int_equal(fcc_mat_copy(&a, &wide), FCC_ERR_SIZE);
    assert_int_equal(fcc_mat_add(&a, &tall_b, &c), FCC_ERR_SIZE);
    assert_int_equal(fcc_mat_add(&a, &wide_b, &c), FCC_ERR_SIZE);
    assert_int_equal(fcc_mat_sub(&a, &b, &tall), FCC_ERR_SIZE);
    assert_int_equal(fcc_mat_scale(&a, 2, &wide), FCC_ERR_SIZE);
    assert_int_equal(fcc_mat_rel_diff(&a, &tall_b, &v), FCC_ERR_SIZE);
    /* a transpose needs c = cols x rows of a, and no alias */
    const fcc_mat_t a23 = FCC_MAT(2, 3, g_a);
    fcc_mat_t c23 = FCC_MAT(2, 3, g_c);
    fcc_mat_t c22 = FCC_MAT(2, 2, g_c);
    fcc_mat_t c33 = FCC_MAT(3, 3, g_c);
    fcc_mat_t alias = FCC_MAT(3, 2, g_a);
    assert_int_equal(fcc_mat_trans(&a23, &alias), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_trans(&a23, &c23), FCC_ERR_SIZE); /* rows wrong */
    assert_int_equal(fcc_mat_trans(&a23, &c22), FCC_ERR_SIZE); /* rows right, cols wrong */
    assert_int_equal(fcc_mat_trans(&a23, &c33), FCC_ERR_SIZE);
}

static void products_refuse_aliases_and_sizes(void **state)
{
    (void)state;
    const fcc_mat_t a23 = FCC_MAT(2, 3, g_a);
    const fcc_mat_t b32 = FCC_MAT(3, 2, g_b);
    fcc_mat_t c22 = FCC_MAT(2, 2, g_c);
    fcc_mat_t on_a = FCC_MAT(2, 2, g_a);
    fcc_mat_t on_b = FCC_MAT(2, 2, g_b);
    assert_int_equal(fcc_mat_mul(&a23, &b32, &on_a), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_mul(&a23, &b32, &on_b), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_mul(&a23, &a23, &c22), FCC_ERR_SIZE);  /* inner 3 vs 2 */
    fcc_mat_t c32 = FCC_MAT(3, 2, g_c);
    fcc_mat_t c23 = FCC_MAT(2, 3, g_c);
    assert_int_equal(fcc_mat_mul(&a23, &b32, &c32), FCC_ERR_SIZE);  /* rows of c */
    assert_int_equal(fcc_mat_mul(&a23, &b32, &c23), FCC_ERR_SIZE);  /* cols of c */
    /* a^T b and a b^T by hand: a = [1 2 3; 4 5 6] */
    const fcc_real_t av[6] = {1, 2, 3, 4, 5, 6};
    memcpy(g_a, av, sizeof av);
    memcpy(g_b, av, sizeof av);
    const fcc_mat_t b23 = FCC_MAT(2, 3, g_b);
    fcc_mat_t c33 = FCC_MAT(3, 3, g_c);
    fcc_assert_ok(fcc_mat_mul_tn(&a23, &b23, &c33)); /* a^T a */
    const double ata[9] = {17, 22, 27, 22, 29, 36, 27, 36, 45};
    fcc_assert_reals_close(g_c, ata, 9, 0, "a^T a");
    fcc_assert_ok(fcc_mat_mul_nt(&a23, &b23, &c22)); /* a a^T */
    const double aat[4] = {14, 32, 32, 77};
    fcc_assert_reals_close(g_c, aat, 4, 0, "a a^T");
}

static void blocks_stay_inside(void **state)
{
    (void)state;
    const fcc_mat_t a33 = FCC_MAT(3, 3, g_a);
    fcc_mat_t blk = FCC_MAT(2, 2, g_b);
    fcc_mat_t alias = FCC_MAT(2, 2, g_a);
    assert_int_equal(fcc_mat_get_block(&a33, 0, 0, &alias), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_get_block(&a33, 2, 0, &blk), FCC_ERR_SIZE);
    assert_int_equal(fcc_mat_get_block(&a33, 0, 2, &blk), FCC_ERR_SIZE);
    fcc_assert_ok(fcc_mat_get_block(&a33, 1, 1, &blk));
    fcc_mat_t d33 = FCC_MAT(3, 3, g_c);
    const fcc_mat_t on_c = FCC_MAT(2, 2, g_c);
    assert_int_equal(fcc_mat_set_block(&d33, 0, 0, &on_c), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_set_block(&d33, 2, 0, &blk), FCC_ERR_SIZE);
    assert_int_equal(fcc_mat_set_block(&d33, 0, 2, &blk), FCC_ERR_SIZE);
    /* (r0 + rows) computed wide: no wrap of uint16_t lets a block in */
    assert_int_equal(fcc_mat_get_block(&a33, UINT16_MAX, 0, &blk), FCC_ERR_SIZE);
    assert_int_equal(fcc_mat_set_block(&d33, 0, UINT16_MAX, &blk), FCC_ERR_SIZE);
    /* and a copy onto itself is allowed, a no-op */
    for (int i = 0; i < 9; ++i) {
        g_a[i] = (fcc_real_t)i;
    }
    fcc_mat_t self = FCC_MAT(3, 3, g_a);
    fcc_assert_ok(fcc_mat_copy(&a33, &self));
    assert_true(g_a[8] == 8);
}

static void norms_of_degenerate_matrices(void **state)
{
    (void)state;
    fcc_real_t v = -1;
    memset(g_a, 0, sizeof g_a);
    const fcc_mat_t a = FCC_MAT(2, 2, g_a);
    fcc_assert_ok(fcc_mat_norm_fro(&a, &v));
    assert_true(v == 0); /* zero: no division by the zero scale */
    g_a[1] = (fcc_real_t)INFINITY;
    fcc_assert_ok(fcc_mat_norm_fro(&a, &v));
    assert_true(isinf(v));
    /* entries near the largest real: the scaled sum does not overflow */
    const fcc_real_t big = (fcc_real_t)(sizeof(fcc_real_t) == sizeof(double) ? 1e300 : 1e30);
    g_a[0] = big;
    g_a[1] = big;
    fcc_assert_ok(fcc_mat_norm_fro(&a, &v));
    fcc_assert_close(v, (double)big * sqrt(2.0), FCC_TEST_TOL(1e-15, 1e-6), 0);
    /* rel_diff: relative to b's scale; absolute when b is zero; refused when not finite */
    const fcc_real_t av[4] = {1, 2, 3, 4};
    const fcc_real_t bv[4] = {1, 2, 3, 5};
    memcpy(g_a, av, sizeof av);
    memcpy(g_b, bv, sizeof bv);
    const fcc_mat_t b = FCC_MAT(2, 2, g_b);
    fcc_assert_ok(fcc_mat_rel_diff(&a, &b, &v));
    fcc_assert_close(v, 0.2, FCC_TEST_TOL(1e-15, 1e-6), 0);
    memset(g_b, 0, sizeof g_b);
    fcc_assert_ok(fcc_mat_rel_diff(&a, &b, &v));
    fcc_assert_close(v, 4.0, 0, 0);
    g_a[2] = (fcc_real_t)INFINITY; /* the difference is not finite */
    assert_int_equal(fcc_mat_rel_diff(&a, &b, &v), FCC_ERR_NOT_FINITE);
    g_b[2] = (fcc_real_t)INFINITY; /* inf - inf: no finite difference, an infinite scale */
    assert_int_equal(fcc_mat_rel_diff(&a, &b, &v), FCC_ERR_NOT_FINITE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(init_and_unusable_descriptors),
        cmocka_unit_test(binary_operations_refuse),
        cmocka_unit_test(products_refuse_aliases_and_sizes),
        cmocka_unit_test(blocks_stay_inside),
        cmocka_unit_test(norms_of_degenerate_matrices),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
