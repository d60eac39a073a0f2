/*
 * fcc_main.c -- the fcc executable: the portable node (firmware/app) on Linux.
 *
 * One thread, one loop, no heap.  The loop waits (poll) on three
 * descriptors: the CAN socket, a timerfd armed at the next absolute deadline
 * (CLOCK_MONOTONIC, TFD_TIMER_ABSTIME: no drift, whatever the loop's own
 * delays), and a signalfd for SIGINT/SIGTERM (no asynchronous handler, so no
 * race with the wait).  Frames are handed to the node one by one, in arrival
 * order; in lockstep the node steps on SIM_TICK inside that call; in realtime
 * the loop releases each application's step at its deadline (fcc_node_rt:
 * the master's sampling instants while a time master is followed).
 *
 * System calls are the cost here (under User-Mode Linux each one costs about as
 * much as a lockstep step's arithmetic), so an iteration makes only those its
 * work needs: the wait, one receive for the frames that woke it (the port knows
 * when the kernel's queue is empty), one send per step (the port stamps a command's
 * send time there: a clock read, which is also the loop's time after the command),
 * and one clock read after the work when time matters to it (a timer came due, the
 * interface is down, the realtime schedule, the time sync's timeouts);
 * the timer is re-armed only when the next wake moves (or it expired: setting it clears
 * the expiration, no read).  The rest of a wake for frames needs no clock: whatever is
 * due at a time has the timer armed for it.  The clock is the port's (fcc_hostclock.h:
 * the time-stamp counter, a clock_gettime at most every 5 ms).
 */
#define _GNU_SOURCE 1 /* signalfd, timerfd, sigprocmask */

#include <errno.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/signalfd.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include "fcc_cli.h"
#include "fcc_hist.h"
#include "fcc_hostport.h"
#include "fcc_keyfile.h"
#include "fcc_node.h"
#include "fcc_report.h"

/* Frames handled before a due step or timer is looked at again: a babbling
 * node must not delay a deadline by more than this many frames. */
#define FRAME_BUDGET 32u

typedef struct {
    fcc_cli_t cli;
    fcc_report_t report;
    fcc_hostport_t hp;
    fcc_node_t node;
    int sig_fd;
    int timer_fd;
    uint64_t start_us;
    uint64_t end_us;
    uint64_t status_period_us;
    uint64_t next_status_us;
    uint64_t wake_us;        /* the next wake the loop computed */
    uint64_t armed_us;       /* the timer's setting (UINT64_MAX: disarmed) */
    bool timer_expired;      /* it expired and the expiration is not cleared yet */
    uint64_t now_us;         /* the loop's last clock read */
    uint64_t next_sync_poll_us;
    fcc_node_rt_t rt[FCC_N_APPS];
    uint32_t seen_steps[FCC_N_APPS]; /* steps already measured */
    uint32_t seen_cmd_sends;
    fcc_hist_t exec[FCC_N_APPS];
    fcc_hist_t jitter[FCC_N_APPS];
    fcc_hist_t latency; /* missile: newest sensor frame used received -> command sent */
    fcc_hist_t delay;   /* missile, synced: sampling instant -> command sent */
    fcc_hist_t sync_offset; /* |sync residual| per sample used */
    uint32_t seen_sync_samples;
    const char *stop_reason;
} host_t;

static host_t g_host; /* ~150 kB: static, never on the stack or the heap */

static const char *const k_app_names[FCC_N_APPS] = {"cdrw", "missile"};

/* ---- measurements ------------------------------------------------------------- */

/* After any call that may have run steps: record their execution times. */
static void measure_steps(host_t *h)
{
    for (uint32_t a = 0u; a < FCC_N_APPS; ++a) {
        const fcc_node_app_t *na = &h->node.app[a];
        if (na->steps != h->seen_steps[a]) {
            h->seen_steps[a] = na->steps;
            fcc_hist_add(&h->exec[a], na->last_exec_us);
        }
    }
}

/* After a command was sent (if any; stamped at its send by the port): its data age,
 * and the time sync's residual. */
static void measure_command(host_t *h)
{
    if (h->hp.cmd_sends != h->seen_cmd_sends) {
        h->seen_cmd_sends = h->hp.cmd_sends;
        /* every command computed from a sample, a held one too (its age is what the
         * command used): the commands an observer on the bus times, each from the
         * newest sensor frame before it */
        const fcc_app_msl_result_t *r = &h->node.msl.last;
        if (r->newest_rx_us != 0u && h->hp.cmd_sent_us >= r->newest_rx_us) {
            fcc_hist_add(&h->latency, h->hp.cmd_sent_us - r->newest_rx_us);
        }
        const fcc_node_rt_t *rt = &h->rt[FCC_APP_MSL];
        if (rt->synced && h->hp.cmd_sent_us >= rt->last_instant) {
            fcc_hist_add(&h->delay, h->hp.cmd_sent_us - rt->last_instant);
        }
    }
    const fcc_tsync_t *ts = &h->node.tsync;
    if (ts->cnt.samples != h->seen_sync_samples) {
        h->seen_sync_samples = ts->cnt.samples;
        const int32_t e = ts->last_residual_us;
        fcc_hist_add(&h->sync_offset, (uint64_t)((e < 0) ? -(int64_t)e : (int64_t)e));
    }
}

/* The loop's time now: the commands sent since the last one measured (their send times
 * stamped by the port at the send). */
static void take_command(host_t *h, uint64_t now)
{
    h->now_us = now;
    fcc_hostport_take_command(&h->hp);
    measure_command(h);
}

/* ---- frames ------------------------------------------------------------------- */

static void handle_frames(host_t *h, uint32_t budget)
{
    for (uint32_t i = 0u; i < budget; ++i) {
        uint32_t n = 0u;
        (void)fcc_node_poll(&h->node, 1u, &n); /* an I/O error closes the port itself */
        measure_steps(h);
        if (h->hp.cmd_untaken) { /* before the next frame can run the next step; the loop's
                                  * time is the command's send stamp (read as it went out) */
            take_command(h, h->hp.cmd_sent_us);
        }
        if (n == 0u || fcc_node_shutdown_requested(&h->node)) {
            return;
        }
    }
}

/* ---- realtime schedule -------------------------------------------------------- */

static void rt_run_due(host_t *h)
{
    if (h->cli.node.mode != FCC_MODE_REALTIME) {
        return;
    }
    uint64_t jitter[FCC_N_APPS];
    if (fcc_node_rt_run_due(&h->node, h->rt, jitter) == 0u) {
        return;
    }
    for (uint32_t a = 0u; a < FCC_N_APPS; ++a) {
        if (jitter[a] != UINT64_MAX) {
            fcc_hist_add(&h->jitter[a], jitter[a]);
        }
    }
    measure_steps(h);
}

/* ---- the loop ----------------------------------------------------------------- */

static uint64_t min_u64(uint64_t a, uint64_t b)
{
    return (a < b) ? a : b;
}

/* The time sync has something timed to check (fcc_node_sync_poll): the loss of the
 * master it follows, or a SYNC waiting for its FOLLOW_UP.  (Its frames poll it as
 * they come.) */
static bool sync_timed(const host_t *h)
{
    const fcc_tsync_t *ts = &h->node.tsync;
    return ts->pending || ts->state == FCC_TSYNC_LOCKING || ts->state == FCC_TSYNC_LOCKED ||
           ts->state == FCC_TSYNC_HOLDOVER;
}

static uint64_t next_wake(host_t *h, uint64_t now)
{
    uint64_t wake = min_u64(h->end_us, h->next_status_us);
    wake = min_u64(wake, fcc_hostport_service(&h->hp, now));
    if (h->cli.node.mode == FCC_MODE_REALTIME) {
        wake = min_u64(wake, fcc_node_rt_next(&h->node, h->rt));
    }
    if (sync_timed(h)) {
        wake = min_u64(wake, h->next_sync_poll_us);
    }
    return wake;
}

/* Arms the timer for wake (UINT64_MAX: disarmed), unless it is so already.  Setting it
 * also clears an expiration the loop has not read (timerfd_settime resets the count), so
 * a wake by the timer needs no read of it: one system call less before a realtime step. */
static void arm_timer(host_t *h, uint64_t wake)
{
    if (wake == h->armed_us && !h->timer_expired) {
        return;
    }
    h->armed_us = wake;
    struct itimerspec its;
    memset(&its, 0, sizeof its);
    if (wake != UINT64_MAX) {
        its.it_value.tv_sec = (time_t)(wake / 1000000u);
        its.it_value.tv_nsec = (long)(wake % 1000000u) * 1000L;
        if (its.it_value.tv_sec == 0 && its.it_value.tv_nsec == 0) {
            its.it_value.tv_nsec = 1; /* 0 would disarm */
        }
    }
    if (timerfd_settime(h->timer_fd, TFD_TIMER_ABSTIME, &its, NULL) != 0 && h->timer_expired) {
        uint64_t expirations; /* not set (cannot happen with these arguments): read it clear */
        (void)read(h->timer_fd, &expirations, sizeof expirations);
    }
    h->timer_expired = false;
}

static void send_status_if_due(host_t *h, uint64_t now)
{
    if (now < h->next_status_us) {
        return;
    }
    (void)fcc_node_send_status(&h->node);
    h->next_status_us += h->status_period_us;
    if (h->next_status_us <= now) { /* far behind (stopped, debugger): no burst */
        h->next_status_us = now + h->status_period_us;
    }
}

/* The time sync's loss detection (its frames are handled as they come): at most once
 * per this many microseconds -- its limits are whole sync intervals. */
#define SYNC_POLL_US 1000u

static void sync_poll_if_due(host_t *h, uint64_t now)
{
    if (!sync_timed(h) || now < h->next_sync_poll_us) {
        return;
    }
    (void)fcc_node_sync_poll(&h->node);
    h->next_sync_poll_us = now + SYNC_POLL_US;
}

/* One wait and everything that became due.  False when the loop must end. */
static bool loop_once(host_t *h)
{
    arm_timer(h, h->wake_us);
    struct pollfd fds[3] = {{h->sig_fd, POLLIN, 0}, {h->timer_fd, POLLIN, 0},
                            {fcc_hostport_fd(&h->hp), POLLIN, 0}};
    const nfds_t nfds = (fds[2].fd >= 0) ? 3u : 2u;
    /* frames read ahead by the port are not on the descriptor any more: no wait then */
    const bool pending = fcc_hostport_pending(&h->hp);
    if (poll(fds, nfds, pending ? 0 : -1) < 0 && errno != EINTR) {
        h->stop_reason = "poll failed";
        return false;
    }
    if ((fds[0].revents & POLLIN) != 0) {
        struct signalfd_siginfo si;
        const ssize_t n = read(h->sig_fd, &si, sizeof si);
        h->stop_reason = (n == (ssize_t)sizeof si && si.ssi_signo == SIGINT) ? "SIGINT" : "SIGTERM";
        return false;
    }
    const bool timer_due = (fds[1].revents & POLLIN) != 0;
    if (timer_due) {
        h->timer_expired = true; /* cleared by the next arm_timer, which sets it again */
        h->armed_us = UINT64_MAX;
    }
    if (nfds == 3u && fds[2].revents != 0) {
        fcc_hostport_readable(&h->hp);
    }
    if (nfds == 3u && (fds[2].revents != 0 || pending)) {
        handle_frames(h, FRAME_BUDGET);
    }
    rt_run_due(h);
    const bool timed = timer_due || !h->hp.up || sync_timed(h) ||
                       h->cli.node.mode == FCC_MODE_REALTIME || h->hp.cmd_untaken;
    if (timed) {
        const uint64_t now = fcc_hostport_now(&h->hp); /* the iteration's one clock read */
        take_command(h, now);
        send_status_if_due(h, now);
        (void)fcc_hostport_service(&h->hp, now);
        sync_poll_if_due(h, now);
        measure_steps(h);
    }
    while (fcc_node_background(&h->node) == FCC_OK) { /* idle time: a pending LQG redesign, */
    }                                                  /* all its slices (36 us on the host) */
    if (timed) {
        h->wake_us = next_wake(h, h->now_us);
    }
    if (fcc_node_shutdown_requested(&h->node)) {
        h->stop_reason = "shutdown frame";
        return false;
    }
    if (h->now_us >= h->end_us) {
        h->stop_reason = "--duration elapsed";
        return false;
    }
    return true;
}

/* ---- start and stop ----------------------------------------------------------- */

static int setup_fds(host_t *h)
{
    sigset_t mask;
    sigemptyset(&mask);
    sigaddset(&mask, SIGINT);
    sigaddset(&mask, SIGTERM);
    if (sigprocmask(SIG_BLOCK, &mask, NULL) != 0) {
        return -1;
    }
    h->sig_fd = signalfd(-1, &mask, SFD_CLOEXEC | SFD_NONBLOCK);
    h->timer_fd = timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC | TFD_NONBLOCK);
    return (h->sig_fd >= 0 && h->timer_fd >= 0) ? 0 : -1;
}

static uint64_t host_now(void)
{
    return fcc_hostport_now(&g_host.hp);
}

static void print_hist(const char *what, const char *app, const fcc_hist_t *hist)
{
    fprintf(stderr, "fcc summary: %s %s n=%llu p50=%llu p99=%llu max=%llu\n", what, app,
            (unsigned long long)hist->n, (unsigned long long)fcc_hist_quantile(hist, 0.50),
            (unsigned long long)fcc_hist_quantile(hist, 0.99), (unsigned long long)hist->max);
}

/* now_us: the clock at the stop, for the run's length */
static void print_summary(const host_t *h, uint64_t now_us)
{
    const fcc_node_t *n = &h->node;
    fcc_bus_counters_t bc;
    fcc_can_port_counters_t pc;
    (void)fcc_bus_get_counters(&n->bus, &bc);
    (void)n->port.can.counters(n->port.can.ctx, &pc);
    const double secs = (double)(now_us - h->start_us) * 1e-6;
    fprintf(stderr, "fcc: stopping (%s) after %.2f s, mode %s\n", h->stop_reason, secs,
            n->cfg.mode == FCC_MODE_LOCKSTEP ? "lockstep" : "realtime");
    for (uint32_t a = 0u; a < FCC_N_APPS; ++a) {
        const fcc_node_app_t *s = &n->app[a];
        fprintf(stderr,
                "fcc summary: %s steps=%lu degraded=%lu errors=%lu ticks_lost=%lu "
                "ticks_repeated=%lu ticks_behind=%lu ticks_ignored=%lu overruns=%lu "
                "worst_exec_us=%lu\n",
                k_app_names[a], (unsigned long)s->steps, (unsigned long)s->degraded_steps,
                (unsigned long)s->step_errors, (unsigned long)s->ticks_lost,
                (unsigned long)s->ticks_repeated, (unsigned long)s->ticks_behind,
                (unsigned long)s->ticks_ignored, (unsigned long)s->overruns,
                (unsigned long)s->worst_exec_us);
    }
    fprintf(stderr, "fcc summary: lqg period_s=%.4f bits=%u designs_applied=%lu "
            "designs_failed=%lu\n", (double)fcc_app_msl_period(&n->msl),
            (unsigned)fcc_app_msl_bits(&n->msl), (unsigned long)n->msl.designs_applied,
            (unsigned long)n->msl.designs_failed);
    fprintf(stderr, "fcc summary: e2e ok=%lu repeated=%lu ok_some_lost=%lu wrong_sequence=%lu "
            "error=%lu no_new_data=%lu stale_now=%lu\n",
            (unsigned long)bc.e2e[FCC_E2E_OK], (unsigned long)bc.e2e[FCC_E2E_REPEATED],
            (unsigned long)bc.e2e[FCC_E2E_OK_SOME_LOST],
            (unsigned long)bc.e2e[FCC_E2E_WRONG_SEQUENCE], (unsigned long)bc.e2e[FCC_E2E_ERROR],
            (unsigned long)bc.e2e[FCC_E2E_NO_NEW_DATA], (unsigned long)bc.stale_now);
    fprintf(stderr, "fcc summary: rejected unknown_id=%lu wrong_dlc=%lu out_of_range=%lu "
            "tx_refused=%lu tx_saturated=%lu\n", (unsigned long)bc.unknown_id,
            (unsigned long)bc.wrong_dlc, (unsigned long)bc.out_of_range,
            (unsigned long)bc.tx_refused, (unsigned long)bc.tx_saturated);
    fprintf(stderr, "fcc summary: port rx_frames=%lu tx_frames=%lu tx_failed=%lu bus_errors=%lu "
            "rx_overflows=%lu tx_dropped=%lu tx_retries=%lu iface_down=%lu iface_up=%lu\n",
            (unsigned long)n->cnt.rx_frames, (unsigned long)n->cnt.tx_frames,
            (unsigned long)n->cnt.tx_failed, (unsigned long)pc.bus_errors,
            (unsigned long)pc.rx_overflows, (unsigned long)pc.tx_dropped,
            (unsigned long)pc.tx_retries, (unsigned long)h->hp.downs,
            (unsigned long)h->hp.reopens);
    const fcc_socketcan_ctrl_t *ctrl = &h->hp.sc.ctrl;
    fprintf(stderr, "fcc summary: controller state=%s protocol_errors=%lu warnings=%lu "
            "error_passive=%lu bus_off=%lu restarts=%lu tec_max=%lu rec_max=%lu\n",
            fcc_socketcan_ctrl_state_name(ctrl->state), (unsigned long)ctrl->protocol_errors,
            (unsigned long)ctrl->warnings, (unsigned long)ctrl->passive,
            (unsigned long)ctrl->bus_off, (unsigned long)ctrl->restarts,
            (unsigned long)ctrl->tec_max, (unsigned long)ctrl->rec_max);
    /* the clock's reads, and how many took a system call (clock_gettime: the counter's
     * anchor too old, or no counter) */
    fprintf(stderr, "fcc summary: clock reads=%llu real=%lu counter=%s\n",
            (unsigned long long)h->hp.clock_reads, (unsigned long)h->hp.clock.samples,
            h->hp.clock.counter ? "yes" : "no");
    fprintf(stderr, "fcc summary: control resets=%lu configs_accepted=%lu configs_applied=%lu "
            "configs_rejected=%lu heartbeats=%lu oracle_events=%lu\n",
            (unsigned long)n->cnt.resets, (unsigned long)n->cnt.configs_accepted,
            (unsigned long)n->cnt.configs_applied, (unsigned long)n->cnt.configs_rejected,
            (unsigned long)n->cnt.status_sent, (unsigned long)n->cnt.oracle_events);
    static const char *const k_modes[] = {"ground", "flight", "maintenance"};
    fprintf(stderr, "fcc summary: security mode=%s verified=%lu mac_failed=%lu "
            "freshness_failed=%lu unpaired=%lu mode_refused=%lu mode_changes=%lu\n",
            k_modes[(unsigned int)fcc_node_op_mode(n) % 3u], (unsigned long)n->sec.cnt.verified,
            (unsigned long)n->sec.cnt.mac_failed, (unsigned long)n->sec.cnt.freshness_failed,
            (unsigned long)n->sec.cnt.unpaired, (unsigned long)n->cnt.mode_refused,
            (unsigned long)n->cnt.mode_changes);
    for (uint32_t a = 0u; a < FCC_N_APPS; ++a) {
        print_hist("exec_us", k_app_names[a], &h->exec[a]);
    }
    if (n->cfg.mode == FCC_MODE_REALTIME) {
        for (uint32_t a = 0u; a < FCC_N_APPS; ++a) {
            print_hist("jitter_us", k_app_names[a], &h->jitter[a]);
        }
    }
    print_hist("latency_us", "missile", &h->latency);
    const fcc_tsync_t *ts = &n->tsync;
    const fcc_tsync_counters_t *tc = &ts->cnt;
    fprintf(stderr, "fcc summary: sync state=%u master=%u rate_ppm=%.3f syncs=%lu samples=%lu "
            "missing_fup=%lu orphan_fup=%lu repeated_seq=%lu past=%lu future=%lu backwards=%lu "
            "jumps=%lu foreign=%lu losses=%lu recoveries=%lu releases=%lu aligns=%lu\n",
            (unsigned)ts->state, (unsigned)ts->master, (double)ts->rate_ppb * 1e-3,
            (unsigned long)tc->syncs, (unsigned long)tc->samples, (unsigned long)tc->missing_fup,
            (unsigned long)tc->orphan_fup, (unsigned long)tc->repeated_seq,
            (unsigned long)tc->past, (unsigned long)tc->future, (unsigned long)tc->backwards,
            (unsigned long)tc->jumps, (unsigned long)tc->foreign, (unsigned long)tc->losses,
            (unsigned long)tc->recoveries, (unsigned long)tc->releases,
            (unsigned long)(h->rt[FCC_APP_MSL].aligns + h->rt[FCC_APP_CDRW].aligns));
    const fcc_tsync_auth_counters_t *ac = &n->tsync_auth.cnt;
    fprintf(stderr, "fcc summary: sync_refused mac_failed=%lu freshness_failed=%lu "
            "unauthenticated=%lu step_refused=%lu rate_refused=%lu\n",
            (unsigned long)ac->mac_failed, (unsigned long)ac->freshness_failed,
            (unsigned long)ac->unauthenticated, (unsigned long)tc->step_refused,
            (unsigned long)tc->rate_refused);
    print_hist("sync_offset_us", "abs", &h->sync_offset);
    print_hist("delay_us", "missile", &h->delay);
    char events[512];
    fcc_report_totals(&h->report, events, sizeof events);
    fprintf(stderr, "fcc summary: events %s\n", events[0] != '\0' ? events : "none");
}

/* Real-time scheduling, as on a flight computer: the control loop is never
 * preempted by ordinary processes and never waits for a page fault.  Refused
 * (no privilege): one line, and the run goes on with normal scheduling. */
static void set_rt_priority(int priority)
{
    if (priority <= 0) {
        return;
    }
    struct sched_param sp;
    memset(&sp, 0, sizeof sp);
    sp.sched_priority = priority;
    if (sched_setscheduler(0, SCHED_FIFO, &sp) != 0) {
        fprintf(stderr, "fcc: --rt-priority %d refused (%s): normal scheduling\n", priority,
                strerror(errno));
        return;
    }
    if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
        fprintf(stderr, "fcc: memory not locked (%s)\n", strerror(errno));
    }
}

static int start(host_t *h)
{
    fcc_report_init(&h->report, stderr, FCC_REPORT_DEFAULT_INTERVAL_US, host_now);
    if (setup_fds(h) != 0) {
        fprintf(stderr, "fcc: cannot set up signals and timers: %s\n", strerror(errno));
        return 1;
    }
    if (fcc_hostport_init(&h->hp, h->cli.iface, fcc_report_event, &h->report) != FCC_OK) {
        fprintf(stderr, "fcc: bad interface name '%s'\n", h->cli.iface);
        return 2;
    }
    /* The applications first: a configuration the firmware refuses (e.g. F
     * singular, a design that fails for these variances) is a command-line
     * error, whatever the bus. */
    const fcc_port_t port = fcc_hostport_port(&h->hp);
    h->cli.node.security.trip = (h->cli.trip != 0u) ? h->cli.trip : fcc_keyfile_random_trip();
    if (h->cli.node.security.trip == 0u) {
        fprintf(stderr, "fcc: no random trip counter: getrandom failed: %s\n", strerror(errno));
        return 1;
    }
    const bool test_key = fcc_keyfile_is_test_key(h->cli.node.security.key);
    const fcc_status_t st = fcc_node_init(&h->node, &h->cli.node, &port);
    memset(h->cli.node.security.key, 0, sizeof h->cli.node.security.key);
    if (st != FCC_OK) {
        fprintf(stderr, "fcc: configuration refused by the firmware: %s (identification "
                "generators --p0/--e/--f, or no LQG design for T = %g s with these variances)\n",
                fcc_status_str(st), (double)h->cli.node.msl.period);
        return 2;
    }
    if (test_key) {
        fprintf(stderr, "fcc: WARNING: --key-file holds the published test key: the bus is not "
                "protected (tests only)\n");
    }
    if (fcc_hostport_open(&h->hp) != FCC_OK) {
        fprintf(stderr, "fcc: cannot open CAN interface '%s': it does not exist, is down, or "
                "the kernel has no CAN support\n", h->cli.iface);
        return 1;
    }
    set_rt_priority(h->cli.rt_priority);
    h->start_us = fcc_hostport_now(&h->hp);
    h->now_us = h->start_us;
    h->end_us = (h->cli.duration_s > 0.0)
                    ? h->start_us + (uint64_t)(h->cli.duration_s * 1e6)
                    : UINT64_MAX;
    h->status_period_us = (h->cli.status_rate_hz > 0.0)
                              ? (uint64_t)(1e6 / h->cli.status_rate_hz)
                              : UINT64_MAX;
    h->next_status_us = (h->status_period_us == UINT64_MAX)
                            ? UINT64_MAX
                            : h->start_us + h->status_period_us;
    fcc_node_rt_start(&h->node, h->rt, h->start_us);
    h->armed_us = UINT64_MAX; /* timerfd_create leaves it disarmed */
    h->wake_us = next_wake(h, h->start_us);
    for (uint32_t a = 0u; a < FCC_N_APPS; ++a) {
        fcc_hist_init(&h->exec[a]);
        fcc_hist_init(&h->jitter[a]);
    }
    fcc_hist_init(&h->latency);
    fcc_hist_init(&h->delay);
    fcc_hist_init(&h->sync_offset);
    (void)fcc_node_send_status(&h->node); /* "listening" */
    fprintf(stderr, "fcc: ready on %s, %s, apps %s%s%s, LQG T = %.4f s N = %u, stale limit %u\n",
            h->cli.iface, h->cli.node.mode == FCC_MODE_LOCKSTEP ? "lockstep" : "realtime",
            h->cli.node.app_enabled[FCC_APP_CDRW] ? "cdrw" : "",
            (h->cli.node.app_enabled[FCC_APP_CDRW] && h->cli.node.app_enabled[FCC_APP_MSL]) ? ","
                                                                                            : "",
            h->cli.node.app_enabled[FCC_APP_MSL] ? "missile" : "",
            (double)fcc_app_msl_period(&h->node.msl), (unsigned)fcc_app_msl_bits(&h->node.msl),
            (unsigned)h->cli.node.stale_limit);
    fflush(stderr);
    return 0;
}

int main(int argc, char **argv)
{
    host_t *h = &g_host;
    char err[256];
    const int r = fcc_cli_parse(argc, argv, &h->cli, err, sizeof err, stdout);
    if (r == 1) {
        return 0;
    }
    if (r != 0) {
        fprintf(stderr, "fcc: %s\n", err);
        return 2;
    }
    const int rc = start(h);
    if (rc != 0) {
        return rc;
    }
    while (loop_once(h)) {
    }
    (void)fcc_node_send_status(&h->node); /* the last heartbeat, flushed before exit */
    fcc_report_flush(&h->report);
    print_summary(h, fcc_hostport_now(&h->hp));
    fcc_hostport_close(&h->hp);
    return 0;
}
