/*
 * test_app_sensor.c -- per-step sensor verdicts (firmware/app/fcc_sensor.h).
 */
#include "fcc_test.h"

#include "fcc_sensor.h"

static fcc_sensor_state_t close_at(fcc_sensor_t *s, uint16_t step, uint16_t limit,
                                   fcc_sensor_sample_t *out)
{
    return fcc_sensor_close(s, true, step, limit, out);
}

static void test_ok_uses_newest_aligned(void **state)
{
    (void)state;
    fcc_sensor_t s;
    fcc_sensor_init(&s, 0x50u);
    fcc_sensor_sample_t out = {0};
    assert_int_equal(s.state, FCC_SENSOR_STALE);
    fcc_assert_ok(fcc_sensor_offer(&s, FCC_R(0.1), 3u, 100u));
    fcc_assert_ok(fcc_sensor_offer(&s, FCC_R(0.2), 4u, 200u)); /* delayed frame of another step */
    fcc_assert_ok(fcc_sensor_offer(&s, FCC_R(0.3), 3u, 300u)); /* duplicate, newer */
    assert_int_equal(close_at(&s, 3u, 1u, &out), FCC_SENSOR_OK);
    fcc_assert_close(out.value, 0.3, 0.0, 1e-7);
    assert_int_equal(out.t_us, 300u);
    /* realtime: the step field is not compared, the newest frame wins */
    fcc_assert_ok(fcc_sensor_offer(&s, FCC_R(0.4), 9u, 400u));
    fcc_assert_ok(fcc_sensor_offer(&s, FCC_R(0.5), 1u, 500u));
    assert_int_equal(fcc_sensor_close(&s, false, 4u, 1u, &out), FCC_SENSOR_OK);
    fcc_assert_close(out.value, 0.5, 0.0, 1e-7);
}

static void test_hold_then_stale_then_recover(void **state)
{
    (void)state;
    fcc_sensor_t s;
    fcc_sensor_init(&s, 0x40u);
    fcc_sensor_sample_t out = {0};
    assert_int_equal(close_at(&s, 0u, 2u, &out), FCC_SENSOR_STALE); /* never seen */
    fcc_assert_ok(fcc_sensor_offer(&s, FCC_R(1.5), 1u, 10u));
    assert_int_equal(close_at(&s, 1u, 2u, &out), FCC_SENSOR_OK);
    out.value = FCC_R(0.0);
    assert_int_equal(close_at(&s, 2u, 2u, &out), FCC_SENSOR_HELD);
    fcc_assert_close(out.value, 1.5, 0.0, 1e-7);
    assert_int_equal(close_at(&s, 3u, 2u, &out), FCC_SENSOR_HELD);
    assert_int_equal(close_at(&s, 4u, 2u, &out), FCC_SENSOR_STALE);
    assert_int_equal(s.missing_run, 3u);
    assert_false(fcc_sensor_usable(s.state));
    fcc_assert_ok(fcc_sensor_offer(&s, FCC_R(-1.0), 5u, 50u));
    assert_int_equal(close_at(&s, 5u, 2u, &out), FCC_SENSOR_OK);
    assert_int_equal(s.missing_run, 0u);
    assert_int_equal(s.count[FCC_SENSOR_OK], 2u);
    assert_int_equal(s.count[FCC_SENSOR_HELD], 2u);
    assert_int_equal(s.count[FCC_SENSOR_STALE], 2u);
    /* stale limit 0: the first missing frame is already stale */
    assert_int_equal(close_at(&s, 6u, 0u, &out), FCC_SENSOR_STALE);
}

static void test_rejected_and_misaligned_are_not_held(void **state)
{
    (void)state;
    fcc_sensor_t s;
    fcc_sensor_init(&s, 0x51u);
    fcc_sensor_sample_t out = {0};
    fcc_assert_ok(fcc_sensor_offer(&s, FCC_R(0.7), 0u, 1u));
    assert_int_equal(close_at(&s, 0u, 5u, &out), FCC_SENSOR_OK);
    fcc_sensor_reject(&s);
    out.value = FCC_R(9.0);
    assert_int_equal(close_at(&s, 1u, 5u, &out), FCC_SENSOR_REJECTED);
    fcc_assert_close(out.value, 9.0, 0.0, 0.0); /* untouched: no value to use */
    fcc_assert_ok(fcc_sensor_offer(&s, FCC_R(0.8), 7u, 2u));
    assert_int_equal(close_at(&s, 2u, 5u, &out), FCC_SENSOR_MISALIGNED);
    /* a rejected frame and a good one in the same step: the good one is used */
    fcc_sensor_reject(&s);
    fcc_assert_ok(fcc_sensor_offer(&s, FCC_R(0.9), 3u, 3u));
    assert_int_equal(close_at(&s, 3u, 5u, &out), FCC_SENSOR_OK);
    fcc_assert_close(out.value, 0.9, 0.0, 1e-7);
}

static void test_non_finite_and_overflow(void **state)
{
    (void)state;
    fcc_sensor_t s;
    fcc_sensor_init(&s, 0x52u);
    fcc_sensor_sample_t out = {0};
    const fcc_real_t zero = FCC_R(0.0);
    assert_int_equal(fcc_sensor_offer(&s, zero / zero, 0u, 0u), FCC_ERR_NOT_FINITE);
    assert_int_equal(close_at(&s, 0u, 1u, &out), FCC_SENSOR_REJECTED);
    for (unsigned int i = 0u; i < 10u; ++i) { /* more than FCC_SENSOR_MAX_PENDING */
        fcc_assert_ok(fcc_sensor_offer(&s, (fcc_real_t)i, (uint16_t)i, i));
    }
    assert_int_equal(s.n_pending, FCC_SENSOR_MAX_PENDING);
    assert_int_equal(close_at(&s, 9u, 1u, &out), FCC_SENSOR_OK);
    fcc_assert_close(out.value, 9.0, 0.0, 0.0);
    assert_int_equal(close_at(&s, 0u, 1u, &out), FCC_SENSOR_HELD); /* old frames are gone */
    fcc_sensor_reset(&s);
    assert_int_equal(close_at(&s, 0u, 1u, &out), FCC_SENSOR_STALE);
    assert_int_equal(fcc_sensor_offer(NULL, FCC_R(0.0), 0u, 0u), FCC_ERR_ARG);
    assert_int_equal(fcc_sensor_close(NULL, true, 0u, 1u, &out), FCC_SENSOR_STALE);
    assert_string_equal(fcc_sensor_state_str(FCC_SENSOR_MISALIGNED), "MISALIGNED");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ok_uses_newest_aligned),
        cmocka_unit_test(test_hold_then_stale_then_recover),
        cmocka_unit_test(test_rejected_and_misaligned_are_not_held),
        cmocka_unit_test(test_non_finite_and_overflow),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
