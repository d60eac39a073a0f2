/*
 * fcc_mat_eig.c -- real nonsymmetric eigenvalues and eigenvectors.
 *
 * The classical dense path (Golub & Van Loan, "Matrix Computations", ch. 7):
 *   1. balance: D^-1 A D with D a diagonal of powers of two, so that row and
 *      column norms are comparable (exact in binary arithmetic; it reduces
 *      the norm that rounding errors are proportional to);
 *   2. Householder reduction to upper Hessenberg form H = Q^T A Q;
 *   3. Francis implicit double-shift QR iteration on H, deflating on small
 *      subdiagonal entries, until H is quasi-triangular (real Schur form
 *      T = Z^T A Z, 1x1 blocks for real and 2x2 blocks for complex pairs); a
 *      2x2 block with real eigenvalues is split by one plane rotation;
 *   4. eigenvectors of T by back substitution, x -> Z x -> D x, normalised.
 * All updates are applied to the whole of T (not only the active window) so
 * that step 4 sees a true Schur form.
 */
#include "fcc_mat_impl.h"

#define AT(p, n, i, j) ((p)[(size_t)(i) * (n) + (size_t)(j)])

/* Iterations allowed per eigenvalue before giving up (EISPACK/LAPACK use 30),
 * with exceptional shifts at 10 and 20 to break cycles. */
#define QR_MAX_ITER 30

typedef struct {
    real_t re;
    real_t im;
} cplx_t;

static cplx_t c_mul(cplx_t a, cplx_t b)
{
    const cplx_t r = {a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re};
    return r;
}

static cplx_t c_sub(cplx_t a, cplx_t b)
{
    const cplx_t r = {a.re - b.re, a.im - b.im};
    return r;
}

/* a / b by Smith's algorithm (no overflow from squaring b). */
static cplx_t c_div(cplx_t a, cplx_t b)
{
    cplx_t r;
    if (MFABS(b.re) >= MFABS(b.im)) {
        const real_t t = b.im / b.re;
        const real_t d = b.re + b.im * t;
        r.re = (a.re + a.im * t) / d;
        r.im = (a.im - a.re * t) / d;
    } else {
        const real_t t = b.re / b.im;
        const real_t d = b.im + b.re * t;
        r.re = (a.re * t + a.im) / d;
        r.im = (a.im * t - a.re) / d;
    }
    return r;
}

static real_t c_abs1(cplx_t a)
{
    return MFABS(a.re) + MFABS(a.im);
}

/* ---- 1. balancing ---------------------------------------------------------- */

static void balance(real_t *h, uint16_t n, real_t *scale)
{
    for (uint16_t i = 0; i < n; ++i) {
        scale[i] = RL(1.0);
    }
    bool done = false;
    for (int sweep = 0; sweep < 100 && !done; ++sweep) {
        done = true;
        for (uint16_t i = 0; i < n; ++i) {
            real_t c = RL(0.0);
            real_t r = RL(0.0);
            for (uint16_t j = 0; j < n; ++j) {
                if (j != i) {
                    c += MFABS(AT(h, n, j, i));
                    r += MFABS(AT(h, n, i, j));
                }
            }
            if (c == RL(0.0) || r == RL(0.0)) {
                continue;
            }
            /* Find f = 2^k bringing c*f and r/f within a factor 2 of each other. */
            const real_t total = c + r;
            real_t f = RL(1.0);
            while (c < RL(0.5) * r) {
                f *= RL(2.0);
                c *= RL(4.0);
            }
            while (c >= RL(2.0) * r) {
                f *= RL(0.5);
                c *= RL(0.25);
            }
            if ((c + r) / f < RL(0.95) * total) {
                done = false;
                scale[i] *= f;
                for (uint16_t j = 0; j < n; ++j) {
                    AT(h, n, i, j) /= f;
                    AT(h, n, j, i) *= f;
                }
            }
        }
    }
}

/* ---- 2. Hessenberg reduction ----------------------------------------------- */

/* Householder vector v (len entries, scaled) with P = I - tau v v^T mapping x
 * onto a multiple of e1; returns tau (0: nothing to do).  v may be x. */
static real_t householder(const real_t *x, uint16_t len, real_t *v)
{
    real_t xmax = RL(0.0);
    for (uint16_t i = 0; i < len; ++i) {
        xmax = (MFABS(x[i]) > xmax) ? MFABS(x[i]) : xmax;
    }
    if (xmax == RL(0.0)) {
        return RL(0.0);
    }
    real_t tail = RL(0.0);
    for (uint16_t i = 0; i < len; ++i) {
        v[i] = x[i] / xmax;
        tail += (i > 0U) ? v[i] * v[i] : RL(0.0);
    }
    if (tail == RL(0.0)) {
        return RL(0.0); /* already a multiple of e1 */
    }
    const real_t sigma = MSQRT(v[0] * v[0] + tail);
    v[0] += MCOPYSIGN(sigma, v[0]);
    return RL(2.0) / (v[0] * v[0] + tail);
}

/* Rows r0..r0+len-1 of h, columns c0..n-1:  h <- (I - tau v v^T) h. */
static void reflect_rows(real_t *h, uint16_t n, uint16_t r0, uint16_t len, uint16_t c0,
                         const real_t *v, real_t tau)
{
    for (uint16_t j = c0; j < n; ++j) {
        real_t s = RL(0.0);
        for (uint16_t i = 0; i < len; ++i) {
            s += v[i] * AT(h, n, r0 + i, j);
        }
        s *= tau;
        for (uint16_t i = 0; i < len; ++i) {
            AT(h, n, r0 + i, j) -= s * v[i];
        }
    }
}

/* Columns c0..c0+len-1 of m, rows 0..rlast:  m <- m (I - tau v v^T). */
static void reflect_cols(real_t *m, uint16_t n, uint16_t c0, uint16_t len, uint16_t rlast,
                         const real_t *v, real_t tau)
{
    for (uint16_t i = 0; i <= rlast; ++i) {
        real_t s = RL(0.0);
        for (uint16_t j = 0; j < len; ++j) {
            s += AT(m, n, i, c0 + j) * v[j];
        }
        s *= tau;
        for (uint16_t j = 0; j < len; ++j) {
            AT(m, n, i, c0 + j) -= s * v[j];
        }
    }
}

static void hessenberg(real_t *h, real_t *z, uint16_t n)
{
    real_t x[FCC_MAT_MAX_DIM];
    real_t v[FCC_MAT_MAX_DIM];
    for (uint16_t k = 0; k + 2U < n; ++k) {
        const uint16_t len = (uint16_t)(n - k - 1U);
        for (uint16_t i = 0; i < len; ++i) {
            x[i] = AT(h, n, k + 1U + i, k);
        }
        const real_t tau = householder(x, len, v);
        if (tau == RL(0.0)) {
            continue;
        }
        reflect_rows(h, n, (uint16_t)(k + 1U), len, k, v, tau);
        reflect_cols(h, n, (uint16_t)(k + 1U), len, (uint16_t)(n - 1U), v, tau);
        if (z != NULL) {
            reflect_cols(z, n, (uint16_t)(k + 1U), len, (uint16_t)(n - 1U), v, tau);
        }
        for (uint16_t i = (uint16_t)(k + 2U); i < n; ++i) {
            AT(h, n, i, k) = RL(0.0);
        }
    }
}

/* ---- 3. Francis double-shift QR ------------------------------------------- */

typedef struct {
    real_t *h;
    real_t *z; /* NULL when eigenvectors are not wanted */
    uint16_t n;
    real_t *wr;
    real_t *wi;
} schur_t;

/* Apply the rotation [c -s; s c] to rows/cols p, p+1 of T (and columns of Z). */
static void rotate_pair(schur_t *sc, uint16_t p, real_t c, real_t s)
{
    const uint16_t n = sc->n;
    const uint16_t q = (uint16_t)(p + 1U);
    for (uint16_t j = p; j < n; ++j) {
        const real_t hp = AT(sc->h, n, p, j);
        const real_t hq = AT(sc->h, n, q, j);
        AT(sc->h, n, p, j) = c * hp + s * hq;
        AT(sc->h, n, q, j) = c * hq - s * hp;
    }
    for (uint16_t i = 0; i <= q; ++i) {
        const real_t hp = AT(sc->h, n, i, p);
        const real_t hq = AT(sc->h, n, i, q);
        AT(sc->h, n, i, p) = c * hp + s * hq;
        AT(sc->h, n, i, q) = c * hq - s * hp;
    }
    if (sc->z != NULL) {
        for (uint16_t i = 0; i < n; ++i) {
            const real_t zp = AT(sc->z, n, i, p);
            const real_t zq = AT(sc->z, n, i, q);
            AT(sc->z, n, i, p) = c * zp + s * zq;
            AT(sc->z, n, i, q) = c * zq - s * zp;
        }
    }
}

/* A converged 2x2 block at rows/cols p, p+1: complex pair, or split by a
 * rotation onto the eigenvector of one real eigenvalue. */
static void settle_block(schur_t *sc, uint16_t p)
{
    const uint16_t n = sc->n;
    const uint16_t q = (uint16_t)(p + 1U);
    const real_t a = AT(sc->h, n, p, p);
    const real_t b = AT(sc->h, n, p, q);
    const real_t c = AT(sc->h, n, q, p);
    const real_t d = AT(sc->h, n, q, q);
    const real_t half = RL(0.5) * (a - d);
    const real_t disc = half * half + b * c;
    if (disc < RL(0.0)) {
        sc->wr[p] = d + half;
        sc->wr[q] = d + half;
        sc->wi[p] = MSQRT(-disc);
        sc->wi[q] = -sc->wi[p];
        return;
    }
    /* lambda = d + zz with zz = half + sign(half) sqrt(disc) (no cancellation);
     * its eigenvector is (zz, c). */
    const real_t zz = half + MCOPYSIGN(MSQRT(disc), half);
    const real_t r = MHYPOT(zz, c);
    if (r > RL(0.0)) {
        rotate_pair(sc, p, zz / r, c / r);
    }
    AT(sc->h, n, q, p) = RL(0.0);
    sc->wr[p] = AT(sc->h, n, p, p);
    sc->wr[q] = AT(sc->h, n, q, q);
    sc->wi[p] = RL(0.0);
    sc->wi[q] = RL(0.0);
}

/* One implicit double-shift step on the active window lo..hi (hi - lo >= 2). */
static void francis_step(schur_t *sc, uint16_t lo, uint16_t hi, int iter)
{
    real_t *h = sc->h;
    const uint16_t n = sc->n;
    real_t tr;
    real_t det;
    if (iter == 10 || iter == 20) {
        /* Exceptional shift (EISPACK's ad hoc values) to break a cycle. */
        const real_t s = MFABS(AT(h, n, hi, hi - 1U)) + MFABS(AT(h, n, hi - 1U, hi - 2U));
        tr = RL(1.5) * s;
        det = s * s;
    } else {
        const real_t a = AT(h, n, hi - 1U, hi - 1U);
        const real_t d = AT(h, n, hi, hi);
        tr = a + d;
        det = a * d - AT(h, n, hi - 1U, hi) * AT(h, n, hi, hi - 1U);
    }
    /* First column of (H - s1 I)(H - s2 I) = H^2 - tr H + det I. */
    const real_t h00 = AT(h, n, lo, lo);
    const real_t h10 = AT(h, n, lo + 1U, lo);
    real_t x[3];
    x[0] = h00 * h00 + AT(h, n, lo, lo + 1U) * h10 - tr * h00 + det;
    x[1] = h10 * (h00 + AT(h, n, lo + 1U, lo + 1U) - tr);
    x[2] = h10 * AT(h, n, lo + 2U, lo + 1U);
    real_t v[3];
    for (uint16_t k = lo; k + 1U <= hi; ++k) {
        const uint16_t len = (k + 2U <= hi) ? 3U : 2U;
        const real_t tau = householder(x, len, v);
        if (tau != RL(0.0)) {
            const uint16_t c0 = (k > lo) ? (uint16_t)(k - 1U) : lo;
            const uint16_t rlast = (k + 3U <= hi) ? (uint16_t)(k + 3U) : hi;
            reflect_rows(h, n, k, len, c0, v, tau);
            reflect_cols(h, n, k, len, rlast, v, tau);
            if (sc->z != NULL) {
                reflect_cols(sc->z, n, k, len, (uint16_t)(n - 1U), v, tau);
            }
            if (k > lo) {
                /* The bulge entries just annihilated: exactly zero. */
                for (uint16_t i = 1; i < len; ++i) {
                    AT(h, n, k + i, k - 1U) = RL(0.0);
                }
            }
        }
        if (k + 2U <= hi) {
            x[0] = AT(h, n, k + 1U, k);
            x[1] = AT(h, n, k + 2U, k);
            x[2] = (k + 3U <= hi) ? AT(h, n, k + 3U, k) : RL(0.0);
        }
    }
}

/* Index lo <= hi of the top of the unreduced block ending at hi (a negligible
 * subdiagonal entry is set to zero). */
static uint16_t find_split(schur_t *sc, uint16_t hi, real_t hnorm)
{
    real_t *h = sc->h;
    const uint16_t n = sc->n;
    uint16_t l = hi;
    while (l > 0U) {
        real_t s = MFABS(AT(h, n, l - 1U, l - 1U)) + MFABS(AT(h, n, l, l));
        if (s == RL(0.0)) {
            s = hnorm;
        }
        if (MFABS(AT(h, n, l, l - 1U)) <= MEPS * s) {
            AT(h, n, l, l - 1U) = RL(0.0);
            break;
        }
        --l;
    }
    return l;
}

static fcc_status_t francis_qr(schur_t *sc)
{
    const uint16_t n = sc->n;
    real_t hnorm = RL(0.0);
    for (size_t i = 0; i < (size_t)n * n; ++i) {
        hnorm += MFABS(sc->h[i]);
    }
    int hi = (int)n - 1;
    int iter = 0;
    while (hi >= 0) {
        const uint16_t uhi = (uint16_t)hi;
        const uint16_t lo = find_split(sc, uhi, hnorm);
        if (lo == uhi) {
            sc->wr[uhi] = AT(sc->h, n, uhi, uhi);
            sc->wi[uhi] = RL(0.0);
            hi -= 1;
            iter = 0;
        } else if (lo + 1U == uhi) {
            settle_block(sc, lo);
            hi -= 2;
            iter = 0;
        } else {
            if (++iter > QR_MAX_ITER) {
                return FCC_ERR_NO_CONVERGENCE;
            }
            francis_step(sc, lo, uhi, iter);
        }
    }
    return FCC_OK;
}

/* ---- 4. eigenvectors of the Schur form ------------------------------------ */

/* Solve the 2x2 complex system a x = r by complete pivoting; pivots below
 * smin are replaced by smin (perturbation for (nearly) repeated eigenvalues). */
static void solve2(cplx_t a[2][2], const cplx_t r[2], real_t smin, cplx_t x[2])
{
    unsigned pr = 0U;
    unsigned pc = 0U;
    for (unsigned i = 0; i < 2U; ++i) {
        for (unsigned j = 0; j < 2U; ++j) {
            if (c_abs1(a[i][j]) > c_abs1(a[pr][pc])) {
                pr = i;
                pc = j;
            }
        }
    }
    if (c_abs1(a[pr][pc]) < smin) {
        a[pr][pc].re = smin;
        a[pr][pc].im = RL(0.0);
    }
    const unsigned orow = 1U - pr;
    const unsigned ocol = 1U - pc;
    const cplx_t l = c_div(a[orow][pc], a[pr][pc]);
    cplx_t u22 = c_sub(a[orow][ocol], c_mul(l, a[pr][ocol]));
    if (c_abs1(u22) < smin) {
        u22.re = smin;
        u22.im = RL(0.0);
    }
    x[ocol] = c_div(c_sub(r[orow], c_mul(l, r[pr])), u22);
    x[pc] = c_div(c_sub(r[pr], c_mul(a[pr][ocol], x[ocol])), a[pr][pc]);
}

/* x[lo..top] <- x[lo..top] / max when entries grow past what further back
 * substitution steps could multiply without overflow. */
static void rescale_if_large(cplx_t *x, uint16_t lo, uint16_t top)
{
    const real_t big = RL(1.0) / (MEPS * MEPS);
    real_t m = RL(0.0);
    for (uint16_t i = lo; i <= top; ++i) {
        m = (c_abs1(x[i]) > m) ? c_abs1(x[i]) : m;
    }
    if (m > big) {
        for (uint16_t i = lo; i <= top; ++i) {
            x[i].re /= m;
            x[i].im /= m;
        }
    }
}

/* -sum_{j=i+1..top} t(i,j) x_j */
static cplx_t minus_row_dot(const real_t *t, uint16_t n, uint16_t i, uint16_t top,
                            const cplx_t *x)
{
    cplx_t s = {RL(0.0), RL(0.0)};
    for (uint16_t j = (uint16_t)(i + 1U); j <= top; ++j) {
        s.re -= AT(t, n, i, j) * x[j].re;
        s.im -= AT(t, n, i, j) * x[j].im;
    }
    return s;
}

/* Back substitution (T - lambda I) x = 0 above the seed entries x[i > below]. */
static void back_substitute(const real_t *t, uint16_t n, uint16_t below, uint16_t top,
                            cplx_t lambda, real_t smin, cplx_t *x)
{
    int i = (int)below - 1;
    while (i >= 0) {
        const uint16_t ui = (uint16_t)i;
        if (ui > 0U && AT(t, n, ui, ui - 1U) != RL(0.0)) {
            /* 2x2 diagonal block at rows ui-1, ui */
            cplx_t a[2][2];
            cplx_t r[2];
            cplx_t y[2];
            const uint16_t p = (uint16_t)(ui - 1U);
            a[0][0].re = AT(t, n, p, p) - lambda.re;
            a[0][0].im = -lambda.im;
            a[0][1].re = AT(t, n, p, ui);
            a[0][1].im = RL(0.0);
            a[1][0].re = AT(t, n, ui, p);
            a[1][0].im = RL(0.0);
            a[1][1].re = AT(t, n, ui, ui) - lambda.re;
            a[1][1].im = -lambda.im;
            r[0] = minus_row_dot(t, n, p, top, x);
            r[1] = minus_row_dot(t, n, ui, top, x);
            solve2(a, r, smin, y);
            x[p] = y[0];
            x[ui] = y[1];
            rescale_if_large(x, p, top);
            i -= 2;
        } else {
            cplx_t d = {AT(t, n, ui, ui) - lambda.re, -lambda.im};
            if (c_abs1(d) < smin) {
                d.re = smin;
                d.im = RL(0.0);
            }
            x[ui] = c_div(minus_row_dot(t, n, ui, top, x), d);
            rescale_if_large(x, ui, top);
            i -= 1;
        }
    }
}

/* Column k (and k+1 for a complex vector) of v <- D Z x, normalised to unit
 * 2-norm with its largest component real. */
static void store_vector(const schur_t *sc, const real_t *scale, const cplx_t *x, uint16_t top,
                         bool complex_pair, uint16_t k, mat_t *v)
{
    const uint16_t n = sc->n;
    cplx_t y[FCC_MAT_MAX_DIM];
    real_t ymax = RL(0.0);
    uint16_t imax = 0;
    for (uint16_t i = 0; i < n; ++i) {
        y[i].re = RL(0.0);
        y[i].im = RL(0.0);
        for (uint16_t j = 0; j <= top; ++j) {
            y[i].re += AT(sc->z, n, i, j) * x[j].re;
            y[i].im += AT(sc->z, n, i, j) * x[j].im;
        }
        y[i].re *= scale[i];
        y[i].im *= scale[i];
        if (c_abs1(y[i]) > ymax) {
            ymax = c_abs1(y[i]);
            imax = i;
        }
    }
    /* Divide by the largest entry first (no overflow), then by the 2-norm. */
    const cplx_t pivot = y[imax];
    real_t sum = RL(0.0);
    for (uint16_t i = 0; i < n; ++i) {
        y[i] = c_div(y[i], pivot);
        sum += y[i].re * y[i].re + y[i].im * y[i].im;
    }
    const real_t inv_norm = RL(1.0) / MSQRT(sum);
    for (uint16_t i = 0; i < n; ++i) {
        FCC_MAT_AT(v, i, k) = y[i].re * inv_norm;
        if (complex_pair) {
            FCC_MAT_AT(v, i, k + 1U) = y[i].im * inv_norm;
        }
    }
}

static void schur_vectors(const schur_t *sc, const real_t *scale, mat_t *v)
{
    const uint16_t n = sc->n;
    const real_t *t = sc->h;
    real_t tnorm = RL(0.0);
    for (size_t i = 0; i < (size_t)n * n; ++i) {
        tnorm += MFABS(t[i]);
    }
    const real_t smin = (tnorm > RL(0.0)) ? MEPS * tnorm : MEPS;
    cplx_t x[FCC_MAT_MAX_DIM];
    uint16_t k = 0;
    while (k < n) {
        for (uint16_t i = 0; i < n; ++i) {
            x[i].re = RL(0.0);
            x[i].im = RL(0.0);
        }
        const cplx_t lambda = {sc->wr[k], sc->wi[k]};
        if (sc->wi[k] == RL(0.0)) {
            x[k].re = RL(1.0);
            back_substitute(t, n, k, k, lambda, smin, x);
            store_vector(sc, scale, x, k, false, k, v);
            k = (uint16_t)(k + 1U);
            continue;
        }
        /* Pair at (k, k+1), lambda = wr + j wi with wi > 0: seed from the block
         * row that gives the better-scaled null vector of (B - lambda I). */
        const uint16_t q = (uint16_t)(k + 1U);
        const real_t b = AT(t, n, k, q);
        const real_t c = AT(t, n, q, k);
        if (MFABS(b) >= MFABS(c)) {
            x[k].re = b;
            x[q].re = lambda.re - AT(t, n, k, k);
            x[q].im = lambda.im;
        } else {
            x[k].re = lambda.re - AT(t, n, q, q);
            x[k].im = lambda.im;
            x[q].re = c;
        }
        back_substitute(t, n, k, q, lambda, smin, x);
        store_vector(sc, scale, x, q, true, k, v);
        k = (uint16_t)(k + 2U);
    }
}

/* ---- public entry points --------------------------------------------------- */

fcc_status_t MAT(eig)(const mat_t *a, real_t wr[], real_t wi[], mat_t *v,
                         eig_ws_t *ws)
{
    if (!MAT(valid)(a) || wr == NULL || wi == NULL || ws == NULL) {
        return FCC_ERR_ARG;
    }
    if (a->rows != a->cols || a->rows > FCC_MAT_MAX_DIM) {
        return FCC_ERR_SIZE;
    }
    if (v != NULL) {
        if (!MAT(valid)(v) || v->data == a->data) {
            return FCC_ERR_ARG;
        }
        if (!MAT(same_size)(a, v)) {
            return FCC_ERR_SIZE;
        }
    }
    fcc_status_t st = MAT(check_finite)(a);
    if (st != FCC_OK) {
        return st;
    }
    const uint16_t n = a->rows;
    for (size_t i = 0; i < MAT(count)(a); ++i) {
        ws->h[i] = a->data[i];
    }
    schur_t sc = {ws->h, NULL, n, wr, wi};
    if (v != NULL) {
        mat_t z = {n, n, ws->z};
        (void)MAT(identity)(&z);
        sc.z = ws->z;
    }
    balance(ws->h, n, ws->scale);
    hessenberg(ws->h, sc.z, n);
    st = francis_qr(&sc);
    if (st != FCC_OK) {
        return st;
    }
    if (v != NULL) {
        schur_vectors(&sc, ws->scale, v);
        return MAT(check_finite)(v);
    }
    return FCC_OK;
}

fcc_status_t MAT(spectral_radius)(const mat_t *a, real_t *rho, eig_ws_t *ws)
{
    if (rho == NULL) {
        return FCC_ERR_ARG;
    }
    real_t wr[FCC_MAT_MAX_DIM];
    real_t wi[FCC_MAT_MAX_DIM];
    const fcc_status_t st = MAT(eig)(a, wr, wi, NULL, ws);
    if (st != FCC_OK) {
        return st;
    }
    real_t r = RL(0.0);
    for (uint16_t i = 0; i < a->rows; ++i) {
        const real_t m = MHYPOT(wr[i], wi[i]);
        r = (m > r) ? m : r;
    }
    *rho = r;
    return FCC_OK;
}
