/*
 * fuzz_bus_records.h -- how the bus fuzz targets turn input bytes into
 * messages and frames.  Shared by fuzz_bus_rx.c, fuzz_bus_tx.c and the unit
 * test tests/c/test_fuzz_records.c, which checks that every message of the DBC
 * can be chosen (a selector narrower than the message table once left the
 * last messages unfuzzed).
 *
 * A message is chosen by one whole byte modulo FCC_MSG_COUNT, the size of the
 * generated table (firmware/bus/generated/fcc_bus_msgs.h), so the harnesses
 * follow the DBC without a literal count.
 *
 * fuzz_bus_rx's input is a sequence of FUZZ_RX_REC-byte records:
 *   [0] flags: FUZZ_RX_FROM_TABLE = send the chosen DBC message's identifier,
 *       else an arbitrary 11-bit identifier from bits 0..2 of [0] and [1];
 *       FUZZ_RX_PROTECT = E2E-protect the payload (so the checks behind the
 *       CRC run); FUZZ_RX_END_PERIOD = close a receive period of the chosen
 *       message afterwards
 *   [1] the message (fuzz_bus_pick), or the identifier's low byte
 *   [2] dlc (0..255: anything but 8 is a wrong DLC)
 *   [3..10] data, [11] E2E counter (low 4 bits) for FUZZ_RX_PROTECT.
 */
#ifndef FUZZ_BUS_RECORDS_H
#define FUZZ_BUS_RECORDS_H

#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "fcc_bus.h"

/* A byte names every message; the harnesses' node masks (uint64_t, one bit a
 * message) hold them all.  A failed check is a negative array size. */
typedef char fuzz_bus_byte_names_every_message[(FCC_MSG_COUNT <= 256 && FCC_MSG_COUNT < 64) ? 1
                                                                                             : -1];

#define FUZZ_RX_REC 12u
#define FUZZ_RX_FROM_TABLE 0x80u
#define FUZZ_RX_END_PERIOD 0x40u
#define FUZZ_RX_PROTECT 0x20u

/* The message a selector byte names: every one of the DBC's for some byte. */
static inline fcc_msg_t fuzz_bus_pick(uint8_t selector)
{
    return (fcc_msg_t)((unsigned int)selector % (unsigned int)FCC_MSG_COUNT);
}

/* The frame of one fuzz_bus_rx record, and the message it chose (also for a
 * record with an arbitrary identifier: its period may be closed too). */
static inline void fuzz_rx_record(const uint8_t r[FUZZ_RX_REC], fcc_can_frame_t *f,
                                  fcc_msg_t *msg)
{
    const bool from_table = (r[0] & FUZZ_RX_FROM_TABLE) != 0u;
    *msg = fuzz_bus_pick(r[1]);
    memset(f, 0, sizeof *f);
    f->id = from_table ? fcc_bus_msg_table[*msg].id : (((uint32_t)r[0] << 8 | r[1]) & 0x7FFu);
    f->dlc = r[2];
    memcpy(f->data, r + 3, 8);
    if (from_table && (r[0] & FUZZ_RX_PROTECT) != 0u && fcc_bus_msg_table[*msg].data_id != 0u) {
        (void)fcc_e2e_protect(fcc_bus_msg_table[*msg].data_id, (uint8_t)(r[11] & 0x0Fu), f->data);
    }
}

#endif /* FUZZ_BUS_RECORDS_H */
