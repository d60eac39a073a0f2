/*
 * The ZKF's posterior report (fcc_zkf_set_posterior, firmware/sid/fcc_zkf.c)
 * against its definition, computed here from the filter's generators:
 *   G' = M (M + R)^-1 with M = P_bar P_bar^T,  x_k|k = x_k + G' (y_k - x_k),
 *   hull of <x_k|k, [(I - G') P_bar, -G' F]>,  and x_k+1 = A x_k|k + B de + c;
 * unreduced, fully boxed (q = 2) and partly reduced; and a step whose result
 * would leave the filter's range is refused with the filter unchanged.
 */
#include "fcc_test.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include "fcc_sid.h"

static const fcc_real_t k_x0[2] = {FCC_R(0.1), FCC_R(0.02)};
static const fcc_real_t k_p0[4] = {FCC_R(0.1), FCC_R(0.02), FCC_R(0.0), FCC_R(0.05)};
static const fcc_real_t k_e[4] = {FCC_R(0.01), FCC_R(0.0), FCC_R(0.0), FCC_R(0.02)};
static const fcc_real_t k_f[4] = {FCC_R(0.03), FCC_R(0.0), FCC_R(0.0), FCC_R(0.04)};
static const fcc_real_t k_y[2] = {FCC_R(0.13), FCC_R(-0.01)};

static fcc_zkf_t g_zkf;
static fcc_zkf_t g_before;

#define TOL FCC_TEST_TOL(1e-12, 2e-5)

/* A filter with 6 generators (one measurement step from P0), the posterior report on. */
static void start(fcc_sid_model_t *model)
{
    fcc_sid_default_prior(model);
    fcc_assert_ok(fcc_zkf_init(&g_zkf, k_x0, k_p0, k_e, k_f));
    fcc_assert_ok(fcc_zkf_step(&g_zkf, model, FCC_R(0.01), k_y, true, 1000u, NULL));
    assert_int_equal(g_zkf.p, 6u);
    fcc_zkf_set_posterior(&g_zkf, true);
    fcc_zkf_set_posterior(NULL, true); /* no filter: no fault */
    g_before = g_zkf;
}

/* G' = M (M + R)^-1 and the posterior centre, in double. */
static void posterior_gain(const double m[4], double gp[4], double post_x[2])
{
    const double s[4] = {m[0] + (double)g_before.r[0], m[1] + (double)g_before.r[1],
                         m[2] + (double)g_before.r[2], m[3] + (double)g_before.r[3]};
    const double det = s[0] * s[3] - s[1] * s[2];
    const double si[4] = {s[3] / det, -s[1] / det, -s[2] / det, s[0] / det};
    gp[0] = m[0] * si[0] + m[1] * si[2];
    gp[1] = m[0] * si[1] + m[1] * si[3];
    gp[2] = m[2] * si[0] + m[3] * si[2];
    gp[3] = m[2] * si[1] + m[3] * si[3];
    const double i0 = (double)k_y[0] - (double)g_before.x[0];
    const double i1 = (double)k_y[1] - (double)g_before.x[1];
    post_x[0] = (double)g_before.x[0] + gp[0] * i0 + gp[1] * i1;
    post_x[1] = (double)g_before.x[1] + gp[2] * i0 + gp[3] * i1;
}

/* Hull radii of the columns (I - G') P (P: n columns (a, b)) and -G' F. */
static void posterior_hull(const double gp[4], const double *cols, unsigned n, double h[2])
{
    const double t[4] = {1.0 - gp[0], -gp[1], -gp[2], 1.0 - gp[3]};
    h[0] = h[1] = 0.0;
    for (unsigned j = 0; j < n; ++j) {
        const double a = cols[2u * j];
        const double b = cols[2u * j + 1u];
        h[0] += fabs(t[0] * a + t[1] * b);
        h[1] += fabs(t[2] * a + t[3] * b);
    }
    for (unsigned j = 0; j < 2u; ++j) { /* columns of G' F (F row-major) */
        const double a = gp[0] * (double)k_f[j] + gp[1] * (double)k_f[2u + j];
        const double b = gp[2] * (double)k_f[j] + gp[3] * (double)k_f[2u + j];
        h[0] += fabs(a);
        h[1] += fabs(b);
    }
}

/* x_k+1 = A x_k|k + B de + c: the predicted centre is the posterior's prediction. */
static void assert_prediction_of_posterior(const fcc_sid_model_t *model, const fcc_zkf_info_t *info,
                                           fcc_real_t de)
{
    for (int i = 0; i < 2; ++i) {
        const double x = (double)model->a[2 * i] * (double)info->post_x[0] +
                         (double)model->a[2 * i + 1] * (double)info->post_x[1] +
                         (double)model->b[i] * (double)de + (double)model->c[i];
        fcc_assert_close(g_zkf.x[i], x, TOL, TOL);
    }
}

static void posterior_unreduced(void **state)
{
    (void)state;
    fcc_sid_model_t model;
    start(&model);
    fcc_zkf_info_t info;
    fcc_assert_ok(fcc_zkf_step(&g_zkf, &model, FCC_R(0.02), k_y, true, 1000u, &info));
    const double m[4] = {(double)g_before.cov[0], (double)g_before.cov[1], (double)g_before.cov[1],
                         (double)g_before.cov[2]};
    double gp[4], px[2], h[2];
    posterior_gain(m, gp, px);
    double cols[12];
    for (unsigned j = 0; j < 12u; ++j) {
        cols[j] = (double)g_before.gen[j];
    }
    posterior_hull(gp, cols, 6u, h);
    fcc_assert_close(info.post_x[0], px[0], TOL, TOL);
    fcc_assert_close(info.post_x[1], px[1], TOL, TOL);
    fcc_assert_close(info.post_hull[0], h[0], TOL, TOL);
    fcc_assert_close(info.post_hull[1], h[1], TOL, TOL);
    assert_true(info.post_gain_norm > FCC_R(0.0));
    assert_prediction_of_posterior(&model, &info, FCC_R(0.02));
}

/* q = 2: every column boxed, P_bar = diag(hull of P). */
static void posterior_fully_boxed(void **state)
{
    (void)state;
    fcc_sid_model_t model;
    start(&model);
    fcc_zkf_info_t info;
    fcc_assert_ok(fcc_zkf_step(&g_zkf, &model, FCC_R(0.02), k_y, true, FCC_ZONO_MIN_ORDER, &info));
    const double h0 = (double)g_before.hull[0];
    const double h1 = (double)g_before.hull[1];
    const double m[4] = {h0 * h0, 0.0, 0.0, h1 * h1};
    double gp[4], px[2], h[2];
    posterior_gain(m, gp, px);
    const double cols[4] = {h0, 0.0, 0.0, h1};
    posterior_hull(gp, cols, 2u, h);
    fcc_assert_close(info.post_x[0], px[0], TOL, TOL);
    fcc_assert_close(info.post_x[1], px[1], TOL, TOL);
    fcc_assert_close(info.post_hull[0], h[0], TOL, TOL);
    fcc_assert_close(info.post_hull[1], h[1], TOL, TOL);
    assert_prediction_of_posterior(&model, &info, FCC_R(0.02));
}

/* q between: some columns kept, the rest boxed -- q generators, a finite non-empty set, and
 * the identity with the prediction holds. */
static void posterior_partly_reduced(void **state)
{
    (void)state;
    fcc_sid_model_t model;
    start(&model);
    fcc_zkf_info_t part;
    for (uint16_t q = 3u; q <= 5u; ++q) {
        g_zkf = g_before;
        fcc_assert_ok(fcc_zkf_step(&g_zkf, &model, FCC_R(0.02), k_y, true, q, &part));
        assert_int_equal(part.n_generators, q);
        assert_prediction_of_posterior(&model, &part, FCC_R(0.02));
        for (int i = 0; i < 2; ++i) {
            assert_true(FCC_IS_FINITE(part.post_hull[i]));
            assert_true(part.post_hull[i] > FCC_R(0.0));
        }
    }
    /* without a measurement the posterior is the prior: x_k and the hull of P_k */
    g_zkf = g_before;
    fcc_zkf_info_t none;
    fcc_assert_ok(fcc_zkf_step(&g_zkf, &model, FCC_R(0.02), NULL, false, 1000u, &none));
    assert_true(none.post_x[0] == g_before.x[0] && none.post_x[1] == g_before.x[1]);
    assert_true(none.post_hull[0] == g_before.hull[0] && none.post_hull[1] == g_before.hull[1]);
    assert_true(none.post_gain_norm == FCC_R(0.0));
}

/* A result beyond the filter's range (FCC_SID_MAX_MAGNITUDE) is refused, the filter unchanged:
 * through either input gain, or a transition whose norm overflows. */
static void out_of_range_results_are_refused(void **state)
{
    (void)state;
    fcc_sid_model_t model;
    start(&model);
    const fcc_real_t big = (fcc_real_t)(sizeof(fcc_real_t) == sizeof(double) ? 1e200 : 1e20);
    for (int i = 0; i < 2; ++i) {
        fcc_sid_model_t m = model;
        m.b[i] = big;
        assert_int_equal(fcc_zkf_step(&g_zkf, &m, FCC_R(1.0), k_y, true, 1000u, NULL),
                         FCC_ERR_NOT_FINITE);
        assert_memory_equal(&g_zkf, &g_before, sizeof g_zkf);
    }
    /* |A| entries whose sum overflows, from a zero centre (the centre itself stays finite) */
    const fcc_real_t zero[2] = {FCC_R(0.0), FCC_R(0.0)};
    fcc_assert_ok(fcc_zkf_init(&g_zkf, zero, k_p0, k_e, k_f));
    g_before = g_zkf;
    fcc_sid_model_t m = model;
    const fcc_real_t max = (fcc_real_t)(sizeof(fcc_real_t) == sizeof(double) ? DBL_MAX : FLT_MAX);
    m.a[0] = max;
    m.a[1] = max;
    memset(m.b, 0, sizeof m.b);
    memset(m.c, 0, sizeof m.c);
    assert_int_equal(fcc_zkf_step(&g_zkf, &m, FCC_R(0.0), NULL, false, 1000u, NULL),
                     FCC_ERR_NOT_FINITE);
    assert_memory_equal(&g_zkf, &g_before, sizeof g_zkf);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(posterior_unreduced),
        cmocka_unit_test(posterior_fully_boxed),
        cmocka_unit_test(posterior_partly_reduced),
        cmocka_unit_test(out_of_range_results_are_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
