#include "fcc_fault.h"

#include <string.h>

void fcc_fdet_config_default(fcc_fdet_config_t *cfg)
{
    if (cfg == NULL) {
        return;
    }
    cfg->mode = FCC_FDET_ZONOTOPE;
    cfg->margin = FCC_FDET_DEFAULT_MARGIN;
    cfg->raise_count = FCC_FDET_DEFAULT_RAISE;
    cfg->hold_count = FCC_FDET_DEFAULT_HOLD;
    cfg->clear_count = FCC_FDET_DEFAULT_CLEAR;
    cfg->max_fault_steps = FCC_FDET_DEFAULT_MAX_FAULT;
}

fcc_status_t fcc_fdet_config_check(const fcc_fdet_config_t *cfg)
{
    if (cfg == NULL) {
        return FCC_ERR_ARG;
    }
    if (cfg->mode != FCC_FDET_ZONOTOPE && cfg->mode != FCC_FDET_ORACLE &&
        cfg->mode != FCC_FDET_OFF) {
        return FCC_ERR_ARG;
    }
    if (!FCC_IS_FINITE(cfg->margin) || !(cfg->margin > FCC_R(0.0)) || cfg->raise_count < 1u ||
        cfg->clear_count < 1u) {
        return FCC_ERR_RANGE;
    }
    return FCC_OK;
}

fcc_status_t fcc_fdet_init(fcc_fdet_t *det, const fcc_fdet_config_t *cfg)
{
    if (det == NULL) {
        return FCC_ERR_ARG;
    }
    const fcc_status_t st = fcc_fdet_config_check(cfg);
    if (st != FCC_OK) {
        return st;
    }
    memset(det, 0, sizeof *det);
    det->cfg = *cfg;
    return FCC_OK;
}

static bool is_inconsistent(const fcc_fdet_t *det, const fcc_real_t innov[2],
                            const fcc_real_t radius[2])
{
    for (size_t i = 0; i < 2u; ++i) {
        const fcc_real_t bound = det->cfg.margin * radius[i];
        /* Written so that a NaN innovation is inconsistent. */
        if (!(FCC_FABS(innov[i]) <= bound)) {
            return true;
        }
    }
    return false;
}

static uint16_t count_up(uint16_t n)
{
    return n < UINT16_MAX ? (uint16_t)(n + 1u) : n;
}

/* Debounce state machine of the ZONOTOPE mode. */
static void debounce(fcc_fdet_t *det, bool bad)
{
    det->inconsistent = bad;
    det->n_bad = bad ? count_up(det->n_bad) : 0u;
    det->n_good = bad ? 0u : count_up(det->n_good);
    if (!det->fault) {
        if (det->refractory_left > 0u) {
            det->refractory_left--;
        } else if (det->n_bad >= det->cfg.raise_count) {
            det->fault = true;
            det->hold_left = det->cfg.hold_count;
            det->n_good = 0u;
            det->fault_steps = 1u;
            det->n_raised++;
        } else {
            /* not enough inconsistent steps yet: no fault */
        }
        return;
    }
    if (det->cfg.max_fault_steps > 0u && det->fault_steps >= det->cfg.max_fault_steps) {
        det->fault = false; /* persistent: the sensor is not the problem */
        det->refractory_left = det->cfg.max_fault_steps;
        det->n_bad = 0u;
        det->n_dropped++;
        return;
    }
    det->fault_steps = count_up(det->fault_steps);
    if (det->hold_left > 0u) {
        det->hold_left--;
        det->n_good = 0u; /* consistency counts only after the hold */
        return;
    }
    if (det->n_good >= det->cfg.clear_count) {
        det->fault = false;
        det->n_bad = 0u;
    }
}

fcc_status_t fcc_fdet_step(fcc_fdet_t *det, const fcc_real_t innov[2], const fcc_real_t radius[2],
                           bool oracle, bool *fault)
{
    if (det == NULL || fault == NULL) {
        return FCC_ERR_ARG;
    }
    switch (det->cfg.mode) {
    case FCC_FDET_ORACLE:
        if (oracle && !det->fault) {
            det->n_raised++;
        }
        det->fault = oracle;
        det->inconsistent = oracle;
        break;
    case FCC_FDET_OFF:
        det->fault = false;
        det->inconsistent = false;
        break;
    case FCC_FDET_ZONOTOPE:
    default:
        if (innov == NULL || radius == NULL) {
            return FCC_ERR_ARG;
        }
        debounce(det, is_inconsistent(det, innov, radius));
        break;
    }
    *fault = det->fault;
    return FCC_OK;
}
