/* fcc_c2d.c -- ZOH discretisation by Van Loan block exponentials. */
#include "fcc_c2d.h"

#include "fcc_types.h" /* FCC_TRY */

static bool usable(const fcc_mat64_t *m)
{
    return m != NULL && m->data != NULL && m->rows > 0U && m->cols > 0U;
}

static bool is_shape(const fcc_mat64_t *m, uint16_t rows, uint16_t cols)
{
    return m->rows == rows && m->cols == cols;
}

static fcc_status_t check_period(double t)
{
    return (FCC_IS_FINITE(t) && t > 0.0) ? FCC_OK : FCC_ERR_ARG;
}

/* blk(r0.., c0..) = s * src (or s * src^T when trans). */
static void put_scaled(fcc_mat64_t *blk, uint16_t r0, uint16_t c0, const fcc_mat64_t *src, double s,
                       bool trans)
{
    const uint16_t rows = trans ? src->cols : src->rows;
    const uint16_t cols = trans ? src->rows : src->cols;
    for (uint16_t i = 0; i < rows; ++i) {
        for (uint16_t j = 0; j < cols; ++j) {
            const double v = trans ? FCC_MAT_AT(src, j, i) : FCC_MAT_AT(src, i, j);
            FCC_MAT_AT(blk, r0 + i, c0 + j) = s * v;
        }
    }
}

fcc_status_t fcc_c2d_zoh(const fcc_mat64_t *f, const fcc_mat64_t *g, double t, fcc_mat64_t *phi,
                         fcc_mat64_t *gamma, fcc_c2d_ws_t *ws)
{
    if (!usable(f) || !usable(g) || !usable(phi) || !usable(gamma) || ws == NULL) {
        return FCC_ERR_ARG;
    }
    const uint16_t n = f->rows;
    const uint16_t m = g->cols;
    if (!is_shape(f, n, n) || !is_shape(g, n, m) || !is_shape(phi, n, n) ||
        !is_shape(gamma, n, m) || n + m > FCC_MAT_MAX_DIM) {
        return FCC_ERR_SIZE;
    }
    FCC_TRY(check_period(t));
    FCC_TRY(fcc_mat64_check_finite(f));
    FCC_TRY(fcc_mat64_check_finite(g));
    const uint16_t nb = (uint16_t)(n + m);
    fcc_mat64_t blk = FCC_MAT64(nb, nb, ws->blk);
    fcc_mat64_t e = FCC_MAT64(nb, nb, ws->e);
    FCC_TRY(fcc_mat64_zero(&blk));
    put_scaled(&blk, 0, 0, f, t, false);
    put_scaled(&blk, 0, n, g, t, false);
    FCC_TRY(fcc_mat64_expm(&blk, &e, &ws->expm));
    FCC_TRY(fcc_mat64_get_block(&e, 0, 0, phi));
    return fcc_mat64_get_block(&e, 0, n, gamma);
}

fcc_status_t fcc_c2d_noise(const fcc_mat64_t *f, const fcc_mat64_t *qc, double t, fcc_mat64_t *qd,
                           fcc_c2d_ws_t *ws)
{
    if (!usable(f) || !usable(qc) || !usable(qd) || ws == NULL) {
        return FCC_ERR_ARG;
    }
    const uint16_t n = f->rows;
    if (!is_shape(f, n, n) || !is_shape(qc, n, n) || !is_shape(qd, n, n) ||
        2U * n > FCC_MAT_MAX_DIM) {
        return FCC_ERR_SIZE;
    }
    FCC_TRY(check_period(t));
    FCC_TRY(fcc_mat64_check_finite(f));
    FCC_TRY(fcc_mat64_check_finite(qc));
    const uint16_t nb = (uint16_t)(2U * n);
    fcc_mat64_t blk = FCC_MAT64(nb, nb, ws->blk);
    fcc_mat64_t e = FCC_MAT64(nb, nb, ws->e);
    FCC_TRY(fcc_mat64_zero(&blk));
    put_scaled(&blk, 0, 0, f, -t, false);
    put_scaled(&blk, 0, n, qc, t, false);
    put_scaled(&blk, n, n, f, t, true);
    FCC_TRY(fcc_mat64_expm(&blk, &e, &ws->expm));
    /* Q_d = E22^T E12: the blocks are read in place through row strides. */
    for (uint16_t i = 0; i < n; ++i) {
        for (uint16_t j = 0; j < n; ++j) {
            double s = 0.0;
            for (uint16_t k = 0; k < n; ++k) {
                s += FCC_MAT_AT(&e, n + k, n + i) * FCC_MAT_AT(&e, k, n + j);
            }
            FCC_MAT_AT(qd, i, j) = s;
        }
    }
    return fcc_mat64_symmetrize(qd);
}

fcc_status_t fcc_c2d_cost(const fcc_mat64_t *f, const fcc_mat64_t *g, const fcc_mat64_t *wx,
                          const fcc_mat64_t *wu, double t, fcc_mat64_t *q11, fcc_mat64_t *q12,
                          fcc_mat64_t *q22, fcc_c2d_ws_t *ws)
{
    if (!usable(f) || !usable(g) || !usable(wx) || !usable(wu) || !usable(q11) || !usable(q12) ||
        !usable(q22) || ws == NULL) {
        return FCC_ERR_ARG;
    }
    const uint16_t n = f->rows;
    const uint16_t m = g->cols;
    if (!is_shape(f, n, n) || !is_shape(g, n, m) || !is_shape(wx, n, n) || !is_shape(wu, m, m) ||
        !is_shape(q11, n, n) || !is_shape(q12, n, m) || !is_shape(q22, m, m) ||
        2U * (n + m) > FCC_MAT_MAX_DIM) {
        return FCC_ERR_SIZE;
    }
    FCC_TRY(check_period(t));
    FCC_TRY(fcc_mat64_check_finite(f));
    FCC_TRY(fcc_mat64_check_finite(g));
    FCC_TRY(fcc_mat64_check_finite(wx));
    FCC_TRY(fcc_mat64_check_finite(wu));
    const uint16_t na = (uint16_t)(n + m); /* augmented state [x; u] */
    const uint16_t nb = (uint16_t)(2U * na);
    fcc_mat64_t blk = FCC_MAT64(nb, nb, ws->blk);
    fcc_mat64_t e = FCC_MAT64(nb, nb, ws->e);
    FCC_TRY(fcc_mat64_zero(&blk));
    /* [[-Fa^T, Wa], [0, Fa]] T with Fa = [[F, G], [0, 0]], Wa = blkdiag(Wx, Wu) */
    put_scaled(&blk, 0, 0, f, -t, true);
    put_scaled(&blk, n, 0, g, -t, true);
    put_scaled(&blk, 0, na, wx, t, false);
    put_scaled(&blk, n, na + n, wu, t, false);
    put_scaled(&blk, na, na, f, t, false);
    put_scaled(&blk, na, na + n, g, t, false);
    FCC_TRY(fcc_mat64_expm(&blk, &e, &ws->expm));
    /* W = E22^T E12 (na x na), written block by block into Q11, Q12, Q22. */
    for (uint16_t i = 0; i < na; ++i) {
        for (uint16_t j = i; j < na; ++j) {
            double s = 0.0;
            for (uint16_t k = 0; k < na; ++k) {
                s += FCC_MAT_AT(&e, na + k, na + i) * FCC_MAT_AT(&e, k, na + j);
            }
            if (j < n) {
                FCC_MAT_AT(q11, i, j) = s;
                FCC_MAT_AT(q11, j, i) = s;
            } else if (i < n) {
                FCC_MAT_AT(q12, i, j - n) = s;
            } else {
                FCC_MAT_AT(q22, i - n, j - n) = s;
                FCC_MAT_AT(q22, j - n, i - n) = s;
            }
        }
    }
    FCC_TRY(fcc_mat64_check_finite(q11));
    FCC_TRY(fcc_mat64_check_finite(q12));
    return fcc_mat64_check_finite(q22);
}
