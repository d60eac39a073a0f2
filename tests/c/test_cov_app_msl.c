/*
 * The missile autopilot application (firmware/app/fcc_app_msl.c) on its own:
 * the configuration's limits one at a time, run-time requests (a field at 0
 * keeps the newest value), the background design (a copy when only N
 * changes, slices when T changes, a failure keeps the design in use), the
 * switch between two steps, a step without a usable measurement, and the two
 * output frames.  The node's use of it on the bus is tested elsewhere.
 */
#include "fcc_test.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include "fcc_app_msl.h"

static fcc_app_msl_t g_app;
static fcc_app_msl_config_t g_cfg;
static fcc_app_msl_result_t g_res;

static void start(void)
{
    fcc_assert_ok(fcc_app_msl_config_default(&g_cfg));
    fcc_assert_ok(fcc_app_msl_init(&g_app, &g_cfg));
}

static void offer(uint16_t k, fcc_real_t q_g, fcc_real_t n_a)
{
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    d.msl_rate_gyro.q_g = q_g;
    d.msl_rate_gyro.step = k;
    fcc_assert_ok(fcc_app_msl_offer(&g_app, FCC_MSG_MSL_RATE_GYRO, &d, 100u * k + 1u));
    d.msl_accelerometer.n_a = n_a;
    d.msl_accelerometer.step = k;
    fcc_assert_ok(fcc_app_msl_offer(&g_app, FCC_MSG_MSL_ACCELEROMETER, &d, 100u * k + 2u));
}

/* Background design slices until the request is done (bounded). */
static fcc_status_t design_all(void)
{
    for (int i = 0; i < 10000; ++i) {
        const fcc_status_t st = fcc_app_msl_background(&g_app);
        if (st != FCC_OK || g_app.spare != FCC_APP_MSL_SPARE_WANTED) {
            return st;
        }
    }
    return FCC_ERR_AGAIN;
}

static void configuration_limits(void **state)
{
    (void)state;
    assert_int_equal(fcc_app_msl_config_default(NULL), FCC_ERR_ARG);
    assert_true(fcc_app_msl_valid(FCC_APP_MSL_T_MIN, FCC_LQG_BITS_MIN));
    assert_true(fcc_app_msl_valid(FCC_APP_MSL_T_MAX, FCC_LQG_BITS_MAX));
    assert_false(fcc_app_msl_valid((fcc_real_t)NAN, 8u));
    assert_false(fcc_app_msl_valid(FCC_R(0.01), 8u));
    assert_false(fcc_app_msl_valid(FCC_R(0.5), 8u));
    assert_false(fcc_app_msl_valid(FCC_R(0.05), FCC_LQG_BITS_MIN - 1u));
    assert_false(fcc_app_msl_valid(FCC_R(0.05), FCC_LQG_BITS_MAX + 1u));
    fcc_assert_ok(fcc_app_msl_config_default(&g_cfg));
    assert_int_equal(fcc_app_msl_init(NULL, &g_cfg), FCC_ERR_ARG);
    assert_int_equal(fcc_app_msl_init(&g_app, NULL), FCC_ERR_ARG);
    fcc_app_msl_config_t bad = g_cfg;
    bad.period = FCC_R(0.5);
    assert_int_equal(fcc_app_msl_init(&g_app, &bad), FCC_ERR_RANGE);
    const fcc_real_t delays[] = {(fcc_real_t)NAN, FCC_R(-0.001), g_cfg.period, FCC_R(1.0)};
    for (size_t i = 0; i < sizeof delays / sizeof delays[0]; ++i) {
        bad = g_cfg;
        bad.delay = delays[i];
        assert_int_equal(fcc_app_msl_init(&g_app, &bad), FCC_ERR_RANGE);
    }
    bad = g_cfg;
    bad.delay = FCC_APP_MSL_RT_DELAY;
    fcc_assert_ok(fcc_app_msl_init(&g_app, &bad));
    fcc_assert_close(fcc_app_msl_period(&g_app), (double)g_cfg.period, 0, 0);
    assert_int_equal(fcc_app_msl_bits(&g_app), g_cfg.bits);
    assert_true(fcc_app_msl_period(NULL) == FCC_R(0.0));
    assert_int_equal(fcc_app_msl_bits(NULL), 0u);
    assert_int_equal(fcc_app_msl_reset(NULL), FCC_ERR_ARG);
    fcc_assert_ok(fcc_app_msl_reset(&g_app));
}

static void requests_and_background_designs(void **state)
{
    (void)state;
    start();
    assert_int_equal(fcc_app_msl_request(NULL, FCC_R(0.1), 8u), FCC_ERR_ARG);
    assert_int_equal(fcc_app_msl_request(&g_app, (fcc_real_t)NAN, 8u), FCC_ERR_ARG);
    assert_int_equal(fcc_app_msl_request(&g_app, FCC_R(0.5), 0u), FCC_ERR_RANGE);
    assert_int_equal(fcc_app_msl_request(&g_app, FCC_R(0.0), 1u), FCC_ERR_RANGE);
    assert_false(fcc_app_msl_wants_design(NULL));
    assert_false(fcc_app_msl_wants_design(&g_app));
    assert_int_equal(fcc_app_msl_background(NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_app_msl_background(&g_app), FCC_ERR_AGAIN); /* nothing asked */
    /* N only (T field 0: the current T): the gains are copied, no design */
    fcc_assert_ok(fcc_app_msl_request(&g_app, FCC_R(0.0), 12u));
    assert_true(fcc_app_msl_wants_design(&g_app));
    /* a second request with N at 0 keeps the pending N (12), not the active one (8) */
    fcc_assert_ok(fcc_app_msl_request(&g_app, FCC_R(0.0), 0u));
    assert_int_equal(g_app.want_bits, 12u);
    fcc_assert_ok(design_all());
    assert_int_equal(g_app.spare, FCC_APP_MSL_SPARE_READY);
    offer(0u, FCC_R(0.01), FCC_R(0.5));
    fcc_assert_ok(fcc_app_msl_step(&g_app, 0u, true, 3u, &g_res));
    assert_true(g_res.switched);
    assert_int_equal(g_res.bits, 12u);
    assert_int_equal(g_app.designs_applied, 1u);
    /* a new T: designed in slices in the background, switched in at the next step */
    fcc_assert_ok(fcc_app_msl_request(&g_app, FCC_R(0.1), 0u));
    fcc_assert_ok(design_all());
    assert_int_equal(g_app.spare, FCC_APP_MSL_SPARE_READY);
    offer(1u, FCC_R(0.01), FCC_R(0.5));
    fcc_assert_ok(fcc_app_msl_step(&g_app, 1u, true, 3u, &g_res));
    assert_true(g_res.switched);
    fcc_assert_close(g_res.period, (double)FCC_R(0.1), 0, 0);
    assert_int_equal(g_res.bits, 12u);
    /* a T the configured delay does not fit under */
    g_app.cfg.delay = FCC_R(0.03);
    assert_int_equal(fcc_app_msl_request(&g_app, FCC_R(0.025), 0u), FCC_ERR_RANGE);
}

/* A design that cannot be made, or a ready one that cannot be switched in: the design in use
 * stays, the failure is counted and its status kept. */
static void failed_designs_keep_the_one_in_use(void **state)
{
    (void)state;
    start();
    fcc_assert_ok(fcc_app_msl_request(&g_app, FCC_R(0.1), 0u));
    g_app.cfg.plant.f[0] = (fcc_real_t)NAN; /* the plant after start-up, for the next design */
    assert_int_not_equal(design_all(), FCC_OK);
    assert_int_equal(g_app.designs_failed, 1u);
    assert_int_not_equal(g_app.last_design_status, FCC_OK);
    assert_int_equal(g_app.spare, FCC_APP_MSL_SPARE_FREE);
    fcc_assert_close(fcc_app_msl_period(&g_app), (double)g_cfg.period, 0, 0);
    /* a ready slot whose gains are not finite is refused at the switch */
    g_app.slot[1] = g_app.slot[0];
    g_app.slot[1].design.k_u = (fcc_real_t)NAN;
    g_app.spare = FCC_APP_MSL_SPARE_READY;
    offer(0u, FCC_R(0.01), FCC_R(0.5));
    fcc_assert_ok(fcc_app_msl_step(&g_app, 0u, true, 3u, &g_res));
    assert_false(g_res.switched);
    assert_int_equal(g_app.active, 0u);
    assert_int_equal(g_app.designs_failed, 2u);
    assert_int_equal(g_app.last_design_status, FCC_ERR_NOT_FINITE);
}

static void steps_with_and_without_a_measurement(void **state)
{
    (void)state;
    start();
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    assert_null(fcc_app_msl_sensor(NULL, FCC_MSG_MSL_RATE_GYRO));
    assert_int_equal(fcc_app_msl_offer(&g_app, FCC_MSG_SIM_TICK, &d, 1u), FCC_ERR_ARG);
    assert_int_equal(fcc_app_msl_offer(&g_app, FCC_MSG_MSL_RATE_GYRO, NULL, 1u), FCC_ERR_ARG);
    assert_int_equal(fcc_app_msl_step(NULL, 0u, true, 3u, &g_res), FCC_ERR_ARG);
    assert_int_equal(fcc_app_msl_step(&g_app, 0u, true, 3u, NULL), FCC_ERR_ARG);
    offer(0u, FCC_R(0.01), FCC_R(0.5));
    fcc_assert_ok(fcc_app_msl_step(&g_app, 0u, true, 3u, &g_res));
    assert_true(g_res.measured);
    assert_false(g_res.degraded);
    assert_int_equal(g_res.newest_rx_us, 2u);
    /* frames, but for another step (lockstep): a prediction, degraded */
    offer(7u, FCC_R(0.01), FCC_R(0.5));
    fcc_assert_ok(fcc_app_msl_step(&g_app, 1u, true, 3u, &g_res));
    assert_int_equal(g_res.input_state[FCC_APP_MSL_IN_GYRO], FCC_SENSOR_MISALIGNED);
    assert_false(g_res.measured);
    assert_true(g_res.degraded);
    /* a finite measurement the estimator cannot take: predicted instead, the refusal reported */
    const fcc_real_t huge = (fcc_real_t)(sizeof(fcc_real_t) == sizeof(double) ? DBL_MAX : FLT_MAX);
    offer(2u, huge, huge);
    assert_int_equal(fcc_app_msl_step(&g_app, 2u, true, 3u, &g_res), FCC_ERR_NOT_FINITE);
    assert_false(g_res.measured);
    assert_true(g_res.degraded);
    assert_int_equal(g_app.degraded_steps, 2u);
    assert_int_equal(g_app.steps, 3u);
}

static void output_frames(void **state)
{
    (void)state;
    start();
    offer(0u, FCC_R(0.01), FCC_R(0.5));
    fcc_assert_ok(fcc_app_msl_step(&g_app, 0u, true, 3u, &g_res));
    fcc_bus_t bus;
    fcc_assert_ok(fcc_bus_init(&bus, FCC_BUS_NODE_FCC));
    fcc_can_frame_t frames[2];
    uint32_t n = 9u;
    assert_int_equal(fcc_app_msl_encode(NULL, &bus, frames, &n), FCC_ERR_ARG);
    assert_int_equal(fcc_app_msl_encode(&g_res, NULL, frames, &n), FCC_ERR_ARG);
    assert_int_equal(fcc_app_msl_encode(&g_res, &bus, NULL, &n), FCC_ERR_ARG);
    assert_int_equal(fcc_app_msl_encode(&g_res, &bus, frames, NULL), FCC_ERR_ARG);
    assert_int_equal(n, 9u);
    fcc_assert_ok(fcc_app_msl_encode(&g_res, &bus, frames, &n));
    assert_int_equal(n, 2u);
    assert_int_equal(frames[0].id, fcc_bus_desc(FCC_MSG_MSL_ELEV_CMD)->id);
    assert_int_equal(frames[1].id, fcc_bus_desc(FCC_MSG_MSL_STATE_EST)->id);
    fcc_msg_data_t d;
    fcc_assert_ok(fcc_bus_decode(FCC_MSG_MSL_ELEV_CMD, frames[0].data, &d));
    assert_int_equal(d.msl_elev_cmd.da_code, g_res.out.code);
    assert_int_equal(d.msl_elev_cmd.da_bits, g_res.bits);
    /* codes outside int16 (impossible from the quantizer) are clamped, not wrapped */
    fcc_app_msl_result_t res = g_res;
    res.bits = 16u;
    res.out.code = 70000;
    fcc_assert_ok(fcc_app_msl_encode(&res, &bus, frames, &n));
    fcc_assert_ok(fcc_bus_decode(FCC_MSG_MSL_ELEV_CMD, frames[0].data, &d));
    assert_int_equal(d.msl_elev_cmd.da_code, INT16_MAX);
    res.out.code = -70000;
    fcc_assert_ok(fcc_app_msl_encode(&res, &bus, frames, &n));
    fcc_assert_ok(fcc_bus_decode(FCC_MSG_MSL_ELEV_CMD, frames[0].data, &d));
    assert_int_equal(d.msl_elev_cmd.da_code, INT16_MIN);
    /* a command out of its signal's range is refused; the estimate frame still goes */
    res.bits = 0u;
    assert_int_not_equal(fcc_app_msl_encode(&res, &bus, frames, &n), FCC_OK);
    assert_int_equal(n, 1u);
    assert_int_equal(frames[0].id, fcc_bus_desc(FCC_MSG_MSL_STATE_EST)->id);
    /* a bus that may not send them (the simulator's): nothing encoded */
    fcc_bus_t sim;
    fcc_assert_ok(fcc_bus_init(&sim, FCC_BUS_NODE_SIM));
    assert_int_not_equal(fcc_app_msl_encode(&g_res, &sim, frames, &n), FCC_OK);
    assert_int_equal(n, 0u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(configuration_limits),
        cmocka_unit_test(requests_and_background_designs),
        cmocka_unit_test(failed_designs_keep_the_one_in_use),
        cmocka_unit_test(steps_with_and_without_a_measurement),
        cmocka_unit_test(output_frames),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
