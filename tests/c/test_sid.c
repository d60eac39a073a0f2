/* fcc_sid: the closed loops MLS-KF / MLS-ZKF / MLS-AZKF -- identification
 * on a known linear flight, row semantics, bad input (never a NaN out),
 * prediction-only steps, determinism, configuration. */
#include "fcc_test.h"

#include <string.h>

#include "fcc_sid.h"

static fcc_sid_t sid_a;
static fcc_sid_t sid_b;

/* Truth: x+ = A x + B de + v, y = x + w; |v| <= 2e-4, |w| <= 1e-3. */
static const double a_true[4] = {0.96, 0.02, -0.45, 0.93};
static const double b_true[2] = {-0.004, -0.55};

typedef struct {
    double x[2];
    unsigned rng;
    int k;
} flight_t;

static double urand(flight_t *f)
{
    f->rng = f->rng * 1103515245u + 12345u;
    return (double)((f->rng >> 8) & 0xFFFFu) / 32767.5 - 1.0;
}

static void flight_init(flight_t *f)
{
    f->x[0] = 0.16;
    f->x[1] = 0.02;
    f->rng = 4242u;
    f->k = 0;
}

/* Next sample: y (measured), de; advances the truth. */
static void flight_next(flight_t *f, double y[2], double *de, double noise)
{
    const double t = 0.02 * f->k;
    *de = -0.12 + 0.02 * sin(2.0 * 3.14159 * 0.7 * t) + 0.015 * sin(2.0 * 3.14159 * 1.9 * t + 1.0);
    y[0] = f->x[0] + noise * urand(f);
    y[1] = f->x[1] + noise * urand(f);
    const double n0 = a_true[0] * f->x[0] + a_true[1] * f->x[1] + b_true[0] * *de + 2e-4 * urand(f);
    const double n1 = a_true[2] * f->x[0] + a_true[3] * f->x[1] + b_true[1] * *de + 2e-4 * urand(f);
    f->x[0] = n0;
    f->x[1] = n1;
    f->k++;
}

static void assert_out_finite(const fcc_sid_out_t *o)
{
    assert_true(fcc_sid_all_finite(o->x_hat, 2));
    assert_true(fcc_sid_all_finite(o->lo, 2));
    assert_true(fcc_sid_all_finite(o->hi, 2));
    assert_true(fcc_sid_model_is_finite(&o->model));
    assert_true(FCC_IS_FINITE(o->rho));
    assert_true(FCC_IS_FINITE(o->gain_norm));
    assert_true(o->lo[0] <= o->x_hat[0] && o->x_hat[0] <= o->hi[0]);
}

static void closed_loops_identify_the_model(void **state)
{
    (void)state;
    for (int fl = 0; fl < 3; ++fl) {
        fcc_sid_config_t cfg;
        fcc_sid_config_default(&cfg, (fcc_sid_filter_t)fl);
        cfg.f[0] = cfg.f[3] = FCC_R(0.002); /* the flight's sensor is good */
        cfg.e[0] = cfg.e[3] = FCC_R(0.001);
        fcc_assert_ok(fcc_sid_init(&sid_a, &cfg));
        flight_t f;
        flight_init(&f);
        fcc_sid_out_t out;
        for (int k = 0; k < 400; ++k) {
            double y[2], de;
            flight_next(&f, y, &de, 1e-3);
            (void)fcc_sid_step(&sid_a, (fcc_real_t)y[0], (fcc_real_t)y[1], (fcc_real_t)de, false,
                               true, &out);
            assert_true(out.stepped);
            assert_out_finite(&out);
        }
        assert_false(out.model_is_prior);
        /* Filtered data, noisy regression: a few percent of the entries. */
        fcc_assert_close(out.model.a[0], a_true[0], 0.0, 0.02);
        fcc_assert_close(out.model.a[2], a_true[2], 0.0, 0.15);
        fcc_assert_close(out.model.a[3], a_true[3], 0.0, 0.05);
        fcc_assert_close(out.model.b[1], b_true[1], 0.0, 0.15);
        /* rho(A_true) = |complex pair| = sqrt(det). */
        const double rho_true = sqrt(a_true[0] * a_true[3] - a_true[1] * a_true[2]);
        fcc_assert_close(out.rho, rho_true, 0.0, 0.02);
        for (int i = 0; i < FCC_MLS_N_PARAMS; ++i) {
            assert_true(out.se[i] >= FCC_R(0.0));
        }
        assert_int_equal(out.n_transitions, FCC_MLS_DEFAULT_WINDOW);
    }
}

static void first_rows_follow_the_row_semantics(void **state)
{
    (void)state;
    fcc_sid_config_t cfg;
    fcc_sid_config_default(&cfg, FCC_SID_KF);
    fcc_assert_ok(fcc_sid_init(&sid_a, &cfg));
    fcc_sid_out_t out;
    /* KF row 0: the prior updated with y_0, no prediction.  P0 = 0.1 I,
     * R = 0.0004 I: K = 0.1 / 0.1004 I. */
    (void)fcc_sid_step(&sid_a, FCC_R(0.2), FCC_R(0.1), FCC_R(-0.1), false, true, &out);
    const double k = 0.1 / 0.1004;
    const double tol = FCC_TEST_TOL(1e-12, 1e-6);
    fcc_assert_close(out.x_hat[0], 0.1571 + k * (0.2 - 0.1571), tol, tol);
    fcc_assert_close(out.x_hat[1], 0.0204 + k * (0.1 - 0.0204), tol, tol);
    fcc_assert_close(out.gain_norm, k, tol, tol);
    /* +/- 3 sigma, sigma^2 = (1 - K) P0. */
    fcc_assert_close(out.hi[0] - out.x_hat[0], 3.0 * sqrt((1.0 - k) * 0.1), tol, tol);
    assert_int_equal(out.order, 0);
    assert_true(out.model_is_prior);
    /* ZKF row 0: x_0 itself (before y_0), the hull of chol(P0) = sqrt(0.1) I. */
    fcc_sid_config_default(&cfg, FCC_SID_ZKF);
    fcc_assert_ok(fcc_sid_init(&sid_a, &cfg));
    (void)fcc_sid_step(&sid_a, FCC_R(0.2), FCC_R(0.1), FCC_R(-0.1), false, true, &out);
    fcc_assert_close(out.x_hat[0], 0.1571, tol, tol);
    fcc_assert_close(out.hi[0] - out.x_hat[0], sqrt(0.1), tol, tol);
    assert_int_equal(out.order, 1000 < FCC_ZONO_MAX_ORDER ? 1000 : FCC_ZONO_MAX_ORDER);
    assert_int_equal(out.k, 0);
    (void)fcc_sid_step(&sid_a, FCC_R(0.2), FCC_R(0.1), FCC_R(-0.1), false, true, &out);
    assert_int_equal(out.k, 1);
    assert_true(FCC_FABS(out.x_hat[0] - FCC_R(0.1571)) > FCC_R(1e-3)); /* y_0 is in x_1 */
}

static void garbage_never_reaches_the_estimate(void **state)
{
    (void)state;
    const fcc_real_t junk[] = {(fcc_real_t)NAN, (fcc_real_t)INFINITY, -(fcc_real_t)INFINITY,
                               FCC_R(1e30), FCC_R(-1e30), FCC_R(30.0)};
    for (int fl = 0; fl < 3; ++fl) {
        fcc_sid_config_t cfg;
        fcc_sid_config_default(&cfg, (fcc_sid_filter_t)fl);
        fcc_assert_ok(fcc_sid_init(&sid_a, &cfg));
        flight_t f;
        flight_init(&f);
        fcc_sid_out_t out;
        for (int k = 0; k < 300; ++k) {
            double y[2], de;
            flight_next(&f, y, &de, 1e-3);
            fcc_real_t ya = (fcc_real_t)y[0], yq = (fcc_real_t)y[1], u = (fcc_real_t)de;
            const fcc_real_t j = junk[k % 6];
            if (k % 7 == 3) {
                ya = j;
            } else if (k % 11 == 5) {
                yq = j;
            } else if (k % 13 == 6) {
                u = j;
            }
            const fcc_sid_out_t before = sid_a.last;
            const fcc_status_t st = fcc_sid_step(&sid_a, ya, yq, u, false, true, &out);
            assert_out_finite(&out);
            if (u == j) {
                /* An unusable elevator refuses the step: last good output. */
                assert_true(st == FCC_ERR_NOT_FINITE || st == FCC_ERR_RANGE);
                assert_false(out.stepped);
                assert_memory_equal(out.x_hat, before.x_hat, sizeof out.x_hat);
            } else if (ya == j || yq == j) {
                /* An unusable sample: prediction only, reported. */
                assert_true(out.stepped);
                assert_false(out.measurement_used);
                assert_true(out.input_status == FCC_ERR_NOT_FINITE ||
                            out.input_status == FCC_ERR_RANGE);
                assert_int_equal(st, out.input_status);
            }
        }
    }
}

static void invalid_measurement_predicts_and_teaches_nothing(void **state)
{
    (void)state;
    fcc_sid_config_t cfg;
    fcc_sid_config_default(&cfg, FCC_SID_KF);
    fcc_assert_ok(fcc_sid_init(&sid_a, &cfg));
    flight_t f;
    flight_init(&f);
    fcc_sid_out_t out;
    double y[2], de;
    for (int k = 0; k < 50; ++k) {
        flight_next(&f, y, &de, 1e-3);
        (void)fcc_sid_step(&sid_a, (fcc_real_t)y[0], (fcc_real_t)y[1], (fcc_real_t)de, false, true,
                           &out);
    }
    const uint16_t n_before = sid_a.mls.count;
    const fcc_real_t x_prev[2] = {out.x_hat[0], out.x_hat[1]};
    const fcc_sid_model_t model = fcc_mls_estimate(&sid_a.mls)->model;
    const fcc_real_t de_prev = (fcc_real_t)de;
    flight_next(&f, y, &de, 1e-3);
    fcc_assert_ok(fcc_sid_step(&sid_a, FCC_R(99.0), FCC_R(99.0), (fcc_real_t)de, false, false, &out));
    assert_false(out.measurement_used);
    assert_int_equal(out.gain_norm, 0);
    /* The KF coasts: x = A x_prev + B de_prev. */
    const double tol = FCC_TEST_TOL(1e-14, 1e-6);
    fcc_assert_close(out.x_hat[0], model.a[0] * x_prev[0] + model.a[1] * x_prev[1] + model.b[0] * de_prev,
                     tol, tol);
    /* Two more valid steps: the transitions touching the coasted step are
     * not learnt, the next one is. */
    flight_next(&f, y, &de, 1e-3);
    (void)fcc_sid_step(&sid_a, (fcc_real_t)y[0], (fcc_real_t)y[1], (fcc_real_t)de, false, true, &out);
    assert_int_equal(sid_a.mls.count, n_before);
    flight_next(&f, y, &de, 1e-3);
    (void)fcc_sid_step(&sid_a, (fcc_real_t)y[0], (fcc_real_t)y[1], (fcc_real_t)de, false, true, &out);
    assert_int_equal(sid_a.mls.count, n_before + 1u);
}

static void same_input_same_output(void **state)
{
    (void)state;
    for (int fl = 0; fl < 3; ++fl) {
        fcc_sid_config_t cfg;
        fcc_sid_config_default(&cfg, (fcc_sid_filter_t)fl);
        fcc_assert_ok(fcc_sid_init(&sid_a, &cfg));
        fcc_assert_ok(fcc_sid_init(&sid_b, &cfg));
        flight_t f;
        flight_init(&f);
        for (int k = 0; k < 350; ++k) {
            double y[2], de;
            flight_next(&f, y, &de, 5e-3);
            const bool spike = k >= 200 && k < 205;
            const fcc_real_t ya = (fcc_real_t)(y[0] + (spike ? 0.15 : 0.0));
            fcc_sid_out_t oa, ob;
            memset(&oa, 0, sizeof oa);
            memset(&ob, 0, sizeof ob);
            (void)fcc_sid_step(&sid_a, ya, (fcc_real_t)y[1], (fcc_real_t)de, spike, true, &oa);
            (void)fcc_sid_step(&sid_b, ya, (fcc_real_t)y[1], (fcc_real_t)de, spike, true, &ob);
            assert_memory_equal(&oa, &ob, sizeof oa);
        }
    }
}

static void fixed_model_mode(void **state)
{
    (void)state;
    fcc_sid_config_t cfg;
    fcc_sid_config_default(&cfg, FCC_SID_AZKF);
    cfg.mls_enabled = false;
    cfg.mls.prior.a[0] = FCC_R(0.5);
    fcc_assert_ok(fcc_sid_init(&sid_a, &cfg));
    flight_t f;
    flight_init(&f);
    for (int k = 0; k < 200; ++k) {
        double y[2], de;
        flight_next(&f, y, &de, 1e-3);
        fcc_sid_out_t out;
        (void)fcc_sid_step(&sid_a, (fcc_real_t)y[0], (fcc_real_t)y[1], (fcc_real_t)de, false, true,
                           &out);
        assert_memory_equal(&out.model, &cfg.mls.prior, sizeof out.model);
        assert_true(out.model_is_prior);
    }
}

/* The default priors are the CDRW's wind-tunnel model at its trim
 * alpha* = 9 deg, q* = 0, de* = -0.042105 rad: the paper's form keeps the trim
 * a fixed point, the affine form with its c0, and the two differ by the
 * smallest correction c0 phi*^T / |phi*|^2 (fcc_sid.h). */
static void default_priors_hold_the_trim(void **state)
{
    (void)state;
    const double xs[2] = {0.15707963, 0.0};
    const double des = -0.04210504;
    fcc_sid_model_t p, q;
    fcc_sid_default_prior(&p);
    fcc_sid_default_prior_affine(&q);
    assert_true(p.c[0] == FCC_R(0.0) && p.c[1] == FCC_R(0.0));
    const double phi2 = xs[0] * xs[0] + xs[1] * xs[1] + des * des;
    for (int i = 0; i < 2; ++i) {
        const double fp = (double)p.a[2 * i] * xs[0] + (double)p.a[2 * i + 1] * xs[1] +
                          (double)p.b[i] * des;
        const double fq = (double)q.a[2 * i] * xs[0] + (double)q.a[2 * i + 1] * xs[1] +
                          (double)q.b[i] * des + (double)q.c[i];
        fcc_assert_close(fp, xs[i], 0.0, 5e-6); /* digits as printed: 1e-6 */
        fcc_assert_close(fq, xs[i], 0.0, 5e-6);
        const double ci = (double)q.c[i]; /* printed to 1e-6; the correction is 5.9 c0 */
        fcc_assert_close(p.a[2 * i], (double)q.a[2 * i] + ci * xs[0] / phi2, 0.0, 5e-6);
        fcc_assert_close(p.a[2 * i + 1], (double)q.a[2 * i + 1] + ci * xs[1] / phi2, 0.0, 5e-6);
        fcc_assert_close(p.b[i], (double)q.b[i] + ci * des / phi2, 0.0, 5e-6);
    }
    fcc_sid_config_t cfg;
    fcc_sid_config_default(&cfg, FCC_SID_KF);
    assert_memory_equal(&cfg.mls.prior, &p, sizeof p);
    assert_false(cfg.mls.intercept);
    assert_true(cfg.arm_on_prior);
}

/* A spike in the first steps, while the model is still the prior: caught
 * when the detector is armed on the prior, not otherwise. */
static void arming_on_the_prior_catches_an_early_spike(void **state)
{
    (void)state;
    for (int arm = 0; arm < 2; ++arm) {
        fcc_sid_config_t cfg;
        fcc_sid_config_default(&cfg, FCC_SID_AZKF);
        for (int i = 0; i < 4; ++i) {
            cfg.mls.prior.a[i] = (fcc_real_t)a_true[i]; /* a prior that is right */
        }
        cfg.mls.prior.b[0] = (fcc_real_t)b_true[0];
        cfg.mls.prior.b[1] = (fcc_real_t)b_true[1];
        cfg.arm_on_prior = arm == 1;
        fcc_assert_ok(fcc_sid_init(&sid_a, &cfg));
        flight_t f;
        flight_init(&f);
        int flagged = 0, flagged_at_spike = 0;
        for (int k = 0; k < 15; ++k) {
            double y[2], de;
            flight_next(&f, y, &de, 1e-3);
            const bool spike = k == 10;
            fcc_sid_out_t out;
            (void)fcc_sid_step(&sid_a, (fcc_real_t)(y[0] + (spike ? 0.15 : 0.0)),
                               (fcc_real_t)(y[1] + (spike ? 0.3 : 0.0)), (fcc_real_t)de, false, true,
                               &out);
            assert_true(out.model_is_prior);
            flagged += out.fault ? 1 : 0;
            flagged_at_spike += (spike && out.fault) ? 1 : 0;
        }
        assert_int_equal(flagged_at_spike, arm);
        if (arm == 0) {
            assert_int_equal(flagged, 0);
        }
    }
}

static void configuration_is_checked(void **state)
{
    (void)state;
    fcc_sid_config_t cfg;
    fcc_sid_config_default(&cfg, FCC_SID_AZKF);
    /* Paper values. */
    fcc_assert_close(cfg.x0[0], 0.1571, 1e-7, 0.0);
    fcc_assert_close(cfg.x0[1], 0.0204, 1e-7, 0.0);
    fcc_assert_close(cfg.p0[0], 0.1, 1e-7, 0.0);
    fcc_assert_close(cfg.e[3], 0.004, 1e-7, 0.0);
    fcc_assert_close(cfg.f[0], 0.02, 1e-7, 0.0);
    assert_int_equal(cfg.mls.window, 110);
    assert_int_equal(cfg.azkf.q_normal, 2);
    fcc_sid_config_t bad = cfg;
    bad.zkf_order = FCC_ZONO_MAX_ORDER + 1u;
    assert_int_equal(fcc_sid_init(&sid_a, &bad), FCC_ERR_RANGE);
    bad = cfg;
    bad.azkf.q_fault = FCC_ZONO_MAX_ORDER + 1u;
    assert_int_equal(fcc_sid_init(&sid_a, &bad), FCC_ERR_RANGE);
    bad = cfg;
    bad.mls.window = FCC_MLS_MAX_WINDOW + 1u;
    assert_int_equal(fcc_sid_init(&sid_a, &bad), FCC_ERR_RANGE);
    bad = cfg;
    bad.p0[1] = FCC_R(0.5); /* not symmetric */
    assert_int_equal(fcc_sid_init(&sid_a, &bad), FCC_ERR_NOT_POSDEF);
    bad = cfg;
    bad.f[0] = bad.f[3] = FCC_R(0.0);
    assert_int_equal(fcc_sid_init(&sid_a, &bad), FCC_ERR_NOT_POSDEF);
    bad = cfg;
    bad.x0[0] = (fcc_real_t)NAN;
    assert_int_equal(fcc_sid_init(&sid_a, &bad), FCC_ERR_ARG);
    bad = cfg;
    bad.filter = (fcc_sid_filter_t)5;
    assert_int_equal(fcc_sid_init(&sid_a, &bad), FCC_ERR_ARG);
    assert_int_equal(fcc_sid_init(NULL, &cfg), FCC_ERR_ARG);
    fcc_sid_out_t out;
    fcc_assert_ok(fcc_sid_init(&sid_a, &cfg));
    assert_int_equal(fcc_sid_step(NULL, 0, 0, 0, false, true, &out), FCC_ERR_ARG);
    assert_int_equal(fcc_sid_step(&sid_a, 0, 0, 0, false, true, NULL), FCC_ERR_ARG);
}

/* Fills the stack below the caller with a pattern no bool holds, so that a local read
 * before it is written is seen by UBSan (invalid bool load) rather than reading a lucky 0. */
static void poison_stack(void)
{
    volatile unsigned char junk[8192];
    for (size_t i = 0; i < sizeof junk; ++i) {
        junk[i] = 0xA5u;
    }
}

/* Regression: when the AZKF step fails, fcc_sid_step read the AZKF's info (not written on
 * failure) before looking at the status (`fcc --x0 1e308,1e308` aborted under UBSan).  The
 * failure is now reported, nothing uninitialised is read, and the last row is kept. */
static void failed_filter_step_reads_nothing_uninitialised(void **state)
{
    (void)state;
    static const fcc_sid_filter_t filters[3] = {FCC_SID_KF, FCC_SID_ZKF, FCC_SID_AZKF};
    for (int i = 0; i < 3; ++i) {
        fcc_sid_config_t cfg;
        fcc_sid_config_default(&cfg, filters[i]);
        fcc_assert_ok(fcc_sid_init(&sid_a, &cfg));
        fcc_sid_out_t out;
        fcc_assert_ok(fcc_sid_step(&sid_a, FCC_R(0.1), FCC_R(0.0), FCC_R(-0.1), false, true, &out));
        const fcc_sid_out_t good = out;
        /* a state the filter cannot propagate: its step fails (overflow to infinity) */
        fcc_real_t *x = cfg.filter == FCC_SID_KF    ? sid_a.u.kf.x
                        : cfg.filter == FCC_SID_ZKF ? sid_a.u.zkf.x
                                                    : sid_a.u.azkf.zkf.x;
        x[0] = x[1] = FCC_REAL_MAX;
        poison_stack();
        const fcc_status_t st =
            fcc_sid_step(&sid_a, FCC_R(0.1), FCC_R(0.0), FCC_R(-0.1), false, true, &out);
        assert_true(st != FCC_OK);
        assert_false(out.stepped);
        assert_int_equal(out.filter_status, st);
        assert_memory_equal(out.x_hat, good.x_hat, sizeof good.x_hat);
        assert_int_equal(out.k, good.k);
    }
}

/* --x0 beyond what a sensor can read is a configuration error, not a flight. */
static void initial_state_outside_the_sensor_range_is_refused(void **state)
{
    (void)state;
    fcc_sid_config_t cfg;
    fcc_sid_config_default(&cfg, FCC_SID_AZKF);
    cfg.x0[0] = cfg.alpha_limit * FCC_R(1.01);
    assert_int_equal(fcc_sid_init(&sid_a, &cfg), FCC_ERR_RANGE);
    fcc_sid_config_default(&cfg, FCC_SID_AZKF);
    cfg.x0[1] = -cfg.q_limit * FCC_R(1.01);
    assert_int_equal(fcc_sid_init(&sid_a, &cfg), FCC_ERR_RANGE);
    fcc_sid_config_default(&cfg, FCC_SID_AZKF);
    cfg.x0[0] = cfg.alpha_limit;
    cfg.x0[1] = -cfg.q_limit;
    fcc_assert_ok(fcc_sid_init(&sid_a, &cfg));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(closed_loops_identify_the_model),
        cmocka_unit_test(first_rows_follow_the_row_semantics),
        cmocka_unit_test(garbage_never_reaches_the_estimate),
        cmocka_unit_test(invalid_measurement_predicts_and_teaches_nothing),
        cmocka_unit_test(same_input_same_output),
        cmocka_unit_test(fixed_model_mode),
        cmocka_unit_test(default_priors_hold_the_trim),
        cmocka_unit_test(arming_on_the_prior_catches_an_early_spike),
        cmocka_unit_test(configuration_is_checked),
        cmocka_unit_test(failed_filter_step_reads_nothing_uninitialised),
        cmocka_unit_test(initial_state_outside_the_sensor_range_is_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
