/*
 * test_node_rt.c -- the node's realtime schedule (fcc_node_rt.c) on the in-memory
 * port: free-run deadlines on the port's clock, skip-not-burst overruns, the
 * autopilot first, the grid on the ground, and the master's sampling instants
 * once the time sync has the master's time (released when the inputs are in,
 * at the latest when the window closes).  The clock is the test's: it moves
 * only when the test sets it.
 */
#include "fcc_test.h"

#include "test_app_port.h"

static fcc_node_t g_node;
static mem_port_t g_mem;

static void poll_frames(void)
{
    uint32_t n = 0u;
    fcc_assert_ok(fcc_node_poll(&g_node, 100000u, &n));
}

/* A realtime node in FLIGHT, the missile's period msl_period, the identification
 * enabled or not (the probe, in the build that has it, not); the clock stands still at 1 s. */
static void start(double msl_period, bool cdrw)
{
    fcc_port_t port;
    mem_init(&g_mem, &port);
    g_mem.step_us = 0u;
    g_mem.now_us = 1000000u;
    fcc_node_config_t cfg;
    fcc_assert_ok(fcc_node_config_default(&cfg));
    cfg.mode = FCC_MODE_REALTIME;
    cfg.app_enabled[FCC_APP_CDRW] = cdrw;
    cfg.app_enabled[FCC_BUS_APP_PROBE] = false; /* the probe build's third one: not counted here */
    cfg.msl.period = (fcc_real_t)msl_period;
    mem_secure(&cfg);
    fcc_assert_ok(fcc_node_init(&g_node, &cfg, &port));
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_FLIGHT, 0.0, 0u);
    poll_frames();
    assert_int_equal(fcc_node_op_mode(&g_node), FCC_OP_FLIGHT);
}

static uint32_t run_at(fcc_node_rt_t rt[FCC_N_APPS], uint64_t now, uint64_t jitter[FCC_N_APPS])
{
    g_mem.now_us = now;
    return fcc_node_rt_run_due(&g_node, rt, jitter);
}

/* Free-run: each step at its deadline t0 + k T, the jitter its lateness; both due
 * at once, the autopilot's command leaves before the identification's outputs. */
static void test_free_run_deadlines_autopilot_first(void **state)
{
    (void)state;
    start(0.02, true);
    const uint32_t t = fcc_node_app_period_us(&g_node, FCC_APP_MSL);
    assert_int_equal(t, 20000u);
    assert_int_equal(fcc_node_app_period_us(&g_node, FCC_APP_CDRW), t);
    const uint64_t t0 = g_mem.now_us;
    fcc_node_rt_t rt[FCC_N_APPS];
    fcc_node_rt_start(&g_node, rt, t0);
    assert_int_equal(fcc_node_rt_next(&g_node, rt), t0 + t);
    uint64_t jitter[FCC_N_APPS];
    assert_int_equal(run_at(rt, t0 + t - 1u, jitter), 0u);
    assert_true(jitter[FCC_APP_MSL] == UINT64_MAX && jitter[FCC_APP_CDRW] == UINT64_MAX);
    assert_int_equal(run_at(rt, t0 + t + 7u, jitter), 2u);
    assert_int_equal(jitter[FCC_APP_MSL], 7u);
    assert_int_equal(jitter[FCC_APP_CDRW], 7u);
    assert_int_equal(g_node.app[FCC_APP_MSL].steps, 1u);
    assert_int_equal(g_node.app[FCC_APP_CDRW].steps, 1u);
    const long cmd = mem_find_tx(&g_mem, 0u, FCC_MSG_MSL_ELEV_CMD_ID, 0u);
    const long sid = mem_find_tx(&g_mem, 0u, FCC_MSG_SID_OUT_AUTH_ID, 0u);
    assert_true(cmd >= 0 && sid > cmd);
    assert_int_equal(rt[FCC_APP_MSL].k, 1u);
    assert_int_equal(fcc_node_rt_next(&g_node, rt), t0 + 2u * t);
    assert_int_equal(g_node.app[FCC_APP_MSL].overruns, 0u);
}

/* A step that starts whole periods late skips them (counted as overruns, one step
 * run, no burst); one that ends after its next deadline is an overrun too. */
static void test_late_steps_skip_and_count_overruns(void **state)
{
    (void)state;
    start(0.02, false);
    const uint64_t t0 = g_mem.now_us;
    const uint32_t t = fcc_node_app_period_us(&g_node, FCC_APP_MSL);
    fcc_node_rt_t rt[FCC_N_APPS];
    fcc_node_rt_start(&g_node, rt, t0);
    assert_int_equal(fcc_node_rt_next(&g_node, rt), t0 + t); /* the disabled one is not waited for */
    uint64_t jitter[FCC_N_APPS];
    assert_int_equal(run_at(rt, t0 + 4u * t + t / 2u, jitter), 1u); /* 3 periods missed */
    assert_int_equal(jitter[FCC_APP_MSL], t / 2u);
    assert_int_equal(jitter[FCC_APP_CDRW], UINT64_MAX);
    assert_int_equal(g_node.app[FCC_APP_MSL].steps, 1u);
    assert_int_equal(g_node.app[FCC_APP_MSL].overruns, 3u);
    assert_int_equal(g_mem.ev_count[FCC_EV_OVERRUN], 1u);
    assert_int_equal(rt[FCC_APP_MSL].k, 4u);
    assert_int_equal(g_node.app[FCC_APP_CDRW].steps, 0u);
    /* a step that takes longer than a period (the clock moves a period per reading):
     * started on time, it ends after its next deadline */
    g_mem.step_us = t;
    assert_int_equal(run_at(rt, rt[FCC_APP_MSL].deadline - t, jitter), 1u);
    assert_int_equal(jitter[FCC_APP_MSL], 0u);
    assert_int_equal(g_node.app[FCC_APP_MSL].overruns, 4u);
}

/* On the ground nothing steps, and the grid goes on: back in flight the next step is
 * on the same grid, with the step index it would have had. */
static void test_ground_keeps_the_grid(void **state)
{
    (void)state;
    start(0.02, false);
    const uint64_t t0 = g_mem.now_us;
    const uint32_t t = fcc_node_app_period_us(&g_node, FCC_APP_MSL);
    fcc_node_rt_t rt[FCC_N_APPS];
    fcc_node_rt_start(&g_node, rt, t0);
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_GROUND, 0.0, 0u);
    poll_frames();
    assert_int_equal(fcc_node_op_mode(&g_node), FCC_OP_GROUND);
    uint64_t jitter[FCC_N_APPS];
    assert_int_equal(run_at(rt, t0 + t - 1u, jitter), 0u);
    assert_int_equal(rt[FCC_APP_MSL].k, 0u);
    assert_int_equal(run_at(rt, t0 + 3u * t + 5u, jitter), 0u);
    assert_int_equal(jitter[FCC_APP_MSL], UINT64_MAX);
    assert_int_equal(rt[FCC_APP_MSL].k, 3u);
    assert_int_equal(rt[FCC_APP_MSL].deadline, t0 + 4u * t);
    assert_int_equal(g_node.app[FCC_APP_MSL].steps + g_node.app[FCC_APP_MSL].overruns, 0u);
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_FLIGHT, 0.0, 0u);
    poll_frames();
    assert_int_equal(run_at(rt, t0 + 4u * t, jitter), 1u);
    assert_int_equal(jitter[FCC_APP_MSL], 0u);
    assert_int_equal(rt[FCC_APP_MSL].k, 4u);
}

/* The gyro's and the accelerometer's frames for the missile, received at `at`. */
static void push_msl_inputs(uint64_t at)
{
    g_mem.now_us = at;
    mem_push_gyro(&g_mem, 0u, 0.1);
    mem_push_accel(&g_mem, 0u, 1.0);
    poll_frames();
}

/* Ten authentic sync pairs, 100 ms apart (master = local + 3 s): the time sync has the
 * master's time; returns the local time of the last one. */
static uint64_t have_master_time(void)
{
    const uint64_t off = 3000000u;
    uint64_t l = 1000000u;
    for (uint8_t seq = 0u; seq < 10u; ++seq, l += 100000u) {
        mem_push_sync_pair(&g_mem, &g_mem.sim, seq, l, l + off, true);
        poll_frames();
    }
    assert_true(fcc_tsync_has_time(&g_node.tsync));
    return l;
}

/* With the master's time the missile's step n is released at the master's instant
 * n T as soon as its inputs are in (not before the guard), at the latest when the
 * window closes; whole periods late, the missed ones are skipped; without the
 * master's time the schedule free-runs on the own clock from then on. */
static void test_synced_release_inputs_or_window(void **state)
{
    (void)state;
    start(0.02, false);
    const uint32_t t = fcc_node_app_period_us(&g_node, FCC_APP_MSL);
    uint64_t l = have_master_time();
    fcc_node_rt_t rt[FCC_N_APPS];
    fcc_node_rt_start(&g_node, rt, l);
    uint64_t jitter[FCC_N_APPS];
    /* aligned to the next instant; nothing is in yet */
    assert_int_equal(run_at(rt, l, jitter), 0u);
    assert_true(rt[FCC_APP_MSL].synced);
    assert_int_equal(rt[FCC_APP_MSL].aligns, 1u);
    const uint64_t instant = rt[FCC_APP_MSL].instant;
    assert_true(instant > l && instant <= l + t);
    assert_int_equal(rt[FCC_APP_MSL].deadline, instant + FCC_APP_MSL_RT_WINDOW_US);
    uint64_t m = 0u;
    fcc_assert_ok(fcc_tsync_to_master(&g_node.tsync, instant, &m));
    assert_int_equal(m % t, 0u);
    /* inputs received before the guard do not count for this instant */
    push_msl_inputs(instant - FCC_NODE_RT_GUARD_US - 1u);
    assert_int_equal(run_at(rt, instant - 100u, jitter), 0u);
    /* an input stamped ahead of the clock does not release the step before the guard */
    push_msl_inputs(instant);
    assert_int_equal(run_at(rt, instant - FCC_NODE_RT_GUARD_US - 1u, jitter), 0u);
    assert_int_equal(g_node.app[FCC_APP_MSL].steps, 0u);
    /* in, and the guard reached: released at once, jitter 0 (before the instant) */
    assert_int_equal(run_at(rt, instant - FCC_NODE_RT_GUARD_US, jitter), 1u);
    assert_int_equal(jitter[FCC_APP_MSL], 0u);
    assert_int_equal(rt[FCC_APP_MSL].last_instant, instant);
    assert_int_equal(g_node.app[FCC_APP_MSL].steps, 1u);
    /* the next instant, nothing in: released when its window closes */
    const uint64_t next = rt[FCC_APP_MSL].instant;
    assert_int_equal(next, instant + t);
    assert_int_equal(run_at(rt, next + FCC_APP_MSL_RT_WINDOW_US - 1u, jitter), 0u);
    assert_int_equal(run_at(rt, next + FCC_APP_MSL_RT_WINDOW_US, jitter), 1u);
    assert_int_equal(jitter[FCC_APP_MSL], FCC_APP_MSL_RT_WINDOW_US);
    assert_int_equal(g_node.app[FCC_APP_MSL].overruns, 0u);
    /* three periods late: two instants skipped, one step, the overruns counted */
    const uint64_t third = rt[FCC_APP_MSL].instant;
    assert_int_equal(run_at(rt, third + 2u * t + FCC_APP_MSL_RT_WINDOW_US, jitter), 1u);
    assert_int_equal(g_node.app[FCC_APP_MSL].overruns, 2u);
    assert_int_equal(rt[FCC_APP_MSL].last_instant, third + 2u * t);
    assert_int_equal(g_node.app[FCC_APP_MSL].steps, 3u);
    /* the master is gone (no pair for long enough): free-run from now, one period on */
    l = rt[FCC_APP_MSL].instant + 60000000u;
    g_mem.now_us = l;
    (void)fcc_node_sync_poll(&g_node);
    assert_false(fcc_tsync_has_time(&g_node.tsync));
    assert_int_equal(run_at(rt, l, jitter), 0u);
    assert_false(rt[FCC_APP_MSL].synced);
    assert_int_equal(rt[FCC_APP_MSL].deadline, l + t);
    assert_int_equal(run_at(rt, l + t, jitter), 1u);
}

/* With the master's time the identification, which has no release window of its own
 * (fcc_app.h: rt_window_us 0), is released at the latest half a period after its
 * instant; the missile within its window. */
static void test_synced_window_without_its_own_is_half_a_period(void **state)
{
    (void)state;
    start(0.02, true);
    const uint64_t l = have_master_time();
    assert_int_equal(fcc_node_app_ops(FCC_APP_CDRW)->rt_window_us, 0u);
    fcc_node_rt_t rt[FCC_N_APPS];
    fcc_node_rt_start(&g_node, rt, l);
    uint64_t jitter[FCC_N_APPS];
    assert_int_equal(run_at(rt, l, jitter), 0u);
    assert_true(rt[FCC_APP_CDRW].synced && rt[FCC_APP_MSL].synced);
    const uint32_t t_sid = fcc_node_app_period_us(&g_node, FCC_APP_CDRW);
    assert_int_equal(rt[FCC_APP_CDRW].deadline, rt[FCC_APP_CDRW].instant + t_sid / 2u);
    assert_int_equal(rt[FCC_APP_MSL].deadline, rt[FCC_APP_MSL].instant + FCC_APP_MSL_RT_WINDOW_US);
    /* nothing in: the identification steps when its half period is over, not before */
    const uint64_t closes = rt[FCC_APP_CDRW].deadline;
    (void)run_at(rt, closes - 1u, jitter);
    assert_int_equal(g_node.app[FCC_APP_CDRW].steps, 0u);
    (void)run_at(rt, closes, jitter);
    assert_int_equal(g_node.app[FCC_APP_CDRW].steps, 1u);
    assert_int_equal(jitter[FCC_APP_CDRW], t_sid / 2u);
}

/* An rt[] not started by fcc_node_rt_start (all zero: no period) on the ground: its grid
 * stays where it is -- no division by the zero period -- and nothing steps. */
static void test_ground_grid_of_an_unstarted_schedule_stays(void **state)
{
    (void)state;
    start(0.02, true);
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_GROUND, 0.0, 0u);
    poll_frames();
    fcc_node_rt_t rt[FCC_N_APPS];
    memset(rt, 0, sizeof rt);
    uint64_t jitter[FCC_N_APPS];
    assert_int_equal(run_at(rt, 5000000u, jitter), 0u);
    for (uint32_t a = 0u; a < FCC_N_APPS; ++a) {
        assert_int_equal(rt[a].deadline, 0u);
        assert_int_equal(rt[a].k, 0u);
        assert_int_equal(jitter[a], UINT64_MAX);
    }
    assert_int_equal(g_node.app[FCC_APP_MSL].steps + g_node.app[FCC_APP_CDRW].steps, 0u);
}

/* In flight too, a schedule never started has no grid: nothing is released (the period
 * divides the lateness there: a zero period was an integer division by zero). */
static void test_flight_with_an_unstarted_schedule_releases_nothing(void **state)
{
    (void)state;
    start(0.02, true);
    fcc_node_rt_t rt[FCC_N_APPS];
    memset(rt, 0, sizeof rt);
    uint64_t jitter[FCC_N_APPS];
    assert_int_equal(run_at(rt, 5000000u, jitter), 0u);
    for (uint32_t a = 0u; a < FCC_N_APPS; ++a) {
        assert_int_equal(jitter[a], UINT64_MAX);
    }
    assert_int_equal(g_node.app[FCC_APP_MSL].steps + g_node.app[FCC_APP_CDRW].steps, 0u);
}

/* An application's schedule without a period (its rt[] entry never started) is not aligned
 * to the master's instants -- the period divides the master's time there -- and, its
 * deadline not come, nothing steps. */
static void test_a_schedule_without_period_is_not_aligned(void **state)
{
    (void)state;
    start(0.02, false);
    const uint64_t l = have_master_time();
    fcc_node_rt_t rt[FCC_N_APPS];
    fcc_node_rt_start(&g_node, rt, l);
    rt[FCC_APP_MSL].period_us = 0u;
    rt[FCC_APP_MSL].deadline = UINT64_MAX;
    uint64_t jitter[FCC_N_APPS];
    assert_int_equal(run_at(rt, l, jitter), 0u);
    assert_false(rt[FCC_APP_MSL].synced);
    assert_int_equal(rt[FCC_APP_MSL].aligns, 0u);
    assert_int_equal(rt[FCC_APP_MSL].n, 0u);
    assert_int_equal(jitter[FCC_APP_MSL], UINT64_MAX);
    assert_int_equal(g_node.app[FCC_APP_MSL].steps, 0u);
}

/* The node's schedule hooks refuse what is not theirs and change nothing. */
static void test_schedule_hooks_refuse_bad_arguments(void **state)
{
    (void)state;
    start(0.02, true);
    assert_int_equal(fcc_node_run_step(NULL, FCC_APP_MSL, 0u), FCC_ERR_ARG);
    assert_int_equal(fcc_node_run_step(&g_node, FCC_N_APPS, 0u), FCC_ERR_ARG);
    assert_false(fcc_node_inputs_since(NULL, FCC_APP_MSL, 0u));
    assert_false(fcc_node_inputs_since(&g_node, FCC_N_APPS, 0u));
    assert_int_equal(fcc_node_app_period_us(NULL, FCC_APP_MSL), 0u);
    assert_int_equal(fcc_node_app_period_us(&g_node, FCC_N_APPS), 0u);
    assert_false(fcc_node_shutdown_requested(NULL));
    fcc_node_note_overrun(NULL, FCC_APP_MSL, 1u, 0u);
    fcc_node_note_overrun(&g_node, FCC_N_APPS, 1u, 0u);
    fcc_node_note_overrun(&g_node, FCC_APP_MSL, 0u, 0u);
    assert_int_equal(g_node.app[FCC_APP_MSL].overruns + g_node.app[FCC_APP_CDRW].overruns, 0u);
    assert_int_equal(g_mem.ev_count[FCC_EV_OVERRUN], 0u);
    fcc_node_note_overrun(&g_node, FCC_APP_CDRW, 2u, 9u);
    assert_int_equal(g_node.app[FCC_APP_CDRW].overruns, 2u);
    const uint32_t rx = g_node.cnt.rx_frames;
    const fcc_can_frame_t f = {0};
    fcc_node_handle_frame(NULL, &f);
    fcc_node_handle_frame(&g_node, NULL);
    assert_int_equal(g_node.cnt.rx_frames, rx);
    assert_int_equal(g_mem.tx_n, 0u);
}

/* A step whose outputs do not all encode sends none of its secured group (a partial
 * group would not verify): the refusal is counted, the step itself ran.  (The bus is
 * told it no longer produces one message of each group: the only way to make an
 * encoder refuse a finite result.) */
static void test_a_refused_encode_sends_nothing_of_the_group(void **state)
{
    (void)state;
    start(0.02, true);
    g_node.bus.produces &= ~((uint64_t)1u << (uint32_t)FCC_MSG_MSL_STATE_EST);
    g_node.bus.produces &= ~((uint64_t)1u << (uint32_t)FCC_MSG_SID_AZKF_MODEL_B);
    (void)fcc_node_run_step(&g_node, FCC_APP_MSL, 0u); /* its status: the step's, not the send's */
    assert_int_equal(g_node.app[FCC_APP_MSL].steps, 1u);
    assert_int_equal(g_mem.ev_count[FCC_EV_TX_REFUSED], 1u);
    assert_int_equal(g_mem.last_ev[FCC_EV_TX_REFUSED].can_id, FCC_MSG_MSL_ELEV_CMD_AUTH_ID);
    assert_int_equal(g_mem.last_ev[FCC_EV_TX_REFUSED].value, 1); /* the command encoded, alone */
    (void)fcc_node_run_step(&g_node, FCC_APP_CDRW, 0u);
    assert_int_equal(g_mem.ev_count[FCC_EV_TX_REFUSED], 2u);
    assert_int_equal(g_mem.last_ev[FCC_EV_TX_REFUSED].can_id, FCC_MSG_SID_OUT_AUTH_ID);
    assert_int_equal(g_mem.last_ev[FCC_EV_TX_REFUSED].value, (int32_t)FCC_APP_SID_N_FRAMES - 1);
    assert_int_equal(mem_find_tx(&g_mem, 0u, FCC_MSG_MSL_ELEV_CMD_ID, 0u), -1);
    assert_int_equal(mem_find_tx(&g_mem, 0u, FCC_MSG_SID_OUT_AUTH_ID, 0u), -1);
    assert_int_equal(mem_find_tx(&g_mem, 0u, FCC_MSG_SID_AZKF_STATE_ID, 0u), -1);
}

/* fcc_node_init refuses a port without receive or clock, an unknown mode and a zero trip. */
static void test_init_refuses_incomplete_ports_and_configs(void **state)
{
    (void)state;
    static fcc_node_t node;
    mem_port_t *mem = &g_mem;
    fcc_port_t port;
    mem_init(mem, &port);
    fcc_node_config_t cfg;
    fcc_assert_ok(fcc_node_config_default(&cfg));
    mem_secure(&cfg);
    fcc_port_t no_recv = port;
    no_recv.can.recv = NULL;
    assert_int_equal(fcc_node_init(&node, &cfg, &no_recv), FCC_ERR_ARG);
    fcc_port_t no_clock = port;
    no_clock.now_us = NULL;
    assert_int_equal(fcc_node_init(&node, &cfg, &no_clock), FCC_ERR_ARG);
    fcc_node_config_t bad = cfg;
    bad.mode = (fcc_mode_t)7;
    assert_int_equal(fcc_node_init(&node, &bad, &port), FCC_ERR_ARG);
    bad = cfg;
    bad.security.trip = 0u;
    assert_int_equal(fcc_node_init(&node, &bad, &port), FCC_ERR_ARG);
    bad = cfg;
    bad.mode = FCC_MODE_REALTIME;
    fcc_assert_ok(fcc_node_init(&node, &bad, &port));
    fcc_assert_ok(fcc_node_init(&node, &cfg, &port)); /* lockstep */
}

/* A tick for a disabled application is ignored in lockstep too, and counted. */
static void test_lockstep_tick_for_a_disabled_app_is_ignored(void **state)
{
    (void)state;
    fcc_port_t port;
    mem_init(&g_mem, &port);
    fcc_node_config_t cfg;
    fcc_assert_ok(fcc_node_config_default(&cfg));
    cfg.app_enabled[FCC_APP_CDRW] = false;
    mem_secure(&cfg);
    fcc_assert_ok(fcc_node_init(&g_node, &cfg, &port));
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_FLIGHT, 0.0, 0u);
    mem_push_tick(&g_mem, FCC_APP_CDRW, 0u);
    poll_frames();
    assert_int_equal(g_node.app[FCC_APP_CDRW].ticks_ignored, 1u);
    assert_int_equal(g_node.app[FCC_APP_CDRW].steps, 0u);
    assert_int_equal(g_mem.ev_count[FCC_EV_TICK_IGNORED], 1u);
}

/* Every event class has its own name; a value outside the enumeration has one too. */
static void test_every_event_class_is_named(void **state)
{
    (void)state;
    for (int c = 0; c < (int)FCC_EV_COUNT; ++c) {
        const char *name = fcc_event_class_str((fcc_event_class_t)c);
        assert_non_null(name);
        assert_string_not_equal(name, "unknown event");
        for (int d = 0; d < c; ++d) {
            assert_string_not_equal(name, fcc_event_class_str((fcc_event_class_t)d));
        }
    }
    assert_string_equal(fcc_event_class_str(FCC_EV_COUNT), "unknown event");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_free_run_deadlines_autopilot_first),
        cmocka_unit_test(test_late_steps_skip_and_count_overruns),
        cmocka_unit_test(test_ground_keeps_the_grid),
        cmocka_unit_test(test_ground_grid_of_an_unstarted_schedule_stays),
        cmocka_unit_test(test_flight_with_an_unstarted_schedule_releases_nothing),
        cmocka_unit_test(test_synced_release_inputs_or_window),
        cmocka_unit_test(test_synced_window_without_its_own_is_half_a_period),
        cmocka_unit_test(test_a_schedule_without_period_is_not_aligned),
        cmocka_unit_test(test_schedule_hooks_refuse_bad_arguments),
        cmocka_unit_test(test_a_refused_encode_sends_nothing_of_the_group),
        cmocka_unit_test(test_init_refuses_incomplete_ports_and_configs),
        cmocka_unit_test(test_lockstep_tick_for_a_disabled_app_is_ignored),
        cmocka_unit_test(test_every_event_class_is_named),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
