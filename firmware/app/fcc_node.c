/*
 * fcc_node.c -- the flight computer node (see fcc_node.h and README.md).
 */
#include "fcc_node.h"

#include <stddef.h>
#include <string.h>

#define MSG_BIT(m) ((uint64_t)1u << (uint32_t)(m))

/* ---- small helpers ------------------------------------------------------------ */

static void emit(fcc_node_t *node, fcc_event_class_t cls, uint32_t app, uint32_t can_id,
                 int32_t value)
{
    if (node->port.event == NULL) {
        return;
    }
    fcc_event_t ev;
    ev.cls = cls;
    ev.app = (app < FCC_N_APPS) ? (uint8_t)app : (uint8_t)FCC_EV_NO_APP;
    ev.can_id = can_id;
    ev.step = (app < FCC_N_APPS) ? node->app[app].last_step : 0u;
    ev.value = value;
    node->port.event(node->port.event_ctx, &ev);
}

static uint64_t now_us(const fcc_node_t *node)
{
    return node->port.now_us(node->port.clock_ctx);
}

/* What the port did with one frame (fcc_can_txq_done_fn): counted, a frame not
 * sent reported -- when it happened, whether the port sends frame by frame or
 * the node's queue went out in one batch. */
static void frame_done(void *ctx, const fcc_can_frame_t *frame, uint8_t app, fcc_status_t st)
{
    fcc_node_t *node = ctx;
    if (st == FCC_OK) {
        ++node->cnt.tx_frames;
    } else {
        ++node->cnt.tx_failed;
        emit(node, FCC_EV_TX_FAILED, app, frame->id, st);
    }
}

static void send_frame(fcc_node_t *node, const fcc_can_frame_t *frame, uint32_t app)
{
    /* the outcome of every frame goes to frame_done() */
    (void)fcc_can_txq_send(&node->txq, &node->port.can, frame, (uint8_t)app, frame_done, node);
}

/* The queued frames out (one send_many); each reported to frame_done(). */
static void flush_tx(fcc_node_t *node)
{
    (void)fcc_can_txq_flush(&node->txq, &node->port.can, frame_done, node);
}

static void send_frames(fcc_node_t *node, const fcc_can_frame_t *frames, uint32_t n, uint32_t app)
{
    for (uint32_t i = 0u; i < n; ++i) {
        send_frame(node, &frames[i], app);
    }
}

/* A secured group of fcc's (the DBC's SecOC_Pdus of auth_msg): frames[0..n) must be
 * its PDUs in their order; sent followed by their authenticator, or -- all or
 * nothing, a partial group would not verify -- not at all (FCC_ERR_ARG). */
static fcc_status_t send_authenticated(fcc_node_t *node, fcc_msg_t auth_msg,
                                       const fcc_can_frame_t *frames, uint32_t n, uint32_t app)
{
    uint32_t a;
    if (!fcc_secoc_auth_index(auth_msg, &a) || n != fcc_secoc_table[a].n_pdus) {
        return FCC_ERR_ARG;
    }
    uint8_t pdu[FCC_SECOC_PDU_BYTES];
    for (uint32_t i = 0u; i < n; ++i) {
        if (frames[i].id != fcc_bus_msg_table[fcc_secoc_table[a].pdus[i]].id || frames[i].dlc != 8u) {
            return FCC_ERR_ARG;
        }
        memcpy(&pdu[8u * i], frames[i].data, 8u);
    }
    fcc_can_frame_t auth;
    const fcc_status_t st = fcc_secoc_protect(&node->sec, a, pdu, 8u * n, &auth);
    if (st == FCC_OK) {
        send_frames(node, frames, n, app);
        send_frame(node, &auth, app);
    }
    return st;
}

/* The application whose input a message is (generated from the DBC's FccApp), or FCC_N_APPS. */
static uint32_t app_of(fcc_msg_t msg)
{
    return ((uint32_t)msg < (uint32_t)FCC_MSG_COUNT) ? fcc_bus_input_app[msg] : FCC_N_APPS;
}

/* ---- the applications, by id: each one's interface and where its instance and its
 * configuration are (the node's storage: no heap) ------------------------------- */

typedef struct {
    const fcc_app_ops_t *ops; /* NULL: no such application in this build */
    size_t instance;          /* offset of its instance in fcc_node_t */
    size_t config;            /* offset of its configuration in fcc_node_config_t, or NO_CONFIG */
} app_slot_t;

#define NO_CONFIG SIZE_MAX

/* The one list of the applications this build flies (the ids are the DBC's FccApp). */
static const app_slot_t k_apps[FCC_N_APPS] = {
    [FCC_BUS_APP_CDRW] = {&fcc_app_sid_ops, offsetof(fcc_node_t, sid),
                          offsetof(fcc_node_config_t, sid)},
    [FCC_BUS_APP_MISSILE] = {&fcc_app_msl_ops, offsetof(fcc_node_t, msl),
                             offsetof(fcc_node_config_t, msl)},
#if defined(FCC_APP_PROBE)
    [FCC_BUS_APP_PROBE] = {&fcc_app_probe_ops, offsetof(fcc_node_t, probe), NO_CONFIG},
#endif
};

const fcc_app_ops_t *fcc_node_app_ops(uint32_t app)
{
    return (app < FCC_N_APPS) ? k_apps[app].ops : NULL;
}

uint32_t fcc_node_app_named(const char *name, uint32_t len)
{
    for (uint32_t a = 0u; name != NULL && a < FCC_N_APPS; ++a) {
        const fcc_app_ops_t *ops = k_apps[a].ops;
        if (ops != NULL && strlen(ops->name) == len && strncmp(ops->name, name, len) == 0) {
            return a;
        }
    }
    return FCC_N_APPS;
}

/* The instance of application app (its ops not NULL). */
static void *instance(fcc_node_t *node, uint32_t app)
{
    return (unsigned char *)node + k_apps[app].instance;
}

static const void *instance_c(const fcc_node_t *node, uint32_t app)
{
    return (const unsigned char *)node + k_apps[app].instance;
}

/* The configuration of application app in cfg, NULL when it takes none. */
static void *config_of(fcc_node_config_t *cfg, uint32_t app)
{
    return (k_apps[app].config != NO_CONFIG) ? (unsigned char *)cfg + k_apps[app].config : NULL;
}

/* The sensor of an input message (its application's slot), or NULL. */
static fcc_sensor_t *sensor_of(fcc_node_t *node, fcc_msg_t msg)
{
    const uint32_t app = app_of(msg);
    const fcc_app_ops_t *ops = fcc_node_app_ops(app);
    return (ops != NULL) ? ops->sensor(instance(node, app), msg) : NULL;
}

/* ---- set-up ------------------------------------------------------------------- */

fcc_status_t fcc_node_config_default(fcc_node_config_t *cfg)
{
    if (cfg == NULL) {
        return FCC_ERR_ARG;
    }
    memset(cfg, 0, sizeof *cfg);
    cfg->mode = FCC_MODE_LOCKSTEP;
    cfg->stale_limit = (uint16_t)FCC_NODE_DEFAULT_STALE_LIMIT;
    fcc_status_t st = FCC_OK;
    for (uint32_t a = 0u; a < FCC_N_APPS; ++a) {
        cfg->app_enabled[a] = k_apps[a].ops != NULL;
        void *app_cfg = cfg->app_enabled[a] ? config_of(cfg, a) : NULL;
        if (app_cfg != NULL && st == FCC_OK) {
            st = k_apps[a].ops->config_default(app_cfg);
        }
    }
    return st;
}

fcc_status_t fcc_node_init(fcc_node_t *node, const fcc_node_config_t *cfg,
                           const fcc_port_t *port)
{
    if (node == NULL || cfg == NULL || port == NULL || port->can.send == NULL ||
        port->can.recv == NULL || port->now_us == NULL) {
        return FCC_ERR_ARG;
    }
    if ((cfg->mode != FCC_MODE_LOCKSTEP && cfg->mode != FCC_MODE_REALTIME) ||
        cfg->security.trip == 0u) {
        return FCC_ERR_ARG;
    }
    for (uint32_t a = 0u; a < FCC_N_APPS; ++a) {
        if (cfg->app_enabled[a] && k_apps[a].ops == NULL) {
            return FCC_ERR_ARG; /* not in this build */
        }
    }
    memset(node->app, 0, sizeof node->app);
    memset(&node->cnt, 0, sizeof node->cnt);
    (void)fcc_can_txq_init(&node->txq); /* not NULL: cannot fail */
    node->cfg = *cfg;
    node->port = *port;
    node->oracle_fault = false;
    node->shutdown = false;
    node->config_rejected = false;
    node->e2e_fault_flag = false;
    node->overrun_flag = false;
    node->op_mode = FCC_OP_GROUND;
    fcc_status_t st = fcc_secoc_init(&node->sec, cfg->security.key, cfg->security.trip);
    /* The key lives in the SecOC state only (expanded); the copy in cfg is wiped. */
    memset(node->cfg.security.key, 0, sizeof node->cfg.security.key);
    fcc_tsync_config_t tcfg;
    if (st == FCC_OK) {
        st = fcc_tsync_config_default(&tcfg);
    }
    if (st == FCC_OK) {
        st = fcc_tsync_init(&node->tsync, &tcfg);
    }
    if (st == FCC_OK) {
        st = fcc_tsync_auth_init(&node->tsync_auth);
    }
    node->tsync_reported = FCC_TSYNC_FREE_RUN;
    node->tsync_rejected_reported = 0u;
    if (st == FCC_OK) {
        st = fcc_bus_init(&node->bus, FCC_BUS_NODE_FCC);
    }
    for (uint32_t a = 0u; a < FCC_N_APPS && st == FCC_OK; ++a) {
        if (k_apps[a].ops != NULL) {
            st = k_apps[a].ops->init(instance(node, a), config_of(&node->cfg, a));
        }
    }
    return st;
}

fcc_status_t fcc_node_reset(fcc_node_t *node)
{
    if (node == NULL) {
        return FCC_ERR_ARG;
    }
    fcc_status_t st = FCC_OK;
    for (uint32_t a = 0u; a < FCC_N_APPS; ++a) {
        if (k_apps[a].ops != NULL) {
            const fcc_status_t st_a = k_apps[a].ops->reset(instance(node, a));
            st = (st != FCC_OK) ? st : st_a;
        }
        node->app[a].have_last = false;
        node->app[a].last_degraded = false;
    }
    node->oracle_fault = false;
    /* A time master refused (or lost) may be followed again from here: only an
     * authenticated RESET, only on the ground, forgets the time base. */
    (void)fcc_tsync_rebase(&node->tsync);
    /* The simulator may restart its alive counters with a new flight. */
    for (unsigned int i = 0u; i < (unsigned int)FCC_MSG_COUNT; ++i) {
        if ((node->bus.consumes & MSG_BIT(i)) != 0u) {
            fcc_e2e_rx_resync(&node->bus.rx[i]);
        }
    }
    ++node->cnt.resets;
    emit(node, FCC_EV_RESET, FCC_N_APPS, FCC_MSG_SIM_CONTROL_ID, st);
    return st;
}

/* ---- received frames ---------------------------------------------------------- */

static void on_rejected(fcc_node_t *node, const fcc_can_frame_t *frame,
                        const fcc_bus_rx_msg_t *m)
{
    const uint32_t app = (m->msg == FCC_MSG_COUNT) ? FCC_N_APPS : app_of(m->msg);
    fcc_event_class_t cls;
    switch (m->verdict) {
    case FCC_BUS_UNKNOWN_ID: cls = FCC_EV_UNKNOWN_ID; break;
    case FCC_BUS_WRONG_DLC: cls = FCC_EV_WRONG_DLC; break;
    case FCC_BUS_OUT_OF_RANGE: cls = FCC_EV_OUT_OF_RANGE; break;
    default:
        if (m->e2e == FCC_E2E_REPEATED) {
            /* A copy of data already seen: no new data, not corrupted data. */
            emit(node, FCC_EV_E2E_REPEATED, app, frame->id, 0);
            return;
        }
        node->e2e_fault_flag = true;
        cls = (m->e2e == FCC_E2E_WRONG_SEQUENCE) ? FCC_EV_E2E_WRONG_SEQ : FCC_EV_E2E_ERROR;
        break;
    }
    if (m->msg != FCC_MSG_COUNT) {
        fcc_sensor_reject(sensor_of(node, m->msg));
    }
    emit(node, cls, app, frame->id, (int32_t)frame->dlc);
}

static void send_ack(fcc_node_t *node, uint32_t app, uint32_t k)
{
    const fcc_node_app_t *a = &node->app[app];
    fcc_msg_data_t d;
    memset(&d, 0, sizeof d);
    d.fcc_ack.app = (uint8_t)app;
    d.fcc_ack.degraded = a->last_degraded;
    d.fcc_ack.step = k;
    d.fcc_ack.exec_us = (uint16_t)((a->last_exec_us > 0xFFFFu) ? 0xFFFFu : a->last_exec_us);
    fcc_can_frame_t f;
    if (fcc_bus_encode(&node->bus, FCC_MSG_FCC_ACK, &d, &f) == FCC_OK) {
        send_frame(node, &f, app);
    } else {
        emit(node, FCC_EV_TX_REFUSED, app, FCC_MSG_FCC_ACK_ID, 0);
    }
}

static void on_tick(fcc_node_t *node, const fcc_msg_sim_tick_t *tick)
{
    const uint32_t app = tick->app;
    const uint32_t k = tick->step;
    if (app >= FCC_N_APPS) {
        return; /* the DBC range check lets only the FccApp ids through */
    }
    fcc_node_app_t *a = &node->app[app];
    /* (an id without an application in this build is never enabled: fcc_node_init) */
    if (node->cfg.mode != FCC_MODE_LOCKSTEP || !node->cfg.app_enabled[app]) {
        ++a->ticks_ignored;
        emit(node, FCC_EV_TICK_IGNORED, app, FCC_MSG_SIM_TICK_ID, (int32_t)k);
        return;
    }
    if (node->op_mode != FCC_OP_FLIGHT) {
        ++node->cnt.mode_refused; /* the applications run in FLIGHT only */
        emit(node, FCC_EV_MODE_REFUSED, app, FCC_MSG_SIM_TICK_ID, (int32_t)k);
        return;
    }
    if (a->have_last && k == a->last_step) {
        ++a->ticks_repeated;
        emit(node, FCC_EV_TICK_REPEATED, app, FCC_MSG_SIM_TICK_ID, (int32_t)k);
        send_ack(node, app, k);
        return;
    }
    if (a->have_last && k < a->last_step) {
        ++a->ticks_behind;
        emit(node, FCC_EV_TICK_BEHIND, app, FCC_MSG_SIM_TICK_ID, (int32_t)k);
        return;
    }
    if (a->have_last && k - a->last_step > 1u) {
        const uint32_t lost = k - a->last_step - 1u;
        a->ticks_lost += lost;
        emit(node, FCC_EV_TICK_LOST, app, FCC_MSG_SIM_TICK_ID, (int32_t)lost);
    }
    /* Lockstep: a SIM_CONTROL received before this tick applies to it (all
     * its slices now; each call makes progress, so this ends). */
    const fcc_app_ops_t *ops = k_apps[app].ops;
    while (ops->wants_background != NULL && ops->wants_background(instance_c(node, app)) &&
           fcc_node_background(node) == FCC_OK) {
    }
    (void)fcc_node_run_step(node, app, k);
}

/* Is the command (or a new design, `design`) allowed in the current mode?
 * The table is in README.md ("Modes"). */
static bool allowed(fcc_op_mode_t mode, uint32_t command, bool design)
{
    const bool on_ground = mode != FCC_OP_FLIGHT;
    if (design && !on_ground) {
        return false;
    }
    switch (command) {
    case FCC_MSG_SIM_CONTROL_COMMAND_NONE:
    case FCC_MSG_SIM_CONTROL_COMMAND_GROUND:
        return true;
    case FCC_MSG_SIM_CONTROL_COMMAND_FLIGHT:
        return mode != FCC_OP_MAINTENANCE;
    case FCC_MSG_SIM_CONTROL_COMMAND_MAINTENANCE:
    case FCC_MSG_SIM_CONTROL_COMMAND_RESET:
    case FCC_MSG_SIM_CONTROL_COMMAND_SHUTDOWN:
        return on_ground;
    default:
        return false;
    }
}

static void set_mode(fcc_node_t *node, fcc_op_mode_t mode)
{
    if (node->op_mode != mode) {
        node->op_mode = mode;
        ++node->cnt.mode_changes;
        emit(node, FCC_EV_MODE_CHANGED, FCC_N_APPS, FCC_MSG_SIM_CONTROL_ID, (int32_t)mode);
    }
}

/* Applied in this order: reset, design, mode change, shutdown. */
static void on_control(fcc_node_t *node, const fcc_msg_sim_control_t *c)
{
    const bool design = c->lqg_period != FCC_R(0.0) || c->da_bits != 0u;
    if (!allowed(node->op_mode, c->command, design)) {
        ++node->cnt.mode_refused;
        emit(node, FCC_EV_MODE_REFUSED, FCC_N_APPS, FCC_MSG_SIM_CONTROL_ID, (int32_t)c->command);
        return;
    }
    if (c->command == FCC_MSG_SIM_CONTROL_COMMAND_RESET) {
        (void)fcc_node_reset(node);
    }
    for (uint32_t a = 0u; design && a < FCC_N_APPS; ++a) {
        const fcc_app_ops_t *ops = k_apps[a].ops;
        if (ops == NULL || ops->request == NULL) {
            continue; /* takes no design */
        }
        const fcc_status_t st = ops->request(instance(node, a), c->lqg_period, c->da_bits);
        if (st == FCC_OK) {
            ++node->cnt.configs_accepted;
            node->config_rejected = false; /* set again if its design fails */
        } else {
            ++node->cnt.configs_rejected;
            node->config_rejected = true;
            emit(node, FCC_EV_CONFIG_REJECTED, a, FCC_MSG_SIM_CONTROL_ID, st);
        }
    }
    if (c->command == FCC_MSG_SIM_CONTROL_COMMAND_FLIGHT) {
        set_mode(node, FCC_OP_FLIGHT);
    } else if (c->command == FCC_MSG_SIM_CONTROL_COMMAND_GROUND) {
        set_mode(node, FCC_OP_GROUND);
    } else if (c->command == FCC_MSG_SIM_CONTROL_COMMAND_MAINTENANCE) {
        set_mode(node, FCC_OP_MAINTENANCE);
    } else if (c->command == FCC_MSG_SIM_CONTROL_COMMAND_SHUTDOWN) {
        node->shutdown = true;
    } else {
        /* NONE and RESET: no mode change (a reset and a design were applied above) */
    }
}

/* ---- the node's own frames: one handler per message (the applications' inputs go to
 * their application, k_apps) ---------------------------------------------------- */

typedef void (*frame_handler_t)(fcc_node_t *node, const fcc_bus_rx_msg_t *m, uint64_t t_us);

static void handle_tick(fcc_node_t *node, const fcc_bus_rx_msg_t *m, uint64_t t_us)
{
    (void)t_us;
    on_tick(node, &m->data.sim_tick);
}

static void handle_control(fcc_node_t *node, const fcc_bus_rx_msg_t *m, uint64_t t_us)
{
    (void)t_us;
    on_control(node, &m->data.sim_control);
}

static void handle_event(fcc_node_t *node, const fcc_bus_rx_msg_t *m, uint64_t t_us)
{
    (void)t_us;
    node->oracle_fault = m->data.sim_event.oracle_fault;
    ++node->cnt.oracle_events;
}

/* authenticated (handle_tsync); t_us: its receive stamp, taken when it arrived */
static void handle_sync(fcc_node_t *node, const fcc_bus_rx_msg_t *m, uint64_t t_us)
{
    const fcc_msg_tsync_sync_t *s = &m->data.tsync_sync;
    (void)fcc_tsync_on_sync(&node->tsync, s->master, s->seq, s->interval_ms, s->sec, t_us);
    (void)fcc_node_sync_poll(node);
}

static void handle_follow_up(fcc_node_t *node, const fcc_bus_rx_msg_t *m, uint64_t t_us)
{
    (void)t_us;
    const fcc_msg_tsync_follow_up_t *f = &m->data.tsync_follow_up;
    (void)fcc_tsync_on_follow_up(&node->tsync, f->master, f->seq, f->sec_carry, f->ns);
    (void)fcc_node_sync_poll(node);
}

/* RIG_PING: the rig's latency probe, answered by can_echo, not by the flight computer. */
static void handle_ping(fcc_node_t *node, const fcc_bus_rx_msg_t *m, uint64_t t_us)
{
    (void)node;
    (void)m;
    (void)t_us;
}

/* Every other frame the DBC sends to FCC is an application's input (fcc_bus_input_app) or
 * an authenticator (handle_frame); fcc_node_handles() says which, and a unit test fails
 * on a frame sent to FCC that none of them takes. */
static const frame_handler_t k_handlers[FCC_MSG_COUNT] = {
    [FCC_MSG_TSYNC_SYNC] = handle_sync,       [FCC_MSG_TSYNC_FOLLOW_UP] = handle_follow_up,
    [FCC_MSG_SIM_CONTROL] = handle_control,   [FCC_MSG_SIM_TICK] = handle_tick,
    [FCC_MSG_SIM_EVENT] = handle_event,       [FCC_MSG_RIG_PING] = handle_ping,
};

bool fcc_node_handles(fcc_msg_t msg)
{
    uint32_t a;
    const uint32_t app = app_of(msg);
    if (app < FCC_N_APPS) {
        return true; /* generated with its application's input table (fcc_bus_msgs.c) */
    }
    if ((uint32_t)msg >= (uint32_t)FCC_MSG_COUNT) {
        return false;
    }
    /* an authenticator sent to fcc is verified in handle_frame (fcc's own are sent) */
    const bool received = (fcc_bus_msg_table[msg].receivers & (1u << FCC_BUS_NODE_FCC)) != 0u;
    return (k_handlers[msg] != NULL) || (fcc_secoc_auth_index(msg, &a) && received);
}

/* A frame that passed authentication (or needs none): checks, then to its application or
 * its handler (every frame fcc consumes has one of them: fcc_node_handles). */
static void dispatch(fcc_node_t *node, const fcc_can_frame_t *frame)
{
    fcc_bus_rx_msg_t m;
    if (fcc_bus_receive(&node->bus, frame, &m) != FCC_OK) {
        on_rejected(node, frame, &m);
        return;
    }
    const uint32_t app = app_of(m.msg);
    const fcc_app_ops_t *ops = fcc_node_app_ops(app);
    if (ops != NULL) {
        (void)ops->offer(instance(node, app), m.msg, &m.data, frame->t_us);
    } else if (k_handlers[m.msg] != NULL) {
        k_handlers[m.msg](node, &m, frame->t_us);
    } else {
        emit(node, FCC_EV_UNKNOWN_ID, FCC_N_APPS, frame->id, (int32_t)frame->dlc);
    }
}

/* The time master's frames: SYNC and FOLLOW_UP held until TSYNC_AUTH verifies
 * a pair (fcc_tsync_auth.h), which then goes through the checks to the servo. */
static void handle_tsync(fcc_node_t *node, fcc_msg_t msg, const fcc_can_frame_t *frame)
{
    if (msg == FCC_MSG_TSYNC_SYNC) {
        /* the receive stamp is on the port's clock; a port without one: now */
        const uint64_t t = (frame->t_us != 0u) ? frame->t_us : now_us(node);
        (void)fcc_tsync_auth_hold_sync(&node->tsync_auth, frame->data, t);
        return;
    }
    if (msg == FCC_MSG_TSYNC_FOLLOW_UP) {
        (void)fcc_tsync_auth_hold_follow_up(&node->tsync_auth, frame->data);
        return;
    }
    uint32_t a;
    fcc_tsync_held_t sync;
    fcc_can_frame_t fup = *frame;
    const fcc_secoc_verdict_t v =
        fcc_secoc_auth_index(msg, &a)
            ? fcc_tsync_auth_verify(&node->tsync_auth, &node->sec, a, frame->data, &sync, fup.data)
            : FCC_SECOC_NO_PDU;
    if (v != FCC_SECOC_VERIFIED) {
        emit(node, FCC_EV_AUTH_FAILED, FCC_N_APPS, frame->id, (int32_t)v);
        (void)fcc_node_sync_poll(node);
        return;
    }
    fcc_can_frame_t s = *frame;
    s.id = FCC_MSG_TSYNC_SYNC_ID;
    s.t_us = sync.t_us;
    memcpy(s.data, sync.data, 8u);
    fup.id = FCC_MSG_TSYNC_FOLLOW_UP_ID;
    dispatch(node, &s);
    dispatch(node, &fup);
}

static void handle_frame(fcc_node_t *node, const fcc_can_frame_t *frame)
{
    ++node->cnt.rx_frames;
    fcc_msg_t msg;
    uint32_t a;
    const bool listed = fcc_bus_find(frame->id, &msg) == FCC_OK;
    if (listed && (node->bus.produces & MSG_BIT(msg)) != 0u) {
        /* fcc never receives its own frames: another node sends on fcc's identifier */
        ++node->cnt.own_id;
    }
    const bool known = listed && (node->bus.consumes & MSG_BIT(msg)) != 0u && frame->dlc == 8u;
    if (known && (msg == FCC_MSG_TSYNC_SYNC || msg == FCC_MSG_TSYNC_FOLLOW_UP ||
                  msg == FCC_MSG_TSYNC_AUTH)) {
        handle_tsync(node, msg, frame);
        return;
    }
    if (known && fcc_secoc_secured_index(msg, &a)) {
        /* Held until its authenticator comes; E2E and range checks after that. */
        (void)fcc_secoc_hold(&node->sec, a, frame->data);
        return;
    }
    if (known && fcc_secoc_auth_index(msg, &a)) {
        fcc_can_frame_t pdu = *frame;
        const fcc_secoc_verdict_t v = fcc_secoc_verify(&node->sec, a, frame->data, pdu.data);
        if (v != FCC_SECOC_VERIFIED) {
            emit(node, FCC_EV_AUTH_FAILED, FCC_N_APPS, frame->id, (int32_t)v);
            return;
        }
        pdu.id = fcc_bus_msg_table[fcc_secoc_table[a].pdus[0]].id;
        dispatch(node, &pdu);
        return;
    }
    dispatch(node, frame);
}

void fcc_node_handle_frame(fcc_node_t *node, const fcc_can_frame_t *frame)
{
    if (node == NULL || frame == NULL) {
        return;
    }
    handle_frame(node, frame);
    flush_tx(node); /* a repeated tick's ACK (a step has sent its own frames) */
}

fcc_status_t fcc_node_poll(fcc_node_t *node, uint32_t max_frames, uint32_t *n)
{
    if (n != NULL) {
        *n = 0u;
    }
    if (node == NULL) {
        return FCC_ERR_ARG;
    }
    for (uint32_t i = 0u; i < max_frames; ++i) {
        fcc_can_frame_t f;
        const fcc_status_t st = node->port.can.recv(node->port.can.ctx, &f);
        if (st == FCC_ERR_AGAIN) {
            return FCC_OK;
        }
        if (st != FCC_OK) {
            return FCC_ERR_IO;
        }
        fcc_node_handle_frame(node, &f);
        if (n != NULL) {
            ++*n;
        }
    }
    return FCC_OK;
}

/* ---- steps -------------------------------------------------------------------- */

/* One event per sensor whose verdict changed class this step. */
static void report_sensors(fcc_node_t *node, uint32_t app, const fcc_msg_t *msgs, uint32_t n,
                           const fcc_sensor_state_t *before)
{
    for (uint32_t i = 0u; i < n; ++i) {
        const fcc_sensor_t *s = sensor_of(node, msgs[i]);
        const fcc_sensor_state_t now = s->state;
        uint32_t closes = 0u;
        for (unsigned int c = 0u; c < (unsigned int)FCC_SENSOR_N_STATES; ++c) {
            closes += s->count[c];
        }
        /* The first step after start or reset has no history to recover from. */
        const fcc_sensor_state_t was = (closes <= 1u) ? FCC_SENSOR_OK : before[i];
        if (now == was || (fcc_sensor_usable(now) && fcc_sensor_usable(was))) {
            continue;
        }
        fcc_event_class_t cls = FCC_EV_SENSOR_RECOVERED;
        if (now == FCC_SENSOR_STALE) {
            cls = FCC_EV_SENSOR_STALE;
        } else if (now == FCC_SENSOR_REJECTED) {
            cls = FCC_EV_SENSOR_REJECTED;
        } else if (now == FCC_SENSOR_MISALIGNED) {
            cls = FCC_EV_SENSOR_MISALIGNED;
        } else {
            /* usable again: RECOVERED, as initialised */
        }
        emit(node, cls, app, s->can_id, (int32_t)s->missing_run);
    }
}

/* Close the E2E receive period of each sensor (NO_NEW_DATA) and remember
 * the verdicts of the previous step for report_sensors(). */
static void close_periods(fcc_node_t *node, const fcc_msg_t *msgs, uint32_t n,
                          fcc_sensor_state_t *before)
{
    for (uint32_t i = 0u; i < n; ++i) {
        (void)fcc_bus_end_period(&node->bus, msgs[i]);
        before[i] = sensor_of(node, msgs[i])->state;
    }
}

/* A step's outputs: under the application's authenticator (all or none), or plain. */
static fcc_status_t send_outputs(fcc_node_t *node, const fcc_app_ops_t *ops,
                                 const fcc_can_frame_t *frames, uint32_t n, uint32_t app)
{
    if (ops->out_auth == FCC_MSG_COUNT) {
        send_frames(node, frames, n, app);
        return FCC_OK;
    }
    return send_authenticated(node, ops->out_auth, frames, n, app);
}

/* One step of application app through its interface: inputs closed, step, outputs sent,
 * its sensors' changes reported. */
static fcc_status_t step_app(fcc_node_t *node, uint32_t app, uint32_t k, bool check_step,
                             bool *degraded)
{
    const fcc_app_ops_t *ops = k_apps[app].ops;
    void *inst = instance(node, app);
    fcc_sensor_state_t before[FCC_BUS_MAX_APP_INPUTS];
    close_periods(node, ops->inputs, ops->n_inputs, before);
    const fcc_app_tick_t tick = {k, check_step, node->cfg.stale_limit, node->oracle_fault};
    fcc_app_step_t res = {false, false};
    const fcc_status_t st = ops->step(inst, &tick, &res);
    fcc_can_frame_t frames[FCC_SECOC_MAX_PDUS];
    uint32_t n = 0u;
    if (ops->encode(inst, &node->bus, frames, &n) != FCC_OK ||
        send_outputs(node, ops, frames, n, app) != FCC_OK) {
        const uint32_t id = (ops->out_auth != FCC_MSG_COUNT) ? fcc_bus_desc(ops->out_auth)->id
                                                             : FCC_EV_NO_MSG;
        emit(node, FCC_EV_TX_REFUSED, app, id, (int32_t)n);
    }
    if (res.reconfigured) {
        ++node->cnt.configs_applied;
        node->config_rejected = false;
        emit(node, FCC_EV_CONFIG_APPLIED, app, FCC_MSG_SIM_CONTROL_ID,
             (int32_t)fcc_node_app_period_us(node, app));
    }
    report_sensors(node, app, ops->inputs, ops->n_inputs, before);
    *degraded = res.degraded;
    return st;
}

fcc_status_t fcc_node_run_step(fcc_node_t *node, uint32_t app, uint32_t k)
{
    if (node == NULL || fcc_node_app_ops(app) == NULL) {
        return FCC_ERR_ARG;
    }
    if (node->op_mode != FCC_OP_FLIGHT) {
        return FCC_ERR_AGAIN; /* GROUND and MAINTENANCE: the applications are idle */
    }
    fcc_node_app_t *a = &node->app[app];
    const bool lockstep = node->cfg.mode == FCC_MODE_LOCKSTEP;
    const uint64_t t0 = now_us(node);
    a->last_step = k;
    a->have_last = true;
    bool degraded = false;
    const fcc_status_t st = step_app(node, app, k, lockstep, &degraded);
    const uint64_t dt = now_us(node) - t0;
    a->last_exec_us = (dt > UINT32_MAX) ? UINT32_MAX : (uint32_t)dt;
    a->worst_exec_us = (a->last_exec_us > a->worst_exec_us) ? a->last_exec_us : a->worst_exec_us;
    a->last_degraded = degraded;
    ++a->steps;
    if (degraded) {
        ++a->degraded_steps;
    }
    if (st != FCC_OK) {
        ++a->step_errors;
        emit(node, FCC_EV_STEP_ERROR, app, FCC_EV_NO_MSG, st);
    }
    if (lockstep) {
        send_ack(node, app, k);
    }
    flush_tx(node); /* the step's outputs (and ACK) leave together, right after the step */
    return st;
}

fcc_status_t fcc_node_background(fcc_node_t *node)
{
    if (node == NULL) {
        return FCC_ERR_ARG;
    }
    fcc_status_t result = FCC_ERR_AGAIN;
    for (uint32_t a = 0u; a < FCC_N_APPS; ++a) {
        const fcc_app_ops_t *ops = k_apps[a].ops;
        if (ops == NULL || ops->background == NULL) {
            continue;
        }
        const fcc_status_t st = ops->background(instance(node, a));
        if (st != FCC_OK && st != FCC_ERR_AGAIN) {
            ++node->cnt.configs_rejected;
            node->config_rejected = true;
            emit(node, FCC_EV_CONFIG_REJECTED, a, FCC_MSG_SIM_CONTROL_ID, st);
        }
        result = (result == FCC_ERR_AGAIN || result == FCC_OK) && st != FCC_ERR_AGAIN ? st : result;
    }
    return result;
}

/* ---- heartbeat ---------------------------------------------------------------- */

static uint16_t wrap16(uint32_t v)
{
    return (uint16_t)(v & 0xFFFFu);
}

/* FCC_STATUS: the DBC gives the identification and the autopilot a field each (steps,
 * degraded); overruns and the worst step are every application's. */
static void fill_status(const fcc_node_t *node, const fcc_bus_counters_t *bc, fcc_msg_data_t *d)
{
    fcc_msg_fcc_status_t *s = &d->fcc_status;
    const fcc_node_app_t *c = &node->app[FCC_BUS_APP_CDRW];
    const fcc_node_app_t *m = &node->app[FCC_BUS_APP_MISSILE];
    uint32_t worst = 0u;
    uint32_t overruns = 0u;
    for (uint32_t a = 0u; a < FCC_N_APPS; ++a) {
        worst = (node->app[a].worst_exec_us > worst) ? node->app[a].worst_exec_us : worst;
        overruns += node->app[a].overruns;
    }
    s->mode = (uint8_t)node->cfg.mode;
    s->op_mode = (uint8_t)node->op_mode;
    s->cdrw_degraded = c->last_degraded;
    s->msl_degraded = m->last_degraded;
    s->sensor_stale = bc->stale_now > 0u;
    s->e2e_fault = node->e2e_fault_flag;
    s->overrun = node->overrun_flag;
    s->config_rejected = node->config_rejected;
    s->overruns = (uint8_t)(overruns & 0x3Fu);
    s->cdrw_steps = wrap16(c->steps);
    s->msl_steps = wrap16(m->steps);
    s->worst_step_us = (uint16_t)((worst > 0xFFFFu) ? 0xFFFFu : worst);
}

static void fill_counts(const fcc_node_t *node, const fcc_bus_counters_t *bc,
                        const fcc_can_port_counters_t *pc, fcc_msg_t msg, fcc_msg_data_t *d)
{
    switch (msg) {
    case FCC_MSG_FCC_E2E_COUNTS:
        d->fcc_e2_e_counts.ok = wrap16(bc->e2e[FCC_E2E_OK]);
        d->fcc_e2_e_counts.repeated = wrap16(bc->e2e[FCC_E2E_REPEATED]);
        d->fcc_e2_e_counts.ok_some_lost = wrap16(bc->e2e[FCC_E2E_OK_SOME_LOST]);
        d->fcc_e2_e_counts.wrong_sequence = wrap16(bc->e2e[FCC_E2E_WRONG_SEQUENCE]);
        break;
    case FCC_MSG_FCC_E2E_FAULTS:
        d->fcc_e2_e_faults.error = wrap16(bc->e2e[FCC_E2E_ERROR]);
        d->fcc_e2_e_faults.no_new_data = wrap16(bc->e2e[FCC_E2E_NO_NEW_DATA]);
        d->fcc_e2_e_faults.stale_now = wrap16(bc->stale_now);
        d->fcc_e2_e_faults.own_id = wrap16(node->cnt.own_id);
        break;
    case FCC_MSG_FCC_REJECT_COUNTS:
        d->fcc_reject_counts.unknown_id = wrap16(bc->unknown_id);
        d->fcc_reject_counts.wrong_dlc = wrap16(bc->wrong_dlc);
        d->fcc_reject_counts.out_of_range = wrap16(bc->out_of_range);
        d->fcc_reject_counts.tx_refused = wrap16(bc->tx_refused);
        break;
    default:
        d->fcc_bus_counts.bus_errors = wrap16(pc->bus_errors);
        d->fcc_bus_counts.rx_overflows = wrap16(pc->rx_overflows);
        d->fcc_bus_counts.tx_dropped = wrap16(pc->tx_dropped);
        d->fcc_bus_counts.tx_retries = wrap16(pc->tx_retries);
        break;
    }
}

static void fill_security(const fcc_node_t *node, fcc_msg_t msg, fcc_msg_data_t *d)
{
    const fcc_secoc_counters_t *s = &node->sec.cnt;
    if (msg == FCC_MSG_FCC_SEC_COUNTS) {
        d->fcc_sec_counts.mac_failed = wrap16(s->mac_failed);
        d->fcc_sec_counts.freshness_failed = wrap16(s->freshness_failed);
        d->fcc_sec_counts.unpaired = wrap16(s->unpaired);
        d->fcc_sec_counts.mode_refused = wrap16(node->cnt.mode_refused);
    } else {
        d->fcc_sec_session.trip = node->sec.trip;
        d->fcc_sec_session.verified = s->verified;
    }
}

uint32_t fcc_node_sync_rejected(const fcc_node_t *node)
{
    if (node == NULL) {
        return 0u;
    }
    const fcc_tsync_auth_counters_t *c = &node->tsync_auth.cnt;
    return fcc_tsync_rejected(&node->tsync) + c->mac_failed + c->freshness_failed +
           c->unauthenticated;
}

static void fill_sync_refusals(const fcc_node_t *node, fcc_msg_data_t *d)
{
    fcc_msg_fcc_sync_refusals_t *r = &d->fcc_sync_refusals;
    const fcc_tsync_auth_counters_t *c = &node->tsync_auth.cnt;
    r->mac_failed = wrap16(c->mac_failed);
    r->freshness_failed = wrap16(c->freshness_failed);
    r->unauthenticated = wrap16(c->unauthenticated);
    r->step_refused = (uint8_t)(node->tsync.cnt.step_refused & 0xFFu);
    r->rate_refused = (uint8_t)(node->tsync.cnt.rate_refused & 0xFFu);
}

static void fill_sync(const fcc_node_t *node, fcc_msg_data_t *d)
{
    const fcc_tsync_t *ts = &node->tsync;
    fcc_msg_fcc_sync_status_t *s = &d->fcc_sync_status;
    s->state = (uint8_t)ts->state;
    s->master = ts->have_master ? ts->master : 0u;
    s->offset_us = (int16_t)((ts->last_residual_us > INT16_MAX)   ? INT16_MAX
                             : (ts->last_residual_us < INT16_MIN) ? INT16_MIN
                                                                  : ts->last_residual_us);
    s->rate_ppm = (fcc_real_t)ts->rate_ppb * FCC_R(1e-3);
    s->syncs = (uint8_t)(ts->cnt.samples & 0xFFu);
    s->rejected = (uint8_t)(fcc_node_sync_rejected(node) & 0xFFu);
    s->losses = (uint8_t)(ts->cnt.losses & 0xFFu);
}

fcc_status_t fcc_node_send_status(fcc_node_t *node)
{
    if (node == NULL) {
        return FCC_ERR_ARG;
    }
    uint32_t ai;
    if (!fcc_secoc_auth_index(FCC_MSG_FCC_STATUS_AUTH, &ai)) {
        return FCC_ERR_ARG;
    }
    const fcc_secoc_desc_t *group = &fcc_secoc_table[ai];
    fcc_bus_counters_t bc;
    fcc_can_port_counters_t pc;
    memset(&pc, 0, sizeof pc);
    (void)fcc_bus_get_counters(&node->bus, &bc);
    if (node->port.can.counters != NULL) {
        (void)node->port.can.counters(node->port.can.ctx, &pc);
    }
    fcc_status_t first = FCC_OK;
    fcc_can_frame_t frames[FCC_SECOC_MAX_PDUS];
    memset(frames, 0, sizeof frames);
    for (unsigned int i = 0u; i < group->n_pdus; ++i) {
        const fcc_msg_t msg = group->pdus[i];
        fcc_msg_data_t d;
        memset(&d, 0, sizeof d);
        if (msg == FCC_MSG_FCC_STATUS) {
            fill_status(node, &bc, &d);
        } else if (msg == FCC_MSG_FCC_SEC_COUNTS || msg == FCC_MSG_FCC_SEC_SESSION) {
            fill_security(node, msg, &d);
        } else if (msg == FCC_MSG_FCC_SYNC_STATUS) {
            fill_sync(node, &d);
        } else if (msg == FCC_MSG_FCC_SYNC_REFUSALS) {
            fill_sync_refusals(node, &d);
        } else {
            fill_counts(node, &bc, &pc, msg, &d);
        }
        /* the sync status saturates (offset and rate are gauges that may leave their range) */
        const fcc_status_t st = (msg == FCC_MSG_FCC_SYNC_STATUS)
                                    ? fcc_bus_encode_sat(&node->bus, msg, &d, &frames[i])
                                    : fcc_bus_encode(&node->bus, msg, &d, &frames[i]);
        first = (first == FCC_OK) ? st : first;
    }
    if (first == FCC_OK) { /* all or nothing: a partial heartbeat would not verify */
        first = send_authenticated(node, FCC_MSG_FCC_STATUS_AUTH, frames, group->n_pdus, FCC_N_APPS);
        flush_tx(node);
    }
    node->e2e_fault_flag = false;
    node->overrun_flag = false;
    ++node->cnt.status_sent;
    return first;
}

/* ---- time sync ---------------------------------------------------------------- */

fcc_tsync_state_t fcc_node_sync_poll(fcc_node_t *node)
{
    if (node == NULL) {
        return FCC_TSYNC_FREE_RUN;
    }
    const fcc_tsync_state_t st = fcc_tsync_poll(&node->tsync, now_us(node));
    if (st != node->tsync_reported) {
        node->tsync_reported = st;
        emit(node, FCC_EV_SYNC_STATE, FCC_N_APPS, FCC_EV_NO_MSG, (int32_t)st);
    }
    const uint32_t rej = fcc_node_sync_rejected(node);
    if (rej != node->tsync_rejected_reported) {
        node->tsync_rejected_reported = rej;
        emit(node, FCC_EV_SYNC_REJECTED, FCC_N_APPS, FCC_MSG_TSYNC_SYNC_ID,
             (int32_t)(rej & 0x7FFFFFFFu));
    }
    return st;
}

bool fcc_node_inputs_since(const fcc_node_t *node, uint32_t app, uint64_t since_us)
{
    if (node == NULL || app >= FCC_N_APPS) {
        return false;
    }
    const fcc_app_ops_t *ops = k_apps[app].ops;
    for (uint32_t i = 0u; ops != NULL && i < ops->n_inputs; ++i) {
        const fcc_sensor_t *s = ops->input(instance_c(node, app), i);
        if (s == NULL || s->n_pending == 0u || s->pending[s->n_pending - 1u].t_us < since_us) {
            return false;
        }
    }
    return true;
}

/* ---- host hooks --------------------------------------------------------------- */

void fcc_node_note_overrun(fcc_node_t *node, uint32_t app, uint32_t missed, uint32_t k)
{
    if (node == NULL || app >= FCC_N_APPS || missed == 0u) {
        return;
    }
    node->app[app].overruns += missed;
    node->overrun_flag = true;
    node->app[app].last_step = k;
    emit(node, FCC_EV_OVERRUN, app, FCC_EV_NO_MSG, (int32_t)missed);
}

void fcc_node_report(fcc_node_t *node, fcc_event_class_t cls, int32_t value)
{
    if (node != NULL) {
        emit(node, cls, FCC_N_APPS, FCC_EV_NO_MSG, value);
    }
}

bool fcc_node_shutdown_requested(const fcc_node_t *node)
{
    return node != NULL && node->shutdown;
}

fcc_op_mode_t fcc_node_op_mode(const fcc_node_t *node)
{
    return (node != NULL) ? node->op_mode : FCC_OP_GROUND;
}

uint32_t fcc_node_app_period_us(const fcc_node_t *node, uint32_t app)
{
    if (node == NULL || app >= FCC_N_APPS) {
        return 0u;
    }
    const fcc_app_ops_t *ops = k_apps[app].ops;
    return (ops != NULL) ? ops->period_us(instance_c(node, app)) : 0u;
}
