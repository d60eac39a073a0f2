/*
 * fcc_bench_flight.c -- the benchmark flights' frames; see fcc_bench_flight.h.
 */
#include "fcc_bench_flight.h"

#include <math.h>
#include <string.h>

#include "fcc_node.h"
#include "fcc_types.h" /* FCC_TRY */

static const uint8_t k_bench_key[FCC_SECOC_KEY_BYTES] = {0, 1, 2,  3,  4,  5,  6,  7,
                                                          8, 9, 10, 11, 12, 13, 14, 15};

void fcc_bench_security(fcc_node_config_t *cfg)
{
    memcpy(cfg->security.key, k_bench_key, sizeof k_bench_key);
    cfg->security.trip = FCC_BENCH_TRIP;
}

/* The authenticator of the secured frame *pdu, into *out. */
static fcc_status_t authenticate(fcc_secoc_t *sec, const fcc_can_frame_t *pdu, fcc_can_frame_t *out)
{
    fcc_msg_t msg;
    uint32_t a;
    FCC_TRY(fcc_bus_find(pdu->id, &msg));
    if (!fcc_secoc_secured_index(msg, &a)) {
        return FCC_ERR_ARG;
    }
    return fcc_secoc_protect(sec, a, pdu->data, 8u, out);
}

static fcc_status_t no_frame(void *ctx, fcc_can_frame_t *frame)
{
    (void)ctx;
    (void)frame;
    return FCC_ERR_AGAIN;
}

fcc_port_t fcc_bench_port(fcc_status_t (*send)(void *ctx, const fcc_can_frame_t *frame),
                          uint64_t (*now_us)(void *ctx))
{
    const fcc_port_t port = {.can = {.send = send, .recv = no_frame}, .now_us = now_us};
    return port;
}

fcc_status_t fcc_bench_take_off(fcc_node_t *node, fcc_bus_t *sim, fcc_secoc_t *sec)
{
    FCC_TRY(fcc_bench_sim_init(sim, sec));
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    d.sim_control.command = FCC_MSG_SIM_CONTROL_COMMAND_FLIGHT;
    fcc_can_frame_t f[2];
    FCC_TRY(fcc_bus_encode(sim, FCC_MSG_SIM_CONTROL, &d, &f[0]));
    FCC_TRY(authenticate(sec, &f[0], &f[1]));
    fcc_node_handle_frame(node, &f[0]);
    fcc_node_handle_frame(node, &f[1]);
    return (fcc_node_op_mode(node) == FCC_OP_FLIGHT) ? FCC_OK : FCC_ERR_RANGE;
}

fcc_status_t fcc_bench_sim_init(fcc_bus_t *sim, fcc_secoc_t *sec)
{
    FCC_TRY(fcc_secoc_init(sec, k_bench_key, FCC_BENCH_TRIP));
    uint64_t produces = 0u;
    uint64_t consumes = 0u;
    for (unsigned int i = 0u; i < (unsigned int)FCC_MSG_COUNT; ++i) {
        if ((fcc_bus_desc((fcc_msg_t)i)->senders & (1u << FCC_BUS_NODE_FCC)) != 0u) {
            consumes |= (uint64_t)1u << i;
        } else {
            produces |= (uint64_t)1u << i;
        }
    }
    return fcc_bus_init_masks(sim, consumes, produces);
}

fcc_status_t fcc_bench_cdrw_frames(fcc_bus_t *sim, fcc_secoc_t *sec, uint32_t k, bool oracle_fault,
                                   fcc_can_frame_t f[FCC_BENCH_MAX_FRAMES], uint32_t *n)
{
    const double t = 0.02 * (double)k;
    const double de = -0.05 - 0.08 * sin(1.3 * t);
    double alpha = 0.16 + 0.1 * sin(0.9 * t) + 0.002 * sin(17.0 * t);
    const double q = 0.09 * cos(0.9 * t) + 0.01 * sin(11.0 * t);
    if (t >= 4.0 && t < 4.1) {
        alpha += 0.15; /* the sensor spike */
    }
    uint32_t i = 0u;
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    d.cdrw_aoa.step = (uint16_t)k;
    d.cdrw_aoa.alpha = (fcc_real_t)alpha;
    FCC_TRY(fcc_bus_encode(sim, FCC_MSG_CDRW_AOA, &d, &f[i++]));
    memset(&d, 0, sizeof d);
    d.cdrw_pitch_rate.step = (uint16_t)k;
    d.cdrw_pitch_rate.q = (fcc_real_t)q;
    FCC_TRY(fcc_bus_encode(sim, FCC_MSG_CDRW_PITCH_RATE, &d, &f[i++]));
    memset(&d, 0, sizeof d);
    d.cdrw_elevator.step = (uint16_t)k;
    d.cdrw_elevator.delta_e = (fcc_real_t)de;
    FCC_TRY(fcc_bus_encode(sim, FCC_MSG_CDRW_ELEVATOR, &d, &f[i++]));
    if (oracle_fault) {
        memset(&d, 0, sizeof d);
        d.sim_event.active = true;
        d.sim_event.oracle_fault = true;
        d.sim_event.target_id = 0x050u;
        d.sim_event.step = (uint16_t)k;
        FCC_TRY(fcc_bus_encode(sim, FCC_MSG_SIM_EVENT, &d, &f[i++]));
    }
    memset(&d, 0, sizeof d);
    d.sim_tick.app = FCC_APP_CDRW;
    d.sim_tick.step = k;
    FCC_TRY(fcc_bus_encode(sim, FCC_MSG_SIM_TICK, &d, &f[i]));
    FCC_TRY(authenticate(sec, &f[i], &f[i + 1u]));
    *n = i + 2u;
    return FCC_OK;
}

fcc_status_t fcc_bench_missile_frames(fcc_bus_t *sim, fcc_secoc_t *sec, uint32_t k,
                                      fcc_can_frame_t f[FCC_BENCH_MAX_FRAMES], uint32_t *n)
{
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    d.msl_rate_gyro.step = (uint16_t)k;
    d.msl_rate_gyro.q_g = (fcc_real_t)(0.1 * cos(0.7 * (double)k) + 0.3 * sin(2.1 * (double)k));
    FCC_TRY(fcc_bus_encode(sim, FCC_MSG_MSL_RATE_GYRO, &d, &f[0]));
    memset(&d, 0, sizeof d);
    d.msl_accelerometer.step = (uint16_t)k;
    d.msl_accelerometer.n_a = (fcc_real_t)(-3.0 + 40.0 * sin(0.45 * (double)k));
    FCC_TRY(fcc_bus_encode(sim, FCC_MSG_MSL_ACCELEROMETER, &d, &f[1]));
    memset(&d, 0, sizeof d);
    d.sim_tick.app = FCC_APP_MSL;
    d.sim_tick.step = k;
    FCC_TRY(fcc_bus_encode(sim, FCC_MSG_SIM_TICK, &d, &f[2]));
    FCC_TRY(authenticate(sec, &f[2], &f[3]));
    *n = 4u;
    return FCC_OK;
}
