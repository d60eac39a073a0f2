#include "fcc_zonotope.h"

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
    uint16_t *idx; /* heap storage */
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
 * the highest-ranked when root_is_lowest, else the lowest-ranked.  After the
 * heap is full, a column can only enter by beating the root, so the scan
 * compares with the root's norm kept in a register: since every later
 * column has a larger index, a tie ranks it below the root (stable). */
static void heap_select(sel_heap_t *h, uint16_t p, uint16_t count)
{
    uint16_t j = 0u;
    for (; j < p && h->size < count; ++j) {
        heap_push(h, j);
    }
    if (count == 0u) {
        return;
    }
    const fcc_real_t *norm2 = h->norm2;
    fcc_real_t root = norm2[h->idx[0]];
    if (h->root_is_lowest) {
        for (; j < p; ++j) {
            if (norm2[j] > root) { /* longer: ranks above the weakest kept */
                heap_replace_root(h, j);
                root = norm2[h->idx[0]];
            }
        }
    } else {
        /* The common case (a few shortest columns among many, every ZKF step
         * at a large order): test four columns at once, without branches. */
        for (; j + 4u <= p; j += 4u) {
            const int any = (norm2[j] <= root) | (norm2[j + 1u] <= root) |
                            (norm2[j + 2u] <= root) | (norm2[j + 3u] <= root);
            if (!any) {
                continue;
            }
            for (uint16_t k = j; k < j + 4u; ++k) {
                if (norm2[k] <= root) { /* not longer, and later: ranks below */
                    heap_replace_root(h, k);
                    root = norm2[h->idx[0]];
                }
            }
        }
        for (; j < p; ++j) {
            if (norm2[j] <= root) {
                heap_replace_root(h, j);
                root = norm2[h->idx[0]];
            }
        }
    }
}

/* Sorts n indices ascending in place (heapsort: O(n log n), no recursion,
 * no extra storage). */
static void sift_down_u16(uint16_t *v, uint32_t root, uint32_t n)
{
    const uint16_t x = v[root];
    for (;;) {
        uint32_t child = 2u * root + 1u;
        if (child >= n) {
            break;
        }
        if (child + 1u < n && v[child + 1u] > v[child]) {
            ++child;
        }
        if (v[child] <= x) {
            break;
        }
        v[root] = v[child];
        root = child;
    }
    v[root] = x;
}

static void sort_u16(uint16_t *v, uint32_t n)
{
    for (uint32_t i = n / 2u; i-- > 0u;) {
        sift_down_u16(v, i, n);
    }
    for (uint32_t end = n; end > 1u; --end) {
        const uint16_t top = v[0];
        v[0] = v[end - 1u];
        v[end - 1u] = top;
        sift_down_u16(v, 0u, end - 1u);
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
    work->n_list = 0u;
    work->list_is_boxed = true;
    if (p <= q) {
        return FCC_OK; /* nothing boxed */
    }
    const uint16_t keep = (uint16_t)(q - FCC_ZONO_MIN_ORDER);
    const uint16_t box = (uint16_t)(p - keep);
    sel_heap_t h = {work->list, 0u, norm2, true};
    if (keep <= box) {
        heap_select(&h, p, keep); /* the `keep` longest columns */
        work->list_is_boxed = false;
    } else {
        h.root_is_lowest = false;
        heap_select(&h, p, box); /* the `box` shortest columns */
    }
    work->n_list = h.size;
    sort_u16(work->list, work->n_list);
    return FCC_OK;
}

bool fcc_zono_is_boxed(const fcc_zono_work_t *work, uint16_t j)
{
    uint32_t lo = 0u;
    uint32_t hi = work->n_list;
    while (lo < hi) {
        const uint32_t mid = (lo + hi) / 2u;
        if (work->list[mid] < j) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    const bool listed = lo < work->n_list && work->list[lo] == j;
    return listed == work->list_is_boxed;
}

/* Moves columns [from, to) of r down to slot *w (w <= from). */
static void move_run(fcc_real_t *r, fcc_real_t *norm2, uint32_t from, uint32_t to, uint32_t *w)
{
    for (uint32_t j = from; j < to; ++j, ++*w) {
        r[2u * *w] = r[2u * j];
        r[2u * *w + 1u] = r[2u * j + 1u];
        norm2[*w] = norm2[j];
    }
}

/* Adds |columns [from, to)| to the box radii. */
static void box_run(const fcc_real_t *r, uint32_t from, uint32_t to, fcc_real_t box[2])
{
    for (uint32_t j = from; j < to; ++j) {
        box[0] += FCC_FABS(r[2u * j]);
        box[1] += FCC_FABS(r[2u * j + 1u]);
    }
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
    fcc_real_t box[2] = {FCC_R(0.0), FCC_R(0.0)};
    uint32_t w = 0u;
    uint32_t next = 0u; /* first column not yet handled */
    for (uint16_t i = 0; i < work->n_list; ++i) {
        const uint32_t j = work->list[i];
        if (work->list_is_boxed) {
            move_run(r, norm2, next, j, &w);
            box_run(r, j, j + 1u, box);
        } else {
            box_run(r, next, j, box);
            move_run(r, norm2, j, j + 1u, &w);
        }
        next = j + 1u;
    }
    if (work->list_is_boxed) {
        move_run(r, norm2, next, *p, &w);
    } else {
        box_run(r, next, *p, box);
    }
    r[2u * w] = box[0];
    r[2u * w + 1u] = FCC_R(0.0);
    norm2[w] = box[0] * box[0];
    ++w;
    r[2u * w] = FCC_R(0.0);
    r[2u * w + 1u] = box[1];
    norm2[w] = box[1] * box[1];
    ++w;
    *p = (uint16_t)w;
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
