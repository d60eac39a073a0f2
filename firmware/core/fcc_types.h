/*
 * fcc_types.h -- the few definitions every firmware module shares.
 *
 * The real type is chosen at build time (FCC_REAL_FLOAT for single-precision
 * microcontroller builds, double otherwise).  Write literals with FCC_R() and
 * call maths through the FCC_ macros so the same source compiles warning-free
 * under -Wconversion -Wdouble-promotion in both builds.
 *
 * Error convention (after libcanard): functions that can fail return
 * fcc_status_t; FCC_OK is zero and every error is negative.  FCC_TRY (below)
 * passes a failure up to the caller.
 */
#ifndef FCC_TYPES_H
#define FCC_TYPES_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#ifdef FCC_REAL_FLOAT
typedef float fcc_real_t;
#define FCC_R(x) (x##f)
#define FCC_SQRT sqrtf
#define FCC_FABS fabsf
#define FCC_EXP expf
#define FCC_LOG logf
#define FCC_POW powf
#define FCC_HYPOT hypotf
#define FCC_FLOOR floorf
#define FCC_ROUND roundf
#define FCC_LDEXP ldexpf
#define FCC_FREXP frexpf
#define FCC_COPYSIGN copysignf
#define FCC_EPS FCC_R(1.1920929e-07)
#define FCC_REAL_MAX FCC_R(3.40282347e+38)
#else
typedef double fcc_real_t;
#define FCC_R(x) (x)
#define FCC_SQRT sqrt
#define FCC_FABS fabs
#define FCC_EXP exp
#define FCC_LOG log
#define FCC_POW pow
#define FCC_HYPOT hypot
#define FCC_FLOOR floor
#define FCC_ROUND round
#define FCC_LDEXP ldexp
#define FCC_FREXP frexp
#define FCC_COPYSIGN copysign
#define FCC_EPS FCC_R(2.220446049250313e-16)
#define FCC_REAL_MAX FCC_R(1.7976931348623157e+308)
#endif

/* True when x is neither NaN nor infinite (C99 isfinite works on both types). */
#define FCC_IS_FINITE(x) (isfinite(x))

typedef int32_t fcc_status_t;

enum {
    FCC_OK = 0,
    FCC_ERR_ARG = -2,            /* bad argument: NULL, size out of bounds, NaN input */
    FCC_ERR_SIZE = -3,           /* dimensions do not fit the operation or storage */
    FCC_ERR_SINGULAR = -4,       /* matrix singular or too ill-conditioned */
    FCC_ERR_NOT_POSDEF = -5,     /* Cholesky met a non-positive pivot */
    FCC_ERR_NO_CONVERGENCE = -6, /* iteration limit reached */
    FCC_ERR_NOT_FINITE = -7,     /* a result would be NaN or infinite */
    FCC_ERR_RANGE = -8,          /* a value outside its documented range */
    FCC_ERR_DISAGREE = -9,       /* two independent methods disagree */
    FCC_ERR_NOT_STABILIZABLE = -10,
    FCC_ERR_NOT_DETECTABLE = -11,
    FCC_ERR_FORMAT = -12,        /* malformed frame or record */
    FCC_ERR_IO = -13,            /* port-level input/output failure */
    FCC_ERR_AGAIN = -14          /* nothing to do now; try later */
};

/* Propagate a failure: FCC_TRY(fcc_mat_mul(&a, &b, &c)); returns the status
 * from the enclosing function (which returns fcc_status_t) unless it is
 * FCC_OK. */
#define FCC_TRY(expr)                                                                             \
    do {                                                                                          \
        const fcc_status_t fcc_try_status_ = (expr);                                              \
        if (fcc_try_status_ != FCC_OK) {                                                          \
            return fcc_try_status_;                                                               \
        }                                                                                         \
    } while (0)

/* A short, static, human-readable name of a status code (never NULL). */
const char *fcc_status_str(fcc_status_t status);

#endif /* FCC_TYPES_H */
