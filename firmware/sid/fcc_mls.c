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

/* s += sign * (phi phi^T, phi z^T, z.^2) of one transition. */
static void sums_add(fcc_mls_sums_t *s, const fcc_mls_transition_t *t, fcc_real_t sign)
{
    const fcc_real_t p0 = sign * t->phi[0];
    const fcc_real_t p1 = sign * t->phi[1];
    const fcc_real_t p2 = sign * t->phi[2];
    s->n[0] += p0 * t->phi[0];
    s->n[1] += p0 * t->phi[1];
    s->n[2] += p0 * t->phi[2];
    s->n[3] += p1 * t->phi[1];
    s->n[4] += p1 * t->phi[2];
    s->n[5] += p2 * t->phi[2];
    s->pz[0] += p0 * t->z[0];
    s->pz[1] += p0 * t->z[1];
    s->pz[2] += p1 * t->z[0];
    s->pz[3] += p1 * t->z[1];
    s->pz[4] += p2 * t->z[0];
    s->pz[5] += p2 * t->z[1];
    s->zz[0] += sign * t->z[0] * t->z[0];
    s->zz[1] += sign * t->z[1] * t->z[1];
}

static void set_prior(fcc_mls_t *mls)
{
    mls->est.model = mls->cfg.prior;
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
    fcc_mls_transition_t *slot = &mls->ring[mls->head];
    if (mls->count == mls->cfg.window) {
        sums_add(&mls->sums, slot, FCC_R(-1.0)); /* the oldest leaves */
    } else {
        mls->count++;
    }
    slot->phi[0] = x[0];
    slot->phi[1] = x[1];
    slot->phi[2] = de;
    slot->z[0] = x_next[0];
    slot->z[1] = x_next[1];
    mls->head = (uint16_t)((mls->head + 1u) % mls->cfg.window);
    sums_add(&mls->sums, slot, FCC_R(1.0));

    /* Exact re-sum: after `window` pushes the shadow holds exactly the
     * transitions now in the window, summed without any subtraction. */
    sums_add(&mls->shadow, slot, FCC_R(1.0));
    mls->shadow_count++;
    if (mls->shadow_count == mls->cfg.window) {
        mls->sums = mls->shadow;
        sums_clear(&mls->shadow);
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

fcc_status_t fcc_mls_solve(fcc_mls_t *mls)
{
    if (mls == NULL) {
        return FCC_ERR_ARG;
    }
    if (mls->count < mls->cfg.min_transitions) {
        set_prior(mls);
        return FCC_OK;
    }
    const fcc_real_t ridge = mls->cfg.ridge;
    fcc_real_t theta0[3][2];
    prior_theta(&mls->cfg.prior, theta0);

    /* Equilibrate N + ridge I to unit diagonal: d_j = 1 / sqrt(Nr_jj). */
    fcc_real_t d[3];
    mat3_t s;
    for (size_t j = 0; j < 3u; ++j) {
        const fcc_real_t njj = mls->sums.n[sym_index(j, j)] + ridge;
        if (!(njj > FCC_R(0.0)) || !FCC_IS_FINITE(njj)) {
            return FCC_ERR_SINGULAR;
        }
        d[j] = FCC_R(1.0) / FCC_SQRT(njj);
    }
    for (size_t j = 0; j < 3u; ++j) {
        for (size_t k = 0; k < 3u; ++k) {
            const fcc_real_t nr = mls->sums.n[sym_index(j, k)] + (j == k ? ridge : FCC_R(0.0));
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
            v[j] = d[j] * (mls->sums.pz[2u * j + i] + ridge * theta0[j][i]);
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
    const fcc_real_t dof = (fcc_real_t)mls->count - FCC_R(3.0);
    for (size_t i = 0; i < 2u; ++i) {
        const fcc_real_t var = dof > FCC_R(0.0) ? row_rss(&mls->sums, i, th[i]) / dof : FCC_R(-1.0);
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
