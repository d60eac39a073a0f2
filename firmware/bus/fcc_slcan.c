/*
 * fcc_slcan.c -- SLCAN (Lawicel ASCII) codec and device; see fcc_slcan.h.
 */
#include "fcc_slcan.h"

#include <string.h>

static const char k_hex[16] = {'0', '1', '2', '3', '4', '5', '6', '7',
                               '8', '9', 'A', 'B', 'C', 'D', 'E', 'F'};

/* Value of one hex digit, or -1. */
static int hex_digit(char c)
{
    if (c >= '0' && c <= '9') {
        return c - '0';
    }
    if (c >= 'A' && c <= 'F') {
        return c - 'A' + 10;
    }
    if (c >= 'a' && c <= 'f') {
        return c - 'a' + 10;
    }
    return -1;
}

/* n hex digits (n <= 8) as a number: FCC_ERR_FORMAT on a non-digit. */
static fcc_status_t hex_value(const char *s, size_t n, uint32_t *out)
{
    uint32_t v = 0u;
    for (size_t i = 0u; i < n; ++i) {
        const int d = hex_digit(s[i]);
        if (d < 0) {
            return FCC_ERR_FORMAT;
        }
        v = (v << 4) | (uint32_t)d;
    }
    *out = v;
    return FCC_OK;
}

/* t/T/r/R lines: identifier, DLC and (data frames) the data bytes, with the
 * line's length exact. */
static fcc_status_t parse_frame(const char *line, size_t len, fcc_slcan_msg_t *msg)
{
    const bool remote = (line[0] == 'r' || line[0] == 'R');
    const bool ext = (line[0] == 'T' || line[0] == 'R');
    const size_t id_chars = ext ? 8u : 3u;
    if (len < 1u + id_chars + 1u) {
        return FCC_ERR_FORMAT;
    }
    uint32_t id = 0u;
    uint32_t dlc = 0u;
    if (hex_value(&line[1], id_chars, &id) != FCC_OK ||
        hex_value(&line[1u + id_chars], 1u, &dlc) != FCC_OK) {
        return FCC_ERR_FORMAT;
    }
    if (id > (ext ? FCC_SLCAN_EXT_ID_MAX : FCC_CAN_STD_ID_MAX) || dlc > FCC_CAN_MAX_DLC) {
        return FCC_ERR_FORMAT;
    }
    const size_t data_chars = remote ? 0u : 2u * (size_t)dlc;
    const size_t frame_chars = 1u + id_chars + 1u + data_chars;
    const bool stamped = (!remote) && (len == (frame_chars + FCC_SLCAN_STAMP_CHARS));
    uint32_t stamp = 0u;
    fcc_status_t st;
    if (stamped) {
        st = hex_value(&line[frame_chars], FCC_SLCAN_STAMP_CHARS, &stamp);
    } else {
        st = (len == frame_chars) ? FCC_OK : FCC_ERR_FORMAT;
    }
    if (st != FCC_OK) {
        return FCC_ERR_FORMAT;
    }
    memset(msg, 0, sizeof *msg);
    msg->stamped = stamped;
    msg->stamp_us = stamp;
    msg->cmd = remote ? FCC_SLCAN_CMD_REMOTE : FCC_SLCAN_CMD_FRAME;
    msg->extended = ext;
    msg->frame.id = id;
    msg->frame.dlc = (uint8_t)dlc;
    for (size_t i = 0u; i < data_chars / 2u; ++i) {
        uint32_t b = 0u;
        if (hex_value(&line[2u + id_chars + 2u * i], 2u, &b) != FCC_OK) {
            return FCC_ERR_FORMAT;
        }
        msg->frame.data[i] = (uint8_t)b;
    }
    return FCC_OK;
}

fcc_status_t fcc_slcan_parse(const char *line, size_t len, fcc_slcan_msg_t *msg)
{
    if (line == NULL || msg == NULL) {
        return FCC_ERR_ARG;
    }
    if (len == 0u || len > FCC_SLCAN_LINE_MAX) {
        return FCC_ERR_FORMAT;
    }
    static const struct {
        char c;
        fcc_slcan_cmd_t cmd;
    } k_single[] = {{'O', FCC_SLCAN_CMD_OPEN},    {'L', FCC_SLCAN_CMD_LISTEN},
                    {'C', FCC_SLCAN_CMD_CLOSE},   {'V', FCC_SLCAN_CMD_VERSION},
                    {'v', FCC_SLCAN_CMD_FW_VERSION}, {'N', FCC_SLCAN_CMD_SERIAL},
                    {'F', FCC_SLCAN_CMD_STATUS}};
    switch (line[0]) {
    case 't':
    case 'T':
    case 'r':
    case 'R':
        return parse_frame(line, len, msg);
    case 'S':
    case 'Z':
        if (len != 2u || line[1] < '0' || line[1] > ((line[0] == 'S') ? '8' : '2')) {
            return FCC_ERR_FORMAT;
        }
        memset(msg, 0, sizeof *msg);
        msg->cmd = (line[0] == 'S') ? FCC_SLCAN_CMD_BITRATE : FCC_SLCAN_CMD_TIMESTAMP;
        msg->arg = (uint16_t)(line[1] - '0');
        return FCC_OK;
    case 's': {
        uint32_t btr = 0u;
        if (len != 5u || hex_value(&line[1], 4u, &btr) != FCC_OK) {
            return FCC_ERR_FORMAT;
        }
        memset(msg, 0, sizeof *msg);
        msg->cmd = FCC_SLCAN_CMD_BTR;
        msg->arg = (uint16_t)btr;
        return FCC_OK;
    }
    default:
        break;
    }
    for (size_t i = 0u; i < sizeof k_single / sizeof k_single[0]; ++i) {
        if (line[0] == k_single[i].c) {
            if (len != 1u) {
                return FCC_ERR_FORMAT;
            }
            memset(msg, 0, sizeof *msg);
            msg->cmd = k_single[i].cmd;
            return FCC_OK;
        }
    }
    return FCC_ERR_FORMAT;
}

fcc_status_t fcc_slcan_encode(const fcc_can_frame_t *frame, bool extended, char *out, size_t cap,
                              size_t *n)
{
    if (frame == NULL || out == NULL || n == NULL) {
        return FCC_ERR_ARG;
    }
    if (frame->dlc > FCC_CAN_MAX_DLC ||
        frame->id > (extended ? FCC_SLCAN_EXT_ID_MAX : FCC_CAN_STD_ID_MAX)) {
        return FCC_ERR_RANGE;
    }
    const size_t id_chars = extended ? 8u : 3u;
    const size_t total = 1u + id_chars + 1u + 2u * (size_t)frame->dlc + 1u;
    if (cap < total) {
        return FCC_ERR_SIZE;
    }
    size_t p = 0u;
    out[p++] = extended ? 'T' : 't';
    for (size_t i = 0u; i < id_chars; ++i) {
        out[p++] = k_hex[(frame->id >> (4u * (id_chars - 1u - i))) & 0xFu];
    }
    out[p++] = k_hex[frame->dlc];
    for (size_t i = 0u; i < (size_t)frame->dlc; ++i) {
        out[p++] = k_hex[frame->data[i] >> 4];
        out[p++] = k_hex[frame->data[i] & 0xFu];
    }
    out[p++] = (char)FCC_SLCAN_CR;
    *n = p;
    return FCC_OK;
}

/* ---- the device ------------------------------------------------------------------ */

fcc_status_t fcc_slcan_dev_init(fcc_slcan_dev_t *dev, fcc_slcan_write_fn write, void *ctx,
                                const char *version, const char *serial)
{
    if (dev == NULL || write == NULL || version == NULL || serial == NULL ||
        strlen(version) != 5u || version[0] != 'V' || strlen(serial) != 5u || serial[0] != 'N') {
        return FCC_ERR_ARG;
    }
    memset(dev, 0, sizeof *dev);
    dev->write = write;
    dev->write_ctx = ctx;
    dev->state = FCC_SLCAN_CLOSED;
    dev->bitrate = 6u;
    dev->version = version;
    dev->serial = serial;
    return FCC_OK;
}

static void reply(fcc_slcan_dev_t *dev, const char *text, size_t n)
{
    if (dev->write(dev->write_ctx, (const uint8_t *)text, n) != FCC_OK) {
        ++dev->cnt.replies_lost;
        dev->overrun = true;
    }
}

static void reply_ok(fcc_slcan_dev_t *dev)
{
    static const char k_cr[1] = {(char)FCC_SLCAN_CR};
    reply(dev, k_cr, 1u);
}

static void reply_error(fcc_slcan_dev_t *dev)
{
    static const char k_bel[1] = {(char)FCC_SLCAN_BEL};
    ++dev->cnt.line_errors;
    reply(dev, k_bel, 1u);
}

/* A 5-character answer ("V0110", "NFCC1", "F00") followed by CR. */
static void reply_text(fcc_slcan_dev_t *dev, const char *text, size_t n)
{
    char buf[8];
    memcpy(buf, text, n);
    buf[n] = (char)FCC_SLCAN_CR;
    reply(dev, buf, n + 1u);
}

/* Commands that only configure: allowed while closed. */
static void configure(fcc_slcan_dev_t *dev, const fcc_slcan_msg_t *m)
{
    if (dev->state != FCC_SLCAN_CLOSED) {
        reply_error(dev);
        return;
    }
    if (m->cmd == FCC_SLCAN_CMD_BITRATE) {
        dev->bitrate = (uint8_t)m->arg;
    }
    if (m->cmd == FCC_SLCAN_CMD_TIMESTAMP) {
        dev->timestamps = (m->arg == 2u);
    }
    reply_ok(dev);
}

static void open_channel(fcc_slcan_dev_t *dev, fcc_slcan_state_t state)
{
    if (dev->state != FCC_SLCAN_CLOSED) {
        reply_error(dev);
        return;
    }
    dev->state = state;
    dev->opened = true;
    reply_ok(dev);
}

static void status_flags(fcc_slcan_dev_t *dev)
{
    char text[3] = {'F', '0', '0'};
    if (dev->overrun) {
        text[2] = '8'; /* bit 3: data overrun (the writer had no room), cleared when read */
    }
    dev->overrun = false;
    reply_text(dev, text, sizeof text);
}

/* A complete, well-formed line: FCC_OK when it was a frame for the node. */
static fcc_status_t execute(fcc_slcan_dev_t *dev, const fcc_slcan_msg_t *m, fcc_can_frame_t *frame)
{
    switch (m->cmd) {
    case FCC_SLCAN_CMD_FRAME:
        if (m->stamped != dev->timestamps) { /* Z2 lines carry a stamp, others none */
            reply_error(dev);
        } else if (dev->state == FCC_SLCAN_CLOSED || m->extended) {
            ++dev->cnt.ignored;
        } else {
            *frame = m->frame;
            dev->rx_stamp_us = m->stamp_us; /* (Z2 only: 0 otherwise) */
            ++dev->cnt.frames_rx;
            return FCC_OK;
        }
        break;
    case FCC_SLCAN_CMD_REMOTE:
        ++dev->cnt.ignored;
        return FCC_ERR_AGAIN;
    case FCC_SLCAN_CMD_OPEN:
        open_channel(dev, FCC_SLCAN_OPEN);
        break;
    case FCC_SLCAN_CMD_LISTEN:
        open_channel(dev, FCC_SLCAN_LISTEN);
        break;
    case FCC_SLCAN_CMD_CLOSE:
        dev->state = FCC_SLCAN_CLOSED;
        reply_ok(dev);
        break;
    case FCC_SLCAN_CMD_BITRATE:
    case FCC_SLCAN_CMD_BTR:
        configure(dev, m);
        break;
    case FCC_SLCAN_CMD_VERSION:
        reply_text(dev, dev->version, 5u);
        break;
    case FCC_SLCAN_CMD_FW_VERSION: {
        char text[5];
        memcpy(text, dev->version, 5u);
        text[0] = 'v';
        reply_text(dev, text, 5u);
        break;
    }
    case FCC_SLCAN_CMD_SERIAL:
        reply_text(dev, dev->serial, 5u);
        break;
    case FCC_SLCAN_CMD_STATUS:
        status_flags(dev);
        break;
    case FCC_SLCAN_CMD_TIMESTAMP:
        if (m->arg == 1u) { /* Lawicel's millisecond stamps on frames sent: not supported */
            reply_error(dev);
        } else if (m->arg == 0u) {
            dev->timestamps = false;
            reply_ok(dev);
        } else {
            configure(dev, m); /* Z2: while closed */
        }
        break;
    default:
        reply_error(dev);
        break;
    }
    return FCC_ERR_AGAIN;
}

/* CR: the line is complete (or garbage). */
static fcc_status_t end_line(fcc_slcan_dev_t *dev, fcc_can_frame_t *frame)
{
    const bool overlong = dev->overlong;
    const bool noise = dev->noise;
    const size_t len = dev->len;
    dev->len = 0u;
    dev->overlong = false;
    dev->noise = false;
    if (len == 0u && !overlong && !noise) {
        return FCC_ERR_AGAIN; /* empty line: hosts send them to flush, no answer */
    }
    ++dev->cnt.lines;
    fcc_slcan_msg_t m;
    if (overlong || noise || fcc_slcan_parse(dev->line, len, &m) != FCC_OK) {
        dev->cnt.overlong += overlong ? 1u : 0u;
        dev->cnt.noise += noise ? 1u : 0u;
        reply_error(dev);
        return FCC_ERR_AGAIN;
    }
    return execute(dev, &m, frame);
}

fcc_status_t fcc_slcan_dev_byte(fcc_slcan_dev_t *dev, uint8_t byte, fcc_can_frame_t *frame)
{
    if (dev == NULL || frame == NULL) {
        return FCC_ERR_ARG;
    }
    if (byte == FCC_SLCAN_CR) {
        return end_line(dev, frame);
    }
    if (byte == 0x0Au && dev->len == 0u && !dev->overlong && !dev->noise) {
        return FCC_ERR_AGAIN; /* the LF of a CR LF pair */
    }
    if (byte < 0x20u || byte > 0x7Eu) {
        dev->noise = true;
    } else if (dev->len >= FCC_SLCAN_LINE_MAX) {
        dev->overlong = true;
    } else {
        dev->line[dev->len++] = (char)byte;
    }
    return FCC_ERR_AGAIN;
}

fcc_status_t fcc_slcan_dev_send(fcc_slcan_dev_t *dev, const fcc_can_frame_t *frame)
{
    if (dev == NULL || frame == NULL) {
        return FCC_ERR_ARG;
    }
    char line[FCC_SLCAN_FRAME_CHARS];
    size_t n = 0u;
    const fcc_status_t st = fcc_slcan_encode(frame, false, line, sizeof line, &n);
    if (st != FCC_OK) {
        ++dev->cnt.tx_refused;
        return st;
    }
    if (dev->state != FCC_SLCAN_OPEN) {
        ++dev->cnt.tx_refused;
        return FCC_ERR_AGAIN;
    }
    if (dev->write(dev->write_ctx, (const uint8_t *)line, n) != FCC_OK) {
        ++dev->cnt.tx_refused;
        dev->overrun = true;
        return FCC_ERR_AGAIN;
    }
    ++dev->cnt.frames_tx;
    return FCC_OK;
}

bool fcc_slcan_dev_take_opened(fcc_slcan_dev_t *dev)
{
    const bool o = (dev != NULL) && dev->opened;
    if (o) {
        dev->opened = false;
    }
    return o;
}
