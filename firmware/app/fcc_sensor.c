/*
 * fcc_sensor.c -- per-step sensor verdicts (see fcc_sensor.h).
 */
#include "fcc_sensor.h"

#include <string.h>

void fcc_sensor_init(fcc_sensor_t *s, uint32_t can_id)
{
    if (s == NULL) {
        return;
    }
    memset(s, 0, sizeof *s);
    s->can_id = can_id;
    s->state = FCC_SENSOR_STALE;
}

void fcc_sensor_reset(fcc_sensor_t *s)
{
    if (s == NULL) {
        return;
    }
    s->n_pending = 0u;
    s->n_rejected = 0u;
    s->have_value = false;
    s->missing_run = 0u;
    s->state = FCC_SENSOR_STALE;
}

fcc_status_t fcc_sensor_offer(fcc_sensor_t *s, fcc_real_t value, uint16_t step, uint64_t t_us)
{
    if (s == NULL) {
        return FCC_ERR_ARG;
    }
    if (!FCC_IS_FINITE(value)) {
        fcc_sensor_reject(s);
        return FCC_ERR_NOT_FINITE;
    }
    if (s->n_pending == FCC_SENSOR_MAX_PENDING) {
        memmove(&s->pending[0], &s->pending[1],
                (FCC_SENSOR_MAX_PENDING - 1u) * sizeof s->pending[0]);
        --s->n_pending;
    }
    fcc_sensor_sample_t *p = &s->pending[s->n_pending++];
    p->value = value;
    p->step = step;
    p->t_us = t_us;
    return FCC_OK;
}

void fcc_sensor_reject(fcc_sensor_t *s)
{
    if (s != NULL && s->n_rejected < UINT8_MAX) {
        ++s->n_rejected;
    }
}

/* Newest pending sample that qualifies, or NULL. */
static const fcc_sensor_sample_t *pick(const fcc_sensor_t *s, bool check_step, uint16_t step)
{
    for (unsigned int i = s->n_pending; i > 0u; --i) {
        const fcc_sensor_sample_t *p = &s->pending[i - 1u];
        if (!check_step || p->step == step) {
            return p;
        }
    }
    return NULL;
}

static fcc_sensor_state_t judge(fcc_sensor_t *s, bool check_step, uint16_t step,
                                uint16_t stale_limit, fcc_sensor_sample_t *sample)
{
    const fcc_sensor_sample_t *p = pick(s, check_step, step);
    if (p != NULL) {
        s->last = *p;
        s->have_value = true;
        s->missing_run = 0u;
        *sample = s->last;
        return FCC_SENSOR_OK;
    }
    if (s->missing_run < UINT16_MAX) {
        ++s->missing_run;
    }
    if (s->n_pending > 0u) {
        return FCC_SENSOR_MISALIGNED;
    }
    if (s->n_rejected > 0u) {
        return FCC_SENSOR_REJECTED;
    }
    if (s->have_value && s->missing_run <= stale_limit) {
        *sample = s->last;
        return FCC_SENSOR_HELD;
    }
    return FCC_SENSOR_STALE;
}

fcc_sensor_state_t fcc_sensor_close(fcc_sensor_t *s, bool check_step, uint16_t step,
                                    uint16_t stale_limit, fcc_sensor_sample_t *sample)
{
    if (s == NULL || sample == NULL) {
        return FCC_SENSOR_STALE;
    }
    const fcc_sensor_state_t st = judge(s, check_step, step, stale_limit, sample);
    s->n_pending = 0u;
    s->n_rejected = 0u;
    s->state = st;
    ++s->count[st];
    return st;
}

bool fcc_sensor_usable(fcc_sensor_state_t state)
{
    return state == FCC_SENSOR_OK || state == FCC_SENSOR_HELD;
}

const char *fcc_sensor_state_str(fcc_sensor_state_t state)
{
    switch (state) {
    case FCC_SENSOR_OK: return "OK";
    case FCC_SENSOR_HELD: return "HELD";
    case FCC_SENSOR_STALE: return "STALE";
    case FCC_SENSOR_REJECTED: return "REJECTED";
    case FCC_SENSOR_MISALIGNED: return "MISALIGNED";
    case FCC_SENSOR_N_STATES:
    default: return "UNKNOWN";
    }
}
