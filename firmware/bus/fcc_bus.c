/*
 * fcc_bus.c -- frame layer: DBC tables + E2E + range checks.  See fcc_bus.h.
 */
#include "fcc_bus.h"

#include <string.h>

/* Message masks are 64-bit: the DBC may grow to 64 messages before this must change. */
typedef char fcc_bus_assert_msg_count[(FCC_MSG_COUNT <= 64) ? 1 : -1];

#define MSG_BIT(i) ((uint64_t)1u << (uint32_t)(i))

/* ---- field access (memcpy: no alignment or aliasing assumptions) ----------- */

static int64_t field_get_int(const void *base, uint16_t offset, uint8_t type)
{
    const uint8_t *p = (const uint8_t *)base + offset;
    switch (type) {
    case FCC_FIELD_U8: { uint8_t v; memcpy(&v, p, sizeof v); return v; }
    case FCC_FIELD_U16: { uint16_t v; memcpy(&v, p, sizeof v); return v; }
    case FCC_FIELD_U32: { uint32_t v; memcpy(&v, p, sizeof v); return v; }
    case FCC_FIELD_I8: { int8_t v; memcpy(&v, p, sizeof v); return v; }
    case FCC_FIELD_I16: { int16_t v; memcpy(&v, p, sizeof v); return v; }
    case FCC_FIELD_I32: { int32_t v; memcpy(&v, p, sizeof v); return v; }
    case FCC_FIELD_U64: { uint64_t v; memcpy(&v, p, sizeof v); return (int64_t)v; }
    case FCC_FIELD_BOOL: { bool v; memcpy(&v, p, sizeof v); return v ? 1 : 0; }
    default: return 0;
    }
}

/* value is already inside the field's range (checked against the DBC limits). */
static void field_set_int(void *base, uint16_t offset, uint8_t type, int64_t value)
{
    uint8_t *p = (uint8_t *)base + offset;
    switch (type) {
    case FCC_FIELD_U8: { const uint8_t v = (uint8_t)value; memcpy(p, &v, sizeof v); break; }
    case FCC_FIELD_U16: { const uint16_t v = (uint16_t)value; memcpy(p, &v, sizeof v); break; }
    case FCC_FIELD_U32: { const uint32_t v = (uint32_t)value; memcpy(p, &v, sizeof v); break; }
    case FCC_FIELD_I8: { const int8_t v = (int8_t)value; memcpy(p, &v, sizeof v); break; }
    case FCC_FIELD_I16: { const int16_t v = (int16_t)value; memcpy(p, &v, sizeof v); break; }
    case FCC_FIELD_I32: { const int32_t v = (int32_t)value; memcpy(p, &v, sizeof v); break; }
    case FCC_FIELD_U64: { const uint64_t v = (uint64_t)value; memcpy(p, &v, sizeof v); break; }
    case FCC_FIELD_BOOL: { const bool v = (value != 0); memcpy(p, &v, sizeof v); break; }
    default: break;
    }
}

static fcc_real_t field_get_real(const void *base, uint16_t offset)
{
    fcc_real_t v;
    memcpy(&v, (const uint8_t *)base + offset, sizeof v);
    return v;
}

static void field_set_real(void *base, uint16_t offset, fcc_real_t value)
{
    memcpy((uint8_t *)base + offset, &value, sizeof value);
}

/* ---- stateless codec --------------------------------------------------------- */

const fcc_bus_msg_desc_t *fcc_bus_desc(fcc_msg_t msg)
{
    return ((unsigned int)msg < (unsigned int)FCC_MSG_COUNT) ? &fcc_bus_msg_table[msg] : NULL;
}

fcc_status_t fcc_bus_find(uint32_t id, fcc_msg_t *msg)
{
    if (msg == NULL) {
        return FCC_ERR_ARG;
    }
    unsigned int lo = 0u;
    unsigned int hi = (unsigned int)FCC_MSG_COUNT;
    while (lo < hi) { /* the table is sorted by identifier */
        const unsigned int mid = lo + (hi - lo) / 2u;
        const uint32_t mid_id = fcc_bus_msg_table[mid].id;
        if (mid_id == id) {
            *msg = (fcc_msg_t)mid;
            return FCC_OK;
        }
        if (mid_id < id) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    return FCC_ERR_RANGE;
}

fcc_status_t fcc_bus_decode(fcc_msg_t msg, const uint8_t data[8], fcc_msg_data_t *out)
{
    const fcc_bus_msg_desc_t *d = fcc_bus_desc(msg);
    if (d == NULL || data == NULL || out == NULL) {
        return FCC_ERR_ARG;
    }
    fcc_bus_raw_t raw;
    if (d->unpack(&raw, data) != 0) {
        return FCC_ERR_FORMAT;
    }
    fcc_msg_data_t phys;
    memset(&phys, 0, sizeof phys);
    for (uint32_t i = 0u; i < d->n_signals; ++i) {
        const fcc_bus_signal_desc_t *s = &d->signals[i];
        const int64_t r = field_get_int(&raw, s->raw_offset, s->raw_type);
        if (r < s->raw_min || r > s->raw_max) {
            return FCC_ERR_RANGE;
        }
        if (s->phys_type == FCC_FIELD_REAL) {
            /* |r| <= 2^21 by DBC design: exact in float, one rounding in the division. */
            field_set_real(&phys, s->phys_offset, (fcc_real_t)r / s->inv_scale);
        } else {
            field_set_int(&phys, s->phys_offset, s->phys_type, r);
        }
    }
    *out = phys;
    return FCC_OK;
}

/* Physical value of one signal -> raw, checked (or clamped when saturate). */
static fcc_status_t to_raw(const fcc_bus_signal_desc_t *s, const fcc_msg_data_t *data,
                           bool saturate, int64_t *raw, bool *clamped)
{
    int64_t r;
    if (s->phys_type == FCC_FIELD_REAL) {
        const fcc_real_t v = field_get_real(data, s->phys_offset);
        if (!FCC_IS_FINITE(v)) {
            return FCC_ERR_NOT_FINITE;
        }
        const fcc_real_t x = FCC_ROUND(v * s->inv_scale);
        if (x < (fcc_real_t)s->raw_min) {
            r = s->raw_min - 1;
        } else if (x > (fcc_real_t)s->raw_max) {
            r = s->raw_max + 1;
        } else {
            r = (int64_t)x;
        }
    } else {
        r = field_get_int(data, s->phys_offset, s->phys_type);
    }
    if (r < s->raw_min || r > s->raw_max) {
        if (!saturate) {
            return FCC_ERR_RANGE;
        }
        r = (r < s->raw_min) ? s->raw_min : s->raw_max;
        *clamped = true;
    }
    *raw = r;
    return FCC_OK;
}

static fcc_status_t pack_checked(fcc_msg_t msg, const fcc_msg_data_t *data, bool saturate,
                                 uint8_t out[8], bool *clamped)
{
    const fcc_bus_msg_desc_t *d = fcc_bus_desc(msg);
    if (d == NULL || data == NULL || out == NULL) {
        return FCC_ERR_ARG;
    }
    fcc_bus_raw_t raw;
    memset(&raw, 0, sizeof raw); /* crc and counter stay 0 until E2E protects */
    for (uint32_t i = 0u; i < d->n_signals; ++i) {
        const fcc_bus_signal_desc_t *s = &d->signals[i];
        int64_t r = 0;
        const fcc_status_t st = to_raw(s, data, saturate, &r, clamped);
        if (st != FCC_OK) {
            return st;
        }
        field_set_int(&raw, s->raw_offset, s->raw_type, r);
    }
    return (d->pack(out, &raw) == (int)FCC_E2E_FRAME_LEN) ? FCC_OK : FCC_ERR_FORMAT;
}

fcc_status_t fcc_bus_pack(fcc_msg_t msg, const fcc_msg_data_t *data, uint8_t out[8])
{
    bool clamped = false;
    return pack_checked(msg, data, false, out, &clamped);
}

fcc_status_t fcc_bus_signal_get(fcc_msg_t msg, uint32_t sig, const fcc_msg_data_t *data,
                                fcc_real_t *real, int64_t *integer)
{
    const fcc_bus_msg_desc_t *d = fcc_bus_desc(msg);
    if (d == NULL || data == NULL || real == NULL || integer == NULL || sig >= d->n_signals) {
        return FCC_ERR_ARG;
    }
    const fcc_bus_signal_desc_t *s = &d->signals[sig];
    if (s->phys_type == FCC_FIELD_REAL) {
        *real = field_get_real(data, s->phys_offset);
        *integer = 0;
    } else {
        *integer = field_get_int(data, s->phys_offset, s->phys_type);
        *real = FCC_R(0.0);
    }
    return FCC_OK;
}

fcc_status_t fcc_bus_signal_set(fcc_msg_t msg, uint32_t sig, fcc_msg_data_t *data,
                                fcc_real_t real, int64_t integer)
{
    const fcc_bus_msg_desc_t *d = fcc_bus_desc(msg);
    if (d == NULL || data == NULL || sig >= d->n_signals) {
        return FCC_ERR_ARG;
    }
    const fcc_bus_signal_desc_t *s = &d->signals[sig];
    if (s->phys_type == FCC_FIELD_REAL) {
        field_set_real(data, s->phys_offset, real);
    } else {
        /* Keep the value representable in the C field; the DBC range is checked at pack. */
        const int64_t lo = (s->phys_type == FCC_FIELD_BOOL) ? 0 : s->raw_min;
        const int64_t hi = (s->phys_type == FCC_FIELD_BOOL) ? 1 : s->raw_max;
        if (integer < lo || integer > hi) {
            return FCC_ERR_RANGE;
        }
        field_set_int(data, s->phys_offset, s->phys_type, integer);
    }
    return FCC_OK;
}

/* ---- stateful node ----------------------------------------------------------- */

fcc_status_t fcc_bus_init_masks(fcc_bus_t *bus, uint64_t consumes, uint64_t produces)
{
    const uint64_t all = (FCC_MSG_COUNT >= 64) ? UINT64_MAX : (MSG_BIT(FCC_MSG_COUNT) - 1u);
    if (bus == NULL || (consumes & ~all) != 0u || (produces & ~all) != 0u) {
        return FCC_ERR_ARG;
    }
    memset(bus, 0, sizeof *bus);
    bus->consumes = consumes;
    bus->produces = produces;
    for (unsigned int i = 0u; i < (unsigned int)FCC_MSG_COUNT; ++i) {
        const fcc_bus_msg_desc_t *d = &fcc_bus_msg_table[i];
        fcc_status_t st = fcc_e2e_rx_init(&bus->rx[i], d->data_id, d->max_delta_counter);
        if (st == FCC_OK) {
            st = fcc_e2e_tx_init(&bus->tx[i], d->data_id);
        }
        if (st != FCC_OK) {
            return st;
        }
    }
    return FCC_OK;
}

fcc_status_t fcc_bus_init(fcc_bus_t *bus, uint32_t node)
{
    if (node >= FCC_BUS_N_NODES) {
        return FCC_ERR_ARG;
    }
    uint64_t consumes = 0u;
    uint64_t produces = 0u;
    for (unsigned int i = 0u; i < (unsigned int)FCC_MSG_COUNT; ++i) {
        if ((fcc_bus_msg_table[i].receivers & (1u << node)) != 0u) {
            consumes |= MSG_BIT(i);
        }
        if ((fcc_bus_msg_table[i].senders & (1u << node)) != 0u) {
            produces |= MSG_BIT(i);
        }
    }
    return fcc_bus_init_masks(bus, consumes, produces);
}

static fcc_status_t reject(fcc_bus_rx_msg_t *out, fcc_bus_verdict_t verdict, uint32_t *counter,
                           fcc_status_t status)
{
    out->verdict = verdict;
    if (counter != NULL) {
        ++*counter;
    }
    return status;
}

fcc_status_t fcc_bus_receive(fcc_bus_t *bus, const fcc_can_frame_t *frame, fcc_bus_rx_msg_t *out)
{
    if (bus == NULL || frame == NULL || out == NULL) {
        return FCC_ERR_ARG;
    }
    out->msg = FCC_MSG_COUNT;
    out->verdict = FCC_BUS_PASS;
    out->e2e = FCC_E2E_OK;
    out->t_us = frame->t_us;
    fcc_msg_t msg;
    if (fcc_bus_find(frame->id, &msg) != FCC_OK || (bus->consumes & MSG_BIT(msg)) == 0u) {
        return reject(out, FCC_BUS_UNKNOWN_ID, &bus->unknown_id, FCC_ERR_FORMAT);
    }
    out->msg = msg;
    if (frame->dlc != FCC_E2E_FRAME_LEN) {
        return reject(out, FCC_BUS_WRONG_DLC, &bus->wrong_dlc, FCC_ERR_FORMAT);
    }
    if (fcc_bus_msg_table[msg].data_id != 0u) {
        out->e2e = fcc_e2e_rx_check(&bus->rx[msg], frame->data, frame->dlc);
        if (!fcc_e2e_usable(out->e2e)) {
            return reject(out, FCC_BUS_E2E, NULL, FCC_ERR_FORMAT);
        }
    }
    const fcc_status_t st = fcc_bus_decode(msg, frame->data, &out->data);
    if (st == FCC_ERR_RANGE) {
        return reject(out, FCC_BUS_OUT_OF_RANGE, &bus->out_of_range, FCC_ERR_RANGE);
    }
    return st;
}

bool fcc_bus_end_period(fcc_bus_t *bus, fcc_msg_t msg)
{
    if (bus == NULL || fcc_bus_desc(msg) == NULL || (bus->consumes & MSG_BIT(msg)) == 0u ||
        fcc_bus_msg_table[msg].data_id == 0u) {
        return false;
    }
    return fcc_e2e_rx_end_period(&bus->rx[msg]);
}

static fcc_status_t encode(fcc_bus_t *bus, fcc_msg_t msg, const fcc_msg_data_t *data,
                           bool saturate, fcc_can_frame_t *out)
{
    if (bus == NULL || out == NULL) {
        return FCC_ERR_ARG;
    }
    fcc_status_t st = FCC_ERR_ARG;
    bool clamped = false;
    if (fcc_bus_desc(msg) != NULL && (bus->produces & MSG_BIT(msg)) != 0u) {
        st = pack_checked(msg, data, saturate, out->data, &clamped);
    }
    if (st == FCC_OK && fcc_bus_msg_table[msg].data_id != 0u) {
        st = fcc_e2e_tx_protect(&bus->tx[msg], out->data);
    }
    if (st != FCC_OK) {
        ++bus->tx_refused;
        return st;
    }
    if (clamped) {
        ++bus->tx_saturated;
    }
    out->id = fcc_bus_msg_table[msg].id;
    out->dlc = (uint8_t)FCC_E2E_FRAME_LEN;
    out->t_us = 0u;
    return FCC_OK;
}

fcc_status_t fcc_bus_encode(fcc_bus_t *bus, fcc_msg_t msg, const fcc_msg_data_t *data,
                            fcc_can_frame_t *out)
{
    return encode(bus, msg, data, false, out);
}

fcc_status_t fcc_bus_encode_sat(fcc_bus_t *bus, fcc_msg_t msg, const fcc_msg_data_t *data,
                                fcc_can_frame_t *out)
{
    return encode(bus, msg, data, true, out);
}

fcc_status_t fcc_bus_get_counters(const fcc_bus_t *bus, fcc_bus_counters_t *out)
{
    if (bus == NULL || out == NULL) {
        return FCC_ERR_ARG;
    }
    memset(out, 0, sizeof *out);
    for (unsigned int i = 0u; i < (unsigned int)FCC_MSG_COUNT; ++i) {
        for (unsigned int c = 0u; c < (unsigned int)FCC_E2E_N_STATUS; ++c) {
            out->e2e[c] += bus->rx[i].count[c];
        }
        if ((bus->consumes & MSG_BIT(i)) != 0u && bus->rx[i].stale) {
            ++out->stale_now;
        }
    }
    out->unknown_id = bus->unknown_id;
    out->wrong_dlc = bus->wrong_dlc;
    out->out_of_range = bus->out_of_range;
    out->tx_refused = bus->tx_refused;
    out->tx_saturated = bus->tx_saturated;
    return FCC_OK;
}

const char *fcc_bus_verdict_str(fcc_bus_verdict_t verdict)
{
    switch (verdict) {
    case FCC_BUS_PASS: return "pass";
    case FCC_BUS_UNKNOWN_ID: return "unknown id";
    case FCC_BUS_WRONG_DLC: return "wrong DLC";
    case FCC_BUS_E2E: return "E2E check failed";
    case FCC_BUS_OUT_OF_RANGE: return "value out of range";
    default: return "unknown verdict";
    }
}
