/*
 * The Van Loan discretisation (firmware/lqg/fcc_c2d.c) refuses each bad
 * argument on its own: every matrix missing, empty or of the wrong shape, a
 * problem too large for the block exponential, a bad period, a non-finite
 * input -- one at a time, the others valid, so that each check is shown to
 * decide by itself.  Closed forms of a scalar plant check what is computed.
 * (The scipy comparison and the double integrator are in test_lqg.c.)
 */
#include "fcc_test.h"

#include <math.h>
#include <string.h>

#include "fcc_c2d.h"

static fcc_c2d_ws_t g_ws;

/* Storage for every matrix of a call, large enough for any shape the tests give them. */
enum { F, G, PHI, GAMMA, QC, QD, WX, WU, Q11, Q12, Q22, N_MATS };
typedef struct {
    double data[N_MATS][FCC_MAT_MAX_ELEMS];
    fcc_mat64_t m[N_MATS];
} problem_t;

static problem_t g_p;

/* A valid problem with n states and m inputs: F = -I (stable), G = 1, Qc = Wx = Wu = I. */
static problem_t *valid(uint16_t n, uint16_t m)
{
    memset(&g_p, 0, sizeof g_p);
    const uint16_t shape[N_MATS][2] = {
        [F] = {n, n},   [G] = {n, m},  [PHI] = {n, n}, [GAMMA] = {n, m}, [QC] = {n, n}, [QD] = {n, n},
        [WX] = {n, n},  [WU] = {m, m}, [Q11] = {n, n}, [Q12] = {n, m},   [Q22] = {m, m},
    };
    for (int k = 0; k < N_MATS; ++k) {
        g_p.m[k] = FCC_MAT64(shape[k][0], shape[k][1], g_p.data[k]);
    }
    for (uint16_t i = 0; i < n; ++i) {
        FCC_MAT_AT(&g_p.m[F], i, i) = -1.0;
        FCC_MAT_AT(&g_p.m[QC], i, i) = 1.0;
        FCC_MAT_AT(&g_p.m[WX], i, i) = 1.0;
        for (uint16_t j = 0; j < m; ++j) {
            FCC_MAT_AT(&g_p.m[G], i, j) = 1.0;
        }
    }
    for (uint16_t j = 0; j < m; ++j) {
        FCC_MAT_AT(&g_p.m[WU], j, j) = 1.0;
    }
    return &g_p;
}

static fcc_status_t zoh(problem_t *p, double t)
{
    return fcc_c2d_zoh(&p->m[F], &p->m[G], t, &p->m[PHI], &p->m[GAMMA], &g_ws);
}

static fcc_status_t noise(problem_t *p, double t)
{
    return fcc_c2d_noise(&p->m[F], &p->m[QC], t, &p->m[QD], &g_ws);
}

static fcc_status_t cost(problem_t *p, double t)
{
    return fcc_c2d_cost(&p->m[F], &p->m[G], &p->m[WX], &p->m[WU], t, &p->m[Q11], &p->m[Q12],
                        &p->m[Q22], &g_ws);
}

typedef fcc_status_t (*call_t)(problem_t *p, double t);

/* The one matrix k of a valid 2-state, 1-input problem spoiled each way a descriptor can be:
 * every call that reads it refuses with FCC_ERR_ARG. */
static void refuses_each_unusable_matrix(call_t call, const int *mats, size_t n_mats)
{
    for (size_t i = 0; i < n_mats; ++i) {
        const int k = mats[i];
        problem_t *p = valid(2, 1);
        fcc_mat64_t kept = p->m[k];
        p->m[k].data = NULL;
        assert_int_equal(call(p, 0.1), FCC_ERR_ARG);
        p->m[k] = kept;
        p->m[k].rows = 0;
        assert_int_equal(call(p, 0.1), FCC_ERR_ARG);
        p->m[k] = kept;
        p->m[k].cols = 0;
        assert_int_equal(call(p, 0.1), FCC_ERR_ARG);
        p->m[k] = kept;
        assert_int_equal(call(p, 0.1), FCC_OK); /* and restored, the call is accepted again */
    }
}

/* Matrix k of a valid problem given one row or one column too many: FCC_ERR_SIZE. */
static void refuses_each_wrong_shape(call_t call, const int *mats, size_t n_mats)
{
    for (size_t i = 0; i < n_mats; ++i) {
        const int k = mats[i];
        problem_t *p = valid(2, 1);
        p->m[k].rows++;
        assert_int_equal(call(p, 0.1), FCC_ERR_SIZE);
        p->m[k].rows--;
        p->m[k].cols++;
        assert_int_equal(call(p, 0.1), FCC_ERR_SIZE);
    }
}

/* Matrix k with a NaN: FCC_ERR_NOT_FINITE. */
static void refuses_each_non_finite(call_t call, const int *mats, size_t n_mats)
{
    for (size_t i = 0; i < n_mats; ++i) {
        problem_t *p = valid(2, 1);
        p->data[mats[i]][0] = NAN;
        assert_int_equal(call(p, 0.1), FCC_ERR_NOT_FINITE);
    }
}

static void refuses_bad_periods(call_t call)
{
    problem_t *p = valid(2, 1);
    assert_int_equal(call(p, 0.0), FCC_ERR_ARG);
    assert_int_equal(call(p, -0.1), FCC_ERR_ARG);
    assert_int_equal(call(p, NAN), FCC_ERR_ARG);
    assert_int_equal(call(p, INFINITY), FCC_ERR_ARG);
}

static void zoh_refusals(void **state)
{
    (void)state;
    static const int mats[] = {F, G, PHI, GAMMA};
    refuses_each_unusable_matrix(zoh, mats, 4);
    refuses_each_wrong_shape(zoh, mats, 4);
    static const int inputs[] = {F, G};
    refuses_each_non_finite(zoh, inputs, 2);
    refuses_bad_periods(zoh);
    problem_t *p = valid(2, 1);
    assert_int_equal(fcc_c2d_zoh(NULL, &p->m[G], 0.1, &p->m[PHI], &p->m[GAMMA], &g_ws), FCC_ERR_ARG);
    assert_int_equal(fcc_c2d_zoh(&p->m[F], &p->m[G], 0.1, &p->m[PHI], &p->m[GAMMA], NULL), FCC_ERR_ARG);
    /* n + m = 11 does not fit the block exponential; n + m = 10 does */
    p = valid(6, 5);
    assert_int_equal(zoh(p, 0.1), FCC_ERR_SIZE);
    p = valid(6, 4);
    fcc_assert_ok(zoh(p, 0.1));
}

static void noise_refusals(void **state)
{
    (void)state;
    static const int mats[] = {F, QC, QD};
    refuses_each_unusable_matrix(noise, mats, 3);
    refuses_each_wrong_shape(noise, mats, 3);
    static const int inputs[] = {F, QC};
    refuses_each_non_finite(noise, inputs, 2);
    refuses_bad_periods(noise);
    problem_t *p = valid(2, 1);
    assert_int_equal(fcc_c2d_noise(&p->m[F], &p->m[QC], 0.1, &p->m[QD], NULL), FCC_ERR_ARG);
    /* 2n = 12 does not fit; 2n = 10 does */
    p = valid(6, 1);
    assert_int_equal(noise(p, 0.1), FCC_ERR_SIZE);
    p = valid(5, 1);
    fcc_assert_ok(noise(p, 0.1));
}

static void cost_refusals(void **state)
{
    (void)state;
    static const int mats[] = {F, G, WX, WU, Q11, Q12, Q22};
    refuses_each_unusable_matrix(cost, mats, 7);
    refuses_each_wrong_shape(cost, mats, 7);
    static const int inputs[] = {F, G, WX, WU};
    refuses_each_non_finite(cost, inputs, 4);
    refuses_bad_periods(cost);
    problem_t *p = valid(2, 1);
    assert_int_equal(fcc_c2d_cost(&p->m[F], &p->m[G], &p->m[WX], &p->m[WU], 0.1, &p->m[Q11],
                                  &p->m[Q12], &p->m[Q22], NULL),
                     FCC_ERR_ARG);
    /* 2(n + m) = 12 does not fit; 2(n + m) = 10 does */
    p = valid(4, 2);
    assert_int_equal(cost(p, 0.1), FCC_ERR_SIZE);
    p = valid(3, 2);
    fcc_assert_ok(cost(p, 0.1));
}

/* x' = a x + u with a = -2, T = 0.5, unit weights and noise density q:
 * Phi = e^{aT}, Gamma = (e^{aT} - 1)/a, Qd = q (e^{2aT} - 1)/(2a),
 * Q11 = (e^{2aT} - 1)/(2a), Q12 = int e^{as} (e^{as} - 1)/a ds, Q22 = int Gamma(s)^2 ds + T. */
static void scalar_closed_forms(void **state)
{
    (void)state;
    const double a = -2.0;
    const double t = 0.5;
    const double q = 3.0;
    problem_t *p = valid(1, 1);
    p->data[F][0] = a;
    p->data[QC][0] = q;
    fcc_assert_ok(zoh(p, t));
    fcc_assert_ok(noise(p, t));
    fcc_assert_ok(cost(p, t));
    const double e1 = exp(a * t);
    const double e2 = exp(2.0 * a * t);
    fcc_assert_close(p->data[PHI][0], e1, 1e-14, 0);
    fcc_assert_close(p->data[GAMMA][0], (e1 - 1.0) / a, 1e-14, 0);
    fcc_assert_close(p->data[QD][0], q * (e2 - 1.0) / (2.0 * a), 1e-14, 0);
    fcc_assert_close(p->data[Q11][0], (e2 - 1.0) / (2.0 * a), 1e-14, 0);
    const double q12 = ((e2 - 1.0) / (2.0 * a) - (e1 - 1.0) / a) / a;
    fcc_assert_close(p->data[Q12][0], q12, 1e-13, 0);
    const double q22 = ((e2 - 1.0) / (2.0 * a) - 2.0 * (e1 - 1.0) / a + t) / (a * a) + t;
    fcc_assert_close(p->data[Q22][0], q22, 1e-13, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(zoh_refusals),
        cmocka_unit_test(noise_refusals),
        cmocka_unit_test(cost_refusals),
        cmocka_unit_test(scalar_closed_forms),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
