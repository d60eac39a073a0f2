/*
 * fcc_cfg_limits.h -- the accepted range of every configuration value that
 * both the host command line (firmware/port/linux/fcc_cli.c) and the boot
 * configuration record (fcc_bootcfg.c, the Cortex-M4F image's command line)
 * carry.  One definition: a value one of them accepts, the other accepts too.
 *
 * Bounds are inclusive unless said otherwise; the values are double (compare
 * a float field as (double)field: the conversion is exact).  The LQG period
 * and word length are the applications' own ranges (fcc_app_msl.h, fcc_lqg.h),
 * named here so that both readers take them from one place.  The defaults are
 * fcc_node_config_default()'s, plus the heartbeat rate below.
 */
#ifndef FCC_CFG_LIMITS_H
#define FCC_CFG_LIMITS_H

#include "fcc_app_msl.h"
#include "fcc_lqg.h"

/* --stale-limit N / stale_limit: missing frames bridged with the last value
 * before a sensor is stale, 0..FCC_CFG_STALE_LIMIT_MAX. */
#define FCC_CFG_STALE_LIMIT_MAX 1000u

/* --status-rate HZ / status_rate: heartbeats per second; 0 = only at start
 * (when the channel is opened) and at exit. */
#define FCC_CFG_STATUS_RATE_MIN_HZ 0.0
#define FCC_CFG_STATUS_RATE_MAX_HZ 1000.0
#define FCC_CFG_STATUS_RATE_DEFAULT_HZ 10.0

/* --lqg-period T / lqg_period: the missile autopilot's sampling period, s. */
#define FCC_CFG_LQG_PERIOD_MIN_S ((double)FCC_APP_MSL_T_MIN)
#define FCC_CFG_LQG_PERIOD_MAX_S ((double)FCC_APP_MSL_T_MAX)

/* --lqg-bits N / lqg_bits: the D/A converter's word length. */
#define FCC_CFG_LQG_BITS_MIN FCC_LQG_BITS_MIN
#define FCC_CFG_LQG_BITS_MAX FCC_LQG_BITS_MAX

/* --lqg-delay D / lqg_delay: the input delay the LQG is designed for, s;
 * 0 <= D < T (the period, compared in fcc_real_t), so never above the
 * longest period. */
#define FCC_CFG_LQG_DELAY_MIN_S 0.0
#define FCC_CFG_LQG_DELAY_MAX_S FCC_CFG_LQG_PERIOD_MAX_S

/* --gyro-var V, --accel-var V / gyro_var, accel_var: the sensors' noise
 * variances (rad^2/s^2, ft^2/s^4) the Kalman filter is designed for. */
#define FCC_CFG_NOISE_VAR_MIN 1e-12
#define FCC_CFG_NOISE_VAR_MAX 1e6

#endif /* FCC_CFG_LIMITS_H */
