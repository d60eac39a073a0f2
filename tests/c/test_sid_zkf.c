/* fcc_zkf and fcc_azkf: eqs. (22)-(25) on hand-worked 2x2 cases, the
 * KF-style covariance recursion without reduction, the gain's response to
 * the order, the AZKF's fault policies, refused steps, storage bounds. */
#include "fcc_test.h"

#include <stddef.h>
#include <string.h>

#include "fcc_azkf.h"
#include "fcc_zkf.h"

#define TOL FCC_TEST_TOL(1e-13, 1e-5)

static fcc_zkf_t zkf;
static fcc_zkf_t zkf2;
static fcc_azkf_t azkf;

static const fcc_sid_model_t jordan = {{1, 1, 0, 1}, {0, 1}, {0, 0}};
static const fcc_real_t eye[4] = {1, 0, 0, 1};
static const fcc_real_t half_eye[4] = {FCC_R(0.5), 0, 0, FCC_R(0.5)};

static void hand_worked_step(void **state)
{
    (void)state;
    /* x = [1, 0], P = I, E = I/2, F = I (R = I), A = [[1,1],[0,1]], B = [0,1],
     * de = 1, y = [2, 2], no reduction (q = 10):
     *   (25) G = A I (I + I)^-1 = A/2 = [[.5, .5], [0, .5]]
     *   (22) x+ = A x + B de + G (y - x) = [1, 1] + G [1, 2] = [2.5, 2]
     *   (24) P+ = [(A - G) I, E, -G F]
     *           = [[.5,.5, .5,0, -.5,-.5], [0,.5, 0,.5, 0,-.5]]. */
    const fcc_real_t x0[2] = {1, 0};
    fcc_assert_ok(fcc_zkf_init(&zkf, x0, eye, half_eye, eye));
    const fcc_real_t y[2] = {2, 2};
    fcc_zkf_info_t info;
    fcc_assert_ok(fcc_zkf_step(&zkf, &jordan, FCC_R(1.0), y, true, 10u, &info));
    fcc_assert_close(zkf.x[0], 2.5, TOL, TOL);
    fcc_assert_close(zkf.x[1], 2.0, TOL, TOL);
    const double g[4] = {0.5, 0.5, 0.0, 0.5};
    for (int i = 0; i < 4; ++i) {
        fcc_assert_close(info.gain[i], g[i], TOL, TOL);
    }
    fcc_assert_close(info.gain_norm, (1.0 + sqrt(5.0)) / 4.0, TOL, TOL);
    assert_int_equal(info.order, 10);
    assert_int_equal(info.n_generators, 2);
    assert_int_equal(zkf.p, 6);
    /* Columns (column-major). */
    const double p1[12] = {0.5, 0.0, 0.5, 0.5, 0.5, 0.0, 0.0, 0.5, -0.5, 0.0, -0.5, -0.5};
    for (int i = 0; i < 12; ++i) {
        fcc_assert_close(zkf.gen[i], p1[i], TOL, TOL);
    }
    fcc_assert_close(zkf.hull[0], 2.5, TOL, TOL);
    fcc_assert_close(zkf.hull[1], 1.5, TOL, TOL);
    /* Next step at q = 2: P_bar = diag(2.5, 1.5) (eq. 18), M = diag(6.25, 2.25),
     * G = A M (M + I)^-1 = [[6.25/7.25, 2.25/3.25], [0, 2.25/3.25]]. */
    fcc_assert_ok(fcc_zkf_step(&zkf, &jordan, FCC_R(0.0), y, true, 2u, &info));
    fcc_assert_close(info.gain[0], 6.25 / 7.25, TOL, TOL);
    fcc_assert_close(info.gain[1], 2.25 / 3.25, TOL, TOL);
    fcc_assert_close(info.gain[2], 0.0, TOL, TOL);
    fcc_assert_close(info.gain[3], 2.25 / 3.25, TOL, TOL);
    assert_int_equal(info.n_generators, 2);
    assert_int_equal(zkf.p, 6);
    /* Output radius of <C x, [C P, F]>: hull(P) + hull(F). */
    fcc_real_t rad[2];
    fcc_zkf_output_radius(&zkf, rad);
    fcc_assert_close(rad[0], zkf.hull[0] + 1.0, TOL, TOL);
}

static void no_reduction_follows_kf_covariance_recursion(void **state)
{
    (void)state;
    /* Without reduction P P^T obeys the one-step-predictor Riccati recursion
     * M+ = A M A^T + Q - A M (M + R)^-1 M A^T. */
    const fcc_sid_model_t m = {{FCC_R(0.97), FCC_R(0.02), FCC_R(-0.4), FCC_R(0.94)},
                               {FCC_R(-0.004), FCC_R(-0.6)}, {0, 0}};
    const fcc_real_t x0[2] = {FCC_R(0.1571), FCC_R(0.0204)};
    const fcc_real_t p0[4] = {FCC_R(0.3162), 0, 0, FCC_R(0.3162)};
    const fcc_real_t e[4] = {FCC_R(0.004), 0, 0, FCC_R(0.004)};
    const fcc_real_t f[4] = {FCC_R(0.02), FCC_R(0.005), 0, FCC_R(0.02)};
    fcc_assert_ok(fcc_zkf_init(&zkf, x0, p0, e, f));
    double mm[4] = {0.3162 * 0.3162, 0, 0, 0.3162 * 0.3162};
    const double a[4] = {0.97, 0.02, -0.4, 0.94};
    const double r[4] = {0.02 * 0.02 + 0.005 * 0.005, 0.005 * 0.02, 0.005 * 0.02, 0.02 * 0.02};
    for (int k = 0; k < 60; ++k) {
        const fcc_real_t y[2] = {(fcc_real_t)(0.15 + 0.01 * sin(0.3 * k)), FCC_R(0.03)};
        fcc_assert_ok(fcc_zkf_step(&zkf, &m, FCC_R(-0.1), y, true, FCC_ZONO_MAX_ORDER, NULL));
        /* Reference recursion in double. */
        const double s[4] = {mm[0] + r[0], mm[1] + r[1], mm[2] + r[2], mm[3] + r[3]};
        const double det = s[0] * s[3] - s[1] * s[2];
        const double si[4] = {s[3] / det, -s[1] / det, -s[2] / det, s[0] / det};
        double am[4], amsi[4], g[4], t[4], next[4];
        am[0] = a[0] * mm[0] + a[1] * mm[2]; am[1] = a[0] * mm[1] + a[1] * mm[3];
        am[2] = a[2] * mm[0] + a[3] * mm[2]; am[3] = a[2] * mm[1] + a[3] * mm[3];
        amsi[0] = am[0] * si[0] + am[1] * si[2]; amsi[1] = am[0] * si[1] + am[1] * si[3];
        amsi[2] = am[2] * si[0] + am[3] * si[2]; amsi[3] = am[2] * si[1] + am[3] * si[3];
        memcpy(g, amsi, sizeof g);
        /* M+ = A M A^T - G (M A^T) + Q with Q = 0.004^2 I. */
        for (int i = 0; i < 2; ++i) {
            for (int j = 0; j < 2; ++j) {
                t[2 * i + j] = am[2 * i] * a[2 * j] + am[2 * i + 1] * a[2 * j + 1]; /* A M A^T */
                const double ma_t_0j = mm[0] * a[2 * j] + mm[1] * a[2 * j + 1];   /* (M A^T)_0j */
                const double ma_t_1j = mm[2] * a[2 * j] + mm[3] * a[2 * j + 1];
                next[2 * i + j] = t[2 * i + j] - (g[2 * i] * ma_t_0j + g[2 * i + 1] * ma_t_1j) +
                                  (i == j ? 0.004 * 0.004 : 0.0);
            }
        }
        memcpy(mm, next, sizeof mm);
        fcc_real_t pp[4];
        fcc_zkf_covariation(&zkf, pp);
        for (int i = 0; i < 4; ++i) {
            fcc_assert_close(pp[i], mm[i], FCC_TEST_TOL(1e-10, 2e-3), FCC_TEST_TOL(1e-16, 1e-8));
        }
    }
    assert_int_equal(zkf.p, 2 + 4 * 60);
}

static void gain_rises_when_order_drops(void **state)
{
    (void)state;
    const fcc_sid_model_t m = {{FCC_R(0.97), FCC_R(0.02), FCC_R(-0.4), FCC_R(0.94)},
                               {FCC_R(-0.004), FCC_R(-0.6)}, {0, 0}};
    const fcc_real_t x0[2] = {FCC_R(0.15), FCC_R(0.02)};
    const fcc_real_t p0[4] = {FCC_R(0.3), 0, 0, FCC_R(0.3)};
    const fcc_real_t e[4] = {FCC_R(0.004), 0, 0, FCC_R(0.004)};
    const fcc_real_t f[4] = {FCC_R(0.02), 0, 0, FCC_R(0.02)};
    fcc_assert_ok(fcc_zkf_init(&zkf, x0, p0, e, f));
    const fcc_real_t y[2] = {FCC_R(0.15), FCC_R(0.02)};
    for (int k = 0; k < 40; ++k) {
        fcc_assert_ok(fcc_zkf_step(&zkf, &m, FCC_R(-0.1), y, true, 1000u, NULL));
    }
    /* Same set, different orders: the gain is monotone in the order. */
    fcc_real_t prev = FCC_R(1e30);
    const uint16_t orders[] = {1000u, 100u, 40u, 10u, 4u, 2u};
    for (size_t i = 0; i < sizeof orders / sizeof orders[0]; ++i) {
        memcpy(&zkf2, &zkf, sizeof zkf);
        fcc_zkf_info_t info;
        fcc_assert_ok(fcc_zkf_step(&zkf2, &m, FCC_R(-0.1), y, true, orders[i], &info));
        if (i > 0) {
            assert_true(info.gain_norm > prev);
        }
        prev = info.gain_norm;
    }
}

/* A short flight of the default prior model with a spike at step 100. */
static void run_azkf(fcc_azkf_policy_t policy, fcc_fdet_mode_t mode, fcc_real_t gains[200],
                     bool faults[200], fcc_real_t xs[200][2])
{
    const fcc_sid_model_t m = {{FCC_R(0.97), FCC_R(0.02), FCC_R(-0.4), FCC_R(0.94)},
                               {FCC_R(-0.004), FCC_R(-0.6)}, {0, 0}};
    fcc_azkf_config_t cfg;
    fcc_azkf_config_default(&cfg);
    cfg.policy = policy;
    cfg.det.mode = mode;
    const fcc_real_t x0[2] = {FCC_R(0.1571), FCC_R(0.0204)};
    const fcc_real_t p0[4] = {FCC_R(0.3162), 0, 0, FCC_R(0.3162)};
    const fcc_real_t e[4] = {FCC_R(0.004), 0, 0, FCC_R(0.004)};
    const fcc_real_t f[4] = {FCC_R(0.02), 0, 0, FCC_R(0.02)};
    fcc_assert_ok(fcc_azkf_init(&azkf, &cfg, x0, p0, e, f));
    double x[2] = {0.1571, 0.0204};
    for (int k = 0; k < 200; ++k) {
        const double de = -0.05 + 0.02 * sin(0.2 * k);
        const bool spike = k >= 100 && k < 105;
        const fcc_real_t y[2] = {(fcc_real_t)(x[0] + 0.005 * sin(1.7 * k) + (spike ? 0.15 : 0.0)),
                                 (fcc_real_t)(x[1] + 0.005 * cos(2.3 * k) + (spike ? 0.6 : 0.0))};
        fcc_azkf_info_t info;
        xs[k][0] = azkf.zkf.x[0];
        xs[k][1] = azkf.zkf.x[1];
        fcc_assert_ok(fcc_azkf_step(&azkf, &m, (fcc_real_t)de, y, true, true, spike, &info));
        gains[k] = info.zkf.gain_norm;
        faults[k] = info.fault;
        if (policy == FCC_AZKF_POLICY_ORDER) {
            assert_int_equal(info.zkf.order, info.fault ? cfg.q_fault : cfg.q_normal);
        } else {
            assert_int_equal(info.zkf.order, cfg.q_normal);
        }
        const double n0 = 0.97 * x[0] + 0.02 * x[1] - 0.004 * de;
        const double n1 = -0.4 * x[0] + 0.94 * x[1] - 0.6 * de;
        x[0] = n0;
        x[1] = n1;
    }
}

static void azkf_gain_falls_on_fault_and_rises_after(void **state)
{
    (void)state;
    static fcc_real_t gains[200];
    static bool faults[200];
    static fcc_real_t xs[200][2];
    for (int mode = 0; mode < 2; ++mode) {
        run_azkf(FCC_AZKF_POLICY_ORDER, mode == 0 ? FCC_FDET_ZONOTOPE : FCC_FDET_ORACLE, gains,
                 faults, xs);
        for (int k = 0; k < 100; ++k) {
            assert_false(faults[k]); /* no false alarm in this clean flight */
        }
        for (int k = 100; k < 105; ++k) {
            assert_true(faults[k]);              /* every faulty sample is flagged */
            assert_true(gains[k] < gains[99]);   /* the gain falls while flagged */
        }
        int cleared = -1;
        for (int k = 105; k < 200 && cleared < 0; ++k) {
            if (!faults[k]) {
                cleared = k;
            }
        }
        assert_true(cleared > 0 && cleared < 130);
        assert_true(gains[cleared] > gains[cleared - 1]); /* and rises with the order drop */
    }
}

static void azkf_skip_policy_predicts_only(void **state)
{
    (void)state;
    static fcc_real_t gains[200];
    static bool faults[200];
    static fcc_real_t xs[200][2];
    run_azkf(FCC_AZKF_POLICY_SKIP, FCC_FDET_ORACLE, gains, faults, xs);
    for (int k = 100; k < 105; ++k) {
        assert_true(faults[k]);
        fcc_assert_close(gains[k], 0.0, 0.0, 0.0);
        /* x_k+1 = A x_k + B de_k exactly. */
        const double de = -0.05 + 0.02 * sin(0.2 * k);
        fcc_assert_close(xs[k + 1][0], 0.97 * xs[k][0] + 0.02 * xs[k][1] - 0.004 * de, TOL, TOL);
        fcc_assert_close(xs[k + 1][1], -0.4 * xs[k][0] + 0.94 * xs[k][1] - 0.6 * de, TOL, TOL);
    }
    assert_true(gains[105] > FCC_R(0.0));
}

static void prediction_only_step(void **state)
{
    (void)state;
    const fcc_real_t x0[2] = {1, 0};
    fcc_assert_ok(fcc_zkf_init(&zkf, x0, eye, half_eye, eye));
    fcc_zkf_info_t info;
    fcc_assert_ok(fcc_zkf_step(&zkf, &jordan, FCC_R(1.0), NULL, false, 10u, &info));
    assert_false(info.updated);
    fcc_assert_close(info.gain_norm, 0.0, 0.0, 0.0);
    fcc_assert_close(zkf.x[0], 1.0, TOL, TOL);
    fcc_assert_close(zkf.x[1], 1.0, TOL, TOL);
    /* P+ = [A P, E]: 4 columns, no zero -G F columns. */
    assert_int_equal(zkf.p, 4);
    const double p1[8] = {1, 0, 1, 1, 0.5, 0, 0, 0.5};
    for (int i = 0; i < 8; ++i) {
        fcc_assert_close(zkf.gen[i], p1[i], TOL, TOL);
    }
}

static void affine_term_enters_the_step(void **state)
{
    (void)state;
    const fcc_real_t x0[2] = {1, 0};
    fcc_assert_ok(fcc_zkf_init(&zkf, x0, eye, half_eye, eye));
    fcc_sid_model_t affine = jordan;
    affine.c[0] = FCC_R(0.25);
    affine.c[1] = FCC_R(-0.5);
    fcc_assert_ok(fcc_zkf_step(&zkf, &affine, FCC_R(1.0), NULL, false, 10u, NULL));
    /* A x + B de + c = [1, 1] + [0.25, -0.5]; the set does not move with c. */
    fcc_assert_close(zkf.x[0], 1.25, TOL, TOL);
    fcc_assert_close(zkf.x[1], 0.5, TOL, TOL);
    fcc_assert_close(zkf.gen[2], 1.0, TOL, TOL);
}

static void refused_step_leaves_filter_unchanged(void **state)
{
    (void)state;
    const fcc_real_t x0[2] = {1, 0};
    fcc_assert_ok(fcc_zkf_init(&zkf, x0, eye, half_eye, eye));
    const fcc_real_t y[2] = {2, 2};
    for (int k = 0; k < 5; ++k) {
        fcc_assert_ok(fcc_zkf_step(&zkf, &jordan, FCC_R(0.1), y, true, 8u, NULL));
    }
    memcpy(&zkf2, &zkf, sizeof zkf);
    const fcc_real_t nan_y[2] = {1, (fcc_real_t)NAN};
    assert_int_equal(fcc_zkf_step(&zkf, &jordan, FCC_R(0.1), nan_y, true, 8u, NULL),
                     FCC_ERR_NOT_FINITE);
    assert_int_equal(fcc_zkf_step(&zkf, &jordan, (fcc_real_t)NAN, y, true, 8u, NULL),
                     FCC_ERR_NOT_FINITE);
    fcc_sid_model_t bad = jordan;
    bad.b[0] = (fcc_real_t)INFINITY;
    assert_int_equal(fcc_zkf_step(&zkf, &bad, FCC_R(0.1), y, true, 8u, NULL), FCC_ERR_NOT_FINITE);
    fcc_sid_model_t huge = jordan;
    huge.a[0] = FCC_SID_MAX_MAGNITUDE;
    assert_int_equal(fcc_zkf_step(&zkf, &huge, FCC_R(0.1), y, true, 8u, NULL), FCC_ERR_NOT_FINITE);
    assert_int_equal(fcc_zkf_step(&zkf, &jordan, FCC_R(0.1), y, true, 1u, NULL), FCC_ERR_RANGE);
    assert_int_equal(fcc_zkf_step(&zkf, &jordan, FCC_R(0.1), y, true, FCC_ZONO_MAX_ORDER + 1u, NULL),
                     FCC_ERR_RANGE);
    assert_int_equal(fcc_zkf_step(&zkf, &jordan, FCC_R(0.1), NULL, true, 8u, NULL), FCC_ERR_ARG);
    /* Everything but the reduction's scratch (work) is as before. */
    assert_memory_equal(&zkf, &zkf2, offsetof(fcc_zkf_t, work));
    /* R must be invertible. */
    const fcc_real_t sing_f[4] = {1, 1, 1, 1};
    assert_int_equal(fcc_zkf_init(&zkf, x0, eye, eye, sing_f), FCC_ERR_NOT_POSDEF);
    /* AZKF configuration ranges. */
    fcc_azkf_config_t cfg;
    fcc_azkf_config_default(&cfg);
    assert_int_equal(cfg.q_normal, 2);
    assert_int_equal(cfg.q_fault, 1000 < FCC_ZONO_MAX_ORDER ? 1000 : FCC_ZONO_MAX_ORDER);
    cfg.q_fault = FCC_ZONO_MAX_ORDER + 1u;
    assert_int_equal(fcc_azkf_init(&azkf, &cfg, x0, eye, eye, eye), FCC_ERR_RANGE);
    fcc_azkf_config_default(&cfg);
    cfg.policy = (fcc_azkf_policy_t)7;
    assert_int_equal(fcc_azkf_init(&azkf, &cfg, x0, eye, eye, eye), FCC_ERR_ARG);
}

static void storage_bound_at_largest_order(void **state)
{
    (void)state;
    const fcc_sid_model_t m = {{FCC_R(0.97), FCC_R(0.02), FCC_R(-0.4), FCC_R(0.94)},
                               {FCC_R(-0.004), FCC_R(-0.6)}, {0, 0}};
    const fcc_real_t x0[2] = {FCC_R(0.15), FCC_R(0.02)};
    const fcc_real_t e[4] = {FCC_R(0.004), 0, 0, FCC_R(0.004)};
    const fcc_real_t f[4] = {FCC_R(0.02), 0, 0, FCC_R(0.02)};
    fcc_assert_ok(fcc_zkf_init(&zkf, x0, eye, e, f));
    const fcc_real_t y[2] = {FCC_R(0.15), FCC_R(0.02)};
    const int steps = FCC_ZONO_MAX_ORDER / 4 + 20;
    for (int k = 0; k < steps; ++k) {
        fcc_zkf_info_t info;
        fcc_assert_ok(fcc_zkf_step(&zkf, &m, FCC_R(-0.1), y, true, FCC_ZONO_MAX_ORDER, &info));
        assert_true(zkf.p <= FCC_ZONO_MAX_COLS);
        assert_true(info.n_generators <= FCC_ZONO_MAX_ORDER);
    }
    assert_int_equal(zkf.p, FCC_ZONO_MAX_COLS);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(hand_worked_step),
        cmocka_unit_test(no_reduction_follows_kf_covariance_recursion),
        cmocka_unit_test(gain_rises_when_order_drops),
        cmocka_unit_test(azkf_gain_falls_on_fault_and_rises_after),
        cmocka_unit_test(azkf_skip_policy_predicts_only),
        cmocka_unit_test(prediction_only_step),
        cmocka_unit_test(affine_term_enters_the_step),
        cmocka_unit_test(refused_step_leaves_filter_unchanged),
        cmocka_unit_test(storage_bound_at_largest_order),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
