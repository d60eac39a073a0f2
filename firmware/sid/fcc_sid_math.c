#include "fcc_sid_math.h"

bool fcc_sid_all_finite(const fcc_real_t *v, size_t n)
{
    for (size_t i = 0; i < n; ++i) {
        if (!FCC_IS_FINITE(v[i])) {
            return false;
        }
    }
    return true;
}

bool fcc_sid_model_is_finite(const fcc_sid_model_t *model)
{
    return fcc_sid_all_finite(model->a, 4) && fcc_sid_all_finite(model->b, 2) &&
           fcc_sid_all_finite(model->c, 2);
}

fcc_real_t fcc_sid_m2_spectral_radius(const fcc_real_t m[4])
{
    const fcc_real_t half_tr = FCC_R(0.5) * (m[0] + m[3]);
    const fcc_real_t half_diff = FCC_R(0.5) * (m[0] - m[3]);
    const fcc_real_t disc = half_diff * half_diff + m[1] * m[2];
    if (disc >= FCC_R(0.0)) {
        /* Two real eigenvalues half_tr +/- sqrt(disc). */
        return FCC_FABS(half_tr) + FCC_SQRT(disc);
    }
    /* Complex pair: |lambda|^2 = det = half_tr^2 - disc > 0. */
    return FCC_SQRT(half_tr * half_tr - disc);
}

fcc_real_t fcc_sid_m2_norm2(const fcc_real_t m[4])
{
    const fcc_real_t s1 = m[0] + m[3];
    const fcc_real_t s2 = m[2] - m[1];
    const fcc_real_t d1 = m[0] - m[3];
    const fcc_real_t d2 = m[1] + m[2];
    return FCC_R(0.5) * (FCC_SQRT(s1 * s1 + s2 * s2) + FCC_SQRT(d1 * d1 + d2 * d2));
}

fcc_status_t fcc_sid_m2_spd_inv(const fcc_real_t s[4], fcc_real_t inv[4])
{
    const fcc_real_t det = s[0] * s[3] - s[1] * s[2];
    if (!(s[0] > FCC_R(0.0)) || !(s[3] > FCC_R(0.0)) || !(det > FCC_EPS * s[0] * s[3])) {
        return FCC_ERR_NOT_POSDEF;
    }
    const fcc_real_t r = FCC_R(1.0) / det;
    inv[0] = s[3] * r;
    inv[1] = -s[1] * r;
    inv[2] = -s[2] * r;
    inv[3] = s[0] * r;
    return FCC_OK;
}

void fcc_sid_m2_mul(const fcc_real_t a[4], const fcc_real_t b[4], fcc_real_t out[4])
{
    out[0] = a[0] * b[0] + a[1] * b[2];
    out[1] = a[0] * b[1] + a[1] * b[3];
    out[2] = a[2] * b[0] + a[3] * b[2];
    out[3] = a[2] * b[1] + a[3] * b[3];
}

void fcc_sid_m2_mul_bt(const fcc_real_t a[4], const fcc_real_t b[4], fcc_real_t out[4])
{
    out[0] = a[0] * b[0] + a[1] * b[1];
    out[1] = a[0] * b[2] + a[1] * b[3];
    out[2] = a[2] * b[0] + a[3] * b[1];
    out[3] = a[2] * b[2] + a[3] * b[3];
}

fcc_status_t fcc_sid_m2_cholesky(const fcc_real_t s[4], fcc_real_t l[4])
{
    if (!fcc_sid_all_finite(s, 4) || !(s[0] > FCC_R(0.0))) {
        return FCC_ERR_NOT_POSDEF;
    }
    const fcc_real_t l11 = FCC_SQRT(s[0]);
    const fcc_real_t l21 = s[2] / l11;
    const fcc_real_t d = s[3] - l21 * l21;
    if (!(d > FCC_EPS * s[3])) {
        return FCC_ERR_NOT_POSDEF;
    }
    l[0] = l11;
    l[1] = FCC_R(0.0);
    l[2] = l21;
    l[3] = FCC_SQRT(d);
    return FCC_OK;
}
