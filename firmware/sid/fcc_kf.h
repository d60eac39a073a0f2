/*
 * fcc_kf.h -- the plain Kalman filter of MLS-KF (Gim et al. 2022, eqs. 8-14), the
 * baseline the paper compares the zonotopic filters with.
 *
 *   predict  x-_k = A_k x_k-1 + B_k de_k-1 (+ c_k)      (10)
 *            P-_k = A_k P_k-1 A_k^T + Q,  Q = E E^T      (11)
 *   update   K_k  = P-_k C^T (C P-_k C^T + R)^-1, R = F F^T   (12)
 *            x_k  = x-_k + K_k (y_k - C x-_k)            (13)
 *            P_k  = (I - K_k C) P-_k                      (14)
 * with C = I2 (c_k: the model's optional affine term, 0 in the paper).  After eq. (14) P is symmetrised ((P + P^T)/2): the printed
 * form is not symmetric in rounding, and float would drift otherwise.
 *
 * The filter starts with an update of the prior (x0, P0) and no prediction
 * (row 0 of the replay is the posterior after y_0).  Without a usable
 * measurement the step is the prediction only.  Every step computes into
 * temporaries and commits only finite results: a refused step leaves the
 * filter unchanged.
 */
#ifndef FCC_KF_H
#define FCC_KF_H

#include <stdbool.h>

#include "fcc_sid_math.h"
#include "fcc_types.h"

typedef struct {
    fcc_real_t x[2]; /* posterior x_k */
    fcc_real_t p[4]; /* posterior covariance P_k (row-major) */
    fcc_real_t q[4]; /* Q = E E^T */
    fcc_real_t r[4]; /* R = F F^T */
    bool started;    /* false until the first step (no prediction then) */
} fcc_kf_t;

typedef struct {
    fcc_real_t gain[4];   /* K_k (row-major), zero without a measurement */
    fcc_real_t gain_norm; /* ||K_k||_2 */
    bool predicted;       /* eqs. 10-11 ran (false on the first step) */
    bool updated;         /* eqs. 12-14 ran */
    fcc_real_t prior_x[2]; /* x-_k, before y_k (step 0: x0) */
    fcc_real_t prior_p[4]; /* P-_k (step 0: P0) */
} fcc_kf_info_t;

/* x0, p0: prior mean and covariance (symmetric positive definite);
 * e, f: 2x2 noise generator matrices (Q = E E^T, R = F F^T, R must be
 * positive definite).  FCC_ERR_ARG on NULL or non-finite values,
 * FCC_ERR_NOT_POSDEF when P0 or R is not positive definite. */
fcc_status_t fcc_kf_init(fcc_kf_t *kf, const fcc_real_t x0[2], const fcc_real_t p0[4],
                         const fcc_real_t e[4], const fcc_real_t f[4]);

/* One step: predict with (A_k, B_k, de_prev) unless this is the first step,
 * then update with y_k when use_measurement.  FCC_ERR_NOT_FINITE on a
 * non-finite input or result (filter unchanged).  info may be NULL. */
fcc_status_t fcc_kf_step(fcc_kf_t *kf, const fcc_sid_model_t *model, fcc_real_t de_prev,
                         const fcc_real_t y[2], bool use_measurement, fcc_kf_info_t *info);

/* Eqs. 10-11 alone on (x, p) in place. */
void fcc_kf_predict(const fcc_real_t q[4], const fcc_sid_model_t *model, fcc_real_t de,
                    fcc_real_t x[2], fcc_real_t p[4]);

/* Eqs. 12-14 alone on (x, p) in place; k receives K.  FCC_ERR_NOT_FINITE
 * when C P C^T + R is not positive definite (x, p untouched). */
fcc_status_t fcc_kf_update(const fcc_real_t r[4], const fcc_real_t y[2], fcc_real_t x[2],
                           fcc_real_t p[4], fcc_real_t k[4]);

#endif /* FCC_KF_H */
