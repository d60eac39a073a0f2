/* fcc_sid_math: eq. (26) spectral radius, gain norm, 2x2 inverse and
 * Cholesky, on hand-worked 2x2 cases. */
#include "fcc_test.h"

#include "fcc_sid_math.h"

#define TOL FCC_TEST_TOL(1e-14, 2e-6)

static void spectral_radius_hand_cases(void **state)
{
    (void)state;
    /* Diagonal: eigenvalues 0.5 and -0.8. */
    const fcc_real_t diag[4] = {FCC_R(0.5), FCC_R(0.0), FCC_R(0.0), FCC_R(-0.8)};
    fcc_assert_close(fcc_sid_m2_spectral_radius(diag), 0.8, TOL, TOL);
    /* Rotation: +/- i, rho = 1. */
    const fcc_real_t rot[4] = {FCC_R(0.0), FCC_R(1.0), FCC_R(-1.0), FCC_R(0.0)};
    fcc_assert_close(fcc_sid_m2_spectral_radius(rot), 1.0, TOL, TOL);
    /* 0.9 +/- 0.1 i: rho = sqrt(0.82). */
    const fcc_real_t damped[4] = {FCC_R(0.9), FCC_R(0.1), FCC_R(-0.1), FCC_R(0.9)};
    fcc_assert_close(fcc_sid_m2_spectral_radius(damped), sqrt(0.82), TOL, TOL);
    /* Symmetric [[2,1],[1,2]]: eigenvalues 3 and 1. */
    const fcc_real_t sym[4] = {FCC_R(2.0), FCC_R(1.0), FCC_R(1.0), FCC_R(2.0)};
    fcc_assert_close(fcc_sid_m2_spectral_radius(sym), 3.0, TOL, TOL);
    /* Jordan block: double eigenvalue 1. */
    const fcc_real_t jordan[4] = {FCC_R(1.0), FCC_R(1.0), FCC_R(0.0), FCC_R(1.0)};
    fcc_assert_close(fcc_sid_m2_spectral_radius(jordan), 1.0, TOL, TOL);
    /* Negative dominant eigenvalue: -3 and 1. */
    const fcc_real_t neg[4] = {FCC_R(-3.0), FCC_R(0.0), FCC_R(0.0), FCC_R(1.0)};
    fcc_assert_close(fcc_sid_m2_spectral_radius(neg), 3.0, TOL, TOL);
    /* The default prior model is stable: complex pair, |lambda|^2 = det. */
    fcc_sid_model_t prior = {{FCC_R(0.97), FCC_R(0.02), FCC_R(-0.4), FCC_R(0.94)}, {0, 0}, {0, 0}};
    fcc_assert_close(fcc_sid_m2_spectral_radius(prior.a), sqrt(0.97 * 0.94 + 0.02 * 0.4), TOL, TOL);
}

static void norm2_hand_cases(void **state)
{
    (void)state;
    /* [[3,0],[4,5]]: A^T A = [[25,20],[20,25]], eigenvalues 45 and 5. */
    const fcc_real_t a[4] = {FCC_R(3.0), FCC_R(0.0), FCC_R(4.0), FCC_R(5.0)};
    fcc_assert_close(fcc_sid_m2_norm2(a), sqrt(45.0), TOL, TOL);
    /* [[1,1],[0,1]]: the golden ratio. */
    const fcc_real_t j[4] = {FCC_R(1.0), FCC_R(1.0), FCC_R(0.0), FCC_R(1.0)};
    fcc_assert_close(fcc_sid_m2_norm2(j), (1.0 + sqrt(5.0)) / 2.0, TOL, TOL);
    const fcc_real_t z[4] = {0, 0, 0, 0};
    fcc_assert_close(fcc_sid_m2_norm2(z), 0.0, 0.0, 0.0);
    /* 0.5 I: every singular value is 0.5. */
    const fcc_real_t h[4] = {FCC_R(0.5), FCC_R(0.0), FCC_R(0.0), FCC_R(0.5)};
    fcc_assert_close(fcc_sid_m2_norm2(h), 0.5, TOL, TOL);
}

static void spd_inverse_and_cholesky(void **state)
{
    (void)state;
    /* [[3,0.5],[0.5,2.5]]: det 7.25. */
    const fcc_real_t s[4] = {FCC_R(3.0), FCC_R(0.5), FCC_R(0.5), FCC_R(2.5)};
    fcc_real_t inv[4];
    fcc_assert_ok(fcc_sid_m2_spd_inv(s, inv));
    fcc_assert_close(inv[0], 2.5 / 7.25, TOL, TOL);
    fcc_assert_close(inv[1], -0.5 / 7.25, TOL, TOL);
    fcc_assert_close(inv[2], -0.5 / 7.25, TOL, TOL);
    fcc_assert_close(inv[3], 3.0 / 7.25, TOL, TOL);
    /* Singular and indefinite matrices are refused. */
    const fcc_real_t sing[4] = {FCC_R(1.0), FCC_R(1.0), FCC_R(1.0), FCC_R(1.0)};
    assert_int_equal(fcc_sid_m2_spd_inv(sing, inv), FCC_ERR_NOT_POSDEF);
    const fcc_real_t indef[4] = {FCC_R(-1.0), FCC_R(0.0), FCC_R(0.0), FCC_R(1.0)};
    assert_int_equal(fcc_sid_m2_spd_inv(indef, inv), FCC_ERR_NOT_POSDEF);
    /* Cholesky of [[4,2],[2,5]] = [[2,0],[1,2]]. */
    const fcc_real_t p[4] = {FCC_R(4.0), FCC_R(2.0), FCC_R(2.0), FCC_R(5.0)};
    fcc_real_t l[4];
    fcc_assert_ok(fcc_sid_m2_cholesky(p, l));
    fcc_assert_close(l[0], 2.0, TOL, TOL);
    fcc_assert_close(l[1], 0.0, 0.0, 0.0);
    fcc_assert_close(l[2], 1.0, TOL, TOL);
    fcc_assert_close(l[3], 2.0, TOL, TOL);
    assert_int_equal(fcc_sid_m2_cholesky(sing, l), FCC_ERR_NOT_POSDEF);
    const fcc_real_t nan_m[4] = {FCC_R(1.0), FCC_R(0.0), FCC_R(0.0), (fcc_real_t)NAN};
    assert_int_equal(fcc_sid_m2_cholesky(nan_m, l), FCC_ERR_NOT_POSDEF);
}

static void products(void **state)
{
    (void)state;
    const fcc_real_t a[4] = {1, 2, 3, 4};
    const fcc_real_t b[4] = {5, 6, 7, 8};
    fcc_real_t c[4];
    fcc_sid_m2_mul(a, b, c); /* [[19,22],[43,50]] */
    fcc_assert_close(c[0], 19.0, 0.0, 0.0);
    fcc_assert_close(c[1], 22.0, 0.0, 0.0);
    fcc_assert_close(c[2], 43.0, 0.0, 0.0);
    fcc_assert_close(c[3], 50.0, 0.0, 0.0);
    fcc_sid_m2_mul_bt(a, b, c); /* a b^T = [[17,23],[39,53]] */
    fcc_assert_close(c[0], 17.0, 0.0, 0.0);
    fcc_assert_close(c[1], 23.0, 0.0, 0.0);
    fcc_assert_close(c[2], 39.0, 0.0, 0.0);
    fcc_assert_close(c[3], 53.0, 0.0, 0.0);
    assert_true(fcc_sid_all_finite(a, 4));
    const fcc_real_t bad[2] = {FCC_R(1.0), (fcc_real_t)INFINITY};
    assert_false(fcc_sid_all_finite(bad, 2));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(spectral_radius_hand_cases),
        cmocka_unit_test(norm2_hand_cases),
        cmocka_unit_test(spd_inverse_and_cholesky),
        cmocka_unit_test(products),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
