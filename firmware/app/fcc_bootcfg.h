/*
 * fcc_bootcfg.h -- the boot configuration record: what the host `fcc` takes
 * on its command line, for an image that has none (the Cortex-M4F board keeps
 * it in a configuration sector of its flash; firmware/port/mps2_an386/README.md
 * documents it for the rig, hil/src/hil/pil/bootcfg.py writes it).
 *
 * 64 bytes, little-endian, ending in a CRC-32 (IEEE, as zlib.crc32) of the
 * first 60.  Values are range-checked exactly as the host command line checks
 * them and converted to fcc_real_t the same way, so the same record gives the
 * same configuration as the same options to a host build of the same real type.
 */
#ifndef FCC_BOOTCFG_H
#define FCC_BOOTCFG_H

#include <stddef.h>
#include <stdint.h>

#include "fcc_node.h"
#include "fcc_types.h"

#define FCC_BOOTCFG_SIZE 64u
#define FCC_BOOTCFG_VERSION 1u

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
