/*
 * LU, Cholesky and the inverse (firmware/linalg/fcc_mat_lu.c) at their edges:
 * every refusal of a bad argument with its status, pivoting that must
 * exchange rows, a factorisation forged out of range, and the condition
 * estimate of a degenerate factor.  The numerical cases are in test_linalg.c.
 */
#include "fcc_test.h"

#include <math.h>
#include <string.h>

#include "fcc_mat.h"

static fcc_mat_lu_t g_lu;

/* A 3x3 that needs a row exchange at every step (pivots 0 on the diagonal). */
static const fcc_real_t pivoting[9] = {0, 2, 1, 1, 0, 3, 4, 1, 0};

/* max_i |(A x - b)_i| (or A^T x with trans) of a 3x3, computed in double. */
static double residual3(const fcc_real_t *a, const fcc_real_t *x, const fcc_real_t *b, bool trans)
{
    double worst = 0.0;
    for (int i = 0; i < 3; ++i) {
        double s = 0.0;
        for (int j = 0; j < 3; ++j) {
            s += (double)(trans ? a[j * 3 + i] : a[i * 3 + j]) * (double)x[j];
        }
        worst = fmax(worst, fabs(s - (double)b[i]));
    }
    return worst;
}

static void factor_pivots_every_column(void **state)
{
    (void)state;
    fcc_real_t d[9];
    memcpy(d, pivoting, sizeof d);
    const fcc_mat_t a = FCC_MAT(3, 3, d);
    fcc_assert_ok(fcc_mat_lu_factor(&g_lu, &a));
    /* |4| is the largest in column 0 (row 2), then |2| of old row 0 */
    assert_int_equal(g_lu.perm[0], 2);
    assert_int_equal(g_lu.perm[1], 0);
    assert_int_equal(g_lu.perm[2], 1);
    /* the multipliers of L are at most 1 in magnitude under partial pivoting */
    for (int i = 1; i < 3; ++i) {
        for (int j = 0; j < i; ++j) {
            assert_true(fabs((double)g_lu.lu[i * 3 + j]) <= 1.0);
        }
    }
    fcc_real_t bd[3] = {3, 4, 5};
    fcc_real_t xd[3];
    const fcc_mat_t b = FCC_MAT(3, 1, bd);
    fcc_mat_t x = FCC_MAT(3, 1, xd);
    fcc_assert_ok(fcc_mat_lu_solve(&g_lu, &b, &x));
    assert_true(residual3(pivoting, xd, bd, false) < FCC_TEST_TOL(1e-14, 1e-5));
    fcc_assert_ok(fcc_mat_lu_solve_trans(&g_lu, &b, &x));
    assert_true(residual3(pivoting, xd, bd, true) < FCC_TEST_TOL(1e-14, 1e-5));
    /* the input is left as it was */
    assert_memory_equal(d, pivoting, sizeof d);
}

static void factor_refuses_bad_input(void **state)
{
    (void)state;
    fcc_real_t d[6] = {1, 2, 3, 4, 5, 6};
    const fcc_mat_t square = FCC_MAT(2, 2, d);
    const fcc_mat_t wide = FCC_MAT(2, 3, d);
    const fcc_mat_t no_data = FCC_MAT(2, 2, NULL);
    assert_int_equal(fcc_mat_lu_factor(NULL, &square), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_lu_factor(&g_lu, NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_lu_factor(&g_lu, &no_data), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_lu_factor(&g_lu, &wide), FCC_ERR_SIZE);
    /* a zero matrix has no pivot at all; a zero column none at its step */
    fcc_real_t z[4] = {0, 0, 0, 0};
    const fcc_mat_t zero = FCC_MAT(2, 2, z);
    assert_int_equal(fcc_mat_lu_factor(&g_lu, &zero), FCC_ERR_SINGULAR);
    fcc_real_t c[4] = {1, 0, 2, 0};
    const fcc_mat_t zero_col = FCC_MAT(2, 2, c);
    assert_int_equal(fcc_mat_lu_factor(&g_lu, &zero_col), FCC_ERR_SINGULAR);
    fcc_real_t xd[2];
    fcc_mat_t x = FCC_MAT(2, 1, xd);
    const fcc_mat_t b = FCC_MAT(2, 1, d);
    assert_int_equal(fcc_mat_solve(&zero_col, &b, &x, &g_lu), FCC_ERR_SINGULAR);
}

static void solve_refuses_bad_arguments(void **state)
{
    (void)state;
    fcc_real_t d[9];
    memcpy(d, pivoting, sizeof d);
    const fcc_mat_t a = FCC_MAT(3, 3, d);
    fcc_assert_ok(fcc_mat_lu_factor(&g_lu, &a));
    fcc_real_t bd[6] = {1, 2, 3, 4, 5, 6};
    fcc_real_t xd[6];
    const fcc_mat_t b = FCC_MAT(3, 1, bd);
    fcc_mat_t x = FCC_MAT(3, 1, xd);
    fcc_mat_t no_data = FCC_MAT(3, 1, NULL);
    const fcc_mat_t b2 = FCC_MAT(2, 1, bd);
    fcc_mat_t x2 = FCC_MAT(3, 2, xd);
    assert_int_equal(fcc_mat_lu_solve(NULL, &b, &x), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_lu_solve(&g_lu, &no_data, &x), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_lu_solve(&g_lu, &b, &no_data), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_lu_solve_trans(&g_lu, NULL, &x), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_lu_solve(&g_lu, &b2, &x), FCC_ERR_SIZE);   /* rows != n */
    assert_int_equal(fcc_mat_lu_solve(&g_lu, &b, &x2), FCC_ERR_SIZE);   /* b, x differ */
    assert_int_equal(fcc_mat_lu_solve_trans(&g_lu, &b, &x2), FCC_ERR_SIZE);
    /* a right-hand side that overflows is reported, not returned as a solution */
    fcc_real_t big[3] = {(fcc_real_t)INFINITY, 0, 0};
    const fcc_mat_t binf = FCC_MAT(3, 1, big);
    assert_int_equal(fcc_mat_lu_solve(&g_lu, &binf, &x), FCC_ERR_NOT_FINITE);
}

/* A factorisation that was never made (n = 0) or forged beyond the workspace is refused by
 * every function that reads one. */
static void forged_factorisation_is_refused(void **state)
{
    (void)state;
    static fcc_mat_lu_t lu;
    fcc_real_t bd[3] = {1, 2, 3};
    fcc_real_t xd[3];
    const fcc_mat_t b = FCC_MAT(3, 1, bd);
    fcc_mat_t x = FCC_MAT(3, 1, xd);
    fcc_real_t rcond = -1;
    memset(&lu, 0, sizeof lu);
    assert_int_equal(fcc_mat_lu_solve(&lu, &b, &x), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_lu_rcond(&lu, &rcond), FCC_ERR_ARG);
    lu.n = FCC_MAT_MAX_DIM + 1;
    assert_int_equal(fcc_mat_lu_solve_trans(&lu, &b, &x), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_lu_rcond(&lu, &rcond), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_lu_rcond(NULL, &rcond), FCC_ERR_ARG);
    lu.n = 3;
    assert_int_equal(fcc_mat_lu_rcond(&lu, NULL), FCC_ERR_ARG);
    assert_true(rcond == -1); /* untouched by every refusal */
}

static void rcond_of_identity_and_degenerate_norms(void **state)
{
    (void)state;
    fcc_real_t d[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    const fcc_mat_t eye = FCC_MAT(3, 3, d);
    fcc_assert_ok(fcc_mat_lu_factor(&g_lu, &eye));
    fcc_real_t rcond = 0;
    fcc_assert_ok(fcc_mat_lu_rcond(&g_lu, &rcond));
    fcc_assert_close(rcond, 1.0, FCC_TEST_TOL(1e-15, 1e-6), 0);
    /* ||A||_1 of zero or beyond the range: the estimate says "do not trust", never inf or nan */
    g_lu.norm1 = 0;
    fcc_assert_ok(fcc_mat_lu_rcond(&g_lu, &rcond));
    assert_true(rcond == 0);
    g_lu.norm1 = (fcc_real_t)INFINITY;
    rcond = 1;
    fcc_assert_ok(fcc_mat_lu_rcond(&g_lu, &rcond));
    assert_true(rcond == 0);
}

static void inverse_refuses_bad_output(void **state)
{
    (void)state;
    fcc_real_t d[9];
    memcpy(d, pivoting, sizeof d);
    const fcc_mat_t a = FCC_MAT(3, 3, d);
    fcc_real_t od[9];
    fcc_mat_t no_data = FCC_MAT(3, 3, NULL);
    fcc_mat_t small = FCC_MAT(2, 2, od);
    fcc_mat_t wide = FCC_MAT(3, 2, od);
    assert_int_equal(fcc_mat_inv(&a, &no_data, &g_lu), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_inv(&a, &small, &g_lu), FCC_ERR_SIZE);
    assert_int_equal(fcc_mat_inv(&a, &wide, &g_lu), FCC_ERR_SIZE);
    fcc_real_t s[4] = {1, 2, 2, 4};
    const fcc_mat_t singular = FCC_MAT(2, 2, s);
    assert_int_equal(fcc_mat_inv(&singular, &small, &g_lu), FCC_ERR_SINGULAR);
    /* and the inverse it returns is one: A A^-1 = I */
    fcc_mat_t inv = FCC_MAT(3, 3, od);
    fcc_assert_ok(fcc_mat_inv(&a, &inv, &g_lu));
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            double s2 = 0.0;
            for (int k = 0; k < 3; ++k) {
                s2 += (double)pivoting[i * 3 + k] * (double)od[k * 3 + j];
            }
            fcc_assert_close(s2, i == j ? 1.0 : 0.0, 0, FCC_TEST_TOL(1e-14, 1e-5));
        }
    }
}

static void cholesky_refuses_bad_arguments(void **state)
{
    (void)state;
    fcc_real_t spd[4] = {4, 2, 2, 3};
    fcc_real_t ld[6];
    const fcc_mat_t a = FCC_MAT(2, 2, spd);
    const fcc_mat_t wide = FCC_MAT(2, 3, ld);
    fcc_mat_t no_data = FCC_MAT(2, 2, NULL);
    fcc_mat_t l_wide = FCC_MAT(2, 3, ld);
    fcc_mat_t l = FCC_MAT(2, 2, ld);
    assert_int_equal(fcc_mat_chol(NULL, &l), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_chol(&wide, &l), FCC_ERR_SIZE);
    assert_int_equal(fcc_mat_chol(&a, &no_data), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_chol(&a, &l_wide), FCC_ERR_SIZE);
    /* a zero diagonal: not positive definite at the first column */
    fcc_real_t zd[4] = {0, 0, 0, 0};
    const fcc_mat_t zero = FCC_MAT(2, 2, zd);
    assert_int_equal(fcc_mat_chol(&zero, &l), FCC_ERR_NOT_POSDEF);
    /* L L^T = A with L lower triangular: 2, 1, sqrt(2) */
    fcc_assert_ok(fcc_mat_chol(&a, &l));
    fcc_assert_close(ld[0], 2.0, FCC_TEST_TOL(1e-15, 1e-6), 0);
    fcc_assert_close(ld[1], 0.0, 0, 0);
    fcc_assert_close(ld[2], 1.0, FCC_TEST_TOL(1e-15, 1e-6), 0);
    fcc_assert_close(ld[3], sqrt(2.0), FCC_TEST_TOL(1e-15, 1e-6), 0);
}

static void cholesky_solve_refuses_bad_arguments(void **state)
{
    (void)state;
    fcc_real_t ld[4] = {2, 0, 1, (fcc_real_t)sqrt(2.0)};
    fcc_real_t bd[4] = {8, 7, 1, 1};
    fcc_real_t xd[4];
    const fcc_mat_t l = FCC_MAT(2, 2, ld);
    const fcc_mat_t b = FCC_MAT(2, 1, bd);
    fcc_mat_t x = FCC_MAT(2, 1, xd);
    const fcc_mat_t no_data = FCC_MAT(2, 2, NULL);
    fcc_mat_t x_no_data = FCC_MAT(2, 1, NULL);
    assert_int_equal(fcc_mat_chol_solve(&no_data, &b, &x), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_chol_solve(&l, NULL, &x), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_chol_solve(&l, &b, &x_no_data), FCC_ERR_ARG);
    const fcc_mat_t l_wide = FCC_MAT(1, 2, ld);
    assert_int_equal(fcc_mat_chol_solve(&l_wide, &b, &x), FCC_ERR_SIZE);
    static fcc_real_t huge_d[(FCC_MAT_MAX_DIM + 1) * (FCC_MAT_MAX_DIM + 1)];
    const fcc_mat_t huge = FCC_MAT(FCC_MAT_MAX_DIM + 1, FCC_MAT_MAX_DIM + 1, huge_d);
    assert_int_equal(fcc_mat_chol_solve(&huge, &b, &x), FCC_ERR_SIZE);
    const fcc_mat_t b3 = FCC_MAT(1, 2, bd);
    assert_int_equal(fcc_mat_chol_solve(&l, &b3, &x), FCC_ERR_SIZE); /* rows differ */
    fcc_mat_t x2 = FCC_MAT(2, 2, xd);
    assert_int_equal(fcc_mat_chol_solve(&l, &b, &x2), FCC_ERR_SIZE); /* b, x differ */
    /* A = L L^T = [4 2; 2 3]: A x = [8 7] has x = [1.25 1.5] */
    fcc_assert_ok(fcc_mat_chol_solve(&l, &b, &x));
    fcc_assert_close(xd[0], 1.25, FCC_TEST_TOL(1e-15, 1e-6), 0);
    fcc_assert_close(xd[1], 1.5, FCC_TEST_TOL(1e-15, 1e-6), 0);
    /* an overflowing right-hand side is reported */
    bd[0] = (fcc_real_t)INFINITY;
    assert_int_equal(fcc_mat_chol_solve(&l, &b, &x), FCC_ERR_NOT_FINITE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(factor_pivots_every_column),
        cmocka_unit_test(factor_refuses_bad_input),
        cmocka_unit_test(solve_refuses_bad_arguments),
        cmocka_unit_test(forged_factorisation_is_refused),
        cmocka_unit_test(rcond_of_identity_and_degenerate_norms),
        cmocka_unit_test(inverse_refuses_bad_output),
        cmocka_unit_test(cholesky_refuses_bad_arguments),
        cmocka_unit_test(cholesky_solve_refuses_bad_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
