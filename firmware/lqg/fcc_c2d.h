/*
 * fcc_c2d.h -- continuous to discrete time with a zero-order hold, by Van
 * Loan's block matrix exponentials (C. F. Van Loan, "Computing integrals
 * involving the matrix exponential", IEEE TAC 23(3), 1978).
 *
 * Why block exponentials: every integral the sampled-data design needs
 * (Gamma, the process-noise covariance Q_d and the cost integrals
 * Q11, Q12, Q22 of the paper's eqs. 5-7, fcc_lqg.h) is a sub-block of ONE
 * matrix exponential,
 * so the whole discretisation reduces to fcc_mat_expm, with no quadrature
 * and no inverse of F (F may be singular).
 */
#ifndef FCC_C2D_H
#define FCC_C2D_H

#include "fcc_mat.h"

/* n + m must fit half of FCC_MAT_MAX_DIM for the cost block (2(n+m) square). */
#define FCC_C2D_MAX_NM (FCC_MAT_MAX_DIM / 2)

typedef struct {
    double blk[FCC_MAT_MAX_ELEMS]; /* the block matrix C T */
    double e[FCC_MAT_MAX_ELEMS];   /* exp(C T) */
    fcc_mat64_expm_ws_t expm;
} fcc_c2d_ws_t;

/*
 * Phi = e^{F T}, Gamma = int_0^T e^{F s} ds G  (n x n, n x m), from
 * exp([[F, G], [0, 0]] T) = [[Phi, Gamma], [0, I]].
 * FCC_ERR_ARG for T <= 0 or non-finite T; FCC_ERR_SIZE for shapes that do not
 * match or do not fit (n + m <= FCC_MAT_MAX_DIM).
 */
fcc_status_t fcc_c2d_zoh(const fcc_mat64_t *f, const fcc_mat64_t *g, double t, fcc_mat64_t *phi,
                         fcc_mat64_t *gamma, fcc_c2d_ws_t *ws);

/*
 * Q_d = int_0^T e^{F s} Qc e^{F^T s} ds for a continuous white noise of
 * spectral density Qc (n x n, symmetric; Qc = f W f^T for noise input f with
 * intensity W), from exp([[-F, Qc], [0, F^T]] T) = [[., E12], [0, E22]]:
 * Phi = E22^T and Q_d = Phi E12 (symmetrised).  Needs 2n <= FCC_MAT_MAX_DIM.
 */
fcc_status_t fcc_c2d_noise(const fcc_mat64_t *f, const fcc_mat64_t *qc, double t, fcc_mat64_t *qd,
                           fcc_c2d_ws_t *ws);

/*
 * The discrete equivalent of the continuous cost int (x^T Wx x + u^T Wu u) dt
 * under a zero-order hold (what MATLAB's lqrd computes):
 *   Q11 = int_0^T Phi(s)^T Wx Phi(s) ds                 (n x n)
 *   Q12 = int_0^T Phi(s)^T Wx Gamma(s) ds               (n x m)
 *   Q22 = int_0^T (Gamma(s)^T Wx Gamma(s) + Wu) ds      (m x m)
 * With Fa = [[F, G], [0, 0]] and Wa = blkdiag(Wx, Wu):
 * exp([[-Fa^T, Wa], [0, Fa]] T) = [[., E12], [0, E22]] and
 * int e^{Fa^T s} Wa e^{Fa s} ds = E22^T E12 = [[Q11, Q12], [Q12^T, Q22]].
 * Needs 2(n + m) <= FCC_MAT_MAX_DIM.
 */
fcc_status_t fcc_c2d_cost(const fcc_mat64_t *f, const fcc_mat64_t *g, const fcc_mat64_t *wx,
                          const fcc_mat64_t *wu, double t, fcc_mat64_t *q11, fcc_mat64_t *q12,
                          fcc_mat64_t *q22, fcc_c2d_ws_t *ws);

#endif /* FCC_C2D_H */
