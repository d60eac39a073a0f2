/* fcc_mat_lu.c -- LU with partial pivoting, Cholesky, solves, inverse, rcond. */
#include "fcc_mat_impl.h"

/* perm[] is uint8_t: keep the maximum dimension within its range. */
typedef char fcc_mat_max_dim_fits_perm[(FCC_MAT_MAX_DIM <= 255) ? 1 : -1];

/* Common checks of a square input: a usable descriptor, a size the workspace
 * holds, finite data. */
static fcc_status_t check_square_input(const mat_t *a)
{
    if (!MAT(valid)(a)) {
        return FCC_ERR_ARG;
    }
    if (a->rows != a->cols || a->rows > FCC_MAT_MAX_DIM) {
        return FCC_ERR_SIZE;
    }
    return MAT(check_finite)(a);
}

#define LU_AT(f, i, j) ((f)->lu[(size_t)(i) * (f)->n + (size_t)(j)])

/* Row index (>= k) of the largest |entry| in column k: the partial pivot. */
static uint16_t pivot_row(const lu_t *lu, uint16_t k)
{
    uint16_t best = k;
    real_t best_abs = MFABS(LU_AT(lu, k, k));
    for (uint16_t i = (uint16_t)(k + 1U); i < lu->n; ++i) {
        const real_t v = MFABS(LU_AT(lu, i, k));
        if (v > best_abs) {
            best_abs = v;
            best = i;
        }
    }
    return best;
}

static void swap_rows(lu_t *lu, uint16_t r1, uint16_t r2)
{
    for (uint16_t j = 0; j < lu->n; ++j) {
        const real_t t = LU_AT(lu, r1, j);
        LU_AT(lu, r1, j) = LU_AT(lu, r2, j);
        LU_AT(lu, r2, j) = t;
    }
    const uint8_t p = lu->perm[r1];
    lu->perm[r1] = lu->perm[r2];
    lu->perm[r2] = p;
}

fcc_status_t MAT(lu_factor)(lu_t *lu, const mat_t *a)
{
    if (lu == NULL) {
        return FCC_ERR_ARG;
    }
    const fcc_status_t st = check_square_input(a);
    if (st != FCC_OK) {
        return st;
    }
    const uint16_t n = a->rows;
    lu->n = n;
    real_t amax = RL(0.0);
    for (size_t i = 0; i < MAT(count)(a); ++i) {
        lu->lu[i] = a->data[i];
        amax = (MFABS(a->data[i]) > amax) ? MFABS(a->data[i]) : amax;
    }
    for (uint16_t i = 0; i < n; ++i) {
        lu->perm[i] = (uint8_t)i;
    }
    (void)MAT(norm_1)(a, &lu->norm1);
    /* A pivot this small is indistinguishable from rounding noise in A. */
    const real_t tiny = (real_t)n * MEPS * amax;
    for (uint16_t k = 0; k < n; ++k) {
        const uint16_t p = pivot_row(lu, k);
        if (!(MFABS(LU_AT(lu, p, k)) > tiny)) {
            return FCC_ERR_SINGULAR;
        }
        if (p != k) {
            swap_rows(lu, k, p);
        }
        const real_t pivot = LU_AT(lu, k, k);
        for (uint16_t i = (uint16_t)(k + 1U); i < n; ++i) {
            const real_t factor = LU_AT(lu, i, k) / pivot;
            LU_AT(lu, i, k) = factor;
            for (uint16_t j = (uint16_t)(k + 1U); j < n; ++j) {
                LU_AT(lu, i, j) -= factor * LU_AT(lu, k, j);
            }
        }
    }
    return FCC_OK;
}

static fcc_status_t check_rhs(const lu_t *lu, const mat_t *b, const mat_t *x)
{
    if (lu == NULL || !MAT(valid)(b) || !MAT(valid)(x)) {
        return FCC_ERR_ARG;
    }
    if (lu->n == 0U || lu->n > FCC_MAT_MAX_DIM) {
        return FCC_ERR_ARG;
    }
    if (b->rows != lu->n || !MAT(same_size)(b, x)) {
        return FCC_ERR_SIZE;
    }
    return FCC_OK;
}

/* y <- U^-1 L^-1 y (y already permuted). */
static void lu_substitute(const lu_t *lu, real_t y[])
{
    const uint16_t n = lu->n;
    for (uint16_t i = 1; i < n; ++i) {
        for (uint16_t k = 0; k < i; ++k) {
            y[i] -= LU_AT(lu, i, k) * y[k];
        }
    }
    for (uint16_t i = n; i-- > 0U;) {
        for (uint16_t k = (uint16_t)(i + 1U); k < n; ++k) {
            y[i] -= LU_AT(lu, i, k) * y[k];
        }
        y[i] /= LU_AT(lu, i, i);
    }
}

/* y <- L^-T U^-T y (the result still needs the inverse permutation). */
static void lu_substitute_trans(const lu_t *lu, real_t y[])
{
    const uint16_t n = lu->n;
    for (uint16_t i = 0; i < n; ++i) {
        for (uint16_t k = 0; k < i; ++k) {
            y[i] -= LU_AT(lu, k, i) * y[k];
        }
        y[i] /= LU_AT(lu, i, i);
    }
    for (uint16_t i = n; i-- > 0U;) {
        for (uint16_t k = (uint16_t)(i + 1U); k < n; ++k) {
            y[i] -= LU_AT(lu, k, i) * y[k];
        }
    }
}

/* x = A^-1 b, or A^-T b with trans, column by column (x may be b).  With
 * P A = L U the row permutation gathers b's rows for A and scatters x's rows
 * for A^T. */
static fcc_status_t lu_solve_columns(const lu_t *lu, const mat_t *b, mat_t *x, bool trans)
{
    const fcc_status_t st = check_rhs(lu, b, x);
    if (st != FCC_OK) {
        return st;
    }
    real_t y[FCC_MAT_MAX_DIM];
    for (uint16_t j = 0; j < b->cols; ++j) {
        for (uint16_t i = 0; i < lu->n; ++i) {
            y[i] = FCC_MAT_AT(b, trans ? i : lu->perm[i], j);
        }
        if (trans) {
            lu_substitute_trans(lu, y);
        } else {
            lu_substitute(lu, y);
        }
        for (uint16_t i = 0; i < lu->n; ++i) {
            FCC_MAT_AT(x, trans ? lu->perm[i] : i, j) = y[i];
        }
    }
    return MAT(check_finite)(x);
}

fcc_status_t MAT(lu_solve)(const lu_t *lu, const mat_t *b, mat_t *x)
{
    return lu_solve_columns(lu, b, x, false);
}

fcc_status_t MAT(lu_solve_trans)(const lu_t *lu, const mat_t *b, mat_t *x)
{
    return lu_solve_columns(lu, b, x, true);
}

fcc_status_t MAT(lu_rcond)(const lu_t *lu, real_t *rcond)
{
    if (lu == NULL || rcond == NULL || lu->n == 0U || lu->n > FCC_MAT_MAX_DIM) {
        return FCC_ERR_ARG;
    }
    /* ||A^-1||_1 column by column: A^-1 e_j. */
    real_t inv_norm = RL(0.0);
    real_t y[FCC_MAT_MAX_DIM];
    for (uint16_t j = 0; j < lu->n; ++j) {
        for (uint16_t i = 0; i < lu->n; ++i) {
            y[i] = (lu->perm[i] == j) ? RL(1.0) : RL(0.0);
        }
        lu_substitute(lu, y);
        real_t sum = RL(0.0);
        for (uint16_t i = 0; i < lu->n; ++i) {
            sum += MFABS(y[i]);
        }
        inv_norm = (sum > inv_norm) ? sum : inv_norm;
    }
    const real_t denom = lu->norm1 * inv_norm;
    *rcond = (FCC_IS_FINITE(denom) && denom > RL(0.0)) ? RL(1.0) / denom : RL(0.0);
    return FCC_OK;
}

fcc_status_t MAT(solve)(const mat_t *a, const mat_t *b, mat_t *x, lu_t *lu)
{
    const fcc_status_t st = MAT(lu_factor)(lu, a);
    if (st != FCC_OK) {
        return st;
    }
    return MAT(lu_solve)(lu, b, x);
}

fcc_status_t MAT(inv)(const mat_t *a, mat_t *ainv, lu_t *lu)
{
    fcc_status_t st = MAT(lu_factor)(lu, a);
    if (st != FCC_OK) {
        return st;
    }
    if (!MAT(valid)(ainv)) {
        return FCC_ERR_ARG;
    }
    if (!MAT(same_size)(a, ainv)) {
        return FCC_ERR_SIZE;
    }
    st = MAT(identity)(ainv);
    if (st != FCC_OK) {
        return st;
    }
    return MAT(lu_solve)(lu, ainv, ainv);
}

fcc_status_t MAT(chol)(const mat_t *a, mat_t *l)
{
    fcc_status_t st = check_square_input(a);
    if (st != FCC_OK) {
        return st;
    }
    if (!MAT(valid)(l)) {
        return FCC_ERR_ARG;
    }
    if (!MAT(same_size)(a, l)) {
        return FCC_ERR_SIZE;
    }
    const uint16_t n = a->rows;
    real_t dmax = RL(0.0);
    for (uint16_t i = 0; i < n; ++i) {
        dmax = (FCC_MAT_AT(a, i, i) > dmax) ? FCC_MAT_AT(a, i, i) : dmax;
    }
    const real_t tiny = (real_t)n * MEPS * dmax;
    /* Column by column; each a(i,j) is read just before l(i,j) overwrites it,
     * so l may be the same matrix as a. */
    for (uint16_t j = 0; j < n; ++j) {
        real_t d = FCC_MAT_AT(a, j, j);
        for (uint16_t k = 0; k < j; ++k) {
            d -= FCC_MAT_AT(l, j, k) * FCC_MAT_AT(l, j, k);
        }
        if (!(d > tiny)) {
            return FCC_ERR_NOT_POSDEF;
        }
        const real_t ljj = MSQRT(d);
        FCC_MAT_AT(l, j, j) = ljj;
        for (uint16_t i = (uint16_t)(j + 1U); i < n; ++i) {
            real_t s = FCC_MAT_AT(a, i, j);
            for (uint16_t k = 0; k < j; ++k) {
                s -= FCC_MAT_AT(l, i, k) * FCC_MAT_AT(l, j, k);
            }
            FCC_MAT_AT(l, i, j) = s / ljj;
        }
    }
    for (uint16_t i = 0; i < n; ++i) {
        for (uint16_t j = (uint16_t)(i + 1U); j < n; ++j) {
            FCC_MAT_AT(l, i, j) = RL(0.0);
        }
    }
    return FCC_OK;
}

fcc_status_t MAT(chol_solve)(const mat_t *l, const mat_t *b, mat_t *x)
{
    if (!MAT(valid)(l) || !MAT(valid)(b) || !MAT(valid)(x)) {
        return FCC_ERR_ARG;
    }
    if (l->rows != l->cols || l->rows > FCC_MAT_MAX_DIM || b->rows != l->rows ||
        !MAT(same_size)(b, x)) {
        return FCC_ERR_SIZE;
    }
    const uint16_t n = l->rows;
    real_t y[FCC_MAT_MAX_DIM];
    for (uint16_t c = 0; c < b->cols; ++c) {
        for (uint16_t i = 0; i < n; ++i) {
            real_t s = FCC_MAT_AT(b, i, c);
            for (uint16_t k = 0; k < i; ++k) {
                s -= FCC_MAT_AT(l, i, k) * y[k];
            }
            y[i] = s / FCC_MAT_AT(l, i, i);
        }
        for (uint16_t i = n; i-- > 0U;) {
            real_t s = y[i];
            for (uint16_t k = (uint16_t)(i + 1U); k < n; ++k) {
                s -= FCC_MAT_AT(l, k, i) * y[k];
            }
            y[i] = s / FCC_MAT_AT(l, i, i);
        }
        for (uint16_t i = 0; i < n; ++i) {
            FCC_MAT_AT(x, i, c) = y[i];
        }
    }
    return MAT(check_finite)(x);
}
