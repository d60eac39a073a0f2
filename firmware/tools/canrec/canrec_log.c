/*
 * canrec_log.c -- candump log lines (see canrec_log.h).
 */
#include "canrec_log.h"

#include <string.h>

static const char hex_digits[] = "0123456789ABCDEF";

/* Appends v in hex, `digits` digits (the low ones). */
static char *put_hex(char *p, uint32_t v, unsigned digits)
{
    for (unsigned i = digits; i > 0u; --i) {
        p[i - 1u] = hex_digits[v & 0xFu];
        v >>= 4;
    }
    return p + digits;
}

/* Appends v in decimal, zero-padded to at least `width` digits. */
static char *put_dec(char *p, uint64_t v, unsigned width)
{
    char tmp[20];
    unsigned n = 0u;
    do {
        tmp[n++] = (char)('0' + (int)(v % 10u));
        v /= 10u;
    } while (v != 0u);
    while (n < width) {
        tmp[n++] = '0';
    }
    while (n > 0u) {
        *p++ = tmp[--n];
    }
    return p;
}

size_t canrec_log_line(char *buf, size_t cap, int64_t sec, int64_t usec, const char *iface,
                       const struct canfd_frame *f, bool fd)
{
    const size_t name_len = strlen(iface);
    /* "(" 20 "." 6 ") " name " " id(8) "##" flag 128 "\n" NUL */
    if (sec < 0 || usec < 0 || usec > 999999 || cap < name_len + 172u) {
        return 0u;
    }
    char *p = buf;
    *p++ = '(';
    p = put_dec(p, (uint64_t)sec, 10u);
    *p++ = '.';
    p = put_dec(p, (uint64_t)usec, 6u);
    *p++ = ')';
    *p++ = ' ';
    memcpy(p, iface, name_len);
    p += name_len;
    *p++ = ' ';

    const canid_t id = f->can_id;
    if ((id & CAN_ERR_FLAG) != 0u) {
        p = put_hex(p, id & (CAN_ERR_MASK | CAN_ERR_FLAG), 8u);
    } else if ((id & CAN_EFF_FLAG) != 0u) {
        p = put_hex(p, id & CAN_EFF_MASK, 8u);
    } else {
        p = put_hex(p, id & CAN_SFF_MASK, 3u);
    }
    *p++ = '#';
    const unsigned max_len = fd ? CANFD_MAX_DLEN : CAN_MAX_DLEN;
    const unsigned len = (f->len > max_len) ? max_len : f->len;
    if (!fd && (id & CAN_RTR_FLAG) != 0u) {
        *p++ = 'R';
        if (f->len > 0u && f->len <= CAN_MAX_DLEN) {
            *p++ = hex_digits[f->len];
        }
    } else {
        if (fd) {
            *p++ = '#';
            *p++ = hex_digits[f->flags & 0xFu];
        }
        for (unsigned i = 0u; i < len; ++i) {
            p = put_hex(p, f->data[i], 2u);
        }
    }
    *p++ = '\n';
    *p = '\0';
    return (size_t)(p - buf);
}

uint32_t canrec_drops_since(uint32_t before, uint32_t now)
{
    return (uint32_t)(now - before);
}
