/*
 * fcc_sid.h -- one real-time identification loop: one MLS closed with one
 * state filter (MLS-KF, MLS-ZKF or MLS-AZKF; Fig. 3 of S. Gim, H. G. Harno,
 * S. Saderla and Y. Kim, "Real-time System Identification of Aircraft in Upset
 * Condition Using Adaptive-order Zonotopic Kalman Filter", J. Korean Soc.
 * Aeronaut. Space Sci. 50(2), 93-101, 2022: "Gim et al. 2022" or "the paper"
 * in firmware/sid).
 *
 * This is the API the fcc application uses: it owns three fcc_sid_t (one
 * per filter, the paper's side-by-side comparison), feeds each the same
 * sample every 20 ms and publishes fcc_sid_out_t.  No maths is needed on
 * top of it.
 *
 *   fcc_sid_config_t cfg;
 *   fcc_sid_config_default(&cfg, FCC_SID_AZKF);    // paper values
 *   static fcc_sid_t sid;   // 18.9 kB (float, M4F) / 36.8 kB (double): static
 *   if (fcc_sid_init(&sid, &cfg) != FCC_OK) ...
 *   each step: fcc_sid_step(&sid, y_alpha, y_q, de, oracle_fault, valid, &out);
 *
 * The loop (per step k, sample y_k, elevator de_k):
 *  - the filter runs with the model [A B] the MLS fitted on the filter's own
 *    past estimates (the data of the MLS are the *filtered* states);
 *  - then the transition that ends at the newest estimate is added to the
 *    MLS window and the model refitted, for the next step.
 * A transition is learnt only when both its ends were corrected by a
 * measurement: a step without a usable sample (measurement_valid false,
 * non-finite or out-of-range sample) or with a flagged fault (AZKF, when
 * mls_hold_on_fault) only predicts, and a prediction teaches the MLS
 * nothing but its own model.  The AZKF's fault detector is armed from the
 * first step when arm_on_prior (default: the prior is the aircraft's
 * wind-tunnel model, consistent with trim flight), otherwise only once the
 * MLS has fitted a model (or when the MLS is off).
 *
 * Output semantics (one row per step, comparable with another
 * implementation), chosen by cfg.rows:
 *  - FCC_SID_ROWS_PAPER (default, the paper's printed equations): KF row k
 *    is the posterior after y_k (step 0 updates x0, P0 without a
 *    prediction), bounds +/- 3 sigma, order 0, fault 0; ZKF and AZKF row k
 *    is x_k before y_k is used (their step is one combined predict-correct),
 *    with the gain and order used in step k and the interval hull of
 *    <x_k, P_k> as bounds.
 *  - FCC_SID_ROWS_POSTERIOR: every filter after y_k.  KF as above; ZKF/AZKF
 *    x_k|k = x_k + G'_k (y_k - x_k), G'_k = P_bar P_bar^T (P_bar P_bar^T + R)^-1,
 *    bounds the hull of [(I - G'_k) P_bar, -G'_k F], gain ||G'_k||_2
 *    (fcc_zkf.h; without a measurement: x_k, the hull of P_k, 0).
 *  - FCC_SID_ROWS_PRIOR: every filter before y_k, with the gain used in step
 *    k.  ZKF/AZKF as PAPER; KF x-_k, P-_k (step 0: x0, P0), +/- 3 sigma.
 *  In every mode the MLS learns from the states the rows report: the
 *  transition ending at the newest such state, after each step (PAPER: KF
 *  posteriors, ZKF/AZKF priors).
 *  - A_k, B_k, rho(A_k), standard errors: the model used in the step.
 *
 * Bad input: a non-finite or out-of-range elevator refuses the step
 * (status returned, nothing changes, out = last good output with
 * stepped = false); a non-finite or out-of-range sample is treated as
 * unusable (prediction only) and reported in out.input_status.  No NaN can
 * reach A_k, B_k or x.
 */
#ifndef FCC_SID_H
#define FCC_SID_H

#include <stdbool.h>
#include <stdint.h>

#include "fcc_azkf.h"
#include "fcc_kf.h"
#include "fcc_mls.h"
#include "fcc_sid_math.h"
#include "fcc_types.h"
#include "fcc_zkf.h"

typedef enum {
    FCC_SID_KF = 0,
    FCC_SID_ZKF = 1,
    FCC_SID_AZKF = 2
} fcc_sid_filter_t;

/* Paper values (section 2.3). */
#define FCC_SID_DEFAULT_X0_ALPHA FCC_R(0.1571)
#define FCC_SID_DEFAULT_X0_Q FCC_R(0.0204)
#define FCC_SID_DEFAULT_P0 FCC_R(0.1)
#define FCC_SID_DEFAULT_E FCC_R(0.004)
#define FCC_SID_DEFAULT_F FCC_R(0.02)
/* "MLS-ZKF" of the paper: the ZKF at one fixed large order. */
#define FCC_SID_DEFAULT_ZKF_ORDER FCC_AZKF_DEFAULT_Q_FAULT
/* Plausibility limits of the inputs (rad, rad/s, rad): a deep stall stays
 * under 90 deg of alpha, a small UAV under 10 rad/s of pitch rate, an
 * elevator under 1 rad.  Beyond, the value is a broken sensor or frame. */
#define FCC_SID_DEFAULT_ALPHA_LIMIT FCC_R(1.5707963)
#define FCC_SID_DEFAULT_Q_LIMIT FCC_R(10.0)
#define FCC_SID_DEFAULT_DE_LIMIT FCC_R(1.0)

/* Which estimate a row reports (see the file comment). */
typedef enum {
    FCC_SID_ROWS_PAPER = 0,     /* KF after y_k, ZKF/AZKF before y_k (the paper's equations) */
    FCC_SID_ROWS_PRIOR = 1,     /* every filter before y_k */
    FCC_SID_ROWS_POSTERIOR = 2  /* every filter after y_k */
} fcc_sid_rows_t;

typedef struct {
    fcc_sid_filter_t filter;
    fcc_sid_rows_t rows;     /* row semantics and what the MLS learns from (PAPER) */
    fcc_real_t x0[2];        /* initial estimate (rad, rad/s) */
    fcc_real_t p0[4];        /* initial KF covariance (SPD); the ZKF starts from its
                                Cholesky factor, i.e. the same P0 as covariation */
    fcc_real_t e[4];         /* process noise generators E (Q = E E^T), row-major */
    fcc_real_t f[4];         /* measurement noise generators F (R = F F^T), row-major */
    bool mls_enabled;        /* false: mls.prior is the model every step (filter alone) */
    bool mls_hold_on_fault;  /* AZKF: do not learn transitions while a fault is flagged */
    bool arm_on_prior;       /* AZKF: detector armed while the model is still the prior
                                (true: the prior is a real model, see fcc_sid_default_prior) */
    fcc_mls_config_t mls;    /* window, ridge, guards, prior model */
    uint16_t zkf_order;      /* ZKF's fixed order, 2..FCC_ZONO_MAX_ORDER */
    fcc_azkf_config_t azkf;  /* q_normal, q_fault, policy, detector */
    fcc_real_t alpha_limit;  /* |alpha| above: sample unusable */
    fcc_real_t q_limit;      /* |q| above: sample unusable */
    fcc_real_t de_limit;     /* |de| above: step refused */
} fcc_sid_config_t;

typedef struct {
    uint32_t k;                      /* step index of this output */
    fcc_real_t x_hat[2];             /* see the row semantics above */
    fcc_real_t lo[2];                /* lower interval bounds (alpha, q) */
    fcc_real_t hi[2];                /* upper interval bounds */
    fcc_real_t gain_norm;            /* ||K_k||_2 or ||G_k||_2, 0 without update */
    uint16_t order;                  /* q used (0 for the KF) */
    uint16_t n_generators;           /* columns of P_bar_k (0 for the KF) */
    bool fault;                      /* fault flag acted upon (AZKF only) */
    bool measurement_used;           /* y_k entered the step */
    bool stepped;                    /* false: step refused, this is the last good output */
    fcc_sid_model_t model;           /* A_k, B_k used in the step */
    fcc_real_t rho;                  /* rho(A_k) */
    fcc_real_t se[FCC_MLS_N_PARAMS]; /* standard errors (a11 a12 a21 a22 b1 b2), -1 = n/a */
    uint16_t n_transitions;          /* MLS window fill when the model was fitted */
    bool model_is_prior;             /* the model is the prior (or the fixed model) */
    fcc_status_t status;             /* first error among the three below, else FCC_OK */
    fcc_status_t input_status;       /* sample or elevator rejected */
    fcc_status_t mls_status;         /* the fit that produced the model (guard refusal...) */
    fcc_status_t filter_status;      /* the filter step */
} fcc_sid_out_t;

typedef struct {
    fcc_sid_config_t cfg;
    fcc_mls_t mls;
    union {
        fcc_kf_t kf;
        fcc_zkf_t zkf;
        fcc_azkf_t azkf;
    } u;
    fcc_real_t prev_x[2];     /* KF: x_k-1|k-1 (start of the next transition) */
    fcc_real_t prev_de;       /* KF: de_k-1 */
    bool have_prev;           /* KF: prev_x exists */
    bool prev_informed;       /* KF: prev_x was corrected by a measurement */
    bool cur_informed;        /* ZKF/AZKF: x_k was corrected by y_k-1; KF prior rows:
                                 the last step used its measurement */
    fcc_status_t mls_status;  /* status of the last fit */
    uint32_t k;               /* steps done */
    fcc_sid_out_t last;       /* last good output */
} fcc_sid_t;

/* Fills every field with the paper's values and the documented defaults
 * (module headers), for the given filter. */
void fcc_sid_config_default(fcc_sid_config_t *cfg, fcc_sid_filter_t filter);

/* The prior A0, B0: the CDRW's "wind-tunnel" model at trim, i.e. the
 * quasi-steady linearisation (separation point at its static value X0(alpha))
 * at alpha* = 9 deg, q* = 0, de* = -0.0421 rad, in the paper's Euler form
 * (dt = 0.02 s); hil.plants.cdrw_prior.wind_tunnel_prior() computes it and
 * tests/python/reference/test_sid_cdrw.py checks these digits against it.  The
 * paper's regression has no constant term, so this prior has the trim offset
 * c0 absorbed into [A0 B0] by the smallest change that keeps the trim a fixed
 * point (otherwise the filters would drift by c0 per step until the MLS has
 * data; it is also what a fit without intercept converges to on trim data).
 * c = 0.  rho(A0) = 0.935 (the unabsorbed A0: 0.895; the plant's exact
 * linearisation: 0.889).  The application should pass the best model it has. */
void fcc_sid_default_prior(fcc_sid_model_t *prior);

/* The same wind-tunnel model in affine form, x+ = A0 x + B0 de + c0 (the
 * Jacobian itself and the trim offset): the prior for the optional MLS
 * intercept (fcc_mls_config_t.intercept). */
void fcc_sid_default_prior_affine(fcc_sid_model_t *prior);

/* Checks every field; FCC_ERR_ARG / FCC_ERR_RANGE / FCC_ERR_NOT_POSDEF. */
fcc_status_t fcc_sid_config_check(const fcc_sid_config_t *cfg);

fcc_status_t fcc_sid_init(fcc_sid_t *sid, const fcc_sid_config_t *cfg);

/* One step (see the file comment).  Returns out->status.  A non-OK status
 * with out->stepped true is a warning: the step ran, but the sample was
 * unusable (input_status) or the MLS guard kept the last model
 * (mls_status).  With out->stepped false nothing changed. */
fcc_status_t fcc_sid_step(fcc_sid_t *sid, fcc_real_t y_alpha, fcc_real_t y_q, fcc_real_t de,
                          bool oracle_fault, bool measurement_valid, fcc_sid_out_t *out);

#endif /* FCC_SID_H */
