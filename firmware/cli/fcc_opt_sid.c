/*
 * fcc_opt_sid.c -- the identification options of fcc and sid_replay (see
 * fcc_opt_sid.h).
 */
#include "fcc_opt_sid.h"

#include <limits.h>
#include <string.h>

/* Sanity bounds on the reals (the firmware only needs the lower ones). */
#define RIDGE_MAX 1e12
#define MAX_COND_MAX 1e30
#define MAX_RHO_MAX 1e3
#define MARGIN_MIN 1e-6
#define MARGIN_MAX 1e6
/* Bound on every element of a prior model (a 50 Hz discrete model has |a| ~ 1) and of the
 * --p0/--e/--f matrices: beyond these the filters overflow (float) or are meaningless. */
#define PRIOR_MAX 1e3
#define MAT2_MAX 1e6

/* Every value of v[0..n) within -hi..hi, else one message naming the option. */
static fcc_opt_result_t check_abs(const char *name, const double *v, int n, double hi, char *err,
                                  size_t len)
{
    for (int i = 0; i < n; ++i) {
        if (v[i] < -hi || v[i] > hi) {
            return fcc_opt_fail(err, len, "%s: value %d (%g) is outside %g..%g", name, i + 1,
                                v[i], -hi, hi);
        }
    }
    return FCC_OPT_DONE;
}

void fcc_opt_sid_begin(fcc_opt_sid_t *s, fcc_sid_config_t *cfg)
{
    s->cfg = cfg;
    s->prior_given = false;
    s->min_transitions_given = false;
}

/* A zonotope order: the messages name the compile-time bound, which a
 * build can raise (-DFCC_ZONO_MAX_ORDER=...). */
static fcc_opt_result_t get_order(const char *name, const char *val, uint16_t *out, char *err,
                                  size_t len)
{
    unsigned long v = 0u;
    const fcc_opt_result_t r = fcc_opt_uint(name, val, 0u, ULONG_MAX, &v, err, len);
    if (r != FCC_OPT_DONE) {
        return r;
    }
    if (v > FCC_ZONO_MAX_ORDER) {
        return fcc_opt_fail(err, len,
                            "%s: order %lu is above the compile-time bound FCC_ZONO_MAX_ORDER = %u",
                            name, v, FCC_ZONO_MAX_ORDER);
    }
    if (v < FCC_ZONO_MIN_ORDER) {
        return fcc_opt_fail(err, len, "%s: order %lu is below the state dimension %u", name, v,
                            FCC_ZONO_MIN_ORDER);
    }
    *out = (uint16_t)v;
    return FCC_OPT_DONE;
}

fcc_opt_result_t fcc_opt_sid_model(fcc_opt_sid_t *s, const char *name, const char *val,
                                   char *err, size_t len)
{
    double v[8];
    if (val == NULL) {
        return FCC_OPT_NEED_VALUE;
    }
    const int n = fcc_opt_list(val, v, 8);
    if (n != 6 && n != 8) {
        return fcc_opt_fail(
            err, len, "%s: expected a11,a12,a21,a22,b1,b2[,c1,c2] (6 or 8 finite numbers), got '%s'",
            name, val);
    }
    const fcc_opt_result_t r = check_abs(name, v, n, PRIOR_MAX, err, len);
    if (r != FCC_OPT_DONE) {
        return r;
    }
    fcc_sid_model_t *m = &s->cfg->mls.prior;
    for (int i = 0; i < 4; ++i) {
        m->a[i] = (fcc_real_t)v[i];
    }
    m->b[0] = (fcc_real_t)v[4];
    m->b[1] = (fcc_real_t)v[5];
    m->c[0] = (n == 8) ? (fcc_real_t)v[6] : FCC_R(0.0);
    m->c[1] = (n == 8) ? (fcc_real_t)v[7] : FCC_R(0.0);
    if (n == 8) {
        s->cfg->mls.intercept = true;
    }
    s->prior_given = true;
    return FCC_OPT_DONE;
}

/* The MLS: window, guards, prior. */
static fcc_opt_result_t apply_mls(fcc_opt_sid_t *s, const char *name, const char *val, char *err,
                                  size_t len)
{
    fcc_mls_config_t *m = &s->cfg->mls;
    if (strcmp(name, "--window") == 0) {
        return fcc_opt_u16(name, val, 4u, FCC_MLS_MAX_WINDOW, &m->window, err, len);
    }
    if (strcmp(name, "--min-transitions") == 0) {
        const fcc_opt_result_t r =
            fcc_opt_u16(name, val, 4u, FCC_MLS_MAX_WINDOW, &m->min_transitions, err, len);
        s->min_transitions_given = s->min_transitions_given || r == FCC_OPT_DONE;
        return r;
    }
    if (strcmp(name, "--ridge") == 0) {
        return fcc_opt_real(name, val, 0.0, RIDGE_MAX, &m->ridge, err, len);
    }
    if (strcmp(name, "--max-cond") == 0) {
        return fcc_opt_real(name, val, 1.0, MAX_COND_MAX, &m->max_cond, err, len);
    }
    if (strcmp(name, "--max-rho") == 0) {
        return fcc_opt_real(name, val, 0.0, MAX_RHO_MAX, &m->max_rho, err, len);
    }
    if (strcmp(name, "--prior") == 0) {
        return fcc_opt_sid_model(s, name, val, err, len);
    }
    if (strcmp(name, "--mls-intercept") == 0) {
        return fcc_opt_flag(name, val, &m->intercept, true, err, len);
    }
    if (strcmp(name, "--no-mls-hold") == 0) {
        return fcc_opt_flag(name, val, &s->cfg->mls_hold_on_fault, false, err, len);
    }
    return FCC_OPT_NOT_MINE;
}

/* The filters: orders, initial state, noise generators. */
static fcc_opt_result_t apply_filters(fcc_sid_config_t *c, const char *name, const char *val,
                                      char *err, size_t len)
{
    if (strcmp(name, "--zkf-order") == 0) return get_order(name, val, &c->zkf_order, err, len);
    if (strcmp(name, "--rows") == 0) {
        static const char *const rows[] = {"paper", "prior", "posterior"};
        static const fcc_sid_rows_t rows_of[] = {FCC_SID_ROWS_PAPER, FCC_SID_ROWS_PRIOR,
                                                 FCC_SID_ROWS_POSTERIOR};
        int i = 0;
        const fcc_opt_result_t r = fcc_opt_choice(name, val, rows, 3, &i, err, len);
        c->rows = (r == FCC_OPT_DONE) ? rows_of[i] : c->rows;
        return r;
    }
    if (strcmp(name, "--q-normal") == 0) return get_order(name, val, &c->azkf.q_normal, err, len);
    if (strcmp(name, "--q-fault") == 0) return get_order(name, val, &c->azkf.q_fault, err, len);
    fcc_real_t *mat = NULL;
    if (strcmp(name, "--p0") == 0) mat = c->p0;
    if (strcmp(name, "--e") == 0) mat = c->e;
    if (strcmp(name, "--f") == 0) mat = c->f;
    if (mat != NULL) {
        fcc_real_t m[4];
        const fcc_opt_result_t r = fcc_opt_mat2(name, val, m, err, len);
        if (r != FCC_OPT_DONE) {
            return r;
        }
        const double d[4] = {(double)m[0], (double)m[1], (double)m[2], (double)m[3]};
        const fcc_opt_result_t b = check_abs(name, d, 4, MAT2_MAX, err, len);
        if (b == FCC_OPT_DONE) {
            memcpy(mat, m, sizeof m);
        }
        return b;
    }
    if (strcmp(name, "--x0") == 0) {
        double v[2];
        if (val == NULL) {
            return FCC_OPT_NEED_VALUE;
        }
        if (fcc_opt_list(val, v, 2) != 2) {
            return fcc_opt_fail(err, len, "--x0: expected alpha,q (2 finite numbers), got '%s'",
                                val);
        }
        const double lim[2] = {(double)c->alpha_limit, (double)c->q_limit};
        for (int i = 0; i < 2; ++i) {
            if (v[i] < -lim[i] || v[i] > lim[i]) {
                return fcc_opt_fail(err, len, "--x0: %s = %g is outside %g..%g (what the "
                                    "sensor can read)", i == 0 ? "alpha" : "q", v[i], -lim[i],
                                    lim[i]);
            }
        }
        c->x0[0] = (fcc_real_t)v[0];
        c->x0[1] = (fcc_real_t)v[1];
        return FCC_OPT_DONE;
    }
    return FCC_OPT_NOT_MINE;
}

/* The AZKF's fault policy and its detector. */
static fcc_opt_result_t apply_detector(fcc_sid_config_t *c, const char *name, const char *val,
                                       char *err, size_t len)
{
    static const char *const policies[] = {"order", "skip"};
    static const fcc_azkf_policy_t policy_of[] = {FCC_AZKF_POLICY_ORDER, FCC_AZKF_POLICY_SKIP};
    static const char *const modes[] = {"zonotope", "oracle", "off"};
    static const fcc_fdet_mode_t mode_of[] = {FCC_FDET_ZONOTOPE, FCC_FDET_ORACLE, FCC_FDET_OFF};
    fcc_fdet_config_t *d = &c->azkf.det;
    int i = 0;
    fcc_opt_result_t r = FCC_OPT_NOT_MINE;
    if (strcmp(name, "--fault-policy") == 0) {
        r = fcc_opt_choice(name, val, policies, 2, &i, err, len);
        c->azkf.policy = (r == FCC_OPT_DONE) ? policy_of[i] : c->azkf.policy;
    } else if (strcmp(name, "--detector") == 0) {
        r = fcc_opt_choice(name, val, modes, 3, &i, err, len);
        d->mode = (r == FCC_OPT_DONE) ? mode_of[i] : d->mode;
    } else if (strcmp(name, "--margin") == 0) {
        r = fcc_opt_real(name, val, MARGIN_MIN, MARGIN_MAX, &d->margin, err, len);
    } else if (strcmp(name, "--raise") == 0) {
        r = fcc_opt_u16(name, val, 1u, UINT16_MAX, &d->raise_count, err, len);
    } else if (strcmp(name, "--hold") == 0) {
        r = fcc_opt_u16(name, val, 0u, UINT16_MAX, &d->hold_count, err, len);
    } else if (strcmp(name, "--clear") == 0) {
        r = fcc_opt_u16(name, val, 1u, UINT16_MAX, &d->clear_count, err, len);
    } else if (strcmp(name, "--max-fault") == 0) {
        r = fcc_opt_u16(name, val, 0u, UINT16_MAX, &d->max_fault_steps, err, len);
    } else if (strcmp(name, "--no-arm-on-prior") == 0) {
        r = fcc_opt_flag(name, val, &c->arm_on_prior, false, err, len);
    }
    return r;
}

fcc_opt_result_t fcc_opt_sid_apply(fcc_opt_sid_t *s, const char *name, const char *val,
                                   char *err, size_t len)
{
    fcc_opt_result_t r = apply_mls(s, name, val, err, len);
    if (r == FCC_OPT_NOT_MINE) {
        r = apply_filters(s->cfg, name, val, err, len);
    }
    if (r == FCC_OPT_NOT_MINE) {
        r = apply_detector(s->cfg, name, val, err, len);
    }
    return r;
}

void fcc_opt_sid_end(fcc_opt_sid_t *s)
{
    fcc_mls_config_t *m = &s->cfg->mls;
    if (!s->min_transitions_given && m->min_transitions > m->window) {
        m->min_transitions = m->window;
    }
    if (m->intercept && !s->prior_given) {
        fcc_sid_default_prior_affine(&m->prior);
    }
}

void fcc_opt_sid_usage(FILE *out)
{
    fprintf(out,
        "identification options (the same in fcc and sid_replay; defaults: the paper's\n"
        "and the firmware's):\n"
        "  --window N                    MLS window, transitions (%u; 4..%u)\n"
        "  --min-transitions N           prior model until N transitions (%u, at most the\n"
        "                                window)\n"
        "  --ridge R                     Tikhonov weight toward the prior (%g)\n"
        "  --max-cond R                  MLS conditioning guard (%g)\n"
        "  --max-rho R                   refuse fits with rho(A) above R, 0 = off (%g)\n"
        "  --prior a11,a12,a21,a22,b1,b2[,c1,c2]  prior model (default: the CDRW's\n"
        "                                wind-tunnel model at trim, see fcc_sid.h;\n"
        "                                8 values: with c, which turns the intercept on)\n"
        "  --mls-intercept               fit x+ = A x + B de + c (not in the paper; the\n"
        "                                default prior becomes the affine wind-tunnel model)\n"
        "  --no-mls-hold                 AZKF: keep learning while a fault is flagged\n"
        "  --no-arm-on-prior             AZKF: detector off until the MLS has fitted a model\n"
        "  --rows paper|prior|posterior  estimate each row reports, and the MLS learns from:\n"
        "                                paper = KF after y_k, ZKF/AZKF before (default);\n"
        "                                prior = all before y_k; posterior = all after\n"
        "  --zkf-order N                 ZKF fixed order (%u; %u..%u)\n"
        "  --q-normal N / --q-fault N    AZKF orders without / during a fault (%u / %u)\n"
        "  --fault-policy order|skip     AZKF fault policy (order)\n"
        "  --detector zonotope|oracle|off  fault detector (zonotope; oracle: the simulator's\n"
        "                                fault flag, a 'fault' column or SIM_EVENT)\n"
        "  --margin M                    detector margin on the hull (%g)\n"
        "  --raise N / --hold N / --clear N  detector counts (%u / %u / %u)\n"
        "  --max-fault N                 longest flagged fault, steps; 0 = no limit (%u)\n"
        "  --x0 a,q                      initial estimate (%g,%g; |a| <= %g rad, |q| <= %g rad/s)\n"
        "  --p0 s | s1,s2 | p11,p12,p21,p22  initial KF covariance; the ZKFs start\n"
        "                                from its Cholesky factor (%g)\n"
        "  --e s | e1,e2 | 4 values      process noise generators E (%g)\n"
        "  --f s | f1,f2 | 4 values      measurement noise generators F (%g)\n",
        FCC_MLS_DEFAULT_WINDOW, FCC_MLS_MAX_WINDOW, FCC_MLS_DEFAULT_MIN_TRANSITIONS,
        (double)FCC_MLS_DEFAULT_RIDGE, (double)FCC_MLS_DEFAULT_MAX_COND,
        (double)FCC_MLS_DEFAULT_MAX_RHO, (unsigned)FCC_SID_DEFAULT_ZKF_ORDER, FCC_ZONO_MIN_ORDER,
        FCC_ZONO_MAX_ORDER, FCC_AZKF_DEFAULT_Q_NORMAL, FCC_AZKF_DEFAULT_Q_FAULT,
        (double)FCC_FDET_DEFAULT_MARGIN, FCC_FDET_DEFAULT_RAISE, FCC_FDET_DEFAULT_HOLD,
        FCC_FDET_DEFAULT_CLEAR, FCC_FDET_DEFAULT_MAX_FAULT, (double)FCC_SID_DEFAULT_X0_ALPHA,
        (double)FCC_SID_DEFAULT_X0_Q, (double)FCC_SID_DEFAULT_ALPHA_LIMIT,
        (double)FCC_SID_DEFAULT_Q_LIMIT, (double)FCC_SID_DEFAULT_P0, (double)FCC_SID_DEFAULT_E,
        (double)FCC_SID_DEFAULT_F);
}
