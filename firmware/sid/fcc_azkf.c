#include "fcc_azkf.h"

#include <string.h>

void fcc_azkf_config_default(fcc_azkf_config_t *cfg)
{
    if (cfg == NULL) {
        return;
    }
    cfg->q_normal = FCC_AZKF_DEFAULT_Q_NORMAL;
    cfg->q_fault = FCC_AZKF_DEFAULT_Q_FAULT < FCC_ZONO_MAX_ORDER ? FCC_AZKF_DEFAULT_Q_FAULT
                                                                 : FCC_ZONO_MAX_ORDER;
    cfg->policy = FCC_AZKF_POLICY_ORDER;
    fcc_fdet_config_default(&cfg->det);
}

fcc_status_t fcc_azkf_config_check(const fcc_azkf_config_t *cfg)
{
    if (cfg == NULL) {
        return FCC_ERR_ARG;
    }
    if (cfg->policy != FCC_AZKF_POLICY_ORDER && cfg->policy != FCC_AZKF_POLICY_SKIP) {
        return FCC_ERR_ARG;
    }
    if (cfg->q_normal < FCC_ZONO_MIN_ORDER || cfg->q_normal > FCC_ZONO_MAX_ORDER ||
        cfg->q_fault < FCC_ZONO_MIN_ORDER || cfg->q_fault > FCC_ZONO_MAX_ORDER) {
        return FCC_ERR_RANGE;
    }
    return fcc_fdet_config_check(&cfg->det);
}

fcc_status_t fcc_azkf_init(fcc_azkf_t *azkf, const fcc_azkf_config_t *cfg, const fcc_real_t x0[2],
                           const fcc_real_t p0[4], const fcc_real_t e[4], const fcc_real_t f[4])
{
    if (azkf == NULL) {
        return FCC_ERR_ARG;
    }
    fcc_status_t st = fcc_azkf_config_check(cfg);
    if (st != FCC_OK) {
        return st;
    }
    st = fcc_zkf_init(&azkf->zkf, x0, p0, e, f);
    if (st != FCC_OK) {
        return st;
    }
    azkf->cfg = *cfg;
    return fcc_fdet_init(&azkf->det, &cfg->det);
}

fcc_status_t fcc_azkf_step(fcc_azkf_t *azkf, const fcc_sid_model_t *model, fcc_real_t de,
                           const fcc_real_t y[2], bool have_measurement, bool armed,
                           bool oracle_fault, fcc_azkf_info_t *info)
{
    if (azkf == NULL || model == NULL || (have_measurement && y == NULL)) {
        return FCC_ERR_ARG;
    }
    /* The detector is stepped on a copy: committed only with the ZKF step. */
    fcc_fdet_t det = azkf->det;
    if (!armed) {
        det.fault = false;
    }
    bool fault = det.fault;
    if (have_measurement && armed) {
        const fcc_real_t innov[2] = {y[0] - azkf->zkf.x[0], y[1] - azkf->zkf.x[1]};
        fcc_real_t radius[2];
        fcc_zkf_output_radius(&azkf->zkf, radius);
        const fcc_status_t st = fcc_fdet_step(&det, innov, radius, oracle_fault, &fault);
        if (st != FCC_OK) {
            return st;
        }
    }
    const bool skip = fault && azkf->cfg.policy == FCC_AZKF_POLICY_SKIP;
    const uint16_t q =
        (fault && azkf->cfg.policy == FCC_AZKF_POLICY_ORDER) ? azkf->cfg.q_fault : azkf->cfg.q_normal;
    fcc_zkf_info_t zinfo;
    const fcc_status_t st =
        fcc_zkf_step(&azkf->zkf, model, de, y, have_measurement && !skip, q, &zinfo);
    if (st != FCC_OK) {
        return st;
    }
    azkf->det = det;
    if (info != NULL) {
        info->zkf = zinfo;
        info->fault = fault;
    }
    return FCC_OK;
}
