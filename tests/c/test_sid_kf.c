/* fcc_kf: eqs. (10)-(14) on a hand-worked 2x2 case, the first-step rule,
 * prediction-only steps and refused input. */
#include "fcc_test.h"

#include <string.h>

#include "fcc_kf.h"

#define TOL FCC_TEST_TOL(1e-14, 1e-6)

/* A = [[1,1],[0,1]], B = [0,1], Q = E E^T = I, R = F F^T = I, x0 = [1,0], P0 = I. */
static const fcc_sid_model_t model = {{1, 1, 0, 1}, {0, 1}, {0, 0}};
static const fcc_real_t eye[4] = {1, 0, 0, 1};

static void init(fcc_kf_t *kf)
{
    const fcc_real_t x0[2] = {1, 0};
    fcc_assert_ok(fcc_kf_init(kf, x0, eye, eye, eye));
}

static void hand_worked_two_steps(void **state)
{
    (void)state;
    fcc_kf_t kf;
    init(&kf);
    fcc_kf_info_t info;
    /* Step 0, no prediction: K = I (I + I)^-1 = I/2;
     * x = [1,0] + (1/2)([2,2] - [1,0]) = [1.5, 1]; P = I/2. */
    const fcc_real_t y0[2] = {2, 2};
    fcc_assert_ok(fcc_kf_step(&kf, &model, FCC_R(123.0), y0, true, &info));
    assert_false(info.predicted);
    assert_true(info.updated);
    fcc_assert_close(kf.x[0], 1.5, TOL, TOL);
    fcc_assert_close(kf.x[1], 1.0, TOL, TOL);
    fcc_assert_close(kf.p[0], 0.5, TOL, TOL);
    fcc_assert_close(kf.p[1], 0.0, TOL, TOL);
    fcc_assert_close(kf.p[3], 0.5, TOL, TOL);
    fcc_assert_close(info.gain_norm, 0.5, TOL, TOL);
    /* Step 1 with de = 1:
     * (10) x- = A x + B = [2.5, 2]
     * (11) P- = A (I/2) A^T + I = [[2, .5], [.5, 1.5]]
     * (12) S = P- + I = [[3, .5], [.5, 2.5]], det 7.25,
     *      K = P- S^-1 = [[4.75, .5], [.5, 4.25]] / 7.25
     * (13) y = [3, 2], innovation [.5, 0]: x = [2.5 + 2.375/7.25, 2 + .25/7.25]
     * (14) P = (I - K) P- = S^-1 P- (R = I) = K. */
    const fcc_real_t y1[2] = {3, 2};
    fcc_assert_ok(fcc_kf_step(&kf, &model, FCC_R(1.0), y1, true, &info));
    assert_true(info.predicted);
    const double k[4] = {4.75 / 7.25, 0.5 / 7.25, 0.5 / 7.25, 4.25 / 7.25};
    for (int i = 0; i < 4; ++i) {
        fcc_assert_close(info.gain[i], k[i], TOL, TOL);
        fcc_assert_close(kf.p[i], k[i], TOL, TOL);
    }
    fcc_assert_close(kf.x[0], 2.5 + 2.375 / 7.25, TOL, TOL);
    fcc_assert_close(kf.x[1], 2.0 + 0.25 / 7.25, TOL, TOL);
    /* ||K||_2 of the symmetric K: its largest eigenvalue
     * (4.5 + sqrt(0.0625 + 0.25)) / 7.25. */
    fcc_assert_close(info.gain_norm, (4.5 + sqrt(0.3125)) / 7.25, TOL, TOL);
}

static void prediction_only_without_measurement(void **state)
{
    (void)state;
    fcc_kf_t kf;
    init(&kf);
    const fcc_real_t y0[2] = {2, 2};
    fcc_assert_ok(fcc_kf_step(&kf, &model, FCC_R(0.0), y0, true, NULL));
    fcc_kf_info_t info;
    fcc_assert_ok(fcc_kf_step(&kf, &model, FCC_R(1.0), NULL, false, &info));
    assert_false(info.updated);
    fcc_assert_close(info.gain_norm, 0.0, 0.0, 0.0);
    fcc_assert_close(kf.x[0], 2.5, TOL, TOL);
    fcc_assert_close(kf.x[1], 2.0, TOL, TOL);
    fcc_assert_close(kf.p[0], 2.0, TOL, TOL);
    fcc_assert_close(kf.p[1], 0.5, TOL, TOL);
    fcc_assert_close(kf.p[3], 1.5, TOL, TOL);
}

static void affine_term_enters_the_prediction(void **state)
{
    (void)state;
    fcc_kf_t kf;
    init(&kf);
    const fcc_real_t y0[2] = {2, 2};
    fcc_assert_ok(fcc_kf_step(&kf, &model, FCC_R(0.0), y0, true, NULL));
    fcc_sid_model_t affine = model;
    affine.c[0] = FCC_R(0.25);
    affine.c[1] = FCC_R(-0.5);
    /* x- = A [1.5, 1] + B + c = [2.5 + 0.25, 2 - 0.5]; P as without c. */
    fcc_assert_ok(fcc_kf_step(&kf, &affine, FCC_R(1.0), NULL, false, NULL));
    fcc_assert_close(kf.x[0], 2.75, TOL, TOL);
    fcc_assert_close(kf.x[1], 1.5, TOL, TOL);
    fcc_assert_close(kf.p[0], 2.0, TOL, TOL);
    /* a non-finite c is refused like any other model entry */
    affine.c[1] = (fcc_real_t)NAN;
    assert_int_equal(fcc_kf_step(&kf, &affine, FCC_R(1.0), NULL, false, NULL), FCC_ERR_NOT_FINITE);
    fcc_assert_close(kf.x[0], 2.75, TOL, TOL);
}

static void covariance_stays_symmetric(void **state)
{
    (void)state;
    fcc_kf_t kf;
    const fcc_real_t x0[2] = {FCC_R(0.1571), FCC_R(0.0204)};
    const fcc_real_t p0[4] = {FCC_R(0.1), 0, 0, FCC_R(0.1)};
    const fcc_real_t e[4] = {FCC_R(0.004), 0, 0, FCC_R(0.004)};
    const fcc_real_t f[4] = {FCC_R(0.02), 0, 0, FCC_R(0.02)};
    fcc_assert_ok(fcc_kf_init(&kf, x0, p0, e, f));
    const fcc_sid_model_t m = {{FCC_R(0.97), FCC_R(0.02), FCC_R(-0.4), FCC_R(0.94)},
                               {FCC_R(-0.004), FCC_R(-0.6)}, {0, 0}};
    for (int k = 0; k < 500; ++k) {
        const fcc_real_t y[2] = {(fcc_real_t)(0.15 + 0.01 * sin(0.1 * k)), FCC_R(0.02)};
        fcc_assert_ok(fcc_kf_step(&kf, &m, FCC_R(-0.1), y, true, NULL));
        assert_true(kf.p[1] == kf.p[2]);
        assert_true(kf.p[0] > FCC_R(0.0) && kf.p[3] > FCC_R(0.0));
        assert_true(kf.p[0] * kf.p[3] > kf.p[1] * kf.p[1]);
    }
}

static void refused_input_leaves_filter_unchanged(void **state)
{
    (void)state;
    fcc_kf_t kf;
    init(&kf);
    const fcc_real_t y0[2] = {2, 2};
    fcc_assert_ok(fcc_kf_step(&kf, &model, FCC_R(0.0), y0, true, NULL));
    fcc_kf_t before;
    memcpy(&before, &kf, sizeof kf);
    const fcc_real_t nan_y[2] = {(fcc_real_t)NAN, 1};
    assert_int_equal(fcc_kf_step(&kf, &model, FCC_R(0.0), nan_y, true, NULL), FCC_ERR_NOT_FINITE);
    assert_int_equal(fcc_kf_step(&kf, &model, (fcc_real_t)INFINITY, y0, true, NULL),
                     FCC_ERR_NOT_FINITE);
    fcc_sid_model_t bad = model;
    bad.a[3] = (fcc_real_t)NAN;
    assert_int_equal(fcc_kf_step(&kf, &bad, FCC_R(0.0), y0, true, NULL), FCC_ERR_NOT_FINITE);
    /* A measurement so large that the estimate would leave the plausible range. */
    const fcc_real_t huge_y[2] = {FCC_SID_MAX_MAGNITUDE * FCC_R(100.0), 0};
    assert_int_equal(fcc_kf_step(&kf, &model, FCC_R(0.0), huge_y, true, NULL), FCC_ERR_NOT_FINITE);
    assert_memory_equal(&kf, &before, sizeof kf);
    assert_int_equal(fcc_kf_step(&kf, &model, FCC_R(0.0), NULL, true, NULL), FCC_ERR_ARG);
}

static void init_checks_covariances(void **state)
{
    (void)state;
    fcc_kf_t kf;
    const fcc_real_t x0[2] = {0, 0};
    const fcc_real_t zero[4] = {0, 0, 0, 0};
    const fcc_real_t asym[4] = {1, FCC_R(0.5), 0, 1};
    assert_int_equal(fcc_kf_init(&kf, x0, eye, eye, zero), FCC_ERR_NOT_POSDEF); /* R = 0 */
    assert_int_equal(fcc_kf_init(&kf, x0, zero, eye, eye), FCC_ERR_NOT_POSDEF); /* P0 = 0 */
    assert_int_equal(fcc_kf_init(&kf, x0, asym, eye, eye), FCC_ERR_NOT_POSDEF);
    const fcc_real_t nan_x[2] = {(fcc_real_t)NAN, 0};
    assert_int_equal(fcc_kf_init(&kf, nan_x, eye, eye, eye), FCC_ERR_ARG);
    assert_int_equal(fcc_kf_init(NULL, x0, eye, eye, eye), FCC_ERR_ARG);
    /* Q may be zero (no process noise). */
    fcc_assert_ok(fcc_kf_init(&kf, x0, eye, zero, eye));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(hand_worked_two_steps),
        cmocka_unit_test(prediction_only_without_measurement),
        cmocka_unit_test(affine_term_enters_the_prediction),
        cmocka_unit_test(covariance_stays_symmetric),
        cmocka_unit_test(refused_input_leaves_filter_unchanged),
        cmocka_unit_test(init_checks_covariances),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
