#include "fcc_zonotope.h"

#include <string.h>

void fcc_zono_norms(const fcc_real_t *r, uint16_t p, fcc_real_t *norm2)
{
    for (uint16_t j = 0; j < p; ++j) {
        const fcc_real_t a = r[2u * j];
        const fcc_real_t b = r[2u * j + 1u];
        norm2[j] = a * a + b * b;
    }
}

/* Stable ranking of eq. (17): column i ranks above column j when it is
 * longer, or as long and earlier. */
static bool ranks_above(const fcc_real_t *norm2, uint16_t i, uint16_t j)
{
    return norm2[i] > norm2[j] || (norm2[i] == norm2[j] && i < j);
}

/* A binary heap of column indices whose root is the column that leaves
 * first: for the top-k search the lowest-ranked candidate, for the
 * bottom-b search the highest-ranked one.  closer(a, b): a belongs nearer
 * the root than b. */
typedef struct {
    uint16_t *idx;
    uint16_t size;
    const fcc_real_t *norm2;
    bool root_is_lowest;
} sel_heap_t;

static bool closer(const sel_heap_t *h, uint16_t a, uint16_t b)
{
    return h->root_is_lowest ? ranks_above(h->norm2, b, a) : ranks_above(h->norm2, a, b);
}

static void heap_push(sel_heap_t *h, uint16_t col)
{
    uint16_t i = h->size++;
    while (i > 0u) {
        const uint16_t parent = (uint16_t)((i - 1u) / 2u);
        if (!closer(h, col, h->idx[parent])) {
            break;
        }
        h->idx[i] = h->idx[parent];
        i = parent;
    }
    h->idx[i] = col;
}

static void heap_replace_root(sel_heap_t *h, uint16_t col)
{
    uint16_t i = 0u;
    for (;;) {
        const uint32_t left = 2u * (uint32_t)i + 1u;
        if (left >= h->size) {
            break;
        }
        uint16_t child = (uint16_t)left;
        if (left + 1u < h->size && closer(h, h->idx[left + 1u], h->idx[left])) {
            child = (uint16_t)(left + 1u);
        }
        if (!closer(h, h->idx[child], col)) {
            break;
        }
        h->idx[i] = h->idx[child];
        i = child;
    }
    h->idx[i] = col;
}

/* Fills the heap with the `count` columns that are extreme in the ranking:
 * the highest-ranked when root_is_lowest, else the lowest-ranked. */
static void heap_select(sel_heap_t *h, uint16_t p, uint16_t count)
{
    for (uint16_t j = 0; j < p; ++j) {
        if (h->size < count) {
            heap_push(h, j);
        } else if (closer(h, h->idx[0], j)) {
            heap_replace_root(h, j);
        }
    }
}

fcc_status_t fcc_zono_select(const fcc_real_t *norm2, uint16_t p, uint16_t q,
                             fcc_zono_work_t *work)
{
    if (norm2 == NULL || work == NULL || q < FCC_ZONO_MIN_ORDER) {
        return FCC_ERR_ARG;
    }
    if (q > FCC_ZONO_MAX_ORDER) {
        return FCC_ERR_RANGE;
    }
    if (p > FCC_ZONO_MAX_COLS) {
        return FCC_ERR_SIZE;
    }
    if (p <= q) {
        memset(work->boxed, 0, p);
        return FCC_OK;
    }
    const uint16_t keep = (uint16_t)(q - FCC_ZONO_MIN_ORDER);
    const uint16_t box = (uint16_t)(p - keep);
    sel_heap_t h = {work->heap, 0u, norm2, true};
    if (keep <= box) {
        /* Find the `keep` longest columns; every other one is boxed. */
        memset(work->boxed, 1, p);
        heap_select(&h, p, keep);
        for (uint16_t i = 0; i < h.size; ++i) {
            work->boxed[h.idx[i]] = 0u;
        }
    } else {
        /* Fewer to box than to keep: find the `box` shortest columns. */
        memset(work->boxed, 0, p);
        h.root_is_lowest = false;
        heap_select(&h, p, box);
        for (uint16_t i = 0; i < h.size; ++i) {
            work->boxed[h.idx[i]] = 1u;
        }
    }
    return FCC_OK;
}

fcc_status_t fcc_zono_reduce(fcc_real_t *r, fcc_real_t *norm2, uint16_t *p, uint16_t q,
                             fcc_zono_work_t *work)
{
    if (r == NULL || p == NULL) {
        return FCC_ERR_ARG;
    }
    const fcc_status_t st = fcc_zono_select(norm2, *p, q, work);
    if (st != FCC_OK || *p <= q) {
        return st;
    }
    fcc_real_t box0 = FCC_R(0.0);
    fcc_real_t box1 = FCC_R(0.0);
    uint16_t w = 0u;
    for (uint16_t j = 0; j < *p; ++j) {
        const fcc_real_t a = r[2u * j];
        const fcc_real_t b = r[2u * j + 1u];
        if (work->boxed[j] != 0u) {
            box0 += FCC_FABS(a);
            box1 += FCC_FABS(b);
        } else {
            r[2u * w] = a;
            r[2u * w + 1u] = b;
            norm2[w] = norm2[j];
            ++w;
        }
    }
    r[2u * w] = box0;
    r[2u * w + 1u] = FCC_R(0.0);
    norm2[w] = box0 * box0;
    ++w;
    r[2u * w] = FCC_R(0.0);
    r[2u * w + 1u] = box1;
    norm2[w] = box1 * box1;
    ++w;
    *p = w;
    return FCC_OK;
}

void fcc_zono_hull(const fcc_real_t *r, uint16_t p, fcc_real_t hull[2])
{
    fcc_real_t h0 = FCC_R(0.0);
    fcc_real_t h1 = FCC_R(0.0);
    for (uint16_t j = 0; j < p; ++j) {
        h0 += FCC_FABS(r[2u * j]);
        h1 += FCC_FABS(r[2u * j + 1u]);
    }
    hull[0] = h0;
    hull[1] = h1;
}

void fcc_zono_covariation(const fcc_real_t *r, uint16_t p, fcc_real_t m[4])
{
    fcc_real_t m00 = FCC_R(0.0);
    fcc_real_t m01 = FCC_R(0.0);
    fcc_real_t m11 = FCC_R(0.0);
    for (uint16_t j = 0; j < p; ++j) {
        const fcc_real_t a = r[2u * j];
        const fcc_real_t b = r[2u * j + 1u];
        m00 += a * a;
        m01 += a * b;
        m11 += b * b;
    }
    m[0] = m00;
    m[1] = m01;
    m[2] = m01;
    m[3] = m11;
}

fcc_real_t fcc_zono_size(const fcc_real_t *r, uint16_t p)
{
    fcc_real_t m[4];
    fcc_zono_covariation(r, p, m);
    return FCC_SQRT(m[0] + m[3]);
}

fcc_real_t fcc_zono_support(const fcc_real_t c[2], const fcc_real_t *r, uint16_t p,
                            const fcc_real_t d[2])
{
    fcc_real_t h = d[0] * c[0] + d[1] * c[1];
    for (uint16_t j = 0; j < p; ++j) {
        h += FCC_FABS(d[0] * r[2u * j] + d[1] * r[2u * j + 1u]);
    }
    return h;
}

bool fcc_zono_contains(const fcc_real_t c[2], const fcc_real_t *r, uint16_t p,
                       const fcc_real_t point[2], fcc_real_t tol)
{
    /* A 2-D zonotope is the intersection of the slabs |d^T (x - c)| <= h(d)
     * with d normal to each generator (plus the axes, which cover the
     * degenerate case of parallel or zero generators). */
    const fcc_real_t dx = point[0] - c[0];
    const fcc_real_t dy = point[1] - c[1];
    const fcc_real_t zero[2] = {FCC_R(0.0), FCC_R(0.0)};
    for (uint32_t j = 0; j < (uint32_t)p + 2u; ++j) {
        fcc_real_t d[2];
        if (j < p) {
            d[0] = -r[2u * j + 1u];
            d[1] = r[2u * j];
        } else {
            d[0] = j == p ? FCC_R(1.0) : FCC_R(0.0);
            d[1] = j == p ? FCC_R(0.0) : FCC_R(1.0);
        }
        const fcc_real_t scale = FCC_FABS(d[0]) + FCC_FABS(d[1]);
        if (scale == FCC_R(0.0)) {
            continue;
        }
        const fcc_real_t proj = FCC_FABS(d[0] * dx + d[1] * dy);
        if (proj > fcc_zono_support(zero, r, p, d) + tol * scale) {
            return false;
        }
    }
    return true;
}
