/*
 * test_bootcfg.c -- the boot configuration record (firmware/app/fcc_bootcfg.h):
 * the CRC-32 check value, the named layout against the table of
 * firmware/port/mps2_an386/README.md, a record written through it, and every
 * refusal (no record, version, length, CRC, each field out of range) leaving
 * the configuration untouched.
 */
#include "fcc_test.h"

#include <math.h>
#include <string.h>

#include "fcc_bootcfg.h"
#include "fcc_cfg_limits.h"

static void put16(uint8_t *p, uint16_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
}

static void put32(uint8_t *p, uint32_t v)
{
    for (unsigned i = 0u; i < 4u; ++i) {
        p[i] = (uint8_t)(v >> (8u * i));
    }
}

static void put_f32(uint8_t *p, float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    put32(p, u);
}

static void put_f64(uint8_t *p, double d)
{
    uint64_t u;
    memcpy(&u, &d, sizeof u);
    put32(p, (uint32_t)u);
    put32(p + 4, (uint32_t)(u >> 32));
}

static void seal(uint8_t rec[FCC_BOOTCFG_SIZE])
{
    put32(&rec[FCC_BOOTCFG_CRC_OFF], fcc_bootcfg_crc32(rec, FCC_BOOTCFG_CRC_OFF));
}

/* Realtime, missile only, stale limit 3, 20 Hz, T = 0.1 s, 12 bits, oracle,
 * skip, variances 0.5 / 2.0, input delay 5 ms. */
static void record(uint8_t rec[FCC_BOOTCFG_SIZE])
{
    memset(rec, 0, FCC_BOOTCFG_SIZE);
    memcpy(&rec[FCC_BOOTCFG_MAGIC_OFF], "FCCB", 4u);
    put16(&rec[FCC_BOOTCFG_VERSION_OFF], 1u);
    put16(&rec[FCC_BOOTCFG_LENGTH_OFF], 64u);
    rec[FCC_BOOTCFG_MODE_OFF] = FCC_BOOTCFG_MODE_REALTIME;
    rec[FCC_BOOTCFG_APPS_OFF] = FCC_BOOTCFG_APP_MSL;
    put16(&rec[FCC_BOOTCFG_STALE_LIMIT_OFF], 3u);
    put_f32(&rec[FCC_BOOTCFG_STATUS_RATE_OFF], 20.0f);
    put_f64(&rec[FCC_BOOTCFG_LQG_PERIOD_OFF], 0.1);
    rec[FCC_BOOTCFG_LQG_BITS_OFF] = 12u;
    rec[FCC_BOOTCFG_DETECTOR_OFF] = 1u;
    rec[FCC_BOOTCFG_FAULT_POLICY_OFF] = 1u;
    put_f64(&rec[FCC_BOOTCFG_GYRO_VAR_OFF], 0.5);
    put_f64(&rec[FCC_BOOTCFG_ACCEL_VAR_OFF], 2.0);
    put_f64(&rec[FCC_BOOTCFG_LQG_DELAY_OFF], 0.005);
    seal(rec);
}

/* The named layout is the documented one (the README's table, written out
 * here by hand) and covers the record with no gap or overlap. */
static void test_layout_is_the_documented_table(void **state)
{
    (void)state;
    static const struct {
        unsigned off;
        unsigned len;
        unsigned doc_off;
        unsigned doc_len;
    } fields[] = {
        {FCC_BOOTCFG_MAGIC_OFF, FCC_BOOTCFG_MAGIC_LEN, 0u, 4u},
        {FCC_BOOTCFG_VERSION_OFF, FCC_BOOTCFG_VERSION_LEN, 4u, 2u},
        {FCC_BOOTCFG_LENGTH_OFF, FCC_BOOTCFG_LENGTH_LEN, 6u, 2u},
        {FCC_BOOTCFG_MODE_OFF, FCC_BOOTCFG_MODE_LEN, 8u, 1u},
        {FCC_BOOTCFG_APPS_OFF, FCC_BOOTCFG_APPS_LEN, 9u, 1u},
        {FCC_BOOTCFG_STALE_LIMIT_OFF, FCC_BOOTCFG_STALE_LIMIT_LEN, 10u, 2u},
        {FCC_BOOTCFG_STATUS_RATE_OFF, FCC_BOOTCFG_STATUS_RATE_LEN, 12u, 4u},
        {FCC_BOOTCFG_LQG_PERIOD_OFF, FCC_BOOTCFG_LQG_PERIOD_LEN, 16u, 8u},
        {FCC_BOOTCFG_LQG_BITS_OFF, FCC_BOOTCFG_LQG_BITS_LEN, 24u, 1u},
        {FCC_BOOTCFG_DETECTOR_OFF, FCC_BOOTCFG_DETECTOR_LEN, 25u, 1u},
        {FCC_BOOTCFG_FAULT_POLICY_OFF, FCC_BOOTCFG_FAULT_POLICY_LEN, 26u, 1u},
        {FCC_BOOTCFG_PAD_OFF, FCC_BOOTCFG_PAD_LEN, 27u, 1u},
        {FCC_BOOTCFG_GYRO_VAR_OFF, FCC_BOOTCFG_GYRO_VAR_LEN, 28u, 8u},
        {FCC_BOOTCFG_ACCEL_VAR_OFF, FCC_BOOTCFG_ACCEL_VAR_LEN, 36u, 8u},
        {FCC_BOOTCFG_LQG_DELAY_OFF, FCC_BOOTCFG_LQG_DELAY_LEN, 44u, 8u},
        {FCC_BOOTCFG_RESERVED_OFF, FCC_BOOTCFG_RESERVED_LEN, 52u, 8u},
        {FCC_BOOTCFG_CRC_OFF, FCC_BOOTCFG_CRC_LEN, 60u, 4u},
    };
    unsigned end = 0u;
    for (size_t i = 0u; i < sizeof fields / sizeof fields[0]; ++i) {
        assert_int_equal(fields[i].off, fields[i].doc_off);
        assert_int_equal(fields[i].len, fields[i].doc_len);
        assert_int_equal(fields[i].off, end);
        end += fields[i].len;
    }
    assert_int_equal(end, FCC_BOOTCFG_SIZE);
    assert_int_equal(FCC_BOOTCFG_SIZE, 64u);
    assert_memory_equal(FCC_BOOTCFG_MAGIC, "FCCB", FCC_BOOTCFG_MAGIC_LEN);
}

static void test_crc32_check_value(void **state)
{
    (void)state;
    const uint8_t check[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
    assert_int_equal(fcc_bootcfg_crc32(check, sizeof check), 0xCBF43926u);
    assert_int_equal(fcc_bootcfg_crc32(NULL, 0u), 0u);
}

static void test_record_applied(void **state)
{
    (void)state;
    uint8_t rec[FCC_BOOTCFG_SIZE];
    record(rec);
    fcc_node_config_t cfg;
    fcc_assert_ok(fcc_node_config_default(&cfg));
    float rate = 10.0f;
    const char *field = "x";
    fcc_assert_ok(fcc_bootcfg_apply(rec, &cfg, &rate, &field));
    assert_null(field);
    assert_int_equal(cfg.mode, FCC_MODE_REALTIME);
    assert_false(cfg.app_enabled[FCC_APP_CDRW]);
    assert_true(cfg.app_enabled[FCC_APP_MSL]);
    assert_int_equal(cfg.stale_limit, 3u);
    assert_true(rate == 20.0f);
    assert_true(cfg.msl.period == (fcc_real_t)0.1);
    assert_int_equal(cfg.msl.bits, 12u);
    assert_int_equal(cfg.sid.base.azkf.det.mode, FCC_FDET_ORACLE);
    assert_int_equal(cfg.sid.base.azkf.policy, FCC_AZKF_POLICY_SKIP);
    assert_true(cfg.msl.plant.gyro_var == (fcc_real_t)0.5);
    assert_true(cfg.msl.plant.accel_var == (fcc_real_t)2.0);
    assert_true(cfg.msl.delay == (fcc_real_t)0.005);
}

/* Zero delay bytes (records written before the field existed) mean no delay. */
static void test_zero_delay_bytes_mean_no_delay(void **state)
{
    (void)state;
    uint8_t rec[FCC_BOOTCFG_SIZE];
    record(rec);
    memset(&rec[FCC_BOOTCFG_LQG_DELAY_OFF], 0, FCC_BOOTCFG_LQG_DELAY_LEN);
    seal(rec);
    fcc_node_config_t cfg;
    fcc_assert_ok(fcc_node_config_default(&cfg));
    cfg.msl.delay = FCC_R(0.001);
    float rate = 10.0f;
    const char *field = NULL;
    fcc_assert_ok(fcc_bootcfg_apply(rec, &cfg, &rate, &field));
    assert_true(cfg.msl.delay == FCC_R(0.0));
}

static void test_refusals_change_nothing(void **state)
{
    (void)state;
    static const struct {
        unsigned offset;
        uint8_t value;
        bool reseal;
        fcc_status_t status;
        const char *field;
    } cases[] = {
        {FCC_BOOTCFG_MAGIC_OFF, 0xFFu, true, FCC_ERR_AGAIN, NULL},            /* erased flash: no record */
        {FCC_BOOTCFG_VERSION_OFF, 2u, true, FCC_ERR_FORMAT, "version"},
        {FCC_BOOTCFG_LENGTH_OFF, 63u, true, FCC_ERR_FORMAT, "length"},
        {FCC_BOOTCFG_LQG_PERIOD_OFF + 4u, 0x01u, false, FCC_ERR_FORMAT, "crc"},        /* a flipped bit */
        {FCC_BOOTCFG_MODE_OFF, 2u, true, FCC_ERR_RANGE, "mode"},
        {FCC_BOOTCFG_APPS_OFF, 0u, true, FCC_ERR_RANGE, "apps"},
        {FCC_BOOTCFG_APPS_OFF, 4u, true, FCC_ERR_RANGE, "apps"},
        {FCC_BOOTCFG_STALE_LIMIT_OFF + 1u, 0x04u, true, FCC_ERR_RANGE, "stale_limit"}, /* 1027 */
        {FCC_BOOTCFG_LQG_BITS_OFF, 17u, true, FCC_ERR_RANGE, "lqg_bits"},
        {FCC_BOOTCFG_LQG_BITS_OFF, 1u, true, FCC_ERR_RANGE, "lqg_bits"},
        {FCC_BOOTCFG_LQG_PERIOD_OFF + 7u, 0x40u, true, FCC_ERR_RANGE, "lqg_period"},  /* 0.1 -> 2.x */
        {FCC_BOOTCFG_DETECTOR_OFF, 3u, true, FCC_ERR_RANGE, "detector"},
        {FCC_BOOTCFG_FAULT_POLICY_OFF, 2u, true, FCC_ERR_RANGE, "fault_policy"},
        {FCC_BOOTCFG_GYRO_VAR_OFF + 7u, 0xFFu, true, FCC_ERR_RANGE, "gyro_var"},    /* 0.5 -> -2^1023 */
        {FCC_BOOTCFG_ACCEL_VAR_OFF + 7u, 0x80u, true, FCC_ERR_RANGE, "accel_var"},   /* 2.0 -> -0.0 */
        {FCC_BOOTCFG_STATUS_RATE_OFF + 3u, 0xFFu, true, FCC_ERR_RANGE, "status_rate"}, /* NaN */
        {FCC_BOOTCFG_LQG_DELAY_OFF + 7u, 0xBFu, true, FCC_ERR_RANGE, "lqg_delay"},   /* 0.005 -> negative */
        {FCC_BOOTCFG_LQG_DELAY_OFF + 6u, 0xBCu, true, FCC_ERR_RANGE, "lqg_delay"},   /* 0.005 -> 0.11125: not < T = 0.1 */
        {FCC_BOOTCFG_LQG_DELAY_OFF + 7u, 0x40u, true, FCC_ERR_RANGE, "lqg_delay"},   /* 0.005 -> 327.68 */
    };
    for (size_t i = 0u; i < sizeof cases / sizeof cases[0]; ++i) {
        uint8_t rec[FCC_BOOTCFG_SIZE];
        record(rec);
        const unsigned at = cases[i].offset;
        rec[at] = cases[i].reseal ? cases[i].value : (uint8_t)(rec[at] ^ cases[i].value);
        if (cases[i].reseal) {
            seal(rec);
        }
        fcc_node_config_t cfg;
        fcc_node_config_t before;
        fcc_assert_ok(fcc_node_config_default(&cfg));
        memcpy(&before, &cfg, sizeof cfg);
        float rate = 10.0f;
        const char *field = NULL;
        const fcc_status_t st = fcc_bootcfg_apply(rec, &cfg, &rate, &field);
        if (st != cases[i].status) {
            fail_msg("case %zu (offset %u): status %d, expected %d", i, cases[i].offset, (int)st,
                     (int)cases[i].status);
        }
        if (cases[i].field == NULL) {
            assert_null(field);
        } else {
            assert_non_null(field);
            assert_string_equal(field, cases[i].field);
        }
        assert_memory_equal(&cfg, &before, sizeof cfg);
        assert_true(rate == 10.0f);
    }
    fcc_node_config_t cfg;
    float rate = 0.0f;
    const char *field = NULL;
    uint8_t rec[FCC_BOOTCFG_SIZE];
    record(rec);
    assert_int_equal(fcc_bootcfg_apply(NULL, &cfg, &rate, &field), FCC_ERR_ARG);
    assert_int_equal(fcc_bootcfg_apply(rec, NULL, &rate, &field), FCC_ERR_ARG);
    assert_int_equal(fcc_bootcfg_apply(rec, &cfg, NULL, &field), FCC_ERR_ARG);
    assert_int_equal(fcc_bootcfg_apply(rec, &cfg, &rate, NULL), FCC_ERR_ARG);
}

/* A lockstep record is applied as lockstep. */
static void test_lockstep_record_applied(void **state)
{
    (void)state;
    uint8_t rec[FCC_BOOTCFG_SIZE];
    record(rec);
    rec[FCC_BOOTCFG_MODE_OFF] = FCC_BOOTCFG_MODE_LOCKSTEP;
    seal(rec);
    const char *field = "x";
    fcc_node_config_t cfg;
    fcc_assert_ok(fcc_node_config_default(&cfg));
    cfg.mode = FCC_MODE_REALTIME;
    float rate = 0.0f;
    fcc_assert_ok(fcc_bootcfg_apply(rec, &cfg, &rate, &field));
    assert_null(field);
    assert_int_equal(cfg.mode, FCC_MODE_LOCKSTEP);
}

/* The record's status; *field named on a refusal. */
static fcc_status_t apply(uint8_t rec[FCC_BOOTCFG_SIZE], const char **field)
{
    seal(rec);
    fcc_node_config_t cfg;
    fcc_assert_ok(fcc_node_config_default(&cfg));
    float rate = 0.0f;
    *field = NULL;
    return fcc_bootcfg_apply(rec, &cfg, &rate, field);
}

/* Each range of fcc_cfg_limits.h (the host command line's too) at its edges:
 * the limit itself accepted, the next value outside it refused. */
static void test_limits_shared_with_the_command_line(void **state)
{
    (void)state;
    static const struct {
        unsigned offset;
        double ok;
        double bad;
        const char *field;
    } f64[] = {
        {FCC_BOOTCFG_LQG_PERIOD_OFF, FCC_CFG_LQG_PERIOD_MIN_S, 0.0, "lqg_period"},
        {FCC_BOOTCFG_LQG_PERIOD_OFF, FCC_CFG_LQG_PERIOD_MAX_S, 0.0, "lqg_period"},
        {FCC_BOOTCFG_GYRO_VAR_OFF, FCC_CFG_NOISE_VAR_MIN, 0.0, "gyro_var"},
        {FCC_BOOTCFG_GYRO_VAR_OFF, FCC_CFG_NOISE_VAR_MAX, 0.0, "gyro_var"},
        {FCC_BOOTCFG_ACCEL_VAR_OFF, FCC_CFG_NOISE_VAR_MIN, 0.0, "accel_var"},
        {FCC_BOOTCFG_ACCEL_VAR_OFF, FCC_CFG_NOISE_VAR_MAX, 0.0, "accel_var"},
    };
    const char *field = NULL;
    uint8_t rec[FCC_BOOTCFG_SIZE];
    for (size_t i = 0u; i < sizeof f64 / sizeof f64[0]; ++i) {
        const bool low = (i % 2u) == 0u;
        record(rec);
        put_f64(&rec[FCC_BOOTCFG_LQG_DELAY_OFF], 0.0); /* no delay: any period may be tried */
        put_f64(&rec[f64[i].offset], f64[i].ok);
        if (apply(rec, &field) != FCC_OK) {
            fail_msg("%s = %g refused (%s)", f64[i].field, f64[i].ok, field);
        }
        put_f64(&rec[f64[i].offset], nextafter(f64[i].ok, low ? -INFINITY : INFINITY));
        assert_int_equal(apply(rec, &field), FCC_ERR_RANGE);
        assert_string_equal(field, f64[i].field);
    }
    static const uint8_t bits[] = {FCC_CFG_LQG_BITS_MIN, FCC_CFG_LQG_BITS_MAX};
    for (size_t i = 0u; i < 2u; ++i) {
        record(rec);
        rec[FCC_BOOTCFG_LQG_BITS_OFF] = bits[i];
        fcc_assert_ok(apply(rec, &field));
        rec[FCC_BOOTCFG_LQG_BITS_OFF] = (uint8_t)((i == 0u) ? bits[i] - 1u : bits[i] + 1u);
        assert_int_equal(apply(rec, &field), FCC_ERR_RANGE);
        assert_string_equal(field, "lqg_bits");
    }
    record(rec);
    put16(&rec[FCC_BOOTCFG_STALE_LIMIT_OFF], FCC_CFG_STALE_LIMIT_MAX);
    fcc_assert_ok(apply(rec, &field));
    put16(&rec[FCC_BOOTCFG_STALE_LIMIT_OFF], FCC_CFG_STALE_LIMIT_MAX + 1u);
    assert_int_equal(apply(rec, &field), FCC_ERR_RANGE);
    assert_string_equal(field, "stale_limit");
    static const float rates[] = {(float)FCC_CFG_STATUS_RATE_MIN_HZ,
                                  (float)FCC_CFG_STATUS_RATE_MAX_HZ};
    for (size_t i = 0u; i < 2u; ++i) {
        record(rec);
        put_f32(&rec[FCC_BOOTCFG_STATUS_RATE_OFF], rates[i]);
        fcc_assert_ok(apply(rec, &field));
        put_f32(&rec[FCC_BOOTCFG_STATUS_RATE_OFF], nextafterf(rates[i], (i == 0u) ? -INFINITY : INFINITY));
        assert_int_equal(apply(rec, &field), FCC_ERR_RANGE);
        assert_string_equal(field, "status_rate");
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_crc32_check_value),
        cmocka_unit_test(test_layout_is_the_documented_table),
        cmocka_unit_test(test_record_applied),
        cmocka_unit_test(test_refusals_change_nothing),
        cmocka_unit_test(test_lockstep_record_applied),
        cmocka_unit_test(test_zero_delay_bytes_mean_no_delay),
        cmocka_unit_test(test_limits_shared_with_the_command_line),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
