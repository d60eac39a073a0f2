#include "fcc_types.h"

const char *fcc_status_str(fcc_status_t status)
{
    switch (status) {
    case FCC_OK: return "ok";
    case FCC_ERR_ARG: return "invalid argument";
    case FCC_ERR_SIZE: return "size mismatch";
    case FCC_ERR_SINGULAR: return "singular matrix";
    case FCC_ERR_NOT_POSDEF: return "matrix not positive definite";
    case FCC_ERR_NO_CONVERGENCE: return "no convergence";
    case FCC_ERR_NOT_FINITE: return "non-finite value";
    case FCC_ERR_RANGE: return "value out of range";
    case FCC_ERR_DISAGREE: return "independent methods disagree";
    case FCC_ERR_NOT_STABILIZABLE: return "model not stabilisable";
    case FCC_ERR_NOT_DETECTABLE: return "model not detectable";
    case FCC_ERR_FORMAT: return "malformed input";
    case FCC_ERR_IO: return "input/output error";
    case FCC_ERR_AGAIN: return "try again";
    default: return "unknown status";
    }
}
