/*
 * fcc_opt.h -- command-line helpers of the host programs (fcc, sid_replay):
 * the one-line error formatter, the number / list / range / choice parsers,
 * and the walk over one "--name value" / "--name=value" argument.
 *
 * Host only (stdio, strtod): never linked into fcc_core or the target image.
 * One copy, so that the two programs that take the same options refuse the
 * same values with the same words.
 *
 * Protocol.  An option handler gets (name, val) and answers with an
 * fcc_opt_result_t.  val is NULL when the argument had no "=value": a flag
 * is then applied, an option that takes a value answers FCC_OPT_NEED_VALUE
 * and fcc_opt_take() calls it again with the next argument.  Every value
 * parser below answers FCC_OPT_NEED_VALUE for val == NULL, so a handler
 * needs no test of its own for that.
 */
#ifndef FCC_OPT_H
#define FCC_OPT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fcc_types.h"

typedef enum {
    FCC_OPT_ERROR = -1,     /* bad value: one line (no newline) in err */
    FCC_OPT_DONE = 0,       /* applied */
    FCC_OPT_NOT_MINE = 1,   /* not an option of this handler */
    FCC_OPT_NEED_VALUE = 2  /* takes a value and val was NULL */
} fcc_opt_result_t;

typedef fcc_opt_result_t (*fcc_opt_handler_t)(void *ctx, const char *name, const char *val,
                                              char *err, size_t err_len);

/* Formats one line into err; always returns FCC_OPT_ERROR. */
#ifdef __GNUC__
__attribute__((format(printf, 3, 4)))
#endif
fcc_opt_result_t fcc_opt_fail(char *err, size_t err_len, const char *fmt, ...);

/* Comma-separated finite numbers into v: how many (1..max), or -1 (empty
 * item, not a number, overflow, NaN/Inf, more than max). */
int fcc_opt_list(const char *s, double *v, int max);

/* One finite number in lo..hi. */
fcc_opt_result_t fcc_opt_double(const char *name, const char *val, double lo, double hi,
                                double *out, char *err, size_t err_len);
fcc_opt_result_t fcc_opt_real(const char *name, const char *val, double lo, double hi,
                              fcc_real_t *out, char *err, size_t err_len);

/* One decimal integer in lo..hi (no sign). */
fcc_opt_result_t fcc_opt_uint(const char *name, const char *val, unsigned long lo,
                              unsigned long hi, unsigned long *out, char *err, size_t err_len);
fcc_opt_result_t fcc_opt_u16(const char *name, const char *val, unsigned long lo,
                             unsigned long hi, uint16_t *out, char *err, size_t err_len);

/* val is one of names[0..n-1]: its index in *out.  The error lists them
 * ("--x: 'v' is not a, b or c"). */
fcc_opt_result_t fcc_opt_choice(const char *name, const char *val, const char *const *names,
                                int n, int *out, char *err, size_t err_len);

/* A 2x2 matrix, row-major: 1 value s (s I), 2 (diagonal) or 4. */
fcc_opt_result_t fcc_opt_mat2(const char *name, const char *val, fcc_real_t m[4], char *err,
                              size_t err_len);

/* A flag: *field = value; a flag given a value ("--flag=x") is an error. */
fcc_opt_result_t fcc_opt_flag(const char *name, const char *val, bool *field, bool value,
                              char *err, size_t err_len);

/* Applies the option argv[*i] ("--name" or "--name=value") through handler:
 * with the inline value, or NULL and then, if the handler asks for one, the
 * next argument (*i then advances).  FCC_OPT_DONE, or FCC_OPT_ERROR with one
 * line in err: the handler's, or "unknown option '--x' (HINT)" /
 * "option --x needs a value (HINT)" with the program's hint (e.g. "see
 * --help"), the same words in every program. */
fcc_opt_result_t fcc_opt_take(int argc, char *const *argv, int *i, fcc_opt_handler_t handler,
                              void *ctx, const char *hint, char *err, size_t err_len);

#endif /* FCC_OPT_H */
