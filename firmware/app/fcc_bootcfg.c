/*
 * fcc_bootcfg.c -- the boot configuration record; see fcc_bootcfg.h.
 */
#include "fcc_bootcfg.h"

#include <math.h>
#include <string.h>

#include "fcc_cfg_limits.h" /* the ranges, shared with the host command line */

/* The layout tiles the record: each field starts where the one before ends,
 * the CRC ends the record (a failed check is a negative array size). */
#define FOLLOWS(next, prev)                                                                       \
    (FCC_BOOTCFG_##next##_OFF == FCC_BOOTCFG_##prev##_OFF + FCC_BOOTCFG_##prev##_LEN)
#define LAYOUT_OK                                                                                 \
    (FCC_BOOTCFG_MAGIC_OFF == 0u && FOLLOWS(VERSION, MAGIC) && FOLLOWS(LENGTH, VERSION) &&        \
     FOLLOWS(MODE, LENGTH) && FOLLOWS(APPS, MODE) && FOLLOWS(STALE_LIMIT, APPS) &&                \
     FOLLOWS(STATUS_RATE, STALE_LIMIT) && FOLLOWS(LQG_PERIOD, STATUS_RATE) &&                     \
     FOLLOWS(LQG_BITS, LQG_PERIOD) && FOLLOWS(DETECTOR, LQG_BITS) &&                              \
     FOLLOWS(FAULT_POLICY, DETECTOR) && FOLLOWS(PAD, FAULT_POLICY) && FOLLOWS(GYRO_VAR, PAD) &&   \
     FOLLOWS(ACCEL_VAR, GYRO_VAR) && FOLLOWS(LQG_DELAY, ACCEL_VAR) &&                             \
     FOLLOWS(RESERVED, LQG_DELAY) && FOLLOWS(CRC, RESERVED) &&                                    \
     FCC_BOOTCFG_CRC_OFF + FCC_BOOTCFG_CRC_LEN == FCC_BOOTCFG_SIZE &&                             \
     sizeof FCC_BOOTCFG_MAGIC - 1u == FCC_BOOTCFG_MAGIC_LEN)
typedef char layout_tiles_the_record[LAYOUT_OK ? 1 : -1];

/* Field readers: the field's name gives its place, the reader's width must be
 * the field's size (a failed check is a negative array size). */
#define WIDTH_IS(name, bytes) ((void)sizeof(char[(FCC_BOOTCFG_##name##_LEN == (bytes)) ? 1 : -1]))
#define U8(rec, name) (WIDTH_IS(name, 1u), (rec)[FCC_BOOTCFG_##name##_OFF])
#define U16(rec, name) (WIDTH_IS(name, 2u), get_u16(&(rec)[FCC_BOOTCFG_##name##_OFF]))
#define U32(rec, name) (WIDTH_IS(name, 4u), get_u32(&(rec)[FCC_BOOTCFG_##name##_OFF]))
#define F32(rec, name) (WIDTH_IS(name, 4u), get_f32(&(rec)[FCC_BOOTCFG_##name##_OFF]))
#define F64(rec, name) (WIDTH_IS(name, 8u), get_f64(&(rec)[FCC_BOOTCFG_##name##_OFF]))

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
    if (memcmp(&rec[FCC_BOOTCFG_MAGIC_OFF], FCC_BOOTCFG_MAGIC, FCC_BOOTCFG_MAGIC_LEN) != 0) {
        return FCC_ERR_AGAIN;
    }
    if (U16(rec, VERSION) != FCC_BOOTCFG_VERSION) {
        return fail(field, "version", FCC_ERR_FORMAT);
    }
    if (U16(rec, LENGTH) != FCC_BOOTCFG_SIZE) {
        return fail(field, "length", FCC_ERR_FORMAT);
    }
    if (U32(rec, CRC) != fcc_bootcfg_crc32(rec, FCC_BOOTCFG_CRC_OFF)) {
        return fail(field, "crc", FCC_ERR_FORMAT);
    }
    const uint8_t mode = U8(rec, MODE);
    const uint8_t apps = U8(rec, APPS);
    const uint16_t stale = U16(rec, STALE_LIMIT);
    const float rate = F32(rec, STATUS_RATE);
    const double period = F64(rec, LQG_PERIOD);
    const uint8_t bits = U8(rec, LQG_BITS);
    const uint8_t detector = U8(rec, DETECTOR);
    const uint8_t policy = U8(rec, FAULT_POLICY);
    const double gyro_var = F64(rec, GYRO_VAR);
    const double accel_var = F64(rec, ACCEL_VAR);
    const double delay = F64(rec, LQG_DELAY);
    if (mode != FCC_BOOTCFG_MODE_LOCKSTEP && mode != FCC_BOOTCFG_MODE_REALTIME) {
        return fail(field, "mode", FCC_ERR_RANGE);
    }
    if (apps == 0u || (apps & ~(FCC_BOOTCFG_APP_CDRW | FCC_BOOTCFG_APP_MSL)) != 0u) {
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
    cfg->mode = (mode == FCC_BOOTCFG_MODE_REALTIME) ? FCC_MODE_REALTIME : FCC_MODE_LOCKSTEP;
    cfg->app_enabled[FCC_APP_CDRW] = (apps & FCC_BOOTCFG_APP_CDRW) != 0u;
    cfg->app_enabled[FCC_APP_MSL] = (apps & FCC_BOOTCFG_APP_MSL) != 0u;
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
