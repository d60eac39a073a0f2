/*
 * fcc_mat_impl.h -- private to the fcc_mat_*.c files: one source, two flavours.
 *
 * Each fcc_mat_<part>.c is written once against the names below and compiled
 * twice: as itself (the fcc_real_t flavour, fcc_mat_*) and through
 * fcc_mat64_<part>.c, which defines FCC_MAT_F64 first (the double flavour,
 * fcc_mat64_*).  Read MAT(mul) as fcc_mat_mul / fcc_mat64_mul, real_t as the
 * element type, RL(0.5) as a literal of that type, MSQRT etc. as its maths.
 */
#ifndef FCC_MAT_IMPL_H
#define FCC_MAT_IMPL_H

#include "fcc_mat.h"

#include <float.h>

#ifdef FCC_MAT_F64
typedef double real_t;
typedef fcc_mat64_t mat_t;
typedef fcc_mat64_lu_t lu_t;
typedef fcc_mat64_expm_ws_t expm_ws_t;
typedef fcc_mat64_eig_ws_t eig_ws_t;
typedef fcc_mat64_svd_ws_t svd_ws_t;
#define MAT(name) fcc_mat64_##name
#define MAT_DESC(r, c, d) FCC_MAT64(r, c, d)
#define MAT_SINGLE 0
#else
typedef fcc_real_t real_t;
typedef fcc_mat_t mat_t;
typedef fcc_mat_lu_t lu_t;
typedef fcc_mat_expm_ws_t expm_ws_t;
typedef fcc_mat_eig_ws_t eig_ws_t;
typedef fcc_mat_svd_ws_t svd_ws_t;
#define MAT(name) fcc_mat_##name
#define MAT_DESC(r, c, d) FCC_MAT(r, c, d)
#ifdef FCC_REAL_FLOAT
#define MAT_SINGLE 1
#else
#define MAT_SINGLE 0
#endif
#endif

#if MAT_SINGLE
#define RL(x) (x##f)
#define MSQRT sqrtf
#define MFABS fabsf
#define MHYPOT hypotf
#define MCOPYSIGN copysignf
#define MFREXP frexpf
#define MLDEXP ldexpf
#define MEPS FLT_EPSILON
#else
#define RL(x) (x)
#define MSQRT sqrt
#define MFABS fabs
#define MHYPOT hypot
#define MCOPYSIGN copysign
#define MFREXP frexp
#define MLDEXP ldexp
#define MEPS DBL_EPSILON
#endif

/* Helpers shared by the part files (not public API). */
bool MAT(valid)(const mat_t *m); /* non-NULL, storage, non-empty shape */
bool MAT(same_size)(const mat_t *a, const mat_t *b);
size_t MAT(count)(const mat_t *m); /* rows * cols */

#endif /* FCC_MAT_IMPL_H */
