/*
 * fcc_bench_flight.c -- the benchmark flights' frames; see fcc_bench_flight.h.
 */
#include "fcc_bench_flight.h"

#include <math.h>
#include <string.h>

#include "fcc_mat.h" /* FCC_TRY */
#include "fcc_node.h"

fcc_status_t fcc_bench_sim_init(fcc_bus_t *sim)
{
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

fcc_status_t fcc_bench_cdrw_frames(fcc_bus_t *sim, uint32_t k, bool oracle_fault,
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
    FCC_TRY(fcc_bus_encode(sim, FCC_MSG_SIM_TICK, &d, &f[i++]));
    *n = i;
    return FCC_OK;
}

fcc_status_t fcc_bench_missile_frames(fcc_bus_t *sim, uint32_t k,
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
    *n = 3u;
    return FCC_OK;
}
