/*
 * m4f_bench.c -- what one step costs on the Cortex-M4F: the on-target half
 * of scripts/bench pil.  Runs under QEMU mps2-an386 with -icount shift=0, where
 * every executed instruction advances virtual time by exactly 1 ns, so the
 * SysTick (25 MHz, 40 ns) counts instructions in units of 40.  Prints
 * "pil ..." lines on the log UART and exits QEMU.
 *
 * Measured, each with the real node (frames in -> step -> frames out, the
 * sent frames encoded as SLCAN lines as the image sends them):
 *   calib         a loop of known length (checks the 40 instructions per tick)
 *   cdrw normal   steps 20..349 of the bench flight, detector off (AZKF at q = 2)
 *   cdrw fault    the same flight with the oracle fault held from step 20
 *                 (AZKF at q = 1000 like the ZKF), steps 40..349
 *   missile       3000 steps at the default T = 0.05 s
 *   design T      one run-time LQG re-design (double on the single-precision
 *                 FPU: software double), per slice and in total, T = 0.02..0.3
 *   boot          fcc_node_init (both applications, the first design)
 */
#include <stdbool.h>
#include <stdint.h>

#include "fcc_bench_flight.h"
#include "fcc_node.h"
#include "fcc_slcan.h"
#include "mps2_board.h"

#define TICK_INSNS 40u /* 1 ns per instruction (-icount shift=0) / 25 MHz SysTick */

static fcc_node_t g_node;
static fcc_bus_t g_sim;
static fcc_secoc_t g_sec; /* the simulator's authenticators */
static uint32_t g_sent;

static fcc_status_t port_send(void *ctx, const fcc_can_frame_t *frame)
{
    (void)ctx;
    char line[FCC_SLCAN_FRAME_CHARS];
    size_t n = 0u;
    const fcc_status_t st = fcc_slcan_encode(frame, false, line, sizeof line, &n);
    g_sent += (st == FCC_OK) ? 1u : 0u;
    return st;
}

static uint64_t port_now(void *ctx)
{
    (void)ctx;
    return mps2_now_us();
}

typedef struct {
    uint32_t n;
    uint64_t sum;
    uint64_t max;
    uint32_t max_k; /* the step of the maximum */
} stat_t;

static void stat_add(stat_t *s, uint32_t k, uint64_t insns)
{
    ++s->n;
    s->sum += insns;
    if (insns > s->max) {
        s->max = insns;
        s->max_k = k;
    }
}

static void put_kv(const char *key, uint64_t v)
{
    mps2_log(" ");
    mps2_log(key);
    mps2_log("=");
    mps2_log_u64(v);
}

static void put_stat(const char *what, const stat_t *s)
{
    mps2_log("pil ");
    mps2_log(what);
    put_kv("steps", s->n);
    put_kv("mean_insns", (s->n != 0u) ? s->sum / s->n : 0u);
    put_kv("max_insns", s->max);
    put_kv("max_at_step", s->max_k);
    mps2_log("\n");
}

static void fail(const char *what)
{
    mps2_log("pil error: ");
    mps2_log(what);
    mps2_log("\n");
    mps2_exit(1);
}

static void start_node(fcc_fdet_mode_t detector)
{
    fcc_node_config_t cfg;
    const fcc_port_t port = fcc_bench_port(port_send, port_now);
    if (fcc_node_config_default(&cfg) != FCC_OK) {
        fail("default configuration");
    }
    cfg.sid.base.azkf.det.mode = detector;
    fcc_bench_security(&cfg);
    const uint64_t t0 = mps2_ticks();
    if (fcc_node_init(&g_node, &cfg, &port) != FCC_OK) {
        fail("node start-up");
    }
    if (fcc_bench_take_off(&g_node, &g_sim, &g_sec) != FCC_OK) { /* fresh simulator, FLIGHT */
        fail("simulator bus");
    }
    static bool reported;
    if (!reported) {
        reported = true;
        mps2_log("pil boot");
        put_kv("insns", (mps2_ticks() - t0) * TICK_INSNS);
        mps2_log("\n");
    }
}

/* Frames of one step through the node; instructions. */
static uint64_t measured_step(const fcc_can_frame_t *f, uint32_t n)
{
    const uint64_t t0 = mps2_ticks();
    for (uint32_t i = 0u; i < n; ++i) {
        fcc_node_handle_frame(&g_node, &f[i]);
    }
    return (mps2_ticks() - t0) * TICK_INSNS;
}

static void bench_cdrw(bool fault_held, uint32_t first, uint32_t last, const char *what)
{
    /* normal: the detector off keeps the AZKF at q = 2; fault: the oracle holds q = 1000 */
    start_node(fault_held ? FCC_FDET_ORACLE : FCC_FDET_OFF);
    stat_t s = {0u, 0u, 0u, 0u};
    uint32_t order = 0u;
    for (uint32_t k = 0u; k <= last; ++k) {
        fcc_can_frame_t f[FCC_BENCH_MAX_FRAMES];
        uint32_t n = 0u;
        if (fcc_bench_cdrw_frames(&g_sim, &g_sec, k, fault_held && k >= 20u, f, &n) != FCC_OK) {
            fail("cdrw frames");
        }
        const uint64_t insns = measured_step(f, n);
        if (k >= first) {
            stat_add(&s, k, insns);
        }
        const fcc_sid_out_t *azkf = &g_node.sid.last.out[FCC_SID_AZKF];
        order = (azkf->order > order) ? azkf->order : order;
    }
    put_stat(what, &s);
    mps2_log("pil ");
    mps2_log(what);
    put_kv("azkf_max_order", order);
    put_kv("degraded", g_node.app[FCC_APP_CDRW].degraded_steps);
    mps2_log("\n");
}

static void bench_missile(uint32_t steps)
{
    start_node(FCC_FDET_ZONOTOPE);
    stat_t s = {0u, 0u, 0u, 0u};
    for (uint32_t k = 0u; k < steps; ++k) {
        fcc_can_frame_t f[FCC_BENCH_MAX_FRAMES];
        uint32_t n = 0u;
        if (fcc_bench_missile_frames(&g_sim, &g_sec, k, f, &n) != FCC_OK) {
            fail("missile frames");
        }
        stat_add(&s, k, measured_step(f, n));
    }
    put_stat("missile", &s);
}

/* One re-design at period t (ms), slice by slice, into the node's spare slot. */
static void bench_design(uint32_t t_ms)
{
    fcc_app_msl_t *app = &g_node.msl;
    const double t = (double)t_ms / 1000.0;
    uint64_t t0 = mps2_ticks();
    if (fcc_lqg_design_begin(&app->cfg.plant, t, app->cfg.solver, &app->ws) != FCC_OK) {
        fail("design begin");
    }
    uint64_t total = (mps2_ticks() - t0) * TICK_INSNS;
    uint64_t worst = total;
    mps2_log("pil design");
    put_kv("t_ms", t_ms);
    fcc_status_t st = FCC_ERR_AGAIN;
    for (uint32_t i = 0u; i < FCC_LQG_DESIGN_SLICES && st == FCC_ERR_AGAIN; ++i) {
        t0 = mps2_ticks();
        st = fcc_lqg_design_slice(&app->ws, &app->slot[1u - app->active].design);
        const uint64_t insns = (mps2_ticks() - t0) * TICK_INSNS;
        total += insns;
        worst = (insns > worst) ? insns : worst;
        mps2_log(" slice");
        mps2_log_u64(i);
        mps2_log("=");
        mps2_log_u64(insns);
    }
    if (st != FCC_OK) {
        fail("design");
    }
    put_kv("total_insns", total);
    put_kv("max_slice_insns", worst);
    mps2_log("\n");
}

static void calibrate(void)
{
    uint32_t n = 1000000u;
    const uint64_t t0 = mps2_ticks();
    __asm__ volatile("1: subs %0, %0, #1\n\tbne 1b" : "+r"(n)::"cc");
    mps2_log("pil calib");
    put_kv("loop_insns", 2000000u);
    put_kv("measured_insns", (mps2_ticks() - t0) * TICK_INSNS);
    mps2_log("\n");
}

int main(void)
{
    mps2_board_init();
    calibrate();
    bench_cdrw(false, 20u, 349u, "cdrw_normal");
    bench_cdrw(true, 40u, 349u, "cdrw_fault");
    bench_missile(3000u);
    static const uint32_t periods_ms[] = {20u, 50u, 100u, 200u, 300u};
    for (uint32_t i = 0u; i < sizeof periods_ms / sizeof periods_ms[0]; ++i) {
        bench_design(periods_ms[i]);
    }
    mps2_log("pil memory");
    put_kv("node_bytes", sizeof(fcc_node_t));
    put_kv("stack_used", mps2_stack_used());
    mps2_log("\npil done\n");
    mps2_exit(0);
}
