/* fcc_lqg_design.c -- the sampled-data LQG design (fcc_lqg.h). */
#include "fcc_lqg.h"

#include <string.h>

#include "fcc_types.h" /* FCC_TRY */

#define NX FCC_LQG_NX
#define NU FCC_LQG_NU
#define NY FCC_LQG_NY
#define NA FCC_LQG_NA
#define NW (NA + NU) /* [x; u_{k-1}; u_k] */

fcc_status_t fcc_lqg_plant_default(fcc_lqg_plant_t *plant)
{
    static const fcc_real_t f[NX * NX] = {FCC_R(-1.2132), FCC_R(-177.0), FCC_R(0.0),
                                          FCC_R(1.0),     FCC_R(-4.03),  FCC_R(0.00149),
                                          FCC_R(0.0),     FCC_R(0.0),    FCC_R(-2.0)};
    static const fcc_real_t g[NX] = {FCC_R(-69.3), FCC_R(-0.2978), FCC_R(0.0)};
    /* gust: sqrt(2 tau_w) sigma_w / tau_w = 24 ft/s per unit noise, enters alpha_T / U0 */
    static const fcc_real_t w[NX] = {FCC_R(0.0), FCC_R(-0.0179), FCC_R(-24.0)};
    static const fcc_real_t wx[NX * NX] = {FCC_R(0.12), FCC_R(0.0), FCC_R(0.0),
                                           FCC_R(0.0),  FCC_R(11.0), FCC_R(0.0),
                                           FCC_R(0.0),  FCC_R(0.0), FCC_R(0.0)};
    static const fcc_real_t h[NY * NX] = {FCC_R(1.0),    FCC_R(0.0),    FCC_R(0.0),
                                          FCC_R(-26.74), FCC_R(-568.4), FCC_R(0.0)};
    if (plant == NULL) {
        return FCC_ERR_ARG;
    }
    for (unsigned i = 0; i < NX * NX; ++i) {
        plant->f[i] = f[i];
        plant->wx[i] = wx[i];
    }
    for (unsigned i = 0; i < NX; ++i) {
        plant->g[i] = g[i];
        plant->w[i] = w[i];
    }
    for (unsigned i = 0; i < NY * NX; ++i) {
        plant->h[i] = h[i];
    }
    plant->wu = FCC_R(1.0);
    plant->gyro_var = FCC_R(0.8);
    plant->accel_var = FCC_R(0.8);
    return FCC_OK;
}

static bool all_finite(const fcc_real_t *v, unsigned n)
{
    for (unsigned i = 0; i < n; ++i) {
        if (!FCC_IS_FINITE(v[i])) {
            return false;
        }
    }
    return true;
}

static fcc_status_t check_inputs(const fcc_lqg_plant_t *plant, double t, fcc_lqg_solver_t solver)
{
    if (solver != FCC_LQG_SOLVER_HAMILTONIAN && solver != FCC_LQG_SOLVER_DOUBLING) {
        return FCC_ERR_ARG;
    }
    if (!FCC_IS_FINITE(t) || !all_finite(plant->f, NX * NX) || !all_finite(plant->g, NX) ||
        !all_finite(plant->w, NX) || !all_finite(plant->wx, NX * NX) ||
        !all_finite(plant->h, NY * NX) || !FCC_IS_FINITE(plant->wu) ||
        !FCC_IS_FINITE(plant->gyro_var) || !FCC_IS_FINITE(plant->accel_var)) {
        return FCC_ERR_ARG;
    }
    if (t < FCC_LQG_T_MIN || t > FCC_LQG_T_MAX || !(plant->wu > FCC_R(0.0)) ||
        !(plant->gyro_var > FCC_R(0.0)) || !(plant->accel_var > FCC_R(0.0))) {
        return FCC_ERR_RANGE;
    }
    return FCC_OK;
}

/* The plant's continuous matrices in double (each discretisation slice
 * rebuilds them: the scratch in between belongs to the c2d routines). */
typedef struct {
    double f[NX * NX];
    double g[NX * NU];
    double wx[NX * NX];
    double wu[NU * NU];
} plant64_t;

static void plant64(const fcc_lqg_plant_t *plant, plant64_t *p)
{
    for (unsigned i = 0; i < NX * NX; ++i) {
        p->f[i] = (double)plant->f[i];
        p->wx[i] = (double)plant->wx[i];
    }
    for (unsigned i = 0; i < NX; ++i) {
        p->g[i] = (double)plant->g[i];
    }
    p->wu[0] = (double)plant->wu;
}

/* Slice 0: Phi, Gamma. */
static fcc_status_t discretise_zoh(fcc_lqg_ws_t *ws)
{
    plant64_t p;
    plant64(ws->plant, &p);
    const fcc_mat64_t f = FCC_MAT64(NX, NX, p.f);
    const fcc_mat64_t g = FCC_MAT64(NX, NU, p.g);
    fcc_mat64_t phi = FCC_MAT64(NX, NX, ws->d.phi);
    fcc_mat64_t gamma = FCC_MAT64(NX, NU, ws->d.gamma);
    return fcc_c2d_zoh(&f, &g, ws->t, &phi, &gamma, &ws->u.c2d);
}

/* Slice 1: Q_d of the noise density w w^T. */
static fcc_status_t discretise_noise(fcc_lqg_ws_t *ws)
{
    plant64_t p;
    plant64(ws->plant, &p);
    for (unsigned i = 0; i < NX; ++i) {
        for (unsigned j = 0; j < NX; ++j) {
            ws->tmp[i * NX + j] = (double)ws->plant->w[i] * (double)ws->plant->w[j];
        }
    }
    const fcc_mat64_t f = FCC_MAT64(NX, NX, p.f);
    const fcc_mat64_t qc = FCC_MAT64(NX, NX, ws->tmp);
    fcc_mat64_t qd = FCC_MAT64(NX, NX, ws->d.qd);
    return fcc_c2d_noise(&f, &qc, ws->t, &qd, &ws->u.c2d);
}

/* Slice 2: the sampled cost Q11, Q12, Q22. */
static fcc_status_t discretise_cost(fcc_lqg_ws_t *ws)
{
    plant64_t p;
    plant64(ws->plant, &p);
    const fcc_mat64_t f = FCC_MAT64(NX, NX, p.f);
    const fcc_mat64_t g = FCC_MAT64(NX, NU, p.g);
    const fcc_mat64_t wx = FCC_MAT64(NX, NX, p.wx);
    const fcc_mat64_t wu = FCC_MAT64(NU, NU, p.wu);
    fcc_mat64_t q11 = FCC_MAT64(NX, NX, ws->d.q11);
    fcc_mat64_t q12 = FCC_MAT64(NX, NU, ws->d.q12);
    fcc_mat64_t q22 = FCC_MAT64(NU, NU, ws->d.q22);
    return fcc_c2d_cost(&f, &g, &wx, &wu, ws->t, &q11, &q12, &q22, &ws->u.c2d);
}

static fcc_status_t solve_with(fcc_lqg_solver_t solver, const fcc_dare_problem_t *p, fcc_mat64_t *x,
                               fcc_dare_info_t *info, fcc_dare_ws_t *ws)
{
    return (solver == FCC_LQG_SOLVER_HAMILTONIAN) ? fcc_dare_hamiltonian(p, x, info, ws)
                                                  : fcc_dare_doubling(p, x, info, ws);
}

/* Riccati equation p solved by both methods, in two slices: `solver` into
 * x/gain (first), then the other into x_alt/gain_alt and the comparison
 * (second, which fills rep: residual, iterations, disagreement). */
typedef fcc_status_t (*gain_fn_t)(const fcc_dare_problem_t *p, const fcc_mat64_t *x, fcc_mat64_t *gain,
                                  fcc_lqg_ws_t *ws);

static fcc_lqg_solver_t other_solver(fcc_lqg_solver_t solver)
{
    return (solver == FCC_LQG_SOLVER_HAMILTONIAN) ? FCC_LQG_SOLVER_DOUBLING
                                                  : FCC_LQG_SOLVER_HAMILTONIAN;
}

static fcc_status_t solve_first(const fcc_dare_problem_t *p, fcc_mat64_t *x, fcc_mat64_t *gain,
                                gain_fn_t gain_fn, fcc_lqg_ws_t *ws)
{
    ws->first = (fcc_dare_info_t){0U, 0.0, 0.0, 0.0};
    FCC_TRY(solve_with(ws->solver, p, x, &ws->first, &ws->u.dare));
    return gain_fn(p, x, gain, ws);
}

static fcc_status_t solve_second(const fcc_dare_problem_t *p, const fcc_mat64_t *x,
                                 const fcc_mat64_t *gain, fcc_mat64_t *x_alt, fcc_mat64_t *gain_alt,
                                 gain_fn_t gain_fn, fcc_lqg_riccati_t *rep, fcc_lqg_ws_t *ws)
{
    const fcc_dare_info_t info = ws->first;
    fcc_dare_info_t info_alt = {0U, 0.0, 0.0, 0.0};
    FCC_TRY(solve_with(other_solver(ws->solver), p, x_alt, &info_alt, &ws->u.dare));
    FCC_TRY(gain_fn(p, x_alt, gain_alt, ws));
    double dx = 0.0;
    double dg = 0.0;
    FCC_TRY(fcc_mat64_rel_diff(x_alt, x, &dx));
    FCC_TRY(fcc_mat64_rel_diff(gain_alt, gain, &dg));
    rep->residual = info.residual;
    rep->disagreement = (dx > dg) ? dx : dg;
    rep->iterations = (ws->solver == FCC_LQG_SOLVER_DOUBLING) ? info.iterations : info_alt.iterations;
    rep->rcond_u1 = (ws->solver == FCC_LQG_SOLVER_HAMILTONIAN) ? info.rcond_u1 : info_alt.rcond_u1;
    return (rep->disagreement <= FCC_LQG_AGREE_TOL) ? FCC_OK : FCC_ERR_DISAGREE;
}

/* LQR gain K = (Q22 + G^T P G)^-1 (G^T P Phi + Q12^T). */
static fcc_status_t lqr_gain(const fcc_dare_problem_t *p, const fcc_mat64_t *x, fcc_mat64_t *gain,
                             fcc_lqg_ws_t *ws)
{
    return fcc_dare_gain(p, x, gain, &ws->u.dare);
}

/* Filter gain, update form: L = M H^T (H M H^T + R)^-1, i.e. (H M H^T + R) L^T = H M
 * (M and H M H^T + R symmetric).  The problem is (Phi^T, H^T, Q_d, R). */
static fcc_status_t kf_gain(const fcc_dare_problem_t *p, const fcc_mat64_t *x, fcc_mat64_t *gain,
                            fcc_lqg_ws_t *ws)
{
    double hm[NY * NX];
    double s[NY * NY];
    double lt[NY * NX];
    fcc_mat64_t mhm = FCC_MAT64(NY, NX, hm);
    fcc_mat64_t ms = FCC_MAT64(NY, NY, s);
    fcc_mat64_t mlt = FCC_MAT64(NY, NX, lt);
    FCC_TRY(fcc_mat64_mul_tn(p->b, x, &mhm)); /* b = H^T: b^T M = H M */
    FCC_TRY(fcc_mat64_mul(&mhm, p->b, &ms));  /* H M H^T */
    FCC_TRY(fcc_mat64_add(&ms, p->r, &ms));
    FCC_TRY(fcc_mat64_solve(&ms, &mhm, &mlt, &ws->u.dare.lu));
    return fcc_mat64_trans(&mlt, gain);
}

/* The Kalman problem speaks of (Phi^T, H^T): name its failures in filter terms. */
static fcc_status_t kf_status(fcc_status_t st)
{
    if (st == FCC_ERR_NOT_STABILIZABLE) {
        return FCC_ERR_NOT_DETECTABLE;
    }
    if (st == FCC_ERR_NOT_DETECTABLE) {
        return FCC_ERR_NOT_STABILIZABLE;
    }
    return st;
}

/* Slices 3 and 4: the LQR, chosen solver then the other. */
static fcc_status_t design_lqr(fcc_lqg_ws_t *ws, bool second)
{
    fcc_lqg_design64_t *d = &ws->d;
    const fcc_mat64_t phi = FCC_MAT64(NX, NX, d->phi);
    const fcc_mat64_t gamma = FCC_MAT64(NX, NU, d->gamma);
    const fcc_mat64_t q11 = FCC_MAT64(NX, NX, d->q11);
    const fcc_mat64_t q12 = FCC_MAT64(NX, NU, d->q12);
    const fcc_mat64_t q22 = FCC_MAT64(NU, NU, d->q22);
    const fcc_dare_problem_t p = {&phi, &gamma, &q11, &q22, &q12};
    fcc_mat64_t x = FCC_MAT64(NX, NX, d->p);
    fcc_mat64_t k = FCC_MAT64(NU, NX, d->k);
    fcc_mat64_t x_alt = FCC_MAT64(NX, NX, ws->x_alt);
    fcc_mat64_t k_alt = FCC_MAT64(NU, NX, ws->g_alt);
    return second ? solve_second(&p, &x, &k, &x_alt, &k_alt, lqr_gain, &ws->lqr, ws)
                  : solve_first(&p, &x, &k, lqr_gain, ws);
}

/* Slices 5 and 6: the Kalman filter (the dual problem), then P+ = (I - L H) M. */
static fcc_status_t design_kf(fcc_lqg_ws_t *ws, bool second)
{
    fcc_lqg_design64_t *d = &ws->d;
    fcc_mat64_t phi = FCC_MAT64(NX, NX, d->phi);
    fcc_mat64_t h = FCC_MAT64(NY, NX, d->h);
    fcc_mat64_t a = FCC_MAT64(NX, NX, ws->a_t);
    fcc_mat64_t b = FCC_MAT64(NX, NY, ws->b_t);
    if (!second) {
        FCC_TRY(fcc_mat64_trans(&phi, &a));
        FCC_TRY(fcc_mat64_trans(&h, &b));
    }
    const fcc_mat64_t qd = FCC_MAT64(NX, NX, d->qd);
    const fcc_mat64_t r = FCC_MAT64(NY, NY, d->r);
    const fcc_dare_problem_t p = {&a, &b, &qd, &r, NULL};
    fcc_mat64_t x = FCC_MAT64(NX, NX, d->m);
    fcc_mat64_t l = FCC_MAT64(NX, NY, d->l);
    if (!second) {
        return kf_status(solve_first(&p, &x, &l, kf_gain, ws));
    }
    fcc_mat64_t x_alt = FCC_MAT64(NX, NX, ws->x_alt);
    fcc_mat64_t l_alt = FCC_MAT64(NX, NY, ws->g_alt);
    FCC_TRY(kf_status(solve_second(&p, &x, &l, &x_alt, &l_alt, kf_gain, &ws->kf, ws)));
    fcc_mat64_t lh = FCC_MAT64(NX, NX, ws->tmp);
    fcc_mat64_t pp = FCC_MAT64(NX, NX, d->p_post);
    FCC_TRY(fcc_mat64_mul(&l, &h, &lh));
    FCC_TRY(fcc_mat64_mul(&lh, &x, &pp));
    FCC_TRY(fcc_mat64_sub(&x, &pp, &pp));
    return fcc_mat64_symmetrize(&pp);
}

/* w(r0.., c0..) += [[q11, q12], [q12^T, q22]] over tau, the cost of one hold
 * interval of length tau for [x; u] at its start. */
static fcc_status_t add_cost_block(plant64_t *pl, double tau, double *w, unsigned ld,
                                   fcc_lqg_ws_t *ws)
{
    double q11[NX * NX];
    double q12[NX * NU];
    double q22[NU * NU];
    const fcc_mat64_t f = FCC_MAT64(NX, NX, pl->f);
    const fcc_mat64_t g = FCC_MAT64(NX, NU, pl->g);
    const fcc_mat64_t wx = FCC_MAT64(NX, NX, pl->wx);
    const fcc_mat64_t wu = FCC_MAT64(NU, NU, pl->wu);
    fcc_mat64_t m11 = FCC_MAT64(NX, NX, q11);
    fcc_mat64_t m12 = FCC_MAT64(NX, NU, q12);
    fcc_mat64_t m22 = FCC_MAT64(NU, NU, q22);
    FCC_TRY(fcc_c2d_cost(&f, &g, &wx, &wu, tau, &m11, &m12, &m22, &ws->u.c2d));
    for (unsigned i = 0; i < NX; ++i) {
        for (unsigned j = 0; j < NX; ++j) {
            w[i * ld + j] += q11[i * NX + j];
        }
        w[i * ld + NX] += q12[i];
        w[NX * ld + i] += q12[i];
    }
    w[NX * ld + NX] += q22[0];
    return FCC_OK;
}

/* Gamma0, Gamma1 and the augmented cost Qa (NW x NW) for delay d. */
static fcc_status_t delay_blocks(plant64_t *pl, double t, double delay,
                                 fcc_lqg_design64_t *d, fcc_lqg_ws_t *ws)
{
    double phi_d[NX * NX];
    double gam_d[NX * NU];
    double phi_r[NX * NX]; /* Phi(T - d) */
    const fcc_mat64_t f = FCC_MAT64(NX, NX, pl->f);
    const fcc_mat64_t g = FCC_MAT64(NX, NU, pl->g);
    fcc_mat64_t mphi_d = FCC_MAT64(NX, NX, phi_d);
    fcc_mat64_t mgam_d = FCC_MAT64(NX, NU, gam_d);
    fcc_mat64_t mphi_r = FCC_MAT64(NX, NX, phi_r);
    fcc_mat64_t mgam0 = FCC_MAT64(NX, NU, d->gamma);
    fcc_mat64_t mgam1 = FCC_MAT64(NX, NU, d->gamma1);
    FCC_TRY(fcc_c2d_zoh(&f, &g, delay, &mphi_d, &mgam_d, &ws->u.c2d));
    FCC_TRY(fcc_c2d_zoh(&f, &g, t - delay, &mphi_r, &mgam0, &ws->u.c2d));
    FCC_TRY(fcc_mat64_mul(&mphi_r, &mgam_d, &mgam1));
    /* Qa = blkdiag(Q(d), 0) + S^T Q(T - d) S, S = [[Phi(d), Gamma(d), 0], [0, 0, I]] */
    double *qa = ws->aug_w;   /* NW x NW */
    double *qr = ws->aug_t;   /* Q(T - d), NA x NA (leading block of an NW buffer) */
    double *sm = ws->aug_s;   /* S, NA x NW */
    for (unsigned i = 0; i < NW * NW; ++i) {
        qa[i] = 0.0;
        qr[i] = 0.0;
    }
    for (unsigned i = 0; i < NA * NW; ++i) {
        sm[i] = 0.0;
    }
    FCC_TRY(add_cost_block(pl, delay, qa, NW, ws));
    FCC_TRY(add_cost_block(pl, t - delay, qr, NA, ws));
    for (unsigned i = 0; i < NX; ++i) {
        for (unsigned j = 0; j < NX; ++j) {
            sm[i * NW + j] = phi_d[i * NX + j];
        }
        sm[i * NW + NX] = gam_d[i];
    }
    sm[NX * NW + NA] = 1.0;
    for (unsigned i = 0; i < NW; ++i) {
        for (unsigned j = 0; j < NW; ++j) {
            double acc = 0.0;
            for (unsigned a = 0; a < NA; ++a) {
                for (unsigned b = 0; b < NA; ++b) {
                    acc += sm[a * NW + i] * qr[a * NA + b] * sm[b * NW + j];
                }
            }
            qa[i * NW + j] += acc;
        }
    }
    for (unsigned i = 0; i < NA; ++i) {
        for (unsigned j = 0; j < NA; ++j) {
            d->qa11[i * NA + j] = 0.5 * (qa[i * NW + j] + qa[j * NW + i]);
        }
        d->qa12[i] = qa[i * NW + NA];
    }
    d->qa22 = qa[NA * NW + NA];
    return FCC_OK;
}

/* The augmented LQR by doubling (see fcc_lqg.h for why not the Hamiltonian). */
static fcc_status_t design_lqr_delayed(fcc_lqg_design64_t *d, fcc_lqg_riccati_t *rep,
                                       fcc_lqg_ws_t *ws)
{
    double *a = ws->aug_a;
    for (unsigned i = 0; i < NA * NA; ++i) {
        a[i] = 0.0;
    }
    for (unsigned i = 0; i < NX; ++i) {
        for (unsigned j = 0; j < NX; ++j) {
            a[i * NA + j] = d->phi[i * NX + j];
        }
        a[i * NA + NX] = d->gamma1[i];
        ws->aug_b[i] = d->gamma[i];
    }
    ws->aug_b[NX] = 1.0;
    const fcc_mat64_t ma = FCC_MAT64(NA, NA, a);
    const fcc_mat64_t mb = FCC_MAT64(NA, NU, ws->aug_b);
    const fcc_mat64_t q11 = FCC_MAT64(NA, NA, d->qa11);
    const fcc_mat64_t q12 = FCC_MAT64(NA, NU, d->qa12);
    const fcc_mat64_t q22 = FCC_MAT64(NU, NU, &d->qa22);
    const fcc_dare_problem_t p = {&ma, &mb, &q11, &q22, &q12};
    fcc_mat64_t x = FCC_MAT64(NA, NA, d->pa);
    fcc_mat64_t k = FCC_MAT64(NU, NA, ws->aug_k);
    fcc_dare_info_t info = {0U, 0.0, 0.0, 0.0};
    FCC_TRY(fcc_dare_doubling(&p, &x, &info, &ws->u.dare));
    FCC_TRY(fcc_dare_gain(&p, &x, &k, &ws->u.dare));
    for (unsigned i = 0; i < NX; ++i) {
        d->k[i] = ws->aug_k[i];
        for (unsigned j = 0; j < NX; ++j) {
            d->p[i * NX + j] = d->pa[i * NA + j];
        }
    }
    d->k_u = ws->aug_k[NX];
    rep->residual = info.residual;
    rep->disagreement = 0.0;
    rep->iterations = info.iterations;
    rep->rcond_u1 = 0.0;
    /* closed loop of the augmented system: a - b k */
    double acl[NA * NA];
    for (unsigned i = 0; i < NA; ++i) {
        for (unsigned j = 0; j < NA; ++j) {
            acl[i * NA + j] = a[i * NA + j] - ws->aug_b[i] * ws->aug_k[j];
        }
    }
    const fcc_mat64_t mcl = FCC_MAT64(NA, NA, acl);
    return fcc_mat64_eig(&mcl, ws->aug_re, ws->aug_im, NULL, &ws->u.dare.eig);
}

/* Sort eigenvalues by decreasing modulus, then decreasing imaginary part. */
static void sort_poles(double *re, double *im, unsigned n)
{
    for (unsigned i = 1; i < n; ++i) {
        const double r = re[i];
        const double m = im[i];
        const double mod = hypot(r, m);
        unsigned j = i;
        while (j > 0U) {
            const double pmod = hypot(re[j - 1U], im[j - 1U]);
            if (pmod > mod || (pmod == mod && im[j - 1U] >= m)) {
                break;
            }
            re[j] = re[j - 1U];
            im[j] = im[j - 1U];
            --j;
        }
        re[j] = r;
        im[j] = m;
    }
}

static fcc_status_t poles(fcc_lqg_design64_t *d, bool delayed, fcc_lqg_ws_t *ws)
{
    const fcc_mat64_t phi = FCC_MAT64(NX, NX, d->phi);
    const fcc_mat64_t gamma = FCC_MAT64(NX, NU, d->gamma);
    const fcc_mat64_t k = FCC_MAT64(NU, NX, d->k);
    const fcc_mat64_t l = FCC_MAT64(NX, NY, d->l);
    const fcc_mat64_t h = FCC_MAT64(NY, NX, d->h);
    fcc_mat64_t t1 = FCC_MAT64(NX, NX, ws->tmp);
    fcc_mat64_t t2 = FCC_MAT64(NX, NX, ws->x_alt);
    fcc_mat64_t acl = FCC_MAT64(NX, NX, ws->a_t);
    if (delayed) {
        /* the augmented loop's poles (design_lqr_delayed), the NX largest */
        sort_poles(ws->aug_re, ws->aug_im, NA);
        for (unsigned i = 0; i < NX; ++i) {
            d->cl_re[i] = ws->aug_re[i];
            d->cl_im[i] = ws->aug_im[i];
        }
    } else {
        FCC_TRY(fcc_mat64_mul(&gamma, &k, &t1));
        FCC_TRY(fcc_mat64_sub(&phi, &t1, &acl));
        FCC_TRY(fcc_mat64_eig(&acl, d->cl_re, d->cl_im, NULL, &ws->u.dare.eig));
    }
    FCC_TRY(fcc_mat64_mul(&l, &h, &t1));
    FCC_TRY(fcc_mat64_mul(&phi, &t1, &t2));
    FCC_TRY(fcc_mat64_sub(&phi, &t2, &acl));
    FCC_TRY(fcc_mat64_eig(&acl, d->est_re, d->est_im, NULL, &ws->u.dare.eig));
    sort_poles(d->cl_re, d->cl_im, NX);
    sort_poles(d->est_re, d->est_im, NX);
    return FCC_OK;
}

/* dst[i] = (fcc_real_t)src[i]: the one place the design changes precision. */
static void narrow(fcc_real_t *dst, const double *src, unsigned n)
{
    for (unsigned i = 0; i < n; ++i) {
        dst[i] = (fcc_real_t)src[i];
    }
}

static void export_design(const fcc_lqg_design64_t *d, fcc_lqg_design_t *out)
{
    narrow(out->phi, d->phi, NX * NX);
    narrow(out->gamma, d->gamma, NX * NU);
    narrow(out->qd, d->qd, NX * NX);
    narrow(out->q11, d->q11, NX * NX);
    narrow(out->q12, d->q12, NX * NU);
    narrow(out->q22, d->q22, NU * NU);
    narrow(out->h, d->h, NY * NX);
    narrow(out->r, d->r, NY * NY);
    narrow(out->p, d->p, NX * NX);
    narrow(out->k, d->k, NU * NX);
    narrow(out->m, d->m, NX * NX);
    narrow(out->p_post, d->p_post, NX * NX);
    narrow(out->l, d->l, NX * NY);
    narrow(out->cl_re, d->cl_re, NX);
    narrow(out->cl_im, d->cl_im, NX);
    narrow(out->est_re, d->est_re, NX);
    narrow(out->est_im, d->est_im, NX);
    narrow(out->gamma1, d->gamma1, NX * NU);
    narrow(out->qa11, d->qa11, NA * NA);
    narrow(out->qa12, d->qa12, NA);
    narrow(out->pa, d->pa, NA * NA);
    out->k_u = (fcc_real_t)d->k_u;
    out->qa22 = (fcc_real_t)d->qa22;
}

fcc_status_t fcc_lqg_design_begin(const fcc_lqg_plant_t *plant, double t, fcc_lqg_solver_t solver,
                                  fcc_lqg_ws_t *ws)
{
    return fcc_lqg_design_begin_delayed(plant, t, 0.0, solver, ws);
}

fcc_status_t fcc_lqg_design_begin_delayed(const fcc_lqg_plant_t *plant, double t, double delay,
                                          fcc_lqg_solver_t solver, fcc_lqg_ws_t *ws)
{
    if (plant == NULL || ws == NULL) {
        return FCC_ERR_ARG;
    }
    ws->slice = FCC_LQG_DESIGN_SLICES;
    FCC_TRY(check_inputs(plant, t, solver));
    if (!FCC_IS_FINITE(delay)) {
        return FCC_ERR_ARG;
    }
    if (delay < 0.0 || delay >= t) {
        return FCC_ERR_RANGE;
    }
    ws->delay = delay;
    fcc_lqg_design64_t *d = &ws->d;
    memset(d, 0, sizeof *d);
    for (unsigned i = 0; i < NY * NX; ++i) {
        d->h[i] = (double)plant->h[i];
    }
    d->r[0] = (double)plant->gyro_var;
    d->r[1] = 0.0;
    d->r[2] = 0.0;
    d->r[3] = (double)plant->accel_var;
    ws->plant = plant;
    ws->t = t;
    ws->solver = solver;
    ws->lqr = (fcc_lqg_riccati_t){0.0, 0.0, 0.0, 0U};
    ws->kf = (fcc_lqg_riccati_t){0.0, 0.0, 0.0, 0U};
    ws->slice = 0U;
    return FCC_OK;
}

static fcc_status_t run_slice(fcc_lqg_ws_t *ws, unsigned slice, fcc_lqg_design_t *out)
{
    switch (slice) {
    case 0U:
        return discretise_zoh(ws);
    case 1U:
        return discretise_noise(ws);
    case 2U:
        return discretise_cost(ws);
    case 3U:
        if (ws->delay > 0.0) { /* the augmented LQR: blocks + doubling (fcc_lqg.h) */
            plant64_t p;
            plant64(ws->plant, &p);
            FCC_TRY(delay_blocks(&p, ws->t, ws->delay, &ws->d, ws));
            return design_lqr_delayed(&ws->d, &ws->lqr, ws);
        }
        return design_lqr(ws, false);
    case 4U:
        return (ws->delay > 0.0) ? FCC_OK : design_lqr(ws, true);
    case 5U:
    case 6U:
        return design_kf(ws, slice == 6U);
    default:
        FCC_TRY(poles(&ws->d, ws->delay > 0.0, ws));
        out->t = (fcc_real_t)ws->t;
        out->delay = (fcc_real_t)ws->delay;
        out->solver = ws->solver;
        out->lqr = ws->lqr;
        out->kf = ws->kf;
        export_design(&ws->d, out);
        return FCC_OK;
    }
}

fcc_status_t fcc_lqg_design_slice(fcc_lqg_ws_t *ws, fcc_lqg_design_t *out)
{
    if (ws == NULL || out == NULL || ws->slice >= FCC_LQG_DESIGN_SLICES) {
        return FCC_ERR_ARG;
    }
    const unsigned slice = ws->slice;
    const fcc_status_t st = run_slice(ws, slice, out);
    ws->slice = (st == FCC_OK && slice + 1U < FCC_LQG_DESIGN_SLICES) ? slice + 1U
                                                                    : FCC_LQG_DESIGN_SLICES;
    if (st != FCC_OK) {
        return st;
    }
    return (ws->slice < FCC_LQG_DESIGN_SLICES) ? FCC_ERR_AGAIN : FCC_OK;
}

fcc_status_t fcc_lqg_design(const fcc_lqg_plant_t *plant, double t, fcc_lqg_solver_t solver,
                            fcc_lqg_design_t *out, fcc_lqg_ws_t *ws)
{
    return fcc_lqg_design_delayed(plant, t, 0.0, solver, out, ws);
}

fcc_status_t fcc_lqg_design_delayed(const fcc_lqg_plant_t *plant, double t, double delay,
                                    fcc_lqg_solver_t solver, fcc_lqg_design_t *out,
                                    fcc_lqg_ws_t *ws)
{
    if (out == NULL) {
        return FCC_ERR_ARG;
    }
    FCC_TRY(fcc_lqg_design_begin_delayed(plant, t, delay, solver, ws));
    fcc_status_t st = FCC_ERR_AGAIN;
    for (unsigned i = 0; i < FCC_LQG_DESIGN_SLICES && st == FCC_ERR_AGAIN; ++i) {
        st = fcc_lqg_design_slice(ws, out);
    }
    return st;
}
