/*
 * test_canrec.c -- canrec's log lines (firmware/tools/canrec) against the
 * candump log format, written out by hand for every kind of frame candump
 * writes (standard, extended, remote with and without DLC, error, CAN FD with
 * its flags, empty, overlong length), the time stamp's padding, a buffer too
 * small; the drop counter's wrap-around; the command line (defaults, each
 * option, every refusal with its one line).
 */
#include "fcc_test.h"

#include <string.h>

#include "canrec_log.h"
#include "canrec_opts.h"

static struct canfd_frame frame(canid_t id, uint8_t len, const char *bytes)
{
    struct canfd_frame f;
    memset(&f, 0, sizeof f);
    f.can_id = id;
    f.len = len;
    if (bytes != NULL) {
        memcpy(f.data, bytes, len);
    }
    return f;
}

/* The line of f at 1700000000.123456 on vcan0. */
static void expect_line(const struct canfd_frame *f, bool fd, const char *want)
{
    char buf[CANREC_LINE_MAX];
    const size_t n = canrec_log_line(buf, sizeof buf, 1700000000, 123456, "vcan0", f, fd);
    assert_string_equal(buf, want);
    assert_int_equal(n, strlen(want));
}

static void test_classic_frames(void **state)
{
    (void)state;
    struct canfd_frame f = frame(0x7F0u, 8u, "\xFF\xFF\xFF\xFF\x00\x00\x00\x00");
    expect_line(&f, false, "(1700000000.123456) vcan0 7F0#FFFFFFFF00000000\n");
    f = frame(0x001u, 3u, "\x0a\xbc\x01");
    expect_line(&f, false, "(1700000000.123456) vcan0 001#0ABC01\n");
    f = frame(0x123u, 0u, NULL);
    expect_line(&f, false, "(1700000000.123456) vcan0 123#\n");
    f = frame(CAN_EFF_FLAG | 0x1ABCDEF0u, 2u, "\x12\x34");
    expect_line(&f, false, "(1700000000.123456) vcan0 1ABCDEF0#1234\n");
    f = frame(CAN_EFF_FLAG | 0x5u, 1u, "\x00");
    expect_line(&f, false, "(1700000000.123456) vcan0 00000005#00\n");
    /* a length beyond 8 in a classic frame: 8 bytes, as candump */
    f = frame(0x100u, 12u, "\x01\x02\x03\x04\x05\x06\x07\x08\x09\x0a\x0b\x0c");
    expect_line(&f, false, "(1700000000.123456) vcan0 100#0102030405060708\n");
}

static void test_remote_and_error_frames(void **state)
{
    (void)state;
    struct canfd_frame f = frame(CAN_RTR_FLAG | 0x321u, 0u, NULL);
    expect_line(&f, false, "(1700000000.123456) vcan0 321#R\n");
    f = frame(CAN_RTR_FLAG | 0x321u, 4u, NULL);
    expect_line(&f, false, "(1700000000.123456) vcan0 321#R4\n");
    f = frame(CAN_RTR_FLAG | CAN_EFF_FLAG | 0x12345u, 8u, NULL);
    expect_line(&f, false, "(1700000000.123456) vcan0 00012345#R8\n");
    f = frame(CAN_ERR_FLAG | 0x4u, 8u, "\x00\x04\x00\x00\x00\x00\x00\x00");
    expect_line(&f, false, "(1700000000.123456) vcan0 20000004#0004000000000000\n");
}

static void test_fd_frames(void **state)
{
    (void)state;
    struct canfd_frame f = frame(0x123u, 2u, "\xde\xad");
    f.flags = CANFD_BRS;
    expect_line(&f, true, "(1700000000.123456) vcan0 123##1DEAD\n");
    f = frame(CAN_EFF_FLAG | 0x10u, 0u, NULL);
    f.flags = 0x13u; /* only the low nibble is written */
    expect_line(&f, true, "(1700000000.123456) vcan0 00000010##3\n");
    /* RTR has no meaning in FD: the data is written */
    f = frame(CAN_RTR_FLAG | 0x7u, 1u, "\x55");
    expect_line(&f, true, "(1700000000.123456) vcan0 007##055\n");
    char bytes[64];
    for (int i = 0; i < 64; ++i) {
        bytes[i] = (char)i;
    }
    f = frame(0x7FFu, 64u, bytes);
    char want[CANREC_LINE_MAX];
    char *p = want + sprintf(want, "(1700000000.123456) vcan0 7FF##0");
    for (int i = 0; i < 64; ++i) {
        p += sprintf(p, "%02X", i);
    }
    strcpy(p, "\n");
    expect_line(&f, true, want);
}

static void test_time_stamps(void **state)
{
    (void)state;
    char buf[CANREC_LINE_MAX];
    const struct canfd_frame f = frame(0x1u, 1u, "\x01");
    canrec_log_line(buf, sizeof buf, 0, 0, "can0", &f, false);
    assert_string_equal(buf, "(0000000000.000000) can0 001#01\n");
    canrec_log_line(buf, sizeof buf, 12, 7, "can0", &f, false);
    assert_string_equal(buf, "(0000000012.000007) can0 001#01\n");
    canrec_log_line(buf, sizeof buf, 99999999999, 999999, "can0", &f, false);
    assert_string_equal(buf, "(99999999999.999999) can0 001#01\n");
    canrec_log_line(buf, sizeof buf, INT64_MAX, 0, "vcan15", &f, false);
    assert_string_equal(buf, "(9223372036854775807.000000) vcan15 001#01\n");
    /* out of range: no line */
    assert_int_equal(canrec_log_line(buf, sizeof buf, -1, 0, "can0", &f, false), 0u);
    assert_int_equal(canrec_log_line(buf, sizeof buf, 1, 1000000, "can0", &f, false), 0u);
    assert_int_equal(canrec_log_line(buf, sizeof buf, 1, -1, "can0", &f, false), 0u);
}

static void test_buffer_too_small(void **state)
{
    (void)state;
    char buf[CANREC_LINE_MAX];
    memset(buf, 'x', sizeof buf);
    const struct canfd_frame f = frame(0x1u, 1u, "\x01");
    assert_int_equal(canrec_log_line(buf, 100u, 1, 0, "can0", &f, false), 0u);
    assert_int_equal(buf[0], 'x');  /* nothing written */
    /* the longest line fits in CANREC_LINE_MAX */
    const struct canfd_frame big = frame(CAN_EFF_FLAG | 0x1FFFFFFFu, 64u, NULL);
    const size_t n = canrec_log_line(buf, sizeof buf, INT64_MAX, 999999, "abcdefghijklmno", &big,
                                     true);
    assert_true(n > 0u && n < CANREC_LINE_MAX);
    assert_int_equal(strlen(buf), n);
}

static void test_drops_wrap(void **state)
{
    (void)state;
    assert_int_equal(canrec_drops_since(0u, 0u), 0u);
    assert_int_equal(canrec_drops_since(5u, 12u), 7u);
    assert_int_equal(canrec_drops_since(0xFFFFFFFEu, 1u), 3u);
}

/* canrec ARGS... parsed: the status, the error line in err. */
static int parse(canrec_opts_t *o, char *err, size_t len, int argc, const char **argv)
{
    FILE *devnull = fopen("/dev/null", "w");
    assert_non_null(devnull);
    err[0] = '\0';
    const int rc = canrec_opts_parse(argc, (char **)(uintptr_t)argv, o, devnull, err, len);
    fclose(devnull);
    return rc;
}

#define PARSE(o, err, ...)                                                                   \
    parse((o), (err), sizeof(err), (int)(sizeof((const char *[]){"canrec", __VA_ARGS__}) /  \
                                         sizeof(const char *)),                              \
          (const char *[]){"canrec", __VA_ARGS__})

static void test_options(void **state)
{
    (void)state;
    canrec_opts_t o;
    char err[256];
    assert_int_equal(PARSE(&o, err, "vcan0"), 0);
    assert_string_equal(o.iface, "vcan0");
    assert_null(o.output);
    assert_int_equal(o.rcvbuf, 0u);
    assert_int_equal(o.batch, CANREC_BATCH_DEFAULT);
    assert_int_equal(o.count, 0u);
    assert_int_equal(o.wait_ms, 0u);
    assert_int_equal(o.ring, CANREC_RING_DEFAULT);
    assert_int_equal(PARSE(&o, err, "-R", "4096", "vcan0"), 0);
    assert_int_equal(o.ring, 4096u);
    assert_int_equal(PARSE(&o, err, "--ring=16777216", "vcan0"), 0);
    assert_int_equal(o.ring, CANREC_RING_MAX);
    assert_int_equal(PARSE(&o, err, "-r", "16777216", "-o", "bus.log", "-b", "256", "-n", "3",
                           "-w", "10", "can1"), 0);
    assert_int_equal(o.wait_ms, 10u);
    assert_string_equal(o.iface, "can1");
    assert_string_equal(o.output, "bus.log");
    assert_int_equal(o.rcvbuf, 16777216u);
    assert_int_equal(o.batch, 256u);
    assert_int_equal(o.count, 3u);
    assert_int_equal(PARSE(&o, err, "--rcvbuf=4096", "--batch=1", "vcan0", "--output", "x"), 0);
    assert_int_equal(o.rcvbuf, 4096u);
    assert_int_equal(o.batch, 1u);
    assert_string_equal(o.output, "x");
    assert_int_equal(PARSE(&o, err, "--help"), 1);
    assert_int_equal(PARSE(&o, err, "vcan0", "-h"), 1);
}

static void expect_refused(int rc, const char *err, const char *words)
{
    assert_int_equal(rc, -1);
    if (strstr(err, words) == NULL) {
        print_error("error line '%s' lacks '%s'\n", err, words);
        fail();
    }
    assert_null(strchr(err, '\n'));
}

static void test_refusals(void **state)
{
    (void)state;
    canrec_opts_t o;
    char err[256];
    expect_refused(PARSE(&o, err, "-r", "1000"), err, "no interface given");
    expect_refused(PARSE(&o, err, "vcan0", "vcan1"), err, "one interface");
    expect_refused(PARSE(&o, err, "vcan0", "-b", "0"), err, "-b: 0 is outside 1..256");
    expect_refused(PARSE(&o, err, "vcan0", "-b", "257"), err, "outside 1..256");
    expect_refused(PARSE(&o, err, "vcan0", "-R", "4095"), err, "-R: 4095 is outside 4096..16777216");
    expect_refused(PARSE(&o, err, "vcan0", "-r", "-5"), err, "not a non-negative integer");
    expect_refused(PARSE(&o, err, "vcan0", "-r", "0"), err, "outside");
    expect_refused(PARSE(&o, err, "vcan0", "-n", "x"), err, "-n: 'x'");
    expect_refused(PARSE(&o, err, "vcan0", "-w", "101"), err, "-w: 101 is outside 0..100");
    expect_refused(PARSE(&o, err, "vcan0", "-o"), err, "option -o needs a value");
    expect_refused(PARSE(&o, err, "vcan0", "-o", ""), err, "empty file name");
    expect_refused(PARSE(&o, err, "vcan0", "-l"), err, "unknown option '-l'");
    expect_refused(PARSE(&o, err, "a_very_long_interface_name"), err, "longer than 15");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_classic_frames),    cmocka_unit_test(test_remote_and_error_frames),
        cmocka_unit_test(test_fd_frames),         cmocka_unit_test(test_time_stamps),
        cmocka_unit_test(test_buffer_too_small),  cmocka_unit_test(test_drops_wrap),
        cmocka_unit_test(test_options),           cmocka_unit_test(test_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
