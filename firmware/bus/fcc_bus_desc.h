/*
 * fcc_bus_desc.h -- the shape of the generated message tables.
 *
 * hil.bus.cgen turns dbc/fcc_hil.dbc into tables of these descriptors
 * (generated/fcc_bus_msgs.c).  The frame layer (fcc_bus.c) walks them, so the
 * range checks and the raw <-> physical conversions are written once, not once
 * per message, and the DBC stays the only place where a signal is defined.
 */
#ifndef FCC_BUS_DESC_H
#define FCC_BUS_DESC_H

#include <stdint.h>

#include "fcc_types.h"

/* C type of a field, in the cantools raw struct and in the physical struct. */
typedef enum {
    FCC_FIELD_U8 = 0,
    FCC_FIELD_U16,
    FCC_FIELD_U32,
    FCC_FIELD_I8,
    FCC_FIELD_I16,
    FCC_FIELD_I32,
    FCC_FIELD_BOOL,  /* physical only: 1-bit signals */
    FCC_FIELD_REAL,  /* physical only: scaled signals, fcc_real_t */
    FCC_FIELD_U64    /* wide integers (SecOC MACs); values fit int64_t */
} fcc_field_type_t;

typedef struct {
    const char *name;
    uint16_t phys_offset;   /* offsetof() in the physical struct */
    uint16_t raw_offset;    /* offsetof() in the cantools raw struct */
    uint8_t phys_type;      /* fcc_field_type_t */
    uint8_t raw_type;       /* fcc_field_type_t */
    fcc_real_t inv_scale;   /* raw = round(phys * inv_scale); 1 for integer signals */
    int64_t raw_min;        /* the DBC minimum, in raw units */
    int64_t raw_max;        /* the DBC maximum, in raw units */
} fcc_bus_signal_desc_t;

typedef struct {
    const char *name;
    uint16_t id;                 /* 11-bit CAN identifier */
    uint16_t data_id;            /* E2E data ID; 0 = not protected */
    uint8_t max_delta_counter;   /* E2E receiver parameter */
    uint16_t cycle_ms;           /* GenMsgCycleTime; 0 = event */
    uint8_t senders;             /* bit mask of FCC_BUS_NODE_* */
    uint8_t receivers;           /* bit mask of FCC_BUS_NODE_* */
    uint8_t n_signals;           /* data signals (crc and counter excluded) */
    const fcc_bus_signal_desc_t *signals;
    /* Thin wrappers around the cantools pack/unpack of this message. */
    int (*unpack)(void *raw, const uint8_t data[8]);
    int (*pack)(uint8_t data[8], const void *raw);
} fcc_bus_msg_desc_t;

#endif /* FCC_BUS_DESC_H */
