/* fcc_zonotope: the reduction operator of eqs. (17)-(18) -- hand-worked
 * cases, its properties (the reduced set contains the original, q >= p is
 * the identity, the result has q columns, ties are stable), eq. (16). */
#include "fcc_test.h"

#include <string.h>

#include "fcc_zonotope.h"

#define TOL FCC_TEST_TOL(1e-14, 1e-6)

static fcc_zono_work_t work;
static fcc_real_t gen[2u * FCC_ZONO_MAX_COLS];
static fcc_real_t norm2[FCC_ZONO_MAX_COLS];

static unsigned lcg = 1u;
static double urand(void)
{
    lcg = lcg * 1103515245u + 12345u;
    return (double)((lcg >> 8) & 0xFFFFu) / 32767.5 - 1.0;
}

/* Loads column-major generators and their norms. */
static void load(const fcc_real_t *cols, uint16_t p)
{
    memcpy(gen, cols, 2u * p * sizeof(fcc_real_t));
    fcc_zono_norms(gen, p, norm2);
}

static void assert_columns(const fcc_real_t *expect, uint16_t p)
{
    for (uint16_t i = 0; i < 2u * p; ++i) {
        fcc_assert_close(gen[i], expect[i], TOL, TOL);
    }
}

/* R = [[3, 0, 1, 0.5], [0, 2, 1, -0.5]]: squared norms 9, 4, 2, 0.5. */
static const fcc_real_t r4[8] = {3, 0, 0, 2, 1, 1, FCC_R(0.5), FCC_R(-0.5)};

static void hand_worked_reductions(void **state)
{
    (void)state;
    uint16_t p = 4u;
    /* q = 3: keep q - n = 1 column (3, 0); box columns 2..4:
     * row sums of |.|: 0 + 1 + 0.5 = 1.5 and 2 + 1 + 0.5 = 3.5. */
    load(r4, 4u);
    fcc_assert_ok(fcc_zono_reduce(gen, norm2, &p, 3u, &work));
    assert_int_equal(p, 3);
    const fcc_real_t q3[6] = {3, 0, FCC_R(1.5), 0, 0, FCC_R(3.5)};
    assert_columns(q3, 3u);
    /* q = 4 = p: identity. */
    p = 4u;
    load(r4, 4u);
    fcc_assert_ok(fcc_zono_reduce(gen, norm2, &p, 4u, &work));
    assert_int_equal(p, 4);
    assert_columns(r4, 4u);
    /* q = 2: everything boxed: diag(4.5, 3.5). */
    load(r4, 4u);
    fcc_assert_ok(fcc_zono_reduce(gen, norm2, &p, 2u, &work));
    assert_int_equal(p, 2);
    const fcc_real_t q2[4] = {FCC_R(4.5), 0, 0, FCC_R(3.5)};
    assert_columns(q2, 2u);
    /* The norms follow the columns. */
    fcc_assert_close(norm2[0], 4.5 * 4.5, TOL, TOL);
    fcc_assert_close(norm2[1], 3.5 * 3.5, TOL, TOL);
}

static void ties_keep_original_order(void **state)
{
    (void)state;
    /* Four unit columns of equal norm and a short one; q = 4 keeps two:
     * the first two in the stable ranking, i.e. columns 0 and 1. */
    const fcc_real_t r[10] = {1, 0, 0, 1, 1, 0, 0, 1, FCC_R(0.1), 0};
    uint16_t p = 5u;
    load(r, 5u);
    fcc_assert_ok(fcc_zono_reduce(gen, norm2, &p, 4u, &work));
    const fcc_real_t expect[8] = {1, 0, 0, 1, FCC_R(1.1), 0, 0, 1};
    assert_int_equal(p, 4);
    assert_columns(expect, 4u);
    /* The other selection branch (fewer boxed than kept): 8 equal columns,
     * q = 7 keeps 5 and boxes the last 3 (stable: later ties lose). */
    fcc_real_t r8[16];
    for (int j = 0; j < 8; ++j) {
        r8[2 * j] = (fcc_real_t)(j % 2 == 0 ? 1.0 : 0.6);
        r8[2 * j + 1] = (fcc_real_t)(j % 2 == 0 ? 0.0 : 0.8);
    }
    load(r8, 8u);
    fcc_assert_ok(fcc_zono_select(norm2, 8u, 7u, &work));
    for (int j = 0; j < 8; ++j) {
        assert_int_equal(fcc_zono_is_boxed(&work, (uint16_t)j), j >= 5);
    }
    assert_true(work.list_is_boxed);
    assert_int_equal(work.n_list, 3);
    /* The first branch (fewer kept than boxed) lists the kept columns. */
    fcc_assert_ok(fcc_zono_select(norm2, 8u, 4u, &work));
    assert_false(work.list_is_boxed);
    assert_int_equal(work.n_list, 2);
    assert_int_equal(work.list[0], 0);
    assert_int_equal(work.list[1], 1);
    assert_false(fcc_zono_is_boxed(&work, 1u));
    assert_true(fcc_zono_is_boxed(&work, 2u));
}

/* Exact 2-D membership: every vertex R s (s in {-1,1}^p) of the original
 * lies in the reduced zonotope, and the support function dominates. */
static void assert_contains(const fcc_real_t *orig, uint16_t p_orig, const fcc_real_t *red,
                            uint16_t p_red)
{
    const fcc_real_t c[2] = {0, 0};
    for (uint32_t s = 0; s < (1u << p_orig); ++s) {
        fcc_real_t pt[2] = {0, 0};
        for (uint16_t j = 0; j < p_orig; ++j) {
            const fcc_real_t sign = (s >> j) & 1u ? FCC_R(1.0) : FCC_R(-1.0);
            pt[0] += sign * orig[2u * j];
            pt[1] += sign * orig[2u * j + 1u];
        }
        assert_true(fcc_zono_contains(c, red, p_red, pt, FCC_TEST_TOL(1e-12, 1e-5)));
    }
    for (int k = 0; k < 360; ++k) {
        const fcc_real_t d[2] = {(fcc_real_t)cos(k * 3.14159265358979 / 180.0),
                                 (fcc_real_t)sin(k * 3.14159265358979 / 180.0)};
        assert_true(fcc_zono_support(c, red, p_red, d) >=
                    fcc_zono_support(c, orig, p_orig, d) - FCC_TEST_TOL(1e-12, 1e-5));
    }
}

static void reduced_set_contains_original(void **state)
{
    (void)state;
    fcc_real_t orig[24];
    for (int trial = 0; trial < 20; ++trial) {
        const uint16_t p = (uint16_t)(3 + trial % 10);
        for (int i = 0; i < 2 * p; ++i) {
            orig[i] = (fcc_real_t)urand();
        }
        for (uint16_t q = 2u; q <= p + 1u; ++q) {
            uint16_t pr = p;
            load(orig, p);
            fcc_assert_ok(fcc_zono_reduce(gen, norm2, &pr, q, &work));
            assert_int_equal(pr, q < p ? q : p); /* q columns, or unchanged */
            assert_contains(orig, p, gen, pr);
            /* The interval hull is preserved exactly. */
            fcc_real_t h0[2], h1[2];
            fcc_zono_hull(orig, p, h0);
            fcc_zono_hull(gen, pr, h1);
            fcc_assert_close(h1[0], h0[0], TOL, TOL);
            fcc_assert_close(h1[1], h0[1], TOL, TOL);
        }
    }
    /* A point outside is rejected by the membership test itself. */
    const fcc_real_t c[2] = {0, 0};
    const fcc_real_t box[4] = {1, 0, 0, 1};
    const fcc_real_t out_pt[2] = {FCC_R(1.01), 0};
    const fcc_real_t in_pt[2] = {FCC_R(0.99), FCC_R(-0.99)};
    assert_false(fcc_zono_contains(c, box, 2u, out_pt, 0));
    assert_true(fcc_zono_contains(c, box, 2u, in_pt, 0));
}

static void size_grows_as_order_drops(void **state)
{
    (void)state;
    /* Eq. (16) J = sqrt(tr(R R^T)); for r4: sqrt(9 + 4 + 2 + 0.5). */
    fcc_assert_close(fcc_zono_size(r4, 4u), sqrt(15.5), TOL, TOL);
    fcc_real_t orig[40];
    for (int i = 0; i < 40; ++i) {
        orig[i] = (fcc_real_t)urand();
    }
    fcc_real_t prev = FCC_R(0.0);
    for (uint16_t q = 20u; q >= 2u; --q) {
        uint16_t p = 20u;
        load(orig, 20u);
        fcc_assert_ok(fcc_zono_reduce(gen, norm2, &p, q, &work));
        const fcc_real_t j = fcc_zono_size(gen, p);
        assert_true(j >= prev - TOL);
        prev = j;
    }
}

static void largest_order_and_bounds(void **state)
{
    (void)state;
    /* A full matrix at the compile-time bound reduces to exactly q columns
     * and never touches storage past it. */
    const uint16_t p = FCC_ZONO_MAX_COLS;
    for (uint16_t j = 0; j < p; ++j) {
        gen[2u * j] = (fcc_real_t)urand();
        gen[2u * j + 1u] = (fcc_real_t)urand();
    }
    fcc_real_t h0[2];
    fcc_zono_hull(gen, p, h0);
    fcc_zono_norms(gen, p, norm2);
    uint16_t pr = p;
    fcc_assert_ok(fcc_zono_reduce(gen, norm2, &pr, FCC_ZONO_MAX_ORDER, &work));
    assert_int_equal(pr, FCC_ZONO_MAX_ORDER);
    fcc_real_t h1[2];
    fcc_zono_hull(gen, pr, h1);
    fcc_assert_close(h1[0], h0[0], FCC_TEST_TOL(1e-12, 1e-4), 0.0);
    /* Half and half: the heap at its largest. */
    pr = p;
    fcc_zono_norms(gen, pr, norm2);
    fcc_assert_ok(fcc_zono_reduce(gen, norm2, &pr, (uint16_t)(p / 2u + 1u), &work));
    assert_int_equal(pr, p / 2u + 1u);
    /* Orders outside 2..FCC_ZONO_MAX_ORDER and oversize matrices. */
    pr = 4u;
    assert_int_equal(fcc_zono_reduce(gen, norm2, &pr, FCC_ZONO_MAX_ORDER + 1u, &work),
                     FCC_ERR_RANGE);
    assert_int_equal(fcc_zono_reduce(gen, norm2, &pr, 1u, &work), FCC_ERR_ARG);
    pr = FCC_ZONO_MAX_COLS + 1u;
    assert_int_equal(fcc_zono_reduce(gen, norm2, &pr, 2u, &work), FCC_ERR_SIZE);
    assert_int_equal(fcc_zono_reduce(NULL, norm2, &pr, 2u, &work), FCC_ERR_ARG);
}

static void covariation(void **state)
{
    (void)state;
    fcc_real_t m[4];
    fcc_zono_covariation(r4, 4u, m);
    /* R R^T = [[9+1+0.25, 1-0.25], [., 4+1+0.25]]. */
    fcc_assert_close(m[0], 10.25, TOL, TOL);
    fcc_assert_close(m[1], 0.75, TOL, TOL);
    fcc_assert_close(m[2], 0.75, TOL, TOL);
    fcc_assert_close(m[3], 5.25, TOL, TOL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(hand_worked_reductions),
        cmocka_unit_test(ties_keep_original_order),
        cmocka_unit_test(reduced_set_contains_original),
        cmocka_unit_test(size_grows_as_order_drops),
        cmocka_unit_test(largest_order_and_bounds),
        cmocka_unit_test(covariation),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
