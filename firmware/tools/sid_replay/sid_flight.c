#include "sid_flight.h"

#include <math.h>

#define DT 0.02
#define PERIOD 7.0

static double smooth_bump(double t, double t0, double t1, double ramp)
{
    double up = (t - t0) / ramp;
    double down = (t1 - t) / ramp;
    double s = up < down ? up : down;
    s = s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s);
    return s * s * (3.0 - 2.0 * s);
}

static double uniform(unsigned *state, double lim)
{
    /* xorshift32: deterministic, portable. */
    unsigned x = *state;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    *state = x;
    return lim * (2.0 * ((double)x / 4294967296.0) - 1.0);
}

void sid_flight_generate(sid_sample_t *s, size_t n, double fault_time, unsigned seed)
{
    unsigned rng = seed != 0u ? seed : 1u;
    const double pi = 3.14159265358979323846;
    double x0 = 0.157;
    double x1 = 0.21;
    for (size_t k = 0; k < n; ++k) {
        const double t = (double)k * DT;
        const double tp = fmod(t, PERIOD);
        const double sb = smooth_bump(tp, 2.4, 5.2, 0.8);
        const double za = -1.5 + 0.3 * sb;
        const double ma = -20.0 + 8.0 * sb;
        const double mq = -3.0 + 1.2 * sb;
        const double de = -0.126 * (1.0 + 0.6 * smooth_bump(tp, 1.5, 3.7, 0.9)) +
                          0.012 * (sin(2.0 * pi * 0.7 * t) + 0.8 * sin(2.0 * pi * 1.9 * t + 1.0) +
                                   0.6 * sin(2.0 * pi * 3.3 * t + 2.0));
        const bool fault = fault_time >= 0.0 && t >= fault_time - 1e-9 && t < fault_time + 0.1 - 1e-9;
        s[k].x[0] = x0;
        s[k].x[1] = x1;
        s[k].de = de;
        s[k].fault = fault;
        s[k].y[0] = x0 + uniform(&rng, 0.01) + (fault ? 0.15 : 0.0);
        s[k].y[1] = x1 + uniform(&rng, 0.015) + (fault ? 0.6 : 0.0);
        const double n0 = x0 + DT * (za * x0 + x1 - 0.2 * de) + uniform(&rng, 0.0005);
        const double n1 = x1 + DT * (ma * x0 + mq * x1 - 30.0 * de) + uniform(&rng, 0.002);
        x0 = n0;
        x1 = n1;
    }
}
