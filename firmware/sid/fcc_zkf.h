/*
 * fcc_zkf.h -- zonotopic Kalman filter (Combastel 2015; Gim et al. 2022,
 * eqs. 19-25), the state-estimation half of MLS-ZKF and MLS-AZKF.
 *
 * State set <x_k, P_k> = {x_k + P_k s : |s|_inf <= 1}, P_k a 2 x p
 * generator matrix.  One combined predict-correct step of order q:
 *   P_bar = reduce_q(P_k)                                   (eqs. 17-18)
 *   G_k   = A P_bar P_bar^T C^T (C P_bar P_bar^T C^T + R)^-1   (eq. 25)
 *   x_k+1 = A x_k + B de_k (+ c) + G_k (y_k - C x_k)         (eq. 22)
 *   P_k+1 = [(A - G_k C) P_bar, E, -G_k F]                   (eq. 24)
 * with C = I2 and R = F F^T.  A small q boxes the set, enlarges
 * P_bar P_bar^T and so raises the gain (trust the sensor); a large q keeps
 * the tight set and a low, KF-like gain.  The order is an argument of every
 * step so that the AZKF can change it (fcc_azkf.h); a fixed-order ZKF
 * passes the same q every time.
 *
 * Without a measurement (sensor unusable, or the AZKF "skip" fault policy)
 * the step is the pure prediction G = 0: P_k+1 = [A P_bar, E] (the zero
 * columns -G F are not stored).
 *
 * Cost: two passes over the p <= q + 4 columns per step.  The commit pass
 * that writes P_k+1 also stores each column's squared norm, the interval
 * hull and the covariation P_k+1 P_k+1^T; the next step then selects the
 * columns to box (one comparison per column) and gets P_bar P_bar^T from
 * that covariation by removing the few boxed columns (the shortest ones,
 * so the subtraction costs no accuracy) and adding their box -- or, when
 * everything is boxed (q = 2), straight from the hull.  Nothing is written
 * before every result is known to be finite, so a refused step leaves the
 * filter exactly as it was.
 */
#ifndef FCC_ZKF_H
#define FCC_ZKF_H

#include <stdbool.h>
#include <stdint.h>

#include "fcc_sid_math.h"
#include "fcc_types.h"
#include "fcc_zonotope.h"

typedef struct {
    fcc_real_t x[2];                           /* centre x_k */
    fcc_real_t gen[2u * FCC_ZONO_MAX_COLS];    /* P_k, column-major */
    fcc_real_t norm2[FCC_ZONO_MAX_COLS];       /* |column|^2 of P_k */
    fcc_real_t hull[2];                        /* interval hull radius of P_k */
    fcc_real_t cov[3];                         /* P_k P_k^T: (1,1), (1,2), (2,2) */
    uint16_t p;                                /* columns of P_k */
    fcc_real_t e[4];                           /* process generators E (row-major) */
    fcc_real_t f[4];                           /* measurement generators F (row-major) */
    fcc_real_t r[4];                           /* R = F F^T */
    fcc_real_t f_hull[2];                      /* interval hull radius of F */
    bool posterior;                            /* also compute the posterior (info.post_*) */
    fcc_zono_work_t work;
} fcc_zkf_t;

/* What one step used (row k of the replay: the gain and order of step k). */
typedef struct {
    fcc_real_t gain[4];    /* G_k (row-major), zero without a measurement */
    fcc_real_t gain_norm;  /* ||G_k||_2 */
    uint16_t order;        /* q used */
    uint16_t n_generators; /* columns of P_bar_k */
    bool updated;          /* the measurement entered the step */
    /* With zkf->posterior (else zero): the estimate after y_k,
     *   x_k|k = x_k + G'_k (y_k - x_k),  G'_k = P_bar P_bar^T (P_bar P_bar^T + R)^-1
     * (so that x_k+1 = A x_k|k + B de_k: G_k = A G'_k), its set
     * <x_k|k, [(I - G'_k) P_bar, -G'_k F]> as interval hull radii, and ||G'_k||_2.
     * Without a measurement: x_k, the hull of P_k and 0.  One extra pass over
     * the kept columns. */
    fcc_real_t post_x[2];
    fcc_real_t post_hull[2];
    fcc_real_t post_gain_norm;
} fcc_zkf_info_t;

/* x0: initial centre; p0: 2x2 initial generator matrix (row-major; the
 * bundle passes the Cholesky factor of the KF's P0); e, f: 2x2 generator
 * matrices of the process and measurement noise (row-major).
 * FCC_ERR_ARG on NULL or non-finite values, FCC_ERR_NOT_POSDEF when
 * R = F F^T is singular (the gain needs (P + R)^-1 to exist). */
fcc_status_t fcc_zkf_init(fcc_zkf_t *zkf, const fcc_real_t x0[2], const fcc_real_t p0[4],
                          const fcc_real_t e[4], const fcc_real_t f[4]);

/* One step of order q (2..FCC_ZONO_MAX_ORDER) with model A_k, B_k and input
 * de_k; y_k is used when use_measurement is true (it may be NULL otherwise).
 * FCC_ERR_ARG on NULL, FCC_ERR_RANGE on q out of range, FCC_ERR_NOT_FINITE on
 * a non-finite input or result: the filter is then left unchanged.  info may
 * be NULL. */
fcc_status_t fcc_zkf_step(fcc_zkf_t *zkf, const fcc_sid_model_t *model, fcc_real_t de,
                          const fcc_real_t y[2], bool use_measurement, uint16_t q,
                          fcc_zkf_info_t *info);

/* Also report the posterior of every step (info.post_*); off after init. */
void fcc_zkf_set_posterior(fcc_zkf_t *zkf, bool on);

/* Radius of the interval hull of the predicted output zonotope
 * <C x_k, [C P_k, F]> (the fault detector's bound on the innovation). */
void fcc_zkf_output_radius(const fcc_zkf_t *zkf, fcc_real_t radius[2]);

/* Covariation P_k P_k^T (row-major 2x2). */
void fcc_zkf_covariation(const fcc_zkf_t *zkf, fcc_real_t m[4]);

#endif /* FCC_ZKF_H */
