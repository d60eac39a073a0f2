/*
 * fcc_bus.h -- the firmware's frame layer: frames in, good physical values out.
 *
 * On top of the codec generated from dbc/fcc_hil.dbc (generated/), it does for
 * every received frame, in this order:
 *   1. identifier known and consumed by this node?   else UNKNOWN_ID
 *   2. data length equal to the DBC length (8)?       else WRONG_DLC
 *   3. E2E check (protected messages)                 else E2E (ERROR,
 *                                                     REPEATED, WRONG_SEQUENCE)
 *   4. every raw value inside the DBC min..max?       else OUT_OF_RANGE
 * and hands the application physical values only when all four pass.  Each
 * rejection class has its own counter.  For transmission it refuses NaN/Inf and
 * out-of-range values (tx_refused), packs and E2E-protects with the message's
 * own alive counter.
 *
 * Typical use (the FCC):
 *     fcc_bus_t bus;                       caller-owned, no heap
 *     fcc_bus_init(&bus, FCC_BUS_NODE_FCC);
 *     fcc_bus_rx_msg_t m;
 *     if (fcc_bus_receive(&bus, &frame, &m) == FCC_OK && m.msg == FCC_MSG_CDRW_AOA)
 *         alpha = m.data.cdrw_aoa.alpha;
 *     fcc_bus_end_period(&bus, FCC_MSG_CDRW_AOA);   once per step: NO_NEW_DATA
 *     fcc_msg_data_t d = {0}; d.msl_elev_cmd.da_code = code; ...
 *     fcc_bus_encode(&bus, FCC_MSG_MSL_ELEV_CMD, &d, &out_frame);
 */
#ifndef FCC_BUS_H
#define FCC_BUS_H

#include <stdbool.h>
#include <stdint.h>

#include "fcc_bus_msgs.h"
#include "fcc_can.h"
#include "fcc_e2e.h"
#include "fcc_types.h"

/* Why a received frame was not handed on (FCC_BUS_PASS: it was). */
typedef enum {
    FCC_BUS_PASS = 0,
    FCC_BUS_UNKNOWN_ID = 1,   /* not in the DBC, or not consumed by this node */
    FCC_BUS_WRONG_DLC = 2,    /* length differs from the DBC */
    FCC_BUS_E2E = 3,          /* E2E class not usable (see fcc_bus_rx_msg_t.e2e) */
    FCC_BUS_OUT_OF_RANGE = 4  /* a raw value outside the DBC minimum..maximum */
} fcc_bus_verdict_t;

typedef struct {
    fcc_msg_t msg;            /* which message (FCC_MSG_COUNT when unknown) */
    fcc_bus_verdict_t verdict;
    fcc_e2e_status_t e2e;     /* E2E class; FCC_E2E_OK for unprotected messages */
    uint64_t t_us;            /* the port's receive time stamp */
    fcc_msg_data_t data;      /* physical values; valid only when verdict == PASS */
} fcc_bus_rx_msg_t;

/* Counters; they wrap like the DBC's 16-bit status signals do when published. */
typedef struct {
    uint32_t e2e[FCC_E2E_N_STATUS]; /* indexed by fcc_e2e_status_t, all messages */
    uint32_t unknown_id;
    uint32_t wrong_dlc;
    uint32_t out_of_range;
    uint32_t tx_refused;    /* encode refused: NaN, Inf, out of range, not ours */
    uint32_t tx_saturated;  /* fcc_bus_encode_sat() clamped a value into range */
    uint32_t stale_now;     /* consumed protected messages whose last period was empty */
} fcc_bus_counters_t;

/* One node's bus state: caller-owned, about 1.3 kB. */
typedef struct {
    uint64_t consumes;   /* bit i: message i is received by this node */
    uint64_t produces;   /* bit i: message i is sent by this node */
    fcc_e2e_rx_t rx[FCC_MSG_COUNT];
    fcc_e2e_tx_t tx[FCC_MSG_COUNT];
    uint32_t unknown_id;
    uint32_t wrong_dlc;
    uint32_t out_of_range;
    uint32_t tx_refused;
    uint32_t tx_saturated;
} fcc_bus_t;

/* A node consumes the messages whose DBC receivers include it and produces the
 * ones whose sender it is (node = FCC_BUS_NODE_*). */
fcc_status_t fcc_bus_init(fcc_bus_t *bus, uint32_t node);
/* Explicit message masks (bit i = fcc_msg_t i): tools, tests, bus monitors. */
fcc_status_t fcc_bus_init_masks(fcc_bus_t *bus, uint64_t consumes, uint64_t produces);

/* Steps 1-4 above.  FCC_OK: out->data holds good values.  Otherwise
 * FCC_ERR_FORMAT (unknown id, wrong DLC, E2E not usable) or FCC_ERR_RANGE, with
 * out->verdict and out->e2e saying why; out->data is then unspecified. */
fcc_status_t fcc_bus_receive(fcc_bus_t *bus, const fcc_can_frame_t *frame, fcc_bus_rx_msg_t *out);

/* Close one receive period of a consumed protected message (call once per
 * expected period, e.g. once per application step for each of its sensors).
 * Returns true, and counts NO_NEW_DATA, when no frame arrived in the period. */
bool fcc_bus_end_period(fcc_bus_t *bus, fcc_msg_t msg);

/* Encode a message this node produces: FCC_ERR_NOT_FINITE for NaN/Inf,
 * FCC_ERR_RANGE for a value outside the DBC range, FCC_ERR_ARG for a message
 * the node does not send; each refusal counts tx_refused and leaves the alive
 * counter alone.  On FCC_OK, out is an 8-byte frame, E2E-protected if the
 * message is. */
fcc_status_t fcc_bus_encode(fcc_bus_t *bus, fcc_msg_t msg, const fcc_msg_data_t *data,
                            fcc_can_frame_t *out);
/* Same, but finite values outside the range are clamped to it (counted in
 * tx_saturated) instead of refused: for diagnostic outputs such as bounds. */
fcc_status_t fcc_bus_encode_sat(fcc_bus_t *bus, fcc_msg_t msg, const fcc_msg_data_t *data,
                                fcc_can_frame_t *out);

/* Totals over every message (E2E classes summed). */
fcc_status_t fcc_bus_get_counters(const fcc_bus_t *bus, fcc_bus_counters_t *out);

/* ---- Stateless helpers (vectors, tools, fuzzing) ---------------------------- */

/* Message of a CAN identifier: FCC_OK, or FCC_ERR_RANGE if not in the DBC. */
fcc_status_t fcc_bus_find(uint32_t id, fcc_msg_t *msg);
/* Descriptor of a message (NULL if msg is out of range). */
const fcc_bus_msg_desc_t *fcc_bus_desc(fcc_msg_t msg);
/* Unpack 8 bytes (no E2E check) into physical values: FCC_ERR_RANGE when a raw
 * value is outside the DBC range (out untouched). */
fcc_status_t fcc_bus_decode(fcc_msg_t msg, const uint8_t data[8], fcc_msg_data_t *out);
/* Pack physical values into 8 bytes with crc = counter = 0 (no E2E). */
fcc_status_t fcc_bus_pack(fcc_msg_t msg, const fcc_msg_data_t *data, uint8_t out[8]);
/* Read / write signal number sig (order of fcc_bus_msg_desc_t.signals): scaled
 * signals through *real, integer and flag signals through *integer. */
fcc_status_t fcc_bus_signal_get(fcc_msg_t msg, uint32_t sig, const fcc_msg_data_t *data,
                                fcc_real_t *real, int64_t *integer);
fcc_status_t fcc_bus_signal_set(fcc_msg_t msg, uint32_t sig, fcc_msg_data_t *data,
                                fcc_real_t real, int64_t integer);
const char *fcc_bus_verdict_str(fcc_bus_verdict_t verdict);

#endif /* FCC_BUS_H */
