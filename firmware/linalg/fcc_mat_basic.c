/* fcc_mat_basic.c -- descriptors, element-wise operations, products, norms. */
#include "fcc_mat_impl.h"

bool MAT(valid)(const mat_t *m)
{
    return m != NULL && m->data != NULL && m->rows > 0U && m->cols > 0U;
}

bool MAT(same_size)(const mat_t *a, const mat_t *b)
{
    return a->rows == b->rows && a->cols == b->cols;
}

size_t MAT(count)(const mat_t *m)
{
    return (size_t)m->rows * (size_t)m->cols;
}

fcc_status_t MAT(init)(mat_t *m, uint16_t rows, uint16_t cols, real_t *data)
{
    if (m == NULL || data == NULL || rows == 0U || cols == 0U) {
        return FCC_ERR_ARG;
    }
    m->rows = rows;
    m->cols = cols;
    m->data = data;
    return FCC_OK;
}

fcc_status_t MAT(zero)(mat_t *m)
{
    if (!MAT(valid)(m)) {
        return FCC_ERR_ARG;
    }
    for (size_t i = 0; i < MAT(count)(m); ++i) {
        m->data[i] = RL(0.0);
    }
    return FCC_OK;
}

fcc_status_t MAT(identity)(mat_t *m)
{
    if (!MAT(valid)(m)) {
        return FCC_ERR_ARG;
    }
    if (m->rows != m->cols) {
        return FCC_ERR_SIZE;
    }
    (void)MAT(zero)(m);
    for (uint16_t i = 0; i < m->rows; ++i) {
        FCC_MAT_AT(m, i, i) = RL(1.0);
    }
    return FCC_OK;
}

fcc_status_t MAT(copy)(const mat_t *src, mat_t *dst)
{
    if (!MAT(valid)(src) || !MAT(valid)(dst)) {
        return FCC_ERR_ARG;
    }
    if (!MAT(same_size)(src, dst)) {
        return FCC_ERR_SIZE;
    }
    if (src->data != dst->data) {
        for (size_t i = 0; i < MAT(count)(src); ++i) {
            dst->data[i] = src->data[i];
        }
    }
    return FCC_OK;
}

/* c = a + sign*b, element-wise; aliasing of c with a or b is fine. */
static fcc_status_t add_signed(const mat_t *a, const mat_t *b, real_t sign,
                               mat_t *c)
{
    if (!MAT(valid)(a) || !MAT(valid)(b) || !MAT(valid)(c)) {
        return FCC_ERR_ARG;
    }
    if (!MAT(same_size)(a, b) || !MAT(same_size)(a, c)) {
        return FCC_ERR_SIZE;
    }
    for (size_t i = 0; i < MAT(count)(a); ++i) {
        c->data[i] = a->data[i] + sign * b->data[i];
    }
    return FCC_OK;
}

fcc_status_t MAT(add)(const mat_t *a, const mat_t *b, mat_t *c)
{
    return add_signed(a, b, RL(1.0), c);
}

fcc_status_t MAT(sub)(const mat_t *a, const mat_t *b, mat_t *c)
{
    return add_signed(a, b, RL(-1.0), c);
}

fcc_status_t MAT(scale)(const mat_t *a, real_t s, mat_t *c)
{
    if (!MAT(valid)(a) || !MAT(valid)(c)) {
        return FCC_ERR_ARG;
    }
    if (!MAT(same_size)(a, c)) {
        return FCC_ERR_SIZE;
    }
    for (size_t i = 0; i < MAT(count)(a); ++i) {
        c->data[i] = s * a->data[i];
    }
    return FCC_OK;
}

fcc_status_t MAT(trans)(const mat_t *a, mat_t *c)
{
    if (!MAT(valid)(a) || !MAT(valid)(c) || a->data == c->data) {
        return FCC_ERR_ARG;
    }
    if (c->rows != a->cols || c->cols != a->rows) {
        return FCC_ERR_SIZE;
    }
    for (uint16_t i = 0; i < a->rows; ++i) {
        for (uint16_t j = 0; j < a->cols; ++j) {
            FCC_MAT_AT(c, j, i) = FCC_MAT_AT(a, i, j);
        }
    }
    return FCC_OK;
}

/*
 * The three products share one kernel: element (i, j) of op(a) op(b) where
 * op is the identity or the transpose, selected by the flags.  Strides make
 * the transposes free (no copy).
 */
static fcc_status_t mul_kernel(const mat_t *a, bool ta, const mat_t *b, bool tb,
                               mat_t *c)
{
    if (!MAT(valid)(a) || !MAT(valid)(b) || !MAT(valid)(c)) {
        return FCC_ERR_ARG;
    }
    if (c->data == a->data || c->data == b->data) {
        return FCC_ERR_ARG;
    }
    const uint16_t m = ta ? a->cols : a->rows;
    const uint16_t k = ta ? a->rows : a->cols;
    const uint16_t kb = tb ? b->cols : b->rows;
    const uint16_t n = tb ? b->rows : b->cols;
    if (k != kb || c->rows != m || c->cols != n) {
        return FCC_ERR_SIZE;
    }
    /* Element (i, p) of op(a) is at a->data[i*ars + p*acs]. */
    const size_t ars = ta ? 1U : a->cols;
    const size_t acs = ta ? a->cols : 1U;
    const size_t brs = tb ? 1U : b->cols;
    const size_t bcs = tb ? b->cols : 1U;
    for (uint16_t i = 0; i < m; ++i) {
        for (uint16_t j = 0; j < n; ++j) {
            real_t sum = RL(0.0);
            for (uint16_t p = 0; p < k; ++p) {
                sum += a->data[i * ars + p * acs] * b->data[p * brs + j * bcs];
            }
            FCC_MAT_AT(c, i, j) = sum;
        }
    }
    return FCC_OK;
}

fcc_status_t MAT(mul)(const mat_t *a, const mat_t *b, mat_t *c)
{
    return mul_kernel(a, false, b, false, c);
}

fcc_status_t MAT(mul_tn)(const mat_t *a, const mat_t *b, mat_t *c)
{
    return mul_kernel(a, true, b, false, c);
}

fcc_status_t MAT(mul_nt)(const mat_t *a, const mat_t *b, mat_t *c)
{
    return mul_kernel(a, false, b, true, c);
}

fcc_status_t MAT(symmetrize)(mat_t *a)
{
    if (!MAT(valid)(a)) {
        return FCC_ERR_ARG;
    }
    if (a->rows != a->cols) {
        return FCC_ERR_SIZE;
    }
    for (uint16_t i = 0; i < a->rows; ++i) {
        for (uint16_t j = (uint16_t)(i + 1U); j < a->cols; ++j) {
            const real_t mean = RL(0.5) * (FCC_MAT_AT(a, i, j) + FCC_MAT_AT(a, j, i));
            FCC_MAT_AT(a, i, j) = mean;
            FCC_MAT_AT(a, j, i) = mean;
        }
    }
    return FCC_OK;
}

fcc_status_t MAT(check_finite)(const mat_t *a)
{
    if (!MAT(valid)(a)) {
        return FCC_ERR_ARG;
    }
    for (size_t i = 0; i < MAT(count)(a); ++i) {
        if (!FCC_IS_FINITE(a->data[i])) {
            return FCC_ERR_NOT_FINITE;
        }
    }
    return FCC_OK;
}

fcc_status_t MAT(get_block)(const mat_t *src, uint16_t r0, uint16_t c0, mat_t *dst)
{
    if (!MAT(valid)(src) || !MAT(valid)(dst) || src->data == dst->data) {
        return FCC_ERR_ARG;
    }
    if ((uint32_t)r0 + dst->rows > src->rows || (uint32_t)c0 + dst->cols > src->cols) {
        return FCC_ERR_SIZE;
    }
    for (uint16_t i = 0; i < dst->rows; ++i) {
        for (uint16_t j = 0; j < dst->cols; ++j) {
            FCC_MAT_AT(dst, i, j) = FCC_MAT_AT(src, r0 + i, c0 + j);
        }
    }
    return FCC_OK;
}

fcc_status_t MAT(set_block)(mat_t *dst, uint16_t r0, uint16_t c0, const mat_t *blk)
{
    if (!MAT(valid)(dst) || !MAT(valid)(blk) || dst->data == blk->data) {
        return FCC_ERR_ARG;
    }
    if ((uint32_t)r0 + blk->rows > dst->rows || (uint32_t)c0 + blk->cols > dst->cols) {
        return FCC_ERR_SIZE;
    }
    for (uint16_t i = 0; i < blk->rows; ++i) {
        for (uint16_t j = 0; j < blk->cols; ++j) {
            FCC_MAT_AT(dst, r0 + i, c0 + j) = FCC_MAT_AT(blk, i, j);
        }
    }
    return FCC_OK;
}

fcc_status_t MAT(norm_1)(const mat_t *a, real_t *out)
{
    if (!MAT(valid)(a) || out == NULL) {
        return FCC_ERR_ARG;
    }
    real_t best = RL(0.0);
    for (uint16_t j = 0; j < a->cols; ++j) {
        real_t sum = RL(0.0);
        for (uint16_t i = 0; i < a->rows; ++i) {
            sum += MFABS(FCC_MAT_AT(a, i, j));
        }
        best = (sum > best) ? sum : best;
    }
    *out = best;
    return FCC_OK;
}

fcc_status_t MAT(norm_inf)(const mat_t *a, real_t *out)
{
    if (!MAT(valid)(a) || out == NULL) {
        return FCC_ERR_ARG;
    }
    real_t best = RL(0.0);
    for (uint16_t i = 0; i < a->rows; ++i) {
        real_t sum = RL(0.0);
        for (uint16_t j = 0; j < a->cols; ++j) {
            sum += MFABS(FCC_MAT_AT(a, i, j));
        }
        best = (sum > best) ? sum : best;
    }
    *out = best;
    return FCC_OK;
}

fcc_status_t MAT(norm_max)(const mat_t *a, real_t *out)
{
    if (!MAT(valid)(a) || out == NULL) {
        return FCC_ERR_ARG;
    }
    real_t best = RL(0.0);
    for (size_t i = 0; i < MAT(count)(a); ++i) {
        const real_t v = MFABS(a->data[i]);
        best = (v > best) ? v : best;
    }
    *out = best;
    return FCC_OK;
}

fcc_status_t MAT(norm_fro)(const mat_t *a, real_t *out)
{
    real_t scale = RL(0.0);
    fcc_status_t st = MAT(norm_max)(a, &scale);
    if (st != FCC_OK) {
        return st;
    }
    if (scale == RL(0.0) || !FCC_IS_FINITE(scale)) {
        *out = scale;
        return FCC_OK;
    }
    /* Scaled sum of squares: no overflow for entries near FCC_REAL_MAX. */
    real_t sum = RL(0.0);
    for (size_t i = 0; i < MAT(count)(a); ++i) {
        const real_t v = a->data[i] / scale;
        sum += v * v;
    }
    *out = scale * MSQRT(sum);
    return FCC_OK;
}

fcc_status_t MAT(rel_diff)(const mat_t *a, const mat_t *b, real_t *out)
{
    if (!MAT(valid)(a) || !MAT(valid)(b) || out == NULL) {
        return FCC_ERR_ARG;
    }
    if (!MAT(same_size)(a, b)) {
        return FCC_ERR_SIZE;
    }
    real_t diff = RL(0.0);
    real_t ref = RL(0.0);
    for (size_t i = 0; i < MAT(count)(a); ++i) {
        const real_t d = MFABS(a->data[i] - b->data[i]);
        const real_t r = MFABS(b->data[i]);
        diff = (d > diff) ? d : diff;
        ref = (r > ref) ? r : ref;
    }
    if (!FCC_IS_FINITE(diff) || !FCC_IS_FINITE(ref)) {
        return FCC_ERR_NOT_FINITE;
    }
    *out = (ref > RL(0.0)) ? diff / ref : diff;
    return FCC_OK;
}
