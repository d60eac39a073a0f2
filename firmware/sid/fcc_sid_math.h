/*
 * fcc_sid_math.h -- the identified model and the few 2x2 facts the
 * identification modules share (firmware/sid/README.md).
 *
 * The state is x = [alpha, q]^T (n = 2) and C = I2 (the CDRW measures both
 * states), so every matrix the filters touch is 2x2.  Closed forms for 2x2
 * are exact, branch-light and far cheaper than a general linear-algebra call,
 * which matters at 50 Hz on a Cortex-M4F.
 *
 * Storage convention: 2x2 matrices are row-major arrays of 4 reals,
 * m[0] = m11, m[1] = m12, m[2] = m21, m[3] = m22.
 */
#ifndef FCC_SID_MATH_H
#define FCC_SID_MATH_H

#include <stdbool.h>

#include "fcc_types.h"

/* Number of states (alpha, q) and of measured outputs (C = I2). */
#define FCC_SID_N 2

/* Largest magnitude any identification state may take (a state, a generator
 * entry): squares of it summed over thousands of generator columns stay far
 * from overflow in either real type. */
#ifdef FCC_REAL_FLOAT
#define FCC_SID_MAX_MAGNITUDE FCC_R(1e16)
#else
#define FCC_SID_MAX_MAGNITUDE FCC_R(1e150)
#endif

/* One discrete model x_{k+1} = A x_k + B de_k + c (eq. 3): a row-major 2x2 A,
 * the 2-vector B and the affine term c.  The paper's model has no c (c = 0,
 * the default): the states are absolute (alpha ~ 9 deg at trim) and A, B
 * absorb the trim offset.  c is non-zero only with the MLS's optional
 * intercept (fcc_mls.h), which lets A, B be the local dynamics instead. */
typedef struct {
    fcc_real_t a[4];
    fcc_real_t b[2];
    fcc_real_t c[2];
} fcc_sid_model_t;

/* True when all n values are finite. */
bool fcc_sid_all_finite(const fcc_real_t *v, size_t n);

/* True when the model has only finite entries. */
bool fcc_sid_model_is_finite(const fcc_sid_model_t *model);

/* Spectral radius rho(M) = max |lambda_i(M)| of a 2x2 matrix (eq. 26).
 * rho < 1 means the discrete model is stable.  The discriminant is formed as
 * ((m11 - m22)/2)^2 + m12 m21, which does not cancel when the eigenvalues are
 * close; a complex pair has |lambda| = sqrt(det). */
fcc_real_t fcc_sid_m2_spectral_radius(const fcc_real_t m[4]);

/* Largest singular value ||M||_2 of a 2x2 matrix (the gain norm of Fig. 9).
 * Uses sigma_max = (|(m11+m22, m21-m12)| + |(m11-m22, m12+m21)|) / 2, which
 * needs two square roots and no eigen-solver. */
fcc_real_t fcc_sid_m2_norm2(const fcc_real_t m[4]);

/* Inverse of a symmetric positive definite 2x2 matrix (the innovation
 * covariance S = C P C^T + R).  FCC_ERR_NOT_POSDEF when s11 <= 0 or
 * det <= FCC_EPS * s11 * s22 (numerically singular); inv is then untouched. */
fcc_status_t fcc_sid_m2_spd_inv(const fcc_real_t s[4], fcc_real_t inv[4]);

/* out = a * b for 2x2 matrices (out may not alias a or b). */
void fcc_sid_m2_mul(const fcc_real_t a[4], const fcc_real_t b[4], fcc_real_t out[4]);

/* out = a * b^T for 2x2 matrices (out may not alias a or b). */
void fcc_sid_m2_mul_bt(const fcc_real_t a[4], const fcc_real_t b[4], fcc_real_t out[4]);

/* Lower Cholesky factor of a symmetric positive definite 2x2 matrix:
 * s = l l^T.  Used to turn the KF's initial covariance P0 into the ZKF's
 * initial generator matrix, so that both filters start from the same second
 * moment.  FCC_ERR_NOT_POSDEF otherwise; l untouched. */
fcc_status_t fcc_sid_m2_cholesky(const fcc_real_t s[4], fcc_real_t l[4]);

#endif /* FCC_SID_MATH_H */
