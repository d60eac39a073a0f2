/*
 * The identification application (firmware/app/fcc_app_sid.c) on its own,
 * without the node around it: its refusals, the three inputs, a step with an
 * input missing, out of range or an elevator the filters refuse, and the
 * twelve output frames with each filter's "degraded" flag.  The node's use of
 * it, on the bus, is tested in test_app_node.c and the Python bus tests.
 */
#include "fcc_test.h"

#include <math.h>
#include <string.h>

#include "fcc_app_sid.h"

static fcc_app_sid_t g_app;
static fcc_app_sid_result_t g_res;

static void start(void)
{
    fcc_app_sid_config_t cfg;
    fcc_app_sid_config_default(&cfg);
    fcc_assert_ok(fcc_app_sid_init(&g_app, &cfg));
}

/* Offer alpha, q and the elevator (the ones not NAN) for step k. */
static void offer(uint16_t k, fcc_real_t alpha, fcc_real_t q, fcc_real_t de)
{
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    if (!isnan(alpha)) {
        d.cdrw_aoa.alpha = alpha;
        d.cdrw_aoa.step = k;
        fcc_assert_ok(fcc_app_sid_offer(&g_app, FCC_MSG_CDRW_AOA, &d, 1000u * k + 1u));
    }
    if (!isnan(q)) {
        d.cdrw_pitch_rate.q = q;
        d.cdrw_pitch_rate.step = k;
        fcc_assert_ok(fcc_app_sid_offer(&g_app, FCC_MSG_CDRW_PITCH_RATE, &d, 1000u * k + 2u));
    }
    if (!isnan(de)) {
        d.cdrw_elevator.delta_e = de;
        d.cdrw_elevator.step = k;
        fcc_assert_ok(fcc_app_sid_offer(&g_app, FCC_MSG_CDRW_ELEVATOR, &d, 1000u * k + 3u));
    }
}

static fcc_status_t step(uint32_t k)
{
    return fcc_app_sid_step(&g_app, k, true, 5u, false, &g_res);
}

static void refusals(void **state)
{
    (void)state;
    fcc_app_sid_config_t cfg;
    fcc_app_sid_config_default(&cfg);
    fcc_app_sid_config_default(NULL); /* nothing to fill: no fault */
    assert_int_equal(fcc_app_sid_init(NULL, &cfg), FCC_ERR_ARG);
    assert_int_equal(fcc_app_sid_init(&g_app, NULL), FCC_ERR_ARG);
    fcc_app_sid_config_t bad = cfg;
    bad.base.de_limit = FCC_R(0.0); /* a limit that refuses every elevator is no configuration */
    assert_int_not_equal(fcc_app_sid_init(&g_app, &bad), FCC_OK);
    assert_int_equal(fcc_app_sid_reset(NULL), FCC_ERR_ARG);
    assert_null(fcc_app_sid_sensor(NULL, FCC_MSG_CDRW_AOA));
    start();
    assert_null(fcc_app_sid_sensor(&g_app, FCC_MSG_SID_AZKF_STATE)); /* not an input */
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    assert_int_equal(fcc_app_sid_offer(&g_app, FCC_MSG_SIM_TICK, &d, 1u), FCC_ERR_ARG);
    assert_int_equal(fcc_app_sid_offer(&g_app, FCC_MSG_CDRW_AOA, NULL, 1u), FCC_ERR_ARG);
    assert_int_equal(fcc_app_sid_offer(NULL, FCC_MSG_CDRW_AOA, &d, 1u), FCC_ERR_ARG);
    assert_int_equal(fcc_app_sid_step(NULL, 0u, true, 5u, false, &g_res), FCC_ERR_ARG);
    assert_int_equal(fcc_app_sid_step(&g_app, 0u, true, 5u, false, NULL), FCC_ERR_ARG);
    assert_int_equal(g_app.steps, 0u); /* no refusal counted as a step */
}

static void healthy_steps_use_every_input(void **state)
{
    (void)state;
    start();
    for (uint16_t k = 0u; k < 3u; ++k) {
        offer(k, FCC_R(0.1), FCC_R(0.05), FCC_R(-0.02));
        (void)step(k);
        assert_true(g_res.measurement_valid);
        assert_int_equal(g_res.newest_rx_us, 1000u * k + 3u); /* the elevator came last */
        for (unsigned int f = 0u; f < FCC_APP_SID_N_FILTERS; ++f) {
            assert_true(g_res.out[f].stepped);
            assert_true(g_res.out[f].measurement_used);
            assert_int_equal(g_res.out[f].input_status, FCC_OK);
        }
    }
    assert_int_equal(g_app.steps, 3u);
    /* a reset starts the loops again: the next step is the filters' first */
    fcc_assert_ok(fcc_app_sid_reset(&g_app));
    offer(3u, FCC_R(0.1), FCC_R(0.05), FCC_R(-0.02));
    (void)step(3u);
    assert_int_equal(g_res.out[0].k, 0u);
}

/* No angle of attack this step: the filters predict without a measurement, the step is degraded
 * but not an error. */
static void missing_input_degrades(void **state)
{
    (void)state;
    start();
    offer(0u, (fcc_real_t)NAN, FCC_R(0.05), FCC_R(-0.02));
    fcc_assert_ok(step(0u));
    assert_false(g_res.measurement_valid);
    assert_false(fcc_sensor_usable(g_res.input_state[FCC_APP_SID_IN_ALPHA]));
    assert_true(fcc_sensor_usable(g_res.input_state[FCC_APP_SID_IN_Q]));
    assert_true(g_res.degraded);
    for (unsigned int f = 0u; f < FCC_APP_SID_N_FILTERS; ++f) {
        assert_true(g_res.out[f].stepped);
        assert_false(g_res.out[f].measurement_used);
    }
    assert_int_equal(g_app.degraded_steps, 1u);
}

/* All three inputs came, but alpha is beyond the filters' limit: every loop steps without it and
 * says why; the step is degraded with that status. */
static void out_of_range_sample_degrades(void **state)
{
    (void)state;
    start();
    offer(0u, FCC_R(3.0), FCC_R(0.05), FCC_R(-0.02));
    assert_int_equal(step(0u), FCC_OK); /* the loops stepped: no step error */
    assert_true(g_res.measurement_valid);
    assert_true(g_res.degraded);
    for (unsigned int f = 0u; f < FCC_APP_SID_N_FILTERS; ++f) {
        assert_true(g_res.out[f].stepped);
        assert_int_equal(g_res.out[f].input_status, FCC_ERR_RANGE);
        assert_false(g_res.out[f].measurement_used);
    }
}

/* An elevator beyond its limit: every loop refuses to step, the step reports the refusal (the
 * first), the outputs are the last good ones; the next good elevator steps again. */
static void refused_elevator_is_a_step_error(void **state)
{
    (void)state;
    start();
    offer(0u, FCC_R(0.1), FCC_R(0.05), FCC_R(-0.02));
    (void)step(0u);
    const fcc_sid_out_t good = g_res.out[FCC_SID_KF];
    offer(1u, FCC_R(0.1), FCC_R(0.05), FCC_R(5.0));
    assert_int_equal(step(1u), FCC_ERR_RANGE);
    assert_int_equal(g_res.status, FCC_ERR_RANGE);
    assert_true(g_res.degraded);
    for (unsigned int f = 0u; f < FCC_APP_SID_N_FILTERS; ++f) {
        assert_false(g_res.out[f].stepped);
    }
    assert_int_equal(g_res.out[FCC_SID_KF].k, good.k);
    fcc_assert_close(g_res.out[FCC_SID_KF].x_hat[0], good.x_hat[0], 0, 0);
    offer(2u, FCC_R(0.1), FCC_R(0.05), FCC_R(-0.02));
    (void)step(2u);
    assert_true(g_res.out[FCC_SID_KF].stepped);
    assert_int_equal(g_res.out[FCC_SID_KF].k, good.k + 1u);
}

static bool degraded_flag(const fcc_can_frame_t *frame, fcc_msg_t msg)
{
    fcc_msg_data_t d;
    fcc_assert_ok(fcc_bus_decode(msg, frame->data, &d));
    return d.sid_azkf_state.degraded; /* the three STATE frames share the layout */
}

static void frames_flag_each_filter(void **state)
{
    (void)state;
    start();
    offer(0u, FCC_R(0.1), FCC_R(0.05), FCC_R(-0.02));
    (void)step(0u);
    fcc_bus_t bus;
    fcc_assert_ok(fcc_bus_init(&bus, FCC_BUS_NODE_FCC));
    fcc_can_frame_t frames[FCC_APP_SID_N_FRAMES];
    uint32_t n = 99u;
    assert_int_equal(fcc_app_sid_encode(NULL, &bus, frames, &n), FCC_ERR_ARG);
    assert_int_equal(fcc_app_sid_encode(&g_res, NULL, frames, &n), FCC_ERR_ARG);
    assert_int_equal(fcc_app_sid_encode(&g_res, &bus, NULL, &n), FCC_ERR_ARG);
    assert_int_equal(fcc_app_sid_encode(&g_res, &bus, frames, NULL), FCC_ERR_ARG);
    assert_int_equal(n, 99u);
    /* one filter refused (AZKF), one stepped on a rejected sample (ZKF), one is well (KF) */
    fcc_app_sid_result_t res = g_res;
    res.degraded = false;
    res.out[FCC_SID_AZKF].stepped = false;
    res.out[FCC_SID_AZKF].status = FCC_OK;
    res.out[FCC_SID_ZKF].stepped = true;
    res.out[FCC_SID_ZKF].status = FCC_ERR_RANGE;
    res.out[FCC_SID_KF].stepped = true;
    res.out[FCC_SID_KF].status = FCC_OK;
    fcc_assert_ok(fcc_app_sid_encode(&res, &bus, frames, &n));
    assert_int_equal(n, FCC_APP_SID_N_FRAMES);
    const fcc_msg_t first[FCC_APP_SID_N_FILTERS] = {FCC_MSG_SID_AZKF_STATE, FCC_MSG_SID_ZKF_STATE,
                                                   FCC_MSG_SID_KF_STATE};
    for (unsigned int i = 0u; i < FCC_APP_SID_N_FILTERS; ++i) {
        for (unsigned int part = 0u; part < 4u; ++part) {
            assert_int_equal(frames[4u * i + part].id, fcc_bus_desc((fcc_msg_t)(first[i] + part))->id);
        }
    }
    assert_true(degraded_flag(&frames[0], FCC_MSG_SID_AZKF_STATE));
    assert_true(degraded_flag(&frames[4], FCC_MSG_SID_ZKF_STATE));
    assert_false(degraded_flag(&frames[8], FCC_MSG_SID_KF_STATE));
    /* a degraded step flags all three */
    res.degraded = true;
    fcc_assert_ok(fcc_app_sid_encode(&res, &bus, frames, &n));
    assert_true(degraded_flag(&frames[8], FCC_MSG_SID_KF_STATE));
    /* a bus that may not send these frames (the simulator's): none encoded, its refusal returned */
    fcc_bus_t sim;
    fcc_assert_ok(fcc_bus_init(&sim, FCC_BUS_NODE_SIM));
    assert_int_not_equal(fcc_app_sid_encode(&res, &sim, frames, &n), FCC_OK);
    assert_int_equal(n, 0u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(refusals),
        cmocka_unit_test(healthy_steps_use_every_input),
        cmocka_unit_test(missing_input_degrades),
        cmocka_unit_test(out_of_range_sample_degrades),
        cmocka_unit_test(refused_elevator_is_a_step_error),
        cmocka_unit_test(frames_flag_each_filter),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
