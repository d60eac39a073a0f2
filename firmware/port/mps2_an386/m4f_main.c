/*
 * m4f_main.c -- the flight computer as it runs on the Cortex-M4F board
 * (QEMU mps2-an386): the same fcc_node as the Linux `fcc`, its CAN port an
 * SLCAN device on UART0, its clock the dual timer, its configuration the boot
 * record, its log UART1.  README.md here is the interface.
 *
 *   boot:    defaults + boot record -> fcc_node_init (the LQG design runs here)
 *   closed:  answers SLCAN commands, sends nothing
 *   O:       the heartbeat ("listening"), then as the host fcc: lockstep steps
 *            on SIM_TICK, or realtime steps on absolute timer deadlines;
 *            heartbeats at the status rate; a pending LQG redesign in idle
 *            time, slice by slice, never across a deadline
 *   SIM_CONTROL shutdown: last heartbeat, summary on the log, QEMU exits 0
 */
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "fcc_bootcfg.h"
#include "fcc_bus_msgs.h"
#include "fcc_cfg_limits.h"
#include "fcc_hist.h"
#include "fcc_node.h"
#include "fcc_slcan.h"
#include "mps2_board.h"

/* Bytes decoded per recv call at most: the receive interrupt keeps adding. */
#define RECV_BYTE_BUDGET 512u
/* Frames handled per loop turn before deadlines are looked at again. */
#define POLL_BUDGET 64u
/* Below this much time to a deadline the loop spins instead of arming the
 * alarm and sleeping. */
#define SPIN_US 50u
#define EVENT_LINE_GAP_US 1000000u
/* A design slice that never finds room before a deadline runs after this. */
#define DESIGN_WAIT_MAX_US 100000u
/* Lines per block of the bus clock's sliding minimum (two blocks: ~4-10 s of
 * a realtime flight's lines). */
#define BUS_CLOCK_BLOCK 512u
/* How fast a following time sync's stamps are steered towards the line's fastest
 * delivery: a quarter of the time sync's rate bound (200 ppm), so the steering
 * never looks like a master running away. */
#define BUS_CLOCK_SLEW_PPM 50

/* The bus's time stamps (SLCAN Z2: each frame's time on the rig's bus, host
 * microseconds modulo 2^32, from slcan_bridge) on this board's clock, as a
 * host maps a USB-CAN adapter's stamps: the target offset = the smallest (line's
 * first byte - bus stamp) over the last one to two blocks of lines, i.e. the
 * line's fastest delivery; a frame's receive stamp = its bus stamp + the offset
 * in use.  A line that waited behind others or behind QEMU comes out stamped
 * with its bus time all the same.  Both clocks are the host's (realtime: no
 * -icount).  The offset in use steps to the target until the time sync takes
 * its first pair; from then on, while it has an estimate (fcc_tsync_has_time),
 * it is steered, never stepped (as a PTP or NTP servo slews a locked clock): it
 * moves towards the target at BUS_CLOCK_SLEW_PPM of the bus time passed, a
 * drift the time sync's rate estimate follows.  Stepping it showed each faster
 * line found after the lock as a residual step of the whole improvement
 * (measured: 254 us peak, p99 284 us at T = 0.05); stepping it until the lock
 * moved the pairs taken while LOCKING (the first lines after boot come 200-400
 * us slower than the fastest: the first LOCKED residual 175 us, the rate 170
 * ppm off, 3 s to decay; measured 2026-12-02). */
typedef struct {
    bool valid;
    uint64_t last_bus_us;   /* the last stamp, unwrapped */
    int64_t cur_min;        /* this block's smallest (first byte - bus) */
    int64_t prev_min;       /* the previous block's (INT64_MAX: none yet) */
    uint32_t in_block;
    int64_t offset_ns;      /* the offset in use (ns: a slew step is a fraction of a us) */
    int64_t ref_offset;     /* the offset (us) when the time sync last took a reference */
    uint32_t rebases;       /* time sync references dropped because the offset moved */
    uint32_t stamped;       /* frames stamped so */
    uint64_t delay_sum_us;  /* their delay beyond the fastest line */
    uint32_t delay_worst_us;
} bus_clock_t;

/* Frames received lately: each one's receive stamp (what the application keeps
 * with its samples) and when its line had arrived whole (ARRIVALS: a few
 * steps' lines, so the newest sample a step used is still here). */
#define ARRIVALS 16u
typedef struct {
    uint64_t rx_us;
    uint64_t arrived_us;
} arrival_t;

typedef struct {
    fcc_node_t node;
    fcc_node_config_t cfg;
    fcc_slcan_dev_t link;
    uint64_t status_period_us; /* 0: only when opened and at shutdown */
    uint64_t next_status_us;
    bool flying;               /* the channel was opened at least once */
    fcc_node_rt_t rt[FCC_N_APPS];
    uint32_t slice_worst_us;   /* longest LQG design slice so far (realtime scheduling) */
    uint64_t slice_wait_since_us; /* a slice has been waiting for room since (0: not) */
    uint32_t slices_forced;    /* slices run without room (DESIGN_WAIT_MAX_US) */
    uint64_t event_last_us[FCC_EV_COUNT];
    uint32_t event_suppressed[FCC_EV_COUNT];
    uint32_t parse_wait_worst_us; /* frames: their line's arrival to their parse */
    uint64_t parse_wait_sum_us;
    bus_clock_t bus_clock;
    uint64_t cmd_sent_us;      /* the last missile command handed to the line */
    uint32_t cmd_sends;        /* missile commands handed to the line */
    uint32_t cmd_sends_seen;   /* ... of which measured */
    fcc_hist_t latency;        /* missile: newest sensor frame used arrived -> command sent */
    arrival_t arrivals[ARRIVALS];
    uint32_t n_arrivals;
} image_t;

static image_t g_img;

/* ---- the port ------------------------------------------------------------------------ */

static fcc_status_t port_send(void *ctx, const fcc_can_frame_t *frame)
{
    image_t *img = ctx;
    const fcc_status_t st = fcc_slcan_dev_send(&img->link, frame);
    if (st == FCC_OK && frame->id == FCC_MSG_MSL_ELEV_CMD_ID) {
        img->cmd_sent_us = mps2_now_us(); /* in the UART's ring: on its way, as the host's "handed" */
        ++img->cmd_sends;
    }
    return st;
}

static void note_arrival(image_t *img, uint64_t rx_us, uint64_t arrived_us)
{
    arrival_t *a = &img->arrivals[img->n_arrivals % ARRIVALS];
    a->rx_us = rx_us;
    a->arrived_us = arrived_us;
    ++img->n_arrivals;
}

/* When the frame with this receive stamp had arrived whole (0: not among the last ARRIVALS). */
static uint64_t arrival_of(const image_t *img, uint64_t rx_us)
{
    uint64_t at = 0u;
    for (uint32_t i = 0u; i < ARRIVALS; ++i) {
        if (img->arrivals[i].rx_us == rx_us) {
            at = img->arrivals[i].arrived_us;
        }
    }
    return at;
}

/* After a missile command went out: sensor to command on this clock, as the host fcc's
 * latency_us -- from the newest sensor frame the step used, when its line had arrived whole
 * (as the host's kernel stamp, a CAN controller's: the node's own time; the line's transfer
 * behind its bus stamp is the link's, rx_timing's bus_delay_us and line_us). */
static void measure_command(image_t *img)
{
    if (img->cmd_sends == img->cmd_sends_seen) {
        return;
    }
    img->cmd_sends_seen = img->cmd_sends;
    const uint64_t arrived = arrival_of(img, img->node.msl.last.newest_rx_us);
    if (arrived != 0u && img->cmd_sent_us >= arrived) {
        fcc_hist_add(&img->latency, img->cmd_sent_us - arrived);
    }
}

/* The offset in use moved towards target: stepped there (steer false), or by at most
 * BUS_CLOCK_SLEW_PPM of elapsed_us (steer true). */
static void steer_offset(bus_clock_t *c, int64_t target, uint64_t elapsed_us, bool steer)
{
    const int64_t want_ns = target * 1000;
    if (!steer) {
        c->offset_ns = want_ns;
        return;
    }
    const uint64_t max_ns = (elapsed_us < (UINT64_MAX / 1000u)) ? elapsed_us * (uint64_t)BUS_CLOCK_SLEW_PPM / 1000u
                                                              : UINT64_MAX;
    const int64_t room = (max_ns > (uint64_t)INT64_MAX) ? INT64_MAX : (int64_t)max_ns;
    const int64_t gap = want_ns - c->offset_ns;
    if (gap > room) {
        c->offset_ns += room;
    } else if (gap < -room) {
        c->offset_ns -= room;
    } else {
        c->offset_ns = want_ns;
    }
}

/* The offset in use, in whole microseconds (a stamp's and the reference's unit). */
static int64_t offset_us(const bus_clock_t *c)
{
    return c->offset_ns / 1000;
}

/* A Z2 bus stamp on this board's clock (bus_clock_t); steer: the time sync has an estimate. */
static uint64_t bus_to_local(bus_clock_t *c, uint32_t bus_us, uint64_t line_rx_us, bool steer)
{
    const uint64_t bus = c->valid ? c->last_bus_us + (uint64_t)(int64_t)(int32_t)(bus_us - (uint32_t)c->last_bus_us)
                                  : (uint64_t)bus_us;
    const int64_t d = (int64_t)line_rx_us - (int64_t)bus;
    const uint64_t elapsed = (c->valid && bus > c->last_bus_us) ? bus - c->last_bus_us : 0u;
    if (!c->valid) {
        c->prev_min = INT64_MAX;
        c->cur_min = d;
        c->valid = true;
    }
    c->last_bus_us = bus;
    c->cur_min = (d < c->cur_min) ? d : c->cur_min;
    const int64_t target = (c->prev_min < c->cur_min) ? c->prev_min : c->cur_min;
    steer_offset(c, target, elapsed, steer && (c->stamped != 0u));
    const int64_t offset = offset_us(c);
    if (c->stamped == 0u) {
        c->ref_offset = offset;
    }
    if (++c->in_block == BUS_CLOCK_BLOCK) {
        c->prev_min = c->cur_min;
        c->cur_min = INT64_MAX;
        c->in_block = 0u;
    }
    const uint64_t delay = (uint64_t)(d - target);
    const uint32_t delay32 = (delay > UINT32_MAX) ? UINT32_MAX : (uint32_t)delay;
    ++c->stamped;
    c->delay_sum_us += delay32;
    c->delay_worst_us = (delay32 > c->delay_worst_us) ? delay32 : c->delay_worst_us;
    return (uint64_t)((int64_t)bus + offset);
}

/* The bus clock's offset fell by more than half the time sync's step bound since the time
 * sync took its reference (the first lines of a session came late, the offset converges on
 * the line's fastest delivery): pairs refused since are this port's doing -- its stamps'
 * origin moved, not the master's time -- so the time sync forgets its reference, which it
 * does only while REFUSED (or LOST).  The offset only ever falls towards the fastest delivery
 * the line allows, so no frame on the bus can bring this about twice. */
static void rebase_on_bus_clock(image_t *img)
{
    bus_clock_t *c = &img->bus_clock;
    const int64_t moved = c->ref_offset - offset_us(c);
    if (c->stamped == 0u || moved <= (int64_t)(img->node.tsync.cfg.max_step_us / 2u)) {
        return;
    }
    if (fcc_tsync_rebase(&img->node.tsync) == FCC_OK) {
        c->ref_offset = offset_us(c);
        ++c->rebases;
    }
}

/* A frame's receive stamp is its time on the bus when the line carries it
 * (Z2, bus_to_local), else its line's first byte's arrival (the receive
 * interrupt's); never the time this loop came to parse it: a control step or
 * a design slice that runs meanwhile must not move a SYNC's stamp (time sync). */
static fcc_status_t port_recv(void *ctx, fcc_can_frame_t *frame)
{
    image_t *img = ctx;
    uint8_t b = 0u;
    uint64_t line_rx_us = 0u;
    for (uint32_t i = 0u; i < RECV_BYTE_BUDGET && mps2_link_getc(&b, &line_rx_us) != 0; ++i) {
        if (fcc_slcan_dev_byte(&img->link, b, frame) == FCC_OK) {
            frame->t_us = img->link.timestamps
                              ? bus_to_local(&img->bus_clock, img->link.rx_stamp_us, line_rx_us,
                                             fcc_tsync_has_time(&img->node.tsync))
                              : line_rx_us;
            note_arrival(img, frame->t_us, mps2_link_line_end_us());
            const uint64_t now = mps2_now_us();
            const uint32_t wait = (now > line_rx_us) ? (uint32_t)(now - line_rx_us) : 0u;
            img->parse_wait_sum_us += wait;
            img->parse_wait_worst_us = (wait > img->parse_wait_worst_us) ? wait : img->parse_wait_worst_us;
            return FCC_OK;
        }
    }
    return FCC_ERR_AGAIN;
}

static fcc_status_t port_counters(void *ctx, fcc_can_port_counters_t *out)
{
    const image_t *img = ctx;
    mps2_counters_t b;
    mps2_counters(&b);
    memset(out, 0, sizeof *out);
    out->rx_frames = img->link.cnt.frames_rx;
    out->tx_frames = img->link.cnt.frames_tx;
    out->bus_errors = img->link.cnt.line_errors;   /* garbled SLCAN lines */
    out->rx_overflows = b.rx_overflows;
    out->tx_dropped = img->link.cnt.tx_refused;
    out->rx_ignored = img->link.cnt.ignored;
    return FCC_OK;
}

static uint64_t port_now(void *ctx)
{
    (void)ctx;
    return mps2_now_us();
}

static void log_kv(const char *key, uint64_t v)
{
    mps2_log(" ");
    mps2_log(key);
    mps2_log("=");
    mps2_log_u64(v);
}

/* One log line per event class per second, with the count suppressed. */
static void port_event(void *ctx, const fcc_event_t *ev)
{
    image_t *img = ctx;
    if ((unsigned)ev->cls >= (unsigned)FCC_EV_COUNT) {
        return;
    }
    const uint64_t now = mps2_now_us();
    const unsigned c = (unsigned)ev->cls;
    if (img->event_last_us[c] != 0u && now - img->event_last_us[c] < EVENT_LINE_GAP_US) {
        ++img->event_suppressed[c];
        return;
    }
    img->event_last_us[c] = (now == 0u) ? 1u : now;
    mps2_log("fcc: ");
    mps2_log(fcc_event_class_str(ev->cls));
    if (ev->app != FCC_EV_NO_APP) {
        mps2_log((ev->app == FCC_APP_CDRW) ? " cdrw" : " missile");
        log_kv("step", ev->step);
    }
    if (ev->can_id != FCC_EV_NO_MSG) {
        log_kv("id", ev->can_id);
    }
    mps2_log((ev->value < 0) ? " value=-" : " value=");
    mps2_log_u64((ev->value < 0) ? (uint64_t)(-(int64_t)ev->value) : (uint64_t)ev->value);
    if (img->event_suppressed[c] != 0u) {
        log_kv("suppressed", img->event_suppressed[c]);
        img->event_suppressed[c] = 0u;
    }
    mps2_log("\n");
}

/* ---- start, loop, stop ------------------------------------------------------------------ */

typedef struct {
    const char *key;
    uint64_t value;
} kv_t;

#define N_KV(a) (sizeof(a) / sizeof((a)[0]))

/* "fcc summary: WHAT key=value ..." (the host fcc's exit summary, on the log UART). */
static void summary_line(const char *what, const kv_t *kv, size_t n)
{
    mps2_log("fcc summary: ");
    mps2_log(what);
    for (size_t i = 0u; i < n; ++i) {
        log_kv(kv[i].key, kv[i].value);
    }
    mps2_log("\n");
}

static void summary_app(const char *name, const fcc_node_app_t *a)
{
    const kv_t kv[] = {
        {"steps", a->steps},
        {"degraded", a->degraded_steps},
        {"errors", a->step_errors},
        {"ticks_lost", a->ticks_lost},
        {"ticks_repeated", a->ticks_repeated},
        {"ticks_behind", a->ticks_behind},
        {"ticks_ignored", a->ticks_ignored},
        {"overruns", a->overruns},
        {"worst_exec_us", a->worst_exec_us},
    };
    summary_line(name, kv, N_KV(kv));
}

static void summary(const image_t *img)
{
    summary_app("cdrw", &img->node.app[FCC_APP_CDRW]);
    summary_app("missile", &img->node.app[FCC_APP_MSL]);
    const kv_t lqg[] = {
        {"period_us", fcc_node_app_period_us(&img->node, FCC_APP_MSL)},
        {"bits", fcc_app_msl_bits(&img->node.msl)},
        {"designs_applied", img->node.msl.designs_applied},
        {"designs_failed", img->node.msl.designs_failed},
    };
    summary_line("lqg", lqg, N_KV(lqg));
    /* the host fcc's histogram line (hil.results.timing reads both) */
    const kv_t latency[] = {
        {"n", img->latency.n},
        {"p50", fcc_hist_quantile(&img->latency, 0.50)},
        {"p99", fcc_hist_quantile(&img->latency, 0.99)},
        {"max", img->latency.max},
    };
    summary_line("latency_us missile", latency, N_KV(latency));
    const fcc_slcan_counters_t *s = &img->link.cnt;
    const kv_t slcan[] = {
        {"lines", s->lines},
        {"frames_rx", s->frames_rx},
        {"frames_tx", s->frames_tx},
        {"line_errors", s->line_errors},
        {"overlong", s->overlong},
        {"noise", s->noise},
        {"ignored", s->ignored},
        {"tx_refused", s->tx_refused},
        {"replies_lost", s->replies_lost},
    };
    summary_line("slcan", slcan, N_KV(slcan));
    const fcc_tsync_counters_t *tc = &img->node.tsync.cnt;
    const fcc_tsync_auth_counters_t *ac = &img->node.tsync_auth.cnt;
    const kv_t sync[] = {
        {"state", (uint32_t)img->node.tsync.state},
        {"samples", tc->samples},
        {"losses", tc->losses},
        {"rejected", fcc_node_sync_rejected(&img->node)},
    };
    summary_line("sync", sync, N_KV(sync));
    const kv_t refused[] = {
        {"mac_failed", ac->mac_failed},
        {"freshness_failed", ac->freshness_failed},
        {"unauthenticated", ac->unauthenticated},
        {"step_refused", tc->step_refused},
        {"rate_refused", tc->rate_refused},
    };
    summary_line("sync_refused", refused, N_KV(refused));
    mps2_counters_t b;
    mps2_counters(&b);
    const kv_t board[] = {
        {"rx_bytes", b.rx_bytes},
        {"rx_overflows", b.rx_overflows},
        {"tx_bytes", b.tx_bytes},
        {"tx_refused", b.tx_refused},
        {"stack_used", mps2_stack_used()},
        {"design_slice_worst_us", img->slice_worst_us},
        {"design_slices_forced", img->slices_forced},
        {"uptime_us", mps2_now_us()},
        {"sleeps", b.sleeps},
    };
    summary_line("board", board, N_KV(board));
    /* Where a received frame's time went: on the line (first byte to CR, as the
     * receive interrupt saw them) and in the image (its line's arrival to its
     * parse: the receive stamp no longer includes this). */
    const uint32_t frames = (s->frames_rx != 0u) ? s->frames_rx : 1u;
    const kv_t rx[] = {
        {"lines", b.lines},
        {"line_us_mean", (b.lines != 0u) ? b.line_us_sum / b.lines : 0u},
        {"line_us_worst", b.line_us_worst},
        {"parse_wait_us_mean", img->parse_wait_sum_us / frames},
        {"parse_wait_us_worst", img->parse_wait_worst_us},
        {"stamps_lost", b.stamps_lost},
        {"bus_stamped", img->bus_clock.stamped},
        {"bus_delay_us_mean", img->bus_clock.delay_sum_us /
                                  ((img->bus_clock.stamped != 0u) ? img->bus_clock.stamped : 1u)},
        {"bus_delay_us_worst", img->bus_clock.delay_worst_us},
        {"bus_rebases", img->bus_clock.rebases},
    };
    summary_line("rx_timing", rx, N_KV(rx));
}

static void refuse(const char *what, const char *detail)
{
    mps2_log("fcc: ");
    mps2_log(what);
    mps2_log(detail);
    mps2_log("\n");
    mps2_exit(2);
}

static void configure(image_t *img)
{
    float rate = (float)FCC_CFG_STATUS_RATE_DEFAULT_HZ;
    const char *field = NULL;
    uint8_t rec[FCC_BOOTCFG_SIZE];
    const volatile uint8_t *sector = mps2_bootcfg();
    for (uint32_t i = 0u; i < FCC_BOOTCFG_SIZE; ++i) {
        rec[i] = sector[i];
    }
    if (fcc_node_config_default(&img->cfg) != FCC_OK) {
        refuse("default configuration refused", "");
    }
    const fcc_status_t st = fcc_bootcfg_apply(rec, &img->cfg, &rate, &field);
    if (st == FCC_ERR_AGAIN) {
        mps2_log("fcc: no boot configuration record: compile-time defaults\n");
    } else if (st != FCC_OK) {
        refuse("boot configuration refused: field ", (field != NULL) ? field : "?");
    } else {
        mps2_log("fcc: boot configuration record applied\n");
    }
    img->status_period_us = (rate > 0.0f) ? (uint64_t)(1e6f / rate) : 0u;
    /* Bus authentication (dbc/README.md): this PIL image carries the published test key
     * (tests/keys/secoc_test.key) and a fixed trip, because the emulated board has neither a
     * protected key store nor entropy nor persistent flash.  A flight image takes its key
     * from a provisioned, read-protected sector and its trip from a TRNG or a boot counter. */
    for (uint32_t i = 0u; i < FCC_SECOC_KEY_BYTES; ++i) {
        img->cfg.security.key[i] = (uint8_t)i;
    }
    img->cfg.security.trip = 0x4D344631u; /* "M4F1" */
}

static void start(image_t *img)
{
    configure(img);
    if (fcc_slcan_dev_init(&img->link, mps2_link_write, NULL, "V0110", "NFCC1") != FCC_OK) {
        refuse("SLCAN device refused its set-up", "");
    }
    const fcc_port_t port = {
        .can = {.ctx = img, .send = port_send, .recv = port_recv, .counters = port_counters},
        .now_us = port_now,
        .event = port_event,
        .event_ctx = img,
    };
    fcc_hist_init(&img->latency);
    if (fcc_node_init(&img->node, &img->cfg, &port) != FCC_OK) {
        refuse("configuration refused by the applications (LQG design failed?)", "");
    }
    mps2_log((img->cfg.mode == FCC_MODE_REALTIME) ? "fcc: ready, realtime" : "fcc: ready, lockstep");
    log_kv("cdrw", img->cfg.app_enabled[FCC_APP_CDRW] ? 1u : 0u);
    log_kv("missile", img->cfg.app_enabled[FCC_APP_MSL] ? 1u : 0u);
    log_kv("missile_period_us", fcc_node_app_period_us(&img->node, FCC_APP_MSL));
    log_kv("boot_us", mps2_now_us());
    mps2_log(", waiting for SLCAN 'O' on UART0\n");
}

static uint64_t min_u64(uint64_t a, uint64_t b)
{
    return (a < b) ? a : b;
}

/* One turn of the loop; the time until which nothing is due. */
static uint64_t loop_once(image_t *img)
{
    (void)fcc_node_poll(&img->node, POLL_BUDGET, NULL);
    measure_command(img); /* lockstep: a SIM_TICK's step */
    (void)fcc_node_sync_poll(&img->node); /* time sync timeouts: loss of sync, holdover */
    rebase_on_bus_clock(img);
    uint64_t now = mps2_now_us();
    if (fcc_slcan_dev_take_opened(&img->link)) {
        (void)fcc_node_send_status(&img->node); /* "listening" */
        img->next_status_us = now + img->status_period_us;
        if (!img->flying) {
            fcc_node_rt_start(&img->node, img->rt, now);
        }
        img->flying = true;
        mps2_log("fcc: SLCAN channel open\n");
    }
    uint64_t wake = UINT64_MAX;
    if (img->flying && img->cfg.mode == FCC_MODE_REALTIME) {
        uint64_t jitter[FCC_N_APPS];
        (void)fcc_node_rt_run_due(&img->node, img->rt, jitter);
        measure_command(img);
        wake = fcc_node_rt_next(&img->node, img->rt);
    }
    now = mps2_now_us();
    if (img->link.state == FCC_SLCAN_OPEN && img->status_period_us != 0u) {
        if (now >= img->next_status_us) {
            (void)fcc_node_send_status(&img->node);
            img->next_status_us += img->status_period_us;
            if (img->next_status_us <= now) { /* far behind: no burst */
                img->next_status_us = now + img->status_period_us;
            }
        }
        wake = min_u64(wake, img->next_status_us);
    }
    /* A pending LQG redesign, one slice at a time, and in realtime only when
     * the longest slice seen so far ends before the next deadline: a design
     * never delays a control step (bench pil: max slice + steps < period).
     * Where no slice ever fits (an emulator starved by its host), a slice
     * runs anyway after DESIGN_WAIT_MAX_US, so that a design still arrives. */
    const bool pending = fcc_app_msl_wants_design(&img->node.msl);
    const bool fits = wake == UINT64_MAX || now + img->slice_worst_us < wake;
    if (pending && !fits && img->slice_wait_since_us == 0u) {
        img->slice_wait_since_us = now;
    }
    const bool starved = pending && img->slice_wait_since_us != 0u &&
                         now - img->slice_wait_since_us >= DESIGN_WAIT_MAX_US;
    if (pending && (fits || starved)) {
        img->slice_wait_since_us = 0u;
        img->slices_forced += starved ? 1u : 0u;
        const uint64_t t0 = mps2_now_us();
        (void)fcc_node_background(&img->node);
        const uint64_t dt = mps2_now_us() - t0;
        img->slice_worst_us = (dt > img->slice_worst_us) ? (uint32_t)dt : img->slice_worst_us;
        return 0u; /* did work: look again before sleeping */
    }
    return wake;
}

int main(void)
{
    image_t *img = &g_img;
    mps2_board_init();
    mps2_log("fcc-m4f: Cortex-M4F image on mps2-an386, SLCAN on UART0, log on UART1\n");
    start(img);
    for (;;) {
        const uint64_t wake = loop_once(img);
        if (fcc_node_shutdown_requested(&img->node)) {
            (void)fcc_node_send_status(&img->node); /* the last heartbeat */
            summary(img);
            mps2_exit(0);
        }
        const uint64_t now = mps2_now_us();
        if (wake > now + SPIN_US) {
            mps2_idle(wake);
        }
    }
}
