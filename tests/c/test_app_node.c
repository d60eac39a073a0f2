/*
 * test_app_node.c -- the flight-computer node (firmware/app/fcc_node.h)
 * driven with frames in memory: lockstep protocol, outputs against the
 * firmware maths run directly, sensor health, run-time commands, heartbeat,
 * garbage.  The node is the real one; only the wires are replaced
 * (test_app_port.h).
 */
#include "fcc_test.h"

#include "fcc_lqg.h"
#include "fcc_sid.h"
#include "test_app_port.h"

static fcc_node_t g_node;
static mem_port_t g_mem;
static fcc_sid_t g_ref_sid[3];
static bool g_batched; /* the port has send_many: the node queues and flushes */
static fcc_secoc_t g_rx;  /* the simulator's receiver of fcc's authenticated outputs */

static void run(void);

/* A node with the test key, in FLIGHT (an authenticated SIM_CONTROL FLIGHT). */
static void start(const fcc_node_config_t *cfg)
{
    fcc_port_t port;
    mem_init(&g_mem, &port);
    if (g_batched) {
        mem_batched(&port);
    }
    fcc_node_config_t c;
    if (cfg != NULL) {
        c = *cfg;
    } else {
        fcc_assert_ok(fcc_node_config_default(&c));
    }
    mem_secure(&c);
    fcc_assert_ok(fcc_node_init(&g_node, &c, &port));
    fcc_assert_ok(fcc_secoc_init(&g_rx, c.security.key, c.security.trip));
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_FLIGHT, 0.0, 0u);
    run();
    assert_int_equal(fcc_node_op_mode(&g_node), FCC_OP_FLIGHT);
}

static void run(void)
{
    uint32_t n = 0u;
    fcc_assert_ok(fcc_node_poll(&g_node, 100000u, &n));
    assert_int_equal(g_node.txq.n, 0u); /* nothing waits in the queue between calls */
}

/* A smooth pull-up: alpha, q, de at step k (rad, rad/s, rad). */
static void flight(uint32_t k, double *alpha, double *q, double *de)
{
    const double t = 0.02 * (double)k;
    *de = -0.05 - 0.08 * sin(1.3 * t);
    *alpha = 0.16 + 0.1 * sin(0.9 * t) + 0.002 * sin(17.0 * t);
    *q = 0.09 * cos(0.9 * t) + 0.01 * sin(11.0 * t);
}

/* Sample k of flight() on the bus: the three CDRW sensor frames (an event
 * for step k goes after them), then push_flight_step() adds the tick. */
static void push_flight_sample(uint32_t k)
{
    double a, q, de;
    flight(k, &a, &q, &de);
    mem_push_cdrw(&g_mem, k, a, q, de);
}

static void push_flight_step(uint32_t k)
{
    push_flight_sample(k);
    mem_push_tick(&g_mem, FCC_APP_CDRW, k);
}

/* The value the node sees after the frame layer (DBC resolution). */
static double quantised(fcc_msg_t msg, double v)
{
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    uint8_t raw[8];
    if (msg == FCC_MSG_CDRW_AOA) {
        d.cdrw_aoa.alpha = (fcc_real_t)v;
    } else if (msg == FCC_MSG_CDRW_PITCH_RATE) {
        d.cdrw_pitch_rate.q = (fcc_real_t)v;
    } else if (msg == FCC_MSG_CDRW_ELEVATOR) {
        d.cdrw_elevator.delta_e = (fcc_real_t)v;
    } else if (msg == FCC_MSG_MSL_RATE_GYRO) {
        d.msl_rate_gyro.q_g = (fcc_real_t)v;
    } else {
        d.msl_accelerometer.n_a = (fcc_real_t)v;
    }
    fcc_assert_ok(fcc_bus_pack(msg, &d, raw));
    fcc_assert_ok(fcc_bus_decode(msg, raw, &d));
    switch (msg) {
    case FCC_MSG_CDRW_AOA: return (double)d.cdrw_aoa.alpha;
    case FCC_MSG_CDRW_PITCH_RATE: return (double)d.cdrw_pitch_rate.q;
    case FCC_MSG_CDRW_ELEVATOR: return (double)d.cdrw_elevator.delta_e;
    case FCC_MSG_MSL_RATE_GYRO: return (double)d.msl_rate_gyro.q_g;
    default: return (double)d.msl_accelerometer.n_a;
    }
}

/* The simulator's side of fcc's authenticated outputs: the frames tx[first ..
 * first + n_pdus) and their authenticator right after them verify under the test
 * key and trip at the next message counter (g_rx keeps the counters). */

static void assert_authenticated(size_t first, fcc_msg_t auth_msg)
{
    uint32_t a;
    assert_true(fcc_secoc_auth_index(auth_msg, &a));
    const fcc_secoc_desc_t *d = &fcc_secoc_table[a];
    uint8_t pdu[FCC_SECOC_PDU_BYTES];
    for (uint32_t i = 0u; i < d->n_pdus; ++i) {
        assert_int_equal(g_mem.tx[first + i].id, fcc_bus_msg_table[d->pdus[i]].id);
        memcpy(&pdu[8u * i], g_mem.tx[first + i].data, 8u);
    }
    const fcc_can_frame_t *auth = &g_mem.tx[first + d->n_pdus];
    assert_int_equal(auth->id, fcc_bus_msg_table[auth_msg].id);
    uint32_t match = 1u;
    assert_int_equal(fcc_secoc_verify_pdus(&g_rx, a, auth->data, pdu, 1u, 8u * d->n_pdus, &match),
                     FCC_SECOC_VERIFIED);
    assert_int_equal(match, 0u);
    /* one bit of any frame changed: the authenticator no longer verifies (a fresh receiver) */
    fcc_secoc_t other;
    fcc_assert_ok(fcc_secoc_init(&other, k_mem_key, MEM_TRIP));
    other.chan[a] = g_rx.chan[a];
    other.chan[a].counter -= 1u;
    pdu[8u * (d->n_pdus - 1u) + 3u] ^= 0x10u;
    assert_int_equal(fcc_secoc_verify_pdus(&other, a, auth->data, pdu, 1u, 8u * d->n_pdus, &match),
                     FCC_SECOC_MAC_FAILED);
}

/* ---- identification ------------------------------------------------------------ */

static void test_cdrw_steps_match_the_sid_loops(void **state)
{
    (void)state;
    /* flight() is not a CDRW flight (its elevator moves 4.6 deg for 0.09 rad/s
     * of pitch rate): give the loops a prior of its scale instead of the CDRW
     * wind-tunnel model, whose refits here would hit the rho guard. */
    fcc_node_config_t cfg;
    fcc_assert_ok(fcc_node_config_default(&cfg));
    const fcc_sid_model_t prior = {{FCC_R(0.97), FCC_R(0.02), FCC_R(-0.4), FCC_R(0.94)},
                                   {FCC_R(-0.004), FCC_R(-0.6)}, {0, 0}};
    cfg.sid.base.mls.prior = prior;
    start(&cfg);
    for (int f = 0; f < 3; ++f) {
        fcc_sid_config_t c = g_node.cfg.sid.base;
        c.filter = (fcc_sid_filter_t)f;
        fcc_assert_ok(fcc_sid_init(&g_ref_sid[f], &c));
    }
    static const uint32_t order[12] = {0x110, 0x111, 0x112, 0x113, 0x120, 0x121,
                                       0x122, 0x123, 0x130, 0x131, 0x132, 0x133};
    for (uint32_t k = 0u; k < 150u; ++k) {
        double a, q, de;
        flight(k, &a, &q, &de);
        const size_t first = g_mem.tx_n;
        push_flight_step(k);
        run();
        assert_int_equal(g_mem.tx_n - first, 14u); /* 12 outputs, their authenticator, ACK */
        for (unsigned int i = 0u; i < 12u; ++i) {
            assert_int_equal(g_mem.tx[first + i].id, order[i]);
        }
        assert_authenticated(first, FCC_MSG_SID_OUT_AUTH);
        const fcc_msg_data_t ack = mem_decode_tx(&g_mem, (long)(first + 13u));
        assert_int_equal(g_mem.tx[first + 13u].id, FCC_MSG_FCC_ACK_ID);
        assert_int_equal(ack.fcc_ack.app, FCC_APP_CDRW);
        assert_int_equal(ack.fcc_ack.step, k);
        assert_false(ack.fcc_ack.degraded);
        /* the reference: the three loops fed the same (quantised) sample */
        fcc_sid_out_t ref[3];
        for (int f = 0; f < 3; ++f) {
            fcc_sid_step(&g_ref_sid[f], (fcc_real_t)quantised(FCC_MSG_CDRW_AOA, a),
                         (fcc_real_t)quantised(FCC_MSG_CDRW_PITCH_RATE, q),
                         (fcc_real_t)quantised(FCC_MSG_CDRW_ELEVATOR, de), false, true, &ref[f]);
        }
        static const int filt[3] = {FCC_SID_AZKF, FCC_SID_ZKF, FCC_SID_KF};
        for (int i = 0; i < 3; ++i) {
            const fcc_sid_out_t *r = &ref[filt[i]];
            const fcc_msg_data_t st = mem_decode_tx(&g_mem, (long)(first + 4u * (unsigned)i));
            const fcc_msg_data_t bo = mem_decode_tx(&g_mem, (long)(first + 4u * (unsigned)i + 1u));
            const fcc_msg_data_t ma = mem_decode_tx(&g_mem, (long)(first + 4u * (unsigned)i + 2u));
            const fcc_msg_data_t mb = mem_decode_tx(&g_mem, (long)(first + 4u * (unsigned)i + 3u));
            fcc_assert_close(st.sid_azkf_state.alpha_hat, r->x_hat[0], 0.0, 0.6e-5);
            fcc_assert_close(st.sid_azkf_state.q_hat, r->x_hat[1], 0.0, 0.6e-5);
            assert_int_equal(st.sid_azkf_state.order, r->order);
            assert_int_equal(st.sid_azkf_state.step, k & 0xFFFu);
            fcc_assert_close(bo.sid_azkf_bounds.alpha_lo, r->lo[0], 0.0, 0.6e-4);
            fcc_assert_close(bo.sid_azkf_bounds.q_hi, r->hi[1], 0.0, 0.6e-4);
            fcc_assert_close(ma.sid_azkf_model_a.a21, r->model.a[2], 0.0, 0.6e-4);
            fcc_assert_close(mb.sid_azkf_model_b.b2, r->model.b[1], 0.0, 0.6e-4);
            fcc_assert_close(mb.sid_azkf_model_b.rho, r->rho, 0.0, 0.6e-4);
            fcc_assert_close(mb.sid_azkf_model_b.gain_norm, r->gain_norm, 0.0, 0.6e-4);
        }
    }
    assert_int_equal(g_node.app[FCC_APP_CDRW].steps, 150u);
    assert_int_equal(g_node.app[FCC_APP_CDRW].degraded_steps, 0u);
    assert_false(g_node.sid.loop[FCC_SID_AZKF].last.model_is_prior); /* the MLS has learnt */
}

/* ---- autopilot ----------------------------------------------------------------- */

static double gyro_at(uint32_t k)
{
    return 0.1 * cos(0.7 * (double)k) + 0.3 * sin(2.1 * (double)k);
}

static double accel_at(uint32_t k)
{
    return -3.0 + 40.0 * sin(0.45 * (double)k);
}

static void ref_design(double period, uint8_t bits, fcc_lqg_ctrl_t *ctrl, const fcc_real_t *x0)
{
    static fcc_lqg_ws_t ws;
    static fcc_lqg_design_t d;
    fcc_lqg_plant_t plant;
    fcc_assert_ok(fcc_lqg_plant_default(&plant));
    fcc_assert_ok(fcc_lqg_design(&plant, (fcc_real_t)period, FCC_LQG_SOLVER_HAMILTONIAN, &d, &ws));
    fcc_assert_ok(fcc_lqg_ctrl_init(ctrl, &d, bits, x0));
}

/* A new design between flights: GROUND, the request, FLIGHT again. */
static void on_ground(double period, uint8_t bits)
{
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_GROUND, 0.0, 0u);
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_NONE, period, bits);
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_FLIGHT, 0.0, 0u);
}

/* One missile step through the node; returns the index of its command frame. */
static long msl_step(uint32_t k, bool gyro, bool accel)
{
    const size_t first = g_mem.tx_n;
    if (gyro) {
        mem_push_gyro(&g_mem, k, gyro_at(k));
    }
    if (accel) {
        mem_push_accel(&g_mem, k, accel_at(k));
    }
    mem_push_tick(&g_mem, FCC_APP_MSL, k);
    run();
    assert_int_equal(g_mem.tx_n - first, 4u);
    assert_int_equal(g_mem.tx[first].id, FCC_MSG_MSL_ELEV_CMD_ID);
    assert_int_equal(g_mem.tx[first + 1u].id, FCC_MSG_MSL_STATE_EST_ID);
    assert_authenticated(first, FCC_MSG_MSL_ELEV_CMD_AUTH); /* command + estimate */
    assert_int_equal(g_mem.tx[first + 3u].id, FCC_MSG_FCC_ACK_ID);
    return (long)first;
}

static void test_missile_commands_match_the_lqg(void **state)
{
    (void)state;
    start(NULL);
    fcc_lqg_ctrl_t ref;
    ref_design(0.05, 8u, &ref, NULL);
    for (uint32_t k = 0u; k < 100u; ++k) {
        const long i = msl_step(k, true, true);
        const fcc_real_t y[2] = {(fcc_real_t)quantised(FCC_MSG_MSL_RATE_GYRO, gyro_at(k)),
                                 (fcc_real_t)quantised(FCC_MSG_MSL_ACCELEROMETER, accel_at(k))};
        fcc_lqg_output_t out;
        fcc_assert_ok(fcc_lqg_ctrl_step(&ref, y, &out));
        const fcc_msg_data_t cmd = mem_decode_tx(&g_mem, i);
        const fcc_msg_data_t est = mem_decode_tx(&g_mem, i + 1);
        assert_int_equal(cmd.msl_elev_cmd.da_code, out.code);
        assert_int_equal(cmd.msl_elev_cmd.da_bits, 8u);
        assert_int_equal(cmd.msl_elev_cmd.step, k);
        assert_int_equal(cmd.msl_elev_cmd.saturated, out.saturated);
        assert_false(cmd.msl_elev_cmd.degraded);
        assert_true(cmd.msl_elev_cmd.da_code >= -128 && cmd.msl_elev_cmd.da_code <= 127);
        fcc_assert_close(est.msl_state_est.q_hat, out.x_hat[0], 0.0, 0.6e-5);
        fcc_assert_close(est.msl_state_est.alpha_t_hat, out.x_hat[1], 0.0, 0.6e-5);
        assert_int_equal(est.msl_state_est.step, k & 0xFFu);
    }
    assert_int_equal(g_node.msl.ctrl.updates, 100u);
}

static void test_missing_sensor_held_then_stale_then_recovered(void **state)
{
    (void)state;
    start(NULL); /* stale limit 1 */
    fcc_lqg_ctrl_t ref;
    ref_design(0.05, 8u, &ref, NULL);
    long i = msl_step(0u, true, true);
    assert_false(mem_decode_tx(&g_mem, i).msl_elev_cmd.degraded);
    i = msl_step(1u, false, true); /* one gyro frame lost: held */
    assert_false(mem_decode_tx(&g_mem, i).msl_elev_cmd.degraded);
    assert_int_equal(g_node.msl.last.input_state[FCC_APP_MSL_IN_GYRO], FCC_SENSOR_HELD);
    i = msl_step(2u, false, true); /* two in a row: stale, prediction only */
    const fcc_msg_data_t cmd = mem_decode_tx(&g_mem, i);
    assert_true(cmd.msl_elev_cmd.degraded);
    assert_false(g_node.msl.last.measured);
    assert_int_equal(g_node.msl.last.input_state[FCC_APP_MSL_IN_GYRO], FCC_SENSOR_STALE);
    assert_int_equal(g_mem.ev_count[FCC_EV_SENSOR_STALE], 1u);
    assert_true(mem_decode_tx(&g_mem, i + 3).fcc_ack.degraded);
    i = msl_step(3u, true, true);
    assert_false(mem_decode_tx(&g_mem, i).msl_elev_cmd.degraded);
    assert_int_equal(g_mem.ev_count[FCC_EV_SENSOR_RECOVERED], 1u);
    fcc_bus_counters_t bc;
    fcc_assert_ok(fcc_bus_get_counters(&g_node.bus, &bc));
    assert_int_equal(bc.e2e[FCC_E2E_NO_NEW_DATA], 2u);
    assert_int_equal(g_node.app[FCC_APP_MSL].degraded_steps, 1u);
    /* the same steps by hand: update, update (held gyro), predict, update */
    const double g0 = quantised(FCC_MSG_MSL_RATE_GYRO, gyro_at(0u));
    fcc_lqg_output_t out;
    fcc_real_t y[2] = {(fcc_real_t)g0, (fcc_real_t)quantised(FCC_MSG_MSL_ACCELEROMETER, accel_at(0u))};
    fcc_assert_ok(fcc_lqg_ctrl_step(&ref, y, &out));
    y[1] = (fcc_real_t)quantised(FCC_MSG_MSL_ACCELEROMETER, accel_at(1u));
    fcc_assert_ok(fcc_lqg_ctrl_step(&ref, y, &out));
    fcc_assert_ok(fcc_lqg_ctrl_predict(&ref, &out));
    assert_int_equal(cmd.msl_elev_cmd.da_code, out.code);
    y[0] = (fcc_real_t)quantised(FCC_MSG_MSL_RATE_GYRO, gyro_at(3u));
    y[1] = (fcc_real_t)quantised(FCC_MSG_MSL_ACCELEROMETER, accel_at(3u));
    fcc_assert_ok(fcc_lqg_ctrl_step(&ref, y, &out));
    assert_int_equal(mem_decode_tx(&g_mem, i).msl_elev_cmd.da_code, out.code);
}

/* ---- lockstep protocol ---------------------------------------------------------- */

static void test_ticks_repeated_lost_behind(void **state)
{
    (void)state;
    start(NULL);
    (void)msl_step(0u, true, true);
    size_t first = g_mem.tx_n;
    mem_push_tick(&g_mem, FCC_APP_MSL, 0u); /* repeated: only the ACK again */
    run();
    assert_int_equal(g_mem.tx_n - first, 1u);
    assert_int_equal(mem_decode_tx(&g_mem, (long)first).fcc_ack.step, 0u);
    assert_int_equal(g_node.app[FCC_APP_MSL].steps, 1u);
    assert_int_equal(g_node.app[FCC_APP_MSL].ticks_repeated, 1u);
    (void)msl_step(4u, true, true); /* 1, 2, 3 never ticked */
    assert_int_equal(g_node.app[FCC_APP_MSL].ticks_lost, 3u);
    assert_int_equal(g_node.app[FCC_APP_MSL].steps, 2u);
    first = g_mem.tx_n;
    mem_push_tick(&g_mem, FCC_APP_MSL, 2u); /* behind: ignored, no ACK */
    run();
    assert_int_equal(g_mem.tx_n, first);
    assert_int_equal(g_node.app[FCC_APP_MSL].ticks_behind, 1u);
    assert_int_equal(g_mem.ev_count[FCC_EV_TICK_BEHIND], 1u);
    /* the other application is independent */
    mem_push_cdrw(&g_mem, 0u, 0.1, 0.0, 0.0);
    mem_push_tick(&g_mem, FCC_APP_CDRW, 0u);
    run();
    assert_int_equal(g_node.app[FCC_APP_CDRW].steps, 1u);
    assert_int_equal(g_node.app[FCC_APP_CDRW].ticks_lost, 0u);
    /* a tick that fails E2E (the same frame again) is not answered */
    first = g_mem.tx_n;
    mem_push_tick(&g_mem, FCC_APP_CDRW, 1u);
    const fcc_can_frame_t dup = g_mem.rx[g_mem.rx_n - 1u];
    mem_push_raw(&g_mem, dup.id, dup.data, 8u);
    run();
    assert_int_equal(g_node.app[FCC_APP_CDRW].steps, 2u);
    assert_int_equal(mem_find_tx(&g_mem, first, FCC_MSG_FCC_ACK_ID, 1u), -1);
}

/* Re-protect a frame after editing its payload, with its own counter. */
static void reprotect(fcc_can_frame_t *f)
{
    fcc_msg_t m;
    fcc_assert_ok(fcc_bus_find(f->id, &m));
    fcc_assert_ok(fcc_e2e_protect(fcc_bus_desc(m)->data_id, (uint8_t)(f->data[1] & 0x0Fu), f->data));
}

static void test_bad_frames_degrade_and_are_counted(void **state)
{
    (void)state;
    start(NULL);
    /* step 0: a CRC error on alpha */
    mem_push_cdrw(&g_mem, 0u, 0.1, 0.01, 0.0);
    g_mem.rx[0].data[0] ^= 0x5Au;
    mem_push_tick(&g_mem, FCC_APP_CDRW, 0u);
    size_t first = g_mem.tx_n;
    run();
    assert_true(mem_decode_tx(&g_mem, (long)first).sid_azkf_state.degraded);
    assert_true(mem_decode_tx(&g_mem, (long)first + 13).fcc_ack.degraded);
    assert_int_equal(g_node.sid.last.input_state[FCC_APP_SID_IN_ALPHA], FCC_SENSOR_REJECTED);
    assert_false(g_node.sid.last.measurement_valid);
    assert_int_equal(g_mem.ev_count[FCC_EV_E2E_ERROR], 1u);
    /* step 1: alpha = 2 rad with a valid CRC (the DBC's limit is 1.5708) */
    mem_push_cdrw(&g_mem, 1u, 0.1, 0.01, 0.0);
    fcc_can_frame_t *aoa = &g_mem.rx[g_mem.rx_n - 3u];
    const int32_t raw = 2000000;
    memcpy(&aoa->data[4], &raw, 4u); /* little-endian host, as the DBC signal */
    reprotect(aoa);
    mem_push_tick(&g_mem, FCC_APP_CDRW, 1u);
    run();
    assert_int_equal(g_node.sid.last.input_state[FCC_APP_SID_IN_ALPHA], FCC_SENSOR_REJECTED);
    /* step 2: wrong length, unknown identifiers, an output of the FCC itself */
    mem_push_cdrw(&g_mem, 2u, 0.1, 0.01, 0.0);
    g_mem.rx[g_mem.rx_n - 2u].dlc = 5u;
    const uint8_t junk[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    mem_push_raw(&g_mem, 0x555u, junk, 8u);
    mem_push_raw(&g_mem, FCC_MSG_SID_KF_STATE_ID, junk, 8u);
    mem_push_tick(&g_mem, FCC_APP_CDRW, 2u);
    run();
    assert_int_equal(g_node.sid.last.input_state[FCC_APP_SID_IN_Q], FCC_SENSOR_REJECTED);
    /* step 3: alpha carries step 9 (a frame of another step) */
    mem_push_cdrw(&g_mem, 3u, 0.1, 0.01, 0.0);
    fcc_can_frame_t *a3 = &g_mem.rx[g_mem.rx_n - 3u];
    a3->data[2] = 9u;
    reprotect(a3);
    mem_push_tick(&g_mem, FCC_APP_CDRW, 3u);
    run();
    assert_int_equal(g_node.sid.last.input_state[FCC_APP_SID_IN_ALPHA], FCC_SENSOR_MISALIGNED);
    fcc_bus_counters_t bc;
    fcc_assert_ok(fcc_bus_get_counters(&g_node.bus, &bc));
    assert_int_equal(bc.e2e[FCC_E2E_ERROR], 1u);
    assert_int_equal(bc.out_of_range, 1u);
    assert_int_equal(bc.wrong_dlc, 1u);
    assert_int_equal(bc.unknown_id, 2u);
    assert_int_equal(g_mem.ev_count[FCC_EV_OUT_OF_RANGE], 1u);
    assert_int_equal(g_mem.ev_count[FCC_EV_WRONG_DLC], 1u);
    assert_int_equal(g_mem.ev_count[FCC_EV_UNKNOWN_ID], 2u);
    assert_int_equal(g_node.cnt.own_id, 1u); /* SID_KF_STATE is fcc's own: impersonation */
    assert_int_equal(g_node.app[FCC_APP_CDRW].degraded_steps, 4u);
    /* recovery: good frames, the next step is clean */
    mem_push_cdrw(&g_mem, 4u, 0.1, 0.01, 0.0);
    mem_push_tick(&g_mem, FCC_APP_CDRW, 4u);
    first = g_mem.tx_n;
    run();
    assert_false(mem_decode_tx(&g_mem, (long)first + 13).fcc_ack.degraded);
    assert_true(g_node.sid.last.measurement_valid);
}

static void test_misaligned_frame(void **state)
{
    (void)state;
    start(NULL);
    mem_push_gyro(&g_mem, 7u, 0.1); /* a frame of step 7 at step 0 */
    mem_push_accel(&g_mem, 0u, 1.0);
    mem_push_tick(&g_mem, FCC_APP_MSL, 0u);
    run();
    assert_int_equal(g_node.msl.last.input_state[FCC_APP_MSL_IN_GYRO], FCC_SENSOR_MISALIGNED);
    assert_true(g_node.msl.last.degraded);
    assert_int_equal(g_mem.ev_count[FCC_EV_SENSOR_MISALIGNED], 1u);
}

/* ---- run-time commands ----------------------------------------------------------- */

static void test_redesign_is_switched_in_between_steps(void **state)
{
    (void)state;
    start(NULL);
    fcc_lqg_ctrl_t ref;
    ref_design(0.05, 8u, &ref, NULL);
    fcc_lqg_output_t out;
    for (uint32_t k = 0u; k < 6u; ++k) {
        if (k == 3u) { /* new period before the tick of step 3 */
            on_ground(0.1, 0u);
            fcc_real_t x[3];
            memcpy(x, ref.x_pred, sizeof x);
            ref_design(0.1, 8u, &ref, x); /* the estimate carries over */
        }
        const long i = msl_step(k, true, true);
        const fcc_real_t y[2] = {(fcc_real_t)quantised(FCC_MSG_MSL_RATE_GYRO, gyro_at(k)),
                                 (fcc_real_t)quantised(FCC_MSG_MSL_ACCELEROMETER, accel_at(k))};
        fcc_assert_ok(fcc_lqg_ctrl_step(&ref, y, &out));
        assert_int_equal(mem_decode_tx(&g_mem, i).msl_elev_cmd.da_code, out.code);
    }
    assert_int_equal(g_node.cnt.configs_applied, 1u);
    assert_int_equal(g_mem.ev_count[FCC_EV_CONFIG_APPLIED], 1u);
    assert_int_equal(fcc_node_app_period_us(&g_node, FCC_APP_MSL), 100000u);
    /* bits only: no new discretisation, the next command is 12-bit */
    on_ground(0.0, 12u);
    long i = msl_step(6u, true, true);
    assert_int_equal(mem_decode_tx(&g_mem, i).msl_elev_cmd.da_bits, 12u);
    fcc_assert_close(fcc_app_msl_period(&g_node.msl), 0.1, 1e-6, 0.0);
    /* refused: T below 0.02 s, N = 1; the design in use stays */
    on_ground(0.01, 0u);
    on_ground(0.0, 1u);
    i = msl_step(7u, true, true);
    assert_int_equal(g_node.cnt.configs_rejected, 2u);
    assert_int_equal(mem_decode_tx(&g_mem, i).msl_elev_cmd.da_bits, 12u);
    assert_int_equal(fcc_node_app_period_us(&g_node, FCC_APP_MSL), 100000u);
    const size_t first = g_mem.tx_n;
    fcc_assert_ok(fcc_node_send_status(&g_node));
    assert_true(mem_decode_tx(&g_mem, (long)first).fcc_status.config_rejected);
    /* a design that fails (impossible plant) keeps the old one too */
    g_node.msl.cfg.plant.gyro_var = FCC_R(-1.0);
    on_ground(0.2, 0u);
    i = msl_step(8u, true, true);
    assert_int_equal(g_node.msl.designs_failed, 1u);
    assert_int_equal(g_node.cnt.configs_rejected, 3u);
    assert_int_equal(fcc_node_app_period_us(&g_node, FCC_APP_MSL), 100000u);
    assert_false(mem_decode_tx(&g_mem, i).msl_elev_cmd.degraded);
}

static void test_pending_requests_merge(void **state)
{
    (void)state;
    start(NULL);
    /* two requests before one step: period from the first, bits from the second */
    on_ground(0.2, 0u);
    on_ground(0.0, 6u);
    const long i = msl_step(0u, true, true);
    assert_int_equal(mem_decode_tx(&g_mem, i).msl_elev_cmd.da_bits, 6u);
    assert_int_equal(fcc_node_app_period_us(&g_node, FCC_APP_MSL), 200000u);
    assert_int_equal(g_node.cnt.configs_accepted, 2u);
    assert_int_equal(g_node.cnt.configs_applied, 1u);
    /* realtime: a request is designed in idle time, not by the step */
    /* in FCC_LQG_DESIGN_SLICES slices; a newer request restarts the design */
    fcc_assert_ok(fcc_app_msl_request(&g_node.msl, FCC_R(0.1), 0u));
    fcc_assert_ok(fcc_node_background(&g_node));
    fcc_assert_ok(fcc_node_background(&g_node));
    fcc_assert_ok(fcc_app_msl_request(&g_node.msl, FCC_R(0.05), 0u));
    assert_true(fcc_app_msl_wants_design(&g_node.msl));
    for (unsigned n = 0u; n < FCC_LQG_DESIGN_SLICES; ++n) {
        assert_true(fcc_app_msl_wants_design(&g_node.msl));
        fcc_assert_ok(fcc_node_background(&g_node));
    }
    assert_false(fcc_app_msl_wants_design(&g_node.msl));
    assert_int_equal(fcc_node_background(&g_node), FCC_ERR_AGAIN);
    assert_int_equal(fcc_node_app_period_us(&g_node, FCC_APP_MSL), 200000u); /* not yet */
    (void)msl_step(1u, true, true);
    assert_int_equal(fcc_node_app_period_us(&g_node, FCC_APP_MSL), 50000u);
}

static void test_reset_and_shutdown(void **state)
{
    (void)state;
    start(NULL);
    size_t first0 = 0u;
    fcc_msg_data_t step0 = {0};
    for (uint32_t k = 0u; k < 10u; ++k) {
        const size_t first = g_mem.tx_n;
        push_flight_step(k);
        run();
        if (k == 1u) {
            first0 = first;
            step0 = mem_decode_tx(&g_mem, (long)first);
        }
    }
    (void)first0;
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_RESET, 0.0, 0u);
    run(); /* not in flight */
    assert_int_equal(g_node.cnt.resets, 0u);
    assert_int_equal(g_node.cnt.mode_refused, 1u);
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_GROUND, 0.0, 0u);
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_RESET, 0.0, 0u);
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_FLIGHT, 0.0, 0u);
    run();
    assert_int_equal(g_node.cnt.resets, 1u);
    assert_int_equal(fcc_node_op_mode(&g_node), FCC_OP_FLIGHT);
    /* a new flight from step 0; the simulator restarted its alive counters too */
    fcc_assert_ok(fcc_bus_init_masks(&g_mem.sim, g_mem.sim.consumes, g_mem.sim.produces));
    for (uint32_t k = 0u; k < 2u; ++k) {
        const size_t first = g_mem.tx_n;
        push_flight_step(k);
        run();
        assert_int_equal(g_mem.tx_n - first, 14u);
        if (k == 1u) { /* the same output as the first flight's step 1 */
            const fcc_msg_data_t again = mem_decode_tx(&g_mem, (long)first);
            fcc_assert_close(again.sid_azkf_state.alpha_hat, step0.sid_azkf_state.alpha_hat, 0.0, 0.0);
            fcc_assert_close(again.sid_azkf_state.q_hat, step0.sid_azkf_state.q_hat, 0.0, 0.0);
        }
    }
    assert_int_equal(g_node.app[FCC_APP_CDRW].ticks_behind, 0u);
    assert_int_equal(g_node.app[FCC_APP_CDRW].steps, 12u); /* counters kept */
    fcc_bus_counters_t bc;
    fcc_assert_ok(fcc_bus_get_counters(&g_node.bus, &bc));
    assert_int_equal(bc.e2e[FCC_E2E_WRONG_SEQUENCE], 0u);
    assert_false(fcc_node_shutdown_requested(&g_node));
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_SHUTDOWN, 0.0, 0u);
    run(); /* not in flight */
    assert_false(fcc_node_shutdown_requested(&g_node));
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_GROUND, 0.0, 0u);
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_SHUTDOWN, 0.0, 0u);
    run();
    assert_true(fcc_node_shutdown_requested(&g_node));
}

static void test_modes_and_authentication(void **state)
{
    (void)state;
    start(NULL);
    /* In flight: design, RESET, SHUTDOWN, MAINTENANCE refused and counted. */
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_NONE, 0.3, 2u);
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_RESET, 0.0, 0u);
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_SHUTDOWN, 0.0, 0u);
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_MAINTENANCE, 0.0, 0u);
    run();
    assert_int_equal(g_node.cnt.mode_refused, 4u);
    assert_int_equal(g_node.cnt.resets, 0u);
    assert_int_equal(g_node.cnt.configs_accepted, 0u);
    assert_false(fcc_node_shutdown_requested(&g_node));
    assert_int_equal(g_mem.ev_count[FCC_EV_MODE_REFUSED], 4u);
    /* Unauthenticated (no authenticator, or a forged one): never acted on. */
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    d.sim_control.command = FCC_MSG_SIM_CONTROL_COMMAND_GROUND;
    fcc_can_frame_t f;
    fcc_assert_ok(fcc_bus_encode(&g_mem.sim, FCC_MSG_SIM_CONTROL, &d, &f));
    mem_push_raw(&g_mem, f.id, f.data, 8u);
    uint32_t ci = 0u;
    assert_true(fcc_secoc_auth_index(FCC_MSG_SIM_CONTROL_AUTH, &ci));
    const uint8_t forged[8] = {(uint8_t)(g_mem.sec.chan[ci].counter + 1u), 0, 1, 2, 3, 4, 5, 6};
    mem_push_raw(&g_mem, FCC_MSG_SIM_CONTROL_AUTH_ID, forged, 8u);
    run();
    assert_int_equal(fcc_node_op_mode(&g_node), FCC_OP_FLIGHT);
    assert_int_equal(g_node.sec.cnt.mac_failed, 1u);
    assert_int_equal(g_mem.ev_count[FCC_EV_AUTH_FAILED], 1u);
    /* A replayed genuine pair: freshness fails. */
    const size_t n0 = g_mem.rx_n;
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_GROUND, 0.0, 0u);
    const fcc_can_frame_t pdu = g_mem.rx[n0], auth = g_mem.rx[n0 + 1u];
    run();
    assert_int_equal(fcc_node_op_mode(&g_node), FCC_OP_GROUND);
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_FLIGHT, 0.0, 0u);
    run();
    mem_push_raw(&g_mem, pdu.id, pdu.data, 8u);
    mem_push_raw(&g_mem, auth.id, auth.data, 8u);
    run();
    assert_int_equal(fcc_node_op_mode(&g_node), FCC_OP_FLIGHT);
    assert_int_equal(g_node.sec.cnt.freshness_failed, 1u);
    /* Ticks on the ground are refused; maintenance allows a design, not FLIGHT. */
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_GROUND, 0.0, 0u);
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_MAINTENANCE, 0.0, 0u);
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_NONE, 0.1, 0u);
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_FLIGHT, 0.0, 0u);
    run();
    assert_int_equal(fcc_node_op_mode(&g_node), FCC_OP_MAINTENANCE);
    assert_int_equal(g_node.cnt.configs_accepted, 1u);
    const size_t tx0 = g_mem.tx_n;
    mem_push_tick(&g_mem, FCC_APP_MSL, 0u);
    run();
    assert_int_equal(g_mem.tx_n, tx0); /* no ACK */
    assert_int_equal(g_node.cnt.mode_refused, 6u);
    const size_t first = g_mem.tx_n;
    fcc_assert_ok(fcc_node_send_status(&g_node));
    assert_int_equal(mem_decode_tx(&g_mem, (long)first).fcc_status.op_mode, FCC_OP_MAINTENANCE);
    const fcc_msg_data_t sc = mem_decode_tx(&g_mem, (long)first + 6); /* FCC_SEC_COUNTS */
    assert_int_equal(sc.fcc_sec_counts.mode_refused, 6u);
    assert_int_equal(sc.fcc_sec_counts.mac_failed, 1u);
    assert_int_equal(sc.fcc_sec_counts.freshness_failed, 1u);
}

static void test_oracle_fault_flag(void **state)
{
    (void)state;
    fcc_node_config_t cfg;
    fcc_assert_ok(fcc_node_config_default(&cfg));
    cfg.sid.base.azkf.det.mode = FCC_FDET_ORACLE;
    start(&cfg);
    /* the detector is armed once the MLS has replaced its prior */
    uint32_t k = 0u;
    for (; k < 2u * FCC_MLS_DEFAULT_MIN_TRANSITIONS; ++k) {
        push_flight_step(k);
    }
    run();
    assert_false(g_node.sid.loop[FCC_SID_AZKF].last.model_is_prior);
    fcc_msg_data_t ev;
    memset(&ev, 0, sizeof ev);
    ev.sim_event.active = true;
    ev.sim_event.oracle_fault = true;
    ev.sim_event.kind = FCC_MSG_SIM_EVENT_KIND_SPIKE;
    ev.sim_event.target_id = FCC_MSG_CDRW_AOA_ID;
    push_flight_sample(k);
    fcc_assert_ok(mem_push(&g_mem, FCC_MSG_SIM_EVENT, &ev));
    mem_push_tick(&g_mem, FCC_APP_CDRW, k);
    size_t first = g_mem.tx_n;
    run();
    fcc_msg_data_t st = mem_decode_tx(&g_mem, (long)first);
    assert_true(st.sid_azkf_state.fault);
    assert_int_equal(st.sid_azkf_state.order, cfg.sid.base.azkf.q_fault);
    assert_true(mem_decode_tx(&g_mem, (long)first + 8).sid_kf_state.fault); /* shown on every row */
    ev.sim_event.active = false;
    ev.sim_event.oracle_fault = false;
    fcc_assert_ok(mem_push(&g_mem, FCC_MSG_SIM_EVENT, &ev));
    ++k;
    push_flight_step(k);
    first = g_mem.tx_n;
    run();
    st = mem_decode_tx(&g_mem, (long)first);
    assert_false(st.sid_azkf_state.fault);
    assert_int_equal(st.sid_azkf_state.order, cfg.sid.base.azkf.q_normal);
    assert_int_equal(g_node.cnt.oracle_events, 2u);
}

/* ---- heartbeat, modes, failures ---------------------------------------------------- */

static void test_heartbeat_frames(void **state)
{
    (void)state;
    start(NULL);
    for (uint32_t k = 0u; k < 3u; ++k) {
        mem_push_cdrw(&g_mem, k, 0.1, 0.0, 0.0);
        mem_push_tick(&g_mem, FCC_APP_CDRW, k);
    }
    g_mem.rx[0].data[0] ^= 1u; /* one CRC error */
    run();
    (void)msl_step(0u, true, false); /* no accelerometer: held? never seen -> stale */
    const size_t first = g_mem.tx_n;
    fcc_assert_ok(fcc_node_send_status(&g_node));
    assert_int_equal(g_mem.tx_n - first, 10u); /* the time sync's status frames in the group */
    static const uint32_t ids[10] = {0x700u, 0x701u, 0x702u, 0x703u, 0x704u,
                                     0x705u, 0x706u, 0x707u, 0x708u, 0x709u};
    for (unsigned int i = 0u; i < 10u; ++i) {
        assert_int_equal(g_mem.tx[first + i].id, ids[i]);
    }
    assert_int_equal(mem_decode_tx(&g_mem, (long)first + 5).fcc_sync_status.state, FCC_TSYNC_FREE_RUN);
    assert_int_equal(mem_decode_tx(&g_mem, (long)first + 8).fcc_sync_refusals.mac_failed, 0u);
    assert_int_equal(mem_decode_tx(&g_mem, (long)first + 7).fcc_sec_session.trip, MEM_TRIP);
    const fcc_msg_data_t s = mem_decode_tx(&g_mem, (long)first);
    assert_int_equal(s.fcc_status.mode, FCC_MODE_LOCKSTEP);
    assert_int_equal(s.fcc_status.cdrw_steps, 3u);
    assert_int_equal(s.fcc_status.msl_steps, 1u);
    assert_true(s.fcc_status.e2e_fault);
    assert_true(s.fcc_status.msl_degraded);
    assert_false(s.fcc_status.cdrw_degraded);
    assert_true(s.fcc_status.sensor_stale);
    assert_true(s.fcc_status.worst_step_us > 0u);
    const fcc_msg_data_t c = mem_decode_tx(&g_mem, (long)first + 1);
    const fcc_msg_data_t f = mem_decode_tx(&g_mem, (long)first + 2);
    const fcc_msg_data_t b = mem_decode_tx(&g_mem, (long)first + 4);
    /* FLIGHT + 9 CDRW sensor frames (1 bad) + 3 ticks + 1 gyro + 1 tick = 14 OK */
    assert_int_equal(c.fcc_e2_e_counts.ok, 14u);
    assert_int_equal(f.fcc_e2_e_faults.error, 1u);
    assert_int_equal(f.fcc_e2_e_faults.no_new_data, 1u);
    assert_int_equal(f.fcc_e2_e_faults.stale_now, 1u);
    assert_int_equal(b.fcc_bus_counts.bus_errors, 7u);
    assert_int_equal(f.fcc_e2_e_faults.own_id, 0u);
    /* a frame on fcc's own identifier (its command): counted as impersonation */
    const uint8_t junk[8] = {0};
    mem_push_raw(&g_mem, FCC_MSG_MSL_ELEV_CMD_ID, junk, 8u);
    mem_push_raw(&g_mem, FCC_MSG_SID_OUT_AUTH_ID, junk, 8u);
    run();
    const size_t again = g_mem.tx_n;
    fcc_assert_ok(fcc_node_send_status(&g_node));
    assert_int_equal(mem_decode_tx(&g_mem, (long)again + 2).fcc_e2_e_faults.own_id, 2u);
    assert_int_equal(mem_decode_tx(&g_mem, (long)again + 3).fcc_reject_counts.unknown_id, 2u);
    /* the since-last-heartbeat flag is cleared */
    fcc_assert_ok(fcc_node_send_status(&g_node));
    assert_false(mem_decode_tx(&g_mem, (long)first + 10).fcc_status.e2e_fault);
}

/* The time master's pairs reach the servo only with their TSYNC_AUTH: the red
 * team's forger (valid E2E, pre-empting the master's alive counters, no key)
 * moves nothing and disturbs no E2E state; its frames are counted in
 * FCC_SYNC_REFUSALS; an authenticated master that steps by 50 ms is refused
 * (REFUSED) until an authenticated RESET on the ground. */
static void test_time_sync_is_authenticated(void **state)
{
    (void)state;
    start(NULL);
    fcc_bus_t forger;
    fcc_assert_ok(fcc_bus_init(&forger, FCC_BUS_NODE_SIM));
    const uint64_t off = 3000000u; /* master = local + 3 s */
    uint64_t l = 1000000u;
    uint8_t seq = 0u;
    for (int i = 0; i < 10; ++i, l += 100000u) {
        mem_push_sync_pair(&g_mem, &g_mem.sim, seq++, l, l + off, true);
        run();
    }
    assert_int_equal(g_node.tsync.state, FCC_TSYNC_LOCKED);
    /* the forger: pairs of the next sequence number first, 50 ms behind, then the master's */
    for (int i = 0; i < 10; ++i, l += 100000u) {
        forger.tx[FCC_MSG_TSYNC_SYNC] = g_mem.sim.tx[FCC_MSG_TSYNC_SYNC];
        forger.tx[FCC_MSG_TSYNC_FOLLOW_UP] = g_mem.sim.tx[FCC_MSG_TSYNC_FOLLOW_UP];
        mem_push_sync_pair(&g_mem, &forger, seq, l - 10u, l - 10u + off - 50000u, false);
        mem_push_sync_pair(&g_mem, &g_mem.sim, seq++, l, l + off, true);
        run();
    }
    assert_int_equal(g_node.tsync.state, FCC_TSYNC_LOCKED);
    assert_int_equal(g_node.tsync.cnt.samples, 20u);
    assert_int_equal(g_node.tsync_auth.cnt.unauthenticated, 20u); /* dropped when the pair verified */
    assert_int_equal(g_node.tsync.cnt.step_refused + g_node.tsync.cnt.past, 0u);
    fcc_bus_counters_t bc;
    fcc_assert_ok(fcc_bus_get_counters(&g_node.bus, &bc));
    assert_int_equal(bc.e2e[FCC_E2E_REPEATED] + bc.e2e[FCC_E2E_WRONG_SEQUENCE] +
                         bc.e2e[FCC_E2E_ERROR], 0u);
    /* a forged authenticator, and a replayed one */
    const uint8_t forged[8] = {0x40u, 0u, 1u, 2u, 3u, 4u, 5u, 6u};
    mem_push_raw(&g_mem, FCC_MSG_TSYNC_AUTH_ID, forged, 8u);
    const size_t n0 = g_mem.rx_n;
    mem_push_sync_pair(&g_mem, &g_mem.sim, seq++, l, l + off, true);
    const fcc_can_frame_t replay = g_mem.rx[n0 + 2u];
    run();
    mem_push_raw(&g_mem, replay.id, replay.data, 8u);
    run();
    l += 100000u;
    assert_int_equal(g_node.tsync_auth.cnt.mac_failed, 1u);
    assert_int_equal(g_node.tsync_auth.cnt.freshness_failed, 1u);
    assert_int_equal(g_mem.ev_count[FCC_EV_AUTH_FAILED], 2u);
    /* the heartbeat says so */
    const size_t first = g_mem.tx_n;
    fcc_assert_ok(fcc_node_send_status(&g_node));
    const fcc_msg_data_t r = mem_decode_tx(&g_mem, (long)first + 8);
    assert_int_equal(r.fcc_sync_refusals.mac_failed, 1u);
    assert_int_equal(r.fcc_sync_refusals.freshness_failed, 1u);
    assert_int_equal(r.fcc_sync_refusals.unauthenticated, 20u);
    const fcc_msg_data_t st = mem_decode_tx(&g_mem, (long)first + 5);
    assert_int_equal(st.fcc_sync_status.state, FCC_TSYNC_LOCKED);
    assert_int_equal(st.fcc_sync_status.rejected, 22u);
    /* the (authenticated) master steps by -50 ms: refused, the estimate goes on */
    for (int i = 0; i < 5; ++i, l += 100000u) {
        mem_push_sync_pair(&g_mem, &g_mem.sim, seq++, l, l + off - 50000u, true);
        run();
    }
    assert_int_equal(g_node.tsync.state, FCC_TSYNC_REFUSED);
    assert_int_equal(g_node.tsync.cnt.step_refused, 5u);
    assert_true(fcc_tsync_has_time(&g_node.tsync));
    uint64_t m = 0u;
    fcc_assert_ok(fcc_tsync_to_master(&g_node.tsync, l, &m));
    assert_true(m + 5u >= l + off && m <= l + off + 5u);
    /* a RESET in flight is refused; on the ground it rebases: the new time base is followed */
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_GROUND, 0.0, 0u);
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_RESET, 0.0, 0u);
    run();
    assert_int_equal(g_node.tsync.state, FCC_TSYNC_FREE_RUN);
    for (int i = 0; i < 5; ++i, l += 100000u) {
        mem_push_sync_pair(&g_mem, &g_mem.sim, seq++, l, l + off - 50000u, true);
        run();
    }
    assert_int_equal(g_node.tsync.state, FCC_TSYNC_LOCKED);
}

static void test_realtime_mode_and_disabled_app(void **state)
{
    (void)state;
    fcc_node_config_t cfg;
    fcc_assert_ok(fcc_node_config_default(&cfg));
    cfg.mode = FCC_MODE_REALTIME;
    cfg.app_enabled[FCC_APP_CDRW] = false;
    start(&cfg);
    mem_push_tick(&g_mem, FCC_APP_MSL, 0u);
    mem_push_tick(&g_mem, FCC_APP_CDRW, 0u);
    run();
    assert_int_equal(g_mem.tx_n, 0u); /* ticks are not answered in realtime */
    assert_int_equal(g_node.app[FCC_APP_MSL].ticks_ignored, 1u);
    assert_int_equal(g_node.app[FCC_APP_CDRW].ticks_ignored, 1u);
    mem_push_gyro(&g_mem, 500u, 0.2); /* the step field is not compared in realtime */
    mem_push_accel(&g_mem, 17u, 10.0);
    run();
    fcc_assert_ok(fcc_node_run_step(&g_node, FCC_APP_MSL, 0u));
    assert_int_equal(g_mem.tx_n, 3u); /* command, its authenticator and estimate, no ACK */
    assert_false(mem_decode_tx(&g_mem, 0).msl_elev_cmd.degraded);
    fcc_assert_ok(fcc_node_send_status(&g_node));
    assert_int_equal(mem_decode_tx(&g_mem, 3).fcc_status.mode, FCC_MODE_REALTIME);
    fcc_node_note_overrun(&g_node, FCC_APP_MSL, 2u, 5u);
    assert_int_equal(g_node.app[FCC_APP_MSL].overruns, 2u);
    fcc_assert_ok(fcc_node_send_status(&g_node));
    const fcc_msg_data_t s = mem_decode_tx(&g_mem, 13);
    assert_true(s.fcc_status.overrun);
    assert_int_equal(s.fcc_status.overruns, 2u);
}

static void test_transmit_failures_are_counted(void **state)
{
    (void)state;
    start(NULL);
    g_mem.fail_send = true;
    mem_push_gyro(&g_mem, 0u, 0.1);
    mem_push_accel(&g_mem, 0u, 1.0);
    mem_push_tick(&g_mem, FCC_APP_MSL, 0u);
    run();
    assert_int_equal(g_node.app[FCC_APP_MSL].steps, 1u);
    assert_int_equal(g_node.cnt.tx_failed, 4u);
    assert_int_equal(g_mem.ev_count[FCC_EV_TX_FAILED], 4u);
    g_mem.fail_send = false;
    (void)msl_step(1u, true, true);
    assert_int_equal(g_node.cnt.tx_frames, 4u);
}

/* ---- batched sends (a port with send_many) --------------------------------------- */

static void test_batched_one_port_call_per_step(void **state)
{
    (void)state;
    g_batched = true;
    start(NULL);
    const uint32_t before = g_mem.batches;
    push_flight_step(0u);
    run();
    assert_int_equal(g_mem.batches - before, 1u); /* 12 outputs, their MAC, the ACK together */
    assert_int_equal(g_mem.batch_len[before], FCC_APP_SID_N_FRAMES + 2u);
    assert_int_equal(g_mem.tx[g_mem.tx_n - 1u].id, FCC_MSG_FCC_ACK_ID);
    (void)msl_step(0u, true, true);
    assert_int_equal(g_mem.batches - before, 2u);
    assert_int_equal(g_mem.batch_len[before + 1u], 4u); /* command, estimate, their MAC, ACK */
    mem_push_tick(&g_mem, FCC_APP_MSL, 0u); /* repeated: its ACK alone, at once */
    run();
    assert_int_equal(g_mem.batches - before, 3u);
    assert_int_equal(g_mem.batch_len[before + 2u], 1u);
    fcc_assert_ok(fcc_node_send_status(&g_node));
    assert_int_equal(g_mem.batches - before, 4u);
    assert_int_equal(g_mem.batch_len[before + 3u], 10u);
    assert_int_equal(g_node.txq.n, 0u);
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_GROUND, 0.0, 0u);
    mem_push_tick(&g_mem, FCC_APP_CDRW, 5u); /* refused on the ground: nothing sent */
    const uint32_t calls = g_mem.batches;
    const size_t sent = g_mem.tx_n;
    run();
    assert_int_equal(g_mem.tx_n, sent);
    assert_int_equal(g_mem.batches, calls); /* an empty queue costs no port call */
    assert_int_equal(g_node.cnt.tx_frames, g_mem.tx_n);
    assert_int_equal(g_node.cnt.tx_failed, 0u);
}

static void test_batched_failures_counted_per_frame(void **state)
{
    (void)state;
    g_batched = true;
    start(NULL);
    g_mem.refuse_id = FCC_MSG_MSL_ELEV_CMD_ID;
    g_mem.refuse_st = FCC_ERR_AGAIN; /* the port gave up on the command alone */
    mem_push_gyro(&g_mem, 0u, 0.1);
    mem_push_accel(&g_mem, 0u, 1.0);
    mem_push_tick(&g_mem, FCC_APP_MSL, 0u);
    run();
    assert_int_equal(g_mem.tx_n, 3u); /* the estimate, MAC and ACK after it still left */
    assert_int_equal(g_mem.tx[0].id, FCC_MSG_MSL_STATE_EST_ID);
    assert_int_equal(g_mem.tx[1].id, FCC_MSG_MSL_ELEV_CMD_AUTH_ID);
    assert_int_equal(g_mem.tx[2].id, FCC_MSG_FCC_ACK_ID);
    assert_int_equal(g_node.cnt.tx_failed, 1u);
    assert_int_equal(g_node.cnt.tx_frames, 3u);
    assert_int_equal(g_mem.ev_count[FCC_EV_TX_FAILED], 1u);
    const fcc_event_t *ev = &g_mem.last_ev[FCC_EV_TX_FAILED];
    assert_int_equal(ev->can_id, FCC_MSG_MSL_ELEV_CMD_ID);
    assert_int_equal(ev->app, FCC_APP_MSL);
    assert_int_equal(ev->step, 0u);
    assert_int_equal(ev->value, FCC_ERR_AGAIN);
    /* an I/O error ends the batch: every later frame of it is not sent, and counted */
    g_mem.refuse_id = FCC_MSG_SID_AZKF_STATE_ID;
    g_mem.refuse_st = FCC_ERR_IO;
    push_flight_step(0u);
    run();
    assert_int_equal(g_mem.tx_n, 3u);
    /* the 12 outputs, their authenticator, the ACK */
    assert_int_equal(g_node.cnt.tx_failed, 1u + FCC_APP_SID_N_FRAMES + 2u);
    assert_int_equal(g_mem.ev_count[FCC_EV_TX_FAILED], 1u + FCC_APP_SID_N_FRAMES + 2u);
    assert_int_equal(g_mem.last_ev[FCC_EV_TX_FAILED].can_id, FCC_MSG_FCC_ACK_ID);
    assert_int_equal(g_mem.last_ev[FCC_EV_TX_FAILED].app, FCC_APP_CDRW);
}

/* A scripted session: CDRW and missile steps, a repeated tick, heartbeats, a redesign. */
static void fly_script(void)
{
    start(NULL);
    for (uint32_t k = 0u; k < 30u; ++k) {
        push_flight_step(k);
        if (k % 3u == 0u) {
            mem_push_gyro(&g_mem, k / 3u, gyro_at(k / 3u));
            mem_push_accel(&g_mem, k / 3u, accel_at(k / 3u));
            mem_push_tick(&g_mem, FCC_APP_MSL, k / 3u);
        }
        if (k == 10u) {
            mem_push_tick(&g_mem, FCC_APP_CDRW, k);
        }
        run();
        if (k % 10u == 9u) {
            fcc_assert_ok(fcc_node_send_status(&g_node));
        }
    }
    on_ground(0.1, 6u); /* a redesign, switched in at the next step */
    run();
    for (uint32_t k = 10u; k < 15u; ++k) {
        (void)msl_step(k, true, true);
    }
    assert_int_equal(g_node.msl.designs_applied, 1u);
}

static void test_batched_frames_equal_frame_by_frame(void **state)
{
    (void)state;
    static fcc_can_frame_t alone[MEM_TX_MAX];
    g_batched = false;
    fly_script();
    const size_t n = g_mem.tx_n;
    memcpy(alone, g_mem.tx, n * sizeof alone[0]);
    assert_int_equal(g_mem.batches, 0u);
    g_batched = true;
    fly_script();
    assert_true(n > 400u);
    assert_int_equal(g_mem.tx_n, n);
    assert_true(g_mem.batches < n / 4u);
    for (size_t i = 0u; i < n; ++i) { /* the same frames in the same order (not the padding) */
        assert_int_equal(g_mem.tx[i].id, alone[i].id);
        assert_int_equal(g_mem.tx[i].dlc, alone[i].dlc);
        assert_memory_equal(g_mem.tx[i].data, alone[i].data, sizeof alone[i].data);
    }
    assert_int_equal(g_node.cnt.tx_frames, n);
}

/* ---- garbage at full rate ----------------------------------------------------------- */

static uint32_t lcg(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}

static void check_outputs_sane(size_t from)
{
    for (size_t i = from; i < g_mem.tx_n; ++i) {
        const fcc_msg_data_t d = mem_decode_tx(&g_mem, (long)i); /* in range, so finite */
        if (g_mem.tx[i].id == FCC_MSG_MSL_ELEV_CMD_ID) {
            const int32_t half = 1 << (d.msl_elev_cmd.da_bits - 1u);
            assert_true(d.msl_elev_cmd.da_code >= -half && d.msl_elev_cmd.da_code < half);
        }
        for (unsigned int s = 0u;; ++s) {
            fcc_msg_t m;
            fcc_assert_ok(fcc_bus_find(g_mem.tx[i].id, &m));
            fcc_real_t r;
            int64_t n;
            if (fcc_bus_signal_get(m, s, &d, &r, &n) != FCC_OK) {
                break;
            }
            assert_true(FCC_IS_FINITE(r));
        }
    }
}

static void test_garbage_never_crashes_nor_sends_nan(void **state)
{
    (void)state;
    start(NULL);
    uint32_t seed = 12345u;
    uint32_t k[2] = {0u, 0u};
    static const uint32_t ids[] = {0x010, 0x020, 0x040, 0x041, 0x050, 0x051, 0x052, 0x710,
                                   0x7F0, 0x555, 0x000, 0x7FF, 0x110};
    for (unsigned int round = 0u; round < 400u; ++round) {
        const size_t from = g_mem.tx_n;
        for (unsigned int j = 0u; j < 40u; ++j) {
            uint8_t data[8];
            for (unsigned int b = 0u; b < 8u; ++b) {
                data[b] = (uint8_t)lcg(&seed);
            }
            const uint32_t id = ids[lcg(&seed) % (sizeof ids / sizeof ids[0])];
            const uint8_t dlc = (lcg(&seed) % 4u == 0u) ? (uint8_t)(lcg(&seed) % 9u) : 8u;
            fcc_msg_t m;
            /* (not for SIM_TICK: a good tick far ahead would, by design, make the
             * real ticks "behind" until the next reset) */
            if (lcg(&seed) % 2u == 0u && fcc_bus_find(id, &m) == FCC_OK &&
                fcc_bus_desc(m)->data_id != 0u && id != FCC_MSG_SIM_TICK_ID) {
                /* valid CRC around random contents: reaches the range checks */
                (void)fcc_e2e_protect(fcc_bus_desc(m)->data_id, (uint8_t)(lcg(&seed) % 16u), data);
            }
            if (id == 0x010u && data[1] >> 4 == 1u) {
                data[1] &= 0x0Fu; /* no random shutdown: the test goes on */
            }
            mem_push_raw(&g_mem, id, data, dlc);
        }
        const uint32_t app = lcg(&seed) % 2u;
        k[app] += 1u + lcg(&seed) % 3u;
        if (app == FCC_APP_MSL) {
            mem_push_gyro(&g_mem, k[app], 30.0 * sin((double)round)); /* beyond +-20: refused */
            mem_push_accel(&g_mem, k[app], 200.0 * cos((double)round));
        } else {
            mem_push_cdrw(&g_mem, k[app], 0.2 * sin((double)round), 0.5, 0.01);
        }
        mem_push_tick(&g_mem, app, k[app]);
        run();
        check_outputs_sane(from);
        if (g_node.shutdown) {
            g_node.shutdown = false;
        }
    }
    assert_true(g_node.app[FCC_APP_MSL].steps > 50u);
    assert_true(g_node.app[FCC_APP_CDRW].steps > 50u);
    /* good frames again: both applications recover on their own */
    fcc_assert_ok(fcc_node_reset(&g_node));
    fcc_assert_ok(fcc_bus_init_masks(&g_mem.sim, g_mem.sim.consumes, g_mem.sim.produces));
    const size_t from = g_mem.tx_n;
    for (uint32_t j = 0u; j < 3u; ++j) {
        (void)msl_step(j, true, true);
        mem_push_cdrw(&g_mem, j, 0.1, 0.0, 0.0);
        mem_push_tick(&g_mem, FCC_APP_CDRW, j);
        run();
    }
    check_outputs_sane(from);
    assert_false(g_node.app[FCC_APP_MSL].last_degraded);
    assert_false(g_node.app[FCC_APP_CDRW].last_degraded);
}

static int per_frame(void **state)
{
    (void)state;
    g_batched = false;
    return 0;
}

static int batched(void **state)
{
    (void)state;
    g_batched = true;
    return 0;
}

/* The node's entry points refuse what they cannot work with, and say so. */
static void test_entry_points_refuse_missing_arguments(void **state)
{
    (void)state;
    assert_int_equal(fcc_node_config_default(NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_node_reset(NULL), FCC_ERR_ARG);
    fcc_node_config_t cfg;
    assert_int_equal(fcc_node_config_default(&cfg), FCC_OK);
    cfg.security.trip = 1u;
    fcc_port_t port;
    memset(&port, 0, sizeof port);
    static fcc_node_t node;
    assert_int_equal(fcc_node_init(NULL, &cfg, &port), FCC_ERR_ARG);
    assert_int_equal(fcc_node_init(&node, NULL, &port), FCC_ERR_ARG);
    assert_int_equal(fcc_node_init(&node, &cfg, NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_node_init(&node, &cfg, &port), FCC_ERR_ARG); /* no send, recv, clock */
}

/* Every frame the DBC sends to FCC is taken by fcc: an input slot of its application
 * (generated from FccApp), a handler of the node's or an authenticator -- a frame added to
 * the DBC and regenerated fails here instead of being dropped in silence.  And nothing else. */
static void test_every_frame_sent_to_fcc_is_taken(void **state)
{
    (void)state;
    const uint8_t fcc = (uint8_t)(1u << FCC_BUS_NODE_FCC);
    uint32_t taken = 0u;
    for (unsigned int i = 0u; i < (unsigned int)FCC_MSG_COUNT; ++i) {
        const fcc_bus_msg_desc_t *d = &fcc_bus_msg_table[i];
        const bool to_fcc = (d->receivers & fcc) != 0u && (d->senders & fcc) == 0u;
        if (to_fcc != fcc_node_handles((fcc_msg_t)i)) {
            fail_msg("%s: sent to FCC %d, taken by fcc %d", d->name, (int)to_fcc, (int)!to_fcc);
        }
        taken += to_fcc ? 1u : 0u;
    }
    assert_true(taken >= 14u); /* today 5 sensors, 3 time sync, 2 control, 2 tick, event, ping */
    assert_false(fcc_node_handles(FCC_MSG_COUNT));
    /* the input tables are the applications' slots, in slot order */
    assert_int_equal(FCC_BUS_APP_CDRW_N_INPUTS, FCC_APP_SID_N_INPUTS);
    assert_int_equal(fcc_bus_app_cdrw_inputs[FCC_APP_SID_IN_Q], FCC_MSG_CDRW_PITCH_RATE);
    assert_int_equal(FCC_BUS_APP_MISSILE_N_INPUTS, FCC_APP_MSL_N_INPUTS);
    assert_int_equal(fcc_bus_app_missile_inputs[FCC_APP_MSL_IN_ACCEL], FCC_MSG_MSL_ACCELEROMETER);
    assert_int_equal(fcc_bus_input_app[FCC_MSG_CDRW_AOA], FCC_APP_CDRW);
    assert_int_equal(fcc_bus_input_app[FCC_MSG_MSL_ELEV_CMD], FCC_BUS_NO_APP); /* an output */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_frame_sent_to_fcc_is_taken),
        cmocka_unit_test(test_entry_points_refuse_missing_arguments),
        cmocka_unit_test(test_cdrw_steps_match_the_sid_loops),
        cmocka_unit_test(test_missile_commands_match_the_lqg),
        cmocka_unit_test(test_missing_sensor_held_then_stale_then_recovered),
        cmocka_unit_test(test_ticks_repeated_lost_behind),
        cmocka_unit_test(test_bad_frames_degrade_and_are_counted),
        cmocka_unit_test(test_misaligned_frame),
        cmocka_unit_test(test_redesign_is_switched_in_between_steps),
        cmocka_unit_test(test_pending_requests_merge),
        cmocka_unit_test(test_reset_and_shutdown),
        cmocka_unit_test(test_oracle_fault_flag),
        cmocka_unit_test(test_heartbeat_frames),
        cmocka_unit_test(test_modes_and_authentication),
        cmocka_unit_test(test_realtime_mode_and_disabled_app),
        cmocka_unit_test(test_time_sync_is_authenticated),
        cmocka_unit_test(test_transmit_failures_are_counted),
        cmocka_unit_test(test_garbage_never_crashes_nor_sends_nan),
    };
    const struct CMUnitTest batch_tests[] = {
        cmocka_unit_test(test_batched_one_port_call_per_step),
        cmocka_unit_test(test_batched_failures_counted_per_frame),
        cmocka_unit_test(test_batched_frames_equal_frame_by_frame),
    };
    /* every test twice: a port that sends frame by frame (the Cortex-M4F image), and
     * one with send_many (Linux), through which the node queues and flushes */
    int failed = cmocka_run_group_tests_name("frame by frame", tests, per_frame, NULL);
    failed += cmocka_run_group_tests_name("batched", tests, batched, NULL);
    failed += cmocka_run_group_tests_name("batches", batch_tests, batched, NULL);
    return failed;
}
