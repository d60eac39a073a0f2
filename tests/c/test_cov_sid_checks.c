/*
 * The identification's argument and configuration checks (firmware/sid:
 * fcc_kf.c, fcc_zkf.c, fcc_azkf.c, fcc_mls.c, fcc_sid.c), each refusal
 * caused by one argument or one field alone, the others valid: every missing
 * pointer, every non-finite array, every limit just outside its range (and
 * the accepted values at its edges).  The filters' numbers are tested in
 * test_sid_*.c.
 */
#include "fcc_test.h"

#include <math.h>
#include <string.h>

#include "fcc_sid.h"

static const fcc_real_t k_x0[2] = {FCC_R(0.1), FCC_R(0.0)};
static const fcc_real_t k_p0[4] = {FCC_R(0.01), FCC_R(0.0), FCC_R(0.0), FCC_R(0.01)};
static const fcc_real_t k_e[4] = {FCC_R(0.001), FCC_R(0.0), FCC_R(0.0), FCC_R(0.001)};
static const fcc_real_t k_f[4] = {FCC_R(0.004), FCC_R(0.0), FCC_R(0.0), FCC_R(0.004)};

static fcc_kf_t g_kf;
static fcc_zkf_t g_zkf;
static fcc_azkf_t g_azkf;
static fcc_mls_t g_mls;
static fcc_sid_t g_sid;

typedef fcc_status_t (*filter_init_t)(const fcc_real_t *x0, const fcc_real_t *p0, const fcc_real_t *e,
                                      const fcc_real_t *f);

static fcc_status_t kf_init(const fcc_real_t *x0, const fcc_real_t *p0, const fcc_real_t *e,
                            const fcc_real_t *f)
{
    return fcc_kf_init(&g_kf, x0, p0, e, f);
}

static fcc_status_t zkf_init(const fcc_real_t *x0, const fcc_real_t *p0, const fcc_real_t *e,
                             const fcc_real_t *f)
{
    return fcc_zkf_init(&g_zkf, x0, p0, e, f);
}

static fcc_status_t azkf_init(const fcc_real_t *x0, const fcc_real_t *p0, const fcc_real_t *e,
                              const fcc_real_t *f)
{
    fcc_azkf_config_t cfg;
    fcc_azkf_config_default(&cfg);
    return fcc_azkf_init(&g_azkf, &cfg, x0, p0, e, f);
}

/* Each of the four arrays missing, then with a NaN, the others valid: FCC_ERR_ARG. */
static void check_filter_init(filter_init_t init)
{
    const fcc_real_t *good[4] = {k_x0, k_p0, k_e, k_f};
    fcc_real_t bad[4][4];
    for (int i = 0; i < 4; ++i) {
        const fcc_real_t *args[4] = {good[0], good[1], good[2], good[3]};
        args[i] = NULL;
        assert_int_equal(init(args[0], args[1], args[2], args[3]), FCC_ERR_ARG);
        memcpy(bad[i], good[i], (i == 0 ? 2 : 4) * sizeof(fcc_real_t));
        bad[i][i == 0 ? 1 : 3] = (fcc_real_t)NAN;
        args[i] = bad[i];
        assert_int_equal(init(args[0], args[1], args[2], args[3]), FCC_ERR_ARG);
    }
    fcc_assert_ok(init(k_x0, k_p0, k_e, k_f));
}

static void filter_inits_refuse_each_argument(void **state)
{
    (void)state;
    assert_int_equal(fcc_kf_init(NULL, k_x0, k_p0, k_e, k_f), FCC_ERR_ARG);
    assert_int_equal(fcc_zkf_init(NULL, k_x0, k_p0, k_e, k_f), FCC_ERR_ARG);
    assert_int_equal(fcc_azkf_init(NULL, NULL, k_x0, k_p0, k_e, k_f), FCC_ERR_ARG);
    check_filter_init(kf_init);
    check_filter_init(zkf_init);
    check_filter_init(azkf_init);
}

/* A step without a filter, a model, or (when a measurement is to be used) a measurement is
 * refused; without a measurement to use, y may be NULL. */
static void filter_steps_refuse_missing_arguments(void **state)
{
    (void)state;
    fcc_sid_model_t model;
    fcc_sid_default_prior(&model);
    const fcc_real_t y[2] = {FCC_R(0.1), FCC_R(0.0)};
    fcc_kf_info_t ki;
    fcc_zkf_info_t zi;
    fcc_azkf_info_t ai;
    fcc_assert_ok(kf_init(k_x0, k_p0, k_e, k_f));
    fcc_assert_ok(zkf_init(k_x0, k_p0, k_e, k_f));
    fcc_assert_ok(azkf_init(k_x0, k_p0, k_e, k_f));
    assert_int_equal(fcc_kf_step(NULL, &model, 0, y, true, &ki), FCC_ERR_ARG);
    assert_int_equal(fcc_kf_step(&g_kf, NULL, 0, y, true, &ki), FCC_ERR_ARG);
    assert_int_equal(fcc_kf_step(&g_kf, &model, 0, NULL, true, &ki), FCC_ERR_ARG);
    fcc_assert_ok(fcc_kf_step(&g_kf, &model, 0, NULL, false, &ki));
    assert_int_equal(fcc_zkf_step(NULL, &model, 0, y, true, 2u, &zi), FCC_ERR_ARG);
    assert_int_equal(fcc_zkf_step(&g_zkf, NULL, 0, y, true, 2u, &zi), FCC_ERR_ARG);
    assert_int_equal(fcc_zkf_step(&g_zkf, &model, 0, NULL, true, 2u, &zi), FCC_ERR_ARG);
    fcc_assert_ok(fcc_zkf_step(&g_zkf, &model, 0, NULL, false, 2u, &zi));
    assert_int_equal(fcc_azkf_step(NULL, &model, 0, y, true, true, false, &ai), FCC_ERR_ARG);
    assert_int_equal(fcc_azkf_step(&g_azkf, NULL, 0, y, true, true, false, &ai), FCC_ERR_ARG);
    assert_int_equal(fcc_azkf_step(&g_azkf, &model, 0, NULL, true, true, false, &ai), FCC_ERR_ARG);
    fcc_assert_ok(fcc_azkf_step(&g_azkf, &model, 0, NULL, false, true, false, &ai));
}

static void azkf_orders_alone(void **state)
{
    (void)state;
    fcc_azkf_config_t ok;
    fcc_azkf_config_default(&ok);
    fcc_azkf_config_t c = ok;
    c.q_normal = FCC_ZONO_MIN_ORDER - 1u;
    assert_int_equal(fcc_azkf_config_check(&c), FCC_ERR_RANGE);
    c = ok;
    c.q_normal = FCC_ZONO_MAX_ORDER + 1u;
    assert_int_equal(fcc_azkf_config_check(&c), FCC_ERR_RANGE);
    c = ok;
    c.q_fault = FCC_ZONO_MIN_ORDER - 1u;
    assert_int_equal(fcc_azkf_config_check(&c), FCC_ERR_RANGE);
    c = ok;
    c.q_fault = FCC_ZONO_MAX_ORDER + 1u;
    assert_int_equal(fcc_azkf_config_check(&c), FCC_ERR_RANGE);
    c.q_normal = FCC_ZONO_MAX_ORDER;
    c.q_fault = FCC_ZONO_MIN_ORDER;
    fcc_assert_ok(fcc_azkf_config_check(&c));
}

static void mls_config_fields_alone(void **state)
{
    (void)state;
    fcc_sid_model_t prior;
    fcc_sid_default_prior(&prior);
    fcc_mls_config_t ok;
    fcc_mls_config_default(&ok, &prior);
    fcc_mls_config_t c = ok;
    fcc_mls_config_default(NULL, &prior); /* nothing to fill: no fault */
    fcc_mls_config_default(&c, NULL);     /* no prior: c left as it was */
    assert_memory_equal(&c, &ok, sizeof c);
    fcc_assert_ok(fcc_mls_config_check(&ok));
    /* non-finite fields: FCC_ERR_ARG */
    c = ok;
    c.prior.b[1] = (fcc_real_t)NAN;
    assert_int_equal(fcc_mls_config_check(&c), FCC_ERR_ARG);
    c = ok;
    c.ridge = (fcc_real_t)INFINITY;
    assert_int_equal(fcc_mls_config_check(&c), FCC_ERR_ARG);
    c = ok;
    c.max_cond = (fcc_real_t)NAN;
    assert_int_equal(fcc_mls_config_check(&c), FCC_ERR_ARG);
    c = ok;
    c.max_rho = (fcc_real_t)NAN;
    assert_int_equal(fcc_mls_config_check(&c), FCC_ERR_ARG);
    /* window and fill out of range: FCC_ERR_RANGE */
    c = ok;
    c.window = 3u;
    c.min_transitions = 3u;
    assert_int_equal(fcc_mls_config_check(&c), FCC_ERR_RANGE);
    c = ok;
    c.window = FCC_MLS_MAX_WINDOW + 1u;
    assert_int_equal(fcc_mls_config_check(&c), FCC_ERR_RANGE);
    c = ok;
    c.min_transitions = 3u;
    assert_int_equal(fcc_mls_config_check(&c), FCC_ERR_RANGE);
    c = ok;
    c.min_transitions = (uint16_t)(c.window + 1u);
    assert_int_equal(fcc_mls_config_check(&c), FCC_ERR_RANGE);
    c = ok;
    c.window = FCC_MLS_MAX_WINDOW;
    c.min_transitions = FCC_MLS_MAX_WINDOW;
    fcc_assert_ok(fcc_mls_config_check(&c));
    /* guards out of range */
    c = ok;
    c.ridge = FCC_R(-0.1);
    assert_int_equal(fcc_mls_config_check(&c), FCC_ERR_RANGE);
    c = ok;
    c.max_cond = FCC_R(1.0);
    assert_int_equal(fcc_mls_config_check(&c), FCC_ERR_RANGE);
    c = ok;
    c.max_rho = FCC_R(-0.1);
    assert_int_equal(fcc_mls_config_check(&c), FCC_ERR_RANGE);
    /* a push needs the MLS and both states */
    fcc_assert_ok(fcc_mls_init(&g_mls, &ok));
    const fcc_real_t x[2] = {FCC_R(0.1), FCC_R(0.0)};
    assert_int_equal(fcc_mls_push(NULL, x, 0, x), FCC_ERR_ARG);
    assert_int_equal(fcc_mls_push(&g_mls, NULL, 0, x), FCC_ERR_ARG);
    assert_int_equal(fcc_mls_push(&g_mls, x, 0, NULL), FCC_ERR_ARG);
    fcc_assert_ok(fcc_mls_push(&g_mls, x, 0, x));
}

static void sid_config_fields_alone(void **state)
{
    (void)state;
    fcc_sid_config_t ok;
    fcc_sid_config_default(&ok, FCC_SID_AZKF);
    fcc_sid_config_t c;
    /* each row semantics is accepted, anything else refused */
    const fcc_sid_rows_t rows[] = {FCC_SID_ROWS_PAPER, FCC_SID_ROWS_PRIOR, FCC_SID_ROWS_POSTERIOR};
    for (size_t i = 0; i < 3; ++i) {
        c = ok;
        c.rows = rows[i];
        fcc_assert_ok(fcc_sid_config_check(&c));
    }
    c = ok;
    c.rows = (fcc_sid_rows_t)7;
    assert_int_equal(fcc_sid_config_check(&c), FCC_ERR_ARG);
    /* each array with a NaN */
    fcc_real_t *arrays[4] = {&c.x0[1], &c.p0[3], &c.e[2], &c.f[1]};
    for (size_t i = 0; i < 4; ++i) {
        c = ok;
        *arrays[i] = (fcc_real_t)NAN;
        assert_int_equal(fcc_sid_config_check(&c), FCC_ERR_ARG);
    }
    /* each limit zero, then infinite */
    fcc_real_t *limits[3] = {&c.alpha_limit, &c.q_limit, &c.de_limit};
    for (size_t i = 0; i < 3; ++i) {
        c = ok;
        *limits[i] = FCC_R(0.0);
        assert_int_equal(fcc_sid_config_check(&c), FCC_ERR_RANGE);
        c = ok;
        *limits[i] = (fcc_real_t)INFINITY;
        assert_int_equal(fcc_sid_config_check(&c), FCC_ERR_RANGE);
    }
    /* the ZKF's order at and past either end */
    c = ok;
    c.zkf_order = FCC_ZONO_MIN_ORDER - 1u;
    assert_int_equal(fcc_sid_config_check(&c), FCC_ERR_RANGE);
    c.zkf_order = FCC_ZONO_MAX_ORDER + 1u;
    assert_int_equal(fcc_sid_config_check(&c), FCC_ERR_RANGE);
    c.zkf_order = FCC_ZONO_MAX_ORDER;
    fcc_assert_ok(fcc_sid_config_check(&c));
}

/* The zonotopic filters start from P0's Cholesky factor: P0 must be symmetric positive
 * definite, each way of not being so refused on its own. */
static void zonotopic_start_needs_spd_p0(void **state)
{
    (void)state;
    const fcc_sid_filter_t filters[2] = {FCC_SID_ZKF, FCC_SID_AZKF};
    for (int i = 0; i < 2; ++i) {
        fcc_sid_config_t c;
        fcc_sid_config_default(&c, filters[i]);
        c.p0[1] = FCC_R(0.001); /* asymmetric, its lower triangle still factors */
        assert_int_equal(fcc_sid_init(&g_sid, &c), FCC_ERR_NOT_POSDEF);
        fcc_sid_config_default(&c, filters[i]);
        c.p0[3] = FCC_R(-0.01); /* symmetric, not positive definite */
        assert_int_equal(fcc_sid_init(&g_sid, &c), FCC_ERR_NOT_POSDEF);
        fcc_sid_config_default(&c, filters[i]);
        fcc_assert_ok(fcc_sid_init(&g_sid, &c));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(filter_inits_refuse_each_argument),
        cmocka_unit_test(filter_steps_refuse_missing_arguments),
        cmocka_unit_test(azkf_orders_alone),
        cmocka_unit_test(mls_config_fields_alone),
        cmocka_unit_test(sid_config_fields_alone),
        cmocka_unit_test(zonotopic_start_needs_spd_p0),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
