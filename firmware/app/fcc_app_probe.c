/*
 * fcc_app_probe.c -- the test build's third application (see fcc_app_probe.h).
 */
#include "fcc_app_probe.h"

#include <stddef.h>

static fcc_status_t probe_init(void *app, const void *cfg)
{
    (void)cfg;
    fcc_app_probe_t *p = app;
    if (p == NULL) {
        return FCC_ERR_ARG;
    }
    p->steps = 0u;
    p->last_k = 0u;
    return FCC_OK;
}

static fcc_status_t probe_reset(void *app)
{
    return probe_init(app, NULL);
}

static fcc_sensor_t *probe_sensor(void *app, fcc_msg_t msg)
{
    (void)app;
    (void)msg;
    return NULL; /* no inputs */
}

static const fcc_sensor_t *probe_input(const void *app, uint32_t slot)
{
    (void)app;
    (void)slot;
    return NULL; /* no inputs */
}

static fcc_status_t probe_offer(void *app, fcc_msg_t msg, const fcc_msg_data_t *data,
                                uint64_t t_us)
{
    (void)app;
    (void)msg;
    (void)data;
    (void)t_us;
    return FCC_ERR_ARG; /* no inputs: nothing is offered to it */
}

static fcc_status_t probe_step(void *app, const fcc_app_tick_t *tick, fcc_app_step_t *out)
{
    fcc_app_probe_t *p = app;
    if (p == NULL || tick == NULL || out == NULL) {
        return FCC_ERR_ARG;
    }
    ++p->steps;
    p->last_k = tick->k;
    out->degraded = (tick->k & 1u) != 0u;
    out->reconfigured = false;
    return FCC_OK;
}

static fcc_status_t probe_encode(const void *app, fcc_bus_t *bus, fcc_can_frame_t *frames,
                                 uint32_t *n)
{
    (void)app;
    (void)bus;
    (void)frames;
    if (n == NULL) {
        return FCC_ERR_ARG;
    }
    *n = 0u; /* no output frames: its FCC_ACK is its answer */
    return FCC_OK;
}

static uint32_t probe_period_us(const void *app)
{
    (void)app;
    return FCC_APP_PROBE_PERIOD_US;
}

const fcc_app_ops_t fcc_app_probe_ops = {
    "probe", NULL, 0u, FCC_MSG_COUNT, 0u,
    NULL, probe_init, probe_reset, probe_sensor, probe_input, probe_offer, probe_step, probe_encode, probe_period_us,
    NULL, NULL, NULL,
};
