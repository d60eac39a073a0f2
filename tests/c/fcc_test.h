/*
 * fcc_test.h -- what every cmocka test program includes.
 *
 * cmocka 1.1 only compares floats; fcc_assert_close() compares reals of either
 * build with a relative and an absolute tolerance and prints both values when
 * it fails.
 */
#ifndef FCC_TEST_H
#define FCC_TEST_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <cmocka.h>

#include "fcc_types.h"

/* Tolerance scale for tests written for the double build: the float build
 * loosens it to what single precision can honestly deliver. */
#ifdef FCC_REAL_FLOAT
#define FCC_TEST_TOL(dbl_tol, flt_tol) (flt_tol)
#else
#define FCC_TEST_TOL(dbl_tol, flt_tol) (dbl_tol)
#endif

static inline void fcc_assert_close_at(double actual, double expected, double rel, double abs_tol,
                                       const char *expr, const char *file, int line)
{
    const double err = fabs(actual - expected);
    const double bound = abs_tol + rel * fabs(expected);
    if (!(err <= bound)) {
        print_error("%s = %.17g, expected %.17g (error %.3g > bound %.3g)\n", expr, actual,
                    expected, err, bound);
        _fail(file, line);
    }
}

#define fcc_assert_close(actual, expected, rel, abs_tol)                                         \
    fcc_assert_close_at((double)(actual), (double)(expected), (rel), (abs_tol), #actual,         \
                        __FILE__, __LINE__)

/* Hex digits into bytes, up to max bytes, stopping at the first non-pair ("-": none). */
static inline size_t fcc_test_hex(const char *s, uint8_t *out, size_t max)
{
    size_t n = 0u;
    if (s[0] == '-' && s[1] == '\0') {
        return 0u;
    }
    while (s[0] != '\0' && s[1] != '\0' && s[0] != ' ' && s[0] != '\n' && n < max) {
        const char b[3] = {s[0], s[1], '\0'};
        out[n++] = (uint8_t)strtoul(b, NULL, 16);
        s += 2;
    }
    return n;
}

#define fcc_assert_ok(expr) assert_int_equal((expr), FCC_OK)

/* A test vector file (tests/vectors/...): each(line, ctx) for every line that is
 * not a '#' comment, then the number of such lines must be `expected` (a file
 * that shrank fails).  A file that cannot be opened fails the test. */
typedef void (*fcc_test_line_fn)(const char *line, void *ctx);

static inline void fcc_test_vector_file(const char *path, unsigned int expected,
                                        fcc_test_line_fn each, void *ctx)
{
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        fail_msg("cannot open %s", path);
        return;
    }
    char line[512];
    unsigned int n = 0u;
    while (fgets(line, sizeof line, f) != NULL) {
        if (line[0] != '#') {
            each(line, ctx);
            ++n;
        }
    }
    (void)fclose(f);
    assert_int_equal(n, expected);
}

/* Matrix-relative comparison: every entry of actual within rel * max|expected|
 * (a matrix's small entries carry the absolute error of its large ones).  The
 * actual values are read through a getter so that one routine serves arrays of
 * fcc_real_t and of double in both builds. */
static inline double fcc_test_real_at(const void *v, size_t i)
{
    return (double)((const fcc_real_t *)v)[i];
}

static inline double fcc_test_double_at(const void *v, size_t i)
{
    return ((const double *)v)[i];
}

static inline void fcc_assert_matrix_close_at(double (*get)(const void *, size_t),
                                              const void *actual, const double *expected,
                                              size_t n, double rel, const char *what,
                                              const char *file, int line)
{
    double scale = 0.0;
    for (size_t i = 0; i < n; ++i) {
        scale = fabs(expected[i]) > scale ? fabs(expected[i]) : scale;
    }
    for (size_t i = 0; i < n; ++i) {
        const double err = fabs(get(actual, i) - expected[i]);
        if (!(err <= rel * scale)) {
            print_error("%s[%zu] = %.17g, expected %.17g (matrix-relative error %.3g > %.3g)\n",
                        what, i, get(actual, i), expected[i], scale > 0.0 ? err / scale : err, rel);
            _fail(file, line);
        }
    }
}

#define fcc_assert_reals_close(actual, expected, n, rel, what)                                   \
    fcc_assert_matrix_close_at(fcc_test_real_at, (actual), (expected), (n), (rel), (what),       \
                               __FILE__, __LINE__)
#define fcc_assert_doubles_close(actual, expected, n, rel, what)                                 \
    fcc_assert_matrix_close_at(fcc_test_double_at, (actual), (expected), (n), (rel), (what),     \
                               __FILE__, __LINE__)

#endif /* FCC_TEST_H */
