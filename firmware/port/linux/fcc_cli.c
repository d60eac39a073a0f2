/*
 * fcc_cli.c -- command line of fcc (see fcc_cli.h).
 */
#include "fcc_cli.h"

#include <string.h>

#include "fcc_cfg_limits.h"
#include "fcc_keyfile.h"
#include "fcc_opt.h"
#include "fcc_opt_sid.h"

typedef struct {
    fcc_cli_t *cli;
    fcc_opt_sid_t sid; /* the identification options, into cli->node.sid.base */
} parse_t;

void fcc_cli_usage(FILE *out)
{
    fprintf(out,
        "usage: fcc [options]\n"
        "The flight computer on a CAN bus: CDRW identification (MLS + KF/ZKF/AZKF, 50 Hz) and\n"
        "the missile LQG autopilot (period T, N-bit D/A). Protocol: firmware/app/README.md.\n"
        "\n"
        "  --key-file PATH               required: the AES-128 key of the bus authentication,\n"
        "                                one line of 32 hex digits (dbc/README.md); a regular\n"
        "                                file of at most 1024 bytes (else refused, exit 2)\n"
        "  --trip N                      the high half of every freshness value, 1..4294967295,\n"
        "                                chosen by the launcher (the rig); default: random\n"
        "  --iface NAME                  CAN interface (vcan0)\n"
        "  --mode lockstep|realtime      step on SIM_TICK, or on the clock (lockstep)\n"
        "  --apps LIST                   cdrw,missile | cdrw | missile (cdrw,missile)\n"
        "  --duration S                  stop after S seconds (0: run until a signal or a\n"
        "                                shutdown frame)\n"
        "  --status-rate HZ              heartbeat rate, 0 = only at start and exit (%g)\n"
        "  --rt-priority P               run under SCHED_FIFO priority P (1..99) with memory\n"
        "                                locked; 0 = normal scheduling (0)\n"
        "  --stale-limit N               missing frames bridged with the last value before a\n"
        "                                sensor is stale and the step degraded (%u)\n"
        "  --check-args                  check the other options and exit: 0 valid, 2 not\n"
        "                                (one line); opens nothing, needs no --key-file\n"
        "  --help                        this text\n"
        "missile autopilot:\n"
        "  --lqg-period T                sampling period, s, %g..%g (0.05)\n"
        "  --lqg-bits N                  D/A word length, %u..%u (8)\n"
        "  --lqg-delay auto|D            design for an input delay of D s, 0 <= D < T (auto:\n"
        "                                0 in lockstep, the 5 ms actuation instant in realtime)\n"
        "  --gyro-var V                  rate-gyro noise variance, rad^2/s^2 (0.8)\n"
        "  --accel-var V                 accelerometer noise variance, ft^2/s^4 (0.8)\n"
        "  --solver hamiltonian|doubling  Riccati solution used (both are computed and\n"
        "                                compared)\n",
        FCC_CFG_STATUS_RATE_DEFAULT_HZ, FCC_NODE_DEFAULT_STALE_LIMIT, FCC_CFG_LQG_PERIOD_MIN_S,
        FCC_CFG_LQG_PERIOD_MAX_S, FCC_CFG_LQG_BITS_MIN, FCC_CFG_LQG_BITS_MAX);
    fcc_opt_sid_usage(out);
    fprintf(out,
        "Exit: 0 after SIGINT/SIGTERM, --duration or a shutdown frame; 1 start-up failure\n"
        "(e.g. no such interface); 2 bad command line.\n");
}

/* ---- value parsers ---------------------------------------------------------- */

/* A SocketCAN interface name: 1..15 characters (IFNAMSIZ). */
static fcc_opt_result_t get_iface(const char *val, const char **iface, char *err, size_t len)
{
    if (val == NULL) {
        return FCC_OPT_NEED_VALUE;
    }
    if (val[0] == '\0' || strlen(val) >= 16u) {
        return fcc_opt_fail(err, len, "--iface: '%s' is not an interface name", val);
    }
    *iface = val;
    return FCC_OPT_DONE;
}

/* --apps NAME[,NAME...]: the applications of this build by their names (fcc_app.h). */
static fcc_opt_result_t get_apps(const char *val, bool enabled[FCC_N_APPS], char *err,
                                 size_t len)
{
    bool on[FCC_N_APPS];
    bool any = false;
    memset(on, 0, sizeof on);
    if (val == NULL) {
        return FCC_OPT_NEED_VALUE;
    }
    const char *p = val;
    while (*p != '\0') {
        const char *comma = strchr(p, ',');
        const size_t n = (comma != NULL) ? (size_t)(comma - p) : strlen(p);
        const uint32_t app = fcc_node_app_named(p, (uint32_t)n);
        if (app >= FCC_N_APPS) {
            return fcc_opt_fail(err, len, "--apps: '%s' names an application this fcc does not have",
                                val);
        }
        on[app] = true;
        any = true;
        p += n;
        if (*p == ',') {
            ++p;
            if (*p == '\0') {
                return fcc_opt_fail(err, len, "--apps: '%s' ends with a comma", val);
            }
        }
    }
    if (!any) {
        return fcc_opt_fail(err, len, "--apps: at least one application is needed");
    }
    memcpy(enabled, on, sizeof on);
    return FCC_OPT_DONE;
}

/* ---- options ------------------------------------------------------------------ */

static fcc_opt_result_t apply_run(fcc_cli_t *c, const char *name, const char *val, char *err,
                                  size_t len)
{
    static const char *const modes[] = {"lockstep", "realtime"};
    static const fcc_mode_t mode_of[] = {FCC_MODE_LOCKSTEP, FCC_MODE_REALTIME};
    int i = 0;
    unsigned long u = 0u;
    fcc_opt_result_t r = FCC_OPT_NOT_MINE;
    if (strcmp(name, "--iface") == 0) {
        r = get_iface(val, &c->iface, err, len);
    } else if (strcmp(name, "--trip") == 0) {
        r = fcc_opt_uint(name, val, 1u, 0xFFFFFFFFuL, &u, err, len);
        c->trip = (r == FCC_OPT_DONE) ? (uint32_t)u : c->trip;
    } else if (strcmp(name, "--key-file") == 0) {
        c->key_file = val;
        r = (val == NULL) ? FCC_OPT_NEED_VALUE : FCC_OPT_DONE;
    } else if (strcmp(name, "--mode") == 0) {
        r = fcc_opt_choice(name, val, modes, 2, &i, err, len);
        c->node.mode = (r == FCC_OPT_DONE) ? mode_of[i] : c->node.mode;
    } else if (strcmp(name, "--apps") == 0) {
        r = get_apps(val, c->node.app_enabled, err, len);
    } else if (strcmp(name, "--duration") == 0) {
        r = fcc_opt_double(name, val, 0.0, 1e7, &c->duration_s, err, len);
    } else if (strcmp(name, "--status-rate") == 0) {
        r = fcc_opt_double(name, val, FCC_CFG_STATUS_RATE_MIN_HZ, FCC_CFG_STATUS_RATE_MAX_HZ,
                           &c->status_rate_hz, err, len);
    } else if (strcmp(name, "--rt-priority") == 0) {
        r = fcc_opt_uint(name, val, 0u, 99u, &u, err, len);
        c->rt_priority = (r == FCC_OPT_DONE) ? (int)u : c->rt_priority;
    } else if (strcmp(name, "--stale-limit") == 0) {
        r = fcc_opt_u16(name, val, 0u, FCC_CFG_STALE_LIMIT_MAX, &c->node.stale_limit, err, len);
    }
    return r;
}

static fcc_opt_result_t apply_msl(fcc_app_msl_config_t *m, const char *name, const char *val,
                                  char *err, size_t len)
{
    static const char *const solvers[] = {"hamiltonian", "doubling"};
    static const fcc_lqg_solver_t solver_of[] = {FCC_LQG_SOLVER_HAMILTONIAN,
                                                 FCC_LQG_SOLVER_DOUBLING};
    int i = 0;
    unsigned long u = 0u;
    fcc_opt_result_t r = FCC_OPT_NOT_MINE;
    if (strcmp(name, "--lqg-period") == 0) {
        r = fcc_opt_real(name, val, FCC_CFG_LQG_PERIOD_MIN_S, FCC_CFG_LQG_PERIOD_MAX_S,
                         &m->period, err, len);
    } else if (strcmp(name, "--lqg-bits") == 0) {
        r = fcc_opt_uint(name, val, FCC_CFG_LQG_BITS_MIN, FCC_CFG_LQG_BITS_MAX, &u, err, len);
        m->bits = (r == FCC_OPT_DONE) ? (uint8_t)u : m->bits;
    } else if (strcmp(name, "--gyro-var") == 0) {
        r = fcc_opt_real(name, val, FCC_CFG_NOISE_VAR_MIN, FCC_CFG_NOISE_VAR_MAX,
                         &m->plant.gyro_var, err, len);
    } else if (strcmp(name, "--accel-var") == 0) {
        r = fcc_opt_real(name, val, FCC_CFG_NOISE_VAR_MIN, FCC_CFG_NOISE_VAR_MAX,
                         &m->plant.accel_var, err, len);
    } else if (strcmp(name, "--solver") == 0) {
        r = fcc_opt_choice(name, val, solvers, 2, &i, err, len);
        m->solver = (r == FCC_OPT_DONE) ? solver_of[i] : m->solver;
    }
    return r;
}

/* --lqg-delay auto|SECONDS (auto: resolved by the mode in fcc_cli_parse). */
static fcc_opt_result_t apply_delay(fcc_cli_t *c, const char *name, const char *val, char *err,
                                    size_t len)
{
    if (strcmp(name, "--lqg-delay") != 0) {
        return FCC_OPT_NOT_MINE;
    }
    if (val == NULL) {
        return FCC_OPT_NEED_VALUE;
    }
    c->lqg_delay_auto = strcmp(val, "auto") == 0;
    if (c->lqg_delay_auto) {
        return FCC_OPT_DONE;
    }
    return fcc_opt_real(name, val, FCC_CFG_LQG_DELAY_MIN_S, FCC_CFG_LQG_DELAY_MAX_S,
                        &c->node.msl.delay, err, len);
}

/* fcc's own options, then the identification options shared with sid_replay. */
static fcc_opt_result_t apply(void *ctx, const char *name, const char *val, char *err,
                              size_t len)
{
    parse_t *p = ctx;
    fcc_opt_result_t r = apply_run(p->cli, name, val, err, len);
    if (r == FCC_OPT_NOT_MINE) {
        r = apply_msl(&p->cli->node.msl, name, val, err, len);
    }
    if (r == FCC_OPT_NOT_MINE) {
        r = apply_delay(p->cli, name, val, err, len);
    }
    if (r == FCC_OPT_NOT_MINE) {
        r = fcc_opt_sid_apply(&p->sid, name, val, err, len);
    }
    return r;
}

/* Cross-field checks the per-option parsers cannot do. */
static int check(fcc_cli_t *c, char *err, size_t len)
{
    if (c->lqg_delay_auto) {
        c->node.msl.delay = (c->node.mode == FCC_MODE_REALTIME) ? FCC_APP_MSL_RT_DELAY : FCC_R(0.0);
    }
    if (!(c->node.msl.delay < c->node.msl.period)) {
        return fcc_opt_fail(err, len, "--lqg-delay %g s must be shorter than the period %g s",
                            (double)c->node.msl.delay, (double)c->node.msl.period);
    }
    for (int f = 0; f < 3; ++f) {
        fcc_sid_config_t s = c->node.sid.base;
        s.filter = (fcc_sid_filter_t)f;
        const fcc_status_t st = fcc_sid_config_check(&s);
        if (st != FCC_OK) {
            return fcc_opt_fail(err, len, "identification options rejected: %s (check --window, "
                                "--min-transitions, --p0, --e, --f, orders)", fcc_status_str(st));
        }
    }
    return 0;
}

int fcc_cli_parse(int argc, char **argv, fcc_cli_t *cli, char *err, size_t err_len, FILE *out)
{
    memset(cli, 0, sizeof *cli);
    cli->iface = "vcan0";
    cli->status_rate_hz = FCC_CFG_STATUS_RATE_DEFAULT_HZ;
    if (fcc_node_config_default(&cli->node) != FCC_OK) {
        return fcc_opt_fail(err, err_len, "internal error: default configuration");
    }
    cli->lqg_delay_auto = true;
    parse_t p = {cli, {NULL, false, false}};
    fcc_opt_sid_begin(&p.sid, &cli->node.sid.base);
    for (int i = 1; i < argc; ++i) {
        const char *arg = argv[i];
        if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) {
            fcc_cli_usage(out);
            return 1;
        }
        if (strcmp(arg, "--check-args") == 0) {
            cli->check_only = true;
            continue;
        }
        if (strncmp(arg, "--", 2) != 0 || arg[2] == '\0') {
            return fcc_opt_fail(err, err_len, "unexpected argument '%s' (try fcc --help)", arg);
        }
        if (fcc_opt_take(argc, argv, &i, apply, &p, "try fcc --help", err, err_len) !=
            FCC_OPT_DONE) {
            return -1;
        }
    }
    fcc_opt_sid_end(&p.sid);
    if (check(cli, err, err_len) != 0) {
        return -1;
    }
    if (cli->check_only && cli->key_file == NULL) {
        return 1; /* the options are valid; the launcher gives the key */
    }
    if (cli->key_file == NULL) {
        return fcc_opt_fail(err, err_len, "--key-file PATH is required: the AES-128 key that "
                            "authenticates commands on the bus (tests: tests/keys/secoc_test.key)");
    }
    if (fcc_keyfile_read(cli->key_file, cli->node.security.key, err, err_len) != 0) {
        return -1;
    }
    return cli->check_only ? 1 : 0;
}
