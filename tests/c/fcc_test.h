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

#define fcc_assert_ok(expr) assert_int_equal((expr), FCC_OK)

#endif /* FCC_TEST_H */
