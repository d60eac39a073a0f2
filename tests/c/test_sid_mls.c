/* fcc_mls: eqs. (5)-(7) and (27)-(30) -- exact recovery, equality with batch
 * least squares on the same window, ridge, guards, standard errors, the
 * O(1) update with its exact re-sum. */
#include "fcc_test.h"

#include <string.h>

#include "fcc_mls.h"

static fcc_mls_t mls; /* large: static, as on the target */

/* A_true = [[0.95, 0.02], [-0.35, 0.93]], B_true = [-0.004, -0.55]. */
static const double a_true[4] = {0.95, 0.02, -0.35, 0.93};
static const double b_true[2] = {-0.004, -0.55};

/* Affine term of the simulated model (0: the paper's model). */
static double c_sim[2] = {0.0, 0.0};

static unsigned lcg_state = 12345u;

/* Uniform in [-1, 1], deterministic. */
static double urand(void)
{
    lcg_state = lcg_state * 1103515245u + 12345u;
    return (double)((lcg_state >> 8) & 0xFFFFu) / 32767.5 - 1.0;
}

static fcc_mls_config_t config(uint16_t window, fcc_real_t ridge)
{
    fcc_sid_model_t prior = {{FCC_R(1.0), FCC_R(0.0), FCC_R(0.0), FCC_R(1.0)}, {0, 0}, {0, 0}};
    fcc_mls_config_t cfg;
    fcc_mls_config_default(&cfg, &prior);
    cfg.window = window;
    cfg.min_transitions = window < 10u ? window : 10u;
    cfg.ridge = ridge;
    return cfg;
}

/* Simulates the true model with an exciting elevator; noise amplitude
 * `noise` on the state.  Keeps the transitions in (xs, des) for checks. */
typedef struct {
    double x[2];
    double xs[4096][2];
    double des[4096];
    size_t n;
} sim_t;

static sim_t sim;

static void sim_reset(void)
{
    memset(&sim, 0, sizeof sim);
    sim.x[0] = 0.15;
    sim.x[1] = 0.05;
    lcg_state = 12345u;
}

/* A fresh MLS on cfg and a fresh simulated flight. */
static void start(const fcc_mls_config_t *cfg)
{
    fcc_assert_ok(fcc_mls_init(&mls, cfg));
    sim_reset();
}

static void sim_step(fcc_mls_t *m, double noise)
{
    const double k = (double)sim.n;
    const double de = -0.1 + 0.05 * sin(0.37 * k) + 0.03 * sin(1.3 * k + 0.5);
    const double x0 = sim.x[0], x1 = sim.x[1];
    const double n0 = a_true[0] * x0 + a_true[1] * x1 + b_true[0] * de + c_sim[0] + noise * urand();
    const double n1 = a_true[2] * x0 + a_true[3] * x1 + b_true[1] * de + c_sim[1] + noise * urand();
    const fcc_real_t xr[2] = {(fcc_real_t)x0, (fcc_real_t)x1};
    const fcc_real_t nr[2] = {(fcc_real_t)n0, (fcc_real_t)n1};
    fcc_assert_ok(fcc_mls_push(m, xr, (fcc_real_t)de, nr));
    sim.xs[sim.n][0] = x0;
    sim.xs[sim.n][1] = x1;
    sim.des[sim.n] = de;
    sim.n++;
    sim.x[0] = n0;
    sim.x[1] = n1;
}

/* 3x3 solve by Cramer's rule (independent of the Cholesky in fcc_mls). */
static double det3(double m[3][3])
{
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

static void cramer3(double m[3][3], const double rhs[3], double out[3])
{
    const double d = det3(m);
    for (int c = 0; c < 3; ++c) {
        double mc[3][3];
        memcpy(mc, m, sizeof mc);
        for (int r = 0; r < 3; ++r) {
            mc[r][c] = rhs[r];
        }
        out[c] = det3(mc) / d;
    }
}

/* Batch least squares over the last `h` simulated transitions, with ridge
 * toward the identity/zero prior; coef[i][j]: output row i, regressor j. */
static void batch_fit(size_t h, double ridge, double coef[2][3], double nr_out[3][3])
{
    double n[3][3] = {{0}};
    double pz[3][2] = {{0}};
    for (size_t t = sim.n - h; t < sim.n; ++t) {
        const double phi[3] = {sim.xs[t][0], sim.xs[t][1], sim.des[t]};
        const double z[2] = {t + 1 < sim.n ? sim.xs[t + 1][0] : sim.x[0],
                             t + 1 < sim.n ? sim.xs[t + 1][1] : sim.x[1]};
        for (int j = 0; j < 3; ++j) {
            for (int k = 0; k < 3; ++k) {
                n[j][k] += phi[j] * phi[k];
            }
            pz[j][0] += phi[j] * z[0];
            pz[j][1] += phi[j] * z[1];
        }
    }
    const double theta0[3][2] = {{1.0, 0.0}, {0.0, 1.0}, {0.0, 0.0}};
    for (int j = 0; j < 3; ++j) {
        n[j][j] += ridge;
    }
    for (int i = 0; i < 2; ++i) {
        const double rhs[3] = {pz[0][i] + ridge * theta0[0][i], pz[1][i] + ridge * theta0[1][i],
                               pz[2][i] + ridge * theta0[2][i]};
        cramer3(n, rhs, coef[i]);
    }
    if (nr_out != NULL) {
        memcpy(nr_out, n, sizeof n);
    }
}

static void assert_model(const fcc_sid_model_t *m, double coef[2][3], double tol)
{
    fcc_assert_close(m->a[0], coef[0][0], tol, tol);
    fcc_assert_close(m->a[1], coef[0][1], tol, tol);
    fcc_assert_close(m->b[0], coef[0][2], tol, tol);
    fcc_assert_close(m->a[2], coef[1][0], tol, tol);
    fcc_assert_close(m->a[3], coef[1][1], tol, tol);
    fcc_assert_close(m->b[1], coef[1][2], tol, tol);
}

static void hand_worked_four_transitions(void **state)
{
    (void)state;
    /* Regressors e1, e2, e3 and (1,1,1) with z = Theta^T phi: the fit must
     * return Theta exactly, with zero residual and zero standard errors. */
    fcc_mls_config_t cfg = config(4u, FCC_R(0.0));
    cfg.min_transitions = 4u;
    fcc_assert_ok(fcc_mls_init(&mls, &cfg));
    const fcc_real_t phis[4][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
    const fcc_real_t a[4] = {FCC_R(0.5), FCC_R(0.1), FCC_R(-0.2), FCC_R(0.9)};
    const fcc_real_t b[2] = {FCC_R(0.1), FCC_R(-1.0)};
    for (int t = 0; t < 4; ++t) {
        const fcc_real_t *p = phis[t];
        const fcc_real_t z[2] = {a[0] * p[0] + a[1] * p[1] + b[0] * p[2],
                                 a[2] * p[0] + a[3] * p[1] + b[1] * p[2]};
        assert_true(fcc_mls_estimate(&mls)->is_prior);
        fcc_assert_ok(fcc_mls_update(&mls, p, p[2], z));
    }
    const fcc_mls_estimate_t *est = fcc_mls_estimate(&mls);
    assert_false(est->is_prior);
    const double tol = FCC_TEST_TOL(1e-14, 1e-6);
    for (int i = 0; i < 4; ++i) {
        fcc_assert_close(est->model.a[i], a[i], tol, tol);
    }
    fcc_assert_close(est->model.b[0], 0.1, tol, tol);
    fcc_assert_close(est->model.b[1], -1.0, tol, tol);
    for (int i = 0; i < FCC_MLS_N_PARAMS; ++i) {
        fcc_assert_close(est->se[i], 0.0, 0.0, FCC_TEST_TOL(1e-7, 2e-3));
    }
    /* N = I + 1 1^T = [[2,1,1],[1,2,1],[1,1,2]], N^-1 = [[3,-1,-1],...]/4:
     * cond_1 = |N|_1 |N^-1|_1 = 4 * 5/4 = 5 (equilibration divides N by 2
     * and leaves the condition number as it is). */
    fcc_assert_close(est->cond, 5.0, FCC_TEST_TOL(1e-12, 1e-5), 0.0);
    /* rho(A): half trace 0.7, disc = (-0.2)^2 + 0.1 * (-0.2) = 0.02. */
    fcc_assert_close(est->rho, 0.7 + sqrt(0.02), tol, tol);
}

static void noise_free_recovers_truth(void **state)
{
    (void)state;
    fcc_mls_config_t cfg = config(110u, FCC_R(0.0));
    start(&cfg);
    for (int k = 0; k < 300; ++k) {
        sim_step(&mls, 0.0);
        assert_int_equal(fcc_mls_solve(&mls), FCC_OK);
    }
    const fcc_mls_estimate_t *est = fcc_mls_estimate(&mls);
    double truth[2][3] = {{a_true[0], a_true[1], b_true[0]}, {a_true[2], a_true[3], b_true[1]}};
    assert_model(&est->model, truth, FCC_TEST_TOL(1e-9, 2e-3));
    assert_int_equal(est->n_transitions, 110);
}

/* x+ = A x + B de + c (a trimmed aircraft in absolute coordinates). */
static void intercept_recovers_affine_model(void **state)
{
    (void)state;
    c_sim[0] = 0.016;
    c_sim[1] = 0.071;
    double truth[2][3] = {{a_true[0], a_true[1], b_true[0]}, {a_true[2], a_true[3], b_true[1]}};
    /* With the intercept: A, B and c exactly. */
    fcc_mls_config_t cfg = config(110u, FCC_R(0.0));
    cfg.intercept = true;
    start(&cfg);
    for (int k = 0; k < 300; ++k) {
        sim_step(&mls, 0.0);
        assert_int_equal(fcc_mls_solve(&mls), FCC_OK);
    }
    const fcc_mls_estimate_t *est = fcc_mls_estimate(&mls);
    assert_model(&est->model, truth, FCC_TEST_TOL(1e-9, 2e-3));
    fcc_assert_close(est->model.c[0], 0.016, 0.0, FCC_TEST_TOL(1e-10, 2e-4));
    fcc_assert_close(est->model.c[1], 0.071, 0.0, FCC_TEST_TOL(1e-10, 2e-3));
    /* The paper's regression on the same data: no c, so A and B absorb it
     * (numpy's lstsq on this window: a21 = -0.151 instead of -0.35). */
    cfg.intercept = false;
    start(&cfg);
    for (int k = 0; k < 300; ++k) {
        sim_step(&mls, 0.0);
        (void)fcc_mls_solve(&mls);
    }
    est = fcc_mls_estimate(&mls);
    assert_true(est->model.c[0] == FCC_R(0.0) && est->model.c[1] == FCC_R(0.0));
    fcc_assert_close(est->model.a[2], -0.15057, 0.0, FCC_TEST_TOL(1e-4, 2e-3));
    c_sim[0] = c_sim[1] = 0.0;
}

/* The intercept fit against an independent batch computation: the
 * regression on the window's data centred on their means (c free, the ridge
 * on A and B), then c = mean(z) - Theta^T mean(phi). */
static void intercept_equals_centred_batch(void **state)
{
    (void)state;
    c_sim[0] = 0.01;
    c_sim[1] = -0.05;
    const double ridge = 0.02;
    fcc_mls_config_t cfg = config(60u, (fcc_real_t)ridge);
    cfg.intercept = true;
    start(&cfg);
    for (int k = 0; k < 173; ++k) {
        sim_step(&mls, 0.003);
        fcc_assert_ok(fcc_mls_solve(&mls));
    }
    const size_t h = 60u;
    double mp[3] = {0, 0, 0}, mz[2] = {0, 0};
    for (size_t t = sim.n - h; t < sim.n; ++t) {
        const double phi[3] = {sim.xs[t][0], sim.xs[t][1], sim.des[t]};
        for (int j = 0; j < 3; ++j) {
            mp[j] += phi[j] / (double)h;
        }
        for (int i = 0; i < 2; ++i) {
            mz[i] += (t + 1 < sim.n ? sim.xs[t + 1][i] : sim.x[i]) / (double)h;
        }
    }
    double n[3][3] = {{0}}, pz[3][2] = {{0}};
    for (size_t t = sim.n - h; t < sim.n; ++t) {
        const double phi[3] = {sim.xs[t][0] - mp[0], sim.xs[t][1] - mp[1], sim.des[t] - mp[2]};
        const double z[2] = {(t + 1 < sim.n ? sim.xs[t + 1][0] : sim.x[0]) - mz[0],
                             (t + 1 < sim.n ? sim.xs[t + 1][1] : sim.x[1]) - mz[1]};
        for (int j = 0; j < 3; ++j) {
            for (int k = 0; k < 3; ++k) {
                n[j][k] += phi[j] * phi[k];
            }
            pz[j][0] += phi[j] * z[0];
            pz[j][1] += phi[j] * z[1];
        }
    }
    const double theta0[3][2] = {{1.0, 0.0}, {0.0, 1.0}, {0.0, 0.0}}; /* config()'s prior */
    for (int j = 0; j < 3; ++j) {
        n[j][j] += ridge;
    }
    double coef[2][3];
    for (int i = 0; i < 2; ++i) {
        const double rhs[3] = {pz[0][i] + ridge * theta0[0][i], pz[1][i] + ridge * theta0[1][i],
                               pz[2][i] + ridge * theta0[2][i]};
        cramer3(n, rhs, coef[i]);
    }
    const fcc_mls_estimate_t *est = fcc_mls_estimate(&mls);
    assert_model(&est->model, coef, FCC_TEST_TOL(1e-9, 5e-3));
    for (int i = 0; i < 2; ++i) {
        const double c = mz[i] - (coef[i][0] * mp[0] + coef[i][1] * mp[1] + coef[i][2] * mp[2]);
        fcc_assert_close(est->model.c[i], c, 0.0, FCC_TEST_TOL(1e-10, 1e-3));
    }
    c_sim[0] = c_sim[1] = 0.0;
}

/* The prior's c is the model's only with the intercept. */
static void prior_affine_term_needs_the_intercept(void **state)
{
    (void)state;
    fcc_mls_config_t cfg = config(60u, FCC_R(0.0));
    cfg.prior.c[0] = FCC_R(0.5);
    cfg.prior.c[1] = FCC_R(-0.25);
    fcc_assert_ok(fcc_mls_init(&mls, &cfg));
    const fcc_mls_estimate_t *est = fcc_mls_estimate(&mls);
    assert_true(est->is_prior);
    assert_true(est->model.c[0] == FCC_R(0.0) && est->model.c[1] == FCC_R(0.0));
    cfg.intercept = true;
    fcc_assert_ok(fcc_mls_init(&mls, &cfg));
    assert_true(est->model.c[0] == FCC_R(0.5) && est->model.c[1] == FCC_R(-0.25));
    cfg.prior.c[0] = (fcc_real_t)INFINITY;
    assert_int_equal(fcc_mls_config_check(&cfg), FCC_ERR_ARG);
}

static void sliding_window_equals_batch(void **state)
{
    (void)state;
    for (int r = 0; r < 2; ++r) {
        const double ridge = r == 0 ? 0.0 : 0.05;
        fcc_mls_config_t cfg = config(50u, (fcc_real_t)ridge);
        start(&cfg);
        for (int k = 0; k < 237; ++k) { /* several wraps, not a multiple of h */
            sim_step(&mls, 0.003);
            fcc_assert_ok(fcc_mls_solve(&mls));
            if (k >= 20) {
                double coef[2][3];
                const size_t h = sim.n < 50u ? sim.n : 50u;
                batch_fit(h, ridge, coef, NULL);
                assert_model(&fcc_mls_estimate(&mls)->model, coef, FCC_TEST_TOL(1e-9, 5e-3));
            }
        }
    }
}

static void standard_errors_match_formula(void **state)
{
    (void)state;
    const double ridge = 0.01;
    fcc_mls_config_t cfg = config(80u, (fcc_real_t)ridge);
    start(&cfg);
    for (int k = 0; k < 150; ++k) {
        sim_step(&mls, 0.004);
    }
    fcc_assert_ok(fcc_mls_solve(&mls));
    double coef[2][3];
    double nr[3][3];
    batch_fit(80u, ridge, coef, nr);
    /* diag((N + ridge I)^-1) by Cramer, RSS from explicit residuals. */
    double inv_diag[3];
    for (int j = 0; j < 3; ++j) {
        double e[3] = {0, 0, 0};
        double col[3];
        e[j] = 1.0;
        cramer3(nr, e, col);
        inv_diag[j] = col[j];
    }
    for (int i = 0; i < 2; ++i) {
        double rss = 0.0;
        for (size_t t = sim.n - 80u; t < sim.n; ++t) {
            const double z = t + 1 < sim.n ? sim.xs[t + 1][i] : sim.x[i];
            const double fit = coef[i][0] * sim.xs[t][0] + coef[i][1] * sim.xs[t][1] +
                               coef[i][2] * sim.des[t];
            rss += (z - fit) * (z - fit);
        }
        const double var = rss / (80.0 - 3.0);
        const fcc_real_t *se = fcc_mls_estimate(&mls)->se;
        const double tol = FCC_TEST_TOL(1e-7, 0.1);
        fcc_assert_close(se[2 * i], sqrt(var * inv_diag[0]), tol, 0.0);
        fcc_assert_close(se[2 * i + 1], sqrt(var * inv_diag[1]), tol, 0.0);
        fcc_assert_close(se[4 + i], sqrt(var * inv_diag[2]), tol, 0.0);
    }
}

static void prior_until_enough_and_huge_ridge_is_prior(void **state)
{
    (void)state;
    fcc_mls_config_t cfg = config(60u, FCC_R(1e12));
    cfg.min_transitions = 30u;
    cfg.max_cond = FCC_R(1e30); /* the guard is not under test here */
    cfg.prior.a[0] = FCC_R(0.9);
    cfg.prior.b[1] = FCC_R(-0.3);
    start(&cfg);
    for (int k = 0; k < 29; ++k) {
        sim_step(&mls, 0.0);
        fcc_assert_ok(fcc_mls_solve(&mls));
        const fcc_mls_estimate_t *est = fcc_mls_estimate(&mls);
        assert_true(est->is_prior);
        assert_memory_equal(&est->model, &cfg.prior, sizeof cfg.prior);
        assert_true(est->se[0] < FCC_R(0.0));
    }
    sim_step(&mls, 0.0);
    fcc_assert_ok(fcc_mls_solve(&mls));
    const fcc_mls_estimate_t *est = fcc_mls_estimate(&mls);
    assert_false(est->is_prior);
    /* ridge 1e12 >> |N|: the fit is the prior to ~|N| / ridge. */
    const double tol = FCC_TEST_TOL(1e-9, 1e-5);
    for (int i = 0; i < 4; ++i) {
        fcc_assert_close(est->model.a[i], cfg.prior.a[i], 0.0, tol);
    }
    fcc_assert_close(est->model.b[1], cfg.prior.b[1], 0.0, tol);
}

static void guard_keeps_last_good_model(void **state)
{
    (void)state;
    fcc_mls_config_t cfg = config(20u, FCC_R(0.0));
    start(&cfg);
    for (int k = 0; k < 40; ++k) {
        sim_step(&mls, 0.001);
    }
    fcc_assert_ok(fcc_mls_solve(&mls));
    const fcc_sid_model_t good = fcc_mls_estimate(&mls)->model;
    /* Now a window with de = 0 and q = 2 alpha: N has rank 1. */
    for (int k = 0; k < 20; ++k) {
        const fcc_real_t x[2] = {FCC_R(0.1), FCC_R(0.2)};
        fcc_assert_ok(fcc_mls_push(&mls, x, FCC_R(0.0), x));
    }
    assert_int_equal(fcc_mls_solve(&mls), FCC_ERR_SINGULAR);
    assert_memory_equal(&fcc_mls_estimate(&mls)->model, &good, sizeof good);
    /* The same data with a ridge is well posed again: it falls onto the
     * prior's directions instead of failing. */
    cfg.ridge = FCC_R(1e-3);
    fcc_assert_ok(fcc_mls_init(&mls, &cfg));
    for (int k = 0; k < 20; ++k) {
        const fcc_real_t x[2] = {FCC_R(0.1), FCC_R(0.2)};
        fcc_assert_ok(fcc_mls_push(&mls, x, FCC_R(0.0), x));
    }
    fcc_assert_ok(fcc_mls_solve(&mls));
    const fcc_mls_estimate_t *est = fcc_mls_estimate(&mls);
    assert_true(fcc_sid_model_is_finite(&est->model));
    /* de was never excited: B stays at the prior (0). */
    fcc_assert_close(est->model.b[0], 0.0, 0.0, 1e-6);
    fcc_assert_close(est->model.b[1], 0.0, 0.0, 1e-6);
}

static void rho_guard_refuses_absurd_fit(void **state)
{
    (void)state;
    fcc_mls_config_t cfg = config(20u, FCC_R(0.0));
    cfg.max_rho = FCC_R(1.2);
    fcc_assert_ok(fcc_mls_init(&mls, &cfg));
    /* Data of x+ = 1.5 x (rho = 1.5) with an exciting elevator. */
    lcg_state = 99u;
    for (int k = 0; k < 20; ++k) {
        const fcc_real_t x[2] = {(fcc_real_t)(0.1 * urand()), (fcc_real_t)(0.1 * urand())};
        const fcc_real_t de = (fcc_real_t)(0.1 * urand());
        const fcc_real_t z[2] = {FCC_R(1.5) * x[0], FCC_R(1.5) * x[1]};
        fcc_assert_ok(fcc_mls_push(&mls, x, de, z));
    }
    assert_int_equal(fcc_mls_solve(&mls), FCC_ERR_RANGE);
    const fcc_mls_estimate_t *est = fcc_mls_estimate(&mls);
    assert_memory_equal(&est->model, &cfg.prior, sizeof cfg.prior);
    /* With the guard off, the fit is accepted and rho = 1.5. */
    cfg.max_rho = FCC_R(0.0);
    mls.cfg.max_rho = FCC_R(0.0);
    fcc_assert_ok(fcc_mls_solve(&mls));
    fcc_assert_close(fcc_mls_estimate(&mls)->rho, 1.5, FCC_TEST_TOL(1e-9, 1e-4), 0.0);
}

static void bad_input_is_refused(void **state)
{
    (void)state;
    fcc_mls_config_t cfg = config(20u, FCC_R(0.0));
    fcc_assert_ok(fcc_mls_init(&mls, &cfg));
    const fcc_real_t x[2] = {FCC_R(0.1), FCC_R(0.2)};
    const fcc_real_t bad[2] = {(fcc_real_t)NAN, FCC_R(0.2)};
    assert_int_equal(fcc_mls_push(&mls, bad, FCC_R(0.0), x), FCC_ERR_NOT_FINITE);
    assert_int_equal(fcc_mls_push(&mls, x, (fcc_real_t)INFINITY, x), FCC_ERR_NOT_FINITE);
    assert_int_equal(fcc_mls_push(&mls, x, FCC_R(0.0), bad), FCC_ERR_NOT_FINITE);
    assert_int_equal(mls.count, 0);
    assert_int_equal(fcc_mls_push(NULL, x, FCC_R(0.0), x), FCC_ERR_ARG);
    /* Configuration ranges. */
    fcc_mls_config_t c2 = cfg;
    c2.window = FCC_MLS_MAX_WINDOW + 1u;
    assert_int_equal(fcc_mls_init(&mls, &c2), FCC_ERR_RANGE);
    c2 = cfg;
    c2.window = 3u;
    assert_int_equal(fcc_mls_init(&mls, &c2), FCC_ERR_RANGE);
    c2 = cfg;
    c2.ridge = FCC_R(-1.0);
    assert_int_equal(fcc_mls_init(&mls, &c2), FCC_ERR_RANGE);
    c2 = cfg;
    c2.min_transitions = 21u;
    assert_int_equal(fcc_mls_init(&mls, &c2), FCC_ERR_RANGE);
    c2 = cfg;
    c2.prior.a[1] = (fcc_real_t)NAN;
    assert_int_equal(fcc_mls_init(&mls, &c2), FCC_ERR_ARG);
    assert_int_equal(fcc_mls_init(&mls, NULL), FCC_ERR_ARG);
}

/* The running sums stay exact to a window's worth of rounding however long
 * the flight: after 20000 pushes they equal a fresh sum of the window (about
 * the accumulator's reference point, fcc_mls_sums_t). */
static void resum_bounds_drift(void **state)
{
    (void)state;
    fcc_mls_config_t cfg = config(110u, FCC_R(0.0));
    fcc_assert_ok(fcc_mls_init(&mls, &cfg));
    lcg_state = 7u;
    for (int k = 0; k < 20000; ++k) {
        /* Large offsets make the add/subtract cancellation as bad as it gets. */
        const fcc_real_t x[2] = {(fcc_real_t)(10.0 + urand()), (fcc_real_t)(-5.0 + urand())};
        const fcc_real_t z[2] = {(fcc_real_t)(3.0 + urand()), (fcc_real_t)urand()};
        fcc_assert_ok(fcc_mls_push(&mls, x, (fcc_real_t)urand(), z));
    }
    double n00 = 0.0, pz21 = 0.0, zz1 = 0.0;
    const fcc_real_t *r = mls.sums.ref_phi;
    const fcc_real_t *rz = mls.sums.ref_z;
    for (size_t i = 0; i < mls.count; ++i) {
        const fcc_mls_transition_t *t = &mls.ring[i];
        const double d0 = (double)t->phi[0] - (double)r[0];
        const double d2 = (double)t->phi[2] - (double)r[2];
        const double e1 = (double)t->z[1] - (double)rz[1];
        n00 += d0 * d0;
        pz21 += d2 * e1;
        zz1 += e1 * e1;
    }
    /* Bound: rounding of one window of 110 sums, not of 20000 steps. */
    const double tol = FCC_TEST_TOL(1e-12, 2e-5);
    fcc_assert_close(mls.sums.n[0], n00, tol, 0.0);
    fcc_assert_close(mls.sums.pz[5], pz21, 0.0, tol * 110.0);
    fcc_assert_close(mls.sums.zz[1], zz1, tol, 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(hand_worked_four_transitions),
        cmocka_unit_test(noise_free_recovers_truth),
        cmocka_unit_test(intercept_recovers_affine_model),
        cmocka_unit_test(intercept_equals_centred_batch),
        cmocka_unit_test(prior_affine_term_needs_the_intercept),
        cmocka_unit_test(sliding_window_equals_batch),
        cmocka_unit_test(standard_errors_match_formula),
        cmocka_unit_test(prior_until_enough_and_huge_ridge_is_prior),
        cmocka_unit_test(guard_keeps_last_good_model),
        cmocka_unit_test(rho_guard_refuses_absurd_fit),
        cmocka_unit_test(bad_input_is_refused),
        cmocka_unit_test(resum_bounds_drift),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
