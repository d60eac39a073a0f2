/* fcc_lqg_design.c -- the sampled-data LQG design of SPEC section 3. */
#include "fcc_lqg.h"

#define NX FCC_LQG_NX
#define NU FCC_LQG_NU
#define NY FCC_LQG_NY

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

static fcc_status_t check_inputs(const fcc_lqg_plant_t *plant, fcc_real_t t, fcc_lqg_solver_t solver)
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

/* Phi, Gamma, Q_d (noise density w w^T), Q11, Q12, Q22. */
static fcc_status_t discretise(const fcc_lqg_plant_t *plant, fcc_real_t t, fcc_lqg_design_t *d,
                               fcc_lqg_ws_t *ws)
{
    fcc_real_t fbuf[NX * NX];
    fcc_real_t gbuf[NX * NU];
    fcc_real_t wxbuf[NX * NX];
    fcc_real_t wubuf[NU * NU] = {plant->wu};
    for (unsigned i = 0; i < NX * NX; ++i) {
        fbuf[i] = plant->f[i];
        wxbuf[i] = plant->wx[i];
    }
    for (unsigned i = 0; i < NX; ++i) {
        gbuf[i] = plant->g[i];
        for (unsigned j = 0; j < NX; ++j) {
            ws->tmp[i * NX + j] = plant->w[i] * plant->w[j];
        }
    }
    const fcc_mat_t f = FCC_MAT(NX, NX, fbuf);
    const fcc_mat_t g = FCC_MAT(NX, NU, gbuf);
    const fcc_mat_t wx = FCC_MAT(NX, NX, wxbuf);
    const fcc_mat_t wu = FCC_MAT(NU, NU, wubuf);
    const fcc_mat_t qc = FCC_MAT(NX, NX, ws->tmp);
    fcc_mat_t phi = FCC_MAT(NX, NX, d->phi);
    fcc_mat_t gamma = FCC_MAT(NX, NU, d->gamma);
    fcc_mat_t qd = FCC_MAT(NX, NX, d->qd);
    fcc_mat_t q11 = FCC_MAT(NX, NX, d->q11);
    fcc_mat_t q12 = FCC_MAT(NX, NU, d->q12);
    fcc_mat_t q22 = FCC_MAT(NU, NU, d->q22);
    FCC_TRY(fcc_c2d_zoh(&f, &g, t, &phi, &gamma, &ws->u.c2d));
    FCC_TRY(fcc_c2d_noise(&f, &qc, t, &qd, &ws->u.c2d));
    return fcc_c2d_cost(&f, &g, &wx, &wu, t, &q11, &q12, &q22, &ws->u.c2d);
}

static fcc_status_t solve_with(fcc_lqg_solver_t solver, const fcc_dare_problem_t *p, fcc_mat_t *x,
                               fcc_dare_info_t *info, fcc_dare_ws_t *ws)
{
    return (solver == FCC_LQG_SOLVER_HAMILTONIAN) ? fcc_dare_hamiltonian(p, x, info, ws)
                                                  : fcc_dare_doubling(p, x, info, ws);
}

/* Solve p by both methods; x/gain from `solver`, the other into x_alt/gain_alt
 * (gain computed by gain_fn); record residual, iterations, disagreement. */
typedef fcc_status_t (*gain_fn_t)(const fcc_dare_problem_t *p, const fcc_mat_t *x, fcc_mat_t *gain,
                                  fcc_lqg_ws_t *ws);

static fcc_status_t solve_both(fcc_lqg_solver_t solver, const fcc_dare_problem_t *p, fcc_mat_t *x,
                               fcc_mat_t *gain, fcc_mat_t *x_alt, fcc_mat_t *gain_alt,
                               gain_fn_t gain_fn, fcc_lqg_riccati_t *rep, fcc_lqg_ws_t *ws)
{
    const fcc_lqg_solver_t other = (solver == FCC_LQG_SOLVER_HAMILTONIAN)
                                       ? FCC_LQG_SOLVER_DOUBLING
                                       : FCC_LQG_SOLVER_HAMILTONIAN;
    fcc_dare_info_t info = {0U, FCC_R(0.0), FCC_R(0.0), FCC_R(0.0)};
    fcc_dare_info_t info_alt = {0U, FCC_R(0.0), FCC_R(0.0), FCC_R(0.0)};
    FCC_TRY(solve_with(solver, p, x, &info, &ws->u.dare));
    FCC_TRY(gain_fn(p, x, gain, ws));
    FCC_TRY(solve_with(other, p, x_alt, &info_alt, &ws->u.dare));
    FCC_TRY(gain_fn(p, x_alt, gain_alt, ws));
    fcc_real_t dx = FCC_R(0.0);
    fcc_real_t dg = FCC_R(0.0);
    FCC_TRY(fcc_mat_rel_diff(x_alt, x, &dx));
    FCC_TRY(fcc_mat_rel_diff(gain_alt, gain, &dg));
    rep->residual = info.residual;
    rep->disagreement = (dx > dg) ? dx : dg;
    rep->iterations = (solver == FCC_LQG_SOLVER_DOUBLING) ? info.iterations : info_alt.iterations;
    rep->rcond_u1 = (solver == FCC_LQG_SOLVER_HAMILTONIAN) ? info.rcond_u1 : info_alt.rcond_u1;
    return (rep->disagreement <= FCC_LQG_AGREE_TOL) ? FCC_OK : FCC_ERR_DISAGREE;
}

/* LQR gain K = (Q22 + G^T P G)^-1 (G^T P Phi + Q12^T). */
static fcc_status_t lqr_gain(const fcc_dare_problem_t *p, const fcc_mat_t *x, fcc_mat_t *gain,
                             fcc_lqg_ws_t *ws)
{
    return fcc_dare_gain(p, x, gain, &ws->u.dare);
}

/* Filter gain, update form: L = M H^T (H M H^T + R)^-1, i.e. (H M H^T + R) L^T = H M
 * (M and H M H^T + R symmetric).  The problem is (Phi^T, H^T, Q_d, R). */
static fcc_status_t kf_gain(const fcc_dare_problem_t *p, const fcc_mat_t *x, fcc_mat_t *gain,
                            fcc_lqg_ws_t *ws)
{
    fcc_real_t hm[NY * NX];
    fcc_real_t s[NY * NY];
    fcc_real_t lt[NY * NX];
    fcc_mat_t mhm = FCC_MAT(NY, NX, hm);
    fcc_mat_t ms = FCC_MAT(NY, NY, s);
    fcc_mat_t mlt = FCC_MAT(NY, NX, lt);
    FCC_TRY(fcc_mat_mul_tn(p->b, x, &mhm)); /* b = H^T: b^T M = H M */
    FCC_TRY(fcc_mat_mul(&mhm, p->b, &ms));  /* H M H^T */
    FCC_TRY(fcc_mat_add(&ms, p->r, &ms));
    FCC_TRY(fcc_mat_solve(&ms, &mhm, &mlt, &ws->u.dare.lu));
    return fcc_mat_trans(&mlt, gain);
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

static fcc_status_t design_lqr(fcc_lqg_solver_t solver, fcc_lqg_design_t *d, fcc_lqg_ws_t *ws)
{
    const fcc_mat_t phi = FCC_MAT(NX, NX, d->phi);
    const fcc_mat_t gamma = FCC_MAT(NX, NU, d->gamma);
    const fcc_mat_t q11 = FCC_MAT(NX, NX, d->q11);
    const fcc_mat_t q12 = FCC_MAT(NX, NU, d->q12);
    const fcc_mat_t q22 = FCC_MAT(NU, NU, d->q22);
    const fcc_dare_problem_t p = {&phi, &gamma, &q11, &q22, &q12};
    fcc_mat_t x = FCC_MAT(NX, NX, d->p);
    fcc_mat_t k = FCC_MAT(NU, NX, d->k);
    fcc_mat_t x_alt = FCC_MAT(NX, NX, ws->x_alt);
    fcc_mat_t k_alt = FCC_MAT(NU, NX, ws->g_alt);
    return solve_both(solver, &p, &x, &k, &x_alt, &k_alt, lqr_gain, &d->lqr, ws);
}

static fcc_status_t design_kf(fcc_lqg_solver_t solver, fcc_lqg_design_t *d, fcc_lqg_ws_t *ws)
{
    fcc_mat_t phi = FCC_MAT(NX, NX, d->phi);
    fcc_mat_t h = FCC_MAT(NY, NX, d->h);
    fcc_mat_t a = FCC_MAT(NX, NX, ws->a_t);
    fcc_mat_t b = FCC_MAT(NX, NY, ws->b_t);
    FCC_TRY(fcc_mat_trans(&phi, &a));
    FCC_TRY(fcc_mat_trans(&h, &b));
    const fcc_mat_t qd = FCC_MAT(NX, NX, d->qd);
    const fcc_mat_t r = FCC_MAT(NY, NY, d->r);
    const fcc_dare_problem_t p = {&a, &b, &qd, &r, NULL};
    fcc_mat_t x = FCC_MAT(NX, NX, d->m);
    fcc_mat_t l = FCC_MAT(NX, NY, d->l);
    fcc_mat_t x_alt = FCC_MAT(NX, NX, ws->x_alt);
    fcc_mat_t l_alt = FCC_MAT(NX, NY, ws->g_alt);
    FCC_TRY(kf_status(solve_both(solver, &p, &x, &l, &x_alt, &l_alt, kf_gain, &d->kf, ws)));
    /* P+ = (I - L H) M */
    fcc_mat_t lh = FCC_MAT(NX, NX, ws->tmp);
    fcc_mat_t pp = FCC_MAT(NX, NX, d->p_post);
    FCC_TRY(fcc_mat_mul(&l, &h, &lh));
    FCC_TRY(fcc_mat_mul(&lh, &x, &pp));
    FCC_TRY(fcc_mat_sub(&x, &pp, &pp));
    return fcc_mat_symmetrize(&pp);
}

/* Sort eigenvalues by decreasing modulus, then decreasing imaginary part. */
static void sort_poles(fcc_real_t *re, fcc_real_t *im, unsigned n)
{
    for (unsigned i = 1; i < n; ++i) {
        const fcc_real_t r = re[i];
        const fcc_real_t m = im[i];
        const fcc_real_t mod = FCC_HYPOT(r, m);
        unsigned j = i;
        while (j > 0U) {
            const fcc_real_t pmod = FCC_HYPOT(re[j - 1U], im[j - 1U]);
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

static fcc_status_t poles(fcc_lqg_design_t *d, fcc_lqg_ws_t *ws)
{
    const fcc_mat_t phi = FCC_MAT(NX, NX, d->phi);
    const fcc_mat_t gamma = FCC_MAT(NX, NU, d->gamma);
    const fcc_mat_t k = FCC_MAT(NU, NX, d->k);
    const fcc_mat_t l = FCC_MAT(NX, NY, d->l);
    const fcc_mat_t h = FCC_MAT(NY, NX, d->h);
    fcc_mat_t t1 = FCC_MAT(NX, NX, ws->tmp);
    fcc_mat_t t2 = FCC_MAT(NX, NX, ws->x_alt);
    fcc_mat_t acl = FCC_MAT(NX, NX, ws->a_t);
    FCC_TRY(fcc_mat_mul(&gamma, &k, &t1));
    FCC_TRY(fcc_mat_sub(&phi, &t1, &acl));
    FCC_TRY(fcc_mat_eig(&acl, d->cl_re, d->cl_im, NULL, &ws->u.dare.eig));
    FCC_TRY(fcc_mat_mul(&l, &h, &t1));
    FCC_TRY(fcc_mat_mul(&phi, &t1, &t2));
    FCC_TRY(fcc_mat_sub(&phi, &t2, &acl));
    FCC_TRY(fcc_mat_eig(&acl, d->est_re, d->est_im, NULL, &ws->u.dare.eig));
    sort_poles(d->cl_re, d->cl_im, NX);
    sort_poles(d->est_re, d->est_im, NX);
    return FCC_OK;
}

fcc_status_t fcc_lqg_design(const fcc_lqg_plant_t *plant, fcc_real_t t, fcc_lqg_solver_t solver,
                            fcc_lqg_design_t *out, fcc_lqg_ws_t *ws)
{
    if (plant == NULL || out == NULL || ws == NULL) {
        return FCC_ERR_ARG;
    }
    FCC_TRY(check_inputs(plant, t, solver));
    fcc_lqg_design_t *d = &ws->d;
    d->t = t;
    d->solver = solver;
    for (unsigned i = 0; i < NY * NX; ++i) {
        d->h[i] = plant->h[i];
    }
    d->r[0] = plant->gyro_var;
    d->r[1] = FCC_R(0.0);
    d->r[2] = FCC_R(0.0);
    d->r[3] = plant->accel_var;
    FCC_TRY(discretise(plant, t, d, ws));
    FCC_TRY(design_lqr(solver, d, ws));
    FCC_TRY(design_kf(solver, d, ws));
    FCC_TRY(poles(d, ws));
    *out = *d;
    return FCC_OK;
}
