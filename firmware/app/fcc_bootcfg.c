/*
 * fcc_bootcfg.c -- the boot configuration record; see fcc_bootcfg.h.
 */
#include "fcc_bootcfg.h"

#include <math.h>
#include <string.h>

#include "fcc_cfg_limits.h" /* the ranges, shared with the host command line */

static uint16_t get_u16(const uint8_t *p)
{
    return (uint16_t)((unsigned)p[0] | ((unsigned)p[1] << 8));
}

static uint32_t get_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
}

static float get_f32(const uint8_t *p)
{
    const uint32_t u = get_u32(p);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static double get_f64(const uint8_t *p)
{
    const uint64_t u = (uint64_t)get_u32(p) | ((uint64_t)get_u32(p + 4) << 32);
    double d;
    memcpy(&d, &u, sizeof d);
    return d;
}

uint32_t fcc_bootcfg_crc32(const uint8_t *bytes, size_t n)
{
    uint32_t crc = 0xFFFFFFFFu;
    for (size_t i = 0u; i < n; ++i) {
        crc ^= bytes[i];
        for (unsigned b = 0u; b < 8u; ++b) {
            crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
        }
    }
    return ~crc;
}

static bool in_range(double v, double lo, double hi)
{
    return isfinite(v) && v >= lo && v <= hi;
}

static fcc_status_t fail(const char **field, const char *name, fcc_status_t st)
{
    *field = name;
    return st;
}

fcc_status_t fcc_bootcfg_apply(const uint8_t rec[FCC_BOOTCFG_SIZE], fcc_node_config_t *cfg,
                               float *status_rate_hz, const char **field)
{
    if (rec == NULL || cfg == NULL || status_rate_hz == NULL || field == NULL) {
        return FCC_ERR_ARG;
    }
    *field = NULL;
    if (memcmp(rec, "FCCB", 4u) != 0) {
        return FCC_ERR_AGAIN;
    }
    if (get_u16(&rec[4]) != FCC_BOOTCFG_VERSION) {
        return fail(field, "version", FCC_ERR_FORMAT);
    }
    if (get_u16(&rec[6]) != FCC_BOOTCFG_SIZE) {
        return fail(field, "length", FCC_ERR_FORMAT);
    }
    if (get_u32(&rec[60]) != fcc_bootcfg_crc32(rec, 60u)) {
        return fail(field, "crc", FCC_ERR_FORMAT);
    }
    const uint8_t mode = rec[8];
    const uint8_t apps = rec[9];
    const uint16_t stale = get_u16(&rec[10]);
    const float rate = get_f32(&rec[12]);
    const double period = get_f64(&rec[16]);
    const uint8_t bits = rec[24];
    const uint8_t detector = rec[25];
    const uint8_t policy = rec[26];
    const double gyro_var = get_f64(&rec[28]);
    const double accel_var = get_f64(&rec[36]);
    const double delay = get_f64(&rec[44]);
    if (mode > 1u) {
        return fail(field, "mode", FCC_ERR_RANGE);
    }
    if (apps == 0u || apps > 3u) {
        return fail(field, "apps", FCC_ERR_RANGE);
    }
    if (stale > FCC_CFG_STALE_LIMIT_MAX) {
        return fail(field, "stale_limit", FCC_ERR_RANGE);
    }
    if (!in_range((double)rate, FCC_CFG_STATUS_RATE_MIN_HZ, FCC_CFG_STATUS_RATE_MAX_HZ)) {
        return fail(field, "status_rate", FCC_ERR_RANGE);
    }
    if (bits < FCC_CFG_LQG_BITS_MIN || bits > FCC_CFG_LQG_BITS_MAX) {
        return fail(field, "lqg_bits", FCC_ERR_RANGE);
    }
    if (!in_range(period, FCC_CFG_LQG_PERIOD_MIN_S, FCC_CFG_LQG_PERIOD_MAX_S) ||
        !fcc_app_msl_valid((fcc_real_t)period, bits)) {
        return fail(field, "lqg_period", FCC_ERR_RANGE);
    }
    if (detector > (uint8_t)FCC_FDET_OFF) {
        return fail(field, "detector", FCC_ERR_RANGE);
    }
    if (policy > (uint8_t)FCC_AZKF_POLICY_SKIP) {
        return fail(field, "fault_policy", FCC_ERR_RANGE);
    }
    if (!in_range(gyro_var, FCC_CFG_NOISE_VAR_MIN, FCC_CFG_NOISE_VAR_MAX)) {
        return fail(field, "gyro_var", FCC_ERR_RANGE);
    }
    if (!in_range(accel_var, FCC_CFG_NOISE_VAR_MIN, FCC_CFG_NOISE_VAR_MAX)) {
        return fail(field, "accel_var", FCC_ERR_RANGE);
    }
    /* as fcc_cli's --lqg-delay D: 0 <= D < T, compared in fcc_real_t (zero bytes: no delay,
     * the meaning of these bytes in records written before the field existed) */
    if (!in_range(delay, FCC_CFG_LQG_DELAY_MIN_S, FCC_CFG_LQG_DELAY_MAX_S) ||
        !((fcc_real_t)delay < (fcc_real_t)period)) {
        return fail(field, "lqg_delay", FCC_ERR_RANGE);
    }
    cfg->mode = (mode == 1u) ? FCC_MODE_REALTIME : FCC_MODE_LOCKSTEP;
    cfg->app_enabled[FCC_APP_CDRW] = (apps & 1u) != 0u;
    cfg->app_enabled[FCC_APP_MSL] = (apps & 2u) != 0u;
    cfg->stale_limit = stale;
    cfg->msl.period = (fcc_real_t)period;
    cfg->msl.bits = bits;
    cfg->msl.delay = (fcc_real_t)delay;
    cfg->msl.plant.gyro_var = (fcc_real_t)gyro_var;
    cfg->msl.plant.accel_var = (fcc_real_t)accel_var;
    cfg->sid.base.azkf.det.mode = (fcc_fdet_mode_t)detector;
    cfg->sid.base.azkf.policy = (fcc_azkf_policy_t)policy;
    *status_rate_hz = rate;
    return FCC_OK;
}
