/*
 * fcc_mat_svd.c -- singular values by one-sided Jacobi (Hestenes 1958;
 * Demmel & Veselic 1992): rotate pairs of columns of W = A (or A^T, so that
 * W has at least as many rows as columns) until all columns are mutually
 * orthogonal; the singular values are then the column norms.  Converges
 * quadratically, is accurate for small singular values (no A^T A), and needs
 * nothing but the copy of A.
 */
#include "fcc_mat_impl.h"

#define SVD_MAX_SWEEPS 40

/* Rotate columns i and j of the rows x cols array w; returns true if the pair
 * was not yet orthogonal to working precision. */
static bool orthogonalise_pair(real_t *w, uint16_t rows, uint16_t cols, uint16_t i, uint16_t j)
{
    real_t alpha = RL(0.0);
    real_t beta = RL(0.0);
    real_t gamma = RL(0.0);
    for (uint16_t r = 0; r < rows; ++r) {
        const real_t wi = w[(size_t)r * cols + i];
        const real_t wj = w[(size_t)r * cols + j];
        alpha += wi * wi;
        beta += wj * wj;
        gamma += wi * wj;
    }
    if (gamma == RL(0.0) || MFABS(gamma) <= MEPS * MSQRT(alpha) * MSQRT(beta)) {
        return false;
    }
    /* The rotation that zeroes the (i, j) entry of W^T W. */
    const real_t zeta = (beta - alpha) / (RL(2.0) * gamma);
    const real_t t = MCOPYSIGN(RL(1.0), zeta) / (MFABS(zeta) + MHYPOT(RL(1.0), zeta));
    const real_t c = RL(1.0) / MSQRT(RL(1.0) + t * t);
    const real_t s = c * t;
    for (uint16_t r = 0; r < rows; ++r) {
        const real_t wi = w[(size_t)r * cols + i];
        const real_t wj = w[(size_t)r * cols + j];
        w[(size_t)r * cols + i] = c * wi - s * wj;
        w[(size_t)r * cols + j] = s * wi + c * wj;
    }
    return true;
}

/* Insertion sort, decreasing (at most FCC_MAT_MAX_DIM values). */
static void sort_decreasing(real_t *s, uint16_t k)
{
    for (uint16_t i = 1; i < k; ++i) {
        const real_t v = s[i];
        uint16_t j = i;
        while (j > 0U && s[j - 1U] < v) {
            s[j] = s[j - 1U];
            --j;
        }
        s[j] = v;
    }
}

fcc_status_t MAT(svd_values)(const mat_t *a, real_t s[], svd_ws_t *ws)
{
    if (!MAT(valid)(a) || s == NULL || ws == NULL) {
        return FCC_ERR_ARG;
    }
    const bool tall = a->rows >= a->cols;
    const uint16_t rows = tall ? a->rows : a->cols;
    const uint16_t cols = tall ? a->cols : a->rows;
    if (cols > FCC_MAT_MAX_DIM || rows > 2U * FCC_MAT_MAX_DIM) {
        return FCC_ERR_SIZE;
    }
    fcc_status_t st = MAT(check_finite)(a);
    if (st != FCC_OK) {
        return st;
    }
    /* w is rows x cols: A itself or A^T. */
    real_t amax = RL(0.0);
    (void)MAT(norm_max)(a, &amax);
    if (amax == RL(0.0)) {
        for (uint16_t k = 0; k < cols; ++k) {
            s[k] = RL(0.0);
        }
        return FCC_OK;
    }
    /* Work on A / max|a_ij|: sums of squares cannot overflow or underflow. */
    for (uint16_t i = 0; i < a->rows; ++i) {
        for (uint16_t j = 0; j < a->cols; ++j) {
            const size_t dst = tall ? (size_t)i * cols + j : (size_t)j * cols + i;
            ws->w[dst] = FCC_MAT_AT(a, i, j) / amax;
        }
    }
    bool rotated = true;
    int sweep = 0;
    while (rotated && sweep < SVD_MAX_SWEEPS) {
        rotated = false;
        for (uint16_t i = 0; i + 1U < cols; ++i) {
            for (uint16_t j = (uint16_t)(i + 1U); j < cols; ++j) {
                rotated = orthogonalise_pair(ws->w, rows, cols, i, j) || rotated;
            }
        }
        ++sweep;
    }
    if (rotated) {
        return FCC_ERR_NO_CONVERGENCE;
    }
    for (uint16_t k = 0; k < cols; ++k) {
        real_t sum = RL(0.0);
        for (uint16_t r = 0; r < rows; ++r) {
            sum += ws->w[(size_t)r * cols + k] * ws->w[(size_t)r * cols + k];
        }
        s[k] = amax * MSQRT(sum);
    }
    sort_decreasing(s, cols);
    return FCC_OK;
}

fcc_status_t MAT(norm_2)(const mat_t *a, real_t *out, svd_ws_t *ws)
{
    if (out == NULL) {
        return FCC_ERR_ARG;
    }
    real_t s[FCC_MAT_MAX_DIM];
    const fcc_status_t st = MAT(svd_values)(a, s, ws);
    if (st == FCC_OK) {
        *out = s[0];
    }
    return st;
}
