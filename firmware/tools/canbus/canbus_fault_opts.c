/*
 * canbus_fault_opts.c -- canbus's fault options (see canbus_fault_opts.h).
 */
#include "canbus_fault_opts.h"

#include <string.h>

#include "tool_args.h"

#define NS_PER_S 1e9
#define SECONDS_MAX 1e6
#define FIELD_LEN 64u

const char *const canbus_babble_names[CANBUS_BABBLE_MAX] = {"babble0", "babble1", "babble2",
                                                             "babble3"};

/* An identifier (0x hex or decimal) up to CANBUS_EXT_ID_MAX. */
static fcc_opt_result_t parse_id(const char *name, const char *s, uint32_t *out, char *err,
                                 size_t len)
{
    unsigned long v = 0u;
    /* a digit first: no blanks or '+' before it, which strtoul would skip */
    const int digit_first = s[0] >= '0' && s[0] <= '9';
    if (!digit_first || tool_args_ulong(s, 0u, CANBUS_EXT_ID_MAX, &v) != 0) {
        return fcc_opt_fail(err, len, "%s: '%s' is not a CAN identifier (0..0x1FFFFFFF)", name,
                            s);
    }
    *out = (uint32_t)v;
    return FCC_OPT_DONE;
}

/* ID or ID-ID into lo..hi. */
static fcc_opt_result_t parse_ids(const char *name, char *s, uint32_t *lo, uint32_t *hi,
                                  char *err, size_t len)
{
    char *dash = strchr(s, '-');
    if (dash != NULL) {
        *dash = '\0';
    }
    if (parse_id(name, s, lo, err, len) != FCC_OPT_DONE ||
        parse_id(name, dash != NULL ? dash + 1 : s, hi, err, len) != FCC_OPT_DONE) {
        return FCC_OPT_ERROR;
    }
    if (*lo > *hi) {
        return fcc_opt_fail(err, len, "%s: identifiers 0x%lX-0x%lX are not in order", name,
                            (unsigned long)*lo, (unsigned long)*hi);
    }
    return FCC_OPT_DONE;
}

static fcc_opt_result_t parse_seconds(const char *name, const char *s, uint64_t *ns, char *err,
                                      size_t len)
{
    double v = 0.0;
    if (fcc_opt_double(name, s, 0.0, SECONDS_MAX, &v, err, len) != FCC_OPT_DONE) {
        return FCC_OPT_ERROR;
    }
    *ns = (uint64_t)(v * NS_PER_S + 0.5);
    return FCC_OPT_DONE;
}

static fcc_opt_result_t parse_u32(const char *name, const char *s, unsigned long lo,
                                  unsigned long hi, uint32_t *out, char *err, size_t len)
{
    unsigned long v = 0u;
    if (fcc_opt_uint(name, s, lo, hi, &v, err, len) != FCC_OPT_DONE) {
        return FCC_OPT_ERROR;
    }
    *out = (uint32_t)v;
    return FCC_OPT_DONE;
}

static fcc_opt_result_t copy_iface(const char *name, const char *s, char *out, char *err,
                                   size_t len)
{
    const size_t n = strlen(s);
    if (n == 0u || n >= CANBUS_IFACE_LEN) {
        return fcc_opt_fail(err, len, "%s: '%s' is not a node's interface", name, s);
    }
    memcpy(out, s, n + 1u);
    return FCC_OPT_DONE;
}

/* One KEY=VALUE of --error. */
static fcc_opt_result_t error_field(canbus_error_opt_t *e, const char *name, const char *key,
                                    char *v, char *err, size_t len)
{
    canbus_fault_t *f = &e->fault;
    if (strcmp(key, "id") == 0) {
        return parse_ids(name, v, &f->id_min, &f->id_max, err, len);
    }
    if (strcmp(key, "node") == 0) {
        return copy_iface(name, v, e->node, err, len);
    }
    if (strcmp(key, "from") == 0) {
        return parse_seconds(name, v, &f->t_from, err, len);
    }
    if (strcmp(key, "to") == 0) {
        return parse_seconds(name, v, &f->t_to, err, len);
    }
    if (strcmp(key, "every") == 0) {
        return parse_u32(name, v, 1u, 1000000u, &f->every, err, len);
    }
    if (strcmp(key, "count") == 0) {
        return parse_u32(name, v, 1u, 1000000000u, &f->count, err, len);
    }
    if (strcmp(key, "superposed") == 0) {
        return parse_u32(name, v, 0u, CANBUS_SUPERPOSED_MAX, &f->superposed, err, len);
    }
    if (strcmp(key, "bit") == 0) {
        if (strcmp(v, "crc-delim") == 0) {
            f->bit = CANBUS_BIT_CRC_DELIM;
            return FCC_OPT_DONE;
        }
        return parse_u32(name, v, 0u, CANBUS_BIT_MAX, &f->bit, err, len);
    }
    return fcc_opt_fail(err, len, "%s: unknown field '%s' (id, node, from, to, every, count, "
                        "bit, superposed)", name, key);
}

/* One KEY=VALUE of --babble. */
static fcc_opt_result_t babble_field(canbus_babble_t *b, const char *name, const char *key,
                                     char *v, char *err, size_t len)
{
    if (strcmp(key, "id") == 0) {
        b->frame.ext = false;
        if (parse_id(name, v, &b->frame.id, err, len) != FCC_OPT_DONE) {
            return FCC_OPT_ERROR;
        }
        b->frame.ext = b->frame.id > CANBUS_STD_ID_MAX;
        return FCC_OPT_DONE;
    }
    if (strcmp(key, "dlc") == 0) {
        uint32_t dlc = 0u;
        if (parse_u32(name, v, 0u, CANBUS_DLC_MAX, &dlc, err, len) != FCC_OPT_DONE) {
            return FCC_OPT_ERROR;
        }
        b->frame.dlc = (uint8_t)dlc;
        return FCC_OPT_DONE;
    }
    if (strcmp(key, "period") == 0) {
        return parse_seconds(name, v, &b->period_ns, err, len);
    }
    if (strcmp(key, "from") == 0) {
        return parse_seconds(name, v, &b->t_from, err, len);
    }
    if (strcmp(key, "to") == 0) {
        return parse_seconds(name, v, &b->t_to, err, len);
    }
    return fcc_opt_fail(err, len, "%s: unknown field '%s' (id, dlc, period, from, to)", name,
                        key);
}

/* One KEY=VALUE of --load. */
static fcc_opt_result_t load_field(canbus_load_cfg_t *l, const char *name, const char *key,
                                   char *v, char *err, size_t len)
{
    if (strcmp(key, "util") == 0) {
        double u = 0.0;
        if (fcc_opt_double(name, v, 1e-6, 1.0, &u, err, len) != FCC_OPT_DONE) {
            return FCC_OPT_ERROR;
        }
        l->ppm = (uint32_t)(u * CANBUS_LOAD_PPM_MAX + 0.5);
        return FCC_OPT_DONE;
    }
    if (strcmp(key, "id") == 0) {
        if (parse_ids(name, v, &l->id_lo, &l->id_hi, err, len) != FCC_OPT_DONE) {
            return FCC_OPT_ERROR;
        }
        return l->id_hi <= CANBUS_STD_ID_MAX
                   ? FCC_OPT_DONE
                   : fcc_opt_fail(err, len, "%s: 11-bit identifiers (up to 0x7FF)", name);
    }
    if (strcmp(key, "seed") == 0) {
        unsigned long seed = 0u;
        if (fcc_opt_uint(name, v, 0u, ~0ul, &seed, err, len) != FCC_OPT_DONE) {
            return FCC_OPT_ERROR;
        }
        l->seed = (uint64_t)seed;
        return FCC_OPT_DONE;
    }
    if (strcmp(key, "from") == 0) {
        return parse_seconds(name, v, &l->start_ns, err, len);
    }
    if (strcmp(key, "to") == 0) {
        return parse_seconds(name, v, &l->end_ns, err, len);
    }
    return fcc_opt_fail(err, len, "%s: unknown field '%s' (util, id, seed, from, to)", name, key);
}

typedef fcc_opt_result_t (*field_fn)(void *target, const char *name, const char *key, char *v,
                                     char *err, size_t len);

static fcc_opt_result_t error_fn(void *t, const char *n, const char *k, char *v, char *e,
                                 size_t l)
{
    return error_field(t, n, k, v, e, l);
}

static fcc_opt_result_t babble_fn(void *t, const char *n, const char *k, char *v, char *e,
                                  size_t l)
{
    return babble_field(t, n, k, v, e, l);
}

static fcc_opt_result_t load_fn(void *t, const char *n, const char *k, char *v, char *e,
                                size_t l)
{
    return load_field(t, n, k, v, e, l);
}

/* KEY=VALUE,KEY=VALUE... each to fn (an empty list: nothing). */
static fcc_opt_result_t fields(const char *name, const char *val, field_fn fn, void *target,
                               char *err, size_t len)
{
    char buf[256];
    if (strlen(val) >= sizeof buf) {
        return fcc_opt_fail(err, len, "%s: too long", name);
    }
    memcpy(buf, val, strlen(val) + 1u);
    for (char *f = buf, *next = NULL; f != NULL; f = next) {
        char *comma = strchr(f, ',');
        next = comma != NULL ? comma + 1 : NULL;
        if (comma != NULL) {
            *comma = '\0';
        }
        char *eq = strchr(f, '=');
        if (eq == NULL || eq[1] == '\0') {
            return fcc_opt_fail(err, len, "%s: '%s' is not KEY=VALUE", name, f);
        }
        *eq = '\0';
        if (fn(target, name, f, eq + 1, err, len) != FCC_OPT_DONE) {
            return FCC_OPT_ERROR;
        }
    }
    return FCC_OPT_DONE;
}

static void default_error(canbus_error_opt_t *e)
{
    memset(e, 0, sizeof *e);
    e->fault.id_max = CANBUS_EXT_ID_MAX;
    e->fault.node = CANBUS_ANY_NODE;
    e->fault.t_to = UINT64_MAX;
    e->fault.every = 1u;
    e->fault.bit = CANBUS_BIT_CRC_DELIM;
}

static fcc_opt_result_t window_in_order(const char *name, uint64_t from, uint64_t to, char *err,
                                        size_t len)
{
    return from <= to ? FCC_OPT_DONE
                      : fcc_opt_fail(err, len, "%s: from is after to", name);
}

/* IFACE[@S]: its frames corrupted from S until it is bus-off. */
static fcc_opt_result_t bus_off_opt(canbus_error_opt_t *e, const char *name, const char *val,
                                    char *err, size_t len)
{
    char buf[CANBUS_IFACE_LEN + 32u];
    if (strlen(val) >= sizeof buf) {
        return fcc_opt_fail(err, len, "%s: too long", name);
    }
    memcpy(buf, val, strlen(val) + 1u);
    char *at = strchr(buf, '@');
    if (at != NULL) {
        *at = '\0';
        if (parse_seconds(name, at + 1, &e->fault.t_from, err, len) != FCC_OPT_DONE) {
            return FCC_OPT_ERROR;
        }
    }
    e->fault.until_bus_off = true;
    return copy_iface(name, buf, e->node, err, len);
}

/* --load FIELDS: a background node (util=0.5, id=0x200-0x6FF by default, as bus_load's). */
static fcc_opt_result_t load_opt(canbus_fault_opts_t *o, const char *name, const char *val,
                                 char *err, size_t len)
{
    if (val == NULL) {
        return FCC_OPT_NEED_VALUE;
    }
    if (o->loads == CANBUS_LOADS_MAX) {
        return fcc_opt_fail(err, len, "%s: at most %u background loads", name, CANBUS_LOADS_MAX);
    }
    canbus_load_cfg_t *l = &o->load[o->loads];
    memset(l, 0, sizeof *l);
    l->id_lo = 0x200u;
    l->id_hi = 0x6FFu;
    l->ppm = CANBUS_LOAD_PPM_MAX / 2u;
    l->end_ns = UINT64_MAX;
    if (fields(name, val, load_fn, l, err, len) != FCC_OPT_DONE) {
        return FCC_OPT_ERROR;
    }
    if (l->start_ns >= l->end_ns) {
        return fcc_opt_fail(err, len, "%s: from is not before to", name);
    }
    ++o->loads;
    return FCC_OPT_DONE;
}

fcc_opt_result_t canbus_fault_opt(canbus_fault_opts_t *o, const char *name, const char *val,
                                  char *err, size_t len)
{
    if (strcmp(name, "--epoch") == 0) {
        if (val == NULL) {
            return FCC_OPT_NEED_VALUE;
        }
        const size_t n = strcmp(val, "first-frame") == 0 ? 0u : strlen(val);
        if (n >= sizeof o->epoch_file || (n == 0u && val[0] == '\0')) {
            return fcc_opt_fail(err, len, "%s: first-frame or a file name (shorter than %u)",
                                name, (unsigned)sizeof o->epoch_file);
        }
        memcpy(o->epoch_file, val, n);
        o->epoch_file[n] = '\0';
        return FCC_OPT_DONE;
    }
    if (strcmp(name, "--load") == 0) {
        return load_opt(o, name, val, err, len);
    }
    const bool error = strcmp(name, "--error") == 0;
    const bool bus_off = strcmp(name, "--bus-off") == 0;
    if (!error && !bus_off && strcmp(name, "--babble") != 0) {
        return FCC_OPT_NOT_MINE;
    }
    if (val == NULL) {
        return FCC_OPT_NEED_VALUE;
    }
    if (error || bus_off) {
        if (o->errors == CANBUS_FAULTS_MAX) {
            return fcc_opt_fail(err, len, "%s: at most %u --error and --bus-off", name,
                                CANBUS_FAULTS_MAX);
        }
        canbus_error_opt_t *e = &o->error[o->errors];
        default_error(e);
        const fcc_opt_result_t r = error ? fields(name, val, error_fn, e, err, len)
                                         : bus_off_opt(e, name, val, err, len);
        if (r != FCC_OPT_DONE ||
            window_in_order(name, e->fault.t_from, e->fault.t_to, err, len) != FCC_OPT_DONE) {
            return FCC_OPT_ERROR;
        }
        ++o->errors;
        return FCC_OPT_DONE;
    }
    if (o->babbles == CANBUS_BABBLE_MAX) {
        return fcc_opt_fail(err, len, "%s: at most %u babbling nodes", name, CANBUS_BABBLE_MAX);
    }
    canbus_babble_t *b = &o->babble[o->babbles];
    memset(b, 0, sizeof *b);
    b->frame.id = UINT32_MAX;
    b->frame.dlc = CANBUS_DLC_MAX;
    memset(b->frame.data, 0xFF, sizeof b->frame.data);
    b->t_to = UINT64_MAX;
    if (fields(name, val, babble_fn, b, err, len) != FCC_OPT_DONE ||
        window_in_order(name, b->t_from, b->t_to, err, len) != FCC_OPT_DONE) {
        return FCC_OPT_ERROR;
    }
    if (b->frame.id == UINT32_MAX) {
        return fcc_opt_fail(err, len, "%s: id=ID is needed", name);
    }
    b->node = o->babbles++;
    return FCC_OPT_DONE;
}

fcc_opt_result_t canbus_fault_opts_resolve(canbus_fault_opts_t *o, char (*names)[16],
                                           uint32_t n, char *err, size_t len)
{
    for (uint32_t k = 0u; k < o->errors; ++k) {
        canbus_error_opt_t *e = &o->error[k];
        if (e->node[0] == '\0') {
            continue;
        }
        e->fault.node = CANBUS_ANY_NODE;
        for (uint32_t i = 0u; i < n; ++i) {
            if (strcmp(names[i], e->node) == 0) {
                e->fault.node = i;
            }
        }
        if (e->fault.node == CANBUS_ANY_NODE) {
            return fcc_opt_fail(err, len, "%s: %s is not a --node", e->fault.until_bus_off
                                ? "--bus-off" : "--error", e->node);
        }
    }
    return FCC_OPT_DONE;
}

fcc_opt_result_t canbus_fault_opts_pairs(canbus_fault_opts_t *o, const char *const *arg,
                                         uint32_t n, char *err, size_t len)
{
    for (uint32_t k = 0u; k < n; ++k) {
        const char *name = arg[2u * k];
        const fcc_opt_result_t r = canbus_fault_opt(o, name, arg[2u * k + 1u], err, len);
        if (r == FCC_OPT_NOT_MINE) {
            return fcc_opt_fail(err, len, "%s: not a fault option", name);
        }
        if (r != FCC_OPT_DONE) {
            return r == FCC_OPT_NEED_VALUE ? fcc_opt_fail(err, len, "%s: needs a value", name)
                                           : FCC_OPT_ERROR;
        }
    }
    return FCC_OPT_DONE;
}

static uint64_t after(uint64_t t0, uint64_t dt)
{
    return dt > UINT64_MAX - t0 ? UINT64_MAX : t0 + dt;
}

fcc_status_t canbus_fault_opts_arm(const canbus_fault_opts_t *o, canbus_core_t *c,
                                   uint32_t first_extra, uint64_t t0, canbus_load_t *load,
                                   uint32_t *load_node)
{
    fcc_status_t st = FCC_OK;
    for (uint32_t k = 0u; k < o->errors && st == FCC_OK; ++k) {
        canbus_fault_t f = o->error[k].fault;
        f.t_from = after(t0, f.t_from);
        f.t_to = after(t0, f.t_to);
        st = canbus_core_add_fault(c, &f);
    }
    for (uint32_t k = 0u; k < o->babbles && st == FCC_OK; ++k) {
        canbus_babble_t b = o->babble[k];
        b.node = first_extra + k;
        b.t_from = after(t0, b.t_from);
        b.t_to = after(t0, b.t_to);
        st = canbus_core_add_babble(c, &b);
    }
    for (uint32_t k = 0u; k < o->loads && st == FCC_OK; ++k) {
        canbus_load_cfg_t cfg = o->load[k];
        cfg.start_ns = after(t0, cfg.start_ns);
        cfg.end_ns = after(t0, cfg.end_ns);
        st = canbus_load_init(&load[k], &cfg, c->bit_ns);
        load_node[k] = first_extra + o->babbles + k;
    }
    return st;
}
