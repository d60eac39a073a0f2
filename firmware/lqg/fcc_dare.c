/* fcc_dare.c -- discrete Riccati equation: symplectic eigenvectors and doubling. */
#include "fcc_dare.h"

#include <float.h>

#include "fcc_types.h" /* FCC_TRY */

/* Scratch slots of ws->tmp, named by use.  evaluate() owns slots 0-3. */
enum { T_XA = 0, T_ATXA = 1, T_N = 2, T_RB = 3, T_K = 4, T_ACL = 5, T_6 = 6, T_7 = 7 };

typedef struct {
    uint16_t n;
    uint16_t m;
} dims_t;

static bool usable(const fcc_mat64_t *m)
{
    return m != NULL && m->data != NULL && m->rows > 0U && m->cols > 0U;
}

static bool is_shape(const fcc_mat64_t *m, uint16_t rows, uint16_t cols)
{
    return m->rows == rows && m->cols == cols;
}

/* sqrt(eps): rank and residual tolerance; 4 sqrt(eps): unit-circle margin. */
static double sqrt_eps(void)
{
    return sqrt(DBL_EPSILON);
}

static fcc_status_t check_symmetric(const fcc_mat64_t *a)
{
    double amax = 0.0;
    FCC_TRY(fcc_mat64_norm_max(a, &amax));
    const double tol = 100.0 * DBL_EPSILON * amax;
    for (uint16_t i = 0; i < a->rows; ++i) {
        for (uint16_t j = (uint16_t)(i + 1U); j < a->cols; ++j) {
            if (fabs(FCC_MAT_AT(a, i, j) - FCC_MAT_AT(a, j, i)) > tol) {
                return FCC_ERR_ARG;
            }
        }
    }
    return FCC_OK;
}

static fcc_status_t check_problem(const fcc_dare_problem_t *p, const fcc_mat64_t *x, dims_t *d)
{
    if (p == NULL || !usable(p->a) || !usable(p->b) || !usable(p->q) || !usable(p->r) ||
        !usable(x) || (p->s != NULL && !usable(p->s))) {
        return FCC_ERR_ARG;
    }
    const uint16_t n = p->a->rows;
    const uint16_t m = p->b->cols;
    if (n > FCC_DARE_MAX_N || m > n || !is_shape(p->a, n, n) || !is_shape(p->b, n, m) ||
        !is_shape(p->q, n, n) || !is_shape(p->r, m, m) || !is_shape(x, n, n) ||
        (p->s != NULL && !is_shape(p->s, n, m))) {
        return FCC_ERR_SIZE;
    }
    FCC_TRY(fcc_mat64_check_finite(p->a));
    FCC_TRY(fcc_mat64_check_finite(p->b));
    FCC_TRY(fcc_mat64_check_finite(p->q));
    FCC_TRY(fcc_mat64_check_finite(p->r));
    if (p->s != NULL) {
        FCC_TRY(fcc_mat64_check_finite(p->s));
    }
    FCC_TRY(check_symmetric(p->q));
    FCC_TRY(check_symmetric(p->r));
    d->n = n;
    d->m = m;
    return FCC_OK;
}

/* ---- existence: PBH rank tests ---------------------------------------------- */

/* Is [M - lambda I; c C] rank deficient (M n x n, C p x n, c = ||M||_F/||C||_F)?
 * A complex lambda is tested through the real 2(n+p) x 2n matrix
 * [[Xr, -Xi], [Xi, Xr]], whose singular values are those of X, twice. */
static fcc_status_t pbh_deficient(const fcc_mat64_t *mm, const fcc_mat64_t *c, double lre,
                                  double lim, bool *deficient, fcc_dare_ws_t *ws)
{
    const uint16_t n = mm->rows;
    const uint16_t p = c->rows;
    double mnorm = 0.0;
    double cnorm = 0.0;
    FCC_TRY(fcc_mat64_norm_fro(mm, &mnorm));
    FCC_TRY(fcc_mat64_norm_fro(c, &cnorm));
    const double cs = (cnorm > 0.0) ? ((mnorm > 0.0) ? mnorm / cnorm : 1.0)
                                               : 0.0;
    const bool cplx = (lim != 0.0);
    const uint16_t xr = (uint16_t)(n + p);
    const uint16_t rows = cplx ? (uint16_t)(2U * xr) : xr;
    const uint16_t cols = cplx ? (uint16_t)(2U * n) : n;
    fcc_mat64_t w = FCC_MAT64(rows, cols, ws->pbh);
    FCC_TRY(fcc_mat64_zero(&w));
    for (uint16_t blk = 0; blk < (cplx ? 2U : 1U); ++blk) {
        const uint16_t r0 = (uint16_t)(blk * xr); /* the Xr blocks on the diagonal */
        const uint16_t c0 = (uint16_t)(blk * n);
        for (uint16_t i = 0; i < n; ++i) {
            for (uint16_t j = 0; j < n; ++j) {
                FCC_MAT_AT(&w, r0 + i, c0 + j) = FCC_MAT_AT(mm, i, j) - ((i == j) ? lre : 0.0);
            }
        }
        for (uint16_t i = 0; i < p; ++i) {
            for (uint16_t j = 0; j < n; ++j) {
                FCC_MAT_AT(&w, r0 + n + i, c0 + j) = cs * FCC_MAT_AT(c, i, j);
            }
        }
    }
    if (cplx) { /* Xi = [-lim I; 0]: -Xi top right, Xi bottom left */
        for (uint16_t i = 0; i < n; ++i) {
            FCC_MAT_AT(&w, i, n + i) = lim;
            FCC_MAT_AT(&w, xr + i, i) = -lim;
        }
    }
    double s[FCC_MAT_MAX_DIM];
    FCC_TRY(fcc_mat64_svd_values(&w, s, &ws->svd));
    *deficient = s[cols - 1U] <= sqrt_eps() * s[0];
    return FCC_OK;
}

/* PBH on every eigenvalue of A~ with |lambda| >= 1 - 4 sqrt(eps). */
static fcc_status_t check_existence(const dims_t *d, const fcc_mat64_t *b, fcc_dare_ws_t *ws)
{
    const uint16_t n = d->n;
    const fcc_mat64_t at = FCC_MAT64(n, n, ws->at);
    const fcc_mat64_t qt = FCC_MAT64(n, n, ws->qt);
    fcc_mat64_t att = FCC_MAT64(n, n, ws->tmp[T_6]);
    fcc_mat64_t bt = FCC_MAT64(d->m, n, ws->tmp[T_7]);
    FCC_TRY(fcc_mat64_trans(&at, &att));
    FCC_TRY(fcc_mat64_trans(b, &bt));
    double wr[FCC_MAT_MAX_DIM];
    double wi[FCC_MAT_MAX_DIM];
    FCC_TRY(fcc_mat64_eig(&at, wr, wi, NULL, &ws->eig));
    const double edge = 1.0 - 4.0 * sqrt_eps();
    for (uint16_t i = 0; i < n; ++i) {
        if (wi[i] < 0.0 || hypot(wr[i], wi[i]) < edge) {
            continue; /* stable, or the conjugate of one already tested */
        }
        bool deficient = false;
        /* rank [A - lI, B] = rank [A^T - conj(l) I; B^T]; conj(l) is tested
         * through l itself: the rank of a real-based matrix is conjugation-invariant. */
        FCC_TRY(pbh_deficient(&att, &bt, wr[i], wi[i], &deficient, ws));
        if (deficient) {
            return FCC_ERR_NOT_STABILIZABLE;
        }
        FCC_TRY(pbh_deficient(&at, &qt, wr[i], wi[i], &deficient, ws));
        if (deficient) {
            return FCC_ERR_NOT_DETECTABLE;
        }
    }
    return FCC_OK;
}

/* ---- common preparation: remove the cross term -------------------------------- */

/* ws->at = A - B R^-1 S^T, ws->qt = Q - S R^-1 S^T, ws->g = B R^-1 B^T. */
static fcc_status_t prepare(const fcc_dare_problem_t *p, const dims_t *d, fcc_dare_ws_t *ws)
{
    const uint16_t n = d->n;
    const uint16_t m = d->m;
    fcc_mat64_t at = FCC_MAT64(n, n, ws->at);
    fcc_mat64_t qt = FCC_MAT64(n, n, ws->qt);
    fcc_mat64_t g = FCC_MAT64(n, n, ws->g);
    fcc_mat64_t l = FCC_MAT64(m, m, ws->tmp[0]);
    fcc_mat64_t y = FCC_MAT64(m, n, ws->tmp[1]);
    fcc_mat64_t t = FCC_MAT64(n, n, ws->tmp[2]);
    FCC_TRY(fcc_mat64_chol(p->r, &l));
    FCC_TRY(fcc_mat64_trans(p->b, &y));
    FCC_TRY(fcc_mat64_chol_solve(&l, &y, &y)); /* R^-1 B^T */
    FCC_TRY(fcc_mat64_mul(p->b, &y, &g));
    FCC_TRY(fcc_mat64_symmetrize(&g));
    FCC_TRY(fcc_mat64_copy(p->a, &at));
    FCC_TRY(fcc_mat64_copy(p->q, &qt));
    if (p->s != NULL) {
        FCC_TRY(fcc_mat64_trans(p->s, &y));
        FCC_TRY(fcc_mat64_chol_solve(&l, &y, &y)); /* R^-1 S^T */
        FCC_TRY(fcc_mat64_mul(p->b, &y, &t));
        FCC_TRY(fcc_mat64_sub(&at, &t, &at));
        FCC_TRY(fcc_mat64_mul(p->s, &y, &t));
        FCC_TRY(fcc_mat64_sub(&qt, &t, &qt));
    }
    FCC_TRY(fcc_mat64_symmetrize(&qt));
    return check_existence(d, p->b, ws);
}

/* The start of both solvers: arguments and shapes checked, the cross term
 * removed, existence checked; *n is the state dimension. */
static fcc_status_t start_solver(const fcc_dare_problem_t *p, const fcc_mat64_t *x,
                                 const fcc_dare_info_t *info, fcc_dare_ws_t *ws, uint16_t *n)
{
    dims_t d;
    if (ws == NULL || info == NULL) {
        return FCC_ERR_ARG;
    }
    FCC_TRY(check_problem(p, x, &d));
    FCC_TRY(prepare(p, &d, ws));
    *n = d.n;
    return FCC_OK;
}

/* ---- gain, residual, acceptance ----------------------------------------------- */

/* K (m x n, into k) and the relative residual of x; uses ws->tmp[0..3]. */
static fcc_status_t evaluate(const fcc_dare_problem_t *p, const fcc_mat64_t *x, fcc_mat64_t *k,
                             double *res, fcc_dare_ws_t *ws)
{
    const uint16_t n = p->a->rows;
    const uint16_t m = p->b->cols;
    fcc_mat64_t xa = FCC_MAT64(n, n, ws->tmp[T_XA]);
    fcc_mat64_t atxa = FCC_MAT64(n, n, ws->tmp[T_ATXA]);
    fcc_mat64_t xb = FCC_MAT64(n, m, ws->tmp[T_N]);
    fcc_mat64_t rb = FCC_MAT64(m, m, ws->tmp[T_RB]);
    fcc_mat64_t nn = FCC_MAT64(m, n, ws->tmp[T_N]);
    FCC_TRY(fcc_mat64_mul(x, p->a, &xa));
    FCC_TRY(fcc_mat64_mul_tn(p->a, &xa, &atxa));
    FCC_TRY(fcc_mat64_mul(x, p->b, &xb));
    FCC_TRY(fcc_mat64_mul_tn(p->b, &xb, &rb));
    FCC_TRY(fcc_mat64_add(&rb, p->r, &rb)); /* R + B^T X B */
    FCC_TRY(fcc_mat64_mul_tn(p->b, &xa, &nn)); /* B^T X A (xb is dead) */
    if (p->s != NULL) {
        for (uint16_t i = 0; i < m; ++i) {
            for (uint16_t j = 0; j < n; ++j) {
                FCC_MAT_AT(&nn, i, j) += FCC_MAT_AT(p->s, j, i);
            }
        }
    }
    FCC_TRY(fcc_mat64_solve(&rb, &nn, k, &ws->lu));
    if (res == NULL) {
        return FCC_OK;
    }
    fcc_mat64_t ntk = FCC_MAT64(n, n, ws->tmp[T_XA]);
    FCC_TRY(fcc_mat64_mul_tn(&nn, k, &ntk));
    double scale = 0.0;
    double v = 0.0;
    const fcc_mat64_t *terms[4] = {&atxa, x, &ntk, p->q};
    for (unsigned i = 0; i < 4U; ++i) {
        FCC_TRY(fcc_mat64_norm_1(terms[i], &v));
        scale += v;
    }
    fcc_mat64_t r = FCC_MAT64(n, n, ws->tmp[T_RB]);
    FCC_TRY(fcc_mat64_sub(&atxa, x, &r));
    FCC_TRY(fcc_mat64_sub(&r, &ntk, &r));
    FCC_TRY(fcc_mat64_add(&r, p->q, &r));
    FCC_TRY(fcc_mat64_norm_1(&r, &v));
    *res = (scale > 0.0) ? v / scale : v;
    return FCC_OK;
}

/* Accept x only if finite, stabilising and with a small residual. */
static fcc_status_t accept(const fcc_dare_problem_t *p, fcc_mat64_t *x, fcc_dare_info_t *info,
                           fcc_dare_ws_t *ws)
{
    const uint16_t n = p->a->rows;
    const uint16_t m = p->b->cols;
    if (fcc_mat64_check_finite(x) != FCC_OK) {
        return FCC_ERR_NO_CONVERGENCE;
    }
    FCC_TRY(fcc_mat64_symmetrize(x));
    fcc_mat64_t k = FCC_MAT64(m, n, ws->tmp[T_K]);
    double res = 0.0;
    FCC_TRY(evaluate(p, x, &k, &res, ws));
    fcc_mat64_t bk = FCC_MAT64(n, n, ws->tmp[T_6]);
    fcc_mat64_t acl = FCC_MAT64(n, n, ws->tmp[T_ACL]);
    FCC_TRY(fcc_mat64_mul(p->b, &k, &bk));
    FCC_TRY(fcc_mat64_sub(p->a, &bk, &acl));
    double rho = 0.0;
    FCC_TRY(fcc_mat64_spectral_radius(&acl, &rho, &ws->eig));
    info->residual = res;
    info->cl_radius = rho;
    if (!(rho < 1.0) || !(res <= sqrt_eps())) {
        return FCC_ERR_NO_CONVERGENCE;
    }
    return FCC_OK;
}

fcc_status_t fcc_dare_gain(const fcc_dare_problem_t *p, const fcc_mat64_t *x, fcc_mat64_t *k,
                           fcc_dare_ws_t *ws)
{
    dims_t d;
    if (ws == NULL || !usable(k)) {
        return FCC_ERR_ARG;
    }
    FCC_TRY(check_problem(p, x, &d));
    if (!is_shape(k, d.m, d.n)) {
        return FCC_ERR_SIZE;
    }
    FCC_TRY(fcc_mat64_check_finite(x));
    return evaluate(p, x, k, NULL, ws);
}

fcc_status_t fcc_dare_residual(const fcc_dare_problem_t *p, const fcc_mat64_t *x, double *res,
                               fcc_dare_ws_t *ws)
{
    dims_t d;
    if (ws == NULL || res == NULL) {
        return FCC_ERR_ARG;
    }
    FCC_TRY(check_problem(p, x, &d));
    FCC_TRY(fcc_mat64_check_finite(x));
    fcc_mat64_t k = FCC_MAT64(d.m, d.n, ws->tmp[T_K]);
    return evaluate(p, x, &k, res, ws);
}

/* ---- method 1: eigenvectors of the symplectic matrix --------------------------- */

/* ws->z = [[A~ + G A~^-T Q~, -G A~^-T], [-A~^-T Q~, A~^-T]]. */
static fcc_status_t build_symplectic(uint16_t n, fcc_dare_ws_t *ws)
{
    const fcc_mat64_t at = FCC_MAT64(n, n, ws->at);
    const fcc_mat64_t qt = FCC_MAT64(n, n, ws->qt);
    const fcc_mat64_t g = FCC_MAT64(n, n, ws->g);
    fcc_mat64_t inv = FCC_MAT64(n, n, ws->tmp[0]);
    fcc_mat64_t ait = FCC_MAT64(n, n, ws->tmp[1]);
    fcc_mat64_t aitq = FCC_MAT64(n, n, ws->tmp[2]);
    fcc_mat64_t t = FCC_MAT64(n, n, ws->tmp[3]);
    fcc_mat64_t z = FCC_MAT64(2U * n, 2U * n, ws->z);
    FCC_TRY(fcc_mat64_inv(&at, &inv, &ws->lu)); /* FCC_ERR_SINGULAR: A~ not invertible */
    FCC_TRY(fcc_mat64_trans(&inv, &ait));
    FCC_TRY(fcc_mat64_mul(&ait, &qt, &aitq));
    FCC_TRY(fcc_mat64_mul(&g, &aitq, &t));
    FCC_TRY(fcc_mat64_add(&at, &t, &t));
    FCC_TRY(fcc_mat64_set_block(&z, 0, 0, &t));
    FCC_TRY(fcc_mat64_mul(&g, &ait, &t));
    FCC_TRY(fcc_mat64_scale(&t, -1.0, &t));
    FCC_TRY(fcc_mat64_set_block(&z, 0, n, &t));
    FCC_TRY(fcc_mat64_scale(&aitq, -1.0, &aitq));
    FCC_TRY(fcc_mat64_set_block(&z, n, 0, &aitq));
    return fcc_mat64_set_block(&z, n, n, &ait);
}

/* Columns of the eigenvector matrix for |lambda| < 1 into U1 (top) and U2
 * (bottom); a pair's two columns are the real basis of its invariant plane. */
static fcc_status_t stable_subspace(uint16_t n, const double *wr, const double *wi,
                                    fcc_mat64_t *u1, fcc_mat64_t *u2, fcc_dare_ws_t *ws)
{
    const fcc_mat64_t v = FCC_MAT64(2U * n, 2U * n, ws->v);
    const double margin = 4.0 * sqrt_eps();
    uint16_t count = 0;
    for (uint16_t i = 0; i < 2U * n; ++i) {
        const double mod = hypot(wr[i], wi[i]);
        if (fabs(mod - 1.0) <= margin) {
            /* An eigenvalue on the unit circle: no stabilising solution. */
            return FCC_ERR_NOT_STABILIZABLE;
        }
        if (mod < 1.0) {
            if (count >= n) {
                return FCC_ERR_NO_CONVERGENCE;
            }
            for (uint16_t r = 0; r < n; ++r) {
                FCC_MAT_AT(u1, r, count) = FCC_MAT_AT(&v, r, i);
                FCC_MAT_AT(u2, r, count) = FCC_MAT_AT(&v, n + r, i);
            }
            ++count;
        }
    }
    return (count == n) ? FCC_OK : FCC_ERR_NO_CONVERGENCE;
}

fcc_status_t fcc_dare_hamiltonian(const fcc_dare_problem_t *p, fcc_mat64_t *x, fcc_dare_info_t *info,
                                  fcc_dare_ws_t *ws)
{
    uint16_t n = 0;
    FCC_TRY(start_solver(p, x, info, ws, &n));
    FCC_TRY(build_symplectic(n, ws));
    fcc_mat64_t z = FCC_MAT64(2U * n, 2U * n, ws->z);
    fcc_mat64_t v = FCC_MAT64(2U * n, 2U * n, ws->v);
    double wr[FCC_MAT_MAX_DIM];
    double wi[FCC_MAT_MAX_DIM];
    FCC_TRY(fcc_mat64_eig(&z, wr, wi, &v, &ws->eig));
    fcc_mat64_t u1 = FCC_MAT64(n, n, ws->tmp[0]);
    fcc_mat64_t u2t = FCC_MAT64(n, n, ws->tmp[1]);
    fcc_mat64_t u2 = FCC_MAT64(n, n, ws->tmp[2]);
    FCC_TRY(stable_subspace(n, wr, wi, &u1, &u2, ws));
    /* X = U2 U1^-1, i.e. U1^T X^T = U2^T. */
    const fcc_status_t st = fcc_mat64_lu_factor(&ws->lu, &u1);
    if (st == FCC_ERR_SINGULAR) {
        return FCC_ERR_NOT_STABILIZABLE; /* the stable subspace is not a graph over x */
    }
    FCC_TRY(st);
    FCC_TRY(fcc_mat64_lu_rcond(&ws->lu, &info->rcond_u1));
    FCC_TRY(fcc_mat64_trans(&u2, &u2t));
    FCC_TRY(fcc_mat64_lu_solve_trans(&ws->lu, &u2t, &u2t));
    FCC_TRY(fcc_mat64_trans(&u2t, x));
    info->iterations = 0;
    return accept(p, x, info, ws);
}

/* ---- method 2: structure-preserving doubling ------------------------------------- */

/* One doubling step on (A_k, G_k, H_k) in tmp[0..2]; *change = ||H_{k+1} - H_k||_1. */
static fcc_status_t doubling_step(uint16_t n, double *change, fcc_dare_ws_t *ws)
{
    fcc_mat64_t ak = FCC_MAT64(n, n, ws->tmp[0]);
    fcc_mat64_t gk = FCC_MAT64(n, n, ws->tmp[1]);
    fcc_mat64_t hk = FCC_MAT64(n, n, ws->tmp[2]);
    fcc_mat64_t x1 = FCC_MAT64(n, n, ws->tmp[3]);
    fcc_mat64_t x2 = FCC_MAT64(n, n, ws->tmp[4]);
    fcc_mat64_t pm = FCC_MAT64(n, n, ws->tmp[5]);
    fcc_mat64_t qm = FCC_MAT64(n, n, ws->tmp[6]);
    FCC_TRY(fcc_mat64_mul(&gk, &hk, &pm));
    for (uint16_t i = 0; i < n; ++i) {
        FCC_MAT_AT(&pm, i, i) += 1.0; /* W = I + G H */
    }
    FCC_TRY(fcc_mat64_lu_factor(&ws->lu, &pm));
    FCC_TRY(fcc_mat64_lu_solve(&ws->lu, &ak, &x1)); /* W^-1 A */
    FCC_TRY(fcc_mat64_lu_solve(&ws->lu, &gk, &x2)); /* W^-1 G */
    FCC_TRY(fcc_mat64_mul(&ak, &x2, &pm));
    FCC_TRY(fcc_mat64_mul_nt(&pm, &ak, &qm));
    FCC_TRY(fcc_mat64_add(&gk, &qm, &gk));
    FCC_TRY(fcc_mat64_symmetrize(&gk));
    FCC_TRY(fcc_mat64_mul(&hk, &x1, &pm));
    FCC_TRY(fcc_mat64_mul_tn(&ak, &pm, &qm));
    FCC_TRY(fcc_mat64_norm_1(&qm, change));
    FCC_TRY(fcc_mat64_add(&hk, &qm, &hk));
    FCC_TRY(fcc_mat64_symmetrize(&hk));
    FCC_TRY(fcc_mat64_mul(&ak, &x1, &pm));
    return fcc_mat64_copy(&pm, &ak);
}

fcc_status_t fcc_dare_doubling(const fcc_dare_problem_t *p, fcc_mat64_t *x, fcc_dare_info_t *info,
                               fcc_dare_ws_t *ws)
{
    uint16_t n = 0;
    FCC_TRY(start_solver(p, x, info, ws, &n));
    const size_t nn = (size_t)n * n;
    for (size_t i = 0; i < nn; ++i) {
        ws->tmp[0][i] = ws->at[i];
        ws->tmp[1][i] = ws->g[i];
        ws->tmp[2][i] = ws->qt[i];
    }
    const fcc_mat64_t hk = FCC_MAT64(n, n, ws->tmp[2]);
    const double tol = 4.0 * (double)n * DBL_EPSILON;
    bool converged = false;
    uint16_t k = 0;
    while (!converged && k < FCC_DARE_MAX_ITER) {
        double change = 0.0;
        double hnorm = 0.0;
        const fcc_status_t st = doubling_step(n, &change, ws);
        if (st == FCC_ERR_SINGULAR || st == FCC_ERR_NOT_FINITE) {
            return FCC_ERR_NO_CONVERGENCE;
        }
        FCC_TRY(st);
        FCC_TRY(fcc_mat64_norm_1(&hk, &hnorm));
        if (!FCC_IS_FINITE(hnorm)) {
            return FCC_ERR_NO_CONVERGENCE;
        }
        converged = change <= tol * hnorm;
        ++k;
    }
    if (!converged) {
        return FCC_ERR_NO_CONVERGENCE;
    }
    FCC_TRY(fcc_mat64_copy(&hk, x));
    info->iterations = k;
    info->rcond_u1 = 0.0;
    return accept(p, x, info, ws);
}
