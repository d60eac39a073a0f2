/* fcc_mat_basic.c -- descriptors, element-wise operations, products, norms. */
#include "fcc_mat.h"
#include "fcc_mat_internal.h"

bool fcc_mat_valid(const fcc_mat_t *m)
{
    return m != NULL && m->data != NULL && m->rows > 0U && m->cols > 0U;
}

bool fcc_mat_same_size(const fcc_mat_t *a, const fcc_mat_t *b)
{
    return a->rows == b->rows && a->cols == b->cols;
}

size_t fcc_mat_count(const fcc_mat_t *m)
{
    return (size_t)m->rows * (size_t)m->cols;
}

fcc_status_t fcc_mat_init(fcc_mat_t *m, uint16_t rows, uint16_t cols, fcc_real_t *data)
{
    if (m == NULL || data == NULL || rows == 0U || cols == 0U) {
        return FCC_ERR_ARG;
    }
    m->rows = rows;
    m->cols = cols;
    m->data = data;
    return FCC_OK;
}

fcc_status_t fcc_mat_zero(fcc_mat_t *m)
{
    if (!fcc_mat_valid(m)) {
        return FCC_ERR_ARG;
    }
    for (size_t i = 0; i < fcc_mat_count(m); ++i) {
        m->data[i] = FCC_R(0.0);
    }
    return FCC_OK;
}

fcc_status_t fcc_mat_identity(fcc_mat_t *m)
{
    if (!fcc_mat_valid(m)) {
        return FCC_ERR_ARG;
    }
    if (m->rows != m->cols) {
        return FCC_ERR_SIZE;
    }
    (void)fcc_mat_zero(m);
    for (uint16_t i = 0; i < m->rows; ++i) {
        FCC_MAT_AT(m, i, i) = FCC_R(1.0);
    }
    return FCC_OK;
}

fcc_status_t fcc_mat_copy(const fcc_mat_t *src, fcc_mat_t *dst)
{
    if (!fcc_mat_valid(src) || !fcc_mat_valid(dst)) {
        return FCC_ERR_ARG;
    }
    if (!fcc_mat_same_size(src, dst)) {
        return FCC_ERR_SIZE;
    }
    if (src->data != dst->data) {
        for (size_t i = 0; i < fcc_mat_count(src); ++i) {
            dst->data[i] = src->data[i];
        }
    }
    return FCC_OK;
}

/* c = a + sign*b, element-wise; aliasing of c with a or b is fine. */
static fcc_status_t add_signed(const fcc_mat_t *a, const fcc_mat_t *b, fcc_real_t sign,
                               fcc_mat_t *c)
{
    if (!fcc_mat_valid(a) || !fcc_mat_valid(b) || !fcc_mat_valid(c)) {
        return FCC_ERR_ARG;
    }
    if (!fcc_mat_same_size(a, b) || !fcc_mat_same_size(a, c)) {
        return FCC_ERR_SIZE;
    }
    for (size_t i = 0; i < fcc_mat_count(a); ++i) {
        c->data[i] = a->data[i] + sign * b->data[i];
    }
    return FCC_OK;
}

fcc_status_t fcc_mat_add(const fcc_mat_t *a, const fcc_mat_t *b, fcc_mat_t *c)
{
    return add_signed(a, b, FCC_R(1.0), c);
}

fcc_status_t fcc_mat_sub(const fcc_mat_t *a, const fcc_mat_t *b, fcc_mat_t *c)
{
    return add_signed(a, b, FCC_R(-1.0), c);
}

fcc_status_t fcc_mat_scale(const fcc_mat_t *a, fcc_real_t s, fcc_mat_t *c)
{
    if (!fcc_mat_valid(a) || !fcc_mat_valid(c)) {
        return FCC_ERR_ARG;
    }
    if (!fcc_mat_same_size(a, c)) {
        return FCC_ERR_SIZE;
    }
    for (size_t i = 0; i < fcc_mat_count(a); ++i) {
        c->data[i] = s * a->data[i];
    }
    return FCC_OK;
}

fcc_status_t fcc_mat_trans(const fcc_mat_t *a, fcc_mat_t *c)
{
    if (!fcc_mat_valid(a) || !fcc_mat_valid(c) || a->data == c->data) {
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
static fcc_status_t mul_kernel(const fcc_mat_t *a, bool ta, const fcc_mat_t *b, bool tb,
                               fcc_mat_t *c)
{
    if (!fcc_mat_valid(a) || !fcc_mat_valid(b) || !fcc_mat_valid(c)) {
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
            fcc_real_t sum = FCC_R(0.0);
            for (uint16_t p = 0; p < k; ++p) {
                sum += a->data[i * ars + p * acs] * b->data[p * brs + j * bcs];
            }
            FCC_MAT_AT(c, i, j) = sum;
        }
    }
    return FCC_OK;
}

fcc_status_t fcc_mat_mul(const fcc_mat_t *a, const fcc_mat_t *b, fcc_mat_t *c)
{
    return mul_kernel(a, false, b, false, c);
}

fcc_status_t fcc_mat_mul_tn(const fcc_mat_t *a, const fcc_mat_t *b, fcc_mat_t *c)
{
    return mul_kernel(a, true, b, false, c);
}

fcc_status_t fcc_mat_mul_nt(const fcc_mat_t *a, const fcc_mat_t *b, fcc_mat_t *c)
{
    return mul_kernel(a, false, b, true, c);
}

fcc_status_t fcc_mat_symmetrize(fcc_mat_t *a)
{
    if (!fcc_mat_valid(a)) {
        return FCC_ERR_ARG;
    }
    if (a->rows != a->cols) {
        return FCC_ERR_SIZE;
    }
    for (uint16_t i = 0; i < a->rows; ++i) {
        for (uint16_t j = (uint16_t)(i + 1U); j < a->cols; ++j) {
            const fcc_real_t mean = FCC_R(0.5) * (FCC_MAT_AT(a, i, j) + FCC_MAT_AT(a, j, i));
            FCC_MAT_AT(a, i, j) = mean;
            FCC_MAT_AT(a, j, i) = mean;
        }
    }
    return FCC_OK;
}

fcc_status_t fcc_mat_check_finite(const fcc_mat_t *a)
{
    if (!fcc_mat_valid(a)) {
        return FCC_ERR_ARG;
    }
    for (size_t i = 0; i < fcc_mat_count(a); ++i) {
        if (!FCC_IS_FINITE(a->data[i])) {
            return FCC_ERR_NOT_FINITE;
        }
    }
    return FCC_OK;
}

fcc_status_t fcc_mat_get_block(const fcc_mat_t *src, uint16_t r0, uint16_t c0, fcc_mat_t *dst)
{
    if (!fcc_mat_valid(src) || !fcc_mat_valid(dst) || src->data == dst->data) {
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

fcc_status_t fcc_mat_set_block(fcc_mat_t *dst, uint16_t r0, uint16_t c0, const fcc_mat_t *blk)
{
    if (!fcc_mat_valid(dst) || !fcc_mat_valid(blk) || dst->data == blk->data) {
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

fcc_status_t fcc_mat_norm_1(const fcc_mat_t *a, fcc_real_t *out)
{
    if (!fcc_mat_valid(a) || out == NULL) {
        return FCC_ERR_ARG;
    }
    fcc_real_t best = FCC_R(0.0);
    for (uint16_t j = 0; j < a->cols; ++j) {
        fcc_real_t sum = FCC_R(0.0);
        for (uint16_t i = 0; i < a->rows; ++i) {
            sum += FCC_FABS(FCC_MAT_AT(a, i, j));
        }
        best = (sum > best) ? sum : best;
    }
    *out = best;
    return FCC_OK;
}

fcc_status_t fcc_mat_norm_inf(const fcc_mat_t *a, fcc_real_t *out)
{
    if (!fcc_mat_valid(a) || out == NULL) {
        return FCC_ERR_ARG;
    }
    fcc_real_t best = FCC_R(0.0);
    for (uint16_t i = 0; i < a->rows; ++i) {
        fcc_real_t sum = FCC_R(0.0);
        for (uint16_t j = 0; j < a->cols; ++j) {
            sum += FCC_FABS(FCC_MAT_AT(a, i, j));
        }
        best = (sum > best) ? sum : best;
    }
    *out = best;
    return FCC_OK;
}

fcc_status_t fcc_mat_norm_max(const fcc_mat_t *a, fcc_real_t *out)
{
    if (!fcc_mat_valid(a) || out == NULL) {
        return FCC_ERR_ARG;
    }
    fcc_real_t best = FCC_R(0.0);
    for (size_t i = 0; i < fcc_mat_count(a); ++i) {
        const fcc_real_t v = FCC_FABS(a->data[i]);
        best = (v > best) ? v : best;
    }
    *out = best;
    return FCC_OK;
}

fcc_status_t fcc_mat_norm_fro(const fcc_mat_t *a, fcc_real_t *out)
{
    fcc_real_t scale = FCC_R(0.0);
    fcc_status_t st = fcc_mat_norm_max(a, &scale);
    if (st != FCC_OK) {
        return st;
    }
    if (scale == FCC_R(0.0) || !FCC_IS_FINITE(scale)) {
        *out = scale;
        return FCC_OK;
    }
    /* Scaled sum of squares: no overflow for entries near FCC_REAL_MAX. */
    fcc_real_t sum = FCC_R(0.0);
    for (size_t i = 0; i < fcc_mat_count(a); ++i) {
        const fcc_real_t v = a->data[i] / scale;
        sum += v * v;
    }
    *out = scale * FCC_SQRT(sum);
    return FCC_OK;
}

fcc_status_t fcc_mat_rel_diff(const fcc_mat_t *a, const fcc_mat_t *b, fcc_real_t *out)
{
    if (!fcc_mat_valid(a) || !fcc_mat_valid(b) || out == NULL) {
        return FCC_ERR_ARG;
    }
    if (!fcc_mat_same_size(a, b)) {
        return FCC_ERR_SIZE;
    }
    fcc_real_t diff = FCC_R(0.0);
    fcc_real_t ref = FCC_R(0.0);
    for (size_t i = 0; i < fcc_mat_count(a); ++i) {
        const fcc_real_t d = FCC_FABS(a->data[i] - b->data[i]);
        const fcc_real_t r = FCC_FABS(b->data[i]);
        diff = (d > diff) ? d : diff;
        ref = (r > ref) ? r : ref;
    }
    if (!FCC_IS_FINITE(diff) || !FCC_IS_FINITE(ref)) {
        return FCC_ERR_NOT_FINITE;
    }
    *out = (ref > FCC_R(0.0)) ? diff / ref : diff;
    return FCC_OK;
}
