/*
 * The frame layer (firmware/bus/fcc_bus.c) and the sensor verdicts
 * (firmware/app/fcc_sensor.c) at their edges: each missing argument, unknown
 * message or signal on its own, a node's masks beyond the message table, a
 * signal value outside its field, the names of every verdict and state, the
 * reject counter's saturation.  The frames themselves are tested in
 * test_bus.c and test_codec.c.
 */
#include "fcc_test.h"

#include <string.h>

#include "fcc_bus.h"
#include "fcc_sensor.h"

static fcc_bus_t g_bus;

static void codec_refuses_each_argument(void **state)
{
    (void)state;
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    uint8_t raw[8] = {0};
    assert_int_equal(fcc_bus_decode(FCC_MSG_COUNT, raw, &d), FCC_ERR_ARG);
    assert_int_equal(fcc_bus_decode(FCC_MSG_MSL_ELEV_CMD, NULL, &d), FCC_ERR_ARG);
    assert_int_equal(fcc_bus_decode(FCC_MSG_MSL_ELEV_CMD, raw, NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_bus_pack(FCC_MSG_COUNT, &d, raw), FCC_ERR_ARG);
    assert_int_equal(fcc_bus_pack(FCC_MSG_MSL_ELEV_CMD, NULL, raw), FCC_ERR_ARG);
    assert_int_equal(fcc_bus_pack(FCC_MSG_MSL_ELEV_CMD, &d, NULL), FCC_ERR_ARG);
}

/* Signals by index: every argument refused alone; a real and an integer signal read back what
 * was set; an integer outside its field (or a bool other than 0, 1) is refused. */
static void signals_by_index(void **state)
{
    (void)state;
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    fcc_real_t real = FCC_R(9.0);
    int64_t integer = 9;
    const fcc_bus_msg_desc_t *desc = fcc_bus_desc(FCC_MSG_MSL_ELEV_CMD);
    assert_non_null(desc);
    const uint32_t n = desc->n_signals;
    assert_int_equal(fcc_bus_signal_get(FCC_MSG_COUNT, 0u, &d, &real, &integer), FCC_ERR_ARG);
    assert_int_equal(fcc_bus_signal_get(FCC_MSG_MSL_ELEV_CMD, 0u, NULL, &real, &integer), FCC_ERR_ARG);
    assert_int_equal(fcc_bus_signal_get(FCC_MSG_MSL_ELEV_CMD, 0u, &d, NULL, &integer), FCC_ERR_ARG);
    assert_int_equal(fcc_bus_signal_get(FCC_MSG_MSL_ELEV_CMD, 0u, &d, &real, NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_bus_signal_get(FCC_MSG_MSL_ELEV_CMD, n, &d, &real, &integer), FCC_ERR_ARG);
    assert_int_equal(fcc_bus_signal_set(FCC_MSG_COUNT, 0u, &d, 0, 0), FCC_ERR_ARG);
    assert_int_equal(fcc_bus_signal_set(FCC_MSG_MSL_ELEV_CMD, 0u, NULL, 0, 0), FCC_ERR_ARG);
    assert_int_equal(fcc_bus_signal_set(FCC_MSG_MSL_ELEV_CMD, n, &d, 0, 0), FCC_ERR_ARG);
    /* da_code (int16): both ends, one past each */
    uint32_t code = n;
    for (uint32_t i = 0u; i < n; ++i) {
        if (strcmp(desc->signals[i].name, "da_code") == 0) {
            code = i;
        }
    }
    assert_true(code < n);
    assert_int_equal(fcc_bus_signal_set(FCC_MSG_MSL_ELEV_CMD, code, &d, 0, -32769), FCC_ERR_RANGE);
    assert_int_equal(fcc_bus_signal_set(FCC_MSG_MSL_ELEV_CMD, code, &d, 0, 32768), FCC_ERR_RANGE);
    fcc_assert_ok(fcc_bus_signal_set(FCC_MSG_MSL_ELEV_CMD, code, &d, 0, -32768));
    fcc_assert_ok(fcc_bus_signal_get(FCC_MSG_MSL_ELEV_CMD, code, &d, &real, &integer));
    assert_int_equal(integer, -32768);
    assert_true(real == FCC_R(0.0));
    assert_int_equal(d.msl_elev_cmd.da_code, -32768);
    /* degraded (bool): 0 and 1 only */
    assert_int_equal(fcc_bus_signal_set(FCC_MSG_MSL_ELEV_CMD, 0u, &d, 0, 2), FCC_ERR_RANGE);
    fcc_assert_ok(fcc_bus_signal_set(FCC_MSG_MSL_ELEV_CMD, 0u, &d, 0, 1));
    assert_true(d.msl_elev_cmd.degraded);
    /* a real signal: the state estimate's q_hat (signal 0) */
    fcc_assert_ok(fcc_bus_signal_set(FCC_MSG_MSL_STATE_EST, 0u, &d, FCC_R(0.25), 0));
    fcc_assert_ok(fcc_bus_signal_get(FCC_MSG_MSL_STATE_EST, 0u, &d, &real, &integer));
    fcc_assert_close(real, 0.25, 0, 0);
    assert_int_equal(integer, 0);
}

static void node_refuses_each_argument(void **state)
{
    (void)state;
    const uint64_t beyond = (FCC_MSG_COUNT >= 64) ? 0u : (1ull << FCC_MSG_COUNT);
    if (beyond != 0u) { /* a message table of 64 leaves no bit beyond it */
        assert_int_equal(fcc_bus_init_masks(&g_bus, beyond, 0u), FCC_ERR_ARG);
        assert_int_equal(fcc_bus_init_masks(&g_bus, 0u, beyond), FCC_ERR_ARG);
    }
    assert_int_equal(fcc_bus_init_masks(NULL, 0u, 0u), FCC_ERR_ARG);
    fcc_assert_ok(fcc_bus_init(&g_bus, FCC_BUS_NODE_FCC));
    fcc_can_frame_t frame;
    memset(&frame, 0, sizeof frame);
    fcc_bus_rx_msg_t rx;
    assert_int_equal(fcc_bus_receive(NULL, &frame, &rx), FCC_ERR_ARG);
    assert_int_equal(fcc_bus_receive(&g_bus, NULL, &rx), FCC_ERR_ARG);
    assert_int_equal(fcc_bus_receive(&g_bus, &frame, NULL), FCC_ERR_ARG);
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    assert_int_equal(fcc_bus_encode(NULL, FCC_MSG_MSL_STATE_EST, &d, &frame), FCC_ERR_ARG);
    assert_int_equal(fcc_bus_encode(&g_bus, FCC_MSG_MSL_STATE_EST, &d, NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_bus_encode(&g_bus, FCC_MSG_COUNT, &d, &frame), FCC_ERR_ARG);
    fcc_bus_counters_t c;
    assert_int_equal(fcc_bus_get_counters(NULL, &c), FCC_ERR_ARG);
    assert_int_equal(fcc_bus_get_counters(&g_bus, NULL), FCC_ERR_ARG);
    fcc_assert_ok(fcc_bus_get_counters(&g_bus, &c));
    assert_int_equal(c.tx_refused, 1u); /* the unknown message; argument errors are not counted */
    /* the end of a period concerns only E2E-protected messages this node consumes */
    assert_false(fcc_bus_end_period(NULL, FCC_MSG_SIM_TICK));
    assert_false(fcc_bus_end_period(&g_bus, FCC_MSG_COUNT));
    assert_false(fcc_bus_end_period(&g_bus, FCC_MSG_MSL_STATE_EST)); /* produced, not consumed */
    assert_int_equal(fcc_bus_desc(FCC_MSG_RIG_PING)->data_id, 0u);
    assert_false(fcc_bus_end_period(&g_bus, FCC_MSG_RIG_PING)); /* consumed, not protected */
}

static void names_of_every_verdict_and_state(void **state)
{
    (void)state;
    assert_string_equal(fcc_bus_verdict_str(FCC_BUS_PASS), "pass");
    assert_string_equal(fcc_bus_verdict_str(FCC_BUS_UNKNOWN_ID), "unknown id");
    assert_string_equal(fcc_bus_verdict_str(FCC_BUS_WRONG_DLC), "wrong DLC");
    assert_string_equal(fcc_bus_verdict_str(FCC_BUS_E2E), "E2E check failed");
    assert_string_equal(fcc_bus_verdict_str(FCC_BUS_OUT_OF_RANGE), "value out of range");
    assert_string_equal(fcc_bus_verdict_str((fcc_bus_verdict_t)99), "unknown verdict");
    assert_string_equal(fcc_sensor_state_str(FCC_SENSOR_OK), "OK");
    assert_string_equal(fcc_sensor_state_str(FCC_SENSOR_HELD), "HELD");
    assert_string_equal(fcc_sensor_state_str(FCC_SENSOR_STALE), "STALE");
    assert_string_equal(fcc_sensor_state_str(FCC_SENSOR_REJECTED), "REJECTED");
    assert_string_equal(fcc_sensor_state_str(FCC_SENSOR_MISALIGNED), "MISALIGNED");
    assert_string_equal(fcc_sensor_state_str(FCC_SENSOR_N_STATES), "UNKNOWN");
}

static void sensor_edges(void **state)
{
    (void)state;
    fcc_sensor_init(NULL, 1u);  /* no sensor: no fault */
    fcc_sensor_reset(NULL);
    fcc_sensor_reject(NULL);
    fcc_sensor_t s;
    fcc_sensor_init(&s, 0x123u);
    fcc_sensor_sample_t sample;
    assert_int_equal(fcc_sensor_close(NULL, false, 0u, 3u, &sample), FCC_SENSOR_STALE);
    assert_int_equal(fcc_sensor_close(&s, false, 0u, 3u, NULL), FCC_SENSOR_STALE);
    assert_int_equal(fcc_sensor_offer(NULL, FCC_R(1.0), 0u, 0u), FCC_ERR_ARG);
    /* the reject counter stops at its maximum instead of wrapping to "nothing rejected" */
    for (int i = 0; i < 300; ++i) {
        fcc_sensor_reject(&s);
    }
    assert_int_equal(s.n_rejected, UINT8_MAX);
    assert_int_equal(fcc_sensor_close(&s, false, 0u, 3u, &sample), FCC_SENSOR_REJECTED);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(codec_refuses_each_argument),
        cmocka_unit_test(signals_by_index),
        cmocka_unit_test(node_refuses_each_argument),
        cmocka_unit_test(names_of_every_verdict_and_state),
        cmocka_unit_test(sensor_edges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
