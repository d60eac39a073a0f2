/*
 * The autopilot's per-period side (firmware/lqg/fcc_lqg_ctrl.c) at its
 * edges: the D/A converter's refusals and clamps, a forged converter, every
 * part of a design that is not finite, an estimate that would overflow (the
 * state is kept), saturation.  A hand-made design with known gains makes each
 * output computable by hand.  The designed autopilot is tested in test_lqg.c.
 */
#include "fcc_test.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include "fcc_lqg.h"

static fcc_lqg_design_t g_d;
static fcc_lqg_ctrl_t g_c;

/* A finite value whose product with 8 is not (the largest of the build's real type / 4). */
#define BIG ((fcc_real_t)(sizeof(fcc_real_t) == sizeof(double) ? DBL_MAX / 4 : FLT_MAX / 4))

/* Phi = I, no input or measurement coupling, K = [1 0 0]: u_cmd = -x1, x stays. */
static fcc_lqg_design_t *design(void)
{
    memset(&g_d, 0, sizeof g_d);
    for (unsigned i = 0; i < FCC_LQG_NX; ++i) {
        g_d.phi[i * FCC_LQG_NX + i] = FCC_R(1.0);
    }
    g_d.k[0] = FCC_R(1.0);
    return &g_d;
}

static void dac_refusals_and_clamps(void **state)
{
    (void)state;
    fcc_lqg_dac_t dac;
    assert_int_equal(fcc_lqg_dac_init(NULL, 8u), FCC_ERR_ARG);
    assert_int_equal(fcc_lqg_dac_init(&dac, FCC_LQG_BITS_MIN - 1u), FCC_ERR_RANGE);
    assert_int_equal(fcc_lqg_dac_init(&dac, FCC_LQG_BITS_MAX + 1u), FCC_ERR_RANGE);
    fcc_assert_ok(fcc_lqg_dac_init(&dac, FCC_LQG_BITS_MIN));
    assert_int_equal(dac.code_min, -2);
    assert_int_equal(dac.code_max, 1);
    fcc_assert_ok(fcc_lqg_dac_init(&dac, FCC_LQG_BITS_MAX));
    assert_int_equal(dac.code_max, 32767);
    int32_t code = 5;
    fcc_real_t u = FCC_R(1.0);
    assert_int_equal(fcc_lqg_dac_convert(NULL, FCC_R(0.1), &code, &u), FCC_ERR_ARG);
    assert_int_equal(fcc_lqg_dac_convert(&dac, FCC_R(0.1), NULL, &u), FCC_ERR_ARG);
    assert_int_equal(fcc_lqg_dac_convert(&dac, FCC_R(0.1), &code, NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_lqg_dac_value(NULL, 0, &u), FCC_ERR_ARG);
    assert_int_equal(fcc_lqg_dac_value(&dac, 0, NULL), FCC_ERR_ARG);
    /* a converter whose bits were never set up (or were overwritten) is refused */
    fcc_lqg_dac_t forged = dac;
    forged.bits = FCC_LQG_BITS_MIN - 1u;
    assert_int_equal(fcc_lqg_dac_convert(&forged, FCC_R(0.1), &code, &u), FCC_ERR_ARG);
    assert_int_equal(fcc_lqg_dac_value(&forged, 0, &u), FCC_ERR_ARG);
    forged.bits = FCC_LQG_BITS_MAX + 1u;
    assert_int_equal(fcc_lqg_dac_convert(&forged, FCC_R(0.1), &code, &u), FCC_ERR_ARG);
    assert_int_equal(code, 5); /* untouched by every refusal */
    /* NaN: the safe code 0 */
    assert_int_equal(fcc_lqg_dac_convert(&dac, (fcc_real_t)NAN, &code, &u), FCC_ERR_NOT_FINITE);
    assert_int_equal(code, 0);
    assert_true(u == FCC_R(0.0));
    /* far beyond either end: the end codes */
    fcc_assert_ok(fcc_lqg_dac_convert(&dac, BIG, &code, &u));
    assert_int_equal(code, dac.code_max);
    fcc_assert_ok(fcc_lqg_dac_convert(&dac, -BIG, &code, &u));
    assert_int_equal(code, dac.code_min);
    fcc_assert_close(u, -(double)FCC_LQG_U_MAX, 0, 0); /* -2^15 LSB of 0.8 / 2^16 */
    /* a code's value, clamped to the range */
    fcc_assert_ok(fcc_lqg_dac_value(&dac, 100000, &u));
    fcc_assert_close(u, (double)((fcc_real_t)dac.code_max * dac.lsb), 0, 0);
    fcc_assert_ok(fcc_lqg_dac_value(&dac, -100000, &u));
    fcc_assert_close(u, -(double)FCC_LQG_U_MAX, 0, 0);
    fcc_assert_ok(fcc_lqg_dac_value(&dac, 3, &u));
    fcc_assert_close(u, (double)((fcc_real_t)3 * dac.lsb), 0, 0);
}

static void init_refuses_what_is_not_finite(void **state)
{
    (void)state;
    const fcc_real_t x0_bad[FCC_LQG_NX] = {0, (fcc_real_t)INFINITY, 0};
    assert_int_equal(fcc_lqg_ctrl_init(NULL, design(), 8u, NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_lqg_ctrl_init(&g_c, NULL, 8u, NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_lqg_ctrl_init(&g_c, design(), 8u, x0_bad), FCC_ERR_NOT_FINITE);
    assert_int_equal(fcc_lqg_ctrl_init(&g_c, design(), 1u, NULL), FCC_ERR_RANGE);
    /* each part of the design the controller copies, one at a time */
    fcc_real_t *parts[] = {&g_d.phi[4], &g_d.gamma[1], &g_d.k[2], &g_d.l[5], &g_d.h[3],
                           &g_d.gamma1[0], &g_d.k_u};
    for (size_t i = 0; i < sizeof parts / sizeof parts[0]; ++i) {
        (void)design();
        *parts[i] = (fcc_real_t)NAN;
        assert_int_equal(fcc_lqg_ctrl_init(&g_c, &g_d, 8u, NULL), FCC_ERR_NOT_FINITE);
    }
    fcc_assert_ok(fcc_lqg_ctrl_init(&g_c, design(), 8u, NULL));
    assert_int_equal(fcc_lqg_ctrl_reset(NULL, NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_lqg_ctrl_reset(&g_c, x0_bad), FCC_ERR_NOT_FINITE);
}

static void commands_follow_the_gains(void **state)
{
    (void)state;
    const fcc_real_t x0[FCC_LQG_NX] = {FCC_R(0.1), FCC_R(2.0), FCC_R(-3.0)};
    fcc_assert_ok(fcc_lqg_ctrl_init(&g_c, design(), 16u, x0));
    fcc_lqg_output_t out;
    assert_int_equal(fcc_lqg_ctrl_predict(NULL, &out), FCC_ERR_ARG);
    assert_int_equal(fcc_lqg_ctrl_predict(&g_c, NULL), FCC_ERR_ARG);
    fcc_assert_ok(fcc_lqg_ctrl_predict(&g_c, &out));
    fcc_assert_close(out.u_cmd, -0.1, FCC_TEST_TOL(1e-15, 1e-6), 0);
    assert_false(out.saturated);
    assert_false(out.measured);
    fcc_assert_close(out.u_applied, -0.1, 0, (double)g_c.dac.lsb); /* within one LSB */
    assert_int_equal(g_c.predictions, 1u);
    /* x1 = 1: -1 rad commanded, 0.4 applied at most */
    const fcc_real_t x1[FCC_LQG_NX] = {FCC_R(1.0), 0, 0};
    fcc_assert_ok(fcc_lqg_ctrl_reset(&g_c, x1));
    fcc_assert_ok(fcc_lqg_ctrl_predict(&g_c, &out));
    assert_true(out.saturated);
    fcc_assert_close(out.u_sat, -(double)FCC_LQG_U_MAX, 0, 0);
    /* a measurement through L = [1 0; 0 0; 0 0] replaces x1 by y1 (H = 0) */
    g_c.l[0] = FCC_R(1.0);
    fcc_assert_ok(fcc_lqg_ctrl_reset(&g_c, NULL));
    const fcc_real_t y[FCC_LQG_NY] = {FCC_R(0.2), FCC_R(5.0)};
    fcc_assert_ok(fcc_lqg_ctrl_step(&g_c, y, &out));
    assert_true(out.measured);
    fcc_assert_close(out.x_hat[0], 0.2, FCC_TEST_TOL(1e-15, 1e-6), 0);
    fcc_assert_close(out.u_cmd, -0.2, FCC_TEST_TOL(1e-15, 1e-6), 0);
    assert_int_equal(g_c.updates, 1u);
}

/* A measurement or a model that would overflow the estimate: refused, the state kept. */
static void overflow_keeps_the_state(void **state)
{
    (void)state;
    fcc_lqg_output_t out;
    const fcc_real_t y_nan[FCC_LQG_NY] = {(fcc_real_t)NAN, 0};
    const fcc_real_t y_big[FCC_LQG_NY] = {BIG, 0};
    (void)design();
    g_d.l[0] = FCC_R(8.0);
    fcc_assert_ok(fcc_lqg_ctrl_init(&g_c, &g_d, 8u, NULL));
    assert_int_equal(fcc_lqg_ctrl_step(NULL, y_big, &out), FCC_ERR_ARG);
    assert_int_equal(fcc_lqg_ctrl_step(&g_c, NULL, &out), FCC_ERR_ARG);
    assert_int_equal(fcc_lqg_ctrl_step(&g_c, y_big, NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_lqg_ctrl_step(&g_c, y_nan, &out), FCC_ERR_NOT_FINITE);
    assert_int_equal(fcc_lqg_ctrl_step(&g_c, y_big, &out), FCC_ERR_NOT_FINITE);
    /* a huge Phi: the prediction overflows, nothing is committed */
    (void)design();
    g_d.k[0] = FCC_R(0.0);
    g_d.phi[0] = BIG;
    const fcc_real_t x0[FCC_LQG_NX] = {FCC_R(8.0), 0, 0};
    fcc_assert_ok(fcc_lqg_ctrl_init(&g_c, &g_d, 8u, x0));
    assert_int_equal(fcc_lqg_ctrl_predict(&g_c, &out), FCC_ERR_NOT_FINITE);
    fcc_assert_close(g_c.x_pred[0], 8.0, 0, 0);
    assert_int_equal(g_c.predictions + g_c.updates, 0u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(dac_refusals_and_clamps),
        cmocka_unit_test(init_refuses_what_is_not_finite),
        cmocka_unit_test(commands_follow_the_gains),
        cmocka_unit_test(overflow_keeps_the_state),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
