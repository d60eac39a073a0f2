/*
 * test_app_iface.c -- the node's one application interface (firmware/app/fcc_app.h): every
 * application of the build has the whole of it and its inputs are the DBC's; an id without
 * an application in this build is refused at start and its ticks are ignored, never run
 * down another application's path; in the probe build (cmake -DFCC_APP_PROBE=ON) the third
 * application's ticks run its own step.
 */
#include "fcc_test.h"

/* the in-memory port's helpers are static; this test uses only some of them */
#pragma GCC diagnostic ignored "-Wunused-function"
#include "test_app_port.h"

static fcc_node_t g_node;
static mem_port_t g_mem;

static void test_every_application_has_the_whole_interface(void **state)
{
    (void)state;
    uint32_t apps = 0u;
    for (uint32_t a = 0u; a < FCC_N_APPS; ++a) {
        const fcc_app_ops_t *ops = fcc_node_app_ops(a);
        if (ops == NULL) {
            continue;
        }
        ++apps;
        assert_non_null(ops->name);
        assert_non_null(ops->init);
        assert_non_null(ops->reset);
        assert_non_null(ops->sensor);
        assert_non_null(ops->input);
        assert_non_null(ops->offer);
        assert_non_null(ops->step);
        assert_non_null(ops->encode);
        assert_non_null(ops->period_us);
        /* the design hooks come together or not at all */
        assert_true((ops->request == NULL) == (ops->background == NULL));
        assert_true((ops->background == NULL) == (ops->wants_background == NULL));
        assert_int_equal(fcc_node_app_named(ops->name, (uint32_t)strlen(ops->name)), a);
        /* its inputs are the DBC's (FccApp): each one maps back to it */
        assert_true(ops->n_inputs <= FCC_BUS_MAX_APP_INPUTS);
        for (uint32_t i = 0u; i < ops->n_inputs; ++i) {
            assert_int_equal(fcc_bus_input_app[ops->inputs[i]], a);
        }
        assert_null(ops->input(NULL, 0u));
    }
    assert_true(apps >= 2u);
    assert_null(fcc_node_app_ops(FCC_N_APPS));
    assert_int_equal(fcc_node_app_named("cdrw", 4u), FCC_APP_CDRW);
    assert_int_equal(fcc_node_app_named("missile", 7u), FCC_APP_MSL);
    assert_int_equal(fcc_node_app_named("missil", 6u), FCC_N_APPS);
    assert_int_equal(fcc_node_app_named(NULL, 0u), FCC_N_APPS);
    assert_int_equal(fcc_node_app_ops(FCC_APP_MSL)->rt_window_us, FCC_APP_MSL_RT_WINDOW_US);
}

static void start(fcc_node_config_t *c)
{
    fcc_port_t port;
    mem_init(&g_mem, &port);
    mem_secure(c);
    fcc_assert_ok(fcc_node_init(&g_node, c, &port));
    mem_push_control(&g_mem, FCC_MSG_SIM_CONTROL_COMMAND_FLIGHT, 0.0, 0u);
    fcc_assert_ok(fcc_node_poll(&g_node, 1000u, NULL));
}

/* The answer to a tick of the probe's id (SIM_TICK.app PROBE): in a build without it, ignored
 * (no step of any application, no ACK); in the probe build, its own step and ACK. */
static void test_the_third_id_takes_its_own_path(void **state)
{
    (void)state;
    fcc_node_config_t c;
    fcc_assert_ok(fcc_node_config_default(&c));
    const bool built = fcc_node_app_ops(FCC_BUS_APP_PROBE) != NULL;
    assert_true(c.app_enabled[FCC_BUS_APP_PROBE] == built);
    if (!built) {
        fcc_node_config_t on = c;
        mem_secure(&on);
        on.app_enabled[FCC_BUS_APP_PROBE] = true;
        fcc_port_t port;
        mem_init(&g_mem, &port);
        assert_int_equal(fcc_node_init(&g_node, &on, &port), FCC_ERR_ARG); /* not in this build */
        assert_int_equal(fcc_node_app_period_us(&g_node, FCC_BUS_APP_PROBE), 0u);
    }
    start(&c);
    for (uint32_t k = 0u; k < 4u; ++k) {
        const size_t first = g_mem.tx_n;
        mem_push_tick(&g_mem, FCC_BUS_APP_PROBE, k);
        fcc_assert_ok(fcc_node_poll(&g_node, 1000u, NULL));
        const long ack = mem_find_tx(&g_mem, first, FCC_MSG_FCC_ACK_ID, 0u);
        if (!built) {
            assert_int_equal(ack, -1);
            assert_int_equal(g_node.app[FCC_BUS_APP_PROBE].ticks_ignored, k + 1u);
            continue;
        }
        assert_int_equal(g_mem.tx_n - first, 1u); /* no outputs of its own: the ACK alone */
        const fcc_msg_data_t d = mem_decode_tx(&g_mem, ack);
        assert_int_equal(d.fcc_ack.app, FCC_BUS_APP_PROBE);
        assert_int_equal(d.fcc_ack.step, k);
        assert_true(d.fcc_ack.degraded == ((k & 1u) != 0u)); /* the probe's own answer */
    }
    assert_int_equal(g_node.app[FCC_APP_MSL].steps, 0u);  /* nothing fell into the missile's */
    assert_int_equal(g_node.app[FCC_APP_CDRW].steps, 0u); /* or the identification's path */
    assert_int_equal(g_node.app[FCC_BUS_APP_PROBE].steps, built ? 4u : 0u);
}

/* Each application's read-only input slots: its own, none past them and none without an
 * instance; a name of the right length but other letters names no application; an id without
 * inputs (the probe's, built or not) has all of them in. */
static void test_input_slots_and_names_are_bounded(void **state)
{
    (void)state;
    fcc_node_config_t c;
    fcc_assert_ok(fcc_node_config_default(&c));
    start(&c);
    for (uint32_t i = 0u; i < FCC_APP_SID_N_INPUTS; ++i) {
        assert_ptr_equal(fcc_app_sid_ops.input(&g_node.sid, i), &g_node.sid.in[i]);
    }
    assert_null(fcc_app_sid_ops.input(&g_node.sid, FCC_APP_SID_N_INPUTS));
    assert_null(fcc_app_sid_ops.input(NULL, 0u));
    for (uint32_t i = 0u; i < FCC_APP_MSL_N_INPUTS; ++i) {
        assert_ptr_equal(fcc_app_msl_ops.input(&g_node.msl, i), &g_node.msl.in[i]);
    }
    assert_null(fcc_app_msl_ops.input(&g_node.msl, FCC_APP_MSL_N_INPUTS));
    assert_null(fcc_app_msl_ops.input(NULL, 0u));
    assert_int_equal(fcc_node_app_named("cdrx", 4u), FCC_N_APPS);
    assert_int_equal(fcc_node_app_named("missila", 7u), FCC_N_APPS);
    assert_true(fcc_node_inputs_since(&g_node, FCC_BUS_APP_PROBE, UINT64_MAX));
    assert_false(fcc_node_inputs_since(&g_node, FCC_APP_MSL, 0u)); /* nothing received yet */
}

/* An application whose configuration its init refuses stops the node's start with that
 * status; the applications after it are not started on a failed node. */
static void test_a_refused_application_config_fails_the_start(void **state)
{
    (void)state;
    fcc_node_config_t c;
    fcc_assert_ok(fcc_node_config_default(&c));
    mem_secure(&c);
    c.msl.period = (fcc_real_t)0.0; /* no valid sampling period */
    fcc_port_t port;
    mem_init(&g_mem, &port);
    assert_int_equal(fcc_node_init(&g_node, &c, &port), FCC_ERR_RANGE);
    fcc_assert_ok(fcc_node_config_default(&c));
    start(&c); /* the default one starts */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_application_has_the_whole_interface),
        cmocka_unit_test(test_the_third_id_takes_its_own_path),
        cmocka_unit_test(test_input_slots_and_names_are_bounded),
        cmocka_unit_test(test_a_refused_application_config_fails_the_start),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
