/*
 * fcc_step_bench -- the cost of one application step of the flight computer,
 * frames in to frames out, for scripts/bench.d/fcc.
 *
 *   fcc_step_bench cdrw|missile STEPS
 *
 * The node is the real one (firmware/app); its port is memory: the frames of
 * every step (sensor frames + SIM_TICK, E2E-protected by the real frame
 * layer) are built before the measurement, and sent frames are only counted.
 * fcc_bench_measured_step() hands one step's frames to the node -- decode,
 * E2E, range checks, the step itself, encode, E2E, send -- and is the only
 * function run under callgrind's --toggle-collect, so the instruction count
 * divided by STEPS is the cost of one step as the firmware would pay it.
 * The CDRW flight is a pull-up with a 0.1 s sensor spike at 4 s (the paper's
 * fault), so the AZKF switches to its large order for a while.
 * Also prints the wall time per step (informative; callgrind is the measure).
 */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "fcc_bench_flight.h"
#include "fcc_node.h"

#define MAX_STEPS 20000u

static fcc_node_t g_node;
static fcc_bus_t g_sim;
static fcc_secoc_t g_sec; /* the simulator's authenticators */
static fcc_can_frame_t g_frames[MAX_STEPS][FCC_BENCH_MAX_FRAMES];
static uint32_t g_nframes[MAX_STEPS];
static uint32_t g_sent;

static fcc_status_t mem_send(void *ctx, const fcc_can_frame_t *f)
{
    (void)ctx;
    (void)f;
    ++g_sent;
    return FCC_OK;
}

static uint64_t mono_us(void *ctx)
{
    (void)ctx;
    struct timespec ts;
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000u + (uint64_t)ts.tv_nsec / 1000u;
}

/* The measured region: one step's frames through the node (noinline so that
 * callgrind can toggle on it). */
void fcc_bench_measured_step(fcc_node_t *node, const fcc_can_frame_t *frames, uint32_t n)
    __attribute__((noinline));
void fcc_bench_measured_step(fcc_node_t *node, const fcc_can_frame_t *frames, uint32_t n)
{
    for (uint32_t i = 0u; i < n; ++i) {
        fcc_node_handle_frame(node, &frames[i]);
    }
}

/* The measured region of `fcc_step_bench mac N`: one authenticator computed. */
void fcc_bench_measured_mac(fcc_secoc_t *sec, const fcc_can_frame_t *pdu, fcc_can_frame_t *out)
    __attribute__((noinline));
void fcc_bench_measured_mac(fcc_secoc_t *sec, const fcc_can_frame_t *pdu, fcc_can_frame_t *out)
{
    uint32_t a = 0u;
    (void)fcc_secoc_secured_index(FCC_MSG_SIM_TICK, &a);
    (void)fcc_secoc_protect(sec, a, pdu->data, 8u, out);
}

int main(int argc, char **argv)
{
    const bool cdrw = argc == 3 && strcmp(argv[1], "cdrw") == 0;
    const bool missile = argc == 3 && strcmp(argv[1], "missile") == 0;
    const bool mac = argc == 3 && strcmp(argv[1], "mac") == 0;
    const long steps = (argc == 3) ? strtol(argv[2], NULL, 10) : 0;
    if ((!cdrw && !missile && !mac) || steps <= 0 || steps > (long)MAX_STEPS) {
        fprintf(stderr, "usage: fcc_step_bench cdrw|missile|mac STEPS (1..%u)\n", MAX_STEPS);
        return 2;
    }
    fcc_status_t st = fcc_bench_sim_init(&g_sim, &g_sec);
    if (mac && st == FCC_OK) { /* STEPS authenticators of a SIM_TICK frame */
        fcc_can_frame_t pdu, auth;
        memset(&pdu, 0, sizeof pdu);
        pdu.id = FCC_MSG_SIM_TICK_ID;
        pdu.dlc = 8u;
        for (long i = 0; i < steps; ++i) {
            pdu.data[2] = (uint8_t)i;
            fcc_bench_measured_mac(&g_sec, &pdu, &auth);
        }
        printf("app=mac frames=%ld\n", steps);
        return 0;
    }
    fcc_node_config_t cfg;
    const fcc_port_t port = fcc_bench_port(mem_send, mono_us);
    if (fcc_node_config_default(&cfg) != FCC_OK) {
        return 1;
    }
    fcc_bench_security(&cfg);
    if (st != FCC_OK || fcc_node_init(&g_node, &cfg, &port) != FCC_OK ||
        fcc_bench_take_off(&g_node, &g_sim, &g_sec) != FCC_OK) {
        fprintf(stderr, "fcc_step_bench: node start-up failed\n");
        return 1;
    }
    for (uint32_t k = 0u; k < (uint32_t)steps && st == FCC_OK; ++k) {
        st = cdrw ? fcc_bench_cdrw_frames(&g_sim, &g_sec, k, false, g_frames[k], &g_nframes[k])
                  : fcc_bench_missile_frames(&g_sim, &g_sec, k, g_frames[k], &g_nframes[k]);
    }
    if (st != FCC_OK) {
        fprintf(stderr, "fcc_step_bench: cannot encode the flight's frames: %s\n", fcc_status_str(st));
        return 1;
    }
    const uint64_t t0 = mono_us(NULL);
    for (uint32_t k = 0u; k < (uint32_t)steps; ++k) {
        fcc_bench_measured_step(&g_node, g_frames[k], g_nframes[k]);
    }
    const uint64_t t1 = mono_us(NULL);
    const uint32_t app = cdrw ? FCC_APP_CDRW : FCC_APP_MSL;
    if (g_node.app[app].steps != (uint32_t)steps) {
        fprintf(stderr, "fcc_step_bench: %lu steps run, %ld expected\n",
                (unsigned long)g_node.app[app].steps, steps);
        return 1;
    }
    printf("app=%s steps=%ld frames_sent=%lu degraded=%lu wall_us_per_step=%.2f "
           "node_bytes=%lu\n", argv[1], steps, (unsigned long)g_sent,
           (unsigned long)g_node.app[app].degraded_steps, (double)(t1 - t0) / (double)steps,
           (unsigned long)sizeof(fcc_node_t));
    return 0;
}
