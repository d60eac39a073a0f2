/*
 * fcc_mat.h -- the firmware's dense linear algebra, without LAPACK, Eigen or a heap.
 *
 * Model: CMSIS-DSP's matrix API.  A matrix is a small descriptor
 * {rows, cols, data} over storage the CALLER owns (row-major, rows*cols
 * reals); functions never allocate, never keep pointers, and return an
 * fcc_status_t (FCC_OK = 0, negative on error; outputs are unspecified on
 * error unless a function says otherwise).  Algorithms that need scratch
 * space take a workspace struct whose size is fixed at compile time by
 * FCC_MAT_MAX_DIM, so the worst-case RAM of every call is known at link time.
 *
 * Two flavours, one implementation (as CMSIS-DSP has _f32 and _f64):
 *   fcc_mat_t   / fcc_mat_*()    over fcc_real_t (float on the Cortex-M4F):
 *                                what runs every control period;
 *   fcc_mat64_t / fcc_mat64_*()  over double: start-up design work whose
 *                                conditioning needs more than 24 bits (the
 *                                LQG design's Riccati eigenvectors lose up to
 *                                1e-4 relative in single precision at T = 10 ms).
 * fcc_mat_api.h lists the functions once; it is included below for each
 * flavour, so read FCC_MAT_API(mul) as fcc_mat_mul / fcc_mat64_mul and
 * FCC_MAT_REAL as fcc_real_t / double.
 *
 * Why these algorithms: the autopilot designs itself on the target for the
 * sampling period it is given (firmware/lqg): Van Loan block exponentials
 * (expm up to 8x8), two Riccati solvers (eigenvectors of a 6x6 symplectic
 * matrix; doubling with LU solves), pole checks (eigenvalues), PBH rank
 * tests (singular values).  Sizes are tiny, so clarity and robustness win
 * over blocking and cache tricks; every routine is O(n^3) with n <= 10.
 *
 * Aliasing: unless a function says so, an output must not share storage with
 * an input (the functions check the data pointers and return FCC_ERR_ARG).
 * Element-wise functions (add, sub, scale, copy) allow out == in.
 * Non-finite data in an input matrix: FCC_ERR_NOT_FINITE.
 */
#ifndef FCC_MAT_H
#define FCC_MAT_H

#include "fcc_types.h"

#include <stdbool.h>

/* Largest square size the factorisations, expm and eig accept.  10 covers the
 * 8x8 cost block of the Van Loan discretisation and the 2n x 2n symplectic
 * matrix of a Riccati equation with n <= 5.  Override with -DFCC_MAT_MAX_DIM. */
#ifndef FCC_MAT_MAX_DIM
#define FCC_MAT_MAX_DIM 10
#endif
#define FCC_MAT_MAX_ELEMS (FCC_MAT_MAX_DIM * FCC_MAT_MAX_DIM)

/* Element (i, j) of either flavour, without bounds checks (for code that has
 * already checked sizes): data[i*cols + j]. */
#define FCC_MAT_AT(m, i, j) ((m)->data[(size_t)(i) * (m)->cols + (size_t)(j)])

/* ---- the fcc_real_t flavour ------------------------------------------------- */
#define FCC_MAT_API(name) fcc_mat_##name
#define FCC_MAT_REAL fcc_real_t
#include "fcc_mat_api.h"
#undef FCC_MAT_API
#undef FCC_MAT_REAL

/* ---- the double flavour ----------------------------------------------------- */
#define FCC_MAT_API(name) fcc_mat64_##name
#define FCC_MAT_REAL double
#include "fcc_mat_api.h"
#undef FCC_MAT_API
#undef FCC_MAT_REAL

/* A descriptor by value, for wrapping fixed arrays: fcc_mat_t m = FCC_MAT(3, 3, buf). */
#define FCC_MAT(r, c, d) ((fcc_mat_t){(uint16_t)(r), (uint16_t)(c), (d)})
#define FCC_MAT64(r, c, d) ((fcc_mat64_t){(uint16_t)(r), (uint16_t)(c), (d)})

#endif /* FCC_MAT_H */
