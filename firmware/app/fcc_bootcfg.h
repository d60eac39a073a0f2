/*
 * fcc_bootcfg.h -- the boot configuration record: what the host `fcc` takes
 * on its command line, for an image that has none (the Cortex-M4F board keeps
 * it in a configuration sector of its flash; firmware/port/mps2_an386/README.md
 * documents it for the rig, hil/src/hil/pil/bootcfg.py writes it).
 *
 * 64 bytes, little-endian, ending in a CRC-32 (IEEE, as zlib.crc32) of the
 * bytes before it.  Values are range-checked exactly as the host command line
 * checks them (fcc_cfg_limits.h) and converted to fcc_real_t the same way, so
 * the same record gives the same configuration as the same options to a host
 * build of the same real type.
 */
#ifndef FCC_BOOTCFG_H
#define FCC_BOOTCFG_H

#include <stddef.h>
#include <stdint.h>

#include "fcc_node.h"
#include "fcc_types.h"

#define FCC_BOOTCFG_SIZE 64u
#define FCC_BOOTCFG_VERSION 1u
#define FCC_BOOTCFG_MAGIC "FCCB"

/* ---- The layout: one definition ---------------------------------------------
 * Each field's byte offset (_OFF) and size in bytes (_LEN), in record order;
 * every field starts where the one before ends (checked at compile time in
 * fcc_bootcfg.c).  u8/u16/u32 are little-endian unsigned integers, f32/f64
 * little-endian IEEE 754 binary32/binary64.  The host option of the same
 * meaning is named after each field. */
#define FCC_BOOTCFG_MAGIC_OFF 0u        /* 4 bytes, FCC_BOOTCFG_MAGIC */
#define FCC_BOOTCFG_MAGIC_LEN 4u
#define FCC_BOOTCFG_VERSION_OFF 4u      /* u16, FCC_BOOTCFG_VERSION */
#define FCC_BOOTCFG_VERSION_LEN 2u
#define FCC_BOOTCFG_LENGTH_OFF 6u       /* u16, FCC_BOOTCFG_SIZE */
#define FCC_BOOTCFG_LENGTH_LEN 2u
#define FCC_BOOTCFG_MODE_OFF 8u         /* u8, --mode: FCC_BOOTCFG_MODE_* */
#define FCC_BOOTCFG_MODE_LEN 1u
#define FCC_BOOTCFG_APPS_OFF 9u         /* u8, --apps: FCC_BOOTCFG_APP_* bits, not 0 */
#define FCC_BOOTCFG_APPS_LEN 1u
#define FCC_BOOTCFG_STALE_LIMIT_OFF 10u /* u16, --stale-limit */
#define FCC_BOOTCFG_STALE_LIMIT_LEN 2u
#define FCC_BOOTCFG_STATUS_RATE_OFF 12u /* f32, --status-rate, Hz */
#define FCC_BOOTCFG_STATUS_RATE_LEN 4u
#define FCC_BOOTCFG_LQG_PERIOD_OFF 16u  /* f64, --lqg-period, s */
#define FCC_BOOTCFG_LQG_PERIOD_LEN 8u
#define FCC_BOOTCFG_LQG_BITS_OFF 24u    /* u8, --lqg-bits */
#define FCC_BOOTCFG_LQG_BITS_LEN 1u
#define FCC_BOOTCFG_DETECTOR_OFF 25u    /* u8, --detector: fcc_fdet_mode_t */
#define FCC_BOOTCFG_DETECTOR_LEN 1u
#define FCC_BOOTCFG_FAULT_POLICY_OFF 26u /* u8, --fault-policy: fcc_azkf_policy_t */
#define FCC_BOOTCFG_FAULT_POLICY_LEN 1u
#define FCC_BOOTCFG_PAD_OFF 27u         /* 1 byte, 0 (aligns the next field; not read) */
#define FCC_BOOTCFG_PAD_LEN 1u
#define FCC_BOOTCFG_GYRO_VAR_OFF 28u    /* f64, --gyro-var, rad^2/s^2 */
#define FCC_BOOTCFG_GYRO_VAR_LEN 8u
#define FCC_BOOTCFG_ACCEL_VAR_OFF 36u   /* f64, --accel-var, ft^2/s^4 */
#define FCC_BOOTCFG_ACCEL_VAR_LEN 8u
#define FCC_BOOTCFG_LQG_DELAY_OFF 44u   /* f64, --lqg-delay D, s (all zero: no delay, the
                                         * meaning of these bytes before the field existed) */
#define FCC_BOOTCFG_LQG_DELAY_LEN 8u
#define FCC_BOOTCFG_RESERVED_OFF 52u    /* 8 bytes, 0 (not read) */
#define FCC_BOOTCFG_RESERVED_LEN 8u
#define FCC_BOOTCFG_CRC_OFF 60u         /* u32, CRC-32 of the bytes before it */
#define FCC_BOOTCFG_CRC_LEN 4u

/* Values of the mode and apps fields. */
#define FCC_BOOTCFG_MODE_LOCKSTEP 0u
#define FCC_BOOTCFG_MODE_REALTIME 1u
#define FCC_BOOTCFG_APP_CDRW 1u
#define FCC_BOOTCFG_APP_MSL 2u

/* Applies the record to cfg (which holds the defaults) and gives the
 * heartbeat rate in *status_rate_hz.  FCC_ERR_AGAIN: no record (the magic
 * "FCCB" is not there: erased flash), nothing changed.  FCC_ERR_FORMAT (wrong
 * version, length or CRC) or FCC_ERR_RANGE (a value out of range): nothing
 * changed and *field names the field.  FCC_ERR_ARG for NULL. */
fcc_status_t fcc_bootcfg_apply(const uint8_t rec[FCC_BOOTCFG_SIZE], fcc_node_config_t *cfg,
                               float *status_rate_hz, const char **field);

/* CRC-32 (IEEE 802.3, reflected, as zlib.crc32) of n bytes. */
uint32_t fcc_bootcfg_crc32(const uint8_t *bytes, size_t n);

#endif /* FCC_BOOTCFG_H */
