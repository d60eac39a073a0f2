/*
 * The guards of the identification and the LQG design that the module tests do
 * not reach (scripts/test coverage's MC/DC): each refusal caused by one field or
 * one argument alone, the others valid, and the state a refused step leaves
 * untouched; and the identification's learning rules (which transitions the MLS
 * learns from) under each row semantics, with a fault held or not.
 */
#include "fcc_test.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include "fcc_lqg.h"
#include "fcc_sid.h"

/* Half the largest real: finite, and its product with anything above 2 is not. */
#define HUGE_REAL ((fcc_real_t)(sizeof(fcc_real_t) == sizeof(float) ? FLT_MAX : DBL_MAX) * FCC_R(0.5))

static const fcc_real_t k_x0[2] = {FCC_R(0.1), FCC_R(0.0)};
static const fcc_real_t k_p0[4] = {FCC_R(0.01), FCC_R(0.0), FCC_R(0.0), FCC_R(0.01)};
static const fcc_real_t k_e[4] = {FCC_R(0.001), FCC_R(0.0), FCC_R(0.0), FCC_R(0.001)};
static const fcc_real_t k_f[4] = {FCC_R(0.004), FCC_R(0.0), FCC_R(0.0), FCC_R(0.004)};
static const fcc_real_t k_y[2] = {FCC_R(0.12), FCC_R(0.01)};

static fcc_kf_t g_kf;
static fcc_zkf_t g_zkf;
static fcc_sid_t g_sid;
static fcc_sid_t g_sid2;
static fcc_lqg_ws_t g_ws;

static fcc_sid_model_t prior(void)
{
    fcc_sid_model_t m;
    fcc_sid_default_prior(&m);
    return m;
}

/* The KF refuses a step whose covariance or state left the representable range, and
 * one whose innovation covariance P + R is not positive definite: the filter keeps
 * its state.  Without the measurement the same filter steps. */
static void test_kf_refuses_a_state_out_of_range(void **state)
{
    (void)state;
    const fcc_sid_model_t model = prior();
#define X0 FCC_R(0.1)
#define P0 FCC_R(0.01)
#define NEG FCC_R(-1.0)
#define NAN_R ((fcc_real_t)NAN)
#define BIG (FCC_R(2.0) * FCC_SID_MAX_MAGNITUDE) /* beyond the filter's magnitude bound */
    static const struct {
        fcc_real_t x[2];
        fcc_real_t p[4];
        bool use_y;
        fcc_status_t status;
    } cases[] = {
        {{X0, 0}, {NEG, 0, 0, NEG}, true, FCC_ERR_NOT_FINITE}, /* P + R not positive definite */
        {{X0, 0}, {NEG, 0, 0, NEG}, false, FCC_OK},            /* no update: no S to invert */
        {{X0, 0}, {P0, NAN_R, NAN_R, P0}, false, FCC_ERR_NOT_FINITE},
        {{X0, BIG}, {P0, 0, 0, P0}, false, FCC_ERR_NOT_FINITE},
        {{X0, 0}, {BIG, 0, 0, P0}, false, FCC_ERR_NOT_FINITE},
        {{X0, 0}, {P0, 0, 0, BIG}, false, FCC_ERR_NOT_FINITE},
    };
    for (size_t i = 0u; i < sizeof cases / sizeof cases[0]; ++i) {
        fcc_assert_ok(fcc_kf_init(&g_kf, k_x0, k_p0, k_e, k_f));
        memcpy(g_kf.x, cases[i].x, sizeof g_kf.x);
        memcpy(g_kf.p, cases[i].p, sizeof g_kf.p);
        fcc_kf_t before;
        memcpy(&before, &g_kf, sizeof before);
        fcc_kf_info_t info;
        const fcc_status_t st = fcc_kf_step(&g_kf, &model, FCC_R(0.0), k_y, cases[i].use_y, &info);
        if (st != cases[i].status) {
            fail_msg("case %zu: status %d, expected %d", i, (int)st, (int)cases[i].status);
        }
        if (st != FCC_OK) {
            assert_memory_equal(&g_kf, &before, sizeof before);
        }
    }
}
#undef X0
#undef P0
#undef NEG
#undef NAN_R
#undef BIG

/* The ZKF refuses a step whose gain cannot be formed (M + R not positive definite)
 * or whose set would outgrow the representable range (a model of half the largest real),
 * its state untouched. */
static void test_zkf_refuses_a_gain_it_cannot_form(void **state)
{
    (void)state;
    const fcc_sid_model_t model = prior();
    fcc_zkf_info_t info;
    fcc_assert_ok(fcc_zkf_init(&g_zkf, k_x0, k_p0, k_e, k_f));
    const fcc_real_t negative[4] = {FCC_R(-1.0), FCC_R(0.0), FCC_R(0.0), FCC_R(-1.0)};
    memcpy(g_zkf.r, negative, sizeof g_zkf.r);
    fcc_zkf_t before;
    memcpy(&before, &g_zkf, sizeof before);
    assert_int_equal(fcc_zkf_step(&g_zkf, &model, FCC_R(0.0), k_y, true, 4u, &info), FCC_ERR_NOT_FINITE);
    assert_memory_equal(&g_zkf, &before, sizeof before);
    fcc_assert_ok(fcc_zkf_step(&g_zkf, &model, FCC_R(0.0), k_y, false, 4u, &info)); /* no gain needed */
    assert_false(info.updated);

    fcc_assert_ok(fcc_zkf_init(&g_zkf, k_x0, k_p0, k_e, k_f));
    fcc_sid_model_t huge = model;
    huge.a[0] = HUGE_REAL;
    huge.a[3] = HUGE_REAL;
    memcpy(&before, &g_zkf, sizeof before);
    assert_int_equal(fcc_zkf_step(&g_zkf, &huge, FCC_R(0.0), k_y, true, 4u, &info), FCC_ERR_NOT_FINITE);
    assert_memory_equal(&g_zkf, &before, sizeof before);
}

/* The 2x2 helpers refuse what is not positive definite, one diagonal entry at a time;
 * the detector and the zonotope reduction refuse a missing argument. */
static void test_small_helpers_refuse_one_argument_at_a_time(void **state)
{
    (void)state;
    fcc_real_t out[4];
    const fcc_real_t s3_zero[4] = {FCC_R(1.0), FCC_R(0.0), FCC_R(0.0), FCC_R(0.0)};
    assert_int_equal(fcc_sid_m2_spd_inv(s3_zero, out), FCC_ERR_NOT_POSDEF);
    const fcc_real_t s0_negative[4] = {FCC_R(-1.0), FCC_R(0.0), FCC_R(0.0), FCC_R(1.0)};
    assert_int_equal(fcc_sid_m2_cholesky(s0_negative, out), FCC_ERR_NOT_POSDEF);
    const fcc_real_t spd[4] = {FCC_R(4.0), FCC_R(0.0), FCC_R(0.0), FCC_R(9.0)};
    fcc_assert_ok(fcc_sid_m2_cholesky(spd, out));
    fcc_assert_close(out[0], 2.0, 1e-6, 0.0);
    fcc_assert_close(out[3], 3.0, 1e-6, 0.0);

    fcc_fdet_config_t cfg;
    fcc_fdet_config_default(&cfg);
    cfg.mode = FCC_FDET_ZONOTOPE;
    fcc_fdet_t det;
    fcc_assert_ok(fcc_fdet_init(&det, &cfg));
    const fcc_real_t innov[2] = {FCC_R(0.0), FCC_R(0.0)};
    bool fault = true;
    assert_int_equal(fcc_fdet_step(NULL, innov, innov, false, &fault), FCC_ERR_ARG);
    assert_int_equal(fcc_fdet_step(&det, innov, NULL, false, &fault), FCC_ERR_ARG);
    assert_true(fault); /* not written on a refusal */
    fcc_assert_ok(fcc_fdet_step(&det, innov, innov, false, &fault));
    assert_false(fault);

    static fcc_zono_work_t work;
    fcc_real_t norm2[4] = {FCC_R(1.0), FCC_R(2.0), FCC_R(3.0), FCC_R(4.0)};
    fcc_real_t r[8] = {FCC_R(0.0)};
    uint16_t p = 4u;
    assert_int_equal(fcc_zono_select(NULL, p, FCC_ZONO_MIN_ORDER, &work), FCC_ERR_ARG);
    assert_int_equal(fcc_zono_select(norm2, p, FCC_ZONO_MIN_ORDER, NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_zono_reduce(r, norm2, NULL, FCC_ZONO_MIN_ORDER, &work), FCC_ERR_ARG);
    assert_int_equal(p, 4u);
}

/* One identification step of a plant that follows the prior model, excited by a
 * sine on the elevator; y is the state. */
typedef struct {
    fcc_real_t x[2];
    uint32_t k;
} plant_t;

static fcc_real_t plant_step(plant_t *pl, const fcc_sid_model_t *m)
{
    const fcc_real_t de = (fcc_real_t)(0.05 * sin(0.7 * (double)pl->k));
    const fcc_real_t x0 = m->a[0] * pl->x[0] + m->a[1] * pl->x[1] + m->b[0] * de;
    const fcc_real_t x1 = m->a[2] * pl->x[0] + m->a[3] * pl->x[1] + m->b[1] * de;
    pl->x[0] = x0;
    pl->x[1] = x1;
    ++pl->k;
    return de;
}

static void sid_start(fcc_sid_t *sid, fcc_sid_filter_t filter, fcc_sid_rows_t rows)
{
    fcc_sid_config_t cfg;
    fcc_sid_config_default(&cfg, filter);
    cfg.rows = rows;
    fcc_assert_ok(fcc_sid_init(sid, &cfg));
}

/* Steps with the measurement valid or not (valid[i]); the MLS's transitions after each. */
static void run_pattern(fcc_sid_t *sid, const bool *valid, size_t n, uint16_t *count)
{
    const fcc_sid_model_t m = prior();
    plant_t pl = {{FCC_R(0.05), FCC_R(0.0)}, 0u};
    fcc_real_t de = FCC_R(0.0);
    for (size_t i = 0u; i < n; ++i) {
        fcc_sid_out_t out;
        fcc_assert_ok(fcc_sid_step(sid, pl.x[0], pl.x[1], de, false, valid[i], &out));
        de = plant_step(&pl, &m);
        count[i] = sid->mls.count;
    }
}

/* Prior rows (the state before y_k): a row is informed when the previous step took its
 * measurement; the MLS learns a transition only between two informed rows. */
static void test_prior_rows_learn_between_informed_rows(void **state)
{
    (void)state;
    sid_start(&g_sid, FCC_SID_KF, FCC_SID_ROWS_PRIOR);
    static const bool valid[] = {true, true, true, false, true, true, true};
    static const uint16_t expected[] = {0u, 0u, 1u, 2u, 2u, 2u, 3u};
    uint16_t count[7];
    run_pattern(&g_sid, valid, 7u, count);
    assert_memory_equal(count, expected, sizeof expected);
}

/* Posterior rows (the state after y_k): a row is informed when its own step took the
 * measurement; the MLS learns between two informed rows. */
static void test_posterior_rows_learn_between_informed_rows(void **state)
{
    (void)state;
    sid_start(&g_sid, FCC_SID_ZKF, FCC_SID_ROWS_POSTERIOR);
    static const bool valid[] = {true, true, false, true, true};
    static const uint16_t expected[] = {0u, 1u, 1u, 1u, 2u};
    uint16_t count[5];
    run_pattern(&g_sid, valid, 5u, count);
    assert_memory_equal(count, expected, sizeof expected);
}

/* The AZKF with the oracle detector: while a fault is flagged, hold-on-fault keeps the
 * steps out of the MLS; without it they are learnt.  With arm_on_prior false the
 * detector is disarmed until the MLS has a model of its own. */
static void test_azkf_learning_with_a_fault_held_or_not(void **state)
{
    (void)state;
    fcc_sid_config_t cfg;
    fcc_sid_config_default(&cfg, FCC_SID_AZKF);
    cfg.azkf.det.mode = FCC_FDET_ORACLE;
    cfg.arm_on_prior = false;
    fcc_assert_ok(fcc_sid_init(&g_sid, &cfg));
    cfg.mls_hold_on_fault = false;
    fcc_assert_ok(fcc_sid_init(&g_sid2, &cfg));
    const fcc_sid_model_t m = prior();
    plant_t pl = {{FCC_R(0.05), FCC_R(0.0)}, 0u};
    fcc_real_t de = FCC_R(0.0);
    fcc_sid_out_t out;
    fcc_sid_out_t out2;
    /* on the prior the detector is not armed: the oracle's fault is not flagged */
    fcc_assert_ok(fcc_sid_step(&g_sid, pl.x[0], pl.x[1], de, true, true, &out));
    fcc_assert_ok(fcc_sid_step(&g_sid2, pl.x[0], pl.x[1], de, true, true, &out2));
    assert_true(out.model_is_prior);
    assert_false(out.fault);
    bool own_model = false;
    for (int i = 0; i < 200 && !own_model; ++i) {
        de = plant_step(&pl, &m);
        fcc_assert_ok(fcc_sid_step(&g_sid, pl.x[0], pl.x[1], de, false, true, &out));
        fcc_assert_ok(fcc_sid_step(&g_sid2, pl.x[0], pl.x[1], de, false, true, &out2));
        own_model = !out.model_is_prior;
    }
    assert_true(own_model);
    assert_int_equal(g_sid.mls.count, g_sid2.mls.count);
    const uint16_t learnt = g_sid.mls.count;
    for (int i = 0; i < 3; ++i) {
        de = plant_step(&pl, &m);
        fcc_assert_ok(fcc_sid_step(&g_sid, pl.x[0], pl.x[1], de, true, true, &out));
        fcc_assert_ok(fcc_sid_step(&g_sid2, pl.x[0], pl.x[1], de, true, true, &out2));
        assert_true(out.fault && out2.fault);
    }
    assert_int_equal(g_sid.mls.count, learnt);
    assert_true(g_sid2.mls.count > learnt);
}

/* The design refuses a plant with one non-finite entry in any of its matrices (ARG)
 * and a weight or a variance that is not positive (RANGE); the stepwise design refuses
 * a missing argument and a step after its last. */
static void test_design_refuses_one_bad_plant_field(void **state)
{
    (void)state;
    fcc_lqg_plant_t plant;
    fcc_assert_ok(fcc_lqg_plant_default(&plant));
    const fcc_lqg_solver_t h = FCC_LQG_SOLVER_HAMILTONIAN;
    fcc_lqg_design_t d;
    fcc_real_t *const fields[] = {&plant.g[1], &plant.w[2], &plant.wx[0], &plant.h[3],
                                  &plant.wu, &plant.gyro_var};
    for (size_t i = 0u; i < sizeof fields / sizeof fields[0]; ++i) {
        const fcc_real_t keep = *fields[i];
        *fields[i] = (fcc_real_t)NAN;
        if (fcc_lqg_design(&plant, 0.1, h, &d, &g_ws) != FCC_ERR_ARG) {
            fail_msg("field %zu: a NaN is not refused", i);
        }
        *fields[i] = keep;
    }
    fcc_real_t *const positive[] = {&plant.wu, &plant.accel_var};
    for (size_t i = 0u; i < sizeof positive / sizeof positive[0]; ++i) {
        const fcc_real_t keep = *positive[i];
        *positive[i] = FCC_R(0.0);
        if (fcc_lqg_design(&plant, 0.1, h, &d, &g_ws) != FCC_ERR_RANGE) {
            fail_msg("field %zu: zero is not refused", i);
        }
        *positive[i] = keep;
    }
    assert_int_equal(fcc_lqg_design_slice(NULL, &d), FCC_ERR_ARG);
    assert_int_equal(fcc_lqg_design_slice(&g_ws, NULL), FCC_ERR_ARG);
    fcc_assert_ok(fcc_lqg_design_begin(&plant, 0.1, h, &g_ws));
    fcc_status_t st = FCC_ERR_AGAIN;
    unsigned slices = 0u;
    while (st == FCC_ERR_AGAIN && slices < 100u) {
        st = fcc_lqg_design_slice(&g_ws, &d);
        ++slices;
    }
    fcc_assert_ok(st);
    assert_int_equal(slices, FCC_LQG_DESIGN_SLICES);
    assert_int_equal(fcc_lqg_design_slice(&g_ws, &d), FCC_ERR_ARG); /* after its last */
}

/* The MLS refuses a window whose normal equations overflow (SINGULAR: a regressor's sum of
 * squares, not NaN) and a fitted model
 * whose spectral radius overflows (RANGE), keeping its last estimate: the prior here. */
static fcc_status_t mls_fed(fcc_mls_t *mls, fcc_real_t x_scale, fcc_real_t next_scale)
{
    fcc_mls_config_t cfg;
    const fcc_sid_model_t m = prior();
    fcc_mls_config_default(&cfg, &m);
    fcc_assert_ok(fcc_mls_init(mls, &cfg));
    fcc_status_t st = FCC_OK;
    for (uint16_t i = 0u; i < cfg.min_transitions; ++i) {
        const fcc_real_t v = FCC_R(0.5) * (fcc_real_t)(i % 3u); /* 0 first: the sums' reference */
        const fcc_real_t w = (fcc_real_t)((i * 7u) % 5u) - FCC_R(2.0);
        const fcc_real_t x[2] = {x_scale * v, w};
        const fcc_real_t x_next[2] = {next_scale * (v + w), next_scale * (w - v)};
        st = fcc_mls_update(mls, x, (fcc_real_t)(i % 2u), x_next);
    }
    return st;
}

static void test_mls_refuses_an_overflowing_fit(void **state)
{
    (void)state;
    static fcc_mls_t mls;
    const fcc_real_t root = FCC_SQRT(HUGE_REAL) * FCC_R(4.0); /* its square overflows */
    fcc_assert_ok(mls_fed(&mls, FCC_R(1.0), FCC_R(0.5)));
    assert_false(mls.est.is_prior);
    assert_int_equal(mls_fed(&mls, root, FCC_R(0.5)), FCC_ERR_SINGULAR);
    assert_true(mls.est.is_prior);
    assert_int_equal(mls_fed(&mls, FCC_R(1.0), root), FCC_ERR_RANGE);
    assert_true(mls.est.is_prior);
    assert_true(FCC_IS_FINITE(mls.est.rho));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_kf_refuses_a_state_out_of_range),
        cmocka_unit_test(test_zkf_refuses_a_gain_it_cannot_form),
        cmocka_unit_test(test_small_helpers_refuse_one_argument_at_a_time),
        cmocka_unit_test(test_prior_rows_learn_between_informed_rows),
        cmocka_unit_test(test_posterior_rows_learn_between_informed_rows),
        cmocka_unit_test(test_azkf_learning_with_a_fault_held_or_not),
        cmocka_unit_test(test_design_refuses_one_bad_plant_field),
        cmocka_unit_test(test_mls_refuses_an_overflowing_fit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
