/*
 * fcc_app_msl.c -- missile autopilot application (see fcc_app_msl.h).
 */
#include "fcc_app_msl.h"

#include <string.h>

/* The input slots are the DBC's missile inputs (FccApp), in identifier order: a frame added to
 * or taken from them in the DBC stops the build here until the slots follow. */
typedef char
    fcc_app_msl_inputs_are_the_dbcs[(FCC_APP_MSL_N_INPUTS == FCC_BUS_APP_MISSILE_N_INPUTS) ? 1 : -1];

fcc_status_t fcc_app_msl_config_default(fcc_app_msl_config_t *cfg)
{
    if (cfg == NULL) {
        return FCC_ERR_ARG;
    }
    memset(cfg, 0, sizeof *cfg);
    cfg->solver = FCC_LQG_SOLVER_HAMILTONIAN;
    cfg->period = FCC_APP_MSL_DEFAULT_T;
    cfg->bits = (uint8_t)FCC_APP_MSL_DEFAULT_BITS;
    return fcc_lqg_plant_default(&cfg->plant);
}

bool fcc_app_msl_valid(fcc_real_t period, uint8_t bits)
{
    return FCC_IS_FINITE(period) && period >= FCC_APP_MSL_T_MIN && period <= FCC_APP_MSL_T_MAX &&
           bits >= FCC_LQG_BITS_MIN && bits <= FCC_LQG_BITS_MAX;
}

/* Design (period, bits) into slot s; the slot is untouched on error. */
static fcc_status_t design_into(fcc_app_msl_t *app, unsigned int s, fcc_real_t period,
                                uint8_t bits)
{
    const fcc_app_msl_slot_t *cur = &app->slot[app->active];
    fcc_app_msl_slot_t *dst = &app->slot[s];
    if (s != app->active && cur->period == period && cur->design.t == period &&
        cur->design.delay == app->cfg.delay) {
        /* Only N changes: the gains do not depend on the converter. */
        dst->design = cur->design;
    } else {
        const fcc_status_t st =
            fcc_lqg_design_delayed(&app->cfg.plant, period, (double)app->cfg.delay,
                                   app->cfg.solver, &dst->design, &app->ws);
        if (st != FCC_OK) {
            return st;
        }
    }
    dst->period = period;
    dst->bits = bits;
    return FCC_OK;
}

/* Make slot s the one in use; the estimate xbar carries over. */
static fcc_status_t switch_to(fcc_app_msl_t *app, unsigned int s, const fcc_real_t *x_pred)
{
    fcc_real_t x0[FCC_LQG_NX];
    if (x_pred != NULL) {
        memcpy(x0, x_pred, sizeof x0);
    }
    fcc_lqg_ctrl_t next;
    const fcc_status_t st = fcc_lqg_ctrl_init(&next, &app->slot[s].design, app->slot[s].bits,
                                              (x_pred != NULL) ? x0 : NULL);
    if (st != FCC_OK) {
        return st;
    }
    next.updates = app->ctrl.updates;
    next.u_prev = app->ctrl.u_prev; /* the command still acting on the plant */
    next.predictions = app->ctrl.predictions;
    app->ctrl = next;
    app->active = (uint8_t)s;
    return FCC_OK;
}

fcc_status_t fcc_app_msl_init(fcc_app_msl_t *app, const fcc_app_msl_config_t *cfg)
{
    if (app == NULL || cfg == NULL) {
        return FCC_ERR_ARG;
    }
    if (!fcc_app_msl_valid(cfg->period, cfg->bits) || !FCC_IS_FINITE(cfg->delay) ||
        cfg->delay < FCC_R(0.0) || cfg->delay >= cfg->period) {
        return FCC_ERR_RANGE;
    }
    memset(&app->ctrl, 0, sizeof app->ctrl);
    app->cfg = *cfg;
    app->active = 0u;
    app->slot[0].period = FCC_R(0.0);
    app->slot[0].design.t = FCC_R(0.0);
    fcc_status_t st = design_into(app, 0u, cfg->period, cfg->bits);
    if (st == FCC_OK) {
        st = switch_to(app, 0u, NULL);
    }
    if (st != FCC_OK) {
        return st;
    }
    app->spare = FCC_APP_MSL_SPARE_FREE;
    for (unsigned int i = 0u; i < FCC_APP_MSL_N_INPUTS; ++i) {
        fcc_sensor_init(&app->in[i], fcc_bus_desc(fcc_bus_app_missile_inputs[i])->id);
    }
    memset(&app->last, 0, sizeof app->last);
    app->steps = 0u;
    app->degraded_steps = 0u;
    app->designs_applied = 0u;
    app->designs_failed = 0u;
    app->last_design_status = FCC_OK;
    app->designing = false;
    return FCC_OK;
}

fcc_status_t fcc_app_msl_reset(fcc_app_msl_t *app)
{
    if (app == NULL) {
        return FCC_ERR_ARG;
    }
    for (unsigned int i = 0u; i < FCC_APP_MSL_N_INPUTS; ++i) {
        fcc_sensor_reset(&app->in[i]);
    }
    memset(&app->last, 0, sizeof app->last);
    return fcc_lqg_ctrl_reset(&app->ctrl, NULL);
}

fcc_real_t fcc_app_msl_period(const fcc_app_msl_t *app)
{
    return (app == NULL) ? FCC_R(0.0) : app->slot[app->active].period;
}

uint8_t fcc_app_msl_bits(const fcc_app_msl_t *app)
{
    return (app == NULL) ? 0u : app->slot[app->active].bits;
}

fcc_status_t fcc_app_msl_request(fcc_app_msl_t *app, fcc_real_t period, uint8_t bits)
{
    if (app == NULL || !FCC_IS_FINITE(period)) {
        return FCC_ERR_ARG;
    }
    /* A field at 0 keeps the newest value: the pending request's, if any. */
    const bool pending = app->spare != FCC_APP_MSL_SPARE_FREE;
    const fcc_app_msl_slot_t *cur = &app->slot[app->active];
    const fcc_real_t base_t = pending ? app->want_period : cur->period;
    const uint8_t base_n = pending ? app->want_bits : cur->bits;
    const fcc_real_t t = (period == FCC_R(0.0)) ? base_t : period;
    const uint8_t n = (bits == 0u) ? base_n : bits;
    if (!fcc_app_msl_valid(t, n) || app->cfg.delay >= t) {
        return FCC_ERR_RANGE;
    }
    app->want_period = t;
    app->want_bits = n;
    app->spare = FCC_APP_MSL_SPARE_WANTED;
    app->designing = false; /* a design under way was for older values: start again */
    return FCC_OK;
}

bool fcc_app_msl_wants_design(const fcc_app_msl_t *app)
{
    return app != NULL && app->spare == FCC_APP_MSL_SPARE_WANTED;
}

static fcc_status_t design_failed(fcc_app_msl_t *app, fcc_status_t st)
{
    app->last_design_status = st;
    app->spare = FCC_APP_MSL_SPARE_FREE;
    app->designing = false;
    ++app->designs_failed;
    return st;
}

fcc_status_t fcc_app_msl_background(fcc_app_msl_t *app)
{
    if (app == NULL) {
        return FCC_ERR_ARG;
    }
    if (app->spare != FCC_APP_MSL_SPARE_WANTED) {
        return FCC_ERR_AGAIN;
    }
    const unsigned int spare = 1u - app->active;
    const fcc_app_msl_slot_t *cur = &app->slot[app->active];
    fcc_status_t st = FCC_OK;
    if (!app->designing && cur->period == app->want_period && cur->design.t == app->want_period &&
        cur->design.delay == app->cfg.delay) {
        st = design_into(app, spare, app->want_period, app->want_bits); /* N only: a copy */
    } else {
        if (!app->designing) {
            st = fcc_lqg_design_begin_delayed(&app->cfg.plant, (double)app->want_period,
                                              (double)app->cfg.delay, app->cfg.solver, &app->ws);
            if (st != FCC_OK) {
                return design_failed(app, st);
            }
            app->designing = true;
        }
        st = fcc_lqg_design_slice(&app->ws, &app->slot[spare].design);
        if (st == FCC_ERR_AGAIN) {
            return FCC_OK; /* more slices to come */
        }
        app->designing = false;
        app->slot[spare].period = app->want_period;
        app->slot[spare].bits = app->want_bits;
    }
    if (st != FCC_OK) {
        return design_failed(app, st);
    }
    app->last_design_status = FCC_OK;
    app->spare = FCC_APP_MSL_SPARE_READY;
    return FCC_OK;
}

fcc_sensor_t *fcc_app_msl_sensor(fcc_app_msl_t *app, fcc_msg_t msg)
{
    if (app == NULL) {
        return NULL;
    }
    for (unsigned int i = 0u; i < FCC_APP_MSL_N_INPUTS; ++i) {
        if (fcc_bus_app_missile_inputs[i] == msg) {
            return &app->in[i];
        }
    }
    return NULL;
}

fcc_status_t fcc_app_msl_offer(fcc_app_msl_t *app, fcc_msg_t msg, const fcc_msg_data_t *data,
                               uint64_t t_us)
{
    fcc_sensor_t *s = fcc_app_msl_sensor(app, msg);
    if (s == NULL || data == NULL) {
        return FCC_ERR_ARG;
    }
    if (msg == FCC_MSG_MSL_RATE_GYRO) {
        return fcc_sensor_offer(s, data->msl_rate_gyro.q_g, data->msl_rate_gyro.step, t_us);
    }
    return fcc_sensor_offer(s, data->msl_accelerometer.n_a, data->msl_accelerometer.step, t_us);
}

/* Step 1: a ready design replaces the one in use, between two steps. */
static bool switch_if_ready(fcc_app_msl_t *app)
{
    if (app->spare != FCC_APP_MSL_SPARE_READY) {
        return false;
    }
    app->spare = FCC_APP_MSL_SPARE_FREE;
    fcc_real_t x_pred[FCC_LQG_NX];
    memcpy(x_pred, app->ctrl.x_pred, sizeof x_pred);
    const fcc_status_t st = switch_to(app, 1u - app->active, x_pred);
    app->last_design_status = st;
    if (st != FCC_OK) {
        ++app->designs_failed;
        return false;
    }
    ++app->designs_applied;
    return true;
}

fcc_status_t fcc_app_msl_step(fcc_app_msl_t *app, uint32_t k, bool check_step,
                              uint16_t stale_limit, fcc_app_msl_result_t *res)
{
    if (app == NULL || res == NULL) {
        return FCC_ERR_ARG;
    }
    memset(res, 0, sizeof *res);
    res->k = k;
    res->switched = switch_if_ready(app);
    fcc_real_t y[FCC_LQG_NY] = {FCC_R(0.0), FCC_R(0.0)};
    bool usable = true;
    for (unsigned int i = 0u; i < FCC_APP_MSL_N_INPUTS; ++i) {
        fcc_sensor_sample_t s;
        memset(&s, 0, sizeof s);
        res->input_state[i] =
            fcc_sensor_close(&app->in[i], check_step, (uint16_t)(k & 0xFFFFu), stale_limit, &s);
        if (fcc_sensor_usable(res->input_state[i])) {
            y[i] = s.value;
            res->newest_rx_us = (s.t_us > res->newest_rx_us) ? s.t_us : res->newest_rx_us;
        } else {
            usable = false;
        }
    }
    res->status = FCC_OK;
    if (usable) {
        res->status = fcc_lqg_ctrl_step(&app->ctrl, y, &res->out);
    }
    if (!usable || res->status != FCC_OK) {
        const fcc_status_t st = fcc_lqg_ctrl_predict(&app->ctrl, &res->out);
        if (res->status == FCC_OK) {
            res->status = st;
        }
    }
    res->measured = res->out.measured;
    res->degraded = !res->measured;
    res->bits = app->slot[app->active].bits;
    res->period = app->slot[app->active].period;
    app->last = *res;
    ++app->steps;
    if (res->degraded) {
        ++app->degraded_steps;
    }
    return res->status;
}

fcc_status_t fcc_app_msl_encode(const fcc_app_msl_result_t *res, fcc_bus_t *bus,
                                fcc_can_frame_t frames[2], uint32_t *n_frames)
{
    if (res == NULL || bus == NULL || frames == NULL || n_frames == NULL) {
        return FCC_ERR_ARG;
    }
    *n_frames = 0u;
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    d.msl_elev_cmd.degraded = res->degraded;
    d.msl_elev_cmd.saturated = res->out.saturated;
    d.msl_elev_cmd.step = (uint16_t)(res->k & 0xFFFFu);
    d.msl_elev_cmd.da_bits = res->bits;
    /* The quantizer keeps the code in [-2^(N-1), 2^(N-1)-1] and N <= 16, so
     * it always fits int16; the clamp only documents that it cannot wrap. */
    d.msl_elev_cmd.da_code = (int16_t)((res->out.code > INT16_MAX) ? INT16_MAX
                                       : (res->out.code < INT16_MIN) ? INT16_MIN
                                                                     : res->out.code);
    fcc_status_t first = fcc_bus_encode(bus, FCC_MSG_MSL_ELEV_CMD, &d, &frames[0]);
    if (first == FCC_OK) {
        ++*n_frames;
    }
    memset(&d, 0, sizeof d);
    d.msl_state_est.q_hat = res->out.x_hat[0];
    d.msl_state_est.alpha_t_hat = res->out.x_hat[1];
    d.msl_state_est.w_g_hat = res->out.x_hat[2];
    d.msl_state_est.step = (uint8_t)(res->k & 0xFFu);
    const fcc_status_t st = fcc_bus_encode_sat(bus, FCC_MSG_MSL_STATE_EST, &d, &frames[*n_frames]);
    if (st == FCC_OK) {
        ++*n_frames;
    } else if (first == FCC_OK) {
        first = st;
    } else {
        /* a later refusal: the first one is returned */
    }
    return first;
}

/* ---- the node's interface (fcc_app.h) ------------------------------------------ */

static fcc_status_t ops_config_default(void *cfg)
{
    return fcc_app_msl_config_default(cfg);
}

static fcc_status_t ops_init(void *app, const void *cfg)
{
    return fcc_app_msl_init(app, cfg);
}

static fcc_status_t ops_reset(void *app)
{
    return fcc_app_msl_reset(app);
}

static fcc_sensor_t *ops_sensor(void *app, fcc_msg_t msg)
{
    return fcc_app_msl_sensor(app, msg);
}

static const fcc_sensor_t *ops_input(const void *app, uint32_t slot)
{
    const fcc_app_msl_t *a = app;
    return (a != NULL && slot < FCC_APP_MSL_N_INPUTS) ? &a->in[slot] : NULL;
}

static fcc_status_t ops_offer(void *app, fcc_msg_t msg, const fcc_msg_data_t *data, uint64_t t_us)
{
    return fcc_app_msl_offer(app, msg, data, t_us);
}

static fcc_status_t ops_step(void *app, const fcc_app_tick_t *tick, fcc_app_step_t *out)
{
    fcc_app_msl_result_t res;
    (void)memset(&res, 0, sizeof res); /* defined when the step refuses its arguments too */
    const fcc_status_t st =
        fcc_app_msl_step(app, tick->k, tick->check_step, tick->stale_limit, &res);
    out->degraded = res.degraded;
    out->reconfigured = res.switched;
    return st;
}

static fcc_status_t ops_encode(const void *app, fcc_bus_t *bus, fcc_can_frame_t *frames,
                               uint32_t *n)
{
    const fcc_app_msl_t *a = app;
    return fcc_app_msl_encode(&a->last, bus, frames, n);
}

static uint32_t ops_period_us(const void *app)
{
    return (uint32_t)FCC_ROUND(fcc_app_msl_period(app) * FCC_R(1e6));
}

static fcc_status_t ops_request(void *app, fcc_real_t period, uint8_t bits)
{
    return fcc_app_msl_request(app, period, bits);
}

static fcc_status_t ops_background(void *app)
{
    return fcc_app_msl_background(app);
}

static bool ops_wants_background(const void *app)
{
    return fcc_app_msl_wants_design(app);
}

/* command and estimate under one authenticator (MSL_ELEV_CMD_AUTH); a step is released within
 * FCC_APP_MSL_RT_WINDOW_US of its sampling instant (its command must leave before the
 * actuation instant) */
const fcc_app_ops_t fcc_app_msl_ops = {
    "missile", fcc_bus_app_missile_inputs, FCC_BUS_APP_MISSILE_N_INPUTS, FCC_MSG_MSL_ELEV_CMD_AUTH,
    FCC_APP_MSL_RT_WINDOW_US,
    ops_config_default, ops_init, ops_reset, ops_sensor, ops_input, ops_offer, ops_step, ops_encode, ops_period_us,
    ops_request, ops_background, ops_wants_background,
};
