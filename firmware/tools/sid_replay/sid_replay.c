/*
 * sid_replay -- replays a flight CSV through the firmware's identification
 * loops (MLS-KF, MLS-ZKF, MLS-AZKF side by side, each with its own MLS) and
 * writes one CSV row per step per filter on stdout.  Row semantics: see
 * fcc_sid.h.  With the MLS intercept (--mls-intercept, or an 8-value model)
 * the rows end with the affine term c1,c2.  --estimates --binary: the estimates'
 * rows as binary64 records (the rig's symmetric tables read them).  Bad input: one line on stderr, exit status 1 (2 for a bad
 * command line).
 */
#include <stdio.h>
#include <string.h>

#include "fcc_sid.h"
#include "sid_replay_csv.h"
#include "sid_replay_opts.h"

static const char *const filter_names[3] = {"kf", "zkf", "azkf"};
/* --all-rows: a row's filter column reads MODE/FILTER, modes in fcc_sid_rows_t order */
static const char *const all_rows_names[3][3] = {{"paper/kf", "paper/zkf", "paper/azkf"},
                                                 {"prior/kf", "prior/zkf", "prior/azkf"},
                                                 {"posterior/kf", "posterior/zkf",
                                                  "posterior/azkf"}};

#ifdef FCC_REAL_FLOAT
#define REAL_FMT "%.9g"
#else
#define REAL_FMT "%.17g"
#endif

static sid_flight_t flight;  /* static: up to SID_CSV_MAX_ROWS rows */
static fcc_sid_t loops[3];  /* one per filter, reused for each row mode (pages already touched) */
static fcc_mls_t mls_alone;
static bool with_c; /* the c1,c2 columns are printed */
static bool estimates_only; /* --estimates: t, filter and the six estimate columns only */
static bool binary;         /* --binary: those as binary64 records, no header */

/* A row of --binary: t, the row's filter code, the six estimates, the fault flag (0 or 1),
 * as binary64. */
#define BINARY_ROW_VALUES 9u

static void print_header(void)
{
    if (binary) {
        return;
    }
    if (estimates_only) {
        fputs("t,filter,alpha_hat,q_hat,alpha_lo,alpha_hi,q_lo,q_hi\n", stdout);
        return;
    }
    fputs("t,filter,alpha_hat,q_hat,alpha_lo,alpha_hi,q_lo,q_hi,gain_norm,order,fault,"
          "a11,a12,a21,a22,b1,b2,rho",
          stdout);
    fputs(with_c ? ",c1,c2\n" : "\n", stdout);
}

static void print_reals(const fcc_real_t *v, size_t n)
{
    for (size_t i = 0; i < n; ++i) {
        printf("," REAL_FMT, (double)v[i]);
    }
}

/* One --binary row; 0, or -1 when stdout refused it. */
static int write_binary_row(double t, unsigned code, const fcc_real_t x[2], const fcc_real_t lo[2],
                            const fcc_real_t hi[2], bool fault)
{
    const double row[BINARY_ROW_VALUES] = {t,           (double)code,  (double)x[0],
                                           (double)x[1], (double)lo[0], (double)hi[0],
                                           (double)lo[1], (double)hi[1], fault ? 1.0 : 0.0};
    return fwrite(row, sizeof row[0], BINARY_ROW_VALUES, stdout) == BINARY_ROW_VALUES ? 0 : -1;
}

static void print_row(double t, const char *name, const fcc_real_t x[2], const fcc_real_t lo[2],
                      const fcc_real_t hi[2], fcc_real_t gain, unsigned order, int fault,
                      const fcc_sid_model_t *m, fcc_real_t rho)
{
    printf("%.17g,%s", t, name);
    const fcc_real_t xb[6] = {x[0], x[1], lo[0], hi[0], lo[1], hi[1]};
    print_reals(xb, 6);
    if (estimates_only) {
        fputc('\n', stdout);
        return;
    }
    printf("," REAL_FMT ",%u,%d", (double)gain, order, fault);
    print_reals(m->a, 4);
    print_reals(m->b, 2);
    printf("," REAL_FMT, (double)rho);
    if (with_c) {
        print_reals(m->c, 2);
    }
    fputc('\n', stdout);
}

static int die(const char *msg)
{
    fprintf(stderr, "sid_replay: %s\n", msg);
    return 1;
}

/* The option behind a configuration the firmware refuses, in words. */
static const char *config_problem(const fcc_sid_config_t *c)
{
    const fcc_mls_config_t *m = &c->mls;
    const fcc_fdet_config_t *d = &c->azkf.det;
    fcc_real_t tmp[4];
    if (m->window < 4u) {
        return "--window must be at least 4";
    }
    if (m->min_transitions < 4u || m->min_transitions > m->window) {
        return "--min-transitions must be between 4 and the window";
    }
    if (m->ridge < FCC_R(0.0)) {
        return "--ridge must be >= 0";
    }
    if (!(m->max_cond > FCC_R(1.0))) {
        return "--max-cond must be > 1";
    }
    if (m->max_rho < FCC_R(0.0)) {
        return "--max-rho must be >= 0";
    }
    if (!(d->margin > FCC_R(0.0))) {
        return "--margin must be > 0";
    }
    if (d->raise_count < 1u || d->clear_count < 1u) {
        return "--raise and --clear must be at least 1";
    }
    if (c->p0[1] != c->p0[2] || fcc_sid_m2_cholesky(c->p0, tmp) != FCC_OK) {
        return "--p0 must be a symmetric positive definite covariance";
    }
    fcc_real_t r[4];
    fcc_sid_m2_mul_bt(c->f, c->f, r);
    if (fcc_sid_m2_spd_inv(r, tmp) != FCC_OK) {
        return "--f must be invertible (R = F F^T is inverted by every filter)";
    }
    return NULL;
}

/* --mls-only: row k is the fit over the transitions that end at x_k. */
static int run_mls_only(const sid_opts_t *o)
{
    const fcc_status_t st = fcc_mls_init(&mls_alone, &o->cfg.mls);
    if (st != FCC_OK) {
        const char *why = config_problem(&o->cfg);
        fprintf(stderr, "sid_replay: invalid configuration: %s\n",
                why != NULL ? why : fcc_status_str(st));
        return 1;
    }
    print_header();
    for (size_t k = 0; k < flight.n; ++k) {
        const fcc_real_t x[2] = {(fcc_real_t)flight.alpha[k], (fcc_real_t)flight.q[k]};
        if (k > 0u) {
            const fcc_real_t xp[2] = {(fcc_real_t)flight.alpha[k - 1u],
                                      (fcc_real_t)flight.q[k - 1u]};
            (void)fcc_mls_update(&mls_alone, xp, (fcc_real_t)flight.de[k - 1u], x);
        }
        const fcc_mls_estimate_t *est = fcc_mls_estimate(&mls_alone);
        print_row(flight.t[k], "mls", x, x, x, FCC_R(0.0), 0u, 0, &est->model, est->rho);
    }
    return 0;
}

/* The loop of filter i in row mode r (a configuration refused: one line, 1). */
static int init_loop(const sid_opts_t *o, int r, int i)
{
    fcc_sid_config_t cfg = o->cfg;
    cfg.filter = (fcc_sid_filter_t)i;
    cfg.rows = (fcc_sid_rows_t)r;
    const fcc_status_t st = fcc_sid_init(&loops[i], &cfg);
    if (st != FCC_OK) {
        const char *why = config_problem(&cfg);
        fprintf(stderr, "sid_replay: invalid configuration: %s\n",
                why != NULL ? why : fcc_status_str(st));
        return 1;
    }
    return 0;
}

/* Row k of the loop of row mode r and filter i; a step that failed: one line, 1. */
static int step_loop(const sid_opts_t *o, size_t k, int r, int i)
{
    fcc_sid_out_t out;
    const fcc_status_t st =
        fcc_sid_step(&loops[i], (fcc_real_t)flight.alpha[k], (fcc_real_t)flight.q[k],
                     (fcc_real_t)flight.de[k], flight.fault[k] != 0u, true, &out);
    if (!out.stepped) { /* the filter did not step: its row would be stale, refuse */
        fflush(stdout);
        fprintf(stderr, "sid_replay: row %zu (t = %g): the %s step failed: %s\n", k + 1u,
                flight.t[k], o->all_rows ? all_rows_names[r][i] : filter_names[i],
                fcc_status_str(st));
        return 1;
    }
    if (binary) {
        const unsigned code = (unsigned)i + (o->all_rows ? 3u * (unsigned)r : 0u);
        return write_binary_row(flight.t[k], code, out.x_hat, out.lo, out.hi, out.fault) == 0
                   ? 0
                   : die("cannot write the output");
    }
    print_row(flight.t[k], o->all_rows ? all_rows_names[r][i] : filter_names[i], out.x_hat,
              out.lo, out.hi, out.gain_norm, out.order, out.fault ? 1 : 0, &out.model, out.rho);
    return 0;
}

/* Every selected filter in the configured row mode, or (--all-rows) in each of the three,
 * one mode after the other. */
static int run_filters(const sid_opts_t *o)
{
    const int r0 = o->all_rows ? 0 : (int)o->cfg.rows;
    const int r1 = o->all_rows ? 2 : r0;
    for (int r = r0; r <= r1; ++r) { /* every configuration is checked before any output */
        for (int i = 0; i < 3; ++i) {
            if (o->run[i] && init_loop(o, r, i) != 0) {
                return 1;
            }
        }
    }
    print_header();
    for (int r = r0; r <= r1; ++r) {
        for (int i = 0; i < 3; ++i) {
            if (o->run[i] && init_loop(o, r, i) != 0) {
                return 1;
            }
        }
        for (size_t k = 0; k < flight.n; ++k) {
            for (int i = 0; i < 3; ++i) {
                if (o->run[i] && step_loop(o, k, r, i) != 0) {
                    return 1;
                }
            }
        }
    }
    return 0;
}

/* Refuses a bad configuration before any input is read. */
static int check_config(const sid_opts_t *o)
{
    const char *why = config_problem(&o->cfg);
    const fcc_status_t st =
        o->mls_only ? fcc_mls_config_check(&o->cfg.mls) : fcc_sid_config_check(&o->cfg);
    if (why == NULL && st == FCC_OK) {
        return 0;
    }
    fprintf(stderr, "sid_replay: invalid configuration: %s\n",
            why != NULL ? why : fcc_status_str(st));
    return 1;
}

static int check_against_data(const sid_opts_t *o)
{
    static char msg[SID_CSV_ERR_LEN];
    const bool uses_mls = o->mls_only || !o->fixed_model;
    if (uses_mls && (size_t)o->cfg.mls.window > flight.n - 1u) {
        snprintf(msg, sizeof msg, "window of %u transitions is longer than the data (%zu rows, %zu "
                 "transitions)", (unsigned)o->cfg.mls.window, flight.n, flight.n - 1u);
        return die(msg);
    }
    if (!o->mls_only && o->run[2] && o->cfg.azkf.det.mode == FCC_FDET_ORACLE && !flight.has_fault) {
        return die("--detector oracle needs a 'fault' column in the input");
    }
    return 0;
}

int main(int argc, char **argv)
{
    static sid_opts_t opts;
    static char err[SID_CSV_ERR_LEN];
    const int pr = sid_opts_parse(argc, argv, &opts, err, sizeof err);
    if (pr != 0) {
        if (pr < 0) {
            fprintf(stderr, "sid_replay: %s\n", err);
            return 2;
        }
        return 0;
    }
    if (check_config(&opts) != 0) {
        return 2;
    }
    FILE *in = stdin;
    if (opts.input != NULL && strcmp(opts.input, "-") != 0) {
        in = fopen(opts.input, "r");
        if (in == NULL) {
            fprintf(stderr, "sid_replay: cannot open '%s'\n", opts.input);
            return 1;
        }
    }
    const sid_csv_limits_t lim = {(double)opts.cfg.alpha_limit, (double)opts.cfg.q_limit,
                                  (double)opts.cfg.de_limit};
    const int rr = sid_csv_read(in, &lim, &flight, err, sizeof err);
    if (in != stdin) {
        fclose(in);
    }
    if (rr != 0) {
        return die(err);
    }
    if (check_against_data(&opts) != 0) {
        return 1;
    }
    with_c = opts.cfg.mls.intercept;
    estimates_only = opts.estimates_only;
    binary = opts.binary;
    const int rc = opts.mls_only ? run_mls_only(&opts) : run_filters(&opts);
    if (rc == 0 && (fflush(stdout) != 0 || ferror(stdout))) {
        return die("cannot write the output");
    }
    return rc;
}
