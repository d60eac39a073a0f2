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
    memcpy(zkf->e, e, sizeof zkf->e);
    memcpy(zkf->f, f, sizeof zkf->f);
    memcpy(zkf->r, r, sizeof zkf->r);
    zkf->f_hull[0] = FCC_FABS(f[0]) + FCC_FABS(f[1]);
    zkf->f_hull[1] = FCC_FABS(f[2]) + FCC_FABS(f[3]);
    return FCC_OK;
}

/* Pass 2: M = P_bar P_bar^T without forming P_bar: kept columns add their
 * outer product, boxed ones their absolute values to the box, whose two
 * diagonal columns are added last. */
static void reduced_covariation(const fcc_zkf_t *zkf, bool reducing, fcc_real_t m[4],
                                fcc_real_t box[2])
{
    fcc_real_t m00 = FCC_R(0.0);
    fcc_real_t m01 = FCC_R(0.0);
    fcc_real_t m11 = FCC_R(0.0);
    fcc_real_t b0 = FCC_R(0.0);
    fcc_real_t b1 = FCC_R(0.0);
    for (uint16_t j = 0; j < zkf->p; ++j) {
        const fcc_real_t a = zkf->gen[2u * j];
        const fcc_real_t b = zkf->gen[2u * j + 1u];
        if (reducing && zkf->work.boxed[j] != 0u) {
            b0 += FCC_FABS(a);
            b1 += FCC_FABS(b);
        } else {
            m00 += a * a;
            m01 += a * b;
            m11 += b * b;
        }
    }
    m[0] = m00 + b0 * b0;
    m[1] = m01;
    m[2] = m01;
    m[3] = m11 + b1 * b1;
    box[0] = b0;
    box[1] = b1;
}

/* Appends column (a, b) at slot w, with its squared norm and hull share. */
static void put_column(fcc_zkf_t *zkf, uint16_t w, fcc_real_t a, fcc_real_t b, fcc_real_t hull[2])
{
    zkf->gen[2u * w] = a;
    zkf->gen[2u * w + 1u] = b;
    zkf->norm2[w] = a * a + b * b;
    hull[0] += FCC_FABS(a);
    hull[1] += FCC_FABS(b);
}

/* Pass 3 (commit): P_k+1 = [T P_bar, E, -G F] with T = A - G. */
static void commit_generators(fcc_zkf_t *zkf, bool reducing, const fcc_real_t t[4],
                              const fcc_real_t box[2], const fcc_real_t g[4], bool updated)
{
    fcc_real_t hull[2] = {FCC_R(0.0), FCC_R(0.0)};
    uint16_t w = 0u;
    for (uint16_t j = 0; j < zkf->p; ++j) {
        if (reducing && zkf->work.boxed[j] != 0u) {
            continue;
        }
        const fcc_real_t a = zkf->gen[2u * j];
        const fcc_real_t b = zkf->gen[2u * j + 1u];
        put_column(zkf, w++, t[0] * a + t[1] * b, t[2] * a + t[3] * b, hull);
    }
    if (reducing) {
        put_column(zkf, w++, t[0] * box[0], t[2] * box[0], hull);
        put_column(zkf, w++, t[1] * box[1], t[3] * box[1], hull);
    }
    put_column(zkf, w++, zkf->e[0], zkf->e[2], hull);
    put_column(zkf, w++, zkf->e[1], zkf->e[3], hull);
    if (updated) {
        fcc_real_t gf[4];
        fcc_sid_m2_mul(g, zkf->f, gf);
        put_column(zkf, w++, -gf[0], -gf[2], hull);
        put_column(zkf, w++, -gf[1], -gf[3], hull);
    }
    zkf->p = w;
    zkf->hull[0] = hull[0];
    zkf->hull[1] = hull[1];
}

/* G = A M (M + R)^-1 (eq. 25 with C = I). */
static fcc_status_t zkf_gain(const fcc_zkf_t *zkf, const fcc_real_t a[4], const fcc_real_t m[4],
                             fcc_real_t g[4])
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
    return FCC_OK;
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
    reduced_covariation(zkf, reducing, m, box);

    fcc_real_t g[4] = {FCC_R(0.0), FCC_R(0.0), FCC_R(0.0), FCC_R(0.0)};
    if (use_measurement && zkf_gain(zkf, model->a, m, g) != FCC_OK) {
        return FCC_ERR_NOT_FINITE;
    }
    const fcc_real_t *a = model->a;
    fcc_real_t x_new[2];
    x_new[0] = a[0] * zkf->x[0] + a[1] * zkf->x[1] + model->b[0] * de;
    x_new[1] = a[2] * zkf->x[0] + a[3] * zkf->x[1] + model->b[1] * de;
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
    }
    commit_generators(zkf, reducing, t, box, g, use_measurement);
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
