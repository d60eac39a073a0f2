/*
 * fcc_e2e.h -- end-to-end protection of CAN frames (AUTOSAR E2E profile 1/11 style).
 *
 * The one specification is dbc/README.md, section "E2E"; hil/src/hil/bus/e2e.py
 * implements the same and tests/vectors/bus/ proves the two agree.  In short:
 *   byte 0  = CRC-8 SAE J1850 (poly 0x1D, init 0xFF, xorout 0xFF; check 0x4B)
 *             over data ID low byte, data ID high byte, frame bytes 1..7;
 *   byte 1  = low nibble: 4-bit alive counter, +1 modulo 16 per frame sent.
 * A receiver classifies each frame OK / REPEATED / OK_SOME_LOST /
 * WRONG_SEQUENCE / ERROR, and each receive period without any frame as
 * NO_NEW_DATA.  Only OK and OK_SOME_LOST data may be used.
 */
#ifndef FCC_E2E_H
#define FCC_E2E_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fcc_types.h"

#define FCC_E2E_FRAME_LEN 8u
#define FCC_E2E_COUNTER_MOD 16u
/* Default maximum counter delta: up to two lost frames in a row are still
 * usable (OK_SOME_LOST); a bigger jump is a WRONG_SEQUENCE.  The DBC attribute
 * E2E_MaxDeltaCounter overrides it per message. */
#define FCC_E2E_DEFAULT_MAX_DELTA 3u

/* The values equal hil.bus.e2e.E2EStatus. */
typedef enum {
    FCC_E2E_OK = 0,             /* counter +1: new data */
    FCC_E2E_REPEATED = 1,       /* same counter again: stale copy, not used */
    FCC_E2E_OK_SOME_LOST = 2,   /* counter +2..max delta: new data, frames lost */
    FCC_E2E_WRONG_SEQUENCE = 3, /* counter jumped or went back: not used, resync */
    FCC_E2E_ERROR = 4,          /* CRC mismatch or wrong length: not used */
    FCC_E2E_NO_NEW_DATA = 5,    /* a receive period passed without any frame */
    FCC_E2E_N_STATUS = 6
} fcc_e2e_status_t;

/* Receiver state of one message.  Caller-owned; init with fcc_e2e_rx_init(). */
typedef struct {
    uint16_t data_id;
    uint8_t max_delta;
    uint8_t last_counter;
    bool synced;
    bool stale;                    /* the last closed period had no frame */
    uint8_t frames_this_period;    /* saturates at 255 */
    uint8_t last_status;           /* fcc_e2e_status_t of the last event */
    uint32_t lost_frames;          /* frames known lost (sum of delta - 1) */
    uint32_t count[FCC_E2E_N_STATUS];
} fcc_e2e_rx_t;

/* Sender state of one message. */
typedef struct {
    uint16_t data_id;
    uint8_t counter; /* counter of the next frame */
} fcc_e2e_tx_t;

/* CRC-8 SAE J1850 of len bytes (init 0xFF, final xor 0xFF): 0x4B for "123456789". */
uint8_t fcc_e2e_crc8(const uint8_t *data, size_t len);

/* The E2E CRC of an 8-byte frame: over data ID (low, high) and bytes 1..7. */
uint8_t fcc_e2e_frame_crc(uint16_t data_id, const uint8_t frame[FCC_E2E_FRAME_LEN]);

/* Write counter (0..15) into byte 1's low nibble, then the CRC into byte 0. */
fcc_status_t fcc_e2e_protect(uint16_t data_id, uint8_t counter, uint8_t frame[FCC_E2E_FRAME_LEN]);

fcc_status_t fcc_e2e_tx_init(fcc_e2e_tx_t *tx, uint16_t data_id);
/* Protect with the next counter and advance it. */
fcc_status_t fcc_e2e_tx_protect(fcc_e2e_tx_t *tx, uint8_t frame[FCC_E2E_FRAME_LEN]);

/* max_delta in 1..14 (0 selects FCC_E2E_DEFAULT_MAX_DELTA). */
fcc_status_t fcc_e2e_rx_init(fcc_e2e_rx_t *rx, uint16_t data_id, uint8_t max_delta);
/* Classify one received frame of len bytes (anything but 8 is an ERROR), update
 * the state and the per-class count.  NULL rx or frame counts nothing and
 * returns FCC_E2E_ERROR. */
fcc_e2e_status_t fcc_e2e_rx_check(fcc_e2e_rx_t *rx, const uint8_t *frame, size_t len);
/* Close one receive period: true, and one NO_NEW_DATA counted, if no frame at
 * all arrived since the previous call. */
bool fcc_e2e_rx_end_period(fcc_e2e_rx_t *rx);
/* Forget the counter history (e.g. after the sender restarted); counts stay. */
void fcc_e2e_rx_resync(fcc_e2e_rx_t *rx);
/* Data of this class may be used (OK or OK_SOME_LOST). */
bool fcc_e2e_usable(fcc_e2e_status_t status);
/* "OK", "REPEATED", ... (never NULL). */
const char *fcc_e2e_status_str(fcc_e2e_status_t status);

#endif /* FCC_E2E_H */
