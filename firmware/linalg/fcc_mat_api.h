/*
 * fcc_mat_api.h -- the function list of fcc_mat.h, written once for both
 * flavours.  Include fcc_mat.h, never this file: it is included there twice,
 * with FCC_MAT_API(x) = fcc_mat_x / fcc_mat64_x and FCC_MAT_REAL = fcc_real_t
 * / double (hence no include guard).
 */
#if !defined(FCC_MAT_API) || !defined(FCC_MAT_REAL)
#error "include fcc_mat.h, not fcc_mat_api.h"
#endif

/* A row-major matrix over caller-owned storage: element (i, j) is data[i*cols + j]. */
typedef struct {
    uint16_t rows;
    uint16_t cols;
    FCC_MAT_REAL *data;
} FCC_MAT_API(t);

/* ---- Descriptors and element-wise operations (fcc_mat_basic.c) ------------ */

/* Describe rows x cols storage at data (which must hold rows*cols reals). */
fcc_status_t FCC_MAT_API(init)(FCC_MAT_API(t) *m, uint16_t rows, uint16_t cols, FCC_MAT_REAL *data);
fcc_status_t FCC_MAT_API(zero)(FCC_MAT_API(t) *m);
fcc_status_t FCC_MAT_API(identity)(FCC_MAT_API(t) *m); /* square only */
fcc_status_t FCC_MAT_API(copy)(const FCC_MAT_API(t) *src, FCC_MAT_API(t) *dst);
/* c = a + b, c = a - b, c = s a, c = a^T */
fcc_status_t FCC_MAT_API(add)(const FCC_MAT_API(t) *a, const FCC_MAT_API(t) *b, FCC_MAT_API(t) *c);
fcc_status_t FCC_MAT_API(sub)(const FCC_MAT_API(t) *a, const FCC_MAT_API(t) *b, FCC_MAT_API(t) *c);
fcc_status_t FCC_MAT_API(scale)(const FCC_MAT_API(t) *a, FCC_MAT_REAL s, FCC_MAT_API(t) *c);
fcc_status_t FCC_MAT_API(trans)(const FCC_MAT_API(t) *a, FCC_MAT_API(t) *c);
/* c = a b, c = a^T b, c = a b^T (transposes are free: strides, no copy) */
fcc_status_t FCC_MAT_API(mul)(const FCC_MAT_API(t) *a, const FCC_MAT_API(t) *b, FCC_MAT_API(t) *c);
fcc_status_t FCC_MAT_API(mul_tn)(const FCC_MAT_API(t) *a, const FCC_MAT_API(t) *b, FCC_MAT_API(t) *c);
fcc_status_t FCC_MAT_API(mul_nt)(const FCC_MAT_API(t) *a, const FCC_MAT_API(t) *b, FCC_MAT_API(t) *c);
/* a <- (a + a^T)/2: removes the rounding asymmetry of covariance products. */
fcc_status_t FCC_MAT_API(symmetrize)(FCC_MAT_API(t) *a);
/* FCC_OK when every element is finite, FCC_ERR_NOT_FINITE otherwise. */
fcc_status_t FCC_MAT_API(check_finite)(const FCC_MAT_API(t) *a);
/* Copy the block of src starting at (r0, c0) with dst's size into dst. */
fcc_status_t FCC_MAT_API(get_block)(const FCC_MAT_API(t) *src, uint16_t r0, uint16_t c0,
                                    FCC_MAT_API(t) *dst);
/* Write blk into dst starting at (r0, c0). */
fcc_status_t FCC_MAT_API(set_block)(FCC_MAT_API(t) *dst, uint16_t r0, uint16_t c0,
                                    const FCC_MAT_API(t) *blk);

/* ---- Norms (fcc_mat_basic.c; the 2-norm is in fcc_mat_svd.c) -------------- */

fcc_status_t FCC_MAT_API(norm_1)(const FCC_MAT_API(t) *a, FCC_MAT_REAL *out);   /* max column sum */
fcc_status_t FCC_MAT_API(norm_inf)(const FCC_MAT_API(t) *a, FCC_MAT_REAL *out); /* max row sum */
fcc_status_t FCC_MAT_API(norm_fro)(const FCC_MAT_API(t) *a, FCC_MAT_REAL *out); /* overflow-safe */
fcc_status_t FCC_MAT_API(norm_max)(const FCC_MAT_API(t) *a, FCC_MAT_REAL *out); /* max |a_ij| */
/* max|a_ij - b_ij| / max|b_ij| (the absolute difference when b is zero): how
 * one solver is checked against another, relative to the matrix's scale so
 * that a structurally tiny entry is not asked for more digits than the data hold. */
fcc_status_t FCC_MAT_API(rel_diff)(const FCC_MAT_API(t) *a, const FCC_MAT_API(t) *b,
                                   FCC_MAT_REAL *out);

/* ---- LU with partial pivoting (fcc_mat_lu.c) ------------------------------ */

/* PA = LU of a square matrix; L unit lower and U share lu[]. */
typedef struct {
    FCC_MAT_REAL lu[FCC_MAT_MAX_ELEMS];
    uint8_t perm[FCC_MAT_MAX_DIM]; /* row i of PA is row perm[i] of A */
    uint16_t n;
    FCC_MAT_REAL norm1; /* ||A||_1, kept for the condition number */
} FCC_MAT_API(lu_t);

/* Factorise.  FCC_ERR_SINGULAR when a pivot is below n*eps*max|a_ij| (singular
 * to working precision); ill-conditioned but non-singular matrices factorise,
 * and lu_rcond says how far to trust the solution. */
fcc_status_t FCC_MAT_API(lu_factor)(FCC_MAT_API(lu_t) *lu, const FCC_MAT_API(t) *a);
/* Solve A x = b for every column of b (n x k); x may be the same matrix as b. */
fcc_status_t FCC_MAT_API(lu_solve)(const FCC_MAT_API(lu_t) *lu, const FCC_MAT_API(t) *b,
                                   FCC_MAT_API(t) *x);
/* Solve A^T x = b (for right divisions X = B A^-1, i.e. A^T X^T = B^T). */
fcc_status_t FCC_MAT_API(lu_solve_trans)(const FCC_MAT_API(lu_t) *lu, const FCC_MAT_API(t) *b,
                                         FCC_MAT_API(t) *x);
/* Reciprocal 1-norm condition number 1/(||A||_1 ||A^-1||_1), computed exactly
 * (n solves; n is small), 0 for a singular matrix. */
fcc_status_t FCC_MAT_API(lu_rcond)(const FCC_MAT_API(lu_t) *lu, FCC_MAT_REAL *rcond);
/* x = a^-1 b and ainv = a^-1, with lu as scratch (ainv may be a itself). */
fcc_status_t FCC_MAT_API(solve)(const FCC_MAT_API(t) *a, const FCC_MAT_API(t) *b, FCC_MAT_API(t) *x,
                                FCC_MAT_API(lu_t) *lu);
fcc_status_t FCC_MAT_API(inv)(const FCC_MAT_API(t) *a, FCC_MAT_API(t) *ainv, FCC_MAT_API(lu_t) *lu);

/* ---- Cholesky (fcc_mat_lu.c) ----------------------------------------------- */

/* a = l l^T with l lower triangular (its upper triangle is zeroed; l may be a
 * itself); only the lower triangle of a is read.  FCC_ERR_NOT_POSDEF on a
 * pivot that is not clearly positive (<= n*eps*max diag): semidefinite
 * matrices are refused. */
fcc_status_t FCC_MAT_API(chol)(const FCC_MAT_API(t) *a, FCC_MAT_API(t) *l);
/* Solve l l^T x = b; x may be the same matrix as b. */
fcc_status_t FCC_MAT_API(chol_solve)(const FCC_MAT_API(t) *l, const FCC_MAT_API(t) *b,
                                     FCC_MAT_API(t) *x);

/* ---- Matrix exponential (fcc_mat_expm.c) ----------------------------------- */

/* Scaling and squaring with a diagonal Pade approximant (Higham 2005): the
 * degree m in {3,5,7,9,13} and the scaling 2^-s are chosen from ||A||_1 so
 * the backward error is below the unit roundoff.  Single precision uses
 * Higham's single-precision table (degrees 3, 5, 7): degree-13 coefficients
 * span 17 decades, more than float resolves. */
typedef struct {
    FCC_MAT_REAL a2[FCC_MAT_MAX_ELEMS];
    FCC_MAT_REAL a4[FCC_MAT_MAX_ELEMS];
    FCC_MAT_REAL a6[FCC_MAT_MAX_ELEMS];
    FCC_MAT_REAL u[FCC_MAT_MAX_ELEMS];
    FCC_MAT_REAL v[FCC_MAT_MAX_ELEMS];
    FCC_MAT_REAL t[FCC_MAT_MAX_ELEMS];
    FCC_MAT_API(lu_t) lu;
} FCC_MAT_API(expm_ws_t);

/* e = exp(a) (e must not be a).  FCC_ERR_NOT_FINITE if the result overflowed. */
fcc_status_t FCC_MAT_API(expm)(const FCC_MAT_API(t) *a, FCC_MAT_API(t) *e,
                               FCC_MAT_API(expm_ws_t) *ws);

/* ---- Nonsymmetric eigenproblem (fcc_mat_eig.c) ----------------------------- */

/* Balancing (diagonal scaling by powers of two) + Householder reduction to
 * Hessenberg form + Francis double-shift QR to real Schur form T = Z^T A Z +
 * back substitution on T for the eigenvectors.  Scratch lives here. */
typedef struct {
    FCC_MAT_REAL h[FCC_MAT_MAX_ELEMS];     /* Hessenberg, then Schur form */
    FCC_MAT_REAL z[FCC_MAT_MAX_ELEMS];     /* accumulated orthogonal transformations */
    FCC_MAT_REAL scale[FCC_MAT_MAX_DIM];   /* balancing D */
} FCC_MAT_API(eig_ws_t);

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
fcc_status_t FCC_MAT_API(eig)(const FCC_MAT_API(t) *a, FCC_MAT_REAL wr[], FCC_MAT_REAL wi[],
                              FCC_MAT_API(t) *v, FCC_MAT_API(eig_ws_t) *ws);
/* max |lambda_i(a)| */
fcc_status_t FCC_MAT_API(spectral_radius)(const FCC_MAT_API(t) *a, FCC_MAT_REAL *rho,
                                          FCC_MAT_API(eig_ws_t) *ws);

/* ---- Singular values (fcc_mat_svd.c) --------------------------------------- */

/* One-sided Jacobi (Hestenes): orthogonalises columns by plane rotations, so
 * small singular values keep the full relative accuracy of the data, which a
 * rank test needs (forming A^T A would halve the digits). */
typedef struct {
    FCC_MAT_REAL w[2 * FCC_MAT_MAX_ELEMS];
} FCC_MAT_API(svd_ws_t);

/* The min(rows, cols) singular values of a, in decreasing order.  Needs
 * min(rows, cols) <= FCC_MAT_MAX_DIM and max(rows, cols) <= 2*FCC_MAT_MAX_DIM
 * (tall stacks such as the PBH test matrix [A - lambda I; C] fit). */
fcc_status_t FCC_MAT_API(svd_values)(const FCC_MAT_API(t) *a, FCC_MAT_REAL s[],
                                     FCC_MAT_API(svd_ws_t) *ws);
/* Spectral norm ||a||_2 = largest singular value. */
fcc_status_t FCC_MAT_API(norm_2)(const FCC_MAT_API(t) *a, FCC_MAT_REAL *out,
                                 FCC_MAT_API(svd_ws_t) *ws);
