/* The shared core definitions: status names and the real type's build switch. */
#include "fcc_test.h"

#include <string.h>

static void status_names_are_distinct_and_never_null(void **state)
{
    (void)state;
    static const fcc_status_t codes[] = {
        FCC_OK, FCC_ERR_ARG, FCC_ERR_SIZE, FCC_ERR_SINGULAR, FCC_ERR_NOT_POSDEF,
        FCC_ERR_NO_CONVERGENCE, FCC_ERR_NOT_FINITE, FCC_ERR_RANGE, FCC_ERR_DISAGREE,
        FCC_ERR_NOT_STABILIZABLE, FCC_ERR_NOT_DETECTABLE, FCC_ERR_FORMAT, FCC_ERR_IO,
        FCC_ERR_AGAIN};
    const size_t n = sizeof codes / sizeof codes[0];
    for (size_t i = 0; i < n; ++i) {
        assert_non_null(fcc_status_str(codes[i]));
        if (codes[i] != FCC_OK) {
            assert_true(codes[i] < 0);
        }
        for (size_t j = 0; j < i; ++j) {
            assert_string_not_equal(fcc_status_str(codes[i]), fcc_status_str(codes[j]));
        }
    }
    assert_string_equal(fcc_status_str(12345), "unknown status");
}

static void real_type_matches_build(void **state)
{
    (void)state;
#ifdef FCC_REAL_FLOAT
    assert_int_equal(sizeof(fcc_real_t), sizeof(float));
#else
    assert_int_equal(sizeof(fcc_real_t), sizeof(double));
#endif
    assert_true(FCC_IS_FINITE(FCC_R(1.0)));
    assert_false(FCC_IS_FINITE(FCC_R(1.0) / FCC_R(0.0)));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(status_names_are_distinct_and_never_null),
        cmocka_unit_test(real_type_matches_build),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
