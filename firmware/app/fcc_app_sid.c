/*
 * fcc_app_sid.c -- identification application (see fcc_app_sid.h).
 */
#include "fcc_app_sid.h"

#include <stddef.h>
#include <string.h>

/* The AZKF, ZKF and KF frames have one layout (the DBC says "same layout"),
 * so one filler writes the AZKF member and the frame layer encodes it under
 * each message's identifier.  These checks make the build fail if the DBC
 * ever gives them different layouts. */
#define FCC_SAME_OFFSET(a, b, f) (offsetof(a, f) == offsetof(b, f))
typedef char fcc_app_sid_assert_state[(
    sizeof(fcc_msg_sid_azkf_state_t) == sizeof(fcc_msg_sid_kf_state_t) &&
    FCC_SAME_OFFSET(fcc_msg_sid_azkf_state_t, fcc_msg_sid_kf_state_t, step) &&
    FCC_SAME_OFFSET(fcc_msg_sid_azkf_state_t, fcc_msg_sid_zkf_state_t, step) &&
    FCC_SAME_OFFSET(fcc_msg_sid_azkf_model_b_t, fcc_msg_sid_kf_model_b_t, gain_norm) &&
    FCC_SAME_OFFSET(fcc_msg_sid_azkf_model_b_t, fcc_msg_sid_zkf_model_b_t, gain_norm)) ? 1 : -1];

/* First frame (STATE) of each filter, in sending order; BOUNDS, MODEL_A and
 * MODEL_B follow it in the message table. */
static const struct {
    fcc_sid_filter_t filter;
    fcc_msg_t first;
} k_out_order[FCC_APP_SID_N_FILTERS] = {
    {FCC_SID_AZKF, FCC_MSG_SID_AZKF_STATE},
    {FCC_SID_ZKF, FCC_MSG_SID_ZKF_STATE},
    {FCC_SID_KF, FCC_MSG_SID_KF_STATE},
};

/* The input slots are the DBC's cdrw inputs (FccApp), in identifier order: a frame added to
 * or taken from them in the DBC stops the build here until the slots follow. */
typedef char fcc_app_sid_inputs_are_the_dbcs[(FCC_APP_SID_N_INPUTS == FCC_BUS_APP_CDRW_N_INPUTS) ? 1
                                                                                         : -1];

void fcc_app_sid_config_default(fcc_app_sid_config_t *cfg)
{
    if (cfg != NULL) {
        fcc_sid_config_default(&cfg->base, FCC_SID_AZKF);
    }
}

static fcc_status_t start_loops(fcc_app_sid_t *app)
{
    for (unsigned int f = 0u; f < FCC_APP_SID_N_FILTERS; ++f) {
        fcc_sid_config_t c = app->cfg.base;
        c.filter = (fcc_sid_filter_t)f;
        const fcc_status_t st = fcc_sid_init(&app->loop[f], &c);
        if (st != FCC_OK) {
            return st;
        }
    }
    for (unsigned int i = 0u; i < FCC_APP_SID_N_INPUTS; ++i) {
        fcc_sensor_reset(&app->in[i]);
    }
    app->de_last = FCC_R(0.0);
    memset(&app->last, 0, sizeof app->last);
    return FCC_OK;
}

fcc_status_t fcc_app_sid_init(fcc_app_sid_t *app, const fcc_app_sid_config_t *cfg)
{
    if (app == NULL || cfg == NULL) {
        return FCC_ERR_ARG;
    }
    for (unsigned int f = 0u; f < FCC_APP_SID_N_FILTERS; ++f) {
        fcc_sid_config_t c = cfg->base;
        c.filter = (fcc_sid_filter_t)f;
        const fcc_status_t st = fcc_sid_config_check(&c);
        if (st != FCC_OK) {
            return st;
        }
    }
    app->cfg = *cfg;
    for (unsigned int i = 0u; i < FCC_APP_SID_N_INPUTS; ++i) {
        fcc_sensor_init(&app->in[i], fcc_bus_desc(fcc_bus_app_cdrw_inputs[i])->id);
    }
    app->steps = 0u;
    app->degraded_steps = 0u;
    return start_loops(app);
}

fcc_status_t fcc_app_sid_reset(fcc_app_sid_t *app)
{
    return (app == NULL) ? FCC_ERR_ARG : start_loops(app);
}

fcc_sensor_t *fcc_app_sid_sensor(fcc_app_sid_t *app, fcc_msg_t msg)
{
    if (app == NULL) {
        return NULL;
    }
    for (unsigned int i = 0u; i < FCC_APP_SID_N_INPUTS; ++i) {
        if (fcc_bus_app_cdrw_inputs[i] == msg) {
            return &app->in[i];
        }
    }
    return NULL;
}

fcc_status_t fcc_app_sid_offer(fcc_app_sid_t *app, fcc_msg_t msg, const fcc_msg_data_t *data,
                               uint64_t t_us)
{
    fcc_sensor_t *s = fcc_app_sid_sensor(app, msg);
    if (s == NULL || data == NULL) {
        return FCC_ERR_ARG;
    }
    switch (msg) {
    case FCC_MSG_CDRW_AOA:
        return fcc_sensor_offer(s, data->cdrw_aoa.alpha, data->cdrw_aoa.step, t_us);
    case FCC_MSG_CDRW_PITCH_RATE:
        return fcc_sensor_offer(s, data->cdrw_pitch_rate.q, data->cdrw_pitch_rate.step, t_us);
    default:
        return fcc_sensor_offer(s, data->cdrw_elevator.delta_e, data->cdrw_elevator.step, t_us);
    }
}

/* Judge the three inputs; true when all are usable. */
static bool judge_inputs(fcc_app_sid_t *app, uint32_t k, bool check_step, uint16_t stale_limit,
                         fcc_sensor_sample_t sample[FCC_APP_SID_N_INPUTS],
                         fcc_app_sid_result_t *res)
{
    bool usable = true;
    res->newest_rx_us = 0u;
    for (unsigned int i = 0u; i < FCC_APP_SID_N_INPUTS; ++i) {
        memset(&sample[i], 0, sizeof sample[i]);
        res->input_state[i] =
            fcc_sensor_close(&app->in[i], check_step, (uint16_t)(k & 0xFFFFu), stale_limit,
                             &sample[i]);
        if (!fcc_sensor_usable(res->input_state[i])) {
            usable = false;
        } else if (sample[i].t_us > res->newest_rx_us) {
            res->newest_rx_us = sample[i].t_us;
        } else {
            /* usable, not newer than the newest: nothing to note */
        }
    }
    return usable;
}

fcc_status_t fcc_app_sid_step(fcc_app_sid_t *app, uint32_t k, bool check_step,
                              uint16_t stale_limit, bool oracle_fault,
                              fcc_app_sid_result_t *res)
{
    if (app == NULL || res == NULL) {
        return FCC_ERR_ARG;
    }
    fcc_sensor_sample_t sample[FCC_APP_SID_N_INPUTS];
    memset(res, 0, sizeof *res);
    res->k = k;
    res->measurement_valid = judge_inputs(app, k, check_step, stale_limit, sample, res);
    if (fcc_sensor_usable(res->input_state[FCC_APP_SID_IN_DE])) {
        app->de_last = sample[FCC_APP_SID_IN_DE].value;
    }
    res->status = FCC_OK;
    bool loop_trouble = false;
    for (unsigned int f = 0u; f < FCC_APP_SID_N_FILTERS; ++f) {
        const fcc_status_t st = fcc_sid_step(&app->loop[f], sample[FCC_APP_SID_IN_ALPHA].value,
                                             sample[FCC_APP_SID_IN_Q].value, app->de_last,
                                             oracle_fault, res->measurement_valid, &res->out[f]);
        /* A filter that did not step is a step error (its outputs are stale); a rejected
         * measurement or a refused MLS fit only degrades the step (the loop stepped). */
        if (!res->out[f].stepped && res->status == FCC_OK) {
            res->status = st; /* != FCC_OK: a filter that refuses to step says why */
        }
        loop_trouble = loop_trouble || st != FCC_OK || !res->out[f].stepped;
    }
    res->degraded = !res->measurement_valid || loop_trouble;
    app->last = *res;
    ++app->steps;
    if (res->degraded) {
        ++app->degraded_steps;
    }
    return res->status;
}

/* ---- frames ------------------------------------------------------------------- */

static void fill_state(const fcc_sid_out_t *o, bool fault, bool degraded, uint32_t k,
                       fcc_msg_data_t *d)
{
    memset(d, 0, sizeof *d);
    d->sid_azkf_state.alpha_hat = o->x_hat[0];
    d->sid_azkf_state.q_hat = o->x_hat[1];
    d->sid_azkf_state.order = (uint16_t)(o->order > 1023u ? 1023u : o->order);
    d->sid_azkf_state.fault = fault;
    d->sid_azkf_state.degraded = degraded;
    d->sid_azkf_state.step = (uint16_t)(k & 0x0FFFu);
}

static void fill_bounds(const fcc_sid_out_t *o, fcc_msg_data_t *d)
{
    memset(d, 0, sizeof *d);
    d->sid_azkf_bounds.alpha_lo = o->lo[0];
    d->sid_azkf_bounds.alpha_hi = o->hi[0];
    d->sid_azkf_bounds.q_lo = o->lo[1];
    d->sid_azkf_bounds.q_hi = o->hi[1];
}

static void fill_model_a(const fcc_sid_out_t *o, fcc_msg_data_t *d)
{
    memset(d, 0, sizeof *d);
    d->sid_azkf_model_a.a11 = o->model.a[0];
    d->sid_azkf_model_a.a12 = o->model.a[1];
    d->sid_azkf_model_a.a21 = o->model.a[2];
    d->sid_azkf_model_a.a22 = o->model.a[3];
}

static void fill_model_b(const fcc_sid_out_t *o, fcc_msg_data_t *d)
{
    memset(d, 0, sizeof *d);
    d->sid_azkf_model_b.b1 = o->model.b[0];
    d->sid_azkf_model_b.b2 = o->model.b[1];
    d->sid_azkf_model_b.rho = o->rho;
    d->sid_azkf_model_b.gain_norm = o->gain_norm;
}

fcc_status_t fcc_app_sid_encode(const fcc_app_sid_result_t *res, fcc_bus_t *bus,
                                fcc_can_frame_t frames[FCC_APP_SID_N_FRAMES], uint32_t *n_frames)
{
    if (res == NULL || bus == NULL || frames == NULL || n_frames == NULL) {
        return FCC_ERR_ARG;
    }
    /* The detector runs in the AZKF loop; the other rows show its flag for
     * information (DBC comment), so the three rows of a step agree. */
    const bool fault = res->out[FCC_SID_AZKF].fault;
    fcc_status_t first = FCC_OK;
    *n_frames = 0u;
    for (unsigned int i = 0u; i < FCC_APP_SID_N_FILTERS; ++i) {
        const fcc_sid_out_t *o = &res->out[k_out_order[i].filter];
        const bool degraded = res->degraded || o->status != FCC_OK || !o->stepped;
        for (unsigned int part = 0u; part < 4u; ++part) {
            fcc_msg_data_t d;
            switch (part) {
            case 0u: fill_state(o, fault, degraded, res->k, &d); break;
            case 1u: fill_bounds(o, &d); break;
            case 2u: fill_model_a(o, &d); break;
            default: fill_model_b(o, &d); break;
            }
            const fcc_msg_t msg = (fcc_msg_t)((unsigned int)k_out_order[i].first + part);
            const fcc_status_t st = fcc_bus_encode_sat(bus, msg, &d, &frames[*n_frames]);
            if (st == FCC_OK) {
                ++*n_frames;
            } else if (first == FCC_OK) {
                first = st;
            } else {
                /* a later refusal: the first one is returned */
            }
        }
    }
    return first;
}

/* ---- the node's interface (fcc_app.h) ------------------------------------------ */

static fcc_status_t ops_config_default(void *cfg)
{
    fcc_app_sid_config_default(cfg);
    return (cfg != NULL) ? FCC_OK : FCC_ERR_ARG;
}

static fcc_status_t ops_init(void *app, const void *cfg)
{
    return fcc_app_sid_init(app, cfg);
}

static fcc_status_t ops_reset(void *app)
{
    return fcc_app_sid_reset(app);
}

static fcc_sensor_t *ops_sensor(void *app, fcc_msg_t msg)
{
    return fcc_app_sid_sensor(app, msg);
}

static const fcc_sensor_t *ops_input(const void *app, uint32_t slot)
{
    const fcc_app_sid_t *a = app;
    return (a != NULL && slot < FCC_APP_SID_N_INPUTS) ? &a->in[slot] : NULL;
}

static fcc_status_t ops_offer(void *app, fcc_msg_t msg, const fcc_msg_data_t *data, uint64_t t_us)
{
    return fcc_app_sid_offer(app, msg, data, t_us);
}

static fcc_status_t ops_step(void *app, const fcc_app_tick_t *tick, fcc_app_step_t *out)
{
    fcc_app_sid_result_t res;
    (void)memset(&res, 0, sizeof res); /* defined when the step refuses its arguments too */
    const fcc_status_t st = fcc_app_sid_step(app, tick->k, tick->check_step, tick->stale_limit,
                                             tick->oracle_fault, &res);
    out->degraded = res.degraded;
    out->reconfigured = false;
    return st;
}

static fcc_status_t ops_encode(const void *app, fcc_bus_t *bus, fcc_can_frame_t *frames,
                               uint32_t *n)
{
    const fcc_app_sid_t *a = app;
    return fcc_app_sid_encode(&a->last, bus, frames, n);
}

static uint32_t ops_period_us(const void *app)
{
    (void)app;
    return FCC_APP_SID_PERIOD_US;
}

/* the step's 12 outputs under one authenticator (SID_OUT_AUTH) */
const fcc_app_ops_t fcc_app_sid_ops = {
    "cdrw", fcc_bus_app_cdrw_inputs, FCC_BUS_APP_CDRW_N_INPUTS, FCC_MSG_SID_OUT_AUTH, 0u,
    ops_config_default, ops_init, ops_reset, ops_sensor, ops_input, ops_offer, ops_step, ops_encode, ops_period_us,
    NULL, NULL, NULL,
};
