/*
 * fcc_mat_expm.c -- matrix exponential by scaling and squaring with Pade.
 *
 * Higham, "The scaling and squaring method for the matrix exponential
 * revisited", SIAM J. Matrix Anal. Appl. 26(4), 2005: for ||A||_1 <= theta_m
 * the [m/m] Pade approximant r_m(A) = (V - U)^-1 (V + U) has a relative
 * backward error below the unit roundoff; otherwise A is scaled by 2^-s into
 * that range and the result squared s times.  The theta_m are the paper's
 * values for IEEE double (degrees 3, 5, 7, 9, 13) and IEEE single (3, 5, 7).
 */
#include "fcc_mat_impl.h"

#if MAT_SINGLE
#define EXPM_NDEG 3
static const uint8_t expm_degree[EXPM_NDEG] = {3U, 5U, 7U};
static const real_t expm_theta[EXPM_NDEG] = {
    RL(4.258730016922831e-1), RL(1.880152677804762), RL(3.925724783138660)};
#else
#define EXPM_NDEG 5
static const uint8_t expm_degree[EXPM_NDEG] = {3U, 5U, 7U, 9U, 13U};
static const real_t expm_theta[EXPM_NDEG] = {
    RL(1.495585217958292e-2), RL(2.539398330063230e-1), RL(9.504178996162932e-1),
    RL(2.097847961257068), RL(5.371920351148152)};
#endif

#define PADE_MAX_DEGREE 13

/* Coefficients of the [m/m] Pade numerator p(x) = sum b_j x^j, normalised to
 * b_0 = 1: b_j = b_{j-1} (m - j + 1) / ((2m - j + 1) j).  The denominator is p(-x). */
static void pade_coefficients(uint8_t m, real_t b[PADE_MAX_DEGREE + 1])
{
    b[0] = RL(1.0);
    for (uint8_t j = 1; j <= m; ++j) {
        b[j] = b[j - 1U] * (real_t)(m - j + 1U) / ((real_t)(2U * m - j + 1U) * (real_t)j);
    }
}

/* dst = sum_k c[k] * term[k] (+ c_id * I), with NULL-terminated terms. */
static void lincomb(real_t *dst, uint16_t n, real_t c_id, const real_t *c,
                    const real_t *const *term, uint8_t nterms)
{
    const size_t count = (size_t)n * n;
    for (size_t i = 0; i < count; ++i) {
        real_t s = RL(0.0);
        for (uint8_t k = 0; k < nterms; ++k) {
            s += c[k] * term[k][i];
        }
        dst[i] = s;
    }
    for (uint16_t i = 0; i < n; ++i) {
        dst[(size_t)i * n + i] += c_id;
    }
}

/* c = a b for n x n arrays of the workspace (no aliasing of c). */
static void mul_raw(real_t *c, real_t *a, real_t *b, uint16_t n)
{
    const mat_t ma = {n, n, a};
    const mat_t mb = {n, n, b};
    mat_t mc = {n, n, c};
    (void)MAT(mul)(&ma, &mb, &mc);
}

/*
 * U (odd part) into ws->u and V (even part) into ws->v of the degree-m
 * approximant of the matrix x (n x n; x holds the already scaled A).
 */
static void pade_uv(uint8_t m, real_t *x, uint16_t n, expm_ws_t *ws)
{
    real_t b[PADE_MAX_DEGREE + 1];
    pade_coefficients(m, b);
    mul_raw(ws->a2, x, x, n);
    mul_raw(ws->a4, ws->a2, ws->a2, n);
    mul_raw(ws->a6, ws->a4, ws->a2, n);
    if (m == 13U) {
        /* Higham's evaluation with 6 products instead of 12. */
        const real_t *const pw[3] = {ws->a6, ws->a4, ws->a2};
        const real_t c_u_hi[3] = {b[13], b[11], b[9]};
        const real_t c_u_lo[3] = {b[7], b[5], b[3]};
        const real_t c_v_hi[3] = {b[12], b[10], b[8]};
        const real_t c_v_lo[3] = {b[6], b[4], b[2]};
        lincomb(ws->t, n, RL(0.0), c_u_hi, pw, 3U);
        mul_raw(ws->u, ws->a6, ws->t, n);
        lincomb(ws->t, n, b[1], c_u_lo, pw, 3U);
        for (size_t i = 0; i < (size_t)n * n; ++i) {
            ws->t[i] += ws->u[i];
        }
        mul_raw(ws->u, x, ws->t, n); /* U */
        lincomb(ws->t, n, RL(0.0), c_v_hi, pw, 3U);
        mul_raw(ws->v, ws->a6, ws->t, n);
        lincomb(ws->t, n, b[0], c_v_lo, pw, 3U);
        for (size_t i = 0; i < (size_t)n * n; ++i) {
            ws->v[i] += ws->t[i]; /* V */
        }
        return;
    }
    /* m in {3, 5, 7, 9}: U = x (b1 I + b3 x^2 + ...), V = b0 I + b2 x^2 + ... */
    const real_t *pw[4] = {ws->a2, ws->a4, ws->a6, ws->u};
    const uint8_t npow = (uint8_t)((m - 1U) / 2U);
    if (m == 9U) {
        mul_raw(ws->u, ws->a4, ws->a4, n); /* x^8 */
    }
    real_t c_odd[4];
    real_t c_even[4];
    for (uint8_t k = 0; k < npow; ++k) {
        c_odd[k] = b[2U * k + 3U];
        c_even[k] = b[2U * k + 2U];
    }
    lincomb(ws->t, n, b[1], c_odd, pw, npow);
    lincomb(ws->v, n, b[0], c_even, pw, npow);
    mul_raw(ws->u, x, ws->t, n);
}

/* Smallest s >= 0 with norm / 2^s <= theta. */
static int scaling_exponent(real_t norm, real_t theta)
{
    if (norm <= theta) {
        return 0;
    }
    int e = 0;
    const real_t f = MFREXP(norm / theta, &e); /* norm/theta = f 2^e, f in [0.5, 1) */
    return (f == RL(0.5)) ? e - 1 : e;
}

fcc_status_t MAT(expm)(const mat_t *a, mat_t *e, expm_ws_t *ws)
{
    if (!MAT(valid)(a) || !MAT(valid)(e) || ws == NULL || a->data == e->data) {
        return FCC_ERR_ARG;
    }
    if (a->rows != a->cols || a->rows > FCC_MAT_MAX_DIM || !MAT(same_size)(a, e)) {
        return FCC_ERR_SIZE;
    }
    fcc_status_t st = MAT(check_finite)(a);
    if (st != FCC_OK) {
        return st;
    }
    const uint16_t n = a->rows;
    real_t norm = RL(0.0);
    (void)MAT(norm_1)(a, &norm);
    if (!FCC_IS_FINITE(norm)) {
        return FCC_ERR_NOT_FINITE;
    }
    uint8_t deg_index = 0;
    while (deg_index + 1U < EXPM_NDEG && norm > expm_theta[deg_index]) {
        ++deg_index;
    }
    const int s = scaling_exponent(norm, expm_theta[deg_index]);
    /* e holds the scaled matrix while the approximant is evaluated. */
    st = MAT(scale)(a, MLDEXP(RL(1.0), -s), e);
    if (st != FCC_OK) {
        return st;
    }
    pade_uv(expm_degree[deg_index], e->data, n, ws);
    mat_t q = {n, n, ws->a2};
    mat_t p = {n, n, ws->a4};
    const mat_t u = {n, n, ws->u};
    const mat_t v = {n, n, ws->v};
    (void)MAT(sub)(&v, &u, &q);
    (void)MAT(add)(&v, &u, &p);
    st = MAT(solve)(&q, &p, e, &ws->lu);
    if (st != FCC_OK) {
        return (st == FCC_ERR_SINGULAR) ? FCC_ERR_NOT_FINITE : st;
    }
    mat_t t = {n, n, ws->t};
    for (int k = 0; k < s; ++k) {
        (void)MAT(mul)(e, e, &t);
        (void)MAT(copy)(&t, e);
    }
    return MAT(check_finite)(e);
}
