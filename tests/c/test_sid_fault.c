/* fcc_fault: the set-membership test with its margin, the raise / hold /
 * clear counts, the oracle and off modes. */
#include "fcc_test.h"

#include "fcc_fault.h"

static const fcc_real_t radius[2] = {FCC_R(0.1), FCC_R(0.2)};
static const fcc_real_t inside[2] = {FCC_R(0.05), FCC_R(-0.15)};
static const fcc_real_t outside[2] = {FCC_R(0.05), FCC_R(0.35)};

static bool step(fcc_fdet_t *d, const fcc_real_t innov[2], bool oracle)
{
    bool fault = false;
    fcc_assert_ok(fcc_fdet_step(d, innov, radius, oracle, &fault));
    return fault;
}

static fcc_fdet_config_t cfg_with(fcc_fdet_mode_t mode, fcc_real_t margin, uint16_t raise,
                                  uint16_t hold, uint16_t clear)
{
    fcc_fdet_config_t c;
    fcc_fdet_config_default(&c);
    c.mode = mode;
    c.margin = margin;
    c.raise_count = raise;
    c.hold_count = hold;
    c.clear_count = clear;
    c.max_fault_steps = 0u;
    return c;
}

static void margin_scales_the_hull(void **state)
{
    (void)state;
    fcc_fdet_t d;
    /* |0.35| > 1.0 * 0.2: inconsistent; with margin 2: 0.35 <= 0.4, consistent. */
    fcc_fdet_config_t c = cfg_with(FCC_FDET_ZONOTOPE, FCC_R(1.0), 1u, 0u, 1u);
    fcc_assert_ok(fcc_fdet_init(&d, &c));
    assert_false(step(&d, inside, false));
    assert_true(step(&d, outside, false));
    assert_true(d.inconsistent);
    c.margin = FCC_R(2.0);
    fcc_assert_ok(fcc_fdet_init(&d, &c));
    assert_false(step(&d, outside, false));
    /* On the boundary is consistent; a NaN innovation is not. */
    const fcc_real_t edge[2] = {FCC_R(-0.2), FCC_R(0.4)};
    assert_false(step(&d, edge, false));
    const fcc_real_t nan_innov[2] = {(fcc_real_t)NAN, 0};
    assert_true(step(&d, nan_innov, false));
}

static void raise_hold_clear_counts(void **state)
{
    (void)state;
    fcc_fdet_t d;
    const fcc_fdet_config_t c = cfg_with(FCC_FDET_ZONOTOPE, FCC_R(1.0), 2u, 3u, 2u);
    fcc_assert_ok(fcc_fdet_init(&d, &c));
    /* raise = 2: one outlier alone is not a fault. */
    assert_false(step(&d, outside, false));
    assert_false(step(&d, inside, false));
    assert_false(step(&d, outside, false));
    assert_true(step(&d, outside, false)); /* second in a row: raised */
    assert_int_equal(d.n_raised, 1);
    /* hold = 3: stays up three steps whatever the data. */
    assert_true(step(&d, inside, false));
    assert_true(step(&d, inside, false));
    assert_true(step(&d, inside, false));
    /* clear = 2 consecutive consistent steps after the hold. */
    assert_true(step(&d, inside, false));
    assert_true(step(&d, outside, false)); /* resets the run */
    assert_true(step(&d, inside, false));
    assert_false(step(&d, inside, false));
    assert_false(step(&d, inside, false));
    assert_int_equal(d.n_raised, 1);
}

static void defaults_raise_at_once(void **state)
{
    (void)state;
    fcc_fdet_config_t c;
    fcc_fdet_config_default(&c);
    assert_int_equal(c.mode, FCC_FDET_ZONOTOPE);
    assert_int_equal(c.raise_count, 1);
    fcc_fdet_t d;
    fcc_assert_ok(fcc_fdet_init(&d, &c));
    const fcc_real_t far[2] = {FCC_R(1.0), 0};
    assert_true(step(&d, far, false));
    /* clear_count consistent steps clear it (hold 0). */
    for (uint16_t i = 0; i + 1u < c.clear_count; ++i) {
        assert_true(step(&d, inside, false));
    }
    assert_false(step(&d, inside, false));
}

static void persistent_fault_is_dropped(void **state)
{
    (void)state;
    fcc_fdet_t d;
    fcc_fdet_config_t c = cfg_with(FCC_FDET_ZONOTOPE, FCC_R(1.0), 1u, 0u, 1u);
    c.max_fault_steps = 4u;
    fcc_assert_ok(fcc_fdet_init(&d, &c));
    /* Inconsistent for ever: flagged 4 steps, then 4 steps without a fault
     * (refractory), then flagged again. */
    for (int round = 0; round < 3; ++round) {
        for (int i = 0; i < 4; ++i) {
            assert_true(step(&d, outside, false));
        }
        for (int i = 0; i < 5; ++i) {
            assert_false(step(&d, outside, false));
        }
    }
    assert_int_equal(d.n_raised, 3);
    assert_int_equal(d.n_dropped, 3);
    /* Without a limit it stays up. */
    c.max_fault_steps = 0u;
    fcc_assert_ok(fcc_fdet_init(&d, &c));
    for (int i = 0; i < 100; ++i) {
        assert_true(step(&d, outside, false));
    }
}

static void oracle_and_off(void **state)
{
    (void)state;
    fcc_fdet_t d;
    fcc_fdet_config_t c = cfg_with(FCC_FDET_ORACLE, FCC_R(1.0), 5u, 5u, 5u);
    fcc_assert_ok(fcc_fdet_init(&d, &c));
    /* The oracle flag is used as given: no debouncing, innovation ignored. */
    assert_false(step(&d, outside, false));
    assert_true(step(&d, inside, true));
    assert_false(step(&d, outside, false));
    bool fault = true;
    fcc_assert_ok(fcc_fdet_step(&d, NULL, NULL, true, &fault));
    assert_true(fault);
    c.mode = FCC_FDET_OFF;
    fcc_assert_ok(fcc_fdet_init(&d, &c));
    assert_false(step(&d, outside, true));
    fcc_assert_ok(fcc_fdet_step(&d, NULL, NULL, true, &fault));
    assert_false(fault);
}

static void bad_configuration(void **state)
{
    (void)state;
    fcc_fdet_t d;
    fcc_fdet_config_t c = cfg_with(FCC_FDET_ZONOTOPE, FCC_R(0.0), 1u, 0u, 1u);
    assert_int_equal(fcc_fdet_init(&d, &c), FCC_ERR_RANGE);
    c = cfg_with(FCC_FDET_ZONOTOPE, (fcc_real_t)NAN, 1u, 0u, 1u);
    assert_int_equal(fcc_fdet_init(&d, &c), FCC_ERR_RANGE);
    c = cfg_with(FCC_FDET_ZONOTOPE, FCC_R(1.0), 0u, 0u, 1u);
    assert_int_equal(fcc_fdet_init(&d, &c), FCC_ERR_RANGE);
    c = cfg_with(FCC_FDET_ZONOTOPE, FCC_R(1.0), 1u, 0u, 0u);
    assert_int_equal(fcc_fdet_init(&d, &c), FCC_ERR_RANGE);
    c = cfg_with((fcc_fdet_mode_t)9, FCC_R(1.0), 1u, 0u, 1u);
    assert_int_equal(fcc_fdet_init(&d, &c), FCC_ERR_ARG);
    c = cfg_with(FCC_FDET_ZONOTOPE, FCC_R(1.0), 1u, 0u, 1u);
    fcc_assert_ok(fcc_fdet_init(&d, &c));
    bool fault;
    assert_int_equal(fcc_fdet_step(&d, NULL, radius, false, &fault), FCC_ERR_ARG);
    assert_int_equal(fcc_fdet_step(&d, inside, radius, false, NULL), FCC_ERR_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(margin_scales_the_hull),
        cmocka_unit_test(raise_hold_clear_counts),
        cmocka_unit_test(defaults_raise_at_once),
        cmocka_unit_test(persistent_fault_is_dropped),
        cmocka_unit_test(oracle_and_off),
        cmocka_unit_test(bad_configuration),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
