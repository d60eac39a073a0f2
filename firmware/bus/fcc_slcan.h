/*
 * fcc_slcan.h -- CAN frames over a serial line in the SLCAN (Lawicel ASCII)
 * protocol, the device side: what a USB-CAN adapter such as a CANable runs,
 * here the flight computer's link to Linux `slcand`
 * (firmware/port/mps2_an386/README.md lists the subset and the answers).
 *
 * Three layers, each usable alone:
 *   fcc_slcan_parse()   one line (without its CR) -> a command or a frame
 *   fcc_slcan_encode()  a frame -> its line, CR included
 *   fcc_slcan_dev_t     the device: bytes in one at a time (bounded line
 *                       buffer, garbage counted and answered with BEL),
 *                       commands answered through a caller-given writer,
 *                       channel state (closed / open / listen-only), frames
 *                       out while open.
 *
 * Portable C99, no heap, no clock, never blocks; every byte sequence is
 * valid input (nothing can overflow, a line always ends at the next CR).
 */
#ifndef FCC_SLCAN_H
#define FCC_SLCAN_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fcc_can.h"
#include "fcc_types.h"

#define FCC_SLCAN_CR 0x0Du
#define FCC_SLCAN_BEL 0x07u
/* Longest line the device accepts, CR excluded: "T" + 8 id + 1 DLC + 16 data
 * = 26; anything longer is garbage by definition. */
#define FCC_SLCAN_LINE_MAX 31u
/* Longest line the encoder writes, CR included ('T' frame, 8 data bytes). */
#define FCC_SLCAN_FRAME_CHARS 27u
#define FCC_SLCAN_EXT_ID_MAX 0x1FFFFFFFu
/* Z2 (this project's extension, spoken by firmware/tools/slcan_bridge): every
 * data frame line to the device carries the frame's time on the bus as 8 hex
 * digits after its data, microseconds modulo 2^32 on the host's clock. */
#define FCC_SLCAN_STAMP_CHARS 8u

typedef enum {
    FCC_SLCAN_CMD_FRAME = 0,   /* t / T: a data frame */
    FCC_SLCAN_CMD_REMOTE,      /* r / R: a remote frame (id and DLC only) */
    FCC_SLCAN_CMD_OPEN,        /* O */
    FCC_SLCAN_CMD_LISTEN,      /* L */
    FCC_SLCAN_CMD_CLOSE,       /* C */
    FCC_SLCAN_CMD_BITRATE,     /* Sn, n = 0..8 in arg */
    FCC_SLCAN_CMD_BTR,         /* sXXYY, the two bytes in arg */
    FCC_SLCAN_CMD_VERSION,     /* V */
    FCC_SLCAN_CMD_FW_VERSION,  /* v */
    FCC_SLCAN_CMD_SERIAL,      /* N */
    FCC_SLCAN_CMD_STATUS,      /* F */
    FCC_SLCAN_CMD_TIMESTAMP    /* Zn, n = 0..2 in arg */
} fcc_slcan_cmd_t;

typedef struct {
    fcc_slcan_cmd_t cmd;
    bool extended;           /* FRAME / REMOTE: 29-bit identifier */
    fcc_can_frame_t frame;   /* FRAME / REMOTE: id, dlc, data (t_us 0) */
    uint16_t arg;            /* BITRATE, BTR, TIMESTAMP */
    bool stamped;            /* FRAME: the line carried a Z2 stamp */
    uint32_t stamp_us;       /* FRAME: that stamp (0 without) */
} fcc_slcan_msg_t;

/* One line, CR excluded, exactly as received (a data frame with or without
 * its Z2 stamp): FCC_OK and *msg, or
 * FCC_ERR_FORMAT (unknown command, wrong length, bad hex digit, id or DLC out
 * of range), FCC_ERR_ARG for NULL.  Hex digits may be upper or lower case. */
fcc_status_t fcc_slcan_parse(const char *line, size_t len, fcc_slcan_msg_t *msg);

/* The line of one data frame, CR included, upper-case hex, no time stamp:
 * "tIIIL..." or, with extended, "TIIIIIIIIL...".  *n = characters written.
 * FCC_ERR_RANGE for a DLC > 8 or an id beyond 11 (29) bits, FCC_ERR_SIZE if
 * cap < the line, FCC_ERR_ARG for NULL. */
fcc_status_t fcc_slcan_encode(const fcc_can_frame_t *frame, bool extended, char *out, size_t cap,
                              size_t *n);

/* ---- the device ------------------------------------------------------------------ */

/* Writes n bytes to the serial line, all or nothing: FCC_ERR_AGAIN when they
 * do not fit now (nothing written). */
typedef fcc_status_t (*fcc_slcan_write_fn)(void *ctx, const uint8_t *bytes, size_t n);

typedef enum {
    FCC_SLCAN_CLOSED = 0,
    FCC_SLCAN_OPEN = 1,
    FCC_SLCAN_LISTEN = 2   /* open, receive only */
} fcc_slcan_state_t;

typedef struct {
    uint32_t lines;          /* lines ended by CR (empty lines excluded) */
    uint32_t frames_rx;      /* data frames handed out (channel open) */
    uint32_t frames_tx;      /* data frames written */
    uint32_t tx_refused;     /* frames not written: channel not open for sending, or no room */
    uint32_t line_errors;    /* lines answered with BEL: garbled, overlong, refused command */
    uint32_t overlong;       /* of which longer than FCC_SLCAN_LINE_MAX */
    uint32_t noise;          /* of which held a byte outside printable ASCII */
    uint32_t ignored;        /* remote and extended frames, frames while closed */
    uint32_t replies_lost;   /* answers the writer had no room for */
} fcc_slcan_counters_t;

typedef struct {
    fcc_slcan_write_fn write;
    void *write_ctx;
    fcc_slcan_state_t state;
    uint8_t bitrate;         /* last S command (6 = 500 kbit/s by default) */
    bool timestamps;         /* Z2 given (while closed): frame lines carry a stamp */
    uint32_t rx_stamp_us;    /* the stamp of the frame fcc_slcan_dev_byte just handed out (Z2) */
    bool opened;             /* an O/L was accepted since fcc_slcan_dev_take_opened() */
    bool overrun;            /* the writer refused bytes since the last F */
    char line[FCC_SLCAN_LINE_MAX];
    uint8_t len;
    bool overlong;           /* current line: discarding until CR */
    bool noise;              /* current line: held a non-printable byte */
    const char *version;     /* V answer, e.g. "V0110" */
    const char *serial;      /* N answer, e.g. "NFCC1" */
    fcc_slcan_counters_t cnt;
} fcc_slcan_dev_t;

/* Closed, S6, the writer for answers and frames, the V/N answers (static
 * strings "V" + 4 chars and "N" + 4 chars). */
fcc_status_t fcc_slcan_dev_init(fcc_slcan_dev_t *dev, fcc_slcan_write_fn write, void *ctx,
                                const char *version, const char *serial);

/* One byte from the serial line.  FCC_OK with *frame when the byte completed
 * a standard data frame and the channel is open (or listen-only);
 * FCC_ERR_AGAIN otherwise (a partial line, a command that was answered,
 * garbage that was counted).  Never fails on any byte value. */
fcc_status_t fcc_slcan_dev_byte(fcc_slcan_dev_t *dev, uint8_t byte, fcc_can_frame_t *frame);

/* Sends one standard data frame while the channel is open: FCC_OK;
 * FCC_ERR_AGAIN when closed / listen-only or the writer has no room (counted
 * in tx_refused); FCC_ERR_RANGE for an id or DLC the encoder refuses. */
fcc_status_t fcc_slcan_dev_send(fcc_slcan_dev_t *dev, const fcc_can_frame_t *frame);

/* True once after each accepted O or L (the device's "listening" moment). */
bool fcc_slcan_dev_take_opened(fcc_slcan_dev_t *dev);

#endif /* FCC_SLCAN_H */
