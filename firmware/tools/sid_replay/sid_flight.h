/*
 * sid_flight.h -- a synthetic flight for the benchmark (host only): the same
 * linear, slowly time-varying short-period model as hil.reference.flight
 * (pull-up every 7 s, multisine elevator, bounded uniform noise), generated
 * in C so that the benchmark needs no input file.
 */
#ifndef SID_FLIGHT_H
#define SID_FLIGHT_H

#include <stdbool.h>
#include <stddef.h>

typedef struct {
    double y[2];  /* measurement (rad, rad/s) */
    double x[2];  /* true state */
    double de;    /* elevator (rad) */
    bool fault;   /* a spike is injected in y */
} sid_sample_t;

/* Fills n samples; a 0.1 s spike (0.15 rad, 0.6 rad/s) starts at fault_time
 * (s) when fault_time >= 0. */
void sid_flight_generate(sid_sample_t *s, size_t n, double fault_time, unsigned seed);

#endif /* SID_FLIGHT_H */
