/*
 * fuzz_node_seed.c -- writes fuzz_node_rx's first corpus entry: a lockstep flight as the
 * simulator flies it (a genuine SIM_CONTROL FLIGHT, then steps of sensor frames and
 * authenticated ticks of both applications), in fuzz_node_rx's record format.  A fuzzer
 * does not find an E2E-valid, in-range, authenticated command by itself in a bounded run;
 * from this entry it mutates a flight, and the dispatch reaches the steps.
 *
 *     fuzz_node_seed FILE
 */
#include <stdio.h>
#include <string.h>

#include "fcc_bus.h"
#include "fuzz_bus_records.h"

#define FUZZ_NODE_AUTH 0x10u
#define FUZZ_NODE_HOUSEKEEPING 0x08u
#define STEPS 12u

static fcc_bus_t g_sim;

/* One record: msg encoded by the simulator's frame layer (E2E included), authenticated by
 * fuzz_node_rx when secured; false when the encoder refused it. */
static int put(FILE *out, fcc_msg_t msg, const fcc_msg_data_t *d)
{
    fcc_can_frame_t f;
    if (fcc_bus_encode(&g_sim, msg, d, &f) != FCC_OK) {
        return -1;
    }
    uint8_t r[FUZZ_RX_REC] = {0};
    r[0] = FUZZ_RX_FROM_TABLE | FUZZ_NODE_AUTH | FUZZ_NODE_HOUSEKEEPING;
    r[1] = (uint8_t)msg;
    r[2] = f.dlc;
    memcpy(&r[3], f.data, 8u);
    r[11] = 1u; /* 100 us later */
    return (fwrite(r, 1u, sizeof r, out) == sizeof r) ? 0 : -1;
}

static int step(FILE *out, uint32_t k)
{
    fcc_msg_data_t d[7];
    memset(d, 0, sizeof d);
    d[0].cdrw_aoa.step = (uint16_t)k;
    d[0].cdrw_aoa.alpha = FCC_R(0.1);
    d[1].cdrw_pitch_rate.step = (uint16_t)k;
    d[1].cdrw_pitch_rate.q = FCC_R(0.01);
    d[2].cdrw_elevator.step = (uint16_t)k;
    d[2].cdrw_elevator.delta_e = FCC_R(-0.05);
    d[3].msl_rate_gyro.step = (uint16_t)k;
    d[3].msl_rate_gyro.q_g = FCC_R(0.1);
    d[4].msl_accelerometer.step = (uint16_t)k;
    d[4].msl_accelerometer.n_a = FCC_R(-3.0);
    d[5].sim_tick.app = 0u;
    d[5].sim_tick.step = k;
    d[6].sim_tick.app = 1u;
    d[6].sim_tick.step = k;
    static const fcc_msg_t k_msgs[7] = {FCC_MSG_CDRW_AOA, FCC_MSG_CDRW_PITCH_RATE,
                                        FCC_MSG_CDRW_ELEVATOR, FCC_MSG_MSL_RATE_GYRO,
                                        FCC_MSG_MSL_ACCELEROMETER, FCC_MSG_SIM_TICK,
                                        FCC_MSG_SIM_TICK};
    for (unsigned int i = 0u; i < 7u; ++i) {
        if (put(out, k_msgs[i], &d[i]) != 0) {
            return -1;
        }
    }
    return 0;
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: fuzz_node_seed FILE\n");
        return 2;
    }
    uint64_t produces = 0u;
    uint64_t consumes = 0u;
    for (unsigned int i = 0u; i < (unsigned int)FCC_MSG_COUNT; ++i) {
        const bool fcc_sends = (fcc_bus_desc((fcc_msg_t)i)->senders & (1u << FCC_BUS_NODE_FCC)) != 0u;
        consumes |= fcc_sends ? (uint64_t)1u << i : 0u;
        produces |= fcc_sends ? 0u : (uint64_t)1u << i;
    }
    FILE *out = fopen(argv[1], "wb");
    if (out == NULL || fcc_bus_init_masks(&g_sim, consumes, produces) != FCC_OK) {
        fprintf(stderr, "fuzz_node_seed: cannot write %s\n", argv[1]);
        return 1;
    }
    int rc = (fputc(0, out) == EOF) ? -1 : 0; /* lockstep */
    fcc_msg_data_t control;
    memset(&control, 0, sizeof control);
    control.sim_control.command = FCC_MSG_SIM_CONTROL_COMMAND_FLIGHT;
    rc = (rc == 0) ? put(out, FCC_MSG_SIM_CONTROL, &control) : rc;
    for (uint32_t k = 1u; k <= STEPS && rc == 0; ++k) {
        rc = step(out, k);
    }
    if (fclose(out) != 0 || rc != 0) {
        fprintf(stderr, "fuzz_node_seed: cannot write %s\n", argv[1]);
        return 1;
    }
    return 0;
}
