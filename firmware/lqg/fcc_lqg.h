/*
 * fcc_lqg.h -- the missile pitch autopilot of S. K. Lee, "Application of
 * Discrete Stochastic Optimal Control System for Aircraft Autopilot Design"
 * (Korean Institute of Aeronautical Technology; "the paper" in firmware/lqg):
 * its sampled-data LQG design for a period T, and the per-step runtime (D/A
 * quantizer + steady-state Kalman filter + LQR command).
 *
 * Split on purpose:
 *  - fcc_lqg_design() runs once at start-up (or when T changes): ZOH
 *    discretisation (Van Loan), both Riccati equations by BOTH solvers
 *    (symplectic eigenvectors, the paper's method, and doubling) with a
 *    cross-check, gains and poles.  It computes in double in every build
 *    (fcc_mat64): single precision cannot hold the Riccati eigenvectors to
 *    1e-4 at T = 10 ms, and on the Cortex-M4F the software double costs only
 *    start-up time.  Only its results are converted to fcc_real_t.  Any
 *    failure leaves the previous design untouched.
 *  - fcc_lqg_ctrl_*() run every period in fcc_real_t: a handful of
 *    multiply-adds, no allocation, no failure except non-finite input, which
 *    leaves the state untouched.  An application (CAN I/O, scheduling) needs
 *    only this API.
 *
 * State x = [q (rad/s), alpha_T (rad), w_g (ft/s)], input u = elevator (rad),
 * measurement y = [q_g (rad/s), n_a (ft/s^2)].
 *
 * Filter (the seed's form, steady-state gains):
 *   update    x^_k   = xbar_k + L (y_k - H xbar_k)
 *   command   u_k    = sat(-K x^_k - K_u u_{k-1}, +-0.4 rad) -> D/A code -> u_applied
 *   propagate xbar_k+1 = Phi x^_k + Gamma0 u_applied + Gamma1 u_{k-1}
 *             (the commands the actuator really got: quantised and
 *             saturated; K_u = Gamma1 = 0 without a delay)
 * L = M H^T (H M H^T + R)^-1 with M the a-priori covariance
 * (M = Phi P+ Phi^T + Q_d, P+ = (I - L H) M).
 */
#ifndef FCC_LQG_H
#define FCC_LQG_H

#include "fcc_c2d.h"
#include "fcc_dare.h"

#define FCC_LQG_NX 3
#define FCC_LQG_NU 1
#define FCC_LQG_NY 2
/* The delay-augmented state z = [x; u_{k-1}]. */
#define FCC_LQG_NA (FCC_LQG_NX + FCC_LQG_NU)

/* Elevator authority, rad. */
#define FCC_LQG_U_MAX FCC_R(0.4)

/* Accepted sampling periods, s.  The paper studies 0.02-0.3 s.  The two
 * solvers still agree to 1e-11 from 0.1 ms to 3 s (measured; at 5 s the
 * Van Loan block exp(-F T) ~ e^20 costs the digits and the cross-check
 * refuses); outside 1 ms-1 s a missile short-period autopilot is absurd. */
#define FCC_LQG_T_MIN 0.001
#define FCC_LQG_T_MAX 1.0

#define FCC_LQG_BITS_MIN 2U
#define FCC_LQG_BITS_MAX 16U

/* Largest relative difference allowed between the two Riccati solvers
 * (max-entry-relative, on P, K, M and L; both run in double). */
#define FCC_LQG_AGREE_TOL 1e-10

typedef enum {
    FCC_LQG_SOLVER_HAMILTONIAN = 0, /* eigenvectors of the symplectic matrix (the paper) */
    FCC_LQG_SOLVER_DOUBLING = 1     /* structure-preserving doubling */
} fcc_lqg_solver_t;

/* The continuous plant, weights and sensor noise (defaults: the paper).
 * The design widens these to double before it computes anything. */
typedef struct {
    fcc_real_t f[FCC_LQG_NX * FCC_LQG_NX]; /* dx/dt = F x + G u + w eta_g */
    fcc_real_t g[FCC_LQG_NX];
    fcc_real_t w[FCC_LQG_NX];               /* gust input (unit-intensity white noise) */
    fcc_real_t wx[FCC_LQG_NX * FCC_LQG_NX]; /* cost weight A on x (symmetric, >= 0) */
    fcc_real_t wu;                          /* cost weight B on u (> 0) */
    fcc_real_t h[FCC_LQG_NY * FCC_LQG_NX];  /* y = H x + v */
    fcc_real_t gyro_var;                    /* E{v_g^2}, rad^2/s^2, > 0 */
    fcc_real_t accel_var;                   /* E{v_a^2}, ft^2/s^4, > 0 */
} fcc_lqg_plant_t;

/* Riccati bookkeeping of one equation (LQR or Kalman). */
typedef struct {
    double residual;     /* relative residual of the reported solution */
    double disagreement; /* max relative difference between the solvers */
    double rcond_u1;     /* Hamiltonian method: conditioning of U1 */
    uint16_t iterations; /* doubling steps */
} fcc_lqg_riccati_t;

/*
 * A known input delay d (0 <= d < T): the command computed from the sample at
 * t_k acts on the plant from t_k + d (computation + transport).  Over
 * [t_k, t_k+1) the plant sees u_{k-1} for d seconds, then u_k, so the
 * standard delayed-input ZOH discretisation (Franklin, Powell & Workman,
 * "Digital Control of Dynamic Systems", sec. 4.3.4) splits Gamma:
 *   x_k+1 = Phi x_k + Gamma1 u_{k-1} + Gamma0 u_k,
 *   Gamma0 = int_0^{T-d} e^{F s} ds G,  Gamma1 = e^{F (T-d)} int_0^d e^{F s} ds G,
 * and the LQR is designed for the augmented state z = [x; u_{k-1}]:
 *   z_k+1 = [[Phi, Gamma1], [0, 0]] z_k + [Gamma0; I] u_k,
 * with the continuous cost integrated over both parts of the period:
 *   [z; u]^T Qa [z; u],  Qa = blkdiag(Q(d), 0) + S^T Q(T-d) S,
 * Q(tau) = [[Q11, Q12], [Q12^T, Q22]](tau) of fcc_c2d_cost over tau, and S
 * mapping [x_k; u_{k-1}; u_k] to [x(t_k + d); u_k] = [[Phi(d), Gamma(d), 0],
 * [0, 0, I]].  The command is u_k = -K x^_k - K_u u_{k-1}.
 * The paper's Hamiltonian method needs Phia - Gammaa Q22^-1 Q12^T invertible;
 * for the augmented system it never is (its last row is the delay state's
 * zero dynamics: condition numbers >= 1e17 measured at T = 0.02-0.1 s), so
 * the augmented LQR is solved by doubling alone (its residual is checked,
 * and tests/vectors/lqg holds scipy's solution).  The Kalman filter needs
 * no augmentation (u_{k-1} is known exactly): its design is the same for
 * every d, by both solvers; only its prediction uses Gamma0 and Gamma1.
 * d = 0 is exactly the undelayed design (Gamma1 = 0, K_u = 0).
 */

/* Everything the design produced (row-major arrays, converted to fcc_real_t). */
typedef struct {
    fcc_real_t t;
    fcc_real_t delay;        /* d, s (0: no delay) */
    fcc_lqg_solver_t solver; /* which solver's X is reported (both are checked) */
    fcc_real_t phi[FCC_LQG_NX * FCC_LQG_NX];
    fcc_real_t gamma[FCC_LQG_NX * FCC_LQG_NU];  /* Gamma0 (Gamma when d = 0) */
    fcc_real_t gamma1[FCC_LQG_NX * FCC_LQG_NU]; /* Gamma1 (0 when d = 0) */
    fcc_real_t k_u;                             /* K_u (0 when d = 0) */
    /* d > 0: the augmented cost and Riccati solution (zero when d = 0) */
    fcc_real_t qa11[FCC_LQG_NA * FCC_LQG_NA];
    fcc_real_t qa12[FCC_LQG_NA];
    fcc_real_t qa22;
    fcc_real_t pa[FCC_LQG_NA * FCC_LQG_NA];
    fcc_real_t qd[FCC_LQG_NX * FCC_LQG_NX];
    fcc_real_t q11[FCC_LQG_NX * FCC_LQG_NX];
    fcc_real_t q12[FCC_LQG_NX * FCC_LQG_NU];
    fcc_real_t q22[FCC_LQG_NU * FCC_LQG_NU];
    fcc_real_t h[FCC_LQG_NY * FCC_LQG_NX];
    fcc_real_t r[FCC_LQG_NY * FCC_LQG_NY];
    fcc_real_t p[FCC_LQG_NX * FCC_LQG_NX];      /* LQR Riccati solution (d > 0: x block of pa) */
    fcc_real_t k[FCC_LQG_NU * FCC_LQG_NX];      /* u = -K x^ */
    fcc_real_t m[FCC_LQG_NX * FCC_LQG_NX];      /* a-priori estimation covariance */
    fcc_real_t p_post[FCC_LQG_NX * FCC_LQG_NX]; /* a-posteriori covariance (I - L H) M */
    fcc_real_t l[FCC_LQG_NX * FCC_LQG_NY];      /* filter gain, update form */
    /* Poles, sorted by decreasing modulus (then decreasing imaginary part). */
    fcc_real_t cl_re[FCC_LQG_NX]; /* eig(Phi - Gamma K); d > 0: the NX largest of the
                                     augmented loop (the fourth is the delay state's) */
    fcc_real_t cl_im[FCC_LQG_NX];
    fcc_real_t est_re[FCC_LQG_NX]; /* eig(Phi - Phi L H) = eig((I - L H) Phi) */
    fcc_real_t est_im[FCC_LQG_NX];
    fcc_lqg_riccati_t lqr; /* d > 0: doubling only (disagreement 0, rcond_u1 0) */
    fcc_lqg_riccati_t kf;
} fcc_lqg_design_t;

/* The design in double, as computed (converted to fcc_lqg_design_t at the end). */
typedef struct {
    double phi[FCC_LQG_NX * FCC_LQG_NX];
    double gamma[FCC_LQG_NX * FCC_LQG_NU];
    double qd[FCC_LQG_NX * FCC_LQG_NX];
    double q11[FCC_LQG_NX * FCC_LQG_NX];
    double q12[FCC_LQG_NX * FCC_LQG_NU];
    double q22[FCC_LQG_NU * FCC_LQG_NU];
    double h[FCC_LQG_NY * FCC_LQG_NX];
    double r[FCC_LQG_NY * FCC_LQG_NY];
    double p[FCC_LQG_NX * FCC_LQG_NX];
    double k[FCC_LQG_NU * FCC_LQG_NX];
    double m[FCC_LQG_NX * FCC_LQG_NX];
    double p_post[FCC_LQG_NX * FCC_LQG_NX];
    double l[FCC_LQG_NX * FCC_LQG_NY];
    double cl_re[FCC_LQG_NX], cl_im[FCC_LQG_NX];
    double est_re[FCC_LQG_NX], est_im[FCC_LQG_NX];
    double gamma1[FCC_LQG_NX * FCC_LQG_NU];
    double k_u;
    double qa11[FCC_LQG_NA * FCC_LQG_NA];
    double qa12[FCC_LQG_NA];
    double qa22;
    double pa[FCC_LQG_NA * FCC_LQG_NA];
} fcc_lqg_design64_t;

/* Scratch of the design (~9 KB; the two phases share storage). */
typedef struct {
    union {
        fcc_c2d_ws_t c2d;
        fcc_dare_ws_t dare;
    } u;
    fcc_lqg_design64_t d; /* the design under construction */
    double x_alt[FCC_LQG_NX * FCC_LQG_NX];
    double g_alt[FCC_LQG_NX * FCC_LQG_NY];
    double a_t[FCC_LQG_NX * FCC_LQG_NX];
    double b_t[FCC_LQG_NX * FCC_LQG_NY];
    double tmp[FCC_LQG_NX * FCC_LQG_NX];
    /* A design in progress (fcc_lqg_design_begin / _slice). */
    const fcc_lqg_plant_t *plant;
    double t;
    fcc_lqg_solver_t solver;
    unsigned slice;               /* next slice, FCC_LQG_DESIGN_SLICES = none pending */
    fcc_dare_info_t first;        /* the first solver's report, kept for the second slice */
    fcc_lqg_riccati_t lqr;
    fcc_lqg_riccati_t kf;
    double delay;                 /* d of the design in progress */
    /* delay: the augmented system, cost blocks and map S, its closed loop */
    double aug_a[FCC_LQG_NA * FCC_LQG_NA];
    double aug_b[FCC_LQG_NA];
    double aug_k[FCC_LQG_NA];
    double aug_w[(FCC_LQG_NA + 1) * (FCC_LQG_NA + 1)];
    double aug_s[FCC_LQG_NA * (FCC_LQG_NA + 1)];
    double aug_t[(FCC_LQG_NA + 1) * (FCC_LQG_NA + 1)];
    double aug_re[FCC_LQG_NA], aug_im[FCC_LQG_NA];
} fcc_lqg_ws_t;

/* The design runs in this many slices (fcc_lqg_design_slice), each a bounded
 * piece of work, so that a caller with a deadline can run it between control
 * steps: ZOH, noise, cost; LQR by the chosen solver, by the other + cross-check;
 * the same for the Kalman filter; poles and the conversion of the result. */
#define FCC_LQG_DESIGN_SLICES 8u

/* The paper's missile (Mach 1.2, sea level), weights A = diag(0.12, 11, 0),
 * B = 1, and noise variances 0.8 / 0.8. */
fcc_status_t fcc_lqg_plant_default(fcc_lqg_plant_t *plant);

/*
 * Design for period t.  Statuses: FCC_ERR_ARG (NULL, unknown solver, NaN),
 * FCC_ERR_RANGE (t outside [FCC_LQG_T_MIN, FCC_LQG_T_MAX], a variance or wu
 * not > 0), FCC_ERR_NOT_STABILIZABLE / FCC_ERR_NOT_DETECTABLE (LQR: (Phi,
 * Gamma) / cost; Kalman: (Phi, H) is reported as NOT_DETECTABLE, (Phi, Q_d)
 * as NOT_STABILIZABLE), FCC_ERR_SINGULAR (the Hamiltonian method needs an
 * invertible Phi - Gamma Q22^-1 Q12^T), FCC_ERR_NO_CONVERGENCE,
 * FCC_ERR_DISAGREE (solvers differ by more than FCC_LQG_AGREE_TOL), and the
 * linear-algebra codes.  *out is written only on FCC_OK.
 */
fcc_status_t fcc_lqg_design(const fcc_lqg_plant_t *plant, double t, fcc_lqg_solver_t solver,
                            fcc_lqg_design_t *out, fcc_lqg_ws_t *ws);

/* The same design in slices: begin checks the inputs (the statuses above) and
 * remembers plant (which must stay valid until the end), t and solver; each
 * slice call does the next piece: FCC_ERR_AGAIN while slices remain, FCC_OK
 * when the last one has written *out, or the design's error (the design is
 * then over).  fcc_lqg_design is begin + slices until done. */
fcc_status_t fcc_lqg_design_begin(const fcc_lqg_plant_t *plant, double t, fcc_lqg_solver_t solver,
                                  fcc_lqg_ws_t *ws);
fcc_status_t fcc_lqg_design_slice(fcc_lqg_ws_t *ws, fcc_lqg_design_t *out);

/* The same for a known input delay d (see above): FCC_ERR_RANGE unless
 * 0 <= d < T, FCC_ERR_ARG for a non-finite d.  d = 0 is fcc_lqg_design();
 * with d > 0 the LQR slices run delay_blocks + the augmented doubling. */
fcc_status_t fcc_lqg_design_delayed(const fcc_lqg_plant_t *plant, double t, double delay,
                                    fcc_lqg_solver_t solver, fcc_lqg_design_t *out,
                                    fcc_lqg_ws_t *ws);
fcc_status_t fcc_lqg_design_begin_delayed(const fcc_lqg_plant_t *plant, double t, double delay,
                                          fcc_lqg_solver_t solver, fcc_lqg_ws_t *ws);

/* ---- D/A converter ------------------------------------------------------------ */

/* N bits over [-0.4, +0.4] rad: LSB = 0.8 / 2^N,
 * code = clamp(round(u / LSB), -2^(N-1), 2^(N-1) - 1), u_applied = code LSB.
 * round() is half away from zero (C99 round). */
typedef struct {
    uint8_t bits;
    fcc_real_t lsb;
    int32_t code_min;
    int32_t code_max;
} fcc_lqg_dac_t;

/* FCC_ERR_RANGE for bits outside [FCC_LQG_BITS_MIN, FCC_LQG_BITS_MAX]. */
fcc_status_t fcc_lqg_dac_init(fcc_lqg_dac_t *dac, uint8_t bits);
/* NaN/Inf u: FCC_ERR_NOT_FINITE with the safe code 0 (u_applied = 0). */
fcc_status_t fcc_lqg_dac_convert(const fcc_lqg_dac_t *dac, fcc_real_t u, int32_t *code,
                                 fcc_real_t *u_applied);
/* The elevator angle of a code (clamped to the converter's range). */
fcc_status_t fcc_lqg_dac_value(const fcc_lqg_dac_t *dac, int32_t code, fcc_real_t *u_applied);

/* ---- runtime controller ----------------------------------------------------- */

typedef struct {
    fcc_real_t x_hat[FCC_LQG_NX]; /* estimate the command was computed from */
    fcc_real_t u_cmd;             /* -K x^, before the limit */
    fcc_real_t u_sat;             /* after the +-0.4 rad limit */
    int32_t code;                 /* D/A code for the actuator frame */
    fcc_real_t u_applied;         /* code * LSB */
    bool saturated;               /* |u_cmd| > 0.4 rad */
    bool measured;                /* false for a prediction-only step */
} fcc_lqg_output_t;

typedef struct {
    fcc_real_t phi[FCC_LQG_NX * FCC_LQG_NX];
    fcc_real_t gamma[FCC_LQG_NX];  /* Gamma0 */
    fcc_real_t gamma1[FCC_LQG_NX]; /* Gamma1 */
    fcc_real_t k[FCC_LQG_NX];
    fcc_real_t k_u;
    fcc_real_t l[FCC_LQG_NX * FCC_LQG_NY];
    fcc_real_t h[FCC_LQG_NY * FCC_LQG_NX];
    fcc_lqg_dac_t dac;
    fcc_real_t x_pred[FCC_LQG_NX]; /* xbar for the next sample */
    fcc_real_t u_prev;             /* u_{k-1} as applied (0 after a reset) */
    uint32_t updates;              /* steps with a measurement */
    uint32_t predictions;          /* prediction-only steps */
} fcc_lqg_ctrl_t;

/* Take the gains of a design, set up a D/A of `bits` bits, and start from the
 * prediction x0 (NULL: zero).  FCC_ERR_RANGE for bad bits, FCC_ERR_NOT_FINITE
 * for a design or x0 that is not finite. */
fcc_status_t fcc_lqg_ctrl_init(fcc_lqg_ctrl_t *c, const fcc_lqg_design_t *d, uint8_t bits,
                               const fcc_real_t x0[FCC_LQG_NX]);
/* Restart the estimate from x0 (NULL: zero); gains and counters are kept. */
fcc_status_t fcc_lqg_ctrl_reset(fcc_lqg_ctrl_t *c, const fcc_real_t x0[FCC_LQG_NX]);
/* One period with the measurement y = [q_g, n_a].  A non-finite y returns
 * FCC_ERR_NOT_FINITE and changes nothing (neither *c nor *out): call
 * fcc_lqg_ctrl_predict() for this period instead. */
fcc_status_t fcc_lqg_ctrl_step(fcc_lqg_ctrl_t *c, const fcc_real_t y[FCC_LQG_NY],
                               fcc_lqg_output_t *out);
/* One period without a usable measurement (stale frame, sensor fault):
 * x^ = xbar, then command and propagation as in a normal step. */
fcc_status_t fcc_lqg_ctrl_predict(fcc_lqg_ctrl_t *c, fcc_lqg_output_t *out);

#endif /* FCC_LQG_H */
