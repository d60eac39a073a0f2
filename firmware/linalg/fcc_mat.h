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
 * Why these algorithms: the autopilot designs itself on the target for the
 * sampling period it is given (SPEC section 3): Van Loan block exponentials
 * (expm of up to 8x8), two Riccati solvers (eigenvectors of a 6x6 symplectic
 * matrix, and doubling with LU solves), pole checks (eigenvalues), PBH rank
 * tests (singular values).  Sizes are tiny, so clarity and robustness win
 * over blocking and cache tricks; every routine is O(n^3) with n <= 10.
 *
 * Aliasing: unless a function says so, an output must not share storage with
 * an input (the functions check the data pointers and return FCC_ERR_ARG).
 * Element-wise functions (add, sub, scale, copy) allow out == in.
 */
#ifndef FCC_MAT_H
#define FCC_MAT_H

#include "fcc_types.h"

#include <stdbool.h>

/* Largest square size the factorisations, expm and eig accept.  10 covers the
 * 8x8 cost block of the Van Loan discretisation and the realified 2n x 2n PBH
 * test matrices (n = 3 states plus outputs).  Override with -DFCC_MAT_MAX_DIM. */
#ifndef FCC_MAT_MAX_DIM
#define FCC_MAT_MAX_DIM 10
#endif
#define FCC_MAT_MAX_ELEMS (FCC_MAT_MAX_DIM * FCC_MAT_MAX_DIM)

/* A row-major matrix over caller-owned storage: element (i, j) is data[i*cols + j]. */
typedef struct {
    uint16_t rows;
    uint16_t cols;
    fcc_real_t *data;
} fcc_mat_t;

/* Propagate a failure: FCC_TRY(fcc_mat_mul(&a, &b, &c)); returns the status
 * from the enclosing function unless it is FCC_OK. */
#ifndef FCC_TRY
#define FCC_TRY(expr)                                                                             \
    do {                                                                                          \
        const fcc_status_t fcc_try_status_ = (expr);                                              \
        if (fcc_try_status_ != FCC_OK) {                                                          \
            return fcc_try_status_;                                                               \
        }                                                                                         \
    } while (0)
#endif

/* A descriptor by value, for wrapping fixed arrays: fcc_mat_t m = FCC_MAT(3, 3, buf). */
#define FCC_MAT(r, c, d) ((fcc_mat_t){(uint16_t)(r), (uint16_t)(c), (d)})

/* Element access without bounds checks (for code that has already checked sizes). */
#define FCC_MAT_AT(m, i, j) ((m)->data[(size_t)(i) * (m)->cols + (size_t)(j)])

/* ---- Descriptors and element-wise operations (fcc_mat_basic.c) ------------ */

/* Describe rows x cols storage at data (which must hold rows*cols reals). */
fcc_status_t fcc_mat_init(fcc_mat_t *m, uint16_t rows, uint16_t cols, fcc_real_t *data);
fcc_status_t fcc_mat_zero(fcc_mat_t *m);
fcc_status_t fcc_mat_identity(fcc_mat_t *m); /* square only */
fcc_status_t fcc_mat_copy(const fcc_mat_t *src, fcc_mat_t *dst);
fcc_status_t fcc_mat_add(const fcc_mat_t *a, const fcc_mat_t *b, fcc_mat_t *c); /* c = a + b */
fcc_status_t fcc_mat_sub(const fcc_mat_t *a, const fcc_mat_t *b, fcc_mat_t *c); /* c = a - b */
fcc_status_t fcc_mat_scale(const fcc_mat_t *a, fcc_real_t s, fcc_mat_t *c);     /* c = s a */
fcc_status_t fcc_mat_trans(const fcc_mat_t *a, fcc_mat_t *c);                   /* c = a^T */
fcc_status_t fcc_mat_mul(const fcc_mat_t *a, const fcc_mat_t *b, fcc_mat_t *c); /* c = a b */
fcc_status_t fcc_mat_mul_tn(const fcc_mat_t *a, const fcc_mat_t *b, fcc_mat_t *c); /* c = a^T b */
fcc_status_t fcc_mat_mul_nt(const fcc_mat_t *a, const fcc_mat_t *b, fcc_mat_t *c); /* c = a b^T */
/* a <- (a + a^T)/2: removes the rounding asymmetry of covariance products. */
fcc_status_t fcc_mat_symmetrize(fcc_mat_t *a);
/* FCC_OK when every element is finite, FCC_ERR_NOT_FINITE otherwise. */
fcc_status_t fcc_mat_check_finite(const fcc_mat_t *a);
/* Copy the block of src starting at (r0, c0) with dst's size into dst. */
fcc_status_t fcc_mat_get_block(const fcc_mat_t *src, uint16_t r0, uint16_t c0, fcc_mat_t *dst);
/* Write blk into dst starting at (r0, c0). */
fcc_status_t fcc_mat_set_block(fcc_mat_t *dst, uint16_t r0, uint16_t c0, const fcc_mat_t *blk);

/* ---- Norms (fcc_mat_basic.c; the 2-norm is in fcc_mat_svd.c) -------------- */

fcc_status_t fcc_mat_norm_1(const fcc_mat_t *a, fcc_real_t *out);   /* max column sum */
fcc_status_t fcc_mat_norm_inf(const fcc_mat_t *a, fcc_real_t *out); /* max row sum */
fcc_status_t fcc_mat_norm_fro(const fcc_mat_t *a, fcc_real_t *out); /* overflow-safe */
fcc_status_t fcc_mat_norm_max(const fcc_mat_t *a, fcc_real_t *out); /* max |a_ij| */
/* max|a_ij - b_ij| / max|b_ij| (the absolute difference when b is zero): the comparison used to
 * check one solver against another; relative to the matrix's scale, so that
 * a structurally tiny entry is not asked for more digits than the data hold. */
fcc_status_t fcc_mat_rel_diff(const fcc_mat_t *a, const fcc_mat_t *b, fcc_real_t *out);

/* ---- LU with partial pivoting (fcc_mat_lu.c) ------------------------------ */

/* PA = LU of a square matrix; L unit lower and U share lu[]. */
typedef struct {
    fcc_real_t lu[FCC_MAT_MAX_ELEMS];
    uint8_t perm[FCC_MAT_MAX_DIM]; /* row i of PA is row perm[i] of A */
    uint16_t n;
    fcc_real_t norm1; /* ||A||_1, kept for the condition number */
} fcc_mat_lu_t;

/* Factorise.  FCC_ERR_SINGULAR when a pivot is below n*eps*max|a_ij| (singular
 * to working precision); ill-conditioned but non-singular matrices factorise,
 * and fcc_mat_lu_rcond says how far to trust the solution. */
fcc_status_t fcc_mat_lu_factor(fcc_mat_lu_t *lu, const fcc_mat_t *a);
/* Solve A x = b for every column of b (n x k); x may be the same matrix as b. */
fcc_status_t fcc_mat_lu_solve(const fcc_mat_lu_t *lu, const fcc_mat_t *b, fcc_mat_t *x);
/* Solve A^T x = b (for right divisions X = B A^-1, i.e. A^T X^T = B^T). */
fcc_status_t fcc_mat_lu_solve_trans(const fcc_mat_lu_t *lu, const fcc_mat_t *b, fcc_mat_t *x);
/* Reciprocal 1-norm condition number 1/(||A||_1 ||A^-1||_1), computed exactly
 * (n solves; n is small), 0 for a singular matrix. */
fcc_status_t fcc_mat_lu_rcond(const fcc_mat_lu_t *lu, fcc_real_t *rcond);
/* x = a^-1 b and ainv = a^-1 using lu as scratch. */
fcc_status_t fcc_mat_solve(const fcc_mat_t *a, const fcc_mat_t *b, fcc_mat_t *x, fcc_mat_lu_t *lu);
fcc_status_t fcc_mat_inv(const fcc_mat_t *a, fcc_mat_t *ainv, fcc_mat_lu_t *lu);

/* ---- Cholesky (fcc_mat_lu.c) ----------------------------------------------- */

/* a = l l^T with l lower triangular (the upper triangle of l is zeroed); only
 * the lower triangle of a is read.  FCC_ERR_NOT_POSDEF on a pivot that is not
 * clearly positive (<= n*eps*max diag), so semidefinite matrices are refused. */
fcc_status_t fcc_mat_chol(const fcc_mat_t *a, fcc_mat_t *l);
/* Solve l l^T x = b; x may be the same matrix as b. */
fcc_status_t fcc_mat_chol_solve(const fcc_mat_t *l, const fcc_mat_t *b, fcc_mat_t *x);

/* ---- Matrix exponential (fcc_mat_expm.c) ----------------------------------- */

/* Scaling and squaring with a diagonal Pade approximant (Higham 2005): the
 * degree m in {3,5,7,9,13} and the scaling 2^-s are chosen from ||A||_1 so the
 * backward error is below the unit roundoff.  The float build uses Higham's
 * single-precision table (degrees 3, 5, 7), because degree-13 coefficients
 * span 17 decades, more than float resolves. */
typedef struct {
    fcc_real_t a2[FCC_MAT_MAX_ELEMS];
    fcc_real_t a4[FCC_MAT_MAX_ELEMS];
    fcc_real_t a6[FCC_MAT_MAX_ELEMS];
    fcc_real_t u[FCC_MAT_MAX_ELEMS];
    fcc_real_t v[FCC_MAT_MAX_ELEMS];
    fcc_real_t t[FCC_MAT_MAX_ELEMS];
    fcc_mat_lu_t lu;
} fcc_mat_expm_ws_t;

/* e = exp(a).  FCC_ERR_RANGE if ||a||_1 is so large that the result would
 * certainly overflow, FCC_ERR_NOT_FINITE if it did. */
fcc_status_t fcc_mat_expm(const fcc_mat_t *a, fcc_mat_t *e, fcc_mat_expm_ws_t *ws);

/* ---- Nonsymmetric eigenproblem (fcc_mat_eig.c) ----------------------------- */

/* Balancing (diagonal scaling by powers of two) + Householder reduction to
 * Hessenberg form + Francis double-shift QR to real Schur form T = Z^T A Z +
 * back substitution on T for the eigenvectors.  Scratch lives here. */
typedef struct {
    fcc_real_t h[FCC_MAT_MAX_ELEMS];  /* Hessenberg, then Schur form */
    fcc_real_t z[FCC_MAT_MAX_ELEMS];  /* accumulated orthogonal transformations */
    fcc_real_t scale[FCC_MAT_MAX_DIM]; /* balancing D */
} fcc_mat_eig_ws_t;

/*
 * Eigenvalues (wr[i] + j wi[i]) and, when v != NULL, eigenvectors of a square
 * real matrix (n <= FCC_MAT_MAX_DIM).  Complex eigenvalues come in conjugate
 * pairs, the one with positive imaginary part first.  Eigenvector storage
 * follows LAPACK: a real eigenvalue's vector is column i of v; for a pair at
 * (i, i+1) the vector of wr[i] + j wi[i] is v[:,i] + j v[:,i+1] (its conjugate
 * belongs to the second eigenvalue).  Each vector has unit 2-norm and its
 * largest component real.  A defective matrix yields (nearly) parallel
 * vectors, as LAPACK's do; nothing fails.  FCC_ERR_NO_CONVERGENCE if QR does
 * not converge within 30 iterations per eigenvalue.
 */
fcc_status_t fcc_mat_eig(const fcc_mat_t *a, fcc_real_t wr[], fcc_real_t wi[], fcc_mat_t *v,
                         fcc_mat_eig_ws_t *ws);
/* max |lambda_i(a)| */
fcc_status_t fcc_mat_spectral_radius(const fcc_mat_t *a, fcc_real_t *rho, fcc_mat_eig_ws_t *ws);

/* ---- Singular values (fcc_mat_svd.c) --------------------------------------- */

/* One-sided Jacobi (Hestenes): orthogonalises columns by plane rotations, so
 * small singular values are found to full relative accuracy of the data,
 * which a rank test needs (squaring into A^T A would halve the digits). */
typedef struct {
    fcc_real_t w[2 * FCC_MAT_MAX_ELEMS];
} fcc_mat_svd_ws_t;

/* The min(rows, cols) singular values of a, in decreasing order.  Needs
 * min(rows, cols) <= FCC_MAT_MAX_DIM and max(rows, cols) <= 2*FCC_MAT_MAX_DIM
 * (tall stacks such as the PBH test matrix [A - lambda I; C] fit). */
fcc_status_t fcc_mat_svd_values(const fcc_mat_t *a, fcc_real_t s[], fcc_mat_svd_ws_t *ws);
/* Spectral norm ||a||_2 = largest singular value. */
fcc_status_t fcc_mat_norm_2(const fcc_mat_t *a, fcc_real_t *out, fcc_mat_svd_ws_t *ws);

#endif /* FCC_MAT_H */
