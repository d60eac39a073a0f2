/*
 * fcc_cli.c -- command line of fcc (see fcc_cli.h).
 */
#include "fcc_cli.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

static int fail(char *err, size_t len, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

static int fail(char *err, size_t len, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    (void)vsnprintf(err, len, fmt, ap);
    va_end(ap);
    return -1;
}

void fcc_cli_usage(FILE *out)
{
    fprintf(out,
        "usage: fcc [options]\n"
        "The flight computer on a CAN bus: CDRW identification (MLS + KF/ZKF/AZKF, 50 Hz) and\n"
        "the missile LQG autopilot (period T, N-bit D/A). Protocol: firmware/app/README.md.\n"
        "\n"
        "  --iface NAME             CAN interface (vcan0)\n"
        "  --mode lockstep|realtime step on SIM_TICK, or on the clock (lockstep)\n"
        "  --apps LIST              cdrw,missile | cdrw | missile (cdrw,missile)\n"
        "  --duration S             stop after S seconds (0: run until a signal or a shutdown frame)\n"
        "  --status-rate HZ         heartbeat rate, 0 = only at start and exit (10)\n"
        "  --rt-priority P          run under SCHED_FIFO priority P (1..99) with memory locked;\n"
        "                           0 = normal scheduling (0)\n"
        "  --stale-limit N          missing frames bridged with the last value before a sensor\n"
        "                           is stale and the step degraded (%u)\n"
        "missile autopilot:\n"
        "  --lqg-period T           sampling period, s, 0.02..0.3 (0.05)\n"
        "  --lqg-bits N             D/A word length, 2..16 (8)\n"
        "  --gyro-var V             rate-gyro noise variance, rad^2/s^2 (0.8)\n"
        "  --accel-var V            accelerometer noise variance, ft^2/s^4 (0.8)\n"
        "  --solver hamiltonian|doubling  Riccati solution used (both are computed and compared)\n"
        "identification (as sid_replay):\n"
        "  --window N               MLS window, transitions (%u; max %u)\n"
        "  --min-transitions N      prior model until N transitions (%u)\n"
        "  --ridge R                Tikhonov weight toward the prior (%g)\n"
        "  --max-cond R             MLS conditioning guard (%g)\n"
        "  --max-rho R              refuse fits with rho(A) above R, 0 = off (%g)\n"
        "  --prior a11,a12,a21,a22,b1,b2  prior model\n"
        "  --no-mls-hold            AZKF: keep learning while a fault is flagged\n"
        "  --zkf-order N            ZKF fixed order (%u; max %u)\n"
        "  --q-normal N             AZKF order without a fault (%u)\n"
        "  --q-fault N              AZKF order during a fault (%u)\n"
        "  --fault-policy order|skip  AZKF fault policy (order)\n"
        "  --detector zonotope|oracle|off  fault detector (zonotope; oracle reads SIM_EVENT)\n"
        "  --margin M               detector margin on the hull (%g)\n"
        "  --raise N / --hold N / --clear N  detector counts (%u / %u / %u)\n"
        "  --x0 a,q                 initial estimate (0.1571,0.0204)\n"
        "  --p0 s | s1,s2 | 4 values  initial covariance (0.1)\n"
        "  --e s | e1,e2 | 4 values process noise generators E (0.004)\n"
        "  --f s | f1,f2 | 4 values measurement noise generators F (0.02)\n"
        "  --help                   this text\n"
        "Exit: 0 after SIGINT/SIGTERM, --duration or a shutdown frame; 1 start-up failure\n"
        "(e.g. no such interface); 2 bad command line.\n",
        FCC_NODE_DEFAULT_STALE_LIMIT, FCC_MLS_DEFAULT_WINDOW, FCC_MLS_MAX_WINDOW,
        FCC_MLS_DEFAULT_MIN_TRANSITIONS, (double)FCC_MLS_DEFAULT_RIDGE,
        (double)FCC_MLS_DEFAULT_MAX_COND, (double)FCC_MLS_DEFAULT_MAX_RHO,
        (unsigned)FCC_SID_DEFAULT_ZKF_ORDER, FCC_ZONO_MAX_ORDER, FCC_AZKF_DEFAULT_Q_NORMAL,
        FCC_AZKF_DEFAULT_Q_FAULT, (double)FCC_FDET_DEFAULT_MARGIN, FCC_FDET_DEFAULT_RAISE,
        FCC_FDET_DEFAULT_HOLD, FCC_FDET_DEFAULT_CLEAR);
}

/* ---- value parsers ---------------------------------------------------------- */

/* Comma-separated finite numbers: how many (<= max), or -1. */
static int parse_list(const char *s, double *v, int max)
{
    int n = 0;
    const char *p = s;
    for (;;) {
        if (n == max || *p == '\0') {
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

static int get_double(const char *name, const char *val, double lo, double hi, double *out,
                      char *err, size_t len)
{
    double v = 0.0;
    if (parse_list(val, &v, 1) != 1) {
        return fail(err, len, "%s: '%s' is not a finite number", name, val);
    }
    if (v < lo || v > hi) {
        return fail(err, len, "%s: %g is outside %g..%g", name, v, lo, hi);
    }
    *out = v;
    return 0;
}

static int get_real(const char *name, const char *val, double lo, double hi, fcc_real_t *out,
                    char *err, size_t len)
{
    double v = 0.0;
    if (get_double(name, val, lo, hi, &v, err, len) != 0) {
        return -1;
    }
    *out = (fcc_real_t)v;
    return 0;
}

static int get_uint(const char *name, const char *val, unsigned long lo, unsigned long hi,
                    unsigned long *out, char *err, size_t len)
{
    char *end = NULL;
    errno = 0;
    if (val[0] == '-' || val[0] == '+' || val[0] == '\0') {
        return fail(err, len, "%s: '%s' is not a non-negative integer", name, val);
    }
    const unsigned long v = strtoul(val, &end, 10);
    if (*end != '\0' || errno == ERANGE) {
        return fail(err, len, "%s: '%s' is not a non-negative integer", name, val);
    }
    if (v < lo || v > hi) {
        return fail(err, len, "%s: %lu is outside %lu..%lu", name, v, lo, hi);
    }
    *out = v;
    return 0;
}

static int get_u16(const char *name, const char *val, unsigned long lo, unsigned long hi,
                   uint16_t *out, char *err, size_t len)
{
    unsigned long v = 0u;
    if (get_uint(name, val, lo, hi, &v, err, len) != 0) {
        return -1;
    }
    *out = (uint16_t)v;
    return 0;
}

/* 1 value: s I; 2: diag(s1, s2); 4: row-major. */
static int get_mat2(const char *name, const char *val, fcc_real_t m[4], char *err, size_t len)
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

static int get_model(const char *name, const char *val, fcc_sid_model_t *m, char *err, size_t len)
{
    double v[6];
    if (parse_list(val, v, 6) != 6) {
        return fail(err, len, "%s: expected a11,a12,a21,a22,b1,b2 (6 finite numbers), got '%s'",
                    name, val);
    }
    for (int i = 0; i < 4; ++i) {
        m->a[i] = (fcc_real_t)v[i];
    }
    m->b[0] = (fcc_real_t)v[4];
    m->b[1] = (fcc_real_t)v[5];
    return 0;
}

static int get_choice(const char *name, const char *val, const char *const *names, int n,
                      int *out, char *err, size_t len)
{
    for (int i = 0; i < n; ++i) {
        if (strcmp(val, names[i]) == 0) {
            *out = i;
            return 0;
        }
    }
    return fail(err, len, "%s: '%s' is not one of the accepted values (see --help)", name, val);
}

static int get_apps(const char *val, bool enabled[FCC_N_APPS], char *err, size_t len)
{
    bool on[FCC_N_APPS] = {false, false};
    const char *p = val;
    while (*p != '\0') {
        const char *comma = strchr(p, ',');
        const size_t n = (comma != NULL) ? (size_t)(comma - p) : strlen(p);
        if (n == 4u && strncmp(p, "cdrw", 4u) == 0) {
            on[FCC_APP_CDRW] = true;
        } else if (n == 7u && strncmp(p, "missile", 7u) == 0) {
            on[FCC_APP_MSL] = true;
        } else {
            return fail(err, len, "--apps: '%s' is not a list of cdrw and missile", val);
        }
        p += n;
        if (*p == ',') {
            ++p;
            if (*p == '\0') {
                return fail(err, len, "--apps: '%s' ends with a comma", val);
            }
        }
    }
    if (!on[FCC_APP_CDRW] && !on[FCC_APP_MSL]) {
        return fail(err, len, "--apps: at least one of cdrw and missile is needed");
    }
    enabled[FCC_APP_CDRW] = on[FCC_APP_CDRW];
    enabled[FCC_APP_MSL] = on[FCC_APP_MSL];
    return 0;
}

/* ---- options ------------------------------------------------------------------ */

static int apply_run(fcc_cli_t *c, const char *name, const char *val, char *err, size_t len)
{
    static const char *const modes[] = {"lockstep", "realtime"};
    if (strcmp(name, "--iface") == 0) {
        if (val[0] == '\0' || strlen(val) >= 16u) {
            return fail(err, len, "--iface: '%s' is not an interface name", val);
        }
        c->iface = val;
        return 0;
    }
    if (strcmp(name, "--mode") == 0) {
        int m = 0;
        if (get_choice(name, val, modes, 2, &m, err, len) != 0) {
            return -1;
        }
        c->node.mode = (m == 0) ? FCC_MODE_LOCKSTEP : FCC_MODE_REALTIME;
        return 0;
    }
    if (strcmp(name, "--apps") == 0) {
        return get_apps(val, c->node.app_enabled, err, len);
    }
    if (strcmp(name, "--duration") == 0) {
        return get_double(name, val, 0.0, 1e7, &c->duration_s, err, len);
    }
    if (strcmp(name, "--status-rate") == 0) {
        return get_double(name, val, 0.0, 1000.0, &c->status_rate_hz, err, len);
    }
    if (strcmp(name, "--rt-priority") == 0) {
        unsigned long p = 0u;
        if (get_uint(name, val, 0u, 99u, &p, err, len) != 0) {
            return -1;
        }
        c->rt_priority = (int)p;
        return 0;
    }
    if (strcmp(name, "--stale-limit") == 0) {
        return get_u16(name, val, 0u, 1000u, &c->node.stale_limit, err, len);
    }
    return 1; /* not a run option */
}

static int apply_msl(fcc_cli_t *c, const char *name, const char *val, char *err, size_t len)
{
    static const char *const solvers[] = {"hamiltonian", "doubling"};
    fcc_app_msl_config_t *m = &c->node.msl;
    if (strcmp(name, "--lqg-period") == 0) {
        return get_real(name, val, (double)FCC_APP_MSL_T_MIN, (double)FCC_APP_MSL_T_MAX,
                        &m->period, err, len);
    }
    if (strcmp(name, "--lqg-bits") == 0) {
        unsigned long n;
        if (get_uint(name, val, FCC_LQG_BITS_MIN, FCC_LQG_BITS_MAX, &n, err, len) != 0) {
            return -1;
        }
        m->bits = (uint8_t)n;
        return 0;
    }
    if (strcmp(name, "--gyro-var") == 0) {
        return get_real(name, val, 1e-12, 1e6, &m->plant.gyro_var, err, len);
    }
    if (strcmp(name, "--accel-var") == 0) {
        return get_real(name, val, 1e-12, 1e6, &m->plant.accel_var, err, len);
    }
    if (strcmp(name, "--solver") == 0) {
        int s = 0;
        if (get_choice(name, val, solvers, 2, &s, err, len) != 0) {
            return -1;
        }
        m->solver = (s == 0) ? FCC_LQG_SOLVER_HAMILTONIAN : FCC_LQG_SOLVER_DOUBLING;
        return 0;
    }
    return 1;
}

static int apply_det(fcc_sid_config_t *s, const char *name, const char *val, char *err,
                     size_t len)
{
    static const char *const policies[] = {"order", "skip"};
    static const char *const detectors[] = {"zonotope", "oracle", "off"};
    int i = 0;
    if (strcmp(name, "--fault-policy") == 0) {
        if (get_choice(name, val, policies, 2, &i, err, len) != 0) {
            return -1;
        }
        s->azkf.policy = (i == 0) ? FCC_AZKF_POLICY_ORDER : FCC_AZKF_POLICY_SKIP;
        return 0;
    }
    if (strcmp(name, "--detector") == 0) {
        if (get_choice(name, val, detectors, 3, &i, err, len) != 0) {
            return -1;
        }
        s->azkf.det.mode = (i == 0) ? FCC_FDET_ZONOTOPE : (i == 1) ? FCC_FDET_ORACLE : FCC_FDET_OFF;
        return 0;
    }
    if (strcmp(name, "--margin") == 0) return get_real(name, val, 1e-6, 1e6, &s->azkf.det.margin, err, len);
    if (strcmp(name, "--raise") == 0) return get_u16(name, val, 1u, 65535u, &s->azkf.det.raise_count, err, len);
    if (strcmp(name, "--hold") == 0) return get_u16(name, val, 0u, 65535u, &s->azkf.det.hold_count, err, len);
    if (strcmp(name, "--clear") == 0) return get_u16(name, val, 1u, 65535u, &s->azkf.det.clear_count, err, len);
    return 1;
}

static int apply_sid(fcc_cli_t *c, const char *name, const char *val, char *err, size_t len)
{
    fcc_sid_config_t *s = &c->node.sid.base;
    const unsigned long max_q = FCC_ZONO_MAX_ORDER;
    if (strcmp(name, "--window") == 0) return get_u16(name, val, 4u, FCC_MLS_MAX_WINDOW, &s->mls.window, err, len);
    if (strcmp(name, "--min-transitions") == 0) return get_u16(name, val, 4u, FCC_MLS_MAX_WINDOW, &s->mls.min_transitions, err, len);
    if (strcmp(name, "--ridge") == 0) return get_real(name, val, 0.0, 1e12, &s->mls.ridge, err, len);
    if (strcmp(name, "--max-cond") == 0) return get_real(name, val, 1.0, 1e30, &s->mls.max_cond, err, len);
    if (strcmp(name, "--max-rho") == 0) return get_real(name, val, 0.0, 1e3, &s->mls.max_rho, err, len);
    if (strcmp(name, "--prior") == 0) return get_model(name, val, &s->mls.prior, err, len);
    if (strcmp(name, "--zkf-order") == 0) return get_u16(name, val, FCC_ZONO_MIN_ORDER, max_q, &s->zkf_order, err, len);
    if (strcmp(name, "--q-normal") == 0) return get_u16(name, val, FCC_ZONO_MIN_ORDER, max_q, &s->azkf.q_normal, err, len);
    if (strcmp(name, "--q-fault") == 0) return get_u16(name, val, FCC_ZONO_MIN_ORDER, max_q, &s->azkf.q_fault, err, len);
    if (strcmp(name, "--x0") == 0) {
        double v[2];
        if (parse_list(val, v, 2) != 2) {
            return fail(err, len, "--x0: expected alpha,q (2 finite numbers), got '%s'", val);
        }
        s->x0[0] = (fcc_real_t)v[0];
        s->x0[1] = (fcc_real_t)v[1];
        return 0;
    }
    if (strcmp(name, "--p0") == 0) return get_mat2(name, val, s->p0, err, len);
    if (strcmp(name, "--e") == 0) return get_mat2(name, val, s->e, err, len);
    if (strcmp(name, "--f") == 0) return get_mat2(name, val, s->f, err, len);
    return apply_det(s, name, val, err, len);
}

static int apply(fcc_cli_t *c, const char *name, const char *val, char *err, size_t len)
{
    int r = apply_run(c, name, val, err, len);
    if (r == 1) {
        r = apply_msl(c, name, val, err, len);
    }
    if (r == 1) {
        r = apply_sid(c, name, val, err, len);
    }
    if (r == 1) {
        return fail(err, len, "unknown option '%s' (try fcc --help)", name);
    }
    return r;
}

/* Cross-field checks the per-option parsers cannot do. */
static int check(const fcc_cli_t *c, char *err, size_t len)
{
    for (int f = 0; f < 3; ++f) {
        fcc_sid_config_t s = c->node.sid.base;
        s.filter = (fcc_sid_filter_t)f;
        const fcc_status_t st = fcc_sid_config_check(&s);
        if (st != FCC_OK) {
            return fail(err, len, "identification options rejected: %s (check --window, "
                        "--min-transitions, --p0, --e, --f, orders)", fcc_status_str(st));
        }
    }
    return 0;
}

int fcc_cli_parse(int argc, char **argv, fcc_cli_t *cli, char *err, size_t err_len, FILE *out)
{
    memset(cli, 0, sizeof *cli);
    cli->iface = "vcan0";
    cli->status_rate_hz = 10.0;
    if (fcc_node_config_default(&cli->node) != FCC_OK) {
        return fail(err, err_len, "internal error: default configuration");
    }
    for (int i = 1; i < argc; ++i) {
        const char *arg = argv[i];
        if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) {
            fcc_cli_usage(out);
            return 1;
        }
        if (strncmp(arg, "--", 2) != 0 || arg[2] == '\0') {
            return fail(err, err_len, "unexpected argument '%s' (try fcc --help)", arg);
        }
        if (strcmp(arg, "--no-mls-hold") == 0) {
            cli->node.sid.base.mls_hold_on_fault = false;
            continue;
        }
        char name[48];
        const char *eq = strchr(arg, '=');
        const char *val = NULL;
        if (eq != NULL) {
            const size_t n = (size_t)(eq - arg);
            if (n >= sizeof name) {
                return fail(err, err_len, "unknown option '%s' (try fcc --help)", arg);
            }
            memcpy(name, arg, n);
            name[n] = '\0';
            val = eq + 1;
        } else {
            if (strlen(arg) >= sizeof name) {
                return fail(err, err_len, "unknown option '%s' (try fcc --help)", arg);
            }
            strcpy(name, arg);
            if (i + 1 >= argc) {
                int dummy = apply(cli, name, "", err, err_len);
                if (dummy != 0 && strncmp(err, "unknown option", 14) == 0) {
                    return -1;
                }
                return fail(err, err_len, "%s needs a value (try fcc --help)", name);
            }
            val = argv[++i];
        }
        if (apply(cli, name, val, err, err_len) != 0) {
            return -1;
        }
    }
    return check(cli, err, err_len);
}
