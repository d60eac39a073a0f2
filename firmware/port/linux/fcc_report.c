/*
 * fcc_report.c -- rate-limited event lines (see fcc_report.h).
 */
#include "fcc_report.h"

#include <string.h>

#include "fcc_bus.h"
#include "fcc_node.h"

void fcc_report_init(fcc_report_t *r, FILE *out, uint64_t interval_us, uint64_t (*now_us)(void))
{
    memset(r, 0, sizeof *r);
    r->out = out;
    r->interval_us = interval_us;
    r->now_us = now_us;
}

static const char *app_name(uint8_t app)
{
    const fcc_app_ops_t *ops = fcc_node_app_ops(app);
    return (ops != NULL) ? ops->name : NULL;
}

/* " NAME (0x050)", or " 0x555" for an identifier the DBC does not know. */
static void msg_text(uint32_t can_id, char *buf, size_t len)
{
    fcc_msg_t m;
    if (can_id == FCC_EV_NO_MSG) {
        buf[0] = '\0';
    } else if (fcc_bus_find(can_id, &m) == FCC_OK) {
        (void)snprintf(buf, len, " %s (0x%03lX)", fcc_bus_desc(m)->name, (unsigned long)can_id);
    } else {
        (void)snprintf(buf, len, " 0x%03lX", (unsigned long)can_id);
    }
}

/* The class-specific part of the line. */
static void detail(const fcc_event_t *ev, char *buf, size_t len)
{
    switch (ev->cls) {
    case FCC_EV_TICK_LOST:
        (void)snprintf(buf, len, "%ld tick(s) skipped", (long)ev->value);
        break;
    case FCC_EV_TICK_REPEATED:
    case FCC_EV_TICK_BEHIND:
    case FCC_EV_TICK_IGNORED:
        (void)snprintf(buf, len, "tick for step %lu", (unsigned long)(uint32_t)ev->value);
        break;
    case FCC_EV_CONFIG_APPLIED:
        (void)snprintf(buf, len, "period now %.4f s", (double)ev->value * 1e-6);
        break;
    case FCC_EV_CONFIG_REJECTED:
    case FCC_EV_STEP_ERROR:
    case FCC_EV_TX_FAILED:
    case FCC_EV_RESET:
        (void)snprintf(buf, len, "%s", fcc_status_str(ev->value));
        break;
    case FCC_EV_SENSOR_STALE:
    case FCC_EV_SENSOR_REJECTED:
    case FCC_EV_SENSOR_MISALIGNED:
        (void)snprintf(buf, len, "%ld step(s) without a good sample, step degraded",
                       (long)ev->value);
        break;
    case FCC_EV_OVERRUN:
        (void)snprintf(buf, len, "%ld period(s) missed", (long)ev->value);
        break;
    case FCC_EV_WRONG_DLC:
        (void)snprintf(buf, len, "DLC %ld", (long)ev->value);
        break;
    case FCC_EV_BUS_ERROR:
        (void)snprintf(buf, len, "%ld new", (long)ev->value);
        break;
    case FCC_EV_AUTH_FAILED:
        (void)snprintf(buf, len, "%s", (ev->value == 1) ? "freshness (replay or beyond the window)"
                                       : (ev->value == 2) ? "MAC matches no held frame"
                                                          : "no frame to authenticate");
        break;
    case FCC_EV_MODE_REFUSED:
        (void)snprintf(buf, len, "command %ld refused", (long)ev->value);
        break;
    case FCC_EV_MODE_CHANGED:
        (void)snprintf(buf, len, "now %s", (ev->value == 1) ? "FLIGHT"
                                          : (ev->value == 2) ? "MAINTENANCE" : "GROUND");
        break;
    case FCC_EV_IFACE_DOWN:
        (void)snprintf(buf, len, "socket closed, probing every 0.5 s; the applications run on "
                       "prediction");
        break;
    case FCC_EV_IFACE_UP:
        (void)snprintf(buf, len, "socket reopened");
        break;
    case FCC_EV_SYNC_STATE: {
        static const char *const states[6] = {
            "free-run (own clock)", "locking", "locked", "holdover (sync lost, degraded)",
            "lost (no sync: own clock)",
            "refused (the master's time is implausible against the own clock: not followed)"};
        (void)snprintf(buf, len, "%s",
                       (ev->value >= 0 && ev->value < 6) ? states[ev->value] : "?");
        break;
    }
    case FCC_EV_SYNC_REJECTED:
        (void)snprintf(buf, len, "%ld refused so far", (long)ev->value);
        break;
    default:
        buf[0] = '\0';
        break;
    }
}

static void print_line(fcc_report_t *r, const fcc_event_t *ev)
{
    char what[96];
    char where[64];
    detail(ev, what, sizeof what);
    msg_text(ev->can_id, where, sizeof where);
    const char *app = app_name(ev->app);
    char step[48] = "";
    if (app != NULL) {
        (void)snprintf(step, sizeof step, ", %s step %lu", app, (unsigned long)ev->step);
    }
    char more[64] = "";
    if (r->suppressed[ev->cls] > 0u) {
        (void)snprintf(more, sizeof more, " [+%lu more since the last line]",
                       (unsigned long)r->suppressed[ev->cls]);
    }
    const char *sep = (what[0] == '\0') ? "" : (where[0] != '\0' || step[0] != '\0') ? ", " : " ";
    fprintf(r->out, "fcc: %s:%s%s%s%s%s\n", fcc_event_class_str(ev->cls), where, step, sep, what,
            more);
    r->suppressed[ev->cls] = 0u;
    ++r->printed[ev->cls];
}

void fcc_report_event(void *ctx, const fcc_event_t *ev)
{
    fcc_report_t *r = ctx;
    if (r == NULL || ev == NULL || (unsigned int)ev->cls >= (unsigned int)FCC_EV_COUNT) {
        return;
    }
    ++r->total[ev->cls];
    const uint64_t now = r->now_us();
    if (r->printed[ev->cls] == 0u || now - r->last_us[ev->cls] >= r->interval_us) {
        r->last_us[ev->cls] = now;
        print_line(r, ev);
    } else {
        ++r->suppressed[ev->cls];
    }
}

void fcc_report_flush(fcc_report_t *r)
{
    for (unsigned int c = 0u; c < (unsigned int)FCC_EV_COUNT; ++c) {
        if (r->suppressed[c] > 0u) {
            fprintf(r->out, "fcc: %s: %lu more not shown\n",
                    fcc_event_class_str((fcc_event_class_t)c), (unsigned long)r->suppressed[c]);
            r->suppressed[c] = 0u;
        }
    }
    fflush(r->out);
}

void fcc_report_totals(const fcc_report_t *r, char *buf, size_t len)
{
    size_t used = 0u;
    buf[0] = '\0';
    for (unsigned int c = 0u; c < (unsigned int)FCC_EV_COUNT && used < len; ++c) {
        if (r->total[c] == 0u) {
            continue;
        }
        char key[40];
        const char *name = fcc_event_class_str((fcc_event_class_t)c);
        size_t k = 0u;
        for (; name[k] != '\0' && k + 1u < sizeof key; ++k) {
            key[k] = (name[k] == ' ') ? '_' : name[k];
        }
        key[k] = '\0';
        const int n = snprintf(buf + used, len - used, "%s%s=%lu", used > 0u ? " " : "", key,
                               (unsigned long)r->total[c]);
        if (n < 0) {
            break;
        }
        used += (size_t)n;
    }
}
