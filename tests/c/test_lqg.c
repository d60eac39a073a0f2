/*
 * The LQG autopilot's design chain (firmware/lqg): Van Loan discretisation, both
 * Riccati solvers, the full LQG design against scipy for every reference
 * period (tests/vectors/lqg/lqg_vectors.h, generated), refusals of bad
 * problems, and the runtime side: D/A converter and estimator/controller.
 */
#include "fcc_test.h"

#include <math.h>
#include <string.h>

#include "fcc_lqg.h"
#include "../vectors/lqg/lqg_vectors.h"

static fcc_c2d_ws_t g_c2d;
static fcc_dare_ws_t g_dare;
static fcc_lqg_ws_t g_ws;

/* The design is computed in double in every build; its results are then
 * rounded to fcc_real_t, which bounds what the float build can show. */
#define DESIGN_TOL FCC_TEST_TOL(1e-9, 1e-5)

/* The paper's continuous plant as double matrices. */
static const double k_f[9] = {-1.2132, -177.0, 0.0, 1.0, -4.03, 0.00149, 0.0, 0.0, -2.0};
static const double k_g[3] = {-69.3, -0.2978, 0.0};
static const double k_w[3] = {0.0, -0.0179, -24.0};

/* ---- Van Loan discretisation ------------------------------------------------- */

static void c2d_matches_scipy(void **state)
{
    (void)state;
    double f[9];
    double g[3];
    double qc[9];
    double wx[9] = {0.12, 0, 0, 0, 11.0, 0, 0, 0, 0};
    double wu[1] = {1.0};
    memcpy(f, k_f, sizeof f);
    memcpy(g, k_g, sizeof g);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            qc[i * 3 + j] = k_w[i] * k_w[j];
        }
    }
    const fcc_mat64_t mf = FCC_MAT64(3, 3, f);
    const fcc_mat64_t mg = FCC_MAT64(3, 1, g);
    const fcc_mat64_t mqc = FCC_MAT64(3, 3, qc);
    const fcc_mat64_t mwx = FCC_MAT64(3, 3, wx);
    const fcc_mat64_t mwu = FCC_MAT64(1, 1, wu);
    for (int c = 0; c < LQG_VECTOR_COUNT; ++c) {
        const lqg_vector_t *v = &lqg_vectors[c];
        double phi[9], gam[3], qd[9], q11[9], q12[3], q22[1];
        fcc_mat64_t mphi = FCC_MAT64(3, 3, phi);
        fcc_mat64_t mgam = FCC_MAT64(3, 1, gam);
        fcc_mat64_t mqd = FCC_MAT64(3, 3, qd);
        fcc_mat64_t m11 = FCC_MAT64(3, 3, q11);
        fcc_mat64_t m12 = FCC_MAT64(3, 1, q12);
        fcc_mat64_t m22 = FCC_MAT64(1, 1, q22);
        fcc_assert_ok(fcc_c2d_zoh(&mf, &mg, v->t, &mphi, &mgam, &g_c2d));
        fcc_assert_ok(fcc_c2d_noise(&mf, &mqc, v->t, &mqd, &g_c2d));
        fcc_assert_ok(fcc_c2d_cost(&mf, &mg, &mwx, &mwu, v->t, &m11, &m12, &m22, &g_c2d));
        fcc_assert_doubles_close(phi, v->phi, 9, 1e-12, "Phi");
        fcc_assert_doubles_close(gam, v->gamma, 3, 1e-12, "Gamma");
        fcc_assert_doubles_close(qd, v->qd, 9, 1e-12, "Qd");
        fcc_assert_doubles_close(q11, v->q11, 9, 1e-12, "Q11");
        fcc_assert_doubles_close(q12, v->q12, 3, 1e-12, "Q12");
        fcc_assert_doubles_close(q22, v->q22, 1, 1e-12, "Q22");
    }
}

static void c2d_closed_forms_and_refusals(void **state)
{
    (void)state;
    /* double integrator: F singular, Phi = [[1, T], [0, 1]], Gamma = [T^2/2, T];
     * cost with Wx = I, Wu = 0: Q11 = [[T, T^2/2], [T^2/2, T + T^3/3]] */
    const double t = 0.3;
    double f[4] = {0, 1, 0, 0};
    double g[2] = {0, 1};
    double wx[4] = {1, 0, 0, 1};
    double wu[1] = {0};
    double phi[4], gam[2], q11[4], q12[2], q22[1];
    const fcc_mat64_t mf = FCC_MAT64(2, 2, f);
    const fcc_mat64_t mg = FCC_MAT64(2, 1, g);
    const fcc_mat64_t mwx = FCC_MAT64(2, 2, wx);
    const fcc_mat64_t mwu = FCC_MAT64(1, 1, wu);
    fcc_mat64_t mphi = FCC_MAT64(2, 2, phi);
    fcc_mat64_t mgam = FCC_MAT64(2, 1, gam);
    fcc_mat64_t m11 = FCC_MAT64(2, 2, q11);
    fcc_mat64_t m12 = FCC_MAT64(2, 1, q12);
    fcc_mat64_t m22 = FCC_MAT64(1, 1, q22);
    fcc_assert_ok(fcc_c2d_zoh(&mf, &mg, t, &mphi, &mgam, &g_c2d));
    const double ephi[4] = {1, t, 0, 1};
    const double egam[2] = {t * t / 2, t};
    fcc_assert_doubles_close(phi, ephi, 4, 1e-15, "Phi");
    fcc_assert_doubles_close(gam, egam, 2, 1e-15, "Gamma");
    fcc_assert_ok(fcc_c2d_cost(&mf, &mg, &mwx, &mwu, t, &m11, &m12, &m22, &g_c2d));
    const double e11[4] = {t, t * t / 2, t * t / 2, t + t * t * t / 3};
    /* Q12 = int Phi(s)^T Gamma(s) ds = [T^3/6, T^2/2 + T^4/8], Q22 = int (s^4/4 + s^2) ds */
    const double e12[2] = {t * t * t / 6, t * t / 2 + t * t * t * t / 8};
    const double e22[1] = {pow(t, 5) / 20 + pow(t, 3) / 3};
    fcc_assert_doubles_close(q11, e11, 4, 1e-14, "Q11");
    fcc_assert_doubles_close(q12, e12, 2, 1e-14, "Q12");
    fcc_assert_doubles_close(q22, e22, 1, 1e-14, "Q22");
    /* refusals */
    assert_int_equal(fcc_c2d_zoh(&mf, &mg, 0.0, &mphi, &mgam, &g_c2d), FCC_ERR_ARG);
    assert_int_equal(fcc_c2d_zoh(&mf, &mg, -0.1, &mphi, &mgam, &g_c2d), FCC_ERR_ARG);
    assert_int_equal(fcc_c2d_zoh(&mf, &mg, NAN, &mphi, &mgam, &g_c2d), FCC_ERR_ARG);
    assert_int_equal(fcc_c2d_zoh(&mf, &mg, t, &mphi, &m11, &g_c2d), FCC_ERR_SIZE);
    assert_int_equal(fcc_c2d_zoh(&mf, &mg, t, &mphi, &mgam, NULL), FCC_ERR_ARG);
    f[1] = INFINITY;
    assert_int_equal(fcc_c2d_zoh(&mf, &mg, t, &mphi, &mgam, &g_c2d), FCC_ERR_NOT_FINITE);
}

/* ---- Riccati solvers ------------------------------------------------------------ */

typedef fcc_status_t (*dare_fn_t)(const fcc_dare_problem_t *, fcc_mat64_t *, fcc_dare_info_t *,
                                  fcc_dare_ws_t *);

static void dare_four_states_cross_term(void **state)
{
    (void)state;
    /* 4 states (2 unstable), 2 inputs, cross term: beyond the autopilot's sizes */
    double a[16], b[8], q[16], r[4], s[8], x[16];
    memcpy(a, lqg_dare4_a, sizeof a);
    memcpy(b, lqg_dare4_b, sizeof b);
    memcpy(q, lqg_dare4_q, sizeof q);
    memcpy(r, lqg_dare4_r, sizeof r);
    memcpy(s, lqg_dare4_s, sizeof s);
    const fcc_mat64_t ma = FCC_MAT64(4, 4, a);
    const fcc_mat64_t mb = FCC_MAT64(4, 2, b);
    const fcc_mat64_t mq = FCC_MAT64(4, 4, q);
    const fcc_mat64_t mr = FCC_MAT64(2, 2, r);
    const fcc_mat64_t ms = FCC_MAT64(4, 2, s);
    fcc_mat64_t mx = FCC_MAT64(4, 4, x);
    const fcc_dare_problem_t p = {&ma, &mb, &mq, &mr, &ms};
    const dare_fn_t solvers[2] = {fcc_dare_hamiltonian, fcc_dare_doubling};
    for (int k = 0; k < 2; ++k) {
        fcc_dare_info_t info;
        fcc_assert_ok(solvers[k](&p, &mx, &info, &g_dare));
        fcc_assert_doubles_close(x, lqg_dare4_x, 16, 1e-10, k == 0 ? "X (hamiltonian)" : "X (doubling)");
        assert_true(info.residual < 1e-13);
        assert_true(info.cl_radius < 1.0);
        double res = 1;
        fcc_assert_ok(fcc_dare_residual(&p, &mx, &res, &g_dare));
        assert_true(res < 1e-13);
        if (k == 1) {
            assert_true(info.iterations > 2 && info.iterations < 20);
        }
    }
}

/* (A, B, Q) 2x2 problems built for one failure each; R = 1. */
static fcc_status_t solve_small(dare_fn_t fn, const double a_in[4], const double b_in[2],
                                const double q_in[4])
{
    double a[4], b[2], q[4], r[1] = {1.0}, x[4];
    memcpy(a, a_in, sizeof a);
    memcpy(b, b_in, sizeof b);
    memcpy(q, q_in, sizeof q);
    const fcc_mat64_t ma = FCC_MAT64(2, 2, a);
    const fcc_mat64_t mb = FCC_MAT64(2, 1, b);
    const fcc_mat64_t mq = FCC_MAT64(2, 2, q);
    const fcc_mat64_t mr = FCC_MAT64(1, 1, r);
    fcc_mat64_t mx = FCC_MAT64(2, 2, x);
    const fcc_dare_problem_t p = {&ma, &mb, &mq, &mr, NULL};
    fcc_dare_info_t info;
    return fn(&p, &mx, &info, &g_dare);
}

static void dare_refuses_bad_problems(void **state)
{
    (void)state;
    const double eye[4] = {1, 0, 0, 1};
    const double only_second[4] = {0, 0, 0, 1};
    const double b2[2] = {0, 1};
    /* unstable mode 1.2 not reachable from u */
    const double unstable[4] = {1.2, 0, 0, 0.5};
    /* an uncontrollable complex pair 1.1 e^(+-j 0.5) */
    const double c = 1.1 * cos(0.5);
    const double s = 1.1 * sin(0.5);
    const double spiral[4] = {c, -s, s, c};
    const double b_none[2] = {0, 0};
    /* a mode on the unit circle, uncontrollable */
    const double marginal[4] = {1.0, 0, 0, 0.5};
    const dare_fn_t solvers[2] = {fcc_dare_hamiltonian, fcc_dare_doubling};
    for (int k = 0; k < 2; ++k) {
        assert_int_equal(solve_small(solvers[k], unstable, b2, eye), FCC_ERR_NOT_STABILIZABLE);
        assert_int_equal(solve_small(solvers[k], spiral, b_none, eye), FCC_ERR_NOT_STABILIZABLE);
        assert_int_equal(solve_small(solvers[k], marginal, b2, eye), FCC_ERR_NOT_STABILIZABLE);
        /* unstable mode 1.2 controllable but invisible to the cost */
        const double b_both[2] = {1, 1};
        assert_int_equal(solve_small(solvers[k], unstable, b_both, only_second),
                         FCC_ERR_NOT_DETECTABLE);
        /* the same with the mode weighted: fine */
        fcc_assert_ok(solve_small(solvers[k], unstable, b_both, eye));
    }
    /* a singular A~: the symplectic matrix needs A~^-1, doubling does not */
    const double nil[4] = {0, 1, 0, 0};
    assert_int_equal(solve_small(fcc_dare_hamiltonian, nil, b2, eye), FCC_ERR_SINGULAR);
    fcc_assert_ok(solve_small(fcc_dare_doubling, nil, b2, eye));

    /* malformed data */
    double a[4] = {0.5, 0, 0, 0.5}, b[2] = {0, 1}, q[4] = {1, 0.5, 0, 1}, r[1] = {-1}, x[4];
    const fcc_mat64_t ma = FCC_MAT64(2, 2, a);
    const fcc_mat64_t mb = FCC_MAT64(2, 1, b);
    const fcc_mat64_t mq = FCC_MAT64(2, 2, q);
    const fcc_mat64_t mr = FCC_MAT64(1, 1, r);
    fcc_mat64_t mx = FCC_MAT64(2, 2, x);
    fcc_mat64_t mx_bad = FCC_MAT64(3, 3, x);
    const fcc_dare_problem_t p = {&ma, &mb, &mq, &mr, NULL};
    fcc_dare_info_t info;
    assert_int_equal(fcc_dare_doubling(&p, &mx, &info, &g_dare), FCC_ERR_ARG); /* Q asymmetric */
    q[1] = 0;
    assert_int_equal(fcc_dare_doubling(&p, &mx, &info, &g_dare), FCC_ERR_NOT_POSDEF); /* R < 0 */
    r[0] = 1;
    fcc_assert_ok(fcc_dare_doubling(&p, &mx, &info, &g_dare));
    assert_int_equal(fcc_dare_doubling(&p, &mx_bad, &info, &g_dare), FCC_ERR_SIZE);
    assert_int_equal(fcc_dare_doubling(NULL, &mx, &info, &g_dare), FCC_ERR_ARG);
    a[3] = NAN;
    assert_int_equal(fcc_dare_hamiltonian(&p, &mx, &info, &g_dare), FCC_ERR_NOT_FINITE);
}

/* ---- the full design against scipy ---------------------------------------------- */

static void assert_poles(const fcc_real_t *re, const fcc_real_t *im, const double *expected,
                         const char *what)
{
    double scale = 0;
    for (int i = 0; i < FCC_LQG_NX; ++i) {
        scale = hypot(expected[2 * i], expected[2 * i + 1]) > scale
                    ? hypot(expected[2 * i], expected[2 * i + 1])
                    : scale;
    }
    for (int i = 0; i < FCC_LQG_NX; ++i) {
        if (!(hypot((double)re[i] - expected[2 * i], (double)im[i] - expected[2 * i + 1]) <=
              DESIGN_TOL * scale)) {
            print_error("%s[%d] = %.17g%+.17gj, expected %.17g%+.17gj\n", what, i, (double)re[i],
                        (double)im[i], expected[2 * i], expected[2 * i + 1]);
            fail();
        }
    }
}

static void design_matches_scipy(void **state)
{
    (void)state;
    fcc_lqg_plant_t plant;
    fcc_assert_ok(fcc_lqg_plant_default(&plant));
    const fcc_lqg_solver_t solvers[2] = {FCC_LQG_SOLVER_HAMILTONIAN, FCC_LQG_SOLVER_DOUBLING};
    for (int c = 0; c < LQG_VECTOR_COUNT; ++c) {
        const lqg_vector_t *v = &lqg_vectors[c];
        for (int k = 0; k < 2; ++k) {
            fcc_lqg_design_t d;
            print_message("T = %g s, %s\n", v->t, k == 0 ? "hamiltonian" : "doubling");
            fcc_assert_ok(fcc_lqg_design(&plant, v->t, solvers[k], &d, &g_ws));
            assert_int_equal(d.solver, solvers[k]);
            fcc_assert_close(d.t, v->t, FCC_TEST_TOL(0, 1e-7), 0);
            fcc_assert_reals_close(d.phi, v->phi, 9, DESIGN_TOL, "Phi");
            fcc_assert_reals_close(d.gamma, v->gamma, 3, DESIGN_TOL, "Gamma");
            fcc_assert_reals_close(d.qd, v->qd, 9, DESIGN_TOL, "Qd");
            fcc_assert_reals_close(d.q11, v->q11, 9, DESIGN_TOL, "Q11");
            fcc_assert_reals_close(d.q12, v->q12, 3, DESIGN_TOL, "Q12");
            fcc_assert_reals_close(d.q22, v->q22, 1, DESIGN_TOL, "Q22");
            fcc_assert_reals_close(d.k, v->k, 3, DESIGN_TOL, "K");
            fcc_assert_reals_close(d.p, v->p, 9, DESIGN_TOL, "P");
            fcc_assert_reals_close(d.m, v->m, 9, DESIGN_TOL, "M");
            fcc_assert_reals_close(d.p_post, v->p_post, 9, DESIGN_TOL, "P_post");
            fcc_assert_reals_close(d.l, v->l, 6, DESIGN_TOL, "L");
            assert_poles(d.cl_re, d.cl_im, v->cl_poles, "closed-loop pole");
            assert_poles(d.est_re, d.est_im, v->est_poles, "estimator pole");
            /* the two Riccati methods agree (both run in double in every build) */
            assert_true(d.lqr.disagreement <= 1e-10);
            assert_true(d.kf.disagreement <= 1e-10);
            assert_true(d.lqr.residual < 1e-12 && d.kf.residual < 1e-12);
            assert_true(d.lqr.iterations > 0 && d.kf.iterations > 0);
            assert_true(d.lqr.rcond_u1 > 0 && d.kf.rcond_u1 > 0);
        }
    }
}

/* The delay-aware design (fcc_lqg.h): Gamma0/Gamma1 and the LQR on [x; u_k-1]
 * against scipy, the Kalman part unchanged, the controller's delayed
 * prediction, and the refusals of a delay outside [0, T). */
static void delayed_design_matches_scipy(void **state)
{
    (void)state;
    fcc_lqg_plant_t plant;
    fcc_assert_ok(fcc_lqg_plant_default(&plant));
    for (int c = 0; c < LQG_DELAYED_VECTOR_COUNT; ++c) {
        const lqg_delayed_vector_t *v = &lqg_delayed_vectors[c];
        print_message("T = %g s, d = %g s\n", v->t, v->delay);
        fcc_lqg_design_t d;
        fcc_lqg_design_t d0;
        fcc_assert_ok(fcc_lqg_design_delayed(&plant, v->t, v->delay, FCC_LQG_SOLVER_HAMILTONIAN,
                                             &d, &g_ws));
        fcc_assert_ok(fcc_lqg_design(&plant, v->t, FCC_LQG_SOLVER_HAMILTONIAN, &d0, &g_ws));
        fcc_assert_close(d.delay, v->delay, FCC_TEST_TOL(0, 1e-7), 0);
        fcc_assert_reals_close(d.gamma, v->gamma0, 3, DESIGN_TOL, "Gamma0");
        fcc_assert_reals_close(d.gamma1, v->gamma1, 3, DESIGN_TOL, "Gamma1");
        fcc_assert_reals_close(d.k, v->k, 3, DESIGN_TOL, "K");
        fcc_assert_reals_close(&d.k_u, v->k_u, 1, DESIGN_TOL, "K_u");
        fcc_assert_reals_close(d.pa, v->pa, 16, DESIGN_TOL, "Pa");
        fcc_assert_reals_close(d.qa11, v->qa11, 16, DESIGN_TOL, "Qa11");
        fcc_assert_reals_close(d.qa12, v->qa12, 4, DESIGN_TOL, "Qa12");
        fcc_assert_reals_close(&d.qa22, v->qa22, 1, DESIGN_TOL, "Qa22");
        assert_poles(d.cl_re, d.cl_im, v->cl_poles, "closed-loop pole");
        assert_true(d.lqr.residual < 1e-12 && d.lqr.iterations > 0);
        /* the filter does not depend on the delay */
        for (int i = 0; i < 6; ++i) {
            assert_true(d.l[i] == d0.l[i]);
        }
        assert_true(d.kf.disagreement <= 1e-10);
        /* one controller step: u = -K x^ - K_u u_prev, xbar+ = Phi x^ + G0 u + G1 u_prev */
        fcc_lqg_ctrl_t ctl;
        fcc_lqg_output_t out;
        const fcc_real_t x0[3] = {FCC_R(0.05), FCC_R(0.002), FCC_R(1.0)};
        fcc_assert_ok(fcc_lqg_ctrl_init(&ctl, &d, 16u, x0));
        ctl.u_prev = FCC_R(0.01);
        fcc_assert_ok(fcc_lqg_ctrl_predict(&ctl, &out));
        fcc_real_t u = -d.k_u * FCC_R(0.01);
        for (int i = 0; i < 3; ++i) {
            u -= d.k[i] * x0[i];
        }
        fcc_assert_close(out.u_cmd, u, FCC_TEST_TOL(1e-12, 1e-5), 0);
        for (int i = 0; i < 3; ++i) {
            fcc_real_t next = d.gamma[i] * out.u_applied + d.gamma1[i] * FCC_R(0.01);
            for (int j = 0; j < 3; ++j) {
                next += d.phi[i * 3 + j] * x0[j];
            }
            fcc_assert_close(ctl.x_pred[i], next, FCC_TEST_TOL(1e-12, 1e-5), 0);
        }
        assert_true(ctl.u_prev == out.u_applied);
    }
    fcc_lqg_design_t d;
    const fcc_lqg_solver_t h = FCC_LQG_SOLVER_HAMILTONIAN;
    assert_int_equal(fcc_lqg_design_delayed(&plant, 0.1, -1e-6, h, &d, &g_ws), FCC_ERR_RANGE);
    assert_int_equal(fcc_lqg_design_delayed(&plant, 0.1, 0.1, h, &d, &g_ws), FCC_ERR_RANGE);
    assert_int_equal(fcc_lqg_design_delayed(&plant, 0.1, NAN, h, &d, &g_ws), FCC_ERR_ARG);
    /* d = 0 is the undelayed design, by both solvers */
    fcc_assert_ok(fcc_lqg_design_delayed(&plant, 0.1, 0.0, h, &d, &g_ws));
    assert_true(d.k_u == FCC_R(0.0) && d.gamma1[0] == FCC_R(0.0) && d.lqr.rcond_u1 > 0);
}

static void design_refuses_bad_input(void **state)
{
    (void)state;
    fcc_lqg_plant_t plant;
    fcc_assert_ok(fcc_lqg_plant_default(&plant));
    fcc_lqg_design_t d;
    fcc_lqg_design_t before;
    fcc_assert_ok(fcc_lqg_design(&plant, 0.1, FCC_LQG_SOLVER_HAMILTONIAN, &d, &g_ws));
    before = d;
    const fcc_lqg_solver_t h = FCC_LQG_SOLVER_HAMILTONIAN;
    assert_int_equal(fcc_lqg_design(&plant, 0.0, h, &d, &g_ws), FCC_ERR_RANGE);
    assert_int_equal(fcc_lqg_design(&plant, -0.1, h, &d, &g_ws), FCC_ERR_RANGE);
    assert_int_equal(fcc_lqg_design(&plant, 1e6, h, &d, &g_ws), FCC_ERR_RANGE);
    assert_int_equal(fcc_lqg_design(&plant, FCC_LQG_T_MAX * 1.01, h, &d, &g_ws), FCC_ERR_RANGE);
    assert_int_equal(fcc_lqg_design(&plant, NAN, h, &d, &g_ws), FCC_ERR_ARG);
    assert_int_equal(fcc_lqg_design(&plant, INFINITY, h, &d, &g_ws), FCC_ERR_ARG);
    assert_int_equal(fcc_lqg_design(&plant, 0.1, (fcc_lqg_solver_t)7, &d, &g_ws), FCC_ERR_ARG);
    assert_int_equal(fcc_lqg_design(NULL, 0.1, h, &d, &g_ws), FCC_ERR_ARG);
    assert_int_equal(fcc_lqg_design(&plant, 0.1, h, &d, NULL), FCC_ERR_ARG);
    fcc_lqg_plant_t bad = plant;
    bad.gyro_var = FCC_R(-0.8);
    assert_int_equal(fcc_lqg_design(&bad, 0.1, h, &d, &g_ws), FCC_ERR_RANGE);
    bad.gyro_var = FCC_R(0.0);
    assert_int_equal(fcc_lqg_design(&bad, 0.1, h, &d, &g_ws), FCC_ERR_RANGE);
    bad = plant;
    bad.accel_var = (fcc_real_t)NAN;
    assert_int_equal(fcc_lqg_design(&bad, 0.1, h, &d, &g_ws), FCC_ERR_ARG);
    bad = plant;
    bad.f[4] = (fcc_real_t)INFINITY;
    assert_int_equal(fcc_lqg_design(&bad, 0.1, h, &d, &g_ws), FCC_ERR_ARG);
    /* the gust mode made unstable (+2 /s): no input reaches it -> not stabilisable */
    bad = plant;
    bad.f[8] = FCC_R(2.0);
    assert_int_equal(fcc_lqg_design(&bad, 0.1, h, &d, &g_ws), FCC_ERR_NOT_STABILIZABLE);
    /* an unstable short period that no sensor sees -> the filter is not detectable */
    bad = plant;
    bad.f[0] = FCC_R(30.0);
    for (int i = 0; i < FCC_LQG_NY * FCC_LQG_NX; ++i) {
        bad.h[i] = FCC_R(0.0);
    }
    bad.h[2] = FCC_R(1.0); /* only the (decoupled) gust is measured */
    bad.f[5] = FCC_R(0.0);
    assert_int_equal(fcc_lqg_design(&bad, 0.1, FCC_LQG_SOLVER_DOUBLING, &d, &g_ws),
                     FCC_ERR_NOT_DETECTABLE);
    /* every failure left the last good design untouched */
    assert_memory_equal(&d, &before, sizeof d);
}

/* ---- D/A converter ------------------------------------------------------------- */

static void dac_quantizes_as_specified(void **state)
{
    (void)state;
    fcc_lqg_dac_t dac;
    int32_t code = 99;
    fcc_real_t u = 0;
    assert_int_equal(fcc_lqg_dac_init(&dac, 1), FCC_ERR_RANGE);
    assert_int_equal(fcc_lqg_dac_init(&dac, 17), FCC_ERR_RANGE);
    assert_int_equal(fcc_lqg_dac_init(NULL, 8), FCC_ERR_ARG);
    for (uint8_t n = FCC_LQG_BITS_MIN; n <= FCC_LQG_BITS_MAX; ++n) {
        fcc_assert_ok(fcc_lqg_dac_init(&dac, n));
        const double lsb = 0.8 / ldexp(1.0, n);
        fcc_assert_close(dac.lsb, lsb, FCC_TEST_TOL(1e-16, 1e-7), 0);
        assert_int_equal(dac.code_min, -(1 << (n - 1)));
        assert_int_equal(dac.code_max, (1 << (n - 1)) - 1);
        /* full scale: -0.4 is a code, +0.4 is one LSB beyond the top code */
        fcc_assert_ok(fcc_lqg_dac_convert(&dac, FCC_R(-0.4), &code, &u));
        assert_int_equal(code, dac.code_min);
        fcc_assert_close(u, -0.4, FCC_TEST_TOL(1e-15, 1e-7), 0);
        fcc_assert_ok(fcc_lqg_dac_convert(&dac, FCC_R(0.4), &code, &u));
        assert_int_equal(code, dac.code_max);
        fcc_assert_close(u, 0.4 - lsb, FCC_TEST_TOL(1e-15, 1e-6), 0);
        /* round half away from zero */
        fcc_assert_ok(fcc_lqg_dac_convert(&dac, (fcc_real_t)(0.5 * lsb), &code, &u));
        assert_int_equal(code, 1);
        fcc_assert_ok(fcc_lqg_dac_convert(&dac, (fcc_real_t)(-0.5 * lsb), &code, &u));
        assert_int_equal(code, -1);
        fcc_assert_ok(fcc_lqg_dac_convert(&dac, (fcc_real_t)(0.49 * lsb), &code, &u));
        assert_int_equal(code, 0);
        if (n >= 3) { /* at 2 bits the codes are -2..1 */
            fcc_assert_ok(fcc_lqg_dac_convert(&dac, (fcc_real_t)(2.6 * lsb), &code, &u));
            assert_int_equal(code, 3);
            fcc_assert_close(u, 3 * lsb, FCC_TEST_TOL(1e-15, 1e-6), 0);
        }
        /* far out of range clamps, no undefined int conversion */
        fcc_assert_ok(fcc_lqg_dac_convert(&dac, FCC_R(1e30), &code, &u));
        assert_int_equal(code, dac.code_max);
        fcc_assert_ok(fcc_lqg_dac_convert(&dac, -FCC_REAL_MAX, &code, &u));
        assert_int_equal(code, dac.code_min);
    }
    /* non-finite command: a status and the safe code 0 */
    fcc_assert_ok(fcc_lqg_dac_init(&dac, 8));
    code = 5;
    u = 1;
    assert_int_equal(fcc_lqg_dac_convert(&dac, (fcc_real_t)NAN, &code, &u), FCC_ERR_NOT_FINITE);
    assert_int_equal(code, 0);
    assert_true(u == 0);
    code = 5;
    assert_int_equal(fcc_lqg_dac_convert(&dac, (fcc_real_t)-INFINITY, &code, &u),
                     FCC_ERR_NOT_FINITE);
    assert_int_equal(code, 0);
    /* code -> angle, clamped */
    fcc_assert_ok(fcc_lqg_dac_value(&dac, 1000, &u));
    fcc_assert_close(u, 127 * 0.8 / 256, FCC_TEST_TOL(1e-15, 1e-7), 0);
    fcc_assert_ok(fcc_lqg_dac_value(&dac, -128, &u));
    fcc_assert_close(u, -0.4, FCC_TEST_TOL(1e-15, 1e-7), 0);
}

/* ---- runtime controller --------------------------------------------------------- */

static fcc_lqg_design_t g_design;

static int design_setup(void **state)
{
    (void)state;
    fcc_lqg_plant_t plant;
    if (fcc_lqg_plant_default(&plant) != FCC_OK) {
        return -1;
    }
    return fcc_lqg_design(&plant, 0.1, FCC_LQG_SOLVER_HAMILTONIAN, &g_design, &g_ws) == FCC_OK ? 0
                                                                                                : -1;
}

static void ctrl_step_is_the_seed_filter(void **state)
{
    (void)state;
    const fcc_lqg_design_t *d = &g_design;
    fcc_lqg_ctrl_t c;
    const fcc_real_t x0[3] = {FCC_R(0.01), FCC_R(-0.002), FCC_R(1.5)};
    fcc_assert_ok(fcc_lqg_ctrl_init(&c, d, 12, x0));
    const fcc_real_t y[2] = {FCC_R(0.03), FCC_R(-0.4)};
    /* reference, in double from the same gains */
    double innov[2];
    double xh[3];
    double xn[3];
    for (int i = 0; i < 2; ++i) {
        innov[i] = (double)y[i];
        for (int j = 0; j < 3; ++j) {
            innov[i] -= (double)d->h[i * 3 + j] * (double)x0[j];
        }
    }
    double u = 0;
    for (int i = 0; i < 3; ++i) {
        xh[i] = (double)x0[i] + (double)d->l[i * 2] * innov[0] + (double)d->l[i * 2 + 1] * innov[1];
    }
    for (int i = 0; i < 3; ++i) {
        u -= (double)d->k[i] * xh[i];
    }
    const double lsb = 0.8 / 4096;
    const double code = round(u / lsb);
    const double ua = code * lsb;
    for (int i = 0; i < 3; ++i) {
        xn[i] = (double)d->gamma[i] * ua;
        for (int j = 0; j < 3; ++j) {
            xn[i] += (double)d->phi[i * 3 + j] * xh[j];
        }
    }
    fcc_lqg_output_t out;
    fcc_assert_ok(fcc_lqg_ctrl_step(&c, y, &out));
    assert_true(out.measured);
    assert_false(out.saturated);
    for (int i = 0; i < 3; ++i) {
        fcc_assert_close(out.x_hat[i], xh[i], FCC_TEST_TOL(1e-14, 1e-5), 1e-9);
        fcc_assert_close(c.x_pred[i], xn[i], FCC_TEST_TOL(1e-14, 1e-5), 1e-9);
    }
    fcc_assert_close(out.u_cmd, u, FCC_TEST_TOL(1e-14, 1e-5), 0);
    assert_int_equal(out.code, (int32_t)code);
    fcc_assert_close(out.u_applied, ua, FCC_TEST_TOL(1e-15, 1e-6), 0);
    assert_int_equal(c.updates, 1);
    /* prediction only: x^ = xbar */
    fcc_real_t xbar[3];
    memcpy(xbar, c.x_pred, sizeof xbar);
    fcc_assert_ok(fcc_lqg_ctrl_predict(&c, &out));
    assert_false(out.measured);
    for (int i = 0; i < 3; ++i) {
        assert_true(out.x_hat[i] == xbar[i]);
    }
    assert_int_equal(c.predictions, 1);
}

static void ctrl_keeps_state_on_bad_input(void **state)
{
    (void)state;
    fcc_lqg_ctrl_t c;
    fcc_assert_ok(fcc_lqg_ctrl_init(&c, &g_design, 8, NULL));
    fcc_lqg_output_t out;
    const fcc_real_t y[2] = {FCC_R(0.1), FCC_R(3.0)};
    fcc_assert_ok(fcc_lqg_ctrl_step(&c, y, &out));
    const fcc_lqg_ctrl_t before = c;
    const fcc_lqg_output_t out_before = out;
    const fcc_real_t y_nan[2] = {(fcc_real_t)NAN, FCC_R(0.0)};
    const fcc_real_t y_inf[2] = {FCC_R(0.0), (fcc_real_t)INFINITY};
    assert_int_equal(fcc_lqg_ctrl_step(&c, y_nan, &out), FCC_ERR_NOT_FINITE);
    assert_int_equal(fcc_lqg_ctrl_step(&c, y_inf, &out), FCC_ERR_NOT_FINITE);
    /* finite but absurd: the estimate would overflow */
    const fcc_real_t y_huge[2] = {FCC_REAL_MAX, -FCC_REAL_MAX};
    assert_int_equal(fcc_lqg_ctrl_step(&c, y_huge, &out), FCC_ERR_NOT_FINITE);
    assert_memory_equal(&c, &before, sizeof c);
    assert_memory_equal(&out, &out_before, sizeof out);
    assert_int_equal(fcc_lqg_ctrl_step(NULL, y, &out), FCC_ERR_ARG);
    assert_int_equal(fcc_lqg_ctrl_predict(&c, NULL), FCC_ERR_ARG);
    /* init refusals */
    fcc_lqg_design_t broken = g_design;
    broken.k[1] = (fcc_real_t)NAN;
    assert_int_equal(fcc_lqg_ctrl_init(&c, &broken, 8, NULL), FCC_ERR_NOT_FINITE);
    assert_int_equal(fcc_lqg_ctrl_init(&c, &g_design, 1, NULL), FCC_ERR_RANGE);
    const fcc_real_t x_nan[3] = {0, (fcc_real_t)NAN, 0};
    assert_int_equal(fcc_lqg_ctrl_reset(&c, x_nan), FCC_ERR_NOT_FINITE);
    /* a large (consistent) angle of attack saturates the command at the limit */
    const fcc_real_t x_big[3] = {0, FCC_R(1.0), 0};
    fcc_assert_ok(fcc_lqg_ctrl_init(&c, &g_design, 8, x_big));
    const fcc_real_t y_big[2] = {FCC_R(0.0), FCC_R(-568.4)};
    fcc_assert_ok(fcc_lqg_ctrl_step(&c, y_big, &out));
    fcc_assert_close(out.u_cmd, -(double)g_design.k[1], 0.05, 0); /* u = -K x^, x^ ~ x_big */
    assert_true(out.saturated);
    fcc_assert_close(fabs((double)out.u_sat), 0.4, FCC_TEST_TOL(1e-15, 1e-7), 0);
    assert_true(out.code == c.dac.code_min || out.code == c.dac.code_max);
}

/* Closed loop on the exactly discretised plant (no noise): the design's
 * estimator and regulator bring q = 0.1 rad/s back to zero (paper's case). */
static void closed_loop_regulates(void **state)
{
    (void)state;
    const fcc_lqg_design_t *d = &g_design;
    const uint8_t bits[3] = {6, 8, 12};
    for (int b = 0; b < 3; ++b) {
        fcc_lqg_ctrl_t c;
        fcc_assert_ok(fcc_lqg_ctrl_init(&c, d, bits[b], NULL)); /* estimator starts at 0 */
        double x[3] = {0.1, 0.0, 0.0};
        double peak_late = 0;
        for (int k = 0; k < 60; ++k) { /* 6 s */
            fcc_real_t y[2];
            for (int i = 0; i < 2; ++i) {
                double s = 0;
                for (int j = 0; j < 3; ++j) {
                    s += (double)d->h[i * 3 + j] * x[j];
                }
                y[i] = (fcc_real_t)s;
            }
            fcc_lqg_output_t out;
            fcc_assert_ok(fcc_lqg_ctrl_step(&c, y, &out));
            double xn[3];
            for (int i = 0; i < 3; ++i) {
                xn[i] = (double)d->gamma[i] * (double)out.u_applied;
                for (int j = 0; j < 3; ++j) {
                    xn[i] += (double)d->phi[i * 3 + j] * x[j];
                }
            }
            memcpy(x, xn, sizeof x);
            if (k >= 30) {
                peak_late = fmax(peak_late, fabs(x[0]));
            }
        }
        /* from 0.1 rad/s to the quantisation floor (measured ~1e-5 rad/s for
         * 6-12 bits, the same in both builds) */
        print_message("%u bits: |q| after 3 s <= %.3g rad/s\n", (unsigned)bits[b], peak_late);
        assert_true(peak_late < 1e-4);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(c2d_matches_scipy),
        cmocka_unit_test(c2d_closed_forms_and_refusals),
        cmocka_unit_test(dare_four_states_cross_term),
        cmocka_unit_test(dare_refuses_bad_problems),
        cmocka_unit_test(design_matches_scipy),
        cmocka_unit_test(delayed_design_matches_scipy),
        cmocka_unit_test(design_refuses_bad_input),
        cmocka_unit_test(dac_quantizes_as_specified),
        cmocka_unit_test_setup(ctrl_step_is_the_seed_filter, design_setup),
        cmocka_unit_test_setup(ctrl_keeps_state_on_bad_input, design_setup),
        cmocka_unit_test_setup(closed_loop_regulates, design_setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
