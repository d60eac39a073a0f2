/*
 * test_bus.c -- the frame layer (fcc_bus.h) as the FCC and the simulator use
 * it: node masks from the DBC, encode refusals (NaN, Inf, out of range, not
 * ours) that leave the alive counter alone, saturating encode, a full
 * FCC -> SIM round trip with E2E classes, NO_NEW_DATA and the counters.
 */
#include "fcc_test.h"

#include <string.h>

#include "fcc_bus.h"

#define BIT(m) ((uint64_t)1u << (uint32_t)(m))

/* Both ends of the link as the DBC makes them: the FCC and the simulator. */
static void open_link(fcc_bus_t *fcc, fcc_bus_t *sim)
{
    fcc_assert_ok(fcc_bus_init(fcc, FCC_BUS_NODE_FCC));
    fcc_assert_ok(fcc_bus_init(sim, FCC_BUS_NODE_SIM));
}

static void test_node_masks_follow_the_dbc(void **state)
{
    (void)state;
    fcc_bus_t fcc;
    fcc_assert_ok(fcc_bus_init(&fcc, FCC_BUS_NODE_FCC));
    assert_true(fcc.consumes & BIT(FCC_MSG_SIM_TICK));
    assert_true(fcc.consumes & BIT(FCC_MSG_CDRW_AOA));
    assert_true(fcc.consumes & BIT(FCC_MSG_MSL_ACCELEROMETER));
    assert_true(fcc.consumes & BIT(FCC_MSG_SIM_EVENT));
    assert_false(fcc.consumes & BIT(FCC_MSG_FCC_ACK));
    assert_true(fcc.produces & BIT(FCC_MSG_FCC_ACK));
    assert_true(fcc.produces & BIT(FCC_MSG_MSL_ELEV_CMD));
    assert_true(fcc.produces & BIT(FCC_MSG_SID_KF_MODEL_B));
    assert_false(fcc.produces & BIT(FCC_MSG_SIM_TICK));
    assert_int_equal(fcc_bus_init(&fcc, FCC_BUS_N_NODES), FCC_ERR_ARG);
    assert_int_equal(fcc_bus_init_masks(&fcc, BIT(FCC_MSG_COUNT), 0u), FCC_ERR_ARG);
    assert_int_equal(fcc_bus_init_masks(NULL, 0u, 0u), FCC_ERR_ARG);
}

static void test_encode_refusals_keep_the_counter(void **state)
{
    (void)state;
    fcc_bus_t fcc;
    fcc_assert_ok(fcc_bus_init(&fcc, FCC_BUS_NODE_FCC));
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    fcc_can_frame_t fr;
    d.sid_azkf_state.alpha_hat = FCC_R(0.1);
    d.sid_azkf_state.q_hat = (fcc_real_t)NAN;
    assert_int_equal(fcc_bus_encode(&fcc, FCC_MSG_SID_AZKF_STATE, &d, &fr), FCC_ERR_NOT_FINITE);
    d.sid_azkf_state.q_hat = (fcc_real_t)INFINITY;
    assert_int_equal(fcc_bus_encode(&fcc, FCC_MSG_SID_AZKF_STATE, &d, &fr), FCC_ERR_NOT_FINITE);
    assert_int_equal(fcc_bus_encode_sat(&fcc, FCC_MSG_SID_AZKF_STATE, &d, &fr), FCC_ERR_NOT_FINITE);
    d.sid_azkf_state.q_hat = FCC_R(5.3); /* max 5.24287 */
    assert_int_equal(fcc_bus_encode(&fcc, FCC_MSG_SID_AZKF_STATE, &d, &fr), FCC_ERR_RANGE);
    d.sid_azkf_state.q_hat = FCC_R(1e30); /* overflows the raw type, still just out of range */
    assert_int_equal(fcc_bus_encode(&fcc, FCC_MSG_SID_AZKF_STATE, &d, &fr), FCC_ERR_RANGE);
    d.sid_azkf_state.q_hat = FCC_R(0.0);
    d.sid_azkf_state.step = 4096u; /* 12-bit field */
    assert_int_equal(fcc_bus_encode(&fcc, FCC_MSG_SID_AZKF_STATE, &d, &fr), FCC_ERR_RANGE);

    memset(&d, 0, sizeof d);
    d.msl_elev_cmd.da_bits = 0u; /* DBC range 1..16 */
    assert_int_equal(fcc_bus_encode(&fcc, FCC_MSG_MSL_ELEV_CMD, &d, &fr), FCC_ERR_RANGE);
    d.msl_elev_cmd.da_bits = 17u;
    assert_int_equal(fcc_bus_encode(&fcc, FCC_MSG_MSL_ELEV_CMD, &d, &fr), FCC_ERR_RANGE);
    /* not a message the FCC sends */
    assert_int_equal(fcc_bus_encode(&fcc, FCC_MSG_SIM_TICK, &d, &fr), FCC_ERR_ARG);
    assert_int_equal(fcc_bus_encode(&fcc, FCC_MSG_COUNT, &d, &fr), FCC_ERR_ARG);
    assert_int_equal(fcc_bus_encode(&fcc, FCC_MSG_FCC_ACK, NULL, &fr), FCC_ERR_ARG);

    fcc_bus_counters_t c;
    fcc_assert_ok(fcc_bus_get_counters(&fcc, &c));
    assert_int_equal(c.tx_refused, 11u);

    d.msl_elev_cmd.da_bits = 8u;
    d.msl_elev_cmd.da_code = -128;
    fcc_assert_ok(fcc_bus_encode(&fcc, FCC_MSG_MSL_ELEV_CMD, &d, &fr));
    assert_int_equal(fr.id, FCC_MSG_MSL_ELEV_CMD_ID);
    assert_int_equal(fr.dlc, 8);
    assert_int_equal(fr.data[1] & 0x0Fu, 0u); /* refusals did not use counter values */
    fcc_assert_ok(fcc_bus_encode(&fcc, FCC_MSG_MSL_ELEV_CMD, &d, &fr));
    assert_int_equal(fr.data[1] & 0x0Fu, 1u);
}

static void test_saturating_encode(void **state)
{
    (void)state;
    fcc_bus_t fcc, sim;
    open_link(&fcc, &sim);
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    d.sid_kf_bounds.alpha_lo = FCC_R(-7.0);
    d.sid_kf_bounds.alpha_hi = FCC_R(7.0);
    d.sid_kf_bounds.q_lo = FCC_R(-0.5);
    d.sid_kf_bounds.q_hi = FCC_R(0.5);
    fcc_can_frame_t fr;
    fcc_assert_ok(fcc_bus_encode_sat(&fcc, FCC_MSG_SID_KF_BOUNDS, &d, &fr));
    fcc_bus_rx_msg_t m;
    fcc_assert_ok(fcc_bus_receive(&sim, &fr, &m));
    fcc_assert_close(m.data.sid_kf_bounds.alpha_lo, -3.2768, 0.0, 1e-6);
    fcc_assert_close(m.data.sid_kf_bounds.alpha_hi, 3.2767, 0.0, 1e-6);
    fcc_assert_close(m.data.sid_kf_bounds.q_hi, 0.5, 0.0, 1e-6);
    fcc_bus_counters_t c;
    fcc_assert_ok(fcc_bus_get_counters(&fcc, &c));
    assert_int_equal(c.tx_saturated, 1u);
    assert_int_equal(c.tx_refused, 0u);
}

/* FCC sends commands, the simulator receives them: every E2E class and verdict. */
static void test_round_trip_and_e2e_classes(void **state)
{
    (void)state;
    fcc_bus_t fcc, sim;
    open_link(&fcc, &sim);
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    d.msl_elev_cmd.step = 41u;
    d.msl_elev_cmd.da_code = -77;
    d.msl_elev_cmd.da_bits = 8u;
    d.msl_elev_cmd.saturated = true;
    fcc_can_frame_t f[6];
    for (unsigned int i = 0u; i < 6u; ++i) {
        fcc_assert_ok(fcc_bus_encode(&fcc, FCC_MSG_MSL_ELEV_CMD, &d, &f[i]));
    }
    fcc_bus_rx_msg_t m;
    fcc_assert_ok(fcc_bus_receive(&sim, &f[0], &m));
    assert_int_equal(m.msg, FCC_MSG_MSL_ELEV_CMD);
    assert_int_equal(m.e2e, FCC_E2E_OK);
    assert_int_equal(m.data.msl_elev_cmd.step, 41u);
    assert_int_equal(m.data.msl_elev_cmd.da_code, -77);
    assert_true(m.data.msl_elev_cmd.saturated);
    assert_false(m.data.msl_elev_cmd.degraded);
    assert_int_equal(fcc_bus_receive(&sim, &f[0], &m), FCC_ERR_FORMAT); /* replay */
    assert_int_equal(m.verdict, FCC_BUS_E2E);
    assert_int_equal(m.e2e, FCC_E2E_REPEATED);
    fcc_assert_ok(fcc_bus_receive(&sim, &f[2], &m)); /* f[1] lost */
    assert_int_equal(m.e2e, FCC_E2E_OK_SOME_LOST);
    assert_int_equal(fcc_bus_receive(&sim, &f[1], &m), FCC_ERR_FORMAT); /* late: went back */
    assert_int_equal(m.e2e, FCC_E2E_WRONG_SEQUENCE);
    fcc_assert_ok(fcc_bus_receive(&sim, &f[2], &m)); /* resynchronised on f[1] */
    assert_int_equal(m.e2e, FCC_E2E_OK);
    f[3].data[4] ^= 0x01u;
    assert_int_equal(fcc_bus_receive(&sim, &f[3], &m), FCC_ERR_FORMAT);
    assert_int_equal(m.e2e, FCC_E2E_ERROR);
    f[4].dlc = 6u;
    assert_int_equal(fcc_bus_receive(&sim, &f[4], &m), FCC_ERR_FORMAT);
    assert_int_equal(m.verdict, FCC_BUS_WRONG_DLC);
    fcc_assert_ok(fcc_bus_receive(&sim, &f[5], &m)); /* counter +3 from f[2] */
    assert_int_equal(m.e2e, FCC_E2E_OK_SOME_LOST);
    /* the FCC does not consume its own command */
    assert_int_equal(fcc_bus_receive(&fcc, &f[5], &m), FCC_ERR_FORMAT);
    assert_int_equal(m.verdict, FCC_BUS_UNKNOWN_ID);

    fcc_bus_counters_t c;
    fcc_assert_ok(fcc_bus_get_counters(&sim, &c));
    assert_int_equal(c.e2e[FCC_E2E_OK], 2u);
    assert_int_equal(c.e2e[FCC_E2E_REPEATED], 1u);
    assert_int_equal(c.e2e[FCC_E2E_OK_SOME_LOST], 2u);
    assert_int_equal(c.e2e[FCC_E2E_WRONG_SEQUENCE], 1u);
    assert_int_equal(c.e2e[FCC_E2E_ERROR], 1u);
    assert_int_equal(c.wrong_dlc, 1u);
    fcc_assert_ok(fcc_bus_get_counters(&fcc, &c));
    assert_int_equal(c.unknown_id, 1u);
}

static void test_out_of_range_is_rejected_not_clamped(void **state)
{
    (void)state;
    fcc_bus_t fcc;
    fcc_assert_ok(fcc_bus_init(&fcc, FCC_BUS_NODE_FCC));
    /* alpha raw 1570801 > 1.5708 rad: E2E fine, value not passed on */
    fcc_can_frame_t fr = {FCC_MSG_CDRW_AOA_ID, 8u, {0, 0, 5, 0, 0xF1, 0xF7, 0x17, 0x00}, 0u};
    fcc_assert_ok(fcc_e2e_protect(0x1050u, 0u, fr.data));
    fcc_bus_rx_msg_t m;
    m.data.cdrw_aoa.alpha = FCC_R(0.25);
    assert_int_equal(fcc_bus_receive(&fcc, &fr, &m), FCC_ERR_RANGE);
    assert_int_equal(m.verdict, FCC_BUS_OUT_OF_RANGE);
    assert_int_equal(m.e2e, FCC_E2E_OK);
    fcc_bus_counters_t c;
    fcc_assert_ok(fcc_bus_get_counters(&fcc, &c));
    assert_int_equal(c.out_of_range, 1u);
    /* one LSB less is the maximum: passed on */
    fr.data[4] = 0xF0u;
    fcc_assert_ok(fcc_e2e_protect(0x1050u, 1u, fr.data));
    fcc_assert_ok(fcc_bus_receive(&fcc, &fr, &m));
    fcc_assert_close(m.data.cdrw_aoa.alpha, 1.5708, 0.0, FCC_TEST_TOL(1e-12, 2e-7));
    assert_int_equal(m.data.cdrw_aoa.step, 5u);
}

static void test_no_new_data_per_period(void **state)
{
    (void)state;
    fcc_bus_t fcc, sim;
    fcc_assert_ok(fcc_bus_init(&fcc, FCC_BUS_NODE_FCC));
    fcc_assert_ok(fcc_bus_init_masks(&sim, 0u, BIT(FCC_MSG_CDRW_AOA) | BIT(FCC_MSG_CDRW_PITCH_RATE)));
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    fcc_can_frame_t fr;
    fcc_bus_rx_msg_t m;
    for (unsigned int step = 0u; step < 10u; ++step) {
        d.cdrw_aoa.step = (uint16_t)step;
        d.cdrw_aoa.alpha = FCC_R(0.15);
        fcc_assert_ok(fcc_bus_encode(&sim, FCC_MSG_CDRW_AOA, &d, &fr));
        if (step % 3u != 0u) { /* every third AoA frame is lost */
            fcc_assert_ok(fcc_bus_receive(&fcc, &fr, &m));
        }
        assert_int_equal(fcc_bus_end_period(&fcc, FCC_MSG_CDRW_AOA), step % 3u == 0u);
        assert_true(fcc_bus_end_period(&fcc, FCC_MSG_CDRW_PITCH_RATE)); /* gyro silent */
    }
    fcc_bus_counters_t c;
    fcc_assert_ok(fcc_bus_get_counters(&fcc, &c));
    assert_int_equal(c.e2e[FCC_E2E_NO_NEW_DATA], 4u + 10u);
    assert_int_equal(c.stale_now, 2u); /* step 9: both stale */
    assert_int_equal(c.e2e[FCC_E2E_OK] + c.e2e[FCC_E2E_OK_SOME_LOST], 6u);
    /* not consumed / not protected: no period bookkeeping */
    assert_false(fcc_bus_end_period(&fcc, FCC_MSG_FCC_ACK));
    assert_false(fcc_bus_end_period(&fcc, FCC_MSG_RIG_PING));
    assert_false(fcc_bus_end_period(NULL, FCC_MSG_CDRW_AOA));
}

static void test_signal_access_and_strings(void **state)
{
    (void)state;
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    fcc_assert_ok(fcc_bus_signal_set(FCC_MSG_SIM_TICK, 1u, &d, FCC_R(0.0), 4000000000LL));
    assert_int_equal(d.sim_tick.step, 4000000000u);
    assert_int_equal(fcc_bus_signal_set(FCC_MSG_SIM_TICK, 0u, &d, FCC_R(0.0), 3), FCC_ERR_RANGE);
    assert_int_equal(fcc_bus_signal_set(FCC_MSG_SIM_TICK, 9u, &d, FCC_R(0.0), 0), FCC_ERR_ARG);
    fcc_real_t r;
    int64_t i;
    fcc_assert_ok(fcc_bus_signal_get(FCC_MSG_SIM_TICK, 1u, &d, &r, &i));
    assert_true(i == 4000000000LL);
    assert_int_equal(fcc_bus_signal_get(FCC_MSG_COUNT, 0u, &d, &r, &i), FCC_ERR_ARG);
    assert_string_equal(fcc_bus_verdict_str(FCC_BUS_OUT_OF_RANGE), "value out of range");
    fcc_bus_rx_msg_t m;
    assert_int_equal(fcc_bus_receive(NULL, NULL, &m), FCC_ERR_ARG);
    uint8_t zero[8] = {0};
    assert_int_equal(fcc_bus_decode(FCC_MSG_COUNT, zero, &d), FCC_ERR_ARG);
    assert_int_equal(fcc_bus_pack(FCC_MSG_SIM_TICK, NULL, zero), FCC_ERR_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_node_masks_follow_the_dbc),
        cmocka_unit_test(test_encode_refusals_keep_the_counter),
        cmocka_unit_test(test_saturating_encode),
        cmocka_unit_test(test_round_trip_and_e2e_classes),
        cmocka_unit_test(test_out_of_range_is_rejected_not_clamped),
        cmocka_unit_test(test_no_new_data_per_period),
        cmocka_unit_test(test_signal_access_and_strings),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
