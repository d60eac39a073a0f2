/*
 * sid_bench -- cost of one identification step, for scripts/bench.d/sid.
 *
 *   sid_bench SCENARIO [MEASURED_STEPS]
 *
 * Runs a warm-up (not measured), then MEASURED_STEPS steps, each through
 * sid_bench_measured(); under valgrind --tool=callgrind
 * --toggle-collect=sid_bench_measured only those calls are counted.  The
 * scenario "baseline" measures the wrapper itself (subtracted by the
 * script).  Prints "SCENARIO STEPS NS_PER_STEP ORDER GENERATORS" (wall time
 * of the measured steps, and the order/generator count of the last one).
 */
#define _POSIX_C_SOURCE 199309L

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "fcc_sid.h"
#include "sid_flight.h"
#include "tool_args.h"

#define MAX_STEPS 20000u

typedef enum { SC_BASELINE, SC_MLS, SC_KF, SC_ZKF, SC_AZKF, SC_AZKF_SPIKE, SC_AZKF_WORST } scenario_t;

typedef struct {
    const char *name;
    scenario_t sc;
    size_t warmup;   /* steps before measuring */
} scenario_desc_t;

static const scenario_desc_t scenarios[] = {
    {"baseline", SC_BASELINE, 300u},
    {"mls", SC_MLS, 300u},
    {"mls-kf", SC_KF, 300u},
    {"mls-zkf", SC_ZKF, 300u},           /* order 1000: p saturated at 1004 after 250 steps */
    {"mls-azkf", SC_AZKF, 300u},         /* normal flight, q = 2 */
    {"mls-azkf-spike", SC_AZKF_SPIKE, 200u}, /* from the 0.1 s spike at 4 s on */
    {"mls-azkf-worst", SC_AZKF_WORST, 300u}, /* fault held: q = 1000, p = 1004 */
};

static sid_sample_t flight[MAX_STEPS];
static fcc_sid_t sid;
static fcc_mls_t mls;
static volatile fcc_real_t sink;

typedef struct {
    scenario_t sc;
    const sid_sample_t *s;
    const sid_sample_t *prev;
    fcc_sid_out_t out;
} bench_ctx_t;

static void do_step(bench_ctx_t *c)
{
    const sid_sample_t *s = c->s;
    switch (c->sc) {
    case SC_BASELINE:
        sink = (fcc_real_t)s->y[0];
        break;
    case SC_MLS: {
        const fcc_real_t xp[2] = {(fcc_real_t)c->prev->x[0], (fcc_real_t)c->prev->x[1]};
        const fcc_real_t x[2] = {(fcc_real_t)s->x[0], (fcc_real_t)s->x[1]};
        (void)fcc_mls_update(&mls, xp, (fcc_real_t)c->prev->de, x);
        break;
    }
    default:
        (void)fcc_sid_step(&sid, (fcc_real_t)s->y[0], (fcc_real_t)s->y[1], (fcc_real_t)s->de,
                           c->sc == SC_AZKF_WORST || s->fault, true, &c->out);
        break;
    }
}

/* The only function whose instructions callgrind counts. */
void sid_bench_measured(bench_ctx_t *c);
__attribute__((noinline)) void sid_bench_measured(bench_ctx_t *c)
{
    do_step(c);
}

static int setup(scenario_t sc)
{
    fcc_sid_filter_t f = FCC_SID_AZKF;
    if (sc == SC_KF) {
        f = FCC_SID_KF;
    } else if (sc == SC_ZKF) {
        f = FCC_SID_ZKF;
    }
    fcc_sid_config_t cfg;
    fcc_sid_config_default(&cfg, f);
    if (sc == SC_AZKF_WORST) {
        cfg.azkf.det.mode = FCC_FDET_ORACLE;
    }
    if (sc == SC_MLS || sc == SC_BASELINE) {
        return fcc_mls_init(&mls, &cfg.mls) == FCC_OK ? 0 : -1;
    }
    return fcc_sid_init(&sid, &cfg) == FCC_OK ? 0 : -1;
}

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

int main(int argc, char **argv)
{
    if (argc < 2 || argc > 3) {
        fprintf(stderr, "usage: sid_bench SCENARIO [MEASURED_STEPS]\n");
        return 2;
    }
    const scenario_desc_t *d = NULL;
    for (size_t i = 0; i < sizeof scenarios / sizeof scenarios[0]; ++i) {
        if (strcmp(argv[1], scenarios[i].name) == 0) {
            d = &scenarios[i];
        }
    }
    unsigned long steps = 1000u;
    const int bad_steps = (argc == 3) ? tool_args_ulong(argv[2], 1u, MAX_STEPS, &steps) : 0;
    if (d == NULL || bad_steps != 0 || (size_t)steps + d->warmup + 1u > MAX_STEPS) {
        fprintf(stderr, "sid_bench: unknown scenario or bad step count\n");
        return 2;
    }
    if (d->sc == SC_AZKF_SPIKE && steps > 50) {
        fprintf(stderr, "sid_bench: mls-azkf-spike measures at most 50 steps after the spike\n");
        return 2;
    }
    const size_t n = d->warmup + (size_t)steps + 1u;
    sid_flight_generate(flight, n, d->sc == SC_AZKF_SPIKE ? 4.0 : -1.0, 12345u);
    if (setup(d->sc) != 0) {
        fprintf(stderr, "sid_bench: configuration refused\n");
        return 1;
    }
    bench_ctx_t c;
    memset(&c, 0, sizeof c);
    c.sc = d->sc;
    for (size_t k = 1; k <= d->warmup; ++k) {
        c.prev = &flight[k - 1u];
        c.s = &flight[k];
        do_step(&c);
    }
    const double t0 = now_ns();
    for (size_t k = d->warmup + 1u; k < n; ++k) {
        c.prev = &flight[k - 1u];
        c.s = &flight[k];
        sid_bench_measured(&c);
    }
    const double t1 = now_ns();
    printf("%s %ld %.1f %u %u\n", d->name, steps, (t1 - t0) / (double)steps, (unsigned)c.out.order,
           (unsigned)c.out.n_generators);
    return 0;
}
