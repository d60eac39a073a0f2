/*
 * fcc_bench_flight.h -- the frames of the benchmark flights, as the simulator
 * would send them (E2E-protected by the real frame layer): one CDRW pull-up
 * with the paper's 0.1 s sensor spike at 4 s, and a missile fed by smooth
 * sensor signals.  Shared by the host bench (fcc_step_bench.c here,
 * callgrind) and the on-target bench (firmware/port/mps2_an386/m4f_bench.c,
 * QEMU).
 */
#ifndef FCC_BENCH_FLIGHT_H
#define FCC_BENCH_FLIGHT_H

#include <stdbool.h>
#include <stdint.h>

#include "fcc_bus.h"
#include "fcc_can.h"
#include "fcc_node.h"
#include "fcc_port.h"
#include "fcc_secoc.h"

#define FCC_BENCH_MAX_FRAMES 6u
#define FCC_BENCH_TRIP 0xBE4Cu

/* The node's key (the published test key) and trip. */
void fcc_bench_security(fcc_node_config_t *cfg);

/* The simulator's side of the bus: it sends what fcc consumes, and authenticates
 * its commands with the bench key and trip (fresh counters: call with each new node). */
fcc_status_t fcc_bench_sim_init(fcc_bus_t *sim, fcc_secoc_t *sec);

/* The port of a bench node: sent frames go to send, nothing is ever received,
 * the clock is now_us (no counters, no events). */
fcc_port_t fcc_bench_port(fcc_status_t (*send)(void *ctx, const fcc_can_frame_t *frame),
                          uint64_t (*now_us)(void *ctx));

/* A node just started with fcc_bench_security's key: the simulator's side made
 * fresh (fcc_bench_sim_init), then its authenticated SIM_CONTROL(FLIGHT) handed
 * to the node (steps run only in FLIGHT); FCC_ERR_RANGE when it refused FLIGHT. */
fcc_status_t fcc_bench_take_off(fcc_node_t *node, fcc_bus_t *sim, fcc_secoc_t *sec);

/* Step k of the CDRW: alpha, q, delta_e, (with oracle_fault: a SIM_EVENT
 * saying a fault is active), then SIM_TICK(0, k) and its authenticator.  *n frames in f. */
fcc_status_t fcc_bench_cdrw_frames(fcc_bus_t *sim, fcc_secoc_t *sec, uint32_t k, bool oracle_fault,
                                   fcc_can_frame_t f[FCC_BENCH_MAX_FRAMES], uint32_t *n);

/* Step k of the missile: gyro, accelerometer, SIM_TICK(1, k) and its authenticator. */
fcc_status_t fcc_bench_missile_frames(fcc_bus_t *sim, fcc_secoc_t *sec, uint32_t k,
                                      fcc_can_frame_t f[FCC_BENCH_MAX_FRAMES], uint32_t *n);

#endif /* FCC_BENCH_FLIGHT_H */
