/*
 * numeric_probe.c -- the outputs of a few numerical computations, printed in full, so that the
 * host double, host float and Cortex-M4F float builds can be compared value by value
 * (tests/target/compare_numeric.py; the tests themselves only assert within a tolerance).
 * One line per value: "group index value" with 9 significant digits beyond float's (%.17g).
 *
 *   lqg_*    the LQG design at T = 0.05 s (computed in double in every build, then rounded)
 *   ctrl_u   200 steps of the LQG controller on a fixed measurement sequence (fcc_real_t)
 *   sid_*    200 steps of the identification (KF, ZKF, AZKF) on a fixed flight (fcc_real_t)
 *   mat_*    inverse, solve and exponential of fixed matrices (fcc_real_t)
 * Exit status 1 when a computation refuses (its status on stderr).
 */
#include <math.h>
#include <stdio.h>

#include "fcc_lqg.h"
#include "fcc_mat.h"
#include "fcc_sid.h"

static fcc_lqg_ws_t g_design_ws;
static fcc_sid_t g_sid;
static fcc_mat_lu_t g_lu;
static fcc_mat_expm_ws_t g_expm_ws;

/* Values first, first + 1, ... of the group (a step's values after the steps before). */
static void print_values(const char *group, int first, const fcc_real_t *v, int n)
{
    for (int i = 0; i < n; ++i) {
        printf("%s %d %.17g\n", group, first + i, (double)v[i]);
    }
}

static int check(fcc_status_t status, const char *what)
{
    if (status != FCC_OK) {
        fprintf(stderr, "numeric_probe: %s: status %d\n", what, (int)status);
        return 1;
    }
    return 0;
}

static int probe_lqg(void)
{
    fcc_lqg_plant_t plant;
    fcc_lqg_design_t d;
    fcc_lqg_ctrl_t ctrl;
    if (check(fcc_lqg_plant_default(&plant), "plant") != 0 ||
        check(fcc_lqg_design(&plant, 0.05, FCC_LQG_SOLVER_HAMILTONIAN, &d, &g_design_ws), "design") != 0 ||
        check(fcc_lqg_ctrl_init(&ctrl, &d, 12u, NULL), "controller") != 0) {
        return 1;
    }
    print_values("lqg_k", 0, d.k, FCC_LQG_NU * FCC_LQG_NX);
    print_values("lqg_l", 0, d.l, FCC_LQG_NX * FCC_LQG_NY);
    print_values("lqg_p", 0, d.p, FCC_LQG_NX * FCC_LQG_NX);
    print_values("lqg_cl_re", 0, d.cl_re, FCC_LQG_NX);
    for (int k = 0; k < 200; ++k) {
        const double t = 0.05 * k;
        const fcc_real_t y[FCC_LQG_NY] = {(fcc_real_t)(0.1 * sin(1.3 * t)), (fcc_real_t)(2.0 * cos(0.7 * t))};
        fcc_lqg_output_t out;
        if (check(fcc_lqg_ctrl_step(&ctrl, y, &out), "controller step") != 0) {
            return 1;
        }
        print_values("ctrl_u", k, &out.u_cmd, 1);
    }
    return 0;
}

static int probe_sid(fcc_sid_filter_t filter, const char *name)
{
    fcc_sid_config_t cfg;
    fcc_sid_config_default(&cfg, filter);
    if (check(fcc_sid_init(&g_sid, &cfg), "sid init") != 0) {
        return 1;
    }
    double x[2] = {0.16, 0.02};
    fcc_sid_out_t out;
    for (int k = 0; k < 200; ++k) {
        const double t = 0.02 * k;
        const double de = -0.12 + 0.02 * sin(4.4 * t) + 0.015 * sin(11.9 * t + 1.0);
        (void)fcc_sid_step(&g_sid, (fcc_real_t)x[0], (fcc_real_t)x[1], (fcc_real_t)de, false, true, &out);
        if (!out.stepped) {
            return check(out.status, name);
        }
        char group[32];
        (void)snprintf(group, sizeof group, "sid_%s_xhat", name);
        print_values(group, 2 * k, out.x_hat, 2);
        const double n0 = 0.96 * x[0] + 0.02 * x[1] - 0.004 * de;
        const double n1 = -0.45 * x[0] + 0.93 * x[1] - 0.55 * de;
        x[0] = n0;
        x[1] = n1;
    }
    char group[32];
    (void)snprintf(group, sizeof group, "sid_%s_model", name);
    print_values(group, 0, out.model.a, 4);
    return 0;
}

static int probe_mat(void)
{
    enum { N = 6 };
    fcc_real_t a[N * N], ainv[N * N], b[N], x[N];
    for (int i = 0; i < N; ++i) {
        b[i] = (fcc_real_t)(1.0 + 0.5 * i);
        for (int j = 0; j < N; ++j) {
            /* diagonally weighted Hilbert-like matrix: condition number ~1e3 */
            a[i * N + j] = (fcc_real_t)(1.0 / (i + j + 1.0) + (i == j ? 0.1 : 0.0));
        }
    }
    fcc_mat_t ma = FCC_MAT(N, N, a), mi = FCC_MAT(N, N, ainv), mb = FCC_MAT(N, 1, b), mx = FCC_MAT(N, 1, x);
    fcc_real_t f[9] = {FCC_R(-0.0607), FCC_R(-8.85), FCC_R(0.0), FCC_R(0.05), FCC_R(-0.2015),
                       FCC_R(0.0000745), FCC_R(0.0), FCC_R(0.0), FCC_R(-0.1)};
    fcc_real_t e[9];
    fcc_mat_t mf = FCC_MAT(3, 3, f), me = FCC_MAT(3, 3, e);
    if (check(fcc_mat_inv(&ma, &mi, &g_lu), "inverse") != 0 ||
        check(fcc_mat_solve(&ma, &mb, &mx, &g_lu), "solve") != 0 ||
        check(fcc_mat_expm(&mf, &me, &g_expm_ws), "expm") != 0) {
        return 1;
    }
    print_values("mat_inv", 0, ainv, N * N);
    print_values("mat_solve", 0, x, N);
    print_values("mat_expm", 0, e, 9);
    return 0;
}

int main(void)
{
    const int failed = probe_lqg() + probe_sid(FCC_SID_KF, "kf") + probe_sid(FCC_SID_ZKF, "zkf") +
                       probe_sid(FCC_SID_AZKF, "azkf") + probe_mat();
    return failed == 0 ? 0 : 1;
}
