/*
 * fcc_mls.h -- moving-window least squares (MLS) identification of [A_k B_k]
 * (Gim et al. 2022, eqs. 5-7 and 27-30).
 *
 * Each transition j of the window is x_j -> x_{j+1} with regressor
 * phi_j = [alpha_j, q_j, de_j]^T.  Eq. (30) is two independent 3-parameter
 * regressions (one per row of [A B]) that share the 3x3 normal matrix
 * N = sum phi phi^T, so one 3x3 factorisation serves both rows.
 *
 * Why the extras beyond the paper:
 *  - O(1) update: the window sums are updated by adding the newest and
 *    subtracting the oldest transition, so the cost does not depend on h.
 *  - Exact re-sum: subtraction lets rounding accumulate (visible in float).
 *    A shadow accumulator adds every new transition and, after exactly h
 *    pushes, holds the exact sum of the current window; it then replaces the
 *    running sums, and the next shadow starts about the newest sample.  This is the periodic exact re-sum (period h) spread over
 *    the window, so no single step pays O(h).
 *  - Prior model: until min_transitions transitions exist, the prior A0, B0
 *    is reported (too few data to fit six parameters).
 *  - Optional intercept (off by default: the paper's eq. 30 has none):
 *    x_{j+1} = A x_j + B de_j + c.  The states are absolute, and a trimmed
 *    aircraft needs c != 0 (gravity, C_m0 and the trim elevator do not
 *    cancel A x* + B de*); without it A, B absorb the trim offset.  With it,
 *    the regression is solved on the window's data centred on their means
 *    (Nc = N - s s^T / m with s = sum phi, the same for sum phi z^T), which
 *    is exact, far better conditioned than appending a column of ones, and
 *    leaves c unregularised; then c = (sum z - Theta^T s) / m.  The ridge
 *    then acts on the *excitation* (the centred sums): with a steady state
 *    A, B fall back onto the prior and c takes the mean offset.
 *  - Tikhonov ridge toward the prior: minimise
 *        sum_j |z_j - Theta^T phi_j|^2 + ridge * |Theta - Theta0|_F^2,
 *    i.e. (N + ridge I) Theta = sum phi z^T + ridge Theta0.  Poor excitation
 *    (a constant elevator, a steady state) can then never make the system
 *    singular, and the estimate falls back smoothly onto the prior.
 *    ridge is in the units of N (rad^2, (rad/s)^2, rad^2 summed over the
 *    window): it weighs like `ridge` extra samples of unit regressor per axis.
 *  - Conditioning guard: the regularised normal matrix is equilibrated
 *    (unit diagonal) and its 1-norm condition number computed exactly (3x3);
 *    above max_cond the solve is refused and the last good model kept.  A
 *    model whose spectral radius exceeds max_rho is refused the same way
 *    (at 50 Hz, rho = 1.2 would double an error every 4 steps: not an
 *    aircraft, a fit to noise).
 *  - Standard errors: sigma_i^2 = RSS_i / (m - p) per row (p = 3, or 4 with
 *    the intercept), and
 *    se = sigma_i sqrt([(N + ridge I)^-1]_jj), the posterior standard
 *    deviation when the ridge is read as a Gaussian prior (the classical
 *    least-squares standard error when ridge = 0).
 *
 * Storage is static: the window ring holds at most FCC_MLS_MAX_WINDOW
 * transitions (compile-time bound, override with -DFCC_MLS_MAX_WINDOW=...).
 */
#ifndef FCC_MLS_H
#define FCC_MLS_H

#include <stdbool.h>
#include <stdint.h>

#include "fcc_sid_math.h"
#include "fcc_types.h"

#ifndef FCC_MLS_MAX_WINDOW
#define FCC_MLS_MAX_WINDOW 256u
#endif

/* Paper value: h = 2.2 s at 50 Hz. */
#define FCC_MLS_DEFAULT_WINDOW 110u
/* Transitions required before the fit replaces the prior: six parameters,
 * 0.4 s of data (enough for a short-period cycle to start). */
#define FCC_MLS_DEFAULT_MIN_TRANSITIONS 20u
/* Ridge toward the prior (see above); 0 disables it.  1e-3: in trim flight
 * the smallest eigenvalue of N (the direction where alpha, q and de are
 * collinear) is 2e-4 after 20 transitions and 1.3e-3 after 90 (CDRW,
 * measured), so 1e-3 holds that direction near the prior, while in the
 * pull-up it is 0.06 and the data decide.  Measured on the CDRW flight
 * (firmware/sid/README.md): with 1e-4 a fit after 20 transitions of trim
 * flight can be wild (the detector's worst fault-free innovation ratio over
 * 50 seeds 5.4), with 1e-3 it is 1.75; 1e-2 holds the stall too close to
 * the trim prior (2.0, larger errors). */
#define FCC_MLS_DEFAULT_RIDGE FCC_R(1e-3)
/* Largest accepted condition number of the equilibrated normal matrix.  The
 * solve loses about log10(cond) digits: 1e6 leaves 10 in double; float
 * keeps 1e4 so that at least 3 digits survive. */
#ifdef FCC_REAL_FLOAT
#define FCC_MLS_DEFAULT_MAX_COND FCC_R(1e4)
#else
#define FCC_MLS_DEFAULT_MAX_COND FCC_R(1e6)
#endif
/* Largest accepted rho(A_k) (0 disables the check). */
#define FCC_MLS_DEFAULT_MAX_RHO FCC_R(1.2)

/* Number of identified parameters, in the order a11, a12, a21, a22, b1, b2. */
#define FCC_MLS_N_PARAMS 6

typedef struct {
    uint16_t window;          /* h: transitions in the window, 4..FCC_MLS_MAX_WINDOW */
    uint16_t min_transitions; /* prior until this many transitions, 4..window */
    fcc_real_t ridge;         /* Tikhonov weight toward the prior, >= 0 */
    fcc_real_t max_cond;      /* conditioning guard, > 1 */
    fcc_real_t max_rho;       /* plausibility guard on rho(A_k); 0 = off */
    fcc_sid_model_t prior;    /* A0, B0 (c0): used until the window has data, and the ridge
                                 target; its c is ignored (taken as 0) without intercept */
    bool intercept;           /* fit the affine term c too (not in the paper; default false) */
} fcc_mls_config_t;

/* The current estimate (always finite). */
typedef struct {
    fcc_sid_model_t model;           /* A_k, B_k: last good model */
    fcc_real_t se[FCC_MLS_N_PARAMS]; /* standard errors (a11,a12,a21,a22,b1,b2); -1 = not available */
    fcc_real_t rho;                  /* rho(A_k) */
    fcc_real_t cond;                 /* condition number of the last solve (0 before any) */
    uint16_t n_transitions;          /* transitions now in the window */
    bool is_prior;                   /* model is the prior (not enough data yet) */
} fcc_mls_estimate_t;

/* One transition of the window: phi = [alpha, q, de], z = [alpha+, q+]. */
typedef struct {
    fcc_real_t phi[3];
    fcc_real_t z[2];
} fcc_mls_transition_t;

/* Running sums of the window about a reference point (ref_phi, ref_z), a
 * sample of the window, with d = phi - ref_phi and e = z - ref_z: sum d d^T
 * (upper triangle n00 n01 n02 n11 n12 n22), sum d e^T (3x2 row-major),
 * sum e_i^2, sum d, sum e.  The solve turns them into sums about the origin
 * (the paper's regression) or about the window means (the intercept); sums
 * about a recent sample keep the centring accurate in float. */
typedef struct {
    fcc_real_t n[6];
    fcc_real_t pz[6];
    fcc_real_t zz[2];
    fcc_real_t ps[3];
    fcc_real_t zs[2];
    fcc_real_t ref_phi[3];
    fcc_real_t ref_z[2];
} fcc_mls_sums_t;

typedef struct {
    fcc_mls_config_t cfg;
    fcc_mls_transition_t ring[FCC_MLS_MAX_WINDOW];
    uint16_t head;  /* slot of the next write (the oldest once the ring is full) */
    uint16_t count; /* transitions in the window */
    fcc_mls_sums_t sums;
    fcc_mls_sums_t shadow; /* exact re-sum in progress */
    uint16_t shadow_count;
    fcc_mls_estimate_t est;
} fcc_mls_t;

/* Fills cfg with the defaults above and the given prior (intercept off). */
void fcc_mls_config_default(fcc_mls_config_t *cfg, const fcc_sid_model_t *prior);

/* Checks a configuration: FCC_ERR_ARG on NULL or non-finite values,
 * FCC_ERR_RANGE on a window, count or guard outside its range. */
fcc_status_t fcc_mls_config_check(const fcc_mls_config_t *cfg);

/* Empties the window and sets the estimate to the prior. */
fcc_status_t fcc_mls_init(fcc_mls_t *mls, const fcc_mls_config_t *cfg);

/* Adds the transition (x, de) -> x_next, dropping the oldest when the window
 * is full.  FCC_ERR_NOT_FINITE (nothing changed) on a non-finite value. */
fcc_status_t fcc_mls_push(fcc_mls_t *mls, const fcc_real_t x[2], fcc_real_t de,
                          const fcc_real_t x_next[2]);

/* Re-estimates [A B] from the window.  FCC_OK when the estimate is the new
 * fit or the prior (too few transitions); FCC_ERR_SINGULAR when the
 * conditioning guard refused the fit, FCC_ERR_RANGE when rho(A) > max_rho,
 * FCC_ERR_NOT_FINITE when the fit was not finite: in those three cases the
 * last good model is kept (its standard errors too). */
fcc_status_t fcc_mls_solve(fcc_mls_t *mls);

/* push then solve; returns the first error. */
fcc_status_t fcc_mls_update(fcc_mls_t *mls, const fcc_real_t x[2], fcc_real_t de,
                            const fcc_real_t x_next[2]);

/* The current estimate (never NULL for a valid mls). */
const fcc_mls_estimate_t *fcc_mls_estimate(const fcc_mls_t *mls);

#endif /* FCC_MLS_H */
