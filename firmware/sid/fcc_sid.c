#include "fcc_sid.h"

#include <string.h>

void fcc_sid_default_prior(fcc_sid_model_t *prior)
{
    if (prior == NULL) {
        return;
    }
    /* [A0 B0] + c0 phi*^T / |phi*|^2, phi* = (alpha*, q*, de*): see the header. */
    prior->a[0] = FCC_R(0.989307);
    prior->a[1] = FCC_R(0.018740);
    prior->a[2] = FCC_R(-0.540133);
    prior->a[3] = FCC_R(0.873259);
    prior->b[0] = FCC_R(-0.039892);
    prior->b[1] = FCC_R(-2.015052);
    prior->c[0] = FCC_R(0.0);
    prior->c[1] = FCC_R(0.0);
}

void fcc_sid_default_prior_affine(fcc_sid_model_t *prior)
{
    if (prior == NULL) {
        return;
    }
    /* A0 = I + dt A_c, B0 = dt B_c, c0 = dt (f* - A_c x* - B_c de*), X = X0(alpha). */
    prior->a[0] = FCC_R(0.895757);
    prior->a[1] = FCC_R(0.018740);
    prior->a[2] = FCC_R(-1.001991);
    prior->a[3] = FCC_R(0.873259);
    prior->b[0] = FCC_R(-0.014816);
    prior->b[1] = FCC_R(-1.891251);
    prior->c[0] = FCC_R(0.015751);
    prior->c[1] = FCC_R(0.077761);
}

static void diag2(fcc_real_t m[4], fcc_real_t v)
{
    m[0] = v;
    m[1] = FCC_R(0.0);
    m[2] = FCC_R(0.0);
    m[3] = v;
}

void fcc_sid_config_default(fcc_sid_config_t *cfg, fcc_sid_filter_t filter)
{
    if (cfg == NULL) {
        return;
    }
    memset(cfg, 0, sizeof *cfg);
    cfg->filter = filter;
    cfg->x0[0] = FCC_SID_DEFAULT_X0_ALPHA;
    cfg->x0[1] = FCC_SID_DEFAULT_X0_Q;
    diag2(cfg->p0, FCC_SID_DEFAULT_P0);
    diag2(cfg->e, FCC_SID_DEFAULT_E);
    diag2(cfg->f, FCC_SID_DEFAULT_F);
    cfg->mls_enabled = true;
    cfg->mls_hold_on_fault = true;
    cfg->arm_on_prior = true;
    fcc_sid_model_t prior;
    fcc_sid_default_prior(&prior);
    fcc_mls_config_default(&cfg->mls, &prior);
    cfg->zkf_order = FCC_SID_DEFAULT_ZKF_ORDER < FCC_ZONO_MAX_ORDER ? FCC_SID_DEFAULT_ZKF_ORDER
                                                                     : FCC_ZONO_MAX_ORDER;
    fcc_azkf_config_default(&cfg->azkf);
    cfg->alpha_limit = FCC_SID_DEFAULT_ALPHA_LIMIT;
    cfg->q_limit = FCC_SID_DEFAULT_Q_LIMIT;
    cfg->de_limit = FCC_SID_DEFAULT_DE_LIMIT;
}

fcc_status_t fcc_sid_config_check(const fcc_sid_config_t *cfg)
{
    if (cfg == NULL) {
        return FCC_ERR_ARG;
    }
    if (cfg->filter != FCC_SID_KF && cfg->filter != FCC_SID_ZKF && cfg->filter != FCC_SID_AZKF) {
        return FCC_ERR_ARG;
    }
    if (cfg->rows != FCC_SID_ROWS_PAPER && cfg->rows != FCC_SID_ROWS_PRIOR &&
        cfg->rows != FCC_SID_ROWS_POSTERIOR) {
        return FCC_ERR_ARG;
    }
    if (!fcc_sid_all_finite(cfg->x0, 2) || !fcc_sid_all_finite(cfg->p0, 4) ||
        !fcc_sid_all_finite(cfg->e, 4) || !fcc_sid_all_finite(cfg->f, 4)) {
        return FCC_ERR_ARG;
    }
    if (!(cfg->alpha_limit > FCC_R(0.0)) || !(cfg->q_limit > FCC_R(0.0)) ||
        !(cfg->de_limit > FCC_R(0.0)) || !FCC_IS_FINITE(cfg->alpha_limit) ||
        !FCC_IS_FINITE(cfg->q_limit) || !FCC_IS_FINITE(cfg->de_limit)) {
        return FCC_ERR_RANGE;
    }
    /* an initial state no sensor could ever read is a configuration error, not a flight */
    if (FCC_FABS(cfg->x0[0]) > cfg->alpha_limit || FCC_FABS(cfg->x0[1]) > cfg->q_limit) {
        return FCC_ERR_RANGE;
    }
    if (cfg->zkf_order < FCC_ZONO_MIN_ORDER || cfg->zkf_order > FCC_ZONO_MAX_ORDER) {
        return FCC_ERR_RANGE;
    }
    fcc_status_t st = fcc_mls_config_check(&cfg->mls);
    if (st == FCC_OK) {
        st = fcc_azkf_config_check(&cfg->azkf);
    }
    return st;
}

/* The model the filter uses now, with its MLS estimate. */
static const fcc_mls_estimate_t *current_estimate(const fcc_sid_t *sid)
{
    return fcc_mls_estimate(&sid->mls);
}

static void fill_model(const fcc_sid_t *sid, fcc_sid_out_t *out)
{
    const fcc_mls_estimate_t *est = current_estimate(sid);
    out->model = est->model;
    out->rho = est->rho;
    memcpy(out->se, est->se, sizeof out->se);
    out->n_transitions = est->n_transitions;
    out->model_is_prior = est->is_prior;
    out->mls_status = sid->mls_status;
}

static void zkf_bounds(const fcc_zkf_t *zkf, fcc_sid_out_t *out)
{
    for (size_t i = 0; i < 2u; ++i) {
        out->x_hat[i] = zkf->x[i];
        out->lo[i] = zkf->x[i] - zkf->hull[i];
        out->hi[i] = zkf->x[i] + zkf->hull[i];
    }
}

/* Row of an estimate x with covariance p: +/- 3 sigma. */
static void kf_row(const fcc_real_t x[2], const fcc_real_t p[4], fcc_sid_out_t *out)
{
    const fcc_real_t s[2] = {FCC_R(3.0) * FCC_SQRT(p[0]), FCC_R(3.0) * FCC_SQRT(p[3])};
    for (size_t i = 0; i < 2u; ++i) {
        out->x_hat[i] = x[i];
        out->lo[i] = x[i] - s[i];
        out->hi[i] = x[i] + s[i];
    }
}

static void kf_bounds(const fcc_kf_t *kf, fcc_sid_out_t *out)
{
    kf_row(kf->x, kf->p, out);
}

fcc_status_t fcc_sid_init(fcc_sid_t *sid, const fcc_sid_config_t *cfg)
{
    if (sid == NULL) {
        return FCC_ERR_ARG;
    }
    fcc_status_t st = fcc_sid_config_check(cfg);
    if (st != FCC_OK) {
        return st;
    }
    memset(sid, 0, sizeof *sid);
    sid->cfg = *cfg;
    st = fcc_mls_init(&sid->mls, &cfg->mls);
    if (st != FCC_OK) {
        return st;
    }
    fcc_real_t p0_gen[4];
    if (cfg->filter == FCC_SID_KF) {
        st = fcc_kf_init(&sid->u.kf, cfg->x0, cfg->p0, cfg->e, cfg->f);
    } else if (fcc_sid_m2_cholesky(cfg->p0, p0_gen) != FCC_OK || cfg->p0[1] != cfg->p0[2]) {
        st = FCC_ERR_NOT_POSDEF;
    } else if (cfg->filter == FCC_SID_ZKF) {
        st = fcc_zkf_init(&sid->u.zkf, cfg->x0, p0_gen, cfg->e, cfg->f);
    } else {
        st = fcc_azkf_init(&sid->u.azkf, &cfg->azkf, cfg->x0, p0_gen, cfg->e, cfg->f);
    }
    if (st != FCC_OK) {
        return st;
    }
    if (cfg->filter != FCC_SID_KF) {
        fcc_zkf_set_posterior(cfg->filter == FCC_SID_ZKF ? &sid->u.zkf : &sid->u.azkf.zkf,
                              cfg->rows == FCC_SID_ROWS_POSTERIOR);
    }
    /* The "last good output" before any step: the prior. */
    fcc_sid_out_t *last = &sid->last;
    if (cfg->filter == FCC_SID_KF) {
        kf_bounds(&sid->u.kf, last);
    } else {
        zkf_bounds(cfg->filter == FCC_SID_ZKF ? &sid->u.zkf : &sid->u.azkf.zkf, last);
        last->order = cfg->filter == FCC_SID_ZKF ? cfg->zkf_order : cfg->azkf.q_normal;
    }
    fill_model(sid, last);
    return FCC_OK;
}

static fcc_status_t refuse(fcc_sid_t *sid, fcc_status_t st, fcc_sid_out_t *out)
{
    *out = sid->last;
    out->stepped = false;
    out->status = st;
    return st;
}

/* Learn the transition (x, de) -> x_next and refit, if both ends were
 * corrected by a measurement. */
static void learn(fcc_sid_t *sid, bool from_informed, const fcc_real_t x[2], fcc_real_t de,
                  const fcc_real_t x_next[2], bool to_informed)
{
    if (!sid->cfg.mls_enabled || !from_informed || !to_informed) {
        return;
    }
    sid->mls_status = fcc_mls_update(&sid->mls, x, de, x_next);
}

static fcc_status_t step_kf(fcc_sid_t *sid, const fcc_real_t y[2], fcc_real_t de, bool use_y,
                            fcc_sid_out_t *out)
{
    fcc_kf_t *kf = &sid->u.kf;
    const fcc_mls_estimate_t *est = current_estimate(sid);
    fcc_kf_info_t info;
    const fcc_status_t st = fcc_kf_step(kf, &est->model, sid->prev_de, y, use_y, &info);
    if (st != FCC_OK) {
        return st;
    }
    fill_model(sid, out);
    out->gain_norm = info.gain_norm;
    out->measurement_used = use_y;

    /* The state this row reports and whether a measurement corrected it. */
    const bool prior_rows = sid->cfg.rows == FCC_SID_ROWS_PRIOR;
    const fcc_real_t *x_row = prior_rows ? info.prior_x : kf->x;
    const bool informed = prior_rows ? (sid->have_prev && sid->cur_informed) : use_y;
    if (prior_rows) {
        kf_row(info.prior_x, info.prior_p, out);
    } else {
        kf_bounds(kf, out);
    }
    learn(sid, sid->have_prev && sid->prev_informed, sid->prev_x, sid->prev_de, x_row, informed);
    sid->prev_x[0] = x_row[0];
    sid->prev_x[1] = x_row[1];
    sid->prev_de = de;
    sid->have_prev = true;
    sid->prev_informed = informed;
    sid->cur_informed = use_y;
    return FCC_OK;
}

static fcc_status_t step_zkf(fcc_sid_t *sid, const fcc_real_t y[2], fcc_real_t de, bool use_y,
                             bool oracle, fcc_sid_out_t *out)
{
    const bool adaptive = sid->cfg.filter == FCC_SID_AZKF;
    fcc_zkf_t *zkf = adaptive ? &sid->u.azkf.zkf : &sid->u.zkf;
    const fcc_real_t x_k[2] = {zkf->x[0], zkf->x[1]};
    fill_model(sid, out);
    zkf_bounds(zkf, out); /* row k: x_k and <x_k, P_k> before y_k */

    const fcc_sid_model_t *model = &current_estimate(sid)->model;
    fcc_zkf_info_t zinfo;
    bool fault = false;
    fcc_status_t st;
    if (adaptive) {
        fcc_azkf_info_t ainfo;
        const bool armed = !sid->cfg.mls_enabled || sid->cfg.arm_on_prior ||
                           !current_estimate(sid)->is_prior;
        st = fcc_azkf_step(&sid->u.azkf, model, de, y, use_y, armed, oracle, &ainfo);
        if (st != FCC_OK) { /* ainfo is not written on failure: read it only after success */
            return st;
        }
        zinfo = ainfo.zkf;
        fault = ainfo.fault;
    } else {
        st = fcc_zkf_step(zkf, model, de, y, use_y, sid->cfg.zkf_order, &zinfo);
        if (st != FCC_OK) {
            return st;
        }
    }
    out->gain_norm = zinfo.gain_norm;
    out->order = zinfo.order;
    out->n_generators = zinfo.n_generators;
    out->fault = fault;
    out->measurement_used = zinfo.updated;

    /* a fault detected with hold-on-fault keeps this step out of the MLS (named apart: clang
     * measures no MC/DC of a decision that negates a nested one) */
    const bool held = fault && sid->cfg.mls_hold_on_fault;
    const bool informed = zinfo.updated && !held;
    if (sid->cfg.rows != FCC_SID_ROWS_POSTERIOR) {
        learn(sid, sid->cur_informed, x_k, de, zkf->x, informed);
        sid->cur_informed = informed;
        return FCC_OK;
    }
    /* Posterior rows: x_k|k, its set, ||G'_k||; the MLS learns x_k-1|k-1 -> x_k|k. */
    for (size_t i = 0; i < 2u; ++i) {
        out->x_hat[i] = zinfo.post_x[i];
        out->lo[i] = zinfo.post_x[i] - zinfo.post_hull[i];
        out->hi[i] = zinfo.post_x[i] + zinfo.post_hull[i];
    }
    out->gain_norm = zinfo.post_gain_norm;
    learn(sid, sid->have_prev && sid->prev_informed, sid->prev_x, sid->prev_de, zinfo.post_x,
          informed);
    sid->prev_x[0] = zinfo.post_x[0];
    sid->prev_x[1] = zinfo.post_x[1];
    sid->prev_de = de;
    sid->have_prev = true;
    sid->prev_informed = informed;
    return FCC_OK;
}

fcc_status_t fcc_sid_step(fcc_sid_t *sid, fcc_real_t y_alpha, fcc_real_t y_q, fcc_real_t de,
                          bool oracle_fault, bool measurement_valid, fcc_sid_out_t *out)
{
    if (sid == NULL || out == NULL) {
        return FCC_ERR_ARG;
    }
    if (!FCC_IS_FINITE(de)) {
        return refuse(sid, FCC_ERR_NOT_FINITE, out);
    }
    if (FCC_FABS(de) > sid->cfg.de_limit) {
        return refuse(sid, FCC_ERR_RANGE, out);
    }
    const fcc_real_t y[2] = {y_alpha, y_q};
    fcc_status_t input_status = FCC_OK;
    bool use_y = measurement_valid;
    if (use_y && !fcc_sid_all_finite(y, 2)) {
        use_y = false;
        input_status = FCC_ERR_NOT_FINITE;
    } else if (use_y && (FCC_FABS(y_alpha) > sid->cfg.alpha_limit ||
                         FCC_FABS(y_q) > sid->cfg.q_limit)) {
        use_y = false;
        input_status = FCC_ERR_RANGE;
    } else {
        /* no measurement, or a usable one: as given */
    }

    fcc_sid_out_t o;
    memset(&o, 0, sizeof o);
    const fcc_status_t st = sid->cfg.filter == FCC_SID_KF
                                ? step_kf(sid, y, de, use_y, &o)
                                : step_zkf(sid, y, de, use_y, oracle_fault, &o);
    if (st != FCC_OK) {
        const fcc_status_t r = refuse(sid, st, out);
        out->filter_status = st;
        return r;
    }
    o.k = sid->k++;
    o.stepped = true;
    o.input_status = input_status;
    o.filter_status = FCC_OK;
    o.status = input_status != FCC_OK ? input_status : o.mls_status;
    sid->last = o;
    *out = o;
    return o.status;
}
