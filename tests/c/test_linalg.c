/*
 * The dense linear algebra core (firmware/linalg): both flavours.  Known
 * closed forms, scipy reference values (tests/vectors/lqg/linalg_vectors.h,
 * generated) and the hard cases: ill-conditioned and (nearly) singular
 * systems, defective and repeated eigenvalues, expm of large-norm matrices.
 */
#include "fcc_test.h"

#include <math.h>
#include <string.h>

#include "fcc_mat.h"
#include "../vectors/lqg/linalg_vectors.h"

/* Scratch shared by the tests (large: keep it off the stack). */
static fcc_mat_lu_t g_lu;
static fcc_mat_expm_ws_t g_expm;
static fcc_mat_eig_ws_t g_eig;
static fcc_mat_svd_ws_t g_svd;
static fcc_mat64_expm_ws_t g_expm64;
static fcc_mat64_eig_ws_t g_eig64;

/* ---- helpers ----------------------------------------------------------------- */

static void load(fcc_real_t *dst, const double *src, size_t n)
{
    for (size_t i = 0; i < n; ++i) {
        dst[i] = (fcc_real_t)src[i];
    }
}

/* max_k ||A v_k - lambda_k v_k|| / ||A||_F over the eigenpairs of (wr, wi, V)
 * in fcc_mat_eig's storage convention, computed in double. */
static double eig_residual(const double *a, const fcc_real_t *wr, const fcc_real_t *wi,
                           const fcc_real_t *v, int n)
{
    double anorm = 0.0;
    for (int i = 0; i < n * n; ++i) {
        anorm += a[i] * a[i];
    }
    anorm = sqrt(anorm);
    double worst = 0.0;
    for (int k = 0; k < n; ++k) {
        const bool cplx = wi[k] != 0;
        const int kr = (cplx && wi[k] < 0) ? k - 1 : k; /* column of the real part */
        const double sign = (cplx && wi[k] < 0) ? -1.0 : 1.0;
        double res = 0.0;
        for (int i = 0; i < n; ++i) {
            double re = 0.0;
            double im = 0.0;
            for (int j = 0; j < n; ++j) {
                re += a[i * n + j] * (double)v[j * n + kr];
                im += cplx ? a[i * n + j] * sign * (double)v[j * n + kr + 1] : 0.0;
            }
            const double vr = (double)v[i * n + kr];
            const double vi = cplx ? sign * (double)v[i * n + kr + 1] : 0.0;
            re -= (double)wr[k] * vr - (double)wi[k] * vi;
            im -= (double)wr[k] * vi + (double)wi[k] * vr;
            res += re * re + im * im;
        }
        worst = sqrt(res) > worst ? sqrt(res) : worst;
    }
    return anorm > 0.0 ? worst / anorm : worst;
}

/* Sort (re, im) by decreasing modulus, then decreasing imaginary part. */
static void sort_eigs(double *re, double *im, int n)
{
    for (int i = 1; i < n; ++i) {
        const double r = re[i];
        const double m = im[i];
        int j = i;
        while (j > 0 && (hypot(re[j - 1], im[j - 1]) < hypot(r, m) ||
                         (hypot(re[j - 1], im[j - 1]) == hypot(r, m) && im[j - 1] < m))) {
            re[j] = re[j - 1];
            im[j] = im[j - 1];
            --j;
        }
        re[j] = r;
        im[j] = m;
    }
}

/* The computed spectrum (re, im) equals the expected one as a multiset:
 * each expected eigenvalue is matched to the nearest unused computed one. */
static void assert_same_spectrum(const double *re, const double *im, const double *ere,
                                 const double *eim, int n, double tol)
{
    bool used[FCC_MAT_MAX_DIM] = {false};
    for (int i = 0; i < n; ++i) {
        int best = -1;
        double dist = INFINITY;
        for (int j = 0; j < n; ++j) {
            const double d = hypot(re[j] - ere[i], im[j] - eim[i]);
            if (!used[j] && d < dist) {
                dist = d;
                best = j;
            }
        }
        used[best] = true;
        if (!(dist <= tol)) {
            print_error("eigenvalue %.17g%+.17gj: nearest computed is %.3g away (> %.3g)\n", ere[i],
                        eim[i], dist, tol);
            fail();
        }
    }
}

/* ---- descriptors, products, norms -------------------------------------------- */

static void basic_operations(void **state)
{
    (void)state;
    fcc_real_t a_d[6] = {1, 2, 3, 4, 5, 6}; /* 2 x 3 */
    fcc_real_t b_d[6] = {7, 8, 9, 10, 11, 12}; /* 3 x 2 */
    fcc_real_t c_d[4];
    fcc_real_t t_d[9];
    fcc_mat_t a;
    fcc_mat_t b;
    fcc_mat_t c = FCC_MAT(2, 2, c_d);
    fcc_assert_ok(fcc_mat_init(&a, 2, 3, a_d));
    fcc_assert_ok(fcc_mat_init(&b, 3, 2, b_d));
    fcc_assert_ok(fcc_mat_mul(&a, &b, &c));
    const double ab[4] = {58, 64, 139, 154};
    fcc_assert_reals_close(c_d, ab, 4, 0.0, "c_d");
    fcc_mat_t t3 = FCC_MAT(3, 3, t_d);
    fcc_assert_ok(fcc_mat_mul_tn(&a, &a, &t3)); /* a^T a */
    const double ata[9] = {17, 22, 27, 22, 29, 36, 27, 36, 45};
    fcc_assert_reals_close(t_d, ata, 9, 0.0, "t_d");
    fcc_assert_ok(fcc_mat_mul_nt(&a, &a, &c)); /* a a^T */
    const double aat[4] = {14, 32, 32, 77};
    fcc_assert_reals_close(c_d, aat, 4, 0.0, "c_d");
    fcc_mat_t at = FCC_MAT(3, 2, t_d);
    fcc_assert_ok(fcc_mat_trans(&a, &at));
    const double a_t[6] = {1, 4, 2, 5, 3, 6};
    fcc_assert_reals_close(t_d, a_t, 6, 0.0, "t_d");
    fcc_assert_ok(fcc_mat_add(&a, &a, &a)); /* in place */
    fcc_assert_ok(fcc_mat_scale(&a, FCC_R(0.5), &a));
    assert_int_equal(fcc_mat_sub(&a, &at, &a), FCC_ERR_SIZE);
    const double a_back[6] = {1, 2, 3, 4, 5, 6};
    fcc_assert_reals_close(a_d, a_back, 6, 0.0, "a_d");

    /* blocks */
    fcc_real_t big_d[16] = {0};
    fcc_mat_t big = FCC_MAT(4, 4, big_d);
    fcc_assert_ok(fcc_mat_set_block(&big, 1, 1, &c));
    fcc_real_t back_d[4];
    fcc_mat_t back = FCC_MAT(2, 2, back_d);
    fcc_assert_ok(fcc_mat_get_block(&big, 1, 1, &back));
    fcc_assert_reals_close(back_d, aat, 4, 0.0, "back_d");
    assert_int_equal(fcc_mat_set_block(&big, 3, 3, &c), FCC_ERR_SIZE);
    fcc_assert_ok(fcc_mat_identity(&big));
    assert_true(big_d[0] == 1 && big_d[5] == 1 && big_d[1] == 0);

    /* symmetrize */
    fcc_real_t s_d[4] = {1, 2, 4, 3};
    fcc_mat_t s = FCC_MAT(2, 2, s_d);
    fcc_assert_ok(fcc_mat_symmetrize(&s));
    assert_true(s_d[1] == 3 && s_d[2] == 3);
}

static void bad_arguments_are_refused(void **state)
{
    (void)state;
    fcc_real_t d[9] = {0};
    fcc_real_t e[9] = {0};
    fcc_real_t w[6] = {0};
    fcc_mat_t m = FCC_MAT(3, 3, d);
    fcc_mat_t n = FCC_MAT(3, 3, e);
    fcc_mat_t wrong = FCC_MAT(2, 3, w);
    fcc_mat_t empty = FCC_MAT(0, 3, e);
    fcc_mat_t null_data = {3, 3, NULL};
    assert_int_equal(fcc_mat_init(&m, 0, 3, d), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_init(&m, 3, 3, NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_init(NULL, 3, 3, d), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_mul(&m, &m, &m), FCC_ERR_ARG); /* output aliases input */
    assert_int_equal(fcc_mat_mul(&m, &n, &wrong), FCC_ERR_SIZE);
    assert_int_equal(fcc_mat_add(&m, &wrong, &n), FCC_ERR_SIZE);
    assert_int_equal(fcc_mat_add(&m, &null_data, &n), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_copy(&empty, &n), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_trans(&m, &m), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_identity(&wrong), FCC_ERR_SIZE);
    fcc_real_t x = 0;
    assert_int_equal(fcc_mat_norm_1(&m, NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_mat_norm_1(NULL, &x), FCC_ERR_ARG);
    d[4] = (fcc_real_t)NAN;
    assert_int_equal(fcc_mat_check_finite(&m), FCC_ERR_NOT_FINITE);
    assert_int_equal(fcc_mat_lu_factor(&g_lu, &m), FCC_ERR_NOT_FINITE);
    assert_int_equal(fcc_mat_expm(&m, &n, &g_expm), FCC_ERR_NOT_FINITE);
    fcc_real_t wr[3];
    fcc_real_t wi[3];
    assert_int_equal(fcc_mat_eig(&m, wr, wi, NULL, &g_eig), FCC_ERR_NOT_FINITE);
    /* too large for the fixed workspaces */
    static fcc_real_t huge_d[(FCC_MAT_MAX_DIM + 1) * (FCC_MAT_MAX_DIM + 1)];
    fcc_mat_t huge = FCC_MAT(FCC_MAT_MAX_DIM + 1, FCC_MAT_MAX_DIM + 1, huge_d);
    assert_int_equal(fcc_mat_lu_factor(&g_lu, &huge), FCC_ERR_SIZE);
    assert_int_equal(fcc_mat_eig(&huge, wr, wi, NULL, &g_eig), FCC_ERR_SIZE);
}

static void norms(void **state)
{
    (void)state;
    fcc_real_t d[4] = {3, 0, 4, 5}; /* singular values sqrt(45), sqrt(5) */
    fcc_mat_t a = FCC_MAT(2, 2, d);
    fcc_real_t v = 0;
    fcc_assert_ok(fcc_mat_norm_1(&a, &v));
    fcc_assert_close(v, 7.0, 0, 0);
    fcc_assert_ok(fcc_mat_norm_inf(&a, &v));
    fcc_assert_close(v, 9.0, 0, 0);
    fcc_assert_ok(fcc_mat_norm_max(&a, &v));
    fcc_assert_close(v, 5.0, 0, 0);
    fcc_assert_ok(fcc_mat_norm_fro(&a, &v));
    fcc_assert_close(v, sqrt(50.0), FCC_TEST_TOL(1e-15, 1e-7), 0);
    fcc_assert_ok(fcc_mat_norm_2(&a, &v, &g_svd));
    fcc_assert_close(v, sqrt(45.0), FCC_TEST_TOL(1e-15, 1e-6), 0);
    /* no overflow in the Frobenius norm of huge entries */
    fcc_real_t h[2] = {FCC_REAL_MAX / 2, FCC_REAL_MAX / 2};
    fcc_mat_t hm = FCC_MAT(1, 2, h);
    fcc_assert_ok(fcc_mat_norm_fro(&hm, &v));
    assert_true(FCC_IS_FINITE(v));
    fcc_assert_close(v, (double)FCC_REAL_MAX / sqrt(2.0), FCC_TEST_TOL(1e-15, 1e-6), 0);
    /* matrix-relative difference */
    fcc_real_t e[4] = {3, 0, 4, (fcc_real_t)5.5};
    fcc_mat_t b = FCC_MAT(2, 2, e);
    fcc_assert_ok(fcc_mat_rel_diff(&b, &a, &v));
    fcc_assert_close(v, 0.1, FCC_TEST_TOL(1e-15, 1e-6), 0);
}

static void singular_values(void **state)
{
    (void)state;
    /* wide 3 x 5 with rank 2 (row 3 = row 1 + row 2) */
    fcc_real_t d[15] = {1, 2, 3, 4, 5, 2, 0, 1, 0, 2, 3, 2, 4, 4, 7};
    fcc_mat_t a = FCC_MAT(3, 5, d);
    fcc_real_t s[3];
    fcc_assert_ok(fcc_mat_svd_values(&a, s, &g_svd));
    assert_true(s[0] >= s[1] && s[1] >= s[2]);
    fcc_assert_close(s[2], 0.0, 0, FCC_TEST_TOL(1e-14, 1e-5) * (double)s[0]);
    assert_true(s[1] > FCC_R(0.5));
    /* Frobenius norm = sqrt(sum s^2) */
    fcc_real_t fro = 0;
    fcc_assert_ok(fcc_mat_norm_fro(&a, &fro));
    fcc_assert_close(sqrt((double)(s[0] * s[0] + s[1] * s[1] + s[2] * s[2])), fro,
                     FCC_TEST_TOL(1e-14, 1e-6), 0);
    /* graded diagonal: small singular values to full relative accuracy */
    fcc_real_t g[9] = {1e-6f, 0, 0, 0, 1, 0, 0, 0, 1e6f};
    fcc_mat_t gm = FCC_MAT(3, 3, g);
    fcc_assert_ok(fcc_mat_svd_values(&gm, s, &g_svd));
    fcc_assert_close(s[2], (double)g[0], FCC_TEST_TOL(1e-14, 1e-6), 0);
    fcc_assert_close(s[0], (double)g[8], FCC_TEST_TOL(1e-14, 1e-6), 0);
}

/* ---- LU, Cholesky, inverse ---------------------------------------------------- */

static void lu_solve_needs_pivoting(void **state)
{
    (void)state;
    /* Without row exchanges the 1e-20 pivot destroys the answer. */
    fcc_real_t d[4] = {(fcc_real_t)1e-20, 1, 1, 1};
    fcc_real_t bd[2] = {1, 2};
    fcc_real_t xd[2];
    fcc_mat_t a = FCC_MAT(2, 2, d);
    fcc_mat_t b = FCC_MAT(2, 1, bd);
    fcc_mat_t x = FCC_MAT(2, 1, xd);
    fcc_assert_ok(fcc_mat_solve(&a, &b, &x, &g_lu));
    fcc_assert_close(xd[0], 1.0, FCC_TEST_TOL(1e-15, 1e-6), 0);
    fcc_assert_close(xd[1], 1.0, FCC_TEST_TOL(1e-15, 1e-6), 0);
    /* A^T x = b through the same factors */
    fcc_real_t m[9] = {4, -2, 1, 3, 6, -4, 2, 1, 8};
    fcc_real_t b3[3] = {1, 2, 3};
    fcc_real_t x3[3];
    fcc_mat_t ma = FCC_MAT(3, 3, m);
    fcc_mat_t mb = FCC_MAT(3, 1, b3);
    fcc_mat_t mx = FCC_MAT(3, 1, x3);
    fcc_assert_ok(fcc_mat_lu_factor(&g_lu, &ma));
    fcc_assert_ok(fcc_mat_lu_solve_trans(&g_lu, &mb, &mx));
    for (int i = 0; i < 3; ++i) { /* (A^T x)_i = sum_j A(j, i) x_j */
        double s = 0;
        for (int j = 0; j < 3; ++j) {
            s += (double)m[j * 3 + i] * (double)x3[j];
        }
        fcc_assert_close(s, b3[i], FCC_TEST_TOL(1e-14, 1e-6), 1e-6);
    }
    /* inverse: A A^-1 = I, in place allowed */
    fcc_real_t inv[9];
    fcc_real_t prod[9];
    fcc_mat_t mi = FCC_MAT(3, 3, inv);
    fcc_mat_t mp = FCC_MAT(3, 3, prod);
    fcc_assert_ok(fcc_mat_inv(&ma, &mi, &g_lu));
    fcc_assert_ok(fcc_mat_mul(&ma, &mi, &mp));
    const double eye[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    fcc_assert_reals_close(prod, eye, 9, FCC_TEST_TOL(1e-15, 1e-6), "prod");
}

static void lu_ill_conditioned_hilbert(void **state)
{
    (void)state;
    /* Hilbert 8x8: cond_1 = 3.387e10.  Double solves it to ~cond*eps; single
     * precision must say it cannot (singular, or rcond below 1e-6). */
    enum { N = 8 };
    fcc_real_t h[N * N];
    fcc_real_t b[N];
    for (int i = 0; i < N; ++i) {
        b[i] = 0;
        for (int j = 0; j < N; ++j) {
            h[i * N + j] = (fcc_real_t)(1.0 / (i + j + 1));
            b[i] += h[i * N + j]; /* exact solution: ones */
        }
    }
    fcc_mat_t a = FCC_MAT(N, N, h);
    const fcc_status_t st = fcc_mat_lu_factor(&g_lu, &a);
    fcc_real_t rcond = 1;
#ifdef FCC_REAL_FLOAT
    if (st == FCC_OK) {
        fcc_assert_ok(fcc_mat_lu_rcond(&g_lu, &rcond));
        assert_true(rcond < FCC_R(1e-6));
    } else {
        assert_int_equal(st, FCC_ERR_SINGULAR);
    }
#else
    fcc_assert_ok(st);
    fcc_assert_ok(fcc_mat_lu_rcond(&g_lu, &rcond));
    assert_true(1.0 / rcond > 1e10 && 1.0 / rcond < 1e11); /* exact: 3.387e10 */
    fcc_real_t x[N];
    fcc_mat_t mb = FCC_MAT(N, 1, b);
    fcc_mat_t mx = FCC_MAT(N, 1, x);
    fcc_assert_ok(fcc_mat_lu_solve(&g_lu, &mb, &mx));
    for (int i = 0; i < N; ++i) {
        fcc_assert_close(x[i], 1.0, 1e-4, 0); /* forward error ~ cond * eps */
    }
    /* ... but the residual is at rounding level (backward stable) */
    for (int i = 0; i < N; ++i) {
        double r = -(double)b[i];
        for (int j = 0; j < N; ++j) {
            r += (double)h[i * N + j] * (double)x[j];
        }
        fcc_assert_close(r, 0.0, 0, 1e-14);
    }
#endif
}

static void lu_singular_and_nearly_singular(void **state)
{
    (void)state;
    fcc_real_t s3[9] = {1, 2, 3, 4, 5, 6, 7, 8, 9}; /* rank 2 */
    fcc_mat_t a = FCC_MAT(3, 3, s3);
    assert_int_equal(fcc_mat_lu_factor(&g_lu, &a), FCC_ERR_SINGULAR);
    fcc_real_t z[4] = {0, 0, 0, 0};
    fcc_mat_t zm = FCC_MAT(2, 2, z);
    assert_int_equal(fcc_mat_lu_factor(&g_lu, &zm), FCC_ERR_SINGULAR);
    fcc_real_t inv[4];
    fcc_mat_t mi = FCC_MAT(2, 2, inv);
    assert_int_equal(fcc_mat_inv(&zm, &mi, &g_lu), FCC_ERR_SINGULAR);
    /* 1 + eps/2 rounds to 1: singular to working precision */
    fcc_real_t n1[4] = {1, 1, 1, 1 + FCC_EPS / 2};
    fcc_mat_t m1 = FCC_MAT(2, 2, n1);
    assert_int_equal(fcc_mat_lu_factor(&g_lu, &m1), FCC_ERR_SINGULAR);
    /* 1 + 64 eps is nearly singular but a matrix: it factorises, rcond tells */
    fcc_real_t n2[4] = {1, 1, 1, 1 + 64 * FCC_EPS};
    fcc_mat_t m2 = FCC_MAT(2, 2, n2);
    fcc_assert_ok(fcc_mat_lu_factor(&g_lu, &m2));
    fcc_real_t rcond = 0;
    fcc_assert_ok(fcc_mat_lu_rcond(&g_lu, &rcond));
    fcc_assert_close(rcond, 64.0 * (double)FCC_EPS / 4.0, 0.05, 0);
}

static void cholesky(void **state)
{
    (void)state;
    /* Hilbert 5x5 is positive definite (cond 4.8e5) */
    enum { N = 5 };
    fcc_real_t h[N * N];
    fcc_real_t l[N * N];
    fcc_real_t b[N];
    fcc_real_t x[N];
    for (int i = 0; i < N; ++i) {
        b[i] = 0;
        for (int j = 0; j < N; ++j) {
            h[i * N + j] = (fcc_real_t)(1.0 / (i + j + 1));
            b[i] += h[i * N + j];
        }
    }
    fcc_mat_t a = FCC_MAT(N, N, h);
    fcc_mat_t ml = FCC_MAT(N, N, l);
    fcc_mat_t mb = FCC_MAT(N, 1, b);
    fcc_mat_t mx = FCC_MAT(N, 1, x);
    fcc_assert_ok(fcc_mat_chol(&a, &ml));
    for (int i = 0; i < N; ++i) {
        for (int j = i + 1; j < N; ++j) {
            assert_true(l[i * N + j] == 0);
        }
        for (int j = 0; j <= i; ++j) { /* (L L^T)_ij = H_ij */
            double s = 0;
            for (int k = 0; k < N; ++k) {
                s += (double)l[i * N + k] * (double)l[j * N + k];
            }
            fcc_assert_close(s, h[i * N + j], FCC_TEST_TOL(1e-14, 1e-6), 0);
        }
    }
    fcc_assert_ok(fcc_mat_chol_solve(&ml, &mb, &mx));
    for (int i = 0; i < N; ++i) {
        fcc_assert_close(x[i], 1.0, FCC_TEST_TOL(1e-9, 0.2), 0);
    }
    /* in place */
    fcc_assert_ok(fcc_mat_chol(&a, &a));
    for (int i = 0; i < N * N; ++i) {
        fcc_assert_close(h[i], l[i], 0, 0);
    }
    /* indefinite and semidefinite matrices are refused */
    fcc_real_t ind[4] = {1, 2, 2, 1};
    fcc_real_t semi[4] = {1, 1, 1, 1};
    fcc_real_t out[4];
    fcc_mat_t mi = FCC_MAT(2, 2, ind);
    fcc_mat_t ms = FCC_MAT(2, 2, semi);
    fcc_mat_t mo = FCC_MAT(2, 2, out);
    assert_int_equal(fcc_mat_chol(&mi, &mo), FCC_ERR_NOT_POSDEF);
    assert_int_equal(fcc_mat_chol(&ms, &mo), FCC_ERR_NOT_POSDEF);
}

/* ---- matrix exponential --------------------------------------------------------- */

static void expm_closed_forms(void **state)
{
    (void)state;
    fcc_real_t a[9] = {0};
    fcc_real_t e[9];
    fcc_mat_t ma = FCC_MAT(3, 3, a);
    fcc_mat_t me = FCC_MAT(3, 3, e);
    fcc_assert_ok(fcc_mat_expm(&ma, &me, &g_expm));
    const double eye[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    fcc_assert_reals_close(e, eye, 9, 0.0, "e");
    /* nilpotent: exp(N) = I + N + N^2/2 exactly */
    const fcc_real_t c = 3;
    fcc_real_t nil[9] = {0, c, 0, 0, 0, c, 0, 0, 0};
    fcc_mat_t mn = FCC_MAT(3, 3, nil);
    fcc_assert_ok(fcc_mat_expm(&mn, &me, &g_expm));
    const double en[9] = {1, 3, 4.5, 0, 1, 3, 0, 0, 1};
    fcc_assert_reals_close(e, en, 9, FCC_TEST_TOL(1e-15, 1e-6), "e");
    /* upper triangular with a large off-diagonal: ||A||_1 = 1e4, 11 squarings in
     * double; single precision needs 12 and each roughly doubles the error */
    const double p = -1.0;
    const double q = -1.5;
    const double b = 1e4;
    fcc_real_t t2[4] = {(fcc_real_t)p, (fcc_real_t)b, 0, (fcc_real_t)q};
    fcc_real_t e2[4];
    fcc_mat_t mt = FCC_MAT(2, 2, t2);
    fcc_mat_t me2 = FCC_MAT(2, 2, e2);
    fcc_assert_ok(fcc_mat_expm(&mt, &me2, &g_expm));
    const double et[4] = {exp(p), b * (exp(p) - exp(q)) / (p - q), 0, exp(q)};
    fcc_assert_reals_close(e2, et, 4, FCC_TEST_TOL(1e-13, 5e-4), "e2");
    /* rotation by 100 rad: norm 100 */
    const double th = 100.0;
    fcc_real_t r[4] = {0, (fcc_real_t)th, (fcc_real_t)-th, 0};
    fcc_mat_t mr = FCC_MAT(2, 2, r);
    fcc_assert_ok(fcc_mat_expm(&mr, &me2, &g_expm));
    const double er[4] = {cos(th), sin(th), -sin(th), cos(th)};
    fcc_assert_reals_close(e2, er, 4, FCC_TEST_TOL(1e-13, 1e-4), "e2");
    /* very negative diagonal underflows gracefully, positive overflows -> status */
    fcc_real_t dn[4] = {-1000, 0, 0, 1};
    fcc_mat_t md = FCC_MAT(2, 2, dn);
    fcc_assert_ok(fcc_mat_expm(&md, &me2, &g_expm));
    /* (2^8 squarings of e^(1/256): the known ~s*eps loss of scaling and
     * squaring when eigenvalue magnitudes differ widely) */
    const double ed[4] = {0, 0, 0, exp(1.0)};
    fcc_assert_reals_close(e2, ed, 4, FCC_TEST_TOL(1e-13, 1e-5), "e2");
    dn[0] = 1000;
    assert_int_equal(fcc_mat_expm(&md, &me2, &g_expm), FCC_ERR_NOT_FINITE);
    assert_int_equal(fcc_mat_expm(&md, &md, &g_expm), FCC_ERR_ARG); /* e aliases a */
}

static void expm_scipy_vectors(void **state)
{
    (void)state;
    /* skew 8x8 with ||A||_1 ~ 300, a non-normal 6x6, the lqrd block at T = 1 s */
    for (int c = 0; c < LINALG_EXPM_VECTOR_COUNT; ++c) {
        const linalg_expm_vector_t *v = &linalg_expm_vectors[c];
        const int n = v->n;
        fcc_real_t a[100];
        fcc_real_t e[100];
        double a64[100];
        double e64[100];
        load(a, v->a, (size_t)(n * n));
        memcpy(a64, v->a, sizeof(double) * (size_t)(n * n));
        fcc_mat_t ma = FCC_MAT(n, n, a);
        fcc_mat_t me = FCC_MAT(n, n, e);
        fcc_mat64_t ma64 = FCC_MAT64(n, n, a64);
        fcc_mat64_t me64 = FCC_MAT64(n, n, e64);
        print_message("expm %s\n", v->name);
        fcc_assert_ok(fcc_mat_expm(&ma, &me, &g_expm));
        fcc_assert_reals_close(e, v->expm, (size_t)(n * n), FCC_TEST_TOL(1e-11, 1e-3), "e");
        fcc_assert_ok(fcc_mat64_expm(&ma64, &me64, &g_expm64));
        fcc_assert_doubles_close(e64, v->expm, (size_t)(n * n), 1e-11, "e64");
    }
}

/* ---- eigenvalues and eigenvectors ----------------------------------------------- */

/* Eigen-decompose a (double data) in the fcc_real_t flavour; check residuals. */
static void eig_with_residual(const double *a, int n, fcc_real_t *wr, fcc_real_t *wi,
                              fcc_real_t *v, double tol)
{
    fcc_real_t ar[FCC_MAT_MAX_ELEMS];
    load(ar, a, (size_t)(n * n));
    fcc_mat_t ma = FCC_MAT(n, n, ar);
    fcc_mat_t mv = FCC_MAT(n, n, v);
    fcc_assert_ok(fcc_mat_eig(&ma, wr, wi, &mv, &g_eig));
    const double res = eig_residual(a, wr, wi, v, n);
    if (!(res <= tol)) {
        print_error("eigenvector residual %.3g > %.3g\n", res, tol);
        fail();
    }
    for (int k = 0; k < n; ++k) { /* unit 2-norm columns (pairs jointly) */
        double s = 0;
        const int cols = (wi[k] != 0) ? 2 : 1;
        const int k0 = (wi[k] < 0) ? k - 1 : k;
        for (int c = 0; c < cols; ++c) {
            for (int i = 0; i < n; ++i) {
                s += (double)v[i * n + k0 + c] * (double)v[i * n + k0 + c];
            }
        }
        fcc_assert_close(s, 1.0, FCC_TEST_TOL(1e-13, 1e-5), 0);
    }
}

static void eig_simple_spectra(void **state)
{
    (void)state;
    fcc_real_t wr[FCC_MAT_MAX_DIM];
    fcc_real_t wi[FCC_MAT_MAX_DIM];
    fcc_real_t v[FCC_MAT_MAX_ELEMS];
    const double tol = FCC_TEST_TOL(1e-14, 1e-6);
    /* triangular: eigenvalues are the diagonal */
    const double tri[9] = {2, 5, -1, 0, -3, 7, 0, 0, 0.5};
    eig_with_residual(tri, 3, wr, wi, v, tol);
    double re[3] = {wr[0], wr[1], wr[2]};
    double im[3] = {wi[0], wi[1], wi[2]};
    sort_eigs(re, im, 3);
    fcc_assert_close(re[0], -3.0, tol, 0);
    fcc_assert_close(re[1], 2.0, tol, 0);
    fcc_assert_close(re[2], 0.5, tol, 0);
    /* rotation generator: +-i, positive imaginary part first */
    const double rot[4] = {0, 1, -1, 0};
    eig_with_residual(rot, 2, wr, wi, v, tol);
    fcc_assert_close(wr[0], 0.0, 0, tol);
    fcc_assert_close(wi[0], 1.0, tol, 0);
    fcc_assert_close(wi[1], -1.0, tol, 0);
    /* companion matrix of (x-1)(x-2)(x-3)(x+1)(x^2+1) = x^6 - 5x^5 + 6x^4 - x^2 + 5x - 6 */
    const double comp[36] = {5, -6, 0, 1, -5, 6, 1, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0,
                             0, 0,  1, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1, 0};
    eig_with_residual(comp, 6, wr, wi, v, FCC_TEST_TOL(1e-13, 1e-5));
    double cre[6];
    double cim[6];
    for (int i = 0; i < 6; ++i) {
        cre[i] = wr[i];
        cim[i] = wi[i];
    }
    const double ere[6] = {3, 2, 1, -1, 0, 0};
    const double eim[6] = {0, 0, 0, 0, 1, -1};
    assert_same_spectrum(cre, cim, ere, eim, 6, FCC_TEST_TOL(1e-12, 1e-4));
    /* zero matrix and 1x1 */
    const double zero[9] = {0};
    eig_with_residual(zero, 3, wr, wi, v, 0.0);
    assert_true(wr[0] == 0 && wr[1] == 0 && wr[2] == 0);
    const double one[1] = {-4.25};
    eig_with_residual(one, 1, wr, wi, v, 0.0);
    assert_true(wr[0] == FCC_R(-4.25) && wi[0] == 0 && (v[0] == 1 || v[0] == -1));
}

static void eig_defective_and_repeated(void **state)
{
    (void)state;
    fcc_real_t wr[FCC_MAT_MAX_DIM];
    fcc_real_t wi[FCC_MAT_MAX_DIM];
    fcc_real_t v[FCC_MAT_MAX_ELEMS];
    /* 2x2 Jordan block: eigenvalue 2 twice, one eigenvector (both columns ~ e1) */
    const double j2[4] = {2, 1, 0, 2};
    eig_with_residual(j2, 2, wr, wi, v, FCC_TEST_TOL(1e-15, 1e-6));
    fcc_assert_close(wr[0], 2.0, 0, 0);
    fcc_assert_close(wr[1], 2.0, 0, 0);
    fcc_assert_close(fabs((double)v[0]), 1.0, FCC_TEST_TOL(1e-15, 1e-6), 0);
    fcc_assert_close(fabs((double)v[1]), 1.0, FCC_TEST_TOL(1e-12, 1e-5), 0);
    /* 4x4 Jordan block J(3) hidden by an orthogonal similarity A = Q J Q
     * (Q = Q^T = Q^-1, entries +-1/2): the eigenvalues move by ~eps^(1/4), the
     * defect's sensitivity, while the residuals stay at rounding level. */
    const double h = 0.5;
    const double q4[16] = {h, h, h, h, h, -h, h, -h, h, h, -h, -h, h, -h, -h, h};
    const double j4[16] = {3, 1, 0, 0, 0, 3, 1, 0, 0, 0, 3, 1, 0, 0, 0, 3};
    double qj[16];
    double a4[16];
    for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) {
            qj[i * 4 + j] = 0;
            for (int k = 0; k < 4; ++k) {
                qj[i * 4 + j] += q4[i * 4 + k] * j4[k * 4 + j];
            }
        }
    }
    for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) {
            a4[i * 4 + j] = 0;
            for (int k = 0; k < 4; ++k) {
                a4[i * 4 + j] += qj[i * 4 + k] * q4[k * 4 + j];
            }
        }
    }
    eig_with_residual(a4, 4, wr, wi, v, FCC_TEST_TOL(1e-13, 1e-5));
    for (int i = 0; i < 4; ++i) {
        fcc_assert_close(hypot((double)wr[i] - 3.0, (double)wi[i]), 0.0, 0,
                         FCC_TEST_TOL(1e-3, 0.1));
    }
    /* identity: repeated but not defective -> independent eigenvectors */
    const double eye[25] = {1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1};
    eig_with_residual(eye, 5, wr, wi, v, 0.0);
    fcc_mat_t mv = FCC_MAT(5, 5, v);
    fcc_assert_ok(fcc_mat_lu_factor(&g_lu, &mv));
    /* diag(1, 1, 2, 2) rotated by the same Q: two double eigenvalues */
    const double dd[4] = {1, 1, 2, 2};
    double rep[16];
    for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) {
            double s = 0;
            for (int k = 0; k < 4; ++k) {
                s += q4[i * 4 + k] * dd[k] * q4[k * 4 + j];
            }
            rep[i * 4 + j] = s;
        }
    }
    eig_with_residual(rep, 4, wr, wi, v, FCC_TEST_TOL(1e-14, 1e-6));
    double rre[4] = {wr[0], wr[1], wr[2], wr[3]};
    double rim[4] = {wi[0], wi[1], wi[2], wi[3]};
    sort_eigs(rre, rim, 4);
    const double expect[4] = {2, 2, 1, 1};
    for (int i = 0; i < 4; ++i) {
        fcc_assert_close(rre[i], expect[i], 0, FCC_TEST_TOL(1e-14, 1e-6));
    }
    fcc_mat_t mv4 = FCC_MAT(4, 4, v);
    fcc_assert_ok(fcc_mat_lu_factor(&g_lu, &mv4)); /* the eigenvectors span R^4 */
}

static void eig_scipy_vectors(void **state)
{
    (void)state;
    /* a random 10x10 (the largest size) and a column-graded 8x8 (1e-4 .. 1e4) */
    for (int c = 0; c < LINALG_EIG_VECTOR_COUNT; ++c) {
        const linalg_eig_vector_t *t = &linalg_eig_vectors[c];
        const int n = t->n;
        fcc_real_t wr[FCC_MAT_MAX_DIM];
        fcc_real_t wi[FCC_MAT_MAX_DIM];
        fcc_real_t v[FCC_MAT_MAX_ELEMS];
        print_message("eig %s\n", t->name);
        eig_with_residual(t->a, n, wr, wi, v, FCC_TEST_TOL(1e-13, 5e-5));
        double re[FCC_MAT_MAX_DIM];
        double im[FCC_MAT_MAX_DIM];
        for (int i = 0; i < n; ++i) {
            re[i] = wr[i];
            im[i] = wi[i];
        }
        double ere[FCC_MAT_MAX_DIM];
        double eim[FCC_MAT_MAX_DIM];
        double scale = 0;
        for (int i = 0; i < n; ++i) {
            ere[i] = t->eig[2 * i];
            eim[i] = t->eig[2 * i + 1];
            scale = hypot(ere[i], eim[i]) > scale ? hypot(ere[i], eim[i]) : scale;
        }
        assert_same_spectrum(re, im, ere, eim, n, FCC_TEST_TOL(1e-12, 1e-4) * scale);
        /* the double flavour, in every build */
        double a64[FCC_MAT_MAX_ELEMS];
        double wr64[FCC_MAT_MAX_DIM];
        double wi64[FCC_MAT_MAX_DIM];
        memcpy(a64, t->a, sizeof(double) * (size_t)(n * n));
        fcc_mat64_t ma64 = FCC_MAT64(n, n, a64);
        fcc_assert_ok(fcc_mat64_eig(&ma64, wr64, wi64, NULL, &g_eig64));
        assert_same_spectrum(wr64, wi64, ere, eim, n, 1e-12 * scale);
    }
}

static void spectral_radius(void **state)
{
    (void)state;
    fcc_real_t d[4] = {FCC_R(0.5), 2, FCC_R(-0.5), FCC_R(0.5)}; /* 0.5 +- i, |.| = sqrt(1.25) */
    fcc_mat_t a = FCC_MAT(2, 2, d);
    fcc_real_t rho = 0;
    fcc_assert_ok(fcc_mat_spectral_radius(&a, &rho, &g_eig));
    fcc_assert_close(rho, sqrt(1.25), FCC_TEST_TOL(1e-15, 1e-6), 0);
    assert_int_equal(fcc_mat_spectral_radius(&a, NULL, &g_eig), FCC_ERR_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(basic_operations),
        cmocka_unit_test(bad_arguments_are_refused),
        cmocka_unit_test(norms),
        cmocka_unit_test(singular_values),
        cmocka_unit_test(lu_solve_needs_pivoting),
        cmocka_unit_test(lu_ill_conditioned_hilbert),
        cmocka_unit_test(lu_singular_and_nearly_singular),
        cmocka_unit_test(cholesky),
        cmocka_unit_test(expm_closed_forms),
        cmocka_unit_test(expm_scipy_vectors),
        cmocka_unit_test(eig_simple_spectra),
        cmocka_unit_test(eig_defective_and_repeated),
        cmocka_unit_test(eig_scipy_vectors),
        cmocka_unit_test(spectral_radius),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
