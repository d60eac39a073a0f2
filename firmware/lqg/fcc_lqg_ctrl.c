/* fcc_lqg_ctrl.c -- the per-period side of the autopilot: D/A and estimator. */
#include "fcc_lqg.h"

#include "fcc_types.h" /* FCC_TRY */

#define NX FCC_LQG_NX
#define NY FCC_LQG_NY

/* ---- D/A converter ---------------------------------------------------------- */

fcc_status_t fcc_lqg_dac_init(fcc_lqg_dac_t *dac, uint8_t bits)
{
    if (dac == NULL) {
        return FCC_ERR_ARG;
    }
    if (bits < FCC_LQG_BITS_MIN || bits > FCC_LQG_BITS_MAX) {
        return FCC_ERR_RANGE;
    }
    const uint32_t half_range = (uint32_t)1u << ((uint32_t)bits - 1u); /* bits <= 16 */
    const int32_t half = (int32_t)half_range;
    dac->bits = bits;
    /* Scaling by 2^-N is exact: the LSB carries only the rounding of 0.8 itself. */
    dac->lsb = FCC_LDEXP(FCC_R(2.0) * FCC_LQG_U_MAX, -(int)bits);
    dac->code_min = -half;
    dac->code_max = half - 1;
    return FCC_OK;
}

static bool dac_ok(const fcc_lqg_dac_t *dac)
{
    return dac != NULL && dac->bits >= FCC_LQG_BITS_MIN && dac->bits <= FCC_LQG_BITS_MAX;
}

fcc_status_t fcc_lqg_dac_convert(const fcc_lqg_dac_t *dac, fcc_real_t u, int32_t *code,
                                 fcc_real_t *u_applied)
{
    if (!dac_ok(dac) || code == NULL || u_applied == NULL) {
        return FCC_ERR_ARG;
    }
    if (!FCC_IS_FINITE(u)) {
        *code = 0;
        *u_applied = FCC_R(0.0);
        return FCC_ERR_NOT_FINITE;
    }
    /* Clamp in the real domain first: the int conversion of a huge value is undefined. */
#ifdef FCC_PLANTED_BUG
    /* A deliberate defect for `hil verify`'s own test (CMake FCC_PLANTED_BUG, never in a
     * release): the D/A truncates towards minus infinity instead of rounding. */
    const fcc_real_t q = FCC_ROUND(u / dac->lsb - FCC_R(0.5));
#else
    const fcc_real_t q = FCC_ROUND(u / dac->lsb);
#endif
    int32_t c;
    if (q >= (fcc_real_t)dac->code_max) {
        c = dac->code_max;
    } else if (q <= (fcc_real_t)dac->code_min) {
        c = dac->code_min;
    } else {
        c = (int32_t)q;
    }
    *code = c;
    *u_applied = (fcc_real_t)c * dac->lsb;
    return FCC_OK;
}

fcc_status_t fcc_lqg_dac_value(const fcc_lqg_dac_t *dac, int32_t code, fcc_real_t *u_applied)
{
    if (!dac_ok(dac) || u_applied == NULL) {
        return FCC_ERR_ARG;
    }
    const int32_t c = (code > dac->code_max) ? dac->code_max
                                             : ((code < dac->code_min) ? dac->code_min : code);
    *u_applied = (fcc_real_t)c * dac->lsb;
    return FCC_OK;
}

/* ---- controller --------------------------------------------------------------- */

static bool finite_vec(const fcc_real_t *v, unsigned n)
{
    for (unsigned i = 0; i < n; ++i) {
        if (!FCC_IS_FINITE(v[i])) {
            return false;
        }
    }
    return true;
}

fcc_status_t fcc_lqg_ctrl_reset(fcc_lqg_ctrl_t *c, const fcc_real_t x0[FCC_LQG_NX])
{
    if (c == NULL) {
        return FCC_ERR_ARG;
    }
    if (x0 != NULL && !finite_vec(x0, NX)) {
        return FCC_ERR_NOT_FINITE;
    }
    for (unsigned i = 0; i < NX; ++i) {
        c->x_pred[i] = (x0 != NULL) ? x0[i] : FCC_R(0.0);
    }
    c->u_prev = FCC_R(0.0);
    return FCC_OK;
}

fcc_status_t fcc_lqg_ctrl_init(fcc_lqg_ctrl_t *c, const fcc_lqg_design_t *d, uint8_t bits,
                               const fcc_real_t x0[FCC_LQG_NX])
{
    if (c == NULL || d == NULL) {
        return FCC_ERR_ARG;
    }
    if (!finite_vec(d->phi, NX * NX) || !finite_vec(d->gamma, NX) || !finite_vec(d->k, NX) ||
        !finite_vec(d->l, NX * NY) || !finite_vec(d->h, NY * NX) ||
        !finite_vec(d->gamma1, NX) || !FCC_IS_FINITE(d->k_u)) {
        return FCC_ERR_NOT_FINITE;
    }
    if (x0 != NULL && !finite_vec(x0, NX)) {
        return FCC_ERR_NOT_FINITE;
    }
    fcc_lqg_dac_t dac;
    FCC_TRY(fcc_lqg_dac_init(&dac, bits));
    for (unsigned i = 0; i < NX * NX; ++i) {
        c->phi[i] = d->phi[i];
    }
    for (unsigned i = 0; i < NX; ++i) {
        c->gamma[i] = d->gamma[i];
        c->gamma1[i] = d->gamma1[i];
        c->k[i] = d->k[i];
    }
    c->k_u = d->k_u;
    for (unsigned i = 0; i < NX * NY; ++i) {
        c->l[i] = d->l[i];
        c->h[i] = d->h[i];
    }
    c->dac = dac;
    c->updates = 0U;
    c->predictions = 0U;
    return fcc_lqg_ctrl_reset(c, x0);
}

/* Command from x_hat, D/A, and the next prediction; commits only if finite. */
static fcc_status_t command_and_propagate(fcc_lqg_ctrl_t *c, const fcc_real_t x_hat[NX],
                                          bool measured, fcc_lqg_output_t *out)
{
    fcc_lqg_output_t o;
    o.u_cmd = -c->k_u * c->u_prev;
    for (unsigned i = 0; i < NX; ++i) {
        o.x_hat[i] = x_hat[i];
        o.u_cmd -= c->k[i] * x_hat[i];
    }
    o.saturated = FCC_FABS(o.u_cmd) > FCC_LQG_U_MAX;
    o.u_sat = o.saturated ? FCC_COPYSIGN(FCC_LQG_U_MAX, o.u_cmd) : o.u_cmd;
    o.measured = measured;
    FCC_TRY(fcc_lqg_dac_convert(&c->dac, o.u_sat, &o.code, &o.u_applied));
    fcc_real_t next[NX];
    for (unsigned i = 0; i < NX; ++i) {
        next[i] = c->gamma[i] * o.u_applied + c->gamma1[i] * c->u_prev;
        for (unsigned j = 0; j < NX; ++j) {
            next[i] += c->phi[i * NX + j] * x_hat[j];
        }
    }
    if (!finite_vec(next, NX)) {
        return FCC_ERR_NOT_FINITE;
    }
    for (unsigned i = 0; i < NX; ++i) {
        c->x_pred[i] = next[i];
    }
    c->u_prev = o.u_applied;
    if (measured) {
        ++c->updates;
    } else {
        ++c->predictions;
    }
    *out = o;
    return FCC_OK;
}

fcc_status_t fcc_lqg_ctrl_step(fcc_lqg_ctrl_t *c, const fcc_real_t y[FCC_LQG_NY],
                               fcc_lqg_output_t *out)
{
    if (c == NULL || y == NULL || out == NULL) {
        return FCC_ERR_ARG;
    }
    if (!finite_vec(y, NY)) {
        return FCC_ERR_NOT_FINITE;
    }
    fcc_real_t innov[NY];
    for (unsigned i = 0; i < NY; ++i) {
        innov[i] = y[i];
        for (unsigned j = 0; j < NX; ++j) {
            innov[i] -= c->h[i * NX + j] * c->x_pred[j];
        }
    }
    fcc_real_t x_hat[NX];
    for (unsigned i = 0; i < NX; ++i) {
        x_hat[i] = c->x_pred[i];
        for (unsigned j = 0; j < NY; ++j) {
            x_hat[i] += c->l[i * NY + j] * innov[j];
        }
    }
    if (!finite_vec(x_hat, NX)) {
        return FCC_ERR_NOT_FINITE; /* a finite but absurd y overflowed: keep the state */
    }
    return command_and_propagate(c, x_hat, true, out);
}

fcc_status_t fcc_lqg_ctrl_predict(fcc_lqg_ctrl_t *c, fcc_lqg_output_t *out)
{
    if (c == NULL || out == NULL) {
        return FCC_ERR_ARG;
    }
    fcc_real_t x_hat[NX];
    for (unsigned i = 0; i < NX; ++i) {
        x_hat[i] = c->x_pred[i];
    }
    return command_and_propagate(c, x_hat, false, out);
}
