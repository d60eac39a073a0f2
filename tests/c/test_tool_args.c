/*
 * test_tool_args.c -- the short-option command line of the host tools
 * (firmware/tools/common): the numbers it takes (bases, bounds, what strtoul
 * would wrongly take), and the walk over the arguments (help first or last,
 * flags, values that look like options, each refusal stopping the walk).  The
 * error lines' words are the tools' own, checked through the programs by
 * tests/python/bus/test_bus_vcan.py and tests/python/scripts/test_scripts_help.py.
 */
#include "fcc_test.h"

#include <string.h>

#include "tool_args.h"

static const tool_args_t tool = {"tool", "tool [-i IFACE] [-n N] [-q]", "  -i IFACE, -n N, -q\n"};

/* What the walk set: the table's targets. */
typedef struct {
    const char *iface;
    unsigned long n;
    int quiet;
} record_t;

#define WALK(r, ...)                                                                          \
    walk(r, (int)(sizeof((const char *[]){"tool", __VA_ARGS__}) / sizeof(const char *)),      \
         (const char *[]){"tool", __VA_ARGS__})

static tool_args_result_t walk(record_t *r, int argc, const char **argv)
{
    /* main's argv is not const: copies of the literals */
    static char text[8][16];
    char *args[8];
    r->iface = NULL;
    r->n = 0u;
    r->quiet = 0;
    const tool_args_opt_t opts[] = {
        {.letter = 'i', .text = &r->iface},
        {.letter = 'n', .number = &r->n, .min = 1u, .max = 10u, .what = "-n needs 1..10, not"},
        {.letter = 'q', .flag = &r->quiet},
    };
    assert_true(argc <= 8);
    for (int i = 0; i < argc; ++i) {
        assert_true(strlen(argv[i]) < sizeof text[i]);
        (void)strcpy(text[i], argv[i]);
        args[i] = text[i];
    }
    return tool_args_parse(&tool, opts, sizeof opts / sizeof opts[0], argc, args);
}

static void expect_ulong(const char *s, unsigned long min, unsigned long max, int rc,
                         unsigned long want)
{
    unsigned long v = 12345u;
    assert_int_equal(tool_args_ulong(s, min, max, &v), rc);
    assert_int_equal(v, rc == 0 ? want : 12345u); /* a refusal leaves *out as it was */
}

static void test_numbers(void **state)
{
    (void)state;
    expect_ulong("0", 0u, 10u, 0, 0u);
    expect_ulong("2046", 0u, 0x7FEu, 0, 2046u);
    expect_ulong("0x7FE", 0u, 0x7FEu, 0, 0x7FEu);
    expect_ulong("0x7FF", 0u, 0x7FEu, -1, 0u);
    expect_ulong("010", 0u, 10u, 0, 8u);                 /* octal, as strtoul's base 0 */
    expect_ulong("08", 0u, 10u, -1, 0u);                 /* not octal */
    expect_ulong("+5", 0u, 10u, 0, 5u);                  /* strtoul's sign */
    expect_ulong(" 5", 0u, 10u, 0, 5u);                  /* and its leading blanks */
    expect_ulong("4294967295", 0u, 0xFFFFFFFFu, 0, 0xFFFFFFFFu);
    expect_ulong("4294967296", 0u, 0xFFFFFFFFu, -1, 0u);
    expect_ulong("99999999999999999999999", 0u, ~0ul, -1, 0u); /* ERANGE, not ULONG_MAX */
    expect_ulong("0", 1u, 10u, -1, 0u);
    expect_ulong("1", 1u, 10u, 0, 1u);
    expect_ulong("-1", 0u, ~0ul, -1, 0u); /* strtoul would take it as ULONG_MAX */
    expect_ulong("", 0u, 10u, -1, 0u);
    expect_ulong(" ", 0u, 10u, -1, 0u);
    expect_ulong("5 ", 0u, 10u, -1, 0u);
    expect_ulong("1.5", 0u, 10u, -1, 0u);
    expect_ulong(NULL, 0u, 10u, -1, 0u);
}

static void test_walk(void **state)
{
    (void)state;
    record_t r;
    assert_int_equal(WALK(&r, "-q", "-i", "vcan0", "-n", "0x3"), TOOL_ARGS_RUN);
    assert_int_equal(r.quiet, 1);
    assert_string_equal(r.iface, "vcan0");
    assert_int_equal(r.n, 3u);
    /* a value is the next argument whatever it looks like; the last one given counts */
    assert_int_equal(WALK(&r, "-i", "-h", "-i", "--help"), TOOL_ARGS_RUN);
    assert_string_equal(r.iface, "--help");
    assert_int_equal(walk(&r, 1, (const char *[]){"tool"}), TOOL_ARGS_RUN);
    assert_null(r.iface);
    assert_int_equal(r.quiet, 0);
    /* help stops the walk where it stands: what came before is applied, nothing after */
    assert_int_equal(WALK(&r, "-q", "--help", "-x"), TOOL_ARGS_HELP);
    assert_int_equal(r.quiet, 1);
    assert_int_equal(WALK(&r, "-h", "-q"), TOOL_ARGS_HELP);
    assert_int_equal(r.quiet, 0);
}

static void test_refusals(void **state)
{
    (void)state;
    record_t r;
    assert_int_equal(WALK(&r, "-x", "-h"), TOOL_ARGS_BAD); /* before the help: refused */
    assert_int_equal(WALK(&r, "-"), TOOL_ARGS_BAD);
    assert_int_equal(WALK(&r, "--"), TOOL_ARGS_BAD);
    assert_int_equal(WALK(&r, "-qq"), TOOL_ARGS_BAD);
    assert_int_equal(WALK(&r, "-in", "x"), TOOL_ARGS_BAD);
    assert_int_equal(WALK(&r, "vcan0"), TOOL_ARGS_BAD);
    assert_int_equal(WALK(&r, "-q", "-i"), TOOL_ARGS_BAD); /* its value missing */
    assert_int_equal(r.quiet, 1);
    assert_null(r.iface);
    assert_int_equal(WALK(&r, "-n", "11", "-q"), TOOL_ARGS_BAD); /* out of the option's range */
    assert_int_equal(r.n, 0u);
    assert_int_equal(r.quiet, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_numbers),
        cmocka_unit_test(test_walk),
        cmocka_unit_test(test_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
