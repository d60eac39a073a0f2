#include "fcc_zkf.h"

#include <string.h>

fcc_status_t fcc_zkf_init(fcc_zkf_t *zkf, const fcc_real_t x0[2], const fcc_real_t p0[4],
                          const fcc_real_t e[4], const fcc_real_t f[4])
{
    if (zkf == NULL || x0 == NULL || p0 == NULL || e == NULL || f == NULL) {
        return FCC_ERR_ARG;
    }
    if (!fcc_sid_all_finite(x0, 2) || !fcc_sid_all_finite(p0, 4) || !fcc_sid_all_finite(e, 4) ||
        !fcc_sid_all_finite(f, 4)) {
        return FCC_ERR_ARG;
    }
    fcc_real_t r[4];
    fcc_sid_m2_mul_bt(f, f, r);
    fcc_real_t rinv[4];
    if (fcc_sid_m2_spd_inv(r, rinv) != FCC_OK) {
        return FCC_ERR_NOT_POSDEF;
    }
    memset(zkf, 0, sizeof *zkf);
    zkf->x[0] = x0[0];
    zkf->x[1] = x0[1];
    /* Columns of the row-major p0: (p11, p21) and (p12, p22). */
    zkf->gen[0] = p0[0];
    zkf->gen[1] = p0[2];
    zkf->gen[2] = p0[1];
    zkf->gen[3] = p0[3];
    zkf->p = 2u;
    fcc_zono_norms(zkf->gen, zkf->p, zkf->norm2);
    fcc_zono_hull(zkf->gen, zkf->p, zkf->hull);
    fcc_real_t m[4];
    fcc_zono_covariation(zkf->gen, zkf->p, m);
    zkf->cov[0] = m[0];
    zkf->cov[1] = m[1];
    zkf->cov[2] = m[3];
    memcpy(zkf->e, e, sizeof zkf->e);
    memcpy(zkf->f, f, sizeof zkf->f);
    memcpy(zkf->r, r, sizeof zkf->r);
    zkf->f_hull[0] = FCC_FABS(f[0]) + FCC_FABS(f[1]);
    zkf->f_hull[1] = FCC_FABS(f[2]) + FCC_FABS(f[3]);
    return FCC_OK;
}

/* Adds |columns [from, to)| of P to the box radii. */
static void box_run(const fcc_real_t *gen, uint32_t from, uint32_t to, fcc_real_t box[2])
{
    for (uint32_t j = from; j < to; ++j) {
        box[0] += FCC_FABS(gen[2u * j]);
        box[1] += FCC_FABS(gen[2u * j + 1u]);
    }
}

/* Adds sign * (col col^T) of column j to the covariation sums c. */
static void cov_add(const fcc_real_t *gen, uint32_t j, fcc_real_t sign, fcc_real_t c[3])
{
    const fcc_real_t a = gen[2u * j];
    const fcc_real_t b = gen[2u * j + 1u];
    c[0] += sign * a * a;
    c[1] += sign * a * b;
    c[2] += sign * b * b;
}

/* M = P_bar P_bar^T and the box radii, without forming P_bar (see the
 * cost note in fcc_zkf.h).  Needs fcc_zono_select's result when reducing. */
static void reduced_covariation(const fcc_zkf_t *zkf, bool reducing, uint16_t q, fcc_real_t m[4],
                                fcc_real_t box[2])
{
    const fcc_zono_work_t *wk = &zkf->work;
    fcc_real_t c[3] = {zkf->cov[0], zkf->cov[1], zkf->cov[2]};
    box[0] = FCC_R(0.0);
    box[1] = FCC_R(0.0);
    if (reducing && q == FCC_ZONO_MIN_ORDER) {
        /* Everything boxed: P_bar = diag(hull). */
        box[0] = zkf->hull[0];
        box[1] = zkf->hull[1];
        c[0] = c[1] = c[2] = FCC_R(0.0);
    } else if (reducing && wk->list_is_boxed) {
        /* A few short columns leave the covariation for the box. */
        for (uint16_t i = 0; i < wk->n_list; ++i) {
            cov_add(zkf->gen, wk->list[i], FCC_R(-1.0), c);
            box_run(zkf->gen, wk->list[i], wk->list[i] + 1u, box);
        }
    } else if (reducing) {
        /* Few kept: their covariation, and the box of the runs between them. */
        c[0] = c[1] = c[2] = FCC_R(0.0);
        uint32_t next = 0u;
        for (uint16_t i = 0; i < wk->n_list; ++i) {
            cov_add(zkf->gen, wk->list[i], FCC_R(1.0), c);
            box_run(zkf->gen, next, wk->list[i], box);
            next = wk->list[i] + 1u;
        }
        box_run(zkf->gen, next, zkf->p, box);
    } else {
        /* not reducing: every column kept, no box */
    }
    m[0] = c[0] + box[0] * box[0];
    m[1] = c[1];
    m[2] = c[1];
    m[3] = c[2] + box[1] * box[1];
}

/* Appends column (a, b) at slot w with its squared norm and sums. */
static void put_column(fcc_zkf_t *zkf, uint16_t w, fcc_real_t a, fcc_real_t b, fcc_real_t s[5])
{
    const fcc_real_t aa = a * a;
    const fcc_real_t bb = b * b;
    zkf->gen[2u * w] = a;
    zkf->gen[2u * w + 1u] = b;
    zkf->norm2[w] = aa + bb;
    s[0] += FCC_FABS(a);
    s[1] += FCC_FABS(b);
    s[2] += aa;
    s[3] += a * b;
    s[4] += bb;
}

/* Sums a commit pass accumulates: hull radii and covariation. */
typedef struct {
    fcc_real_t h0, h1, c00, c01, c11;
} zkf_sums_t;

/* Writes T times columns [from, to) of P from slot *w on (w <= from, so in
 * place is safe), with their squared norms, hull and covariation.  The hot
 * loop of the filter: a run has no per-column test, the sums live in
 * registers. */
static void transform_run(fcc_zkf_t *zkf, const fcc_real_t t[4], uint32_t from, uint32_t to,
                          uint32_t *w, zkf_sums_t *acc)
{
    const fcc_real_t *src = zkf->gen + 2u * from;
    const fcc_real_t *const end = zkf->gen + 2u * to;
    fcc_real_t *dst = zkf->gen + 2u * *w;
    fcc_real_t *restrict nrm = zkf->norm2 + *w;
    const fcc_real_t t0 = t[0], t1 = t[1], t2 = t[2], t3 = t[3];
    zkf_sums_t s = *acc;
    for (; src != end; src += 2, dst += 2) {
        const fcc_real_t a = src[0];
        const fcc_real_t b = src[1];
        const fcc_real_t na = t0 * a + t1 * b;
        const fcc_real_t nb = t2 * a + t3 * b;
        const fcc_real_t aa = na * na;
        const fcc_real_t bb = nb * nb;
        dst[0] = na;
        dst[1] = nb;
        *nrm++ = aa + bb;
        s.h0 += FCC_FABS(na);
        s.h1 += FCC_FABS(nb);
        s.c00 += aa;
        s.c01 += na * nb;
        s.c11 += bb;
    }
    *acc = s;
    *w += to - from;
}

/* T P_bar for the kept columns, compacted from slot 0; returns the count. */
static uint32_t transform_kept(fcc_zkf_t *zkf, bool reducing, const fcc_real_t t[4],
                               zkf_sums_t *acc)
{
    const fcc_zono_work_t *wk = &zkf->work;
    uint32_t w = 0u;
    if (!reducing) {
        transform_run(zkf, t, 0u, zkf->p, &w, acc);
        return w;
    }
    uint32_t next = 0u;
    for (uint16_t i = 0; i < wk->n_list; ++i) {
        const uint32_t j = wk->list[i];
        if (wk->list_is_boxed) {
            transform_run(zkf, t, next, j, &w, acc); /* the run before a boxed column */
        } else {
            transform_run(zkf, t, j, j + 1u, &w, acc); /* a kept column */
        }
        next = j + 1u;
    }
    if (wk->list_is_boxed) {
        transform_run(zkf, t, next, zkf->p, &w, acc);
    }
    return w;
}

/* Commit pass: P_k+1 = [T P_bar, E, -G F] with T = A - G. */
static void commit_generators(fcc_zkf_t *zkf, bool reducing, uint16_t q, const fcc_real_t t[4],
                              const fcc_real_t box[2], const fcc_real_t g[4], bool updated)
{
    zkf_sums_t acc = {FCC_R(0.0), FCC_R(0.0), FCC_R(0.0), FCC_R(0.0), FCC_R(0.0)};
    uint16_t w = 0u;
    if (!reducing || q > FCC_ZONO_MIN_ORDER) {
        w = (uint16_t)transform_kept(zkf, reducing, t, &acc);
    }
    fcc_real_t s[5] = {acc.h0, acc.h1, acc.c00, acc.c01, acc.c11};
    if (reducing) {
        put_column(zkf, w++, t[0] * box[0], t[2] * box[0], s);
        put_column(zkf, w++, t[1] * box[1], t[3] * box[1], s);
    }
    put_column(zkf, w++, zkf->e[0], zkf->e[2], s);
    put_column(zkf, w++, zkf->e[1], zkf->e[3], s);
    if (updated) {
        fcc_real_t gf[4];
        fcc_sid_m2_mul(g, zkf->f, gf);
        put_column(zkf, w++, -gf[0], -gf[2], s);
        put_column(zkf, w++, -gf[1], -gf[3], s);
    }
    zkf->p = w;
    zkf->hull[0] = s[0];
    zkf->hull[1] = s[1];
    zkf->cov[0] = s[2];
    zkf->cov[1] = s[3];
    zkf->cov[2] = s[4];
}

/* G = A M (M + R)^-1 (eq. 25 with C = I); gp = M (M + R)^-1 when not NULL. */
static fcc_status_t zkf_gain(const fcc_zkf_t *zkf, const fcc_real_t a[4], const fcc_real_t m[4],
                             fcc_real_t g[4], fcc_real_t *gp)
{
    const fcc_real_t s[4] = {m[0] + zkf->r[0], m[1] + zkf->r[1], m[2] + zkf->r[2],
                             m[3] + zkf->r[3]};
    fcc_real_t sinv[4];
    if (fcc_sid_m2_spd_inv(s, sinv) != FCC_OK) {
        return FCC_ERR_NOT_FINITE;
    }
    fcc_real_t am[4];
    fcc_sid_m2_mul(a, m, am);
    fcc_sid_m2_mul(am, sinv, g);
    if (gp != NULL) {
        fcc_sid_m2_mul(m, sinv, gp);
    }
    return FCC_OK;
}

/* Adds the interval hull radii of T times columns [from, to) of P to h. */
static void hull_run(const fcc_real_t *gen, const fcc_real_t t[4], uint32_t from, uint32_t to,
                     fcc_real_t h[2])
{
    for (uint32_t j = from; j < to; ++j) {
        const fcc_real_t a = gen[2u * j];
        const fcc_real_t b = gen[2u * j + 1u];
        h[0] += FCC_FABS(t[0] * a + t[1] * b);
        h[1] += FCC_FABS(t[2] * a + t[3] * b);
    }
}

/* Hull radii of [T P_bar, -G' F] (the posterior set), P_bar = the kept
 * columns of P and the box (the columns commit_generators would transform). */
static void posterior_hull(const fcc_zkf_t *zkf, bool reducing, uint16_t q, const fcc_real_t t[4],
                           const fcc_real_t box[2], const fcc_real_t gp[4], fcc_real_t h[2])
{
    const fcc_zono_work_t *wk = &zkf->work;
    h[0] = FCC_R(0.0);
    h[1] = FCC_R(0.0);
    if (!reducing) {
        hull_run(zkf->gen, t, 0u, zkf->p, h);
    } else if (q > FCC_ZONO_MIN_ORDER) {
        uint32_t next = 0u;
        for (uint16_t i = 0; i < wk->n_list; ++i) {
            const uint32_t j = wk->list[i];
            if (wk->list_is_boxed) {
                hull_run(zkf->gen, t, next, j, h);
            } else {
                hull_run(zkf->gen, t, j, j + 1u, h);
            }
            next = j + 1u;
        }
        if (wk->list_is_boxed) {
            hull_run(zkf->gen, t, next, zkf->p, h);
        }
    } else {
        /* reduced to the minimum order: every column boxed, the box below alone */
    }
    if (reducing) {
        h[0] += FCC_FABS(t[0] * box[0]) + FCC_FABS(t[1] * box[1]);
        h[1] += FCC_FABS(t[2] * box[0]) + FCC_FABS(t[3] * box[1]);
    }
    fcc_real_t gf[4];
    fcc_sid_m2_mul(gp, zkf->f, gf);
    h[0] += FCC_FABS(gf[0]) + FCC_FABS(gf[1]);
    h[1] += FCC_FABS(gf[2]) + FCC_FABS(gf[3]);
}

void fcc_zkf_set_posterior(fcc_zkf_t *zkf, bool on)
{
    if (zkf != NULL) {
        zkf->posterior = on;
    }
}

fcc_status_t fcc_zkf_step(fcc_zkf_t *zkf, const fcc_sid_model_t *model, fcc_real_t de,
                          const fcc_real_t y[2], bool use_measurement, uint16_t q,
                          fcc_zkf_info_t *info)
{
    if (zkf == NULL || model == NULL || (use_measurement && y == NULL)) {
        return FCC_ERR_ARG;
    }
    if (q < FCC_ZONO_MIN_ORDER || q > FCC_ZONO_MAX_ORDER) {
        return FCC_ERR_RANGE;
    }
    if (!fcc_sid_model_is_finite(model) || !FCC_IS_FINITE(de) ||
        (use_measurement && !fcc_sid_all_finite(y, 2))) {
        return FCC_ERR_NOT_FINITE;
    }
    /* Pass 1: which columns the reduction boxes. */
    const bool reducing = zkf->p > q;
    if (reducing && fcc_zono_select(zkf->norm2, zkf->p, q, &zkf->work) != FCC_OK) {
        return FCC_ERR_SIZE;
    }
    fcc_real_t m[4];
    fcc_real_t box[2];
    reduced_covariation(zkf, reducing, q, m, box);

    fcc_real_t g[4] = {FCC_R(0.0), FCC_R(0.0), FCC_R(0.0), FCC_R(0.0)};
    fcc_real_t gp[4] = {FCC_R(0.0), FCC_R(0.0), FCC_R(0.0), FCC_R(0.0)};
    if (use_measurement && zkf_gain(zkf, model->a, m, g, zkf->posterior ? gp : NULL) != FCC_OK) {
        return FCC_ERR_NOT_FINITE;
    }
    const fcc_real_t *a = model->a;
    fcc_real_t x_new[2];
    x_new[0] = a[0] * zkf->x[0] + a[1] * zkf->x[1] + model->b[0] * de + model->c[0];
    x_new[1] = a[2] * zkf->x[0] + a[3] * zkf->x[1] + model->b[1] * de + model->c[1];
    if (use_measurement) {
        const fcc_real_t i0 = y[0] - zkf->x[0];
        const fcc_real_t i1 = y[1] - zkf->x[1];
        x_new[0] += g[0] * i0 + g[1] * i1;
        x_new[1] += g[2] * i0 + g[3] * i1;
    }
    const fcc_real_t t[4] = {a[0] - g[0], a[1] - g[1], a[2] - g[2], a[3] - g[3]};
    /* Every new column is T times an old one (or E, -G F): bounded by the
     * row sums of |T| times the hull radius. */
    const fcc_real_t tn = FCC_FABS(t[0]) + FCC_FABS(t[1]) + FCC_FABS(t[2]) + FCC_FABS(t[3]);
    const fcc_real_t hmax = zkf->hull[0] > zkf->hull[1] ? zkf->hull[0] : zkf->hull[1];
    if (!fcc_sid_all_finite(g, 4) || !fcc_sid_all_finite(x_new, 2) || !FCC_IS_FINITE(tn) ||
        tn * hmax > FCC_SID_MAX_MAGNITUDE || FCC_FABS(x_new[0]) > FCC_SID_MAX_MAGNITUDE ||
        FCC_FABS(x_new[1]) > FCC_SID_MAX_MAGNITUDE) {
        return FCC_ERR_NOT_FINITE;
    }

    if (info != NULL) {
        memcpy(info->gain, g, sizeof info->gain);
        info->gain_norm = use_measurement ? fcc_sid_m2_norm2(g) : FCC_R(0.0);
        info->order = q;
        info->n_generators = reducing ? q : zkf->p;
        info->updated = use_measurement;
        info->post_x[0] = info->post_x[1] = FCC_R(0.0);
        info->post_hull[0] = info->post_hull[1] = FCC_R(0.0);
        info->post_gain_norm = FCC_R(0.0);
        if (zkf->posterior && use_measurement) {
            const fcc_real_t i0 = y[0] - zkf->x[0];
            const fcc_real_t i1 = y[1] - zkf->x[1];
            const fcc_real_t tp[4] = {FCC_R(1.0) - gp[0], -gp[1], -gp[2], FCC_R(1.0) - gp[3]};
            info->post_x[0] = zkf->x[0] + gp[0] * i0 + gp[1] * i1;
            info->post_x[1] = zkf->x[1] + gp[2] * i0 + gp[3] * i1;
            posterior_hull(zkf, reducing, q, tp, box, gp, info->post_hull);
            info->post_gain_norm = fcc_sid_m2_norm2(gp);
        } else if (zkf->posterior) {
            info->post_x[0] = zkf->x[0];
            info->post_x[1] = zkf->x[1];
            info->post_hull[0] = zkf->hull[0];
            info->post_hull[1] = zkf->hull[1];
        } else {
            /* no posterior asked for: info's posterior stays zero */
        }
    }
    commit_generators(zkf, reducing, q, t, box, g, use_measurement);
    zkf->x[0] = x_new[0];
    zkf->x[1] = x_new[1];
    return FCC_OK;
}

void fcc_zkf_output_radius(const fcc_zkf_t *zkf, fcc_real_t radius[2])
{
    radius[0] = zkf->hull[0] + zkf->f_hull[0];
    radius[1] = zkf->hull[1] + zkf->f_hull[1];
}

void fcc_zkf_covariation(const fcc_zkf_t *zkf, fcc_real_t m[4])
{
    fcc_zono_covariation(zkf->gen, zkf->p, m);
}
