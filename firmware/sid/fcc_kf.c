#include "fcc_kf.h"

#include <string.h>

fcc_status_t fcc_kf_init(fcc_kf_t *kf, const fcc_real_t x0[2], const fcc_real_t p0[4],
                         const fcc_real_t e[4], const fcc_real_t f[4])
{
    if (kf == NULL || x0 == NULL || p0 == NULL || e == NULL || f == NULL) {
        return FCC_ERR_ARG;
    }
    if (!fcc_sid_all_finite(x0, 2) || !fcc_sid_all_finite(p0, 4) || !fcc_sid_all_finite(e, 4) ||
        !fcc_sid_all_finite(f, 4)) {
        return FCC_ERR_ARG;
    }
    fcc_real_t r[4];
    fcc_real_t tmp[4];
    fcc_sid_m2_mul_bt(f, f, r);
    if (p0[1] != p0[2] || fcc_sid_m2_spd_inv(p0, tmp) != FCC_OK ||
        fcc_sid_m2_spd_inv(r, tmp) != FCC_OK) {
        return FCC_ERR_NOT_POSDEF;
    }
    memset(kf, 0, sizeof *kf);
    memcpy(kf->x, x0, sizeof kf->x);
    memcpy(kf->p, p0, sizeof kf->p);
    fcc_sid_m2_mul_bt(e, e, kf->q);
    memcpy(kf->r, r, sizeof kf->r);
    kf->started = false;
    return FCC_OK;
}

void fcc_kf_predict(const fcc_real_t q[4], const fcc_sid_model_t *model, fcc_real_t de,
                    fcc_real_t x[2], fcc_real_t p[4])
{
    const fcc_real_t *a = model->a;
    const fcc_real_t x0 = a[0] * x[0] + a[1] * x[1] + model->b[0] * de + model->c[0];
    const fcc_real_t x1 = a[2] * x[0] + a[3] * x[1] + model->b[1] * de + model->c[1];
    fcc_real_t ap[4];
    fcc_real_t apat[4];
    fcc_sid_m2_mul(a, p, ap);
    fcc_sid_m2_mul_bt(ap, a, apat);
    x[0] = x0;
    x[1] = x1;
    p[0] = apat[0] + q[0];
    p[1] = apat[1] + q[1];
    p[2] = apat[2] + q[2];
    p[3] = apat[3] + q[3];
}

fcc_status_t fcc_kf_update(const fcc_real_t r[4], const fcc_real_t y[2], fcc_real_t x[2],
                           fcc_real_t p[4], fcc_real_t k[4])
{
    const fcc_real_t s[4] = {p[0] + r[0], p[1] + r[1], p[2] + r[2], p[3] + r[3]};
    fcc_real_t sinv[4];
    if (fcc_sid_m2_spd_inv(s, sinv) != FCC_OK) {
        return FCC_ERR_NOT_FINITE;
    }
    fcc_sid_m2_mul(p, sinv, k); /* (12), C = I */
    const fcc_real_t i0 = y[0] - x[0];
    const fcc_real_t i1 = y[1] - x[1];
    x[0] += k[0] * i0 + k[1] * i1; /* (13) */
    x[1] += k[2] * i0 + k[3] * i1;
    const fcc_real_t ikc[4] = {FCC_R(1.0) - k[0], -k[1], -k[2], FCC_R(1.0) - k[3]};
    fcc_real_t pn[4];
    fcc_sid_m2_mul(ikc, p, pn); /* (14) */
    const fcc_real_t off = FCC_R(0.5) * (pn[1] + pn[2]);
    p[0] = pn[0];
    p[1] = off;
    p[2] = off;
    p[3] = pn[3];
    return FCC_OK;
}

fcc_status_t fcc_kf_step(fcc_kf_t *kf, const fcc_sid_model_t *model, fcc_real_t de_prev,
                         const fcc_real_t y[2], bool use_measurement, fcc_kf_info_t *info)
{
    if (kf == NULL || model == NULL || (use_measurement && y == NULL)) {
        return FCC_ERR_ARG;
    }
    const bool predict = kf->started;
    if ((predict && (!fcc_sid_model_is_finite(model) || !FCC_IS_FINITE(de_prev))) ||
        (use_measurement && !fcc_sid_all_finite(y, 2))) {
        return FCC_ERR_NOT_FINITE;
    }
    fcc_real_t x[2] = {kf->x[0], kf->x[1]};
    fcc_real_t p[4] = {kf->p[0], kf->p[1], kf->p[2], kf->p[3]};
    fcc_real_t k[4] = {FCC_R(0.0), FCC_R(0.0), FCC_R(0.0), FCC_R(0.0)};
    if (predict) {
        fcc_kf_predict(kf->q, model, de_prev, x, p);
    }
    const fcc_real_t prior_x[2] = {x[0], x[1]};
    const fcc_real_t prior_p[4] = {p[0], p[1], p[2], p[3]};
    if (use_measurement && fcc_kf_update(kf->r, y, x, p, k) != FCC_OK) {
        return FCC_ERR_NOT_FINITE;
    }
    if (!fcc_sid_all_finite(x, 2) || !fcc_sid_all_finite(p, 4) || !fcc_sid_all_finite(k, 4) ||
        FCC_FABS(x[0]) > FCC_SID_MAX_MAGNITUDE || FCC_FABS(x[1]) > FCC_SID_MAX_MAGNITUDE ||
        p[0] > FCC_SID_MAX_MAGNITUDE || p[3] > FCC_SID_MAX_MAGNITUDE) {
        return FCC_ERR_NOT_FINITE;
    }
    memcpy(kf->x, x, sizeof kf->x);
    memcpy(kf->p, p, sizeof kf->p);
    kf->started = true;
    if (info != NULL) {
        memcpy(info->gain, k, sizeof info->gain);
        info->gain_norm = use_measurement ? fcc_sid_m2_norm2(k) : FCC_R(0.0);
        info->predicted = predict;
        info->updated = use_measurement;
        memcpy(info->prior_x, prior_x, sizeof info->prior_x);
        memcpy(info->prior_p, prior_p, sizeof info->prior_p);
    }
    return FCC_OK;
}
