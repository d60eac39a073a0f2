/*
 * fcc_mat_internal.h -- helpers shared by the fcc_mat_*.c files; not part of
 * the public API (callers include fcc_mat.h only).
 */
#ifndef FCC_MAT_INTERNAL_H
#define FCC_MAT_INTERNAL_H

#include "fcc_mat.h"

/* Non-NULL descriptor with storage and a non-empty shape. */
bool fcc_mat_valid(const fcc_mat_t *m);
bool fcc_mat_same_size(const fcc_mat_t *a, const fcc_mat_t *b);
/* rows * cols */
size_t fcc_mat_count(const fcc_mat_t *m);

/* Valid, square and small enough for the fixed-size workspaces. */
static inline bool fcc_mat_square_fits(const fcc_mat_t *m)
{
    return fcc_mat_valid(m) && m->rows == m->cols && m->rows <= FCC_MAT_MAX_DIM;
}

#endif /* FCC_MAT_INTERNAL_H */
