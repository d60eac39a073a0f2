/*
 * The Riccati solvers' argument checks (firmware/lqg/fcc_dare.c), one bad
 * argument at a time with the others valid: every matrix missing, empty, of
 * the wrong shape or non-finite, the optional cross term, an asymmetric
 * weight, a problem too large; and the gain and residual of a scalar problem
 * against its closed form.  Existence (PBH) and the 4-state reference are in
 * test_lqg.c.
 */
#include "fcc_test.h"

#include <math.h>
#include <string.h>

#include "fcc_dare.h"

static fcc_dare_ws_t g_ws;

enum { A, B, Q, R, S, X, K, N_MATS };
typedef struct {
    double data[N_MATS][FCC_MAT_MAX_ELEMS];
    fcc_mat64_t m[N_MATS];
    fcc_dare_problem_t p;
    bool with_s;
} problem_t;

static problem_t g_p;

static const fcc_dare_problem_t *problem(problem_t *p)
{
    p->p = (fcc_dare_problem_t){&p->m[A], &p->m[B], &p->m[Q], &p->m[R], p->with_s ? &p->m[S] : NULL};
    return &p->p;
}

/* A valid problem: n states, m inputs, B = [I; 0], the m controlled modes unstable (1.2), the
 * others stable (0.5), Q = I, R = I, S = 0. */
static problem_t *valid(uint16_t n, uint16_t m, bool with_s)
{
    memset(&g_p, 0, sizeof g_p);
    const uint16_t shape[N_MATS][2] = {[A] = {n, n}, [B] = {n, m}, [Q] = {n, n}, [R] = {m, m},
                                       [S] = {n, m}, [X] = {n, n}, [K] = {m, n}};
    for (int k = 0; k < N_MATS; ++k) {
        g_p.m[k] = FCC_MAT64(shape[k][0], shape[k][1], g_p.data[k]);
    }
    for (uint16_t i = 0; i < n; ++i) {
        FCC_MAT_AT(&g_p.m[A], i, i) = i < m ? 1.2 : 0.5;
        FCC_MAT_AT(&g_p.m[Q], i, i) = 1.0;
    }
    for (uint16_t j = 0; j < m; ++j) {
        FCC_MAT_AT(&g_p.m[B], j, j) = 1.0;
        FCC_MAT_AT(&g_p.m[R], j, j) = 1.0;
    }
    g_p.with_s = with_s;
    return &g_p;
}

static fcc_status_t doubling(problem_t *p)
{
    fcc_dare_info_t info;
    return fcc_dare_doubling(problem(p), &p->m[X], &info, &g_ws);
}

static fcc_status_t hamiltonian(problem_t *p)
{
    fcc_dare_info_t info;
    return fcc_dare_hamiltonian(problem(p), &p->m[X], &info, &g_ws);
}

static fcc_status_t gain(problem_t *p)
{
    return fcc_dare_gain(problem(p), &p->m[X], &p->m[K], &g_ws);
}

static fcc_status_t residual(problem_t *p)
{
    double res = 0.0;
    return fcc_dare_residual(problem(p), &p->m[X], &res, &g_ws);
}

typedef fcc_status_t (*call_t)(problem_t *p);
static const call_t k_calls[] = {doubling, hamiltonian, gain, residual};
#define N_CALLS (sizeof k_calls / sizeof k_calls[0])

static void each_unusable_matrix_is_refused(void **state)
{
    (void)state;
    static const int mats[] = {A, B, Q, R, S, X};
    for (size_t c = 0; c < N_CALLS; ++c) {
        for (size_t i = 0; i < sizeof mats / sizeof mats[0]; ++i) {
            problem_t *p = valid(2, 1, true);
            const fcc_mat64_t kept = p->m[mats[i]];
            p->m[mats[i]].data = NULL;
            assert_int_equal(k_calls[c](p), FCC_ERR_ARG);
            p->m[mats[i]] = kept;
            p->m[mats[i]].rows = 0;
            assert_int_equal(k_calls[c](p), FCC_ERR_ARG);
            p->m[mats[i]] = kept;
            p->m[mats[i]].cols = 0;
            assert_int_equal(k_calls[c](p), FCC_ERR_ARG);
            p->m[mats[i]] = kept;
            fcc_assert_ok(k_calls[c](p)); /* restored: accepted */
        }
    }
}

static void each_wrong_shape_is_refused(void **state)
{
    (void)state;
    static const int mats[] = {A, B, Q, R, S, X};
    for (size_t c = 0; c < N_CALLS; ++c) {
        for (size_t i = 0; i < sizeof mats / sizeof mats[0]; ++i) {
            problem_t *p = valid(2, 1, true);
            p->m[mats[i]].rows++;
            assert_int_equal(k_calls[c](p), FCC_ERR_SIZE);
            p->m[mats[i]].rows--;
            p->m[mats[i]].cols++;
            assert_int_equal(k_calls[c](p), FCC_ERR_SIZE);
        }
        /* more inputs than states; more states than the workspace holds; both limits met */
        problem_t *p = valid(2, 2, false);
        p->m[B].cols = 3;
        p->m[R] = FCC_MAT64(3, 3, p->data[R]);
        assert_int_equal(k_calls[c](p), FCC_ERR_SIZE);
        p = valid(FCC_DARE_MAX_N + 1, 1, false);
        assert_int_equal(k_calls[c](p), FCC_ERR_SIZE);
        p = valid(FCC_DARE_MAX_N, FCC_DARE_MAX_N, true);
        fcc_assert_ok(k_calls[c](p));
    }
}

static void non_finite_and_asymmetric_inputs_are_refused(void **state)
{
    (void)state;
    static const int mats[] = {A, B, Q, R, S};
    for (size_t c = 0; c < N_CALLS; ++c) {
        for (size_t i = 0; i < sizeof mats / sizeof mats[0]; ++i) {
            problem_t *p = valid(2, 1, true);
            p->data[mats[i]][0] = INFINITY;
            assert_int_equal(k_calls[c](p), FCC_ERR_NOT_FINITE);
        }
        problem_t *p = valid(2, 1, false);
        p->data[Q][1] = 0.5; /* Q(0,1) without Q(1,0) */
        assert_int_equal(k_calls[c](p), FCC_ERR_ARG);
        p = valid(2, 2, false);
        p->data[R][2] = 0.5; /* R(1,0) without R(0,1) */
        assert_int_equal(k_calls[c](p), FCC_ERR_ARG);
    }
    /* the gain and the residual also read X: a non-finite X is refused */
    problem_t *p = valid(2, 1, false);
    p->data[X][3] = NAN;
    assert_int_equal(gain(p), FCC_ERR_NOT_FINITE);
    assert_int_equal(residual(p), FCC_ERR_NOT_FINITE);
}

static void missing_workspace_or_output_is_refused(void **state)
{
    (void)state;
    problem_t *p = valid(2, 1, false);
    const fcc_dare_problem_t *pr = problem(p);
    fcc_dare_info_t info;
    double res = 0.0;
    assert_int_equal(fcc_dare_doubling(NULL, &p->m[X], &info, &g_ws), FCC_ERR_ARG);
    assert_int_equal(fcc_dare_doubling(pr, &p->m[X], NULL, &g_ws), FCC_ERR_ARG);
    assert_int_equal(fcc_dare_doubling(pr, &p->m[X], &info, NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_dare_hamiltonian(pr, &p->m[X], NULL, &g_ws), FCC_ERR_ARG);
    assert_int_equal(fcc_dare_gain(pr, &p->m[X], &p->m[K], NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_dare_gain(pr, &p->m[X], NULL, &g_ws), FCC_ERR_ARG);
    fcc_mat64_t k_wrong = FCC_MAT64(2, 2, p->data[K]);
    assert_int_equal(fcc_dare_gain(pr, &p->m[X], &k_wrong, &g_ws), FCC_ERR_SIZE);
    assert_int_equal(fcc_dare_residual(pr, &p->m[X], NULL, &g_ws), FCC_ERR_ARG);
    assert_int_equal(fcc_dare_residual(pr, &p->m[X], &res, NULL), FCC_ERR_ARG);
}

/* x' = a x + u, Q = R = 1: X = (a^2 + sqrt(a^4 + 4)) / 2, K = a X / (1 + X); with a cross
 * term S = s the gain becomes (a X + s) / (1 + X). */
static void scalar_closed_form(void **state)
{
    (void)state;
    const double a = 1.2;
    const double x = (a * a + sqrt(a * a * a * a + 4.0)) / 2.0;
    problem_t *p = valid(1, 1, false);
    fcc_assert_ok(doubling(p));
    fcc_assert_close(p->data[X][0], x, 1e-12, 0);
    fcc_assert_ok(hamiltonian(p));
    fcc_assert_close(p->data[X][0], x, 1e-12, 0);
    fcc_assert_ok(gain(p));
    fcc_assert_close(p->data[K][0], a * x / (1.0 + x), 1e-12, 0);
    double res = 1.0;
    fcc_assert_ok(fcc_dare_residual(problem(p), &p->m[X], &res, &g_ws));
    assert_true(res < 1e-14);
    p->data[X][0] = 2.0 * x; /* not the solution: the residual says so */
    fcc_assert_ok(fcc_dare_residual(problem(p), &p->m[X], &res, &g_ws));
    assert_true(res > 0.05);
    p = valid(1, 1, true);
    p->data[S][0] = 0.3;
    p->data[X][0] = x;
    fcc_assert_ok(gain(p));
    fcc_assert_close(p->data[K][0], (a * x + 0.3) / (1.0 + x), 1e-12, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(each_unusable_matrix_is_refused),
        cmocka_unit_test(each_wrong_shape_is_refused),
        cmocka_unit_test(non_finite_and_asymmetric_inputs_are_refused),
        cmocka_unit_test(missing_workspace_or_output_is_refused),
        cmocka_unit_test(scalar_closed_form),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
