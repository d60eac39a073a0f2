/*
 * lqg_design -- run the firmware's own LQG design (fcc_lqg_design) for one
 * sampling period and print every matrix as ONE JSON object on stdout, so
 * that tests and engineers can compare it with scipy / python-control.
 *
 *   lqg_design --period T [--bits N] [--gyro-var V] [--accel-var V]
 *              [--solver hamiltonian|doubling] [--repeat N]
 *
 * Bad input: one line on stderr, exit status 2 (usage) or 1 (the design
 * refused the problem, with the firmware's status name).
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fcc_lqg.h"

#define PROG "lqg_design"

typedef struct {
    double period;
    bool have_period;
    long bits;
    double gyro_var;
    double accel_var;
    fcc_lqg_solver_t solver;
    long repeat;
} options_t;

static void usage(FILE *out)
{
    fprintf(out,
            "usage: " PROG " --period T [--bits N] [--gyro-var V] [--accel-var V]\n"
            "                  [--solver hamiltonian|doubling] [--repeat N]\n"
            "Design the seed-2 missile LQG autopilot for sampling period T (s) with the\n"
            "firmware's own numerics and print one JSON object (matrices row-major).\n"
            "  --period T       sampling period, %g <= T <= %g s (required)\n"
            "  --bits N         D/A converter bits, %u..%u (default 8)\n"
            "  --gyro-var V     rate-gyro noise variance, rad^2/s^2, > 0 (default 0.8)\n"
            "  --accel-var V    accelerometer noise variance, ft^2/s^4, > 0 (default 0.8)\n"
            "  --solver S       Riccati solution reported: hamiltonian (the paper's\n"
            "                   eigenvector method, default) or doubling; both always run\n"
            "                   and must agree\n"
            "  --repeat N       run the design N times (timing aid; prints once)\n"
            "  --help           this text\n",
            FCC_LQG_T_MIN, FCC_LQG_T_MAX, FCC_LQG_BITS_MIN, FCC_LQG_BITS_MAX);
}

static int fail_usage(const char *what, const char *arg)
{
    fprintf(stderr, PROG ": %s%s%s (see --help)\n", what, arg ? ": " : "", arg ? arg : "");
    return 2;
}

/* A whole-string finite decimal. */
static bool parse_real(const char *s, double *out)
{
    char *end = NULL;
    errno = 0;
    const double v = strtod(s, &end);
    if (end == s || *end != '\0' || errno != 0 || !isfinite(v)) {
        return false;
    }
    *out = v;
    return true;
}

static bool parse_long(const char *s, long *out)
{
    char *end = NULL;
    errno = 0;
    const long v = strtol(s, &end, 10);
    if (end == s || *end != '\0' || errno != 0) {
        return false;
    }
    *out = v;
    return true;
}

/* Split "--name=value" or take the next argument; NULL if missing. */
static const char *option_value(int argc, char **argv, int *i, const char *arg, size_t name_len)
{
    if (arg[name_len] == '=') {
        return arg + name_len + 1;
    }
    if (*i + 1 < argc) {
        *i += 1;
        return argv[*i];
    }
    return NULL;
}

/* 0: parsed; 1: --help printed; 2: error printed. */
static int parse_args(int argc, char **argv, options_t *o)
{
    static const char *const names[] = {"--period", "--bits", "--gyro-var", "--accel-var",
                                        "--solver", "--repeat"};
    for (int i = 1; i < argc; ++i) {
        const char *arg = argv[i];
        if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) {
            usage(stdout);
            return 1;
        }
        int which = -1;
        size_t len = 0;
        for (int k = 0; k < (int)(sizeof names / sizeof names[0]); ++k) {
            len = strlen(names[k]);
            if (strncmp(arg, names[k], len) == 0 && (arg[len] == '\0' || arg[len] == '=')) {
                which = k;
                break;
            }
        }
        if (which < 0) {
            return fail_usage("unknown argument", arg);
        }
        const char *val = option_value(argc, argv, &i, arg, len);
        if (val == NULL) {
            return fail_usage("missing value for", names[which]);
        }
        bool ok = true;
        switch (which) {
        case 0: ok = parse_real(val, &o->period); o->have_period = ok; break;
        case 1: ok = parse_long(val, &o->bits); break;
        case 2: ok = parse_real(val, &o->gyro_var); break;
        case 3: ok = parse_real(val, &o->accel_var); break;
        case 4:
            if (strcmp(val, "hamiltonian") == 0) {
                o->solver = FCC_LQG_SOLVER_HAMILTONIAN;
            } else if (strcmp(val, "doubling") == 0) {
                o->solver = FCC_LQG_SOLVER_DOUBLING;
            } else {
                return fail_usage("--solver must be hamiltonian or doubling, not", val);
            }
            break;
        default: ok = parse_long(val, &o->repeat); break;
        }
        if (!ok) {
            return fail_usage("not a valid finite number", val);
        }
    }
    if (!o->have_period) {
        return fail_usage("--period is required", NULL);
    }
    return 0;
}

static int check_ranges(const options_t *o)
{
    char msg[160];
    if (!(o->period >= FCC_LQG_T_MIN && o->period <= FCC_LQG_T_MAX)) {
        snprintf(msg, sizeof msg, "--period %g s is outside [%g, %g] s", o->period,
                 FCC_LQG_T_MIN, FCC_LQG_T_MAX);
        return fail_usage(msg, NULL);
    }
    if (o->bits < (long)FCC_LQG_BITS_MIN || o->bits > (long)FCC_LQG_BITS_MAX) {
        snprintf(msg, sizeof msg, "--bits %ld is outside %u..%u", o->bits, FCC_LQG_BITS_MIN,
                 FCC_LQG_BITS_MAX);
        return fail_usage(msg, NULL);
    }
    if (!(o->gyro_var > 0.0) || !(o->accel_var > 0.0)) {
        return fail_usage("noise variances must be > 0", NULL);
    }
    if (o->repeat < 1 || o->repeat > 1000000) {
        return fail_usage("--repeat must be 1..1000000", NULL);
    }
    return 0;
}

/* ---- JSON output --------------------------------------------------------------- */

static void put_num(double v)
{
    printf("%.17g", v);
}

static void put_matrix(const char *key, const fcc_real_t *a, unsigned rows, unsigned cols)
{
    printf("  \"%s\": [", key);
    for (unsigned i = 0; i < rows; ++i) {
        printf("%s[", i ? ", " : "");
        for (unsigned j = 0; j < cols; ++j) {
            printf("%s", j ? ", " : "");
            put_num((double)a[i * cols + j]);
        }
        printf("]");
    }
    printf("],\n");
}

static void put_poles(const char *key, const fcc_real_t *re, const fcc_real_t *im, bool last)
{
    printf("  \"%s\": [", key);
    for (unsigned i = 0; i < FCC_LQG_NX; ++i) {
        printf("%s[", i ? ", " : "");
        put_num((double)re[i]);
        printf(", ");
        put_num((double)im[i]);
        printf("]");
    }
    printf("]%s\n", last ? "" : ",");
}

static void put_riccati(const char *key, const fcc_lqg_riccati_t *r, bool last)
{
    printf("    \"%s\": {\"residual\": ", key);
    put_num(r->residual);
    printf(", \"solver_disagreement\": ");
    put_num(r->disagreement);
    printf(", \"doubling_iterations\": %u, \"hamiltonian_rcond_u1\": ", (unsigned)r->iterations);
    put_num(r->rcond_u1);
    printf("}%s\n", last ? "" : ",");
}

static void print_design(const fcc_lqg_design_t *d, const fcc_lqg_dac_t *dac)
{
    enum { NX = FCC_LQG_NX, NU = FCC_LQG_NU, NY = FCC_LQG_NY };
    printf("{\n  \"T\": ");
    put_num((double)d->t);
    printf(",\n  \"real\": \"%s\",\n", sizeof(fcc_real_t) == sizeof(float) ? "float" : "double");
    printf("  \"solver\": \"%s\",\n",
           d->solver == FCC_LQG_SOLVER_HAMILTONIAN ? "hamiltonian" : "doubling");
    printf("  \"bits\": %u,\n  \"lsb\": ", (unsigned)dac->bits);
    put_num((double)dac->lsb);
    printf(",\n  \"code_min\": %ld,\n  \"code_max\": %ld,\n", (long)dac->code_min,
           (long)dac->code_max);
    put_matrix("Phi", d->phi, NX, NX);
    put_matrix("Gamma", d->gamma, NX, NU);
    put_matrix("Qd", d->qd, NX, NX);
    put_matrix("Q11", d->q11, NX, NX);
    put_matrix("Q12", d->q12, NX, NU);
    put_matrix("Q22", d->q22, NU, NU);
    put_matrix("H", d->h, NY, NX);
    put_matrix("R", d->r, NY, NY);
    put_matrix("K", d->k, NU, NX);
    put_matrix("P", d->p, NX, NX);
    put_matrix("M", d->m, NX, NX);
    put_matrix("P_post", d->p_post, NX, NX);
    put_matrix("L", d->l, NX, NY);
    printf("  \"riccati\": {\n");
    put_riccati("lqr", &d->lqr, false);
    put_riccati("kalman", &d->kf, true);
    printf("  },\n");
    put_poles("closed_loop_poles", d->cl_re, d->cl_im, false);
    put_poles("estimator_poles", d->est_re, d->est_im, true);
    printf("}\n");
}

int main(int argc, char **argv)
{
    options_t o = {0.0, false, 8, 0.8, 0.8, FCC_LQG_SOLVER_HAMILTONIAN, 1};
    int rc = parse_args(argc, argv, &o);
    if (rc != 0) {
        return (rc == 1) ? 0 : 2;
    }
    rc = check_ranges(&o);
    if (rc != 0) {
        return rc;
    }
    static fcc_lqg_ws_t ws; /* ~10 KB: static, as on the target */
    fcc_lqg_plant_t plant;
    fcc_lqg_design_t design;
    fcc_lqg_dac_t dac;
    (void)fcc_lqg_plant_default(&plant);
    plant.gyro_var = (fcc_real_t)o.gyro_var;
    plant.accel_var = (fcc_real_t)o.accel_var;
    fcc_status_t st = fcc_lqg_dac_init(&dac, (uint8_t)o.bits);
    for (long i = 0; i < o.repeat && st == FCC_OK; ++i) {
        st = fcc_lqg_design(&plant, o.period, o.solver, &design, &ws);
    }
    if (st != FCC_OK) {
        fprintf(stderr, PROG ": design failed for T = %g s: %s (status %d)\n", o.period,
                fcc_status_str(st), (int)st);
        return 1;
    }
    print_design(&design, &dac);
    return 0;
}
