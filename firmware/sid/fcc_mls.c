#include "fcc_mls.h"

#include <string.h>

/* Index of N_jk (j, k in 0..2) in the packed upper triangle. */
static size_t sym_index(size_t j, size_t k)
{
    static const uint8_t idx[3][3] = {{0u, 1u, 2u}, {1u, 3u, 4u}, {2u, 4u, 5u}};
    return idx[j][k];
}

static void sums_clear(fcc_mls_sums_t *s)
{
    memset(s, 0, sizeof *s);
}

/* Empties an accumulator and sets its reference point to transition t. */
static void sums_start(fcc_mls_sums_t *s, const fcc_mls_transition_t *t)
{
    sums_clear(s);
    memcpy(s->ref_phi, t->phi, sizeof s->ref_phi);
    memcpy(s->ref_z, t->z, sizeof s->ref_z);
}

/* s += sign * (d d^T, d e^T, e.^2, d, e) of one transition, with d, e its
 * regressor and target about the accumulator's reference point. */
static void sums_add(fcc_mls_sums_t *s, const fcc_mls_transition_t *t, fcc_real_t sign)
{
    /* Written out: this runs twice per step (newest in, oldest out) plus the shadow. */
    const fcc_real_t d0 = t->phi[0] - s->ref_phi[0];
    const fcc_real_t d1 = t->phi[1] - s->ref_phi[1];
    const fcc_real_t d2 = t->phi[2] - s->ref_phi[2];
    const fcc_real_t e0 = t->z[0] - s->ref_z[0];
    const fcc_real_t e1 = t->z[1] - s->ref_z[1];
    const fcc_real_t p0 = sign * d0;
    const fcc_real_t p1 = sign * d1;
    const fcc_real_t p2 = sign * d2;
    const fcc_real_t q0 = sign * e0;
    const fcc_real_t q1 = sign * e1;
    s->n[0] += p0 * d0;
    s->n[1] += p0 * d1;
    s->n[2] += p0 * d2;
    s->n[3] += p1 * d1;
    s->n[4] += p1 * d2;
    s->n[5] += p2 * d2;
    s->pz[0] += p0 * e0;
    s->pz[1] += p0 * e1;
    s->pz[2] += p1 * e0;
    s->pz[3] += p1 * e1;
    s->pz[4] += p2 * e0;
    s->pz[5] += p2 * e1;
    s->zz[0] += q0 * e0;
    s->zz[1] += q1 * e1;
    s->ps[0] += p0;
    s->ps[1] += p1;
    s->ps[2] += p2;
    s->zs[0] += q0;
    s->zs[1] += q1;
}

static void set_prior(fcc_mls_t *mls)
{
    mls->est.model = mls->cfg.prior;
    if (!mls->cfg.intercept) {
        mls->est.model.c[0] = FCC_R(0.0); /* the paper's model has no affine term */
        mls->est.model.c[1] = FCC_R(0.0);
    }
    for (size_t i = 0; i < FCC_MLS_N_PARAMS; ++i) {
        mls->est.se[i] = FCC_R(-1.0);
    }
    mls->est.rho = fcc_sid_m2_spectral_radius(mls->cfg.prior.a);
    mls->est.is_prior = true;
}

void fcc_mls_config_default(fcc_mls_config_t *cfg, const fcc_sid_model_t *prior)
{
    if (cfg == NULL || prior == NULL) {
        return;
    }
    cfg->window = FCC_MLS_DEFAULT_WINDOW;
    cfg->min_transitions = FCC_MLS_DEFAULT_MIN_TRANSITIONS;
    cfg->ridge = FCC_MLS_DEFAULT_RIDGE;
    cfg->max_cond = FCC_MLS_DEFAULT_MAX_COND;
    cfg->max_rho = FCC_MLS_DEFAULT_MAX_RHO;
    cfg->prior = *prior;
    cfg->intercept = false;
}

fcc_status_t fcc_mls_config_check(const fcc_mls_config_t *cfg)
{
    if (cfg == NULL) {
        return FCC_ERR_ARG;
    }
    if (!fcc_sid_model_is_finite(&cfg->prior) || !FCC_IS_FINITE(cfg->ridge) ||
        !FCC_IS_FINITE(cfg->max_cond) || !FCC_IS_FINITE(cfg->max_rho)) {
        return FCC_ERR_ARG;
    }
    if (cfg->window < 4u || cfg->window > FCC_MLS_MAX_WINDOW || cfg->min_transitions < 4u ||
        cfg->min_transitions > cfg->window) {
        return FCC_ERR_RANGE;
    }
    if (cfg->ridge < FCC_R(0.0) || !(cfg->max_cond > FCC_R(1.0)) || cfg->max_rho < FCC_R(0.0)) {
        return FCC_ERR_RANGE;
    }
    return FCC_OK;
}

fcc_status_t fcc_mls_init(fcc_mls_t *mls, const fcc_mls_config_t *cfg)
{
    if (mls == NULL) {
        return FCC_ERR_ARG;
    }
    const fcc_status_t st = fcc_mls_config_check(cfg);
    if (st != FCC_OK) {
        return st;
    }
    memset(mls, 0, sizeof *mls);
    mls->cfg = *cfg;
    sums_clear(&mls->sums);
    sums_clear(&mls->shadow);
    set_prior(mls);
    return FCC_OK;
}

fcc_status_t fcc_mls_push(fcc_mls_t *mls, const fcc_real_t x[2], fcc_real_t de,
                          const fcc_real_t x_next[2])
{
    if (mls == NULL || x == NULL || x_next == NULL) {
        return FCC_ERR_ARG;
    }
    if (!fcc_sid_all_finite(x, 2) || !fcc_sid_all_finite(x_next, 2) || !FCC_IS_FINITE(de)) {
        return FCC_ERR_NOT_FINITE;
    }
    const fcc_mls_transition_t tr = {{x[0], x[1], de}, {x_next[0], x_next[1]}};
    if (mls->count == 0u) {
        sums_start(&mls->sums, &tr); /* the first transition is the reference point */
        sums_start(&mls->shadow, &tr);
        mls->shadow_count = 0u;
    }
    fcc_mls_transition_t *slot = &mls->ring[mls->head];
    if (mls->count == mls->cfg.window) {
        sums_add(&mls->sums, slot, FCC_R(-1.0)); /* the oldest leaves */
    } else {
        mls->count++;
    }
    *slot = tr;
    mls->head = (uint16_t)((mls->head + 1u) % mls->cfg.window);
    sums_add(&mls->sums, slot, FCC_R(1.0));

    /* Exact re-sum: after `window` pushes the shadow holds exactly the
     * transitions now in the window, summed without any subtraction. */
    sums_add(&mls->shadow, slot, FCC_R(1.0));
    mls->shadow_count++;
    if (mls->shadow_count == mls->cfg.window) {
        mls->sums = mls->shadow;
        sums_start(&mls->shadow, &tr); /* the next window's sums about a recent point */
        mls->shadow_count = 0u;
    }
    mls->est.n_transitions = mls->count;
    return FCC_OK;
}

/* A 3x3 matrix as a value (a struct avoids C99's const-array pitfalls). */
typedef struct {
    fcc_real_t m[3][3];
} mat3_t;

/* Lower Cholesky factor of a 3x3 symmetric matrix with unit diagonal;
 * FCC_ERR_SINGULAR on a pivot that is not clearly positive. */
static fcc_status_t chol3(const mat3_t *sm, mat3_t *lm)
{
    const fcc_real_t tiny = FCC_R(16.0) * FCC_EPS;
    const fcc_real_t(*s)[3] = sm->m;
    fcc_real_t(*l)[3] = lm->m;
    memset(lm, 0, sizeof *lm);
    if (!(s[0][0] > tiny)) {
        return FCC_ERR_SINGULAR;
    }
    l[0][0] = FCC_SQRT(s[0][0]);
    l[1][0] = s[1][0] / l[0][0];
    l[2][0] = s[2][0] / l[0][0];
    const fcc_real_t d1 = s[1][1] - l[1][0] * l[1][0];
    if (!(d1 > tiny)) {
        return FCC_ERR_SINGULAR;
    }
    l[1][1] = FCC_SQRT(d1);
    l[2][1] = (s[2][1] - l[2][0] * l[1][0]) / l[1][1];
    const fcc_real_t d2 = s[2][2] - l[2][0] * l[2][0] - l[2][1] * l[2][1];
    if (!(d2 > tiny)) {
        return FCC_ERR_SINGULAR;
    }
    l[2][2] = FCC_SQRT(d2);
    return FCC_OK;
}

/* w = (l l^T)^-1 from the Cholesky factor. */
static void chol3_inverse(const mat3_t *lm, mat3_t *wm)
{
    const fcc_real_t(*l)[3] = lm->m;
    fcc_real_t(*w)[3] = wm->m;
    fcc_real_t li[3][3]; /* inverse of l, lower triangular */
    li[0][0] = FCC_R(1.0) / l[0][0];
    li[1][1] = FCC_R(1.0) / l[1][1];
    li[2][2] = FCC_R(1.0) / l[2][2];
    li[1][0] = -l[1][0] * li[0][0] * li[1][1];
    li[2][1] = -l[2][1] * li[1][1] * li[2][2];
    li[2][0] = -(l[2][0] * li[0][0] + l[2][1] * li[1][0]) * li[2][2];
    li[0][1] = li[0][2] = li[1][2] = FCC_R(0.0);
    for (size_t j = 0; j < 3u; ++j) {
        for (size_t k = j; k < 3u; ++k) {
            fcc_real_t acc = FCC_R(0.0);
            for (size_t i = k; i < 3u; ++i) {
                acc += li[i][j] * li[i][k];
            }
            w[j][k] = acc;
            w[k][j] = acc;
        }
    }
}

/* 1-norm (max column sum) of a symmetric 3x3 matrix. */
static fcc_real_t norm1_3(const mat3_t *mm)
{
    const fcc_real_t(*m)[3] = mm->m;
    fcc_real_t best = FCC_R(0.0);
    for (size_t k = 0; k < 3u; ++k) {
        const fcc_real_t c = FCC_FABS(m[0][k]) + FCC_FABS(m[1][k]) + FCC_FABS(m[2][k]);
        best = c > best ? c : best;
    }
    return best;
}

/* Solves l l^T y = v in place. */
static void chol3_solve(const mat3_t *lm, fcc_real_t v[3])
{
    const fcc_real_t(*l)[3] = lm->m;
    v[0] = v[0] / l[0][0];
    v[1] = (v[1] - l[1][0] * v[0]) / l[1][1];
    v[2] = (v[2] - l[2][0] * v[0] - l[2][1] * v[1]) / l[2][2];
    v[2] = v[2] / l[2][2];
    v[1] = (v[1] - l[2][1] * v[2]) / l[1][1];
    v[0] = (v[0] - l[1][0] * v[1] - l[2][0] * v[2]) / l[0][0];
}

/* theta0[j][i]: prior coefficient of regressor j in output row i. */
static void prior_theta(const fcc_sid_model_t *m, fcc_real_t theta0[3][2])
{
    theta0[0][0] = m->a[0];
    theta0[1][0] = m->a[1];
    theta0[2][0] = m->b[0];
    theta0[0][1] = m->a[2];
    theta0[1][1] = m->a[3];
    theta0[2][1] = m->b[1];
}

/* Residual sum of squares of output row i for coefficients th (3). */
static fcc_real_t row_rss(const fcc_mls_sums_t *s, size_t i, const fcc_real_t th[3])
{
    fcc_real_t quad = FCC_R(0.0);
    fcc_real_t cross = FCC_R(0.0);
    for (size_t j = 0; j < 3u; ++j) {
        cross += th[j] * s->pz[2u * j + i];
        for (size_t k = 0; k < 3u; ++k) {
            quad += th[j] * s->n[sym_index(j, k)] * th[k];
        }
    }
    const fcc_real_t rss = s->zz[i] - FCC_R(2.0) * cross + quad;
    return rss > FCC_R(0.0) ? rss : FCC_R(0.0);
}

/* The sums the regression is solved on, from the window's sums about their
 * reference point r (d = phi - r, e = z - rz; m transitions):
 *  - the paper's regression needs them about the origin:
 *    N = Sdd + r Sd^T + Sd r^T + m r r^T, the same for phi z^T and z^2;
 *  - with the intercept, about the window means:
 *    Nc = Sdd - Sd Sd^T / m, the same for phi z^T and z^2, and w->ps, w->zs
 *    then hold the means phi_bar = r + Sd / m, z_bar = rz + Se / m.
 * Keeping the sums about a recent sample instead of the origin is what makes
 * the centring accurate in float: the cancellation is of deviations from the
 * reference, not of 9-deg absolute angles.  A centred square sum cannot be
 * negative; rounding could make it so. */
static void normal_data(const fcc_mls_t *mls, fcc_mls_sums_t *w)
{
    const fcc_mls_sums_t *s = &mls->sums;
    const fcc_real_t m = (fcc_real_t)mls->count;
    *w = *s;
    if (mls->cfg.intercept) {
        for (size_t j = 0; j < 3u; ++j) {
            for (size_t k = j; k < 3u; ++k) {
                w->n[sym_index(j, k)] -= s->ps[j] * s->ps[k] / m;
            }
            w->pz[2u * j] -= s->ps[j] * s->zs[0] / m;
            w->pz[2u * j + 1u] -= s->ps[j] * s->zs[1] / m;
            w->ps[j] = s->ref_phi[j] + s->ps[j] / m;
            const size_t d = sym_index(j, j);
            w->n[d] = w->n[d] > FCC_R(0.0) ? w->n[d] : FCC_R(0.0);
        }
        for (size_t i = 0; i < 2u; ++i) {
            w->zz[i] -= s->zs[i] * s->zs[i] / m;
            w->zz[i] = w->zz[i] > FCC_R(0.0) ? w->zz[i] : FCC_R(0.0);
            w->zs[i] = s->ref_z[i] + s->zs[i] / m;
        }
        return;
    }
    const fcc_real_t *r = s->ref_phi;
    const fcc_real_t *rz = s->ref_z;
    for (size_t j = 0; j < 3u; ++j) {
        for (size_t k = j; k < 3u; ++k) {
            w->n[sym_index(j, k)] += r[j] * s->ps[k] + s->ps[j] * r[k] + m * r[j] * r[k];
        }
        for (size_t i = 0; i < 2u; ++i) {
            w->pz[2u * j + i] += r[j] * s->zs[i] + s->ps[j] * rz[i] + m * r[j] * rz[i];
        }
    }
    for (size_t i = 0; i < 2u; ++i) {
        w->zz[i] += FCC_R(2.0) * rz[i] * s->zs[i] + m * rz[i] * rz[i];
    }
}

/* Intercept of output row i, c_i = z_bar_i - th . phi_bar, for the row's
 * coefficients th and the means of normal_data (0 without intercept). */
static fcc_real_t intercept_of(const fcc_mls_t *mls, const fcc_mls_sums_t *nd, size_t i,
                               const fcc_real_t th[3])
{
    if (!mls->cfg.intercept) {
        return FCC_R(0.0);
    }
    return nd->zs[i] - (th[0] * nd->ps[0] + th[1] * nd->ps[1] + th[2] * nd->ps[2]);
}

fcc_status_t fcc_mls_solve(fcc_mls_t *mls)
{
    if (mls == NULL) {
        return FCC_ERR_ARG;
    }
    if (mls->count < mls->cfg.min_transitions) {
        set_prior(mls);
        return FCC_OK;
    }
    fcc_mls_sums_t nd;
    normal_data(mls, &nd);
    const fcc_real_t ridge = mls->cfg.ridge;
    fcc_real_t theta0[3][2];
    prior_theta(&mls->cfg.prior, theta0);

    /* Equilibrate N + ridge I to unit diagonal: d_j = 1 / sqrt(Nr_jj). */
    fcc_real_t d[3];
    mat3_t s;
    for (size_t j = 0; j < 3u; ++j) {
        const fcc_real_t njj = nd.n[sym_index(j, j)] + ridge;
        if (!(njj > FCC_R(0.0)) || !FCC_IS_FINITE(njj)) {
            return FCC_ERR_SINGULAR;
        }
        d[j] = FCC_R(1.0) / FCC_SQRT(njj);
    }
    for (size_t j = 0; j < 3u; ++j) {
        for (size_t k = 0; k < 3u; ++k) {
            const fcc_real_t nr = nd.n[sym_index(j, k)] + (j == k ? ridge : FCC_R(0.0));
            s.m[j][k] = d[j] * nr * d[k];
        }
    }
    mat3_t l;
    if (chol3(&s, &l) != FCC_OK) {
        return FCC_ERR_SINGULAR;
    }
    mat3_t w;
    chol3_inverse(&l, &w);
    const fcc_real_t cond = norm1_3(&s) * norm1_3(&w);
    if (!(cond <= mls->cfg.max_cond)) {
        return FCC_ERR_SINGULAR;
    }

    fcc_real_t th[2][3]; /* th[i]: coefficients of output row i */
    for (size_t i = 0; i < 2u; ++i) {
        fcc_real_t v[3];
        for (size_t j = 0; j < 3u; ++j) {
            v[j] = d[j] * (nd.pz[2u * j + i] + ridge * theta0[j][i]);
        }
        chol3_solve(&l, v);
        for (size_t j = 0; j < 3u; ++j) {
            th[i][j] = d[j] * v[j];
        }
    }
    fcc_sid_model_t model;
    model.a[0] = th[0][0];
    model.a[1] = th[0][1];
    model.b[0] = th[0][2];
    model.a[2] = th[1][0];
    model.a[3] = th[1][1];
    model.b[1] = th[1][2];
    model.c[0] = intercept_of(mls, &nd, 0u, th[0]);
    model.c[1] = intercept_of(mls, &nd, 1u, th[1]);
    if (!fcc_sid_model_is_finite(&model)) {
        return FCC_ERR_NOT_FINITE;
    }
    const fcc_real_t rho = fcc_sid_m2_spectral_radius(model.a);
    if (!FCC_IS_FINITE(rho) || (mls->cfg.max_rho > FCC_R(0.0) && rho > mls->cfg.max_rho)) {
        return FCC_ERR_RANGE;
    }

    /* Standard errors: sigma_i^2 [(N + ridge I)^-1]_jj, the inverse being
     * D W D of the equilibrated factorisation. */
    fcc_real_t se[FCC_MLS_N_PARAMS];
    const fcc_real_t n_par = mls->cfg.intercept ? FCC_R(4.0) : FCC_R(3.0);
    const fcc_real_t dof = (fcc_real_t)mls->count - n_par;
    for (size_t i = 0; i < 2u; ++i) {
        const fcc_real_t var = dof > FCC_R(0.0) ? row_rss(&nd, i, th[i]) / dof : FCC_R(-1.0);
        for (size_t j = 0; j < 3u; ++j) {
            /* Parameter order a11 a12 a21 a22 b1 b2: row i, regressor j. */
            const size_t p = j < 2u ? 2u * i + j : 4u + i;
            se[p] = var < FCC_R(0.0) ? FCC_R(-1.0) : FCC_SQRT(var * d[j] * d[j] * w.m[j][j]);
        }
    }

    mls->est.model = model;
    memcpy(mls->est.se, se, sizeof se);
    mls->est.rho = rho;
    mls->est.cond = cond;
    mls->est.is_prior = false;
    return FCC_OK;
}

fcc_status_t fcc_mls_update(fcc_mls_t *mls, const fcc_real_t x[2], fcc_real_t de,
                            const fcc_real_t x_next[2])
{
    const fcc_status_t st = fcc_mls_push(mls, x, de, x_next);
    if (st != FCC_OK) {
        return st;
    }
    return fcc_mls_solve(mls);
}

const fcc_mls_estimate_t *fcc_mls_estimate(const fcc_mls_t *mls)
{
    return mls == NULL ? NULL : &mls->est;
}
