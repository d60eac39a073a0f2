/*
 * canbus_stats.c -- canbus's measurements and their JSON line (see canbus_stats.h).
 */
#include "canbus_stats.h"

#include <string.h>

void canbus_stats_init(canbus_stats_t *s, uint32_t bitrate)
{
    memset(s, 0, sizeof *s);
    s->bitrate = bitrate;
    canbus_hist_init(&s->delivery);
}

static canbus_id_stats_t *id_stats(canbus_stats_t *s, const canbus_frame_t *f)
{
    for (uint32_t i = 0u; i < s->ids; ++i) {
        if (s->id[i].id == f->id && s->id[i].ext == f->ext) {
            return &s->id[i];
        }
    }
    if (s->ids == CANBUS_IDS_MAX) {
        return NULL;
    }
    canbus_id_stats_t *n = &s->id[s->ids++];
    n->id = f->id;
    n->ext = f->ext;
    canbus_hist_init(&n->response);
    return n;
}

void canbus_stats_frame(canbus_stats_t *s, const canbus_done_t *d, uint64_t bit_ns)
{
    ++s->frames;
    s->busy_ns += (uint64_t)d->bits * bit_ns;
    if (d->node < s->nodes) {
        ++s->node[d->node].sent;
    }
    canbus_id_stats_t *i = id_stats(s, &d->frame);
    if (i == NULL) {
        ++s->ids_untracked;
        return;
    }
    canbus_hist_add(&i->response, d->t_eof - d->t_queued);
}

void canbus_stats_delivery(canbus_stats_t *s, uint64_t eof_ns, uint64_t delivered_ns)
{
    if (delivered_ns < eof_ns) {
        ++s->early;
        canbus_hist_add(&s->delivery, 0u);
        return;
    }
    canbus_hist_add(&s->delivery, delivered_ns - eof_ns);
}

void canbus_stats_recovery(canbus_stats_t *s, uint32_t node, uint64_t bus_off_ns,
                           uint64_t recovered_ns)
{
    if (node >= s->nodes) {
        return;
    }
    canbus_node_stats_t *n = &s->node[node];
    if (n->recoveries < CANBUS_RECOVERIES_MAX) {
        n->recovery_ns[n->recoveries++] = recovered_ns - bus_off_ns;
    }
}

uint64_t canbus_stats_lost(const canbus_stats_t *s)
{
    uint64_t lost = 0u;
    for (uint32_t i = 0u; i < s->nodes; ++i) {
        lost += s->node[i].lost;
    }
    return lost;
}

static double seconds(uint64_t ns)
{
    return (double)ns * 1e-9;
}

/* "n", "p50_s", "p99_s", "max_s" of h (in the same units as summary.json's bus frames). */
static void put_hist(FILE *out, const canbus_hist_t *h)
{
    fprintf(out, "{\"n\": %llu, \"p50_s\": %.9f, \"p99_s\": %.9f, \"max_s\": %.9f",
            (unsigned long long)h->n, seconds(canbus_hist_quantile(h, 50u, 100u)),
            seconds(canbus_hist_quantile(h, 99u, 100u)), seconds(h->max));
}

/* A node's fault confinement: its counters' maxima, errors, episodes, recovery times. */
static void put_confine(FILE *out, const canbus_node_stats_t *n)
{
    const canbus_confine_t *c = &n->confine;
    fprintf(out, "\"tec_max\": %lu, \"rec_max\": %lu, \"tx_errors\": %llu, "
            "\"rx_errors\": %llu, \"error_frames\": %llu, \"error_passive\": %llu, "
            "\"bus_off\": %llu, \"bus_off_dropped\": %llu, \"recovery_s\": [",
            (unsigned long)c->tec_max, (unsigned long)c->rec_max,
            (unsigned long long)c->tx_errors, (unsigned long long)c->rx_errors,
            (unsigned long long)n->error_frames, (unsigned long long)c->passive_episodes,
            (unsigned long long)c->bus_off_episodes, (unsigned long long)c->dropped);
    for (uint32_t k = 0u; k < n->recoveries; ++k) {
        fprintf(out, "%s%.9f", k > 0u ? ", " : "", seconds(n->recovery_ns[k]));
    }
    fputs("]}", out);
}

void canbus_stats_core(canbus_stats_t *s, const canbus_core_t *c)
{
    s->pending = c->busy ? 1u : 0u;
    for (uint32_t i = 0u; i < c->nodes; ++i) {
        s->pending += canbus_core_pending(c, i);
        s->node[i].confine = *canbus_core_confine(c, i);
    }
    s->error_frames = c->error_frames;
    s->babble_dropped = c->babble_dropped;
    s->events_lost = c->events_lost;
    s->late_queued = c->late;
}

void canbus_stats_event(canbus_stats_t *s, const canbus_core_t *c, const canbus_event_t *e)
{
    const canbus_confine_t *n = canbus_core_confine(c, e->node);
    if (e->kind == CANBUS_EV_RESTARTED && n != NULL) {
        canbus_stats_recovery(s, e->node, n->bus_off_at, e->t);
    }
}

fcc_status_t canbus_stats_json(const canbus_stats_t *s, FILE *out)
{
    const double busy = seconds(s->busy_ns);
    fprintf(out, "{\"bitrate\": %lu, \"frames\": %llu, \"busy_s\": %.9f, \"load\": %.4f, "
            "\"wall_s\": %.6f, \"cpu_s\": %.6f, \"pending\": %llu, \"lost\": %llu, "
            "\"late_queued\": %llu, \"delivery_error\": ",
            (unsigned long)s->bitrate, (unsigned long long)s->frames, busy,
            s->wall_s > 0.0 ? busy / s->wall_s : 0.0, s->wall_s, s->cpu_s,
            (unsigned long long)s->pending, (unsigned long long)canbus_stats_lost(s),
            (unsigned long long)s->late_queued);
    put_hist(out, &s->delivery);
    fprintf(out, ", \"early\": %llu}, \"nodes\": [", (unsigned long long)s->early);
    for (uint32_t i = 0u; i < s->nodes; ++i) {
        const canbus_node_stats_t *n = &s->node[i];
        fprintf(out, "%s{\"iface\": \"%s\", \"policy\": \"%s\", \"sent\": %llu, "
                "\"received\": %llu, \"lost\": %llu, ", i > 0u ? ", " : "", n->iface,
                n->policy == CANBUS_FIFO ? "fifo" : "prio", (unsigned long long)n->sent,
                (unsigned long long)n->received, (unsigned long long)n->lost);
        put_confine(out, n);
    }
    fputs("], \"ids\": {", out);
    for (uint32_t i = 0u; i < s->ids; ++i) {
        const canbus_id_stats_t *d = &s->id[i];
        fprintf(out, d->ext ? "%s\"0x%08lX\": " : "%s\"0x%03lX\": ", i > 0u ? ", " : "",
                (unsigned long)d->id);
        put_hist(out, &d->response);
        fputc('}', out);
    }
    fprintf(out, "}, \"ids_untracked\": %llu, \"error_frames\": %llu, \"babble_dropped\": "
            "%llu, \"events_lost\": %llu, \"load_streams\": [", (unsigned long long)s->ids_untracked,
            (unsigned long long)s->error_frames, (unsigned long long)s->babble_dropped,
            (unsigned long long)s->events_lost);
    const char *sep = "";
    for (uint32_t l = 0u; s->load != NULL && l < s->loads; ++l) {
        uint32_t id;
        uint64_t period;
        for (uint32_t i = 0u; canbus_load_stream(&s->load[l], i, &id, &period); ++i) {
            fprintf(out, "%s{\"id\": %lu, \"period_ns\": %llu}", sep, (unsigned long)id,
                    (unsigned long long)period);
            sep = ", ";
        }
    }
    fprintf(out, "], \"load_dropped\": %llu}\n", (unsigned long long)s->load_dropped);
    return fflush(out) == 0 && !ferror(out) ? FCC_OK : FCC_ERR_IO;
}
