/*
 * fcc_dare.h -- the discrete algebraic Riccati equation, solved two
 * independent ways so that each checks the other.
 *
 *   X = A^T X A - (A^T X B + S)(R + B^T X B)^-1 (B^T X A + S^T) + Q
 *
 * is the steady-state LQR equation with cross term S (cost
 * sum x^T Q x + 2 x^T S u + u^T R u) and, with (A, B, Q, R, S) =
 * (Phi^T, H^T, Q_d, R, 0), the steady-state Kalman filter's a-priori
 * covariance equation.  Both solvers first remove the cross term
 * (A~ = A - B R^-1 S^T, Q~ = Q - S R^-1 S^T, the paper's eqs. 5-7) and check
 * the existence conditions by the PBH test on every eigenvalue of A~ on or
 * outside the unit circle (within 4 sqrt(eps)):
 *   (A~, B)  stabilisable : rank [A~ - lambda I, B]   = n, else FCC_ERR_NOT_STABILIZABLE
 *   (A~, Q~) detectable   : rank [A~ - lambda I; Q~]  = n, else FCC_ERR_NOT_DETECTABLE
 * (numerical rank: smallest singular value above sqrt(eps) times the
 * largest, with the second block scaled to the norm of A~).
 *
 * fcc_dare_hamiltonian: the paper's method (Bryson & Hall; Vaughan 1970):
 * the eigenvectors of the symplectic matrix
 *   Z = [[A~ + G A~^-T Q~, -G A~^-T], [-A~^-T Q~, A~^-T]],  G = B R^-1 B^T,
 * that belong to its n eigenvalues inside the unit circle span [U1; U2]
 * and X = U2 U1^-1.  A complex pair contributes the real and imaginary parts
 * of its vector (the real invariant subspace), so everything stays real.
 * Needs A~ invertible (FCC_ERR_SINGULAR otherwise; use doubling then).  An
 * eigenvalue of Z on the unit circle (within 4 sqrt(eps)), or a singular U1,
 * means there is no stabilising solution: FCC_ERR_NOT_STABILIZABLE.
 *
 * fcc_dare_doubling: the structure-preserving doubling algorithm (Chu, Fan,
 * Lin & Wang 2004): A_0 = A~, G_0 = G, H_0 = Q~,
 *   W = I + G_k H_k,  A_{k+1} = A_k W^-1 A_k,
 *   G_{k+1} = G_k + A_k W^-1 G_k A_k^T,  H_{k+1} = H_k + A_k^T H_k W^-1 A_k,
 * H_k -> X quadratically (error ~ rho(A - BK)^(2^k)).  No inverse of A.
 *
 * Double precision (fcc_mat64) in every build: in single precision the
 * eigenvector method loses up to 1e-4 relative at T = 10 ms (measured), and
 * the design runs at start-up, off the control path.
 *
 * Both return a symmetric X and refuse to return one that is not finite,
 * does not stabilise (spectral radius of A - B K >= 1), or leaves a relative
 * residual above sqrt(eps): FCC_ERR_NO_CONVERGENCE.  Sizes: n <= FCC_DARE_MAX_N,
 * 1 <= m <= n.  R must be symmetric positive definite (FCC_ERR_NOT_POSDEF),
 * Q symmetric (FCC_ERR_ARG).  Non-finite data: FCC_ERR_NOT_FINITE.
 */
#ifndef FCC_DARE_H
#define FCC_DARE_H

#include "fcc_mat.h"

#define FCC_DARE_MAX_N (FCC_MAT_MAX_DIM / 2)
#define FCC_DARE_NN (FCC_DARE_MAX_N * FCC_DARE_MAX_N)
#define FCC_DARE_MAX_ITER 64

/* The problem; s == NULL means no cross term. */
typedef struct {
    const fcc_mat64_t *a; /* n x n */
    const fcc_mat64_t *b; /* n x m */
    const fcc_mat64_t *q; /* n x n, symmetric */
    const fcc_mat64_t *r; /* m x m, symmetric positive definite */
    const fcc_mat64_t *s; /* n x m or NULL */
} fcc_dare_problem_t;

/* What the solver saw, for reports and tests. */
typedef struct {
    uint16_t iterations;  /* doubling steps (0 for the Hamiltonian method) */
    double residual;  /* relative residual of the returned X */
    double cl_radius; /* spectral radius of A - B K */
    double rcond_u1;  /* Hamiltonian: reciprocal 1-norm condition of U1 */
} fcc_dare_info_t;

typedef struct {
    double at[FCC_DARE_NN]; /* A~ */
    double qt[FCC_DARE_NN]; /* Q~ */
    double g[FCC_DARE_NN];  /* B R^-1 B^T */
    double tmp[8][FCC_DARE_NN];
    double z[FCC_MAT_MAX_ELEMS];       /* 2n x 2n symplectic matrix */
    double v[FCC_MAT_MAX_ELEMS];       /* its eigenvectors */
    double pbh[2 * FCC_MAT_MAX_ELEMS]; /* realified PBH test matrix */
    fcc_mat64_eig_ws_t eig;
    fcc_mat64_lu_t lu;
    fcc_mat64_svd_ws_t svd;
} fcc_dare_ws_t;

fcc_status_t fcc_dare_hamiltonian(const fcc_dare_problem_t *p, fcc_mat64_t *x, fcc_dare_info_t *info,
                                  fcc_dare_ws_t *ws);
fcc_status_t fcc_dare_doubling(const fcc_dare_problem_t *p, fcc_mat64_t *x, fcc_dare_info_t *info,
                               fcc_dare_ws_t *ws);

/* K = (R + B^T X B)^-1 (B^T X A + S^T)  (m x n), the gain of u = -K x. */
fcc_status_t fcc_dare_gain(const fcc_dare_problem_t *p, const fcc_mat64_t *x, fcc_mat64_t *k,
                           fcc_dare_ws_t *ws);

/* Relative residual ||Res||_1 / (||A^T X A||_1 + ||X||_1 + ||N^T K||_1 + ||Q||_1)
 * of X in the equation above (N = B^T X A + S^T). */
fcc_status_t fcc_dare_residual(const fcc_dare_problem_t *p, const fcc_mat64_t *x, double *res,
                               fcc_dare_ws_t *ws);

#endif /* FCC_DARE_H */
