#include "sid_replay_opts.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef __GNUC__
__attribute__((format(printf, 3, 4)))
#endif
static int fail(char *err, size_t len, const char *fmt, ...);

static int fail(char *err, size_t len, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    (void)vsnprintf(err, len, fmt, ap);
    va_end(ap);
    return -1;
}

void sid_opts_usage(const char *prog)
{
    printf("usage: %s [options] [FILE|-]\n"
           "Replays a flight CSV (t,alpha,q,de[,fault]) through MLS-KF, MLS-ZKF and MLS-AZKF\n"
           "and writes one row per step per filter:\n"
           "  t,filter,alpha_hat,q_hat,alpha_lo,alpha_hi,q_lo,q_hi,gain_norm,order,fault,\n"
           "  a11,a12,a21,a22,b1,b2,rho   (and c1,c2 with --mls-intercept)\n"
           "options (defaults: paper values and firmware defaults):\n"
           "  --filter kf|zkf|azkf|all      filters to run (all)\n"
           "  --window N                    MLS window, transitions (%u; max %u)\n"
           "  --min-transitions N           prior model until N transitions (%u)\n"
           "  --ridge R                     Tikhonov weight toward the prior (%g)\n"
           "  --max-cond R                  MLS conditioning guard (%g)\n"
           "  --max-rho R                   refuse fits with rho(A) above R, 0 = off (%g)\n"
           "  --prior a11,a12,a21,a22,b1,b2[,c1,c2]  prior model (default: the CDRW's\n"
           "                                wind-tunnel model at trim, see fcc_sid.h;\n"
           "                                8 values: with c, which turns the intercept on)\n"
           "  --mls-intercept               fit x+ = A x + B de + c (not in the paper; the\n"
           "                                default prior becomes the affine wind-tunnel model)\n"
           "  --fixed-model a11,...,b2[,c1,c2]  MLS off: this model every step\n"
           "  --mls-only                    input states are exact: print the MLS fit per step\n"
           "  --no-mls-hold                 AZKF: keep learning while a fault is flagged\n"
           "  --no-arm-on-prior             AZKF: detector off until the MLS has fitted a model\n"
           "  --zkf-order N                 ZKF fixed order (%u; max %u)\n"
           "  --q-normal N / --q-fault N    AZKF orders (%u / %u)\n"
           "  --fault-policy order|skip     AZKF fault policy (order)\n"
           "  --detector zonotope|oracle|off  fault detector (zonotope)\n"
           "  --margin M                    detector margin on the hull (%g)\n"
           "  --raise N / --hold N / --clear N  detector counts (%u / %u / %u)\n"
           "  --max-fault N                 longest flagged fault, steps; 0 = no limit (%u)\n"
           "  --x0 a,q                      initial estimate (0.1571,0.0204)\n"
           "  --p0 s | s1,s2 | p11,p12,p21,p22  initial KF covariance; the ZKFs start\n"
           "                                from its Cholesky factor (0.1)\n"
           "  --e s | e1,e2 | 4 values      process noise generators E (0.004)\n"
           "  --f s | f1,f2 | 4 values      measurement noise generators F (0.02)\n",
           prog, FCC_MLS_DEFAULT_WINDOW, FCC_MLS_MAX_WINDOW, FCC_MLS_DEFAULT_MIN_TRANSITIONS,
           (double)FCC_MLS_DEFAULT_RIDGE, (double)FCC_MLS_DEFAULT_MAX_COND,
           (double)FCC_MLS_DEFAULT_MAX_RHO, FCC_SID_DEFAULT_ZKF_ORDER, FCC_ZONO_MAX_ORDER,
           FCC_AZKF_DEFAULT_Q_NORMAL, FCC_AZKF_DEFAULT_Q_FAULT, (double)FCC_FDET_DEFAULT_MARGIN,
           FCC_FDET_DEFAULT_RAISE, FCC_FDET_DEFAULT_HOLD, FCC_FDET_DEFAULT_CLEAR,
           FCC_FDET_DEFAULT_MAX_FAULT);
}

/* Comma-separated finite reals; returns the count or -1. */
static int parse_list(const char *s, double *v, int max)
{
    int n = 0;
    const char *p = s;
    for (;;) {
        if (n == max) {
            return -1;
        }
        char *end = NULL;
        errno = 0;
        v[n] = strtod(p, &end);
        if (end == p || errno == ERANGE || !isfinite(v[n])) {
            return -1;
        }
        ++n;
        if (*end == '\0') {
            return n;
        }
        if (*end != ',') {
            return -1;
        }
        p = end + 1;
    }
}

static int parse_real(const char *name, const char *val, fcc_real_t *out, char *err, size_t len)
{
    double v;
    if (parse_list(val, &v, 1) != 1) {
        return fail(err, len, "%s: '%s' is not a finite number", name, val);
    }
    *out = (fcc_real_t)v;
    return 0;
}

static int parse_count(const char *name, const char *val, unsigned max, uint16_t *out, char *err,
                       size_t len)
{
    char *end = NULL;
    errno = 0;
    const long v = strtol(val, &end, 10);
    if (end == val || *end != '\0' || errno == ERANGE || v < 0) {
        return fail(err, len, "%s: '%s' is not a non-negative integer", name, val);
    }
    if ((unsigned long)v > max) {
        return fail(err, len, "%s: %ld is above the limit %u", name, v, max);
    }
    *out = (uint16_t)v;
    return 0;
}

static int parse_order(const char *name, const char *val, uint16_t *out, char *err, size_t len)
{
    char *end = NULL;
    errno = 0;
    const long v = strtol(val, &end, 10);
    if (end == val || *end != '\0' || errno == ERANGE) {
        return fail(err, len, "%s: '%s' is not an integer", name, val);
    }
    if (v > (long)FCC_ZONO_MAX_ORDER) {
        return fail(err, len, "%s: order %ld is above the compile-time bound FCC_ZONO_MAX_ORDER = %u",
                    name, v, FCC_ZONO_MAX_ORDER);
    }
    if (v < (long)FCC_ZONO_MIN_ORDER) {
        return fail(err, len, "%s: order %ld is below the state dimension %u", name, v,
                    FCC_ZONO_MIN_ORDER);
    }
    *out = (uint16_t)v;
    return 0;
}

/* 1 value: s I; 2: diag; 4: row-major matrix. */
static int parse_matrix(const char *name, const char *val, fcc_real_t m[4], char *err, size_t len)
{
    double v[4];
    const int n = parse_list(val, v, 4);
    if (n == 1 || n == 2) {
        m[0] = (fcc_real_t)v[0];
        m[1] = FCC_R(0.0);
        m[2] = FCC_R(0.0);
        m[3] = (fcc_real_t)v[n - 1];
        return 0;
    }
    if (n == 4) {
        for (int i = 0; i < 4; ++i) {
            m[i] = (fcc_real_t)v[i];
        }
        return 0;
    }
    return fail(err, len, "%s: expected 1, 2 or 4 comma-separated finite numbers, got '%s'", name,
                val);
}

/* 6 values (the paper's model, c = 0) or 8 (with the affine term c, which
 * turns the intercept on so that the MLS keeps it). */
static int parse_model(const char *name, const char *val, fcc_sid_config_t *c, char *err,
                       size_t len)
{
    double v[8];
    const int n = parse_list(val, v, 8);
    if (n != 6 && n != 8) {
        return fail(err, len,
                    "%s: expected a11,a12,a21,a22,b1,b2[,c1,c2] (6 or 8 finite numbers), got '%s'",
                    name, val);
    }
    fcc_sid_model_t *m = &c->mls.prior;
    for (int i = 0; i < 4; ++i) {
        m->a[i] = (fcc_real_t)v[i];
    }
    m->b[0] = (fcc_real_t)v[4];
    m->b[1] = (fcc_real_t)v[5];
    m->c[0] = n == 8 ? (fcc_real_t)v[6] : FCC_R(0.0);
    m->c[1] = n == 8 ? (fcc_real_t)v[7] : FCC_R(0.0);
    if (n == 8) {
        c->mls.intercept = true;
    }
    return 0;
}

static int parse_filter(const char *val, sid_opts_t *o, char *err, size_t len)
{
    static const char *const names[3] = {"kf", "zkf", "azkf"};
    const bool all = strcmp(val, "all") == 0;
    bool any = all;
    for (int i = 0; i < 3; ++i) {
        o->run[i] = all || strcmp(val, names[i]) == 0;
        any = any || o->run[i];
    }
    return any ? 0 : fail(err, len, "--filter: '%s' is not kf, zkf, azkf or all", val);
}

static int parse_detector(const char *val, fcc_fdet_mode_t *mode, char *err, size_t len)
{
    if (strcmp(val, "zonotope") == 0) {
        *mode = FCC_FDET_ZONOTOPE;
    } else if (strcmp(val, "oracle") == 0) {
        *mode = FCC_FDET_ORACLE;
    } else if (strcmp(val, "off") == 0) {
        *mode = FCC_FDET_OFF;
    } else {
        return fail(err, len, "--detector: '%s' is not zonotope, oracle or off", val);
    }
    return 0;
}

static int parse_policy(const char *val, fcc_azkf_policy_t *policy, char *err, size_t len)
{
    if (strcmp(val, "order") == 0) {
        *policy = FCC_AZKF_POLICY_ORDER;
    } else if (strcmp(val, "skip") == 0) {
        *policy = FCC_AZKF_POLICY_SKIP;
    } else {
        return fail(err, len, "--fault-policy: '%s' is not order or skip", val);
    }
    return 0;
}

static int parse_x0(const char *val, fcc_real_t x0[2], char *err, size_t len)
{
    double v[2];
    if (parse_list(val, v, 2) != 2) {
        return fail(err, len, "--x0: expected alpha,q (2 finite numbers), got '%s'", val);
    }
    x0[0] = (fcc_real_t)v[0];
    x0[1] = (fcc_real_t)v[1];
    return 0;
}

/* Options that take a value. */
static int apply(sid_opts_t *o, const char *name, const char *val, bool *min_set, char *err,
                 size_t len)
{
    if (strcmp(name, "--prior") == 0 || strcmp(name, "--fixed-model") == 0) {
        o->prior_given = true;
    }
    fcc_sid_config_t *c = &o->cfg;
    if (strcmp(name, "--filter") == 0) return parse_filter(val, o, err, len);
    if (strcmp(name, "--window") == 0) return parse_count(name, val, FCC_MLS_MAX_WINDOW, &c->mls.window, err, len);
    if (strcmp(name, "--min-transitions") == 0) {
        *min_set = true;
        return parse_count(name, val, FCC_MLS_MAX_WINDOW, &c->mls.min_transitions, err, len);
    }
    if (strcmp(name, "--ridge") == 0) return parse_real(name, val, &c->mls.ridge, err, len);
    if (strcmp(name, "--max-cond") == 0) return parse_real(name, val, &c->mls.max_cond, err, len);
    if (strcmp(name, "--max-rho") == 0) return parse_real(name, val, &c->mls.max_rho, err, len);
    if (strcmp(name, "--prior") == 0) return parse_model(name, val, c, err, len);
    if (strcmp(name, "--fixed-model") == 0) {
        o->fixed_model = true;
        c->mls_enabled = false;
        return parse_model(name, val, c, err, len);
    }
    if (strcmp(name, "--zkf-order") == 0) return parse_order(name, val, &c->zkf_order, err, len);
    if (strcmp(name, "--q-normal") == 0) return parse_order(name, val, &c->azkf.q_normal, err, len);
    if (strcmp(name, "--q-fault") == 0) return parse_order(name, val, &c->azkf.q_fault, err, len);
    if (strcmp(name, "--fault-policy") == 0) return parse_policy(val, &c->azkf.policy, err, len);
    if (strcmp(name, "--detector") == 0) return parse_detector(val, &c->azkf.det.mode, err, len);
    if (strcmp(name, "--margin") == 0) return parse_real(name, val, &c->azkf.det.margin, err, len);
    if (strcmp(name, "--raise") == 0) return parse_count(name, val, UINT16_MAX, &c->azkf.det.raise_count, err, len);
    if (strcmp(name, "--hold") == 0) return parse_count(name, val, UINT16_MAX, &c->azkf.det.hold_count, err, len);
    if (strcmp(name, "--clear") == 0) return parse_count(name, val, UINT16_MAX, &c->azkf.det.clear_count, err, len);
    if (strcmp(name, "--max-fault") == 0) return parse_count(name, val, UINT16_MAX, &c->azkf.det.max_fault_steps, err, len);
    if (strcmp(name, "--x0") == 0) return parse_x0(val, c->x0, err, len);
    if (strcmp(name, "--p0") == 0) return parse_matrix(name, val, c->p0, err, len);
    if (strcmp(name, "--e") == 0) return parse_matrix(name, val, c->e, err, len);
    if (strcmp(name, "--f") == 0) return parse_matrix(name, val, c->f, err, len);
    return fail(err, len, "unknown option '%s' (see --help)", name);
}

/* Options without a value; 1 when name is one of them. */
static int apply_flag(sid_opts_t *o, const char *name)
{
    if (strcmp(name, "--mls-only") == 0) {
        o->mls_only = true;
        return 1;
    }
    if (strcmp(name, "--no-mls-hold") == 0) {
        o->cfg.mls_hold_on_fault = false;
        return 1;
    }
    if (strcmp(name, "--mls-intercept") == 0) {
        o->cfg.mls.intercept = true;
        return 1;
    }
    if (strcmp(name, "--no-arm-on-prior") == 0) {
        o->cfg.arm_on_prior = false;
        return 1;
    }
    return 0;
}

int sid_opts_parse(int argc, char **argv, sid_opts_t *o, char *err, size_t len)
{
    memset(o, 0, sizeof *o);
    fcc_sid_config_default(&o->cfg, FCC_SID_KF);
    o->run[0] = o->run[1] = o->run[2] = true;
    bool min_set = false;
    for (int i = 1; i < argc; ++i) {
        const char *arg = argv[i];
        if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
            sid_opts_usage(argv[0]);
            return 1;
        }
        if (strncmp(arg, "--", 2) != 0 || strcmp(arg, "-") == 0) {
            if (o->input != NULL) {
                return fail(err, len, "more than one input file ('%s', '%s')", o->input, arg);
            }
            o->input = arg;
            continue;
        }
        if (apply_flag(o, arg)) {
            continue;
        }
        char name[64];
        const char *eq = strchr(arg, '=');
        const char *val;
        if (eq != NULL) {
            const size_t n = (size_t)(eq - arg);
            if (n >= sizeof name) {
                return fail(err, len, "unknown option '%s' (see --help)", arg);
            }
            memcpy(name, arg, n);
            name[n] = '\0';
            val = eq + 1;
        } else {
            if (strlen(arg) >= sizeof name) {
                return fail(err, len, "unknown option '%s' (see --help)", arg);
            }
            strcpy(name, arg);
            if (i + 1 >= argc) {
                return fail(err, len, "option %s needs a value", name);
            }
            val = argv[++i];
        }
        if (apply(o, name, val, &min_set, err, len) != 0) {
            return -1;
        }
    }
    if (!min_set && o->cfg.mls.min_transitions > o->cfg.mls.window) {
        o->cfg.mls.min_transitions = o->cfg.mls.window;
    }
    if (o->cfg.mls.intercept && !o->prior_given) {
        fcc_sid_default_prior_affine(&o->cfg.mls.prior);
    }
    return 0;
}
