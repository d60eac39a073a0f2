/*
 * fcc_tsync.c -- time synchronisation slave (see fcc_tsync.h).
 */
#include "fcc_tsync.h"

#include <string.h>

#define PPB 1000000000LL

fcc_status_t fcc_tsync_config_default(fcc_tsync_config_t *cfg)
{
    if (cfg == NULL) {
        return FCC_ERR_ARG;
    }
    cfg->step_us = 1000u;
    cfg->lock_us = 200u;
    cfg->lock_count = 3u;
    cfg->jump_count = 3u;
    cfg->loss_intervals = 3u;
    cfg->release_intervals = 50u;
    cfg->max_rate_ppb = 200000;
    cfg->max_step_us = 1000u;
    return FCC_OK;
}

fcc_status_t fcc_tsync_init(fcc_tsync_t *ts, const fcc_tsync_config_t *cfg)
{
    if (ts == NULL || cfg == NULL) {
        return FCC_ERR_ARG;
    }
    if (cfg->step_us == 0u || cfg->lock_us > cfg->step_us || cfg->lock_count == 0u ||
        cfg->jump_count == 0u || cfg->loss_intervals == 0u ||
        cfg->release_intervals <= cfg->loss_intervals || cfg->max_rate_ppb <= 0 ||
        cfg->max_step_us == 0u) {
        return FCC_ERR_RANGE;
    }
    memset(ts, 0, sizeof *ts);
    ts->cfg = *cfg;
    ts->state = FCC_TSYNC_FREE_RUN;
    ts->interval_us = 100000u;
    return FCC_OK;
}

bool fcc_tsync_has_time(const fcc_tsync_t *ts)
{
    return ts != NULL && ts->have_ref &&
           (ts->state == FCC_TSYNC_LOCKING || ts->state == FCC_TSYNC_LOCKED ||
            ts->state == FCC_TSYNC_HOLDOVER || ts->state == FCC_TSYNC_REFUSED);
}

/* d (1 + rate 1e-9) without overflow for |d| < 2^62 / max rate. */
static int64_t scaled(int64_t d, int32_t rate_ppb)
{
    return d + (d / PPB) * rate_ppb + ((d % PPB) * rate_ppb) / PPB;
}

static int64_t estimate(const fcc_tsync_t *ts, uint64_t local_us)
{
    const int64_t d = (int64_t)(local_us - ts->ref_local_us);
    return (int64_t)ts->ref_master_us + scaled(d, ts->rate_ppb);
}

fcc_status_t fcc_tsync_to_master(const fcc_tsync_t *ts, uint64_t local_us, uint64_t *master_us)
{
    if (ts == NULL || master_us == NULL) {
        return FCC_ERR_ARG;
    }
    if (!fcc_tsync_has_time(ts)) {
        return FCC_ERR_AGAIN;
    }
    const int64_t m = estimate(ts, local_us);
    *master_us = (m > 0) ? (uint64_t)m : 0u;
    return FCC_OK;
}

fcc_status_t fcc_tsync_to_local(const fcc_tsync_t *ts, uint64_t master_us, uint64_t *local_us)
{
    if (ts == NULL || local_us == NULL) {
        return FCC_ERR_ARG;
    }
    if (!fcc_tsync_has_time(ts)) {
        return FCC_ERR_AGAIN;
    }
    /* dl = dm / (1 + r) = dm - dm r / (1 + r) */
    const int64_t dm = (int64_t)(master_us - ts->ref_master_us);
    const int64_t den = PPB + ts->rate_ppb;
    const int64_t corr = (dm / den) * ts->rate_ppb + ((dm % den) * ts->rate_ppb) / den;
    const int64_t l = (int64_t)ts->ref_local_us + dm - corr;
    *local_us = (l > 0) ? (uint64_t)l : 0u;
    return FCC_OK;
}

uint32_t fcc_tsync_rejected(const fcc_tsync_t *ts)
{
    if (ts == NULL) {
        return 0u;
    }
    const fcc_tsync_counters_t *c = &ts->cnt;
    return c->missing_fup + c->orphan_fup + c->repeated_seq + c->past + c->future +
           c->backwards + c->foreign + c->step_refused + c->rate_refused;
}

static int32_t sat32(int64_t v)
{
    return (v > INT32_MAX) ? INT32_MAX : (v < INT32_MIN) ? INT32_MIN : (int32_t)v;
}

static uint64_t abs64(int64_t v)
{
    return (v < 0) ? (uint64_t)(-(v + 1)) + 1u : (uint64_t)v;
}

/* What a rate of rate_ppb accumulates over d microseconds (d < 2^62 / rate). */
static uint64_t drift_us(uint64_t d, int32_t rate_ppb)
{
    const uint64_t r = (uint64_t)((rate_ppb < 0) ? -(int64_t)rate_ppb : rate_ppb);
    return (d / PPB) * r + ((d % PPB) * r) / PPB;
}

/* The plausibility check of an authenticated pair against the own clock (see
 * fcc_tsync.h); the first pair sets the reference.  Counts a refusal. */
static bool plausible(fcc_tsync_t *ts, uint64_t local_us, uint64_t master_us)
{
    const int64_t dev = (int64_t)master_us - (int64_t)local_us;
    const bool had_prev = ts->have_last_auth;
    const int64_t prev = ts->last_auth_dev_us;
    ts->have_last_auth = true;
    ts->last_auth_dev_us = dev;
    if (!ts->have_plaus) {
        ts->have_plaus = true;
        ts->plaus_local_us = local_us;
        ts->plaus_dev_us = dev;
        ts->refusing = false;
        return true;
    }
    const uint64_t dl = (local_us > ts->plaus_local_us) ? local_us - ts->plaus_local_us : 0u;
    if (abs64(dev - ts->plaus_dev_us) <= ts->cfg.max_step_us + drift_us(dl, ts->cfg.max_rate_ppb)) {
        return true;
    }
    if (!ts->refusing) { /* a run of refusals begins: a jump, or a drift out of the bound */
        ts->refusing = true;
        ts->refusing_step = !had_prev || abs64(dev - prev) > ts->cfg.max_step_us;
    }
    if (ts->refusing_step) {
        ++ts->cnt.step_refused;
    } else {
        ++ts->cnt.rate_refused;
    }
    return false;
}

/* An accepted sample moves the plausibility reference towards it, at most at
 * the rate bound. */
static void follow_reference(fcc_tsync_t *ts, uint64_t local_us, uint64_t master_us)
{
    const int64_t dev = (int64_t)master_us - (int64_t)local_us;
    const uint64_t dl = (local_us > ts->plaus_local_us) ? local_us - ts->plaus_local_us : 0u;
    const uint64_t lim = drift_us(dl, ts->cfg.max_rate_ppb);
    const int64_t lim_s = (lim > (uint64_t)INT64_MAX) ? INT64_MAX : (int64_t)lim;
    int64_t delta = dev - ts->plaus_dev_us;
    delta = (delta > lim_s) ? lim_s : (delta < -lim_s) ? -lim_s : delta;
    ts->plaus_dev_us += delta;
    ts->plaus_local_us = (local_us > ts->plaus_local_us) ? local_us : ts->plaus_local_us;
    ts->refusing = false;
}

/* (Re)start the estimate at the sample. */
static void restart(fcc_tsync_t *ts, uint64_t local_us, uint64_t master_us)
{
    ts->have_ref = true;
    ts->ref_local_us = local_us;
    ts->ref_master_us = master_us;
    ts->good_run = 0u;
    ts->outlier_run = 0u;
    ts->last_residual_us = 0;
    ts->state = FCC_TSYNC_LOCKING;
}

static void accept(fcc_tsync_t *ts, uint64_t local_us, uint64_t master_us)
{
    ++ts->cnt.samples;
    follow_reference(ts, local_us, master_us);
    if (ts->state == FCC_TSYNC_HOLDOVER) {
        ++ts->cnt.recoveries;
        ts->state = FCC_TSYNC_LOCKING;
    }
    ts->last_sample_local_us = local_us;
    ts->last_sample_master_us = master_us;
    ts->last_good_local_us = local_us;
}

/* One (local, master) pair through the servo. */
static fcc_status_t sample(fcc_tsync_t *ts, uint64_t local_us, uint64_t master_us)
{
    if (!plausible(ts, local_us, master_us)) {
        if (ts->state != FCC_TSYNC_REFUSED) {
            /* the estimate goes on at the rate of the last quiet residual, not at one
             * that the pairs leading up to the refusal may have pulled */
            ts->rate_ppb = ts->quiet_rate_ppb;
        }
        ts->state = FCC_TSYNC_REFUSED; /* not followed; an estimate, if any, goes on */
        ts->good_run = 0u;
        ts->outlier_run = 0u;
        return FCC_ERR_AGAIN;
    }
    if (ts->state == FCC_TSYNC_REFUSED) {
        ++ts->cnt.recoveries;
        ts->state = ts->have_ref ? FCC_TSYNC_LOCKING : FCC_TSYNC_FREE_RUN;
    }
    if (!ts->have_ref || ts->state == FCC_TSYNC_FREE_RUN || ts->state == FCC_TSYNC_LOST) {
        restart(ts, local_us, master_us);
        accept(ts, local_us, master_us);
        ts->good_run = 1u;
        return FCC_OK;
    }
    if (ts->cnt.samples > 0u && master_us <= ts->last_sample_master_us &&
        local_us > ts->last_sample_local_us) {
        ++ts->cnt.backwards;
        ts->good_run = 0u;
        /* a master clock set back is a jump: the outlier run decides */
    }
    const int64_t e = (int64_t)master_us - estimate(ts, local_us);
    ts->last_residual_us = sat32(e);
    if (abs64(e) > ts->cfg.step_us) {
        if (e < 0) {
            ++ts->cnt.past;
        } else {
            ++ts->cnt.future;
        }
        ts->good_run = 0u;
        if (ts->outlier_run == 0u || abs64(e - ts->outlier_first_us) > ts->cfg.step_us) {
            ts->outlier_run = 1u;
            ts->outlier_first_us = e;
        } else {
            ++ts->outlier_run;
        }
        if (ts->outlier_run >= ts->cfg.jump_count) {
            ++ts->cnt.jumps;
            restart(ts, local_us, master_us);
            accept(ts, local_us, master_us);
            return FCC_OK;
        }
        return FCC_ERR_AGAIN;
    }
    if (master_us <= ts->last_sample_master_us) {
        return FCC_ERR_AGAIN; /* counted above; a small step back is never used */
    }
    ts->outlier_run = 0u;
    /* PI: half the phase error now, a sixteenth of the frequency error */
    const uint64_t dt = local_us - ts->last_sample_local_us;
    int64_t rate = ts->rate_ppb;
    if (dt > 0u && dt < (1ULL << 40)) {
        rate += (e * PPB / (int64_t)dt) / 16;
    }
    const int64_t lim = ts->cfg.max_rate_ppb;
    rate = (rate > lim) ? lim : (rate < -lim) ? -lim : rate;
    const int64_t est = estimate(ts, local_us);
    ts->ref_local_us = local_us;
    ts->ref_master_us = (uint64_t)(est + e / 2);
    ts->rate_ppb = (int32_t)rate;
    if (abs64(e) <= ts->cfg.lock_us) {
        ts->quiet_rate_ppb = ts->rate_ppb;
        ts->good_run = (ts->good_run < 255u) ? (uint8_t)(ts->good_run + 1u) : ts->good_run;
    } else {
        ts->good_run = 0u;
    }
    accept(ts, local_us, master_us);
    if (ts->good_run >= ts->cfg.lock_count) {
        ts->state = FCC_TSYNC_LOCKED;
    }
    return FCC_OK;
}

/* A second time master on the bus: its frames are counted and ignored while ours is followed. */
static bool from_foreign_master(fcc_tsync_t *ts, uint8_t master)
{
    if (ts->have_master && master != ts->master) {
        ++ts->cnt.foreign;
        return true;
    }
    return false;
}

fcc_status_t fcc_tsync_on_sync(fcc_tsync_t *ts, uint8_t master, uint8_t seq, uint8_t interval_ms,
                               uint32_t sec, uint64_t local_us)
{
    if (ts == NULL) {
        return FCC_ERR_ARG;
    }
    if (from_foreign_master(ts, master)) {
        return FCC_ERR_AGAIN;
    }
    if (!ts->have_master) {
        ts->have_master = true;
        ts->master = master;
        ts->have_seq = false;
    }
    if (ts->pending) {
        ++ts->cnt.missing_fup;
        ts->pending = false;
    }
    if (ts->have_seq && seq == ts->last_seq) {
        ++ts->cnt.repeated_seq;
        return FCC_ERR_AGAIN;
    }
    ts->have_seq = true;
    ts->last_seq = seq;
    ts->interval_us = (interval_ms > 0u) ? (uint32_t)interval_ms * 1000u : ts->interval_us;
    ts->pending = true;
    ts->pend_seq = seq;
    ts->pend_sec = sec;
    ts->pend_local_us = local_us;
    ++ts->cnt.syncs;
    return FCC_OK;
}

fcc_status_t fcc_tsync_on_follow_up(fcc_tsync_t *ts, uint8_t master, uint8_t seq,
                                    bool sec_carry, uint32_t ns)
{
    if (ts == NULL) {
        return FCC_ERR_ARG;
    }
    if (from_foreign_master(ts, master)) {
        return FCC_ERR_AGAIN;
    }
    if (!ts->pending || seq != ts->pend_seq || ns >= 1000000000u) {
        ++ts->cnt.orphan_fup;
        return FCC_ERR_AGAIN;
    }
    ts->pending = false;
    const uint64_t m = ((uint64_t)ts->pend_sec + (sec_carry ? 1u : 0u)) * 1000000u + ns / 1000u;
    return sample(ts, ts->pend_local_us, m);
}

fcc_status_t fcc_tsync_rebase(fcc_tsync_t *ts)
{
    if (ts == NULL) {
        return FCC_ERR_ARG;
    }
    if (ts->state != FCC_TSYNC_REFUSED && ts->state != FCC_TSYNC_LOST) {
        return FCC_ERR_AGAIN;
    }
    ts->state = FCC_TSYNC_FREE_RUN;
    ts->have_plaus = false;
    ts->have_last_auth = false;
    ts->refusing = false;
    ts->have_ref = false;
    ts->have_master = false;
    ts->have_seq = false;
    ts->pending = false;
    ts->rate_ppb = 0;
    ts->quiet_rate_ppb = 0;
    return FCC_OK;
}

fcc_tsync_state_t fcc_tsync_poll(fcc_tsync_t *ts, uint64_t now_us)
{
    if (ts == NULL) {
        return FCC_TSYNC_FREE_RUN;
    }
    if (ts->pending && now_us > ts->pend_local_us + ts->interval_us) {
        ++ts->cnt.missing_fup;
        ts->pending = false;
    }
    const uint64_t quiet = now_us - ts->last_good_local_us;
    if ((ts->state == FCC_TSYNC_LOCKING || ts->state == FCC_TSYNC_LOCKED) &&
        now_us > ts->last_good_local_us &&
        quiet > (uint64_t)ts->cfg.loss_intervals * ts->interval_us) {
        ts->state = FCC_TSYNC_HOLDOVER;
        ++ts->cnt.losses;
    }
    if (ts->state == FCC_TSYNC_HOLDOVER && now_us > ts->last_good_local_us &&
        quiet > (uint64_t)ts->cfg.release_intervals * ts->interval_us) {
        ts->state = FCC_TSYNC_LOST; /* the plausibility reference is kept */
        ts->have_master = false;
        ts->have_ref = false;
        ts->have_seq = false;
        ts->rate_ppb = 0;
        ts->quiet_rate_ppb = 0;
        ++ts->cnt.releases;
    }
    return ts->state;
}
