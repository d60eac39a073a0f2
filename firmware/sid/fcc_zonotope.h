/*
 * fcc_zonotope.h -- 2-D zonotopes <c, R> = {c + R s : |s|_inf <= 1} and the
 * reduction operator of order q (Gim et al. 2022, eqs. 15-18).
 *
 * A generator matrix R is 2 x p, stored column-major: column j is
 * (r[2j], r[2j+1]).  The largest number of columns is a compile-time bound
 * so that every array is static: FCC_ZONO_MAX_ORDER (the largest order q
 * any filter may use, default 1000 = the paper's q) plus the 4 columns one
 * ZKF step appends (E and -G F).  Override with -DFCC_ZONO_MAX_ORDER=...
 *
 * Reduction (eqs. 17-18), for p > q:
 *   rank the columns by decreasing 2-norm, ties kept in their original
 *   order (a stable sort: results are reproducible bit for bit);
 *   keep the first q - n and replace the rest by diag(|R_rest| 1), their
 *   interval hull, which contains them.  The result has exactly q columns.
 * p <= q leaves R unchanged.  Only the SET of kept columns matters to the
 * zonotope, so the kept columns stay in their original relative order and
 * the n = 2 box columns are appended last; this avoids moving columns
 * into sorted order and keeps the operator O(p log(min(q - n, p - q + n))).
 * Columns are compared by squared norm (the order of eq. 17 uses |r|^2).
 */
#ifndef FCC_ZONOTOPE_H
#define FCC_ZONOTOPE_H

#include <stdbool.h>
#include <stdint.h>

#include "fcc_types.h"

#ifndef FCC_ZONO_MAX_ORDER
#define FCC_ZONO_MAX_ORDER 1000u
#endif

/* Columns appended by one ZKF step (eq. 24): E (2) and -G F (2). */
#define FCC_ZONO_STEP_COLS 4u
#define FCC_ZONO_MAX_COLS (FCC_ZONO_MAX_ORDER + FCC_ZONO_STEP_COLS)

/* Smallest order: n = 2 (the reduced set is then the interval hull box). */
#define FCC_ZONO_MIN_ORDER 2u

/* The result of a selection (caller-owned scratch, static storage): the
 * smaller of the two sets, boxed or kept columns, as ascending column
 * indices.  Every column not listed belongs to the other set.  Listing the
 * smaller set keeps every later pass O(p) with no per-column flag, and the
 * covariation update O(min(kept, boxed)). */
typedef struct {
    uint16_t list[FCC_ZONO_MAX_COLS / 2u + 1u];
    uint16_t n_list;
    bool list_is_boxed; /* true: list = boxed columns; false: list = kept columns */
} fcc_zono_work_t;

/* norm2[j] = |r_j|^2 for the p columns of r. */
void fcc_zono_norms(const fcc_real_t *r, uint16_t p, fcc_real_t *norm2);

/* Selects the columns that the reduction of order q boxes (exactly
 * p - q + 2 of them, the lowest in the stable ranking; none when p <= q)
 * into work.  FCC_ERR_ARG on NULL or q < 2, FCC_ERR_RANGE when
 * q > FCC_ZONO_MAX_ORDER, FCC_ERR_SIZE when p > FCC_ZONO_MAX_COLS. */
fcc_status_t fcc_zono_select(const fcc_real_t *norm2, uint16_t p, uint16_t q,
                             fcc_zono_work_t *work);

/* True when the last selection boxes column j (binary search: for tests
 * and diagnostics, not for loops). */
bool fcc_zono_is_boxed(const fcc_zono_work_t *work, uint16_t j);

/* In-place reduction R <- reduce_q(R) (eq. 18): *p becomes min(p, q).
 * norm2 must hold the squared column norms of R on entry; it is updated to
 * the columns of the result.  Errors as fcc_zono_select (R untouched). */
fcc_status_t fcc_zono_reduce(fcc_real_t *r, fcc_real_t *norm2, uint16_t *p, uint16_t q,
                             fcc_zono_work_t *work);

/* Interval hull radius: hull[i] = sum_j |r_ij| (the box <c, diag(hull)>
 * is the smallest axis-aligned box containing the zonotope). */
void fcc_zono_hull(const fcc_real_t *r, uint16_t p, fcc_real_t hull[2]);

/* Covariation R R^T (row-major 2x2). */
void fcc_zono_covariation(const fcc_real_t *r, uint16_t p, fcc_real_t m[4]);

/* Size J_R = sqrt(tr(R R^T)) (eq. 16). */
fcc_real_t fcc_zono_size(const fcc_real_t *r, uint16_t p);

/* True when point lies in <c, R> (exact for 2-D zonotopes: the facets are
 * normal to the generators, so the support function is checked along each
 * generator's normal).  tol is an absolute slack for rounding. */
bool fcc_zono_contains(const fcc_real_t c[2], const fcc_real_t *r, uint16_t p,
                       const fcc_real_t point[2], fcc_real_t tol);

/* Support function h(d) = d^T c + sum_j |d^T r_j|: the reduced set
 * contains the original iff its support function is >= in every direction. */
fcc_real_t fcc_zono_support(const fcc_real_t c[2], const fcc_real_t *r, uint16_t p,
                            const fcc_real_t d[2]);

#endif /* FCC_ZONOTOPE_H */
