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
#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fcc_lqg.h"
#include "fcc_opt.h"

#define PROG "lqg_design"

typedef struct {
    double period;
    bool have_period;
    unsigned long bits;
    double gyro_var;
    double accel_var;
    fcc_lqg_solver_t solver;
    unsigned long repeat;
    double delay;
} options_t;

static void usage(FILE *out)
{
    fprintf(out,
            "usage: " PROG " --period T [--bits N] [--gyro-var V] [--accel-var V]\n"
            "                  [--solver hamiltonian|doubling] [--delay D] [--repeat N]\n"
            "Design the missile LQG autopilot for sampling period T (s) with the\n"
            "firmware's own numerics and print one JSON object (matrices row-major).\n"
            "  --period T       sampling period, %g <= T <= %g s (required)\n"
            "  --bits N         D/A converter bits, %u..%u (default 8)\n"
            "  --gyro-var V     rate-gyro noise variance, rad^2/s^2, > 0 (default 0.8)\n"
            "  --accel-var V    accelerometer noise variance, ft^2/s^4, > 0 (default 0.8)\n"
            "  --solver S       Riccati solution reported: hamiltonian (the paper's\n"
            "                   eigenvector method, default) or doubling; both always run\n"
            "                   and must agree\n"
            "  --delay D        design for a known input delay of D s, 0 <= D < T (default\n"
            "                   0): Gamma split into Gamma0/Gamma1, the LQR on [x; u_k-1]\n"
            "                   (solved by doubling; see fcc_lqg.h)\n"
            "  --repeat N       run the design N times (timing aid; prints once)\n"
            "  --help           this text\n",
            FCC_LQG_T_MIN, FCC_LQG_T_MAX, FCC_LQG_BITS_MIN, FCC_LQG_BITS_MAX);
}

/* A noise variance: a finite number > 0. */
static fcc_opt_result_t variance(const char *name, const char *val, double *out, char *err,
                                 size_t err_len)
{
    const fcc_opt_result_t r = fcc_opt_double(name, val, -DBL_MAX, DBL_MAX, out, err, err_len);
    if (r == FCC_OPT_DONE && !(*out > 0.0)) {
        return fcc_opt_fail(err, err_len, "%s: a variance must be > 0, not %g", name, *out);
    }
    return r;
}

static fcc_opt_result_t apply_option(void *ctx, const char *name, const char *val, char *err,
                                     size_t err_len)
{
    static const char *const solvers[] = {"hamiltonian", "doubling"};
    options_t *o = ctx;
    if (strcmp(name, "--delay") == 0) {
        return fcc_opt_double(name, val, 0.0, FCC_LQG_T_MAX, &o->delay, err, err_len);
    }
    if (strcmp(name, "--period") == 0) {
        o->have_period = true;
        return fcc_opt_double(name, val, FCC_LQG_T_MIN, FCC_LQG_T_MAX, &o->period, err, err_len);
    }
    if (strcmp(name, "--bits") == 0) {
        return fcc_opt_uint(name, val, FCC_LQG_BITS_MIN, FCC_LQG_BITS_MAX, &o->bits, err, err_len);
    }
    if (strcmp(name, "--gyro-var") == 0) {
        return variance(name, val, &o->gyro_var, err, err_len);
    }
    if (strcmp(name, "--accel-var") == 0) {
        return variance(name, val, &o->accel_var, err, err_len);
    }
    if (strcmp(name, "--solver") == 0) {
        int which = 0;
        const fcc_opt_result_t r = fcc_opt_choice(name, val, solvers, 2, &which, err, err_len);
        o->solver = which == 0 ? FCC_LQG_SOLVER_HAMILTONIAN : FCC_LQG_SOLVER_DOUBLING;
        return r;
    }
    if (strcmp(name, "--repeat") == 0) {
        return fcc_opt_uint(name, val, 1ul, 1000000ul, &o->repeat, err, err_len);
    }
    return FCC_OPT_NOT_MINE;
}

/* 0: parsed; 1: --help printed; 2: error printed. */
static int parse_args(int argc, char **argv, options_t *o)
{
    char err[200];
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            usage(stdout);
            return 1;
        }
        if (fcc_opt_take(argc, argv, &i, apply_option, o, "see --help", err, sizeof err) !=
            FCC_OPT_DONE) {
            fprintf(stderr, PROG ": %s\n", err);
            return 2;
        }
    }
    if (!o->have_period) {
        fprintf(stderr, PROG ": --period is required (see --help)\n");
        return 2;
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
    enum { NX = FCC_LQG_NX, NU = FCC_LQG_NU, NY = FCC_LQG_NY, NA = FCC_LQG_NA };
    printf("{\n  \"T\": ");
    put_num((double)d->t);
    printf(",\n  \"delay\": ");
    put_num((double)d->delay);
    printf(",\n  \"real\": \"%s\",\n", sizeof(fcc_real_t) == sizeof(float) ? "float" : "double");
    printf("  \"solver\": \"%s\",\n",
           d->solver == FCC_LQG_SOLVER_HAMILTONIAN ? "hamiltonian" : "doubling");
    printf("  \"bits\": %u,\n  \"lsb\": ", (unsigned)dac->bits);
    put_num((double)dac->lsb);
    printf(",\n  \"code_min\": %ld,\n  \"code_max\": %ld,\n", (long)dac->code_min,
           (long)dac->code_max);
    put_matrix("Phi", d->phi, NX, NX);
    put_matrix("Gamma", d->gamma, NX, NU);
    put_matrix("Gamma1", d->gamma1, NX, NU);
    put_matrix("Qd", d->qd, NX, NX);
    put_matrix("Q11", d->q11, NX, NX);
    put_matrix("Q12", d->q12, NX, NU);
    put_matrix("Q22", d->q22, NU, NU);
    put_matrix("H", d->h, NY, NX);
    put_matrix("R", d->r, NY, NY);
    put_matrix("K", d->k, NU, NX);
    printf("  \"K_u\": ");
    put_num((double)d->k_u);
    printf(",\n");
    if (d->delay > 0) {
        put_matrix("Qa11", d->qa11, NA, NA);
        put_matrix("Qa12", d->qa12, NA, NU);
        put_matrix("Qa22", &d->qa22, NU, NU);
        put_matrix("Pa", d->pa, NA, NA);
    }
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
    options_t o = {0.0, false, 8, 0.8, 0.8, FCC_LQG_SOLVER_HAMILTONIAN, 1, 0.0};
    int rc = parse_args(argc, argv, &o);
    if (rc != 0) {
        return (rc == 1) ? 0 : 2;
    }
    static fcc_lqg_ws_t ws; /* ~10 KB: static, as on the target */
    fcc_lqg_plant_t plant;
    fcc_lqg_design_t design;
    fcc_lqg_dac_t dac;
    (void)fcc_lqg_plant_default(&plant);
    plant.gyro_var = (fcc_real_t)o.gyro_var;
    plant.accel_var = (fcc_real_t)o.accel_var;
    fcc_status_t st = fcc_lqg_dac_init(&dac, (uint8_t)o.bits);
    for (unsigned long i = 0; i < o.repeat && st == FCC_OK; ++i) {
        st = fcc_lqg_design_delayed(&plant, o.period, o.delay, o.solver, &design, &ws);
    }
    if (st != FCC_OK) {
        fprintf(stderr, PROG ": design failed for T = %g s, delay %g s: %s (status %d)\n",
                o.period, o.delay, fcc_status_str(st), (int)st);
        return 1;
    }
    print_design(&design, &dac);
    if (fflush(stdout) != 0 || ferror(stdout)) { /* e.g. a full disk: never exit 0 on it */
        fprintf(stderr, PROG ": cannot write the design: %s\n", strerror(errno));
        return 1;
    }
    return 0;
}
