/*
 * fcc_azkf.h -- adaptive-order zonotopic Kalman filter (Gim et al. 2022,
 * section 2.2.2 and Algorithm 1, with the orders of the erratum below).
 *
 * Every step the fault detector (fcc_fault.h) judges y_k against the
 * predicted output zonotope of the ZKF, then:
 *   policy ORDER: no fault -> q = q_normal (default 2: the set is boxed,
 *                 the gain is high, the filter trusts the sensor);
 *                 fault    -> q = q_fault (default 1000: the tight set, a
 *                 low, KF-like gain, the spike barely moves the estimate).
 *   policy SKIP:  q = q_normal always, and no measurement update while a
 *                 fault is flagged (the paper's footnote 2).
 * The printed Algorithm 1 has the two orders swapped; the paper's text,
 * Fig. 9 and the mathematics agree with the assignment above (a small q
 * boxes the set and raises the gain: firmware/sid/README.md, "Erratum").
 */
#ifndef FCC_AZKF_H
#define FCC_AZKF_H

#include <stdbool.h>
#include <stdint.h>

#include "fcc_fault.h"
#include "fcc_types.h"
#include "fcc_zkf.h"

typedef enum {
    FCC_AZKF_POLICY_ORDER = 0,
    FCC_AZKF_POLICY_SKIP = 1
} fcc_azkf_policy_t;

#define FCC_AZKF_DEFAULT_Q_NORMAL 2u
#define FCC_AZKF_DEFAULT_Q_FAULT 1000u

typedef struct {
    uint16_t q_normal; /* order without a fault, 2..FCC_ZONO_MAX_ORDER */
    uint16_t q_fault;  /* order while a fault is flagged (policy ORDER) */
    fcc_azkf_policy_t policy;
    fcc_fdet_config_t det;
} fcc_azkf_config_t;

typedef struct {
    fcc_zkf_t zkf;
    fcc_fdet_t det;
    fcc_azkf_config_t cfg;
} fcc_azkf_t;

typedef struct {
    fcc_zkf_info_t zkf; /* gain, order, generators of the step */
    bool fault;         /* the detector's flag for y_k */
} fcc_azkf_info_t;

/* Defaults: q_normal 2, q_fault 1000 (clamped to FCC_ZONO_MAX_ORDER),
 * policy ORDER, detector defaults. */
void fcc_azkf_config_default(fcc_azkf_config_t *cfg);

/* FCC_ERR_ARG on NULL or an unknown policy; FCC_ERR_RANGE on an order
 * outside 2..FCC_ZONO_MAX_ORDER; detector errors as fcc_fdet_config_check. */
fcc_status_t fcc_azkf_config_check(const fcc_azkf_config_t *cfg);

/* Initial set and noise as fcc_zkf_init. */
fcc_status_t fcc_azkf_init(fcc_azkf_t *azkf, const fcc_azkf_config_t *cfg, const fcc_real_t x0[2],
                           const fcc_real_t p0[4], const fcc_real_t e[4], const fcc_real_t f[4]);

/* One step: detect (y_k against <C x_k, [C P_k, F]>), choose the order or
 * skip the update, run the ZKF step.  have_measurement false: no detection
 * (the flag keeps its value), prediction only.  armed false: no detection
 * and no fault (the bundle disarms the detector while the model is still the
 * prior: consistency with an unidentified model means nothing, and a fault
 * then would freeze the very learning that fixes the model).  Errors as
 * fcc_zkf_step; a refused ZKF step leaves the filter and the detector
 * unchanged. */
fcc_status_t fcc_azkf_step(fcc_azkf_t *azkf, const fcc_sid_model_t *model, fcc_real_t de,
                           const fcc_real_t y[2], bool have_measurement, bool armed,
                           bool oracle_fault, fcc_azkf_info_t *info);

#endif /* FCC_AZKF_H */
