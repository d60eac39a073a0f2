/*
 * fcc_opt.c -- command-line helpers of the host programs (see fcc_opt.h).
 */
#include "fcc_opt.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Longest option name (with "--" and the NUL) fcc_opt_take() looks up;
 * longer ones are unknown. */
#define NAME_MAX_LEN 64u

fcc_opt_result_t fcc_opt_fail(char *err, size_t err_len, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    (void)vsnprintf(err, err_len, fmt, ap);
    va_end(ap);
    return FCC_OPT_ERROR;
}

int fcc_opt_list(const char *s, double *v, int max)
{
    int n = 0;
    const char *p = s;
    for (;;) {
        if (n == max || *p == '\0') {
            return -1;
        }
        char *end = NULL;
        errno = 0;
        v[n] = strtod(p, &end);
        if (end == p || errno == ERANGE || !isfinite(v[n])) {
            return -1;
        }
        ++n;
        if (*end == '\0') {
            return n;
        }
        if (*end != ',') {
            return -1;
        }
        p = end + 1;
    }
}

fcc_opt_result_t fcc_opt_double(const char *name, const char *val, double lo, double hi,
                                double *out, char *err, size_t err_len)
{
    double v = 0.0;
    if (val == NULL) {
        return FCC_OPT_NEED_VALUE;
    }
    if (fcc_opt_list(val, &v, 1) != 1) {
        return fcc_opt_fail(err, err_len, "%s: '%s' is not a finite number", name, val);
    }
    if (v < lo || v > hi) {
        return fcc_opt_fail(err, err_len, "%s: %g is outside %g..%g", name, v, lo, hi);
    }
    *out = v;
    return FCC_OPT_DONE;
}

fcc_opt_result_t fcc_opt_real(const char *name, const char *val, double lo, double hi,
                              fcc_real_t *out, char *err, size_t err_len)
{
    double v = 0.0;
    const fcc_opt_result_t r = fcc_opt_double(name, val, lo, hi, &v, err, err_len);
    if (r == FCC_OPT_DONE) {
        *out = (fcc_real_t)v;
    }
    return r;
}

fcc_opt_result_t fcc_opt_uint(const char *name, const char *val, unsigned long lo,
                              unsigned long hi, unsigned long *out, char *err, size_t err_len)
{
    if (val == NULL) {
        return FCC_OPT_NEED_VALUE;
    }
    char *end = NULL;
    errno = 0;
    /* strtoul would take "-1" as ULONG_MAX and skip leading blanks */
    const unsigned long v = (val[0] >= '0' && val[0] <= '9') ? strtoul(val, &end, 10) : 0u;
    if (end == NULL || *end != '\0' || errno == ERANGE) {
        return fcc_opt_fail(err, err_len, "%s: '%s' is not a non-negative integer", name, val);
    }
    if (v < lo || v > hi) {
        return fcc_opt_fail(err, err_len, "%s: %lu is outside %lu..%lu", name, v, lo, hi);
    }
    *out = v;
    return FCC_OPT_DONE;
}

fcc_opt_result_t fcc_opt_u16(const char *name, const char *val, unsigned long lo,
                             unsigned long hi, uint16_t *out, char *err, size_t err_len)
{
    unsigned long v = 0u;
    const unsigned long top = (hi < UINT16_MAX) ? hi : UINT16_MAX;
    const fcc_opt_result_t r = fcc_opt_uint(name, val, lo, top, &v, err, err_len);
    if (r == FCC_OPT_DONE) {
        *out = (uint16_t)v;
    }
    return r;
}

fcc_opt_result_t fcc_opt_choice(const char *name, const char *val, const char *const *names,
                                int n, int *out, char *err, size_t err_len)
{
    if (val == NULL) {
        return FCC_OPT_NEED_VALUE;
    }
    for (int i = 0; i < n; ++i) {
        if (strcmp(val, names[i]) == 0) {
            *out = i;
            return FCC_OPT_DONE;
        }
    }
    char list[160] = "";
    size_t used = 0u;
    for (int i = 0; i < n && used < sizeof list; ++i) {
        const char *sep = (i == 0) ? "" : (i == n - 1) ? " or " : ", ";
        const int w = snprintf(list + used, sizeof list - used, "%s%s", sep, names[i]);
        used += (w > 0) ? (size_t)w : 0u;
    }
    return fcc_opt_fail(err, err_len, "%s: '%s' is not %s", name, val, list);
}

fcc_opt_result_t fcc_opt_mat2(const char *name, const char *val, fcc_real_t m[4], char *err,
                              size_t err_len)
{
    double v[4];
    if (val == NULL) {
        return FCC_OPT_NEED_VALUE;
    }
    const int n = fcc_opt_list(val, v, 4);
    if (n == 1 || n == 2) {
        m[0] = (fcc_real_t)v[0];
        m[1] = FCC_R(0.0);
        m[2] = FCC_R(0.0);
        m[3] = (fcc_real_t)v[n - 1];
        return FCC_OPT_DONE;
    }
    if (n == 4) {
        for (int i = 0; i < 4; ++i) {
            m[i] = (fcc_real_t)v[i];
        }
        return FCC_OPT_DONE;
    }
    return fcc_opt_fail(err, err_len,
                        "%s: expected 1, 2 or 4 comma-separated finite numbers, got '%s'", name,
                        val);
}

fcc_opt_result_t fcc_opt_flag(const char *name, const char *val, bool *field, bool value,
                              char *err, size_t err_len)
{
    if (val != NULL) {
        return fcc_opt_fail(err, err_len, "%s takes no value (got '%s')", name, val);
    }
    *field = value;
    return FCC_OPT_DONE;
}

fcc_opt_result_t fcc_opt_take(int argc, char *const *argv, int *i, fcc_opt_handler_t handler,
                              void *ctx, const char *hint, char *err, size_t err_len)
{
    const char *arg = argv[*i];
    const char *eq = strchr(arg, '=');
    const size_t n = (eq != NULL) ? (size_t)(eq - arg) : strlen(arg);
    char name[NAME_MAX_LEN];
    if (n >= sizeof name) {
        return fcc_opt_fail(err, err_len, "unknown option '%s' (%s)", arg, hint);
    }
    memcpy(name, arg, n);
    name[n] = '\0';
    fcc_opt_result_t r = handler(ctx, name, (eq != NULL) ? eq + 1 : NULL, err, err_len);
    if (r == FCC_OPT_NEED_VALUE && *i + 1 < argc) {
        *i += 1;
        r = handler(ctx, name, argv[*i], err, err_len);
    }
    if (r == FCC_OPT_NOT_MINE) {
        return fcc_opt_fail(err, err_len, "unknown option '%s' (%s)", name, hint);
    }
    if (r == FCC_OPT_NEED_VALUE) {
        return fcc_opt_fail(err, err_len, "option %s needs a value (%s)", name, hint);
    }
    return r;
}
