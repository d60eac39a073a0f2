/*
 * test_slcan.c -- the SLCAN codec and device (firmware/bus/fcc_slcan.h): frames and
 * commands by hand, encode/parse round trips over every DLC and the id limits,
 * then bad input: garbled lines, overlong lines, line noise, a writer with no
 * room, and a long run of pseudo-random bytes that must neither crash, hang
 * nor leave the device unable to read the next good line.
 */
#include "fcc_test.h"

#include <string.h>

#include "fcc_slcan.h"

/* The serial line seen from the host: what the device wrote. */
typedef struct {
    char buf[4096];
    size_t n;
    size_t room; /* bytes the writer still accepts (SIZE_MAX: unlimited) */
} line_t;

static fcc_status_t line_write(void *ctx, const uint8_t *bytes, size_t n)
{
    line_t *l = ctx;
    if (n > l->room || l->n + n > sizeof l->buf) {
        return FCC_ERR_AGAIN;
    }
    memcpy(&l->buf[l->n], bytes, n);
    l->n += n;
    l->room -= n;
    return FCC_OK;
}

static void dev_start(fcc_slcan_dev_t *dev, line_t *l)
{
    memset(l, 0, sizeof *l);
    l->room = SIZE_MAX;
    assert_int_equal(fcc_slcan_dev_init(dev, line_write, l, "V0110", "NFCC1"), FCC_OK);
}

/* Feeds a string; returns how many frames came out, the last in *last. */
static int feed(fcc_slcan_dev_t *dev, const char *s, size_t n, fcc_can_frame_t *last)
{
    int frames = 0;
    for (size_t i = 0u; i < n; ++i) {
        fcc_can_frame_t f;
        const fcc_status_t st = fcc_slcan_dev_byte(dev, (uint8_t)s[i], &f);
        if (st == FCC_OK) {
            ++frames;
            if (last != NULL) {
                *last = f;
            }
        } else {
            assert_int_equal(st, FCC_ERR_AGAIN);
        }
    }
    return frames;
}

#define FEED(dev, lit, last) feed((dev), (lit), sizeof(lit) - 1u, (last))

static void expect_line(line_t *l, const char *want)
{
    assert_int_equal(l->n, strlen(want));
    assert_memory_equal(l->buf, want, l->n);
    l->n = 0u;
}

/* A device opened ('O', answered CR) on a fresh line. */
static void dev_open(fcc_slcan_dev_t *dev, line_t *l)
{
    dev_start(dev, l);
    assert_int_equal(FEED(dev, "O\r", NULL), 0);
    expect_line(l, "\r");
}

static void test_parse_frames(void **state)
{
    (void)state;
    fcc_slcan_msg_t m;
    assert_int_equal(fcc_slcan_parse("t1233112233", 11u, &m), FCC_OK);
    assert_int_equal(m.cmd, FCC_SLCAN_CMD_FRAME);
    assert_false(m.extended);
    assert_int_equal(m.frame.id, 0x123);
    assert_int_equal(m.frame.dlc, 3);
    assert_int_equal(m.frame.data[0], 0x11);
    assert_int_equal(m.frame.data[2], 0x33);
    assert_int_equal(fcc_slcan_parse("T1FFFFFFF2aBcD", 14u, &m), FCC_OK);
    assert_true(m.extended);
    assert_int_equal(m.frame.id, 0x1FFFFFFF);
    assert_int_equal(m.frame.data[0], 0xAB);
    assert_int_equal(m.frame.data[1], 0xCD);
    assert_int_equal(fcc_slcan_parse("t7FF0", 5u, &m), FCC_OK);
    assert_int_equal(m.frame.dlc, 0);
    assert_int_equal(fcc_slcan_parse("r1008", 5u, &m), FCC_OK);
    assert_int_equal(m.cmd, FCC_SLCAN_CMD_REMOTE);
    assert_int_equal(m.frame.dlc, 8);
    assert_int_equal(fcc_slcan_parse("R000000012", 10u, &m), FCC_OK);
    assert_true(m.extended);
}

static void test_parse_commands(void **state)
{
    (void)state;
    fcc_slcan_msg_t m;
    static const struct {
        const char *line;
        fcc_slcan_cmd_t cmd;
        uint16_t arg;
    } ok[] = {{"O", FCC_SLCAN_CMD_OPEN, 0},      {"L", FCC_SLCAN_CMD_LISTEN, 0},
              {"C", FCC_SLCAN_CMD_CLOSE, 0},     {"S0", FCC_SLCAN_CMD_BITRATE, 0},
              {"S8", FCC_SLCAN_CMD_BITRATE, 8},  {"s031C", FCC_SLCAN_CMD_BTR, 0x031C},
              {"V", FCC_SLCAN_CMD_VERSION, 0},   {"v", FCC_SLCAN_CMD_FW_VERSION, 0},
              {"N", FCC_SLCAN_CMD_SERIAL, 0},    {"F", FCC_SLCAN_CMD_STATUS, 0},
              {"Z0", FCC_SLCAN_CMD_TIMESTAMP, 0}, {"Z1", FCC_SLCAN_CMD_TIMESTAMP, 1}};
    for (size_t i = 0u; i < sizeof ok / sizeof ok[0]; ++i) {
        assert_int_equal(fcc_slcan_parse(ok[i].line, strlen(ok[i].line), &m), FCC_OK);
        assert_int_equal(m.cmd, ok[i].cmd);
        assert_int_equal(m.arg, ok[i].arg);
    }
}

static void test_parse_rejects(void **state)
{
    (void)state;
    static const char *const bad[] = {
        "t",            /* no id */
        "t12",          /* short id */
        "t123",         /* no DLC */
        "t1239",        /* DLC 9 */
        "t8000",        /* id beyond 11 bits */
        "T200000000",   /* id beyond 29 bits */
        "t12321",       /* one data digit missing */
        "t1231112",     /* one data digit too many */
        "t12G1",        /* not hex */
        "t1231zz",      /* data not hex */
        "r12311",       /* remote frame with data */
        "S9", "S", "S12", "Z3", "s12", "s12345", "sGGGG",
        "O1", "CC", "x", "?", " O", "o",
    };
    fcc_slcan_msg_t m;
    for (size_t i = 0u; i < sizeof bad / sizeof bad[0]; ++i) {
        if (fcc_slcan_parse(bad[i], strlen(bad[i]), &m) != FCC_ERR_FORMAT) {
            fail_msg("'%s' was accepted", bad[i]);
        }
    }
    assert_int_equal(fcc_slcan_parse("O", 0u, &m), FCC_ERR_FORMAT);
    assert_int_equal(fcc_slcan_parse(NULL, 1u, &m), FCC_ERR_ARG);
    assert_int_equal(fcc_slcan_parse("O", 1u, NULL), FCC_ERR_ARG);
}

static void test_encode_round_trip(void **state)
{
    (void)state;
    for (uint8_t dlc = 0u; dlc <= 8u; ++dlc) {
        for (int ext = 0; ext <= 1; ++ext) {
            fcc_can_frame_t f = {ext ? 0x1ABCDEF0u : 0x7FFu, dlc, {0}, 0u};
            for (uint8_t i = 0u; i < dlc; ++i) {
                f.data[i] = (uint8_t)(0x0F + 37u * i);
            }
            char line[FCC_SLCAN_FRAME_CHARS];
            size_t n = 0u;
            assert_int_equal(fcc_slcan_encode(&f, ext != 0, line, sizeof line, &n), FCC_OK);
            assert_int_equal(n, (ext ? 10u : 5u) + 2u * dlc + 1u);
            assert_int_equal(line[n - 1u], '\r');
            fcc_slcan_msg_t m;
            assert_int_equal(fcc_slcan_parse(line, n - 1u, &m), FCC_OK);
            assert_int_equal(m.cmd, FCC_SLCAN_CMD_FRAME);
            assert_int_equal(m.extended, ext != 0);
            assert_int_equal(m.frame.id, f.id);
            assert_int_equal(m.frame.dlc, dlc);
            assert_memory_equal(m.frame.data, f.data, dlc);
        }
    }
    const fcc_can_frame_t f = {0x010u, 2u, {0xA5, 0x0F}, 0u};
    char line[FCC_SLCAN_FRAME_CHARS];
    size_t n = 0u;
    assert_int_equal(fcc_slcan_encode(&f, false, line, sizeof line, &n), FCC_OK);
    assert_memory_equal(line, "t0102A50F\r", n);
    assert_int_equal(fcc_slcan_encode(&f, false, line, 9u, &n), FCC_ERR_SIZE);
    const fcc_can_frame_t big_id = {0x800u, 0u, {0}, 0u};
    assert_int_equal(fcc_slcan_encode(&big_id, false, line, sizeof line, &n), FCC_ERR_RANGE);
    const fcc_can_frame_t big_dlc = {0x1u, 9u, {0}, 0u};
    assert_int_equal(fcc_slcan_encode(&big_dlc, false, line, sizeof line, &n), FCC_ERR_RANGE);
}

/* slcand -o -c -s6 as the Linux side sends it, then frames both ways. */
static void test_device_session(void **state)
{
    (void)state;
    fcc_slcan_dev_t dev;
    line_t l;
    dev_start(&dev, &l);
    fcc_can_frame_t f;
    const fcc_can_frame_t out = {0x700u, 1u, {0x42}, 0u};
    assert_int_equal(fcc_slcan_dev_send(&dev, &out), FCC_ERR_AGAIN); /* closed: silent */
    assert_int_equal(l.n, 0u);
    assert_int_equal(FEED(&dev, "t0101AA\r", &f), 0); /* closed: dropped */
    assert_int_equal(dev.cnt.ignored, 1u);
    assert_int_equal(FEED(&dev, "\r\r\rC\r", NULL), 0);
    expect_line(&l, "\r");
    assert_int_equal(FEED(&dev, "S6\r", NULL), 0);
    expect_line(&l, "\r");
    assert_int_equal(dev.bitrate, 6u);
    assert_false(fcc_slcan_dev_take_opened(&dev));
    assert_int_equal(FEED(&dev, "O\r", NULL), 0);
    expect_line(&l, "\r");
    assert_true(fcc_slcan_dev_take_opened(&dev));
    assert_false(fcc_slcan_dev_take_opened(&dev));
    assert_int_equal(FEED(&dev, "S4\r", NULL), 0); /* open: refused */
    expect_line(&l, "\a");
    assert_int_equal(FEED(&dev, "t0202BEEF\r\n", &f), 1);
    assert_int_equal(f.id, 0x020u);
    assert_int_equal(f.dlc, 2u);
    assert_int_equal(f.data[1], 0xEF);
    assert_int_equal(l.n, 0u); /* a good frame is not answered */
    assert_int_equal(FEED(&dev, "T000001001AA\r", NULL), 0); /* extended: ignored */
    assert_int_equal(fcc_slcan_dev_send(&dev, &out), FCC_OK);
    expect_line(&l, "t700142\r");
    assert_int_equal(FEED(&dev, "V\rN\rv\rF\rZ0\rZ1\r", NULL), 0);
    expect_line(&l, "V0110\rNFCC1\rv0110\rF00\r\r\a");
    assert_int_equal(FEED(&dev, "C\r", NULL), 0);
    expect_line(&l, "\r");
    assert_int_equal(fcc_slcan_dev_send(&dev, &out), FCC_ERR_AGAIN);
    assert_int_equal(FEED(&dev, "L\r", NULL), 0);
    expect_line(&l, "\r");
    assert_true(fcc_slcan_dev_take_opened(&dev));
    assert_int_equal(FEED(&dev, "t0200\r", &f), 1);             /* listen-only receives */
    assert_int_equal(fcc_slcan_dev_send(&dev, &out), FCC_ERR_AGAIN); /* but never sends */
    assert_int_equal(l.n, 0u);
    assert_int_equal(dev.cnt.frames_rx, 2u);
    assert_int_equal(dev.cnt.frames_tx, 1u);
    assert_int_equal(dev.cnt.tx_refused, 3u);
}

static void test_device_garbage(void **state)
{
    (void)state;
    fcc_slcan_dev_t dev;
    line_t l;
    dev_open(&dev, &l);
    /* garbled lines */
    assert_int_equal(FEED(&dev, "t12\rxyz\rt0102AAB\r", NULL), 0);
    expect_line(&l, "\a\a\a");
    assert_int_equal(dev.cnt.line_errors, 3u);
    /* an overlong line: discarded up to its CR, the next line is read */
    char longline[200];
    memset(longline, '7', sizeof longline);
    longline[0] = 't';
    fcc_can_frame_t f;
    assert_int_equal(feed(&dev, longline, sizeof longline, &f), 0);
    assert_int_equal(FEED(&dev, "\rt0101AA\r", &f), 1);
    expect_line(&l, "\a");
    assert_int_equal(dev.cnt.overlong, 1u);
    assert_int_equal(f.data[0], 0xAA);
    /* a line of exactly the limit is still read (then refused: no such line) */
    char limit[FCC_SLCAN_LINE_MAX + 1u];
    memset(limit, 'F', FCC_SLCAN_LINE_MAX);
    limit[FCC_SLCAN_LINE_MAX] = '\r';
    assert_int_equal(feed(&dev, limit, sizeof limit, NULL), 0);
    expect_line(&l, "\a");
    assert_int_equal(dev.cnt.overlong, 1u);
    /* line noise inside a frame: the whole line is refused */
    static const char noisy[] = {'t', '0', '1', '0', '\x00', '1', 'A', 'A', '\r'};
    assert_int_equal(feed(&dev, noisy, sizeof noisy, NULL), 0);
    expect_line(&l, "\a");
    assert_int_equal(dev.cnt.noise, 1u);
    static const char high[] = {'\xff', '\x80', '\r', 'N', '\r'};
    assert_int_equal(feed(&dev, high, sizeof high, NULL), 0);
    expect_line(&l, "\aNFCC1\r");
    assert_int_equal(dev.cnt.line_errors, 7u);
    /* commands that make no sense now */
    assert_int_equal(FEED(&dev, "O\rs031C\r", NULL), 0);
    expect_line(&l, "\a\a");
}

static void test_device_writer_full(void **state)
{
    (void)state;
    fcc_slcan_dev_t dev;
    line_t l;
    dev_open(&dev, &l);
    l.room = 10u; /* room for one short frame, not for a second */
    const fcc_can_frame_t out = {0x701u, 2u, {1, 2}, 0u};
    assert_int_equal(fcc_slcan_dev_send(&dev, &out), FCC_OK);
    assert_int_equal(fcc_slcan_dev_send(&dev, &out), FCC_ERR_AGAIN);
    expect_line(&l, "t70120102\r"); /* all or nothing: no half line */
    l.room = 0u;
    assert_int_equal(FEED(&dev, "V\r", NULL), 0);
    assert_int_equal(dev.cnt.replies_lost, 1u);
    l.room = SIZE_MAX;
    assert_int_equal(FEED(&dev, "F\r", NULL), 0);
    expect_line(&l, "F08\r"); /* data overrun flagged */
    const fcc_can_frame_t bad = {0x800u, 1u, {0}, 0u};
    assert_int_equal(fcc_slcan_dev_send(&dev, &bad), FCC_ERR_RANGE);
    assert_int_equal(fcc_slcan_dev_send(NULL, &out), FCC_ERR_ARG);
    assert_int_equal(fcc_slcan_dev_init(&dev, line_write, &l, "V01", "NFCC1"), FCC_ERR_ARG);
}

/* 200 000 pseudo-random bytes (xorshift, CR-rich): no crash (ASan/UBSan
 * builds), every byte consumed in bounded time, the counters add up, and the
 * next good line is still understood. */
static void test_device_random_bytes(void **state)
{
    (void)state;
    fcc_slcan_dev_t dev;
    line_t l;
    dev_open(&dev, &l);
    uint32_t x = 2463534242u;
    uint32_t frames = 0u;
    for (uint32_t i = 0u; i < 200000u; ++i) {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        const uint8_t alphabet[] = "tT0123456789ABCDEFabcdefOCSLrR\r\r\r\n";
        const uint8_t byte = ((x >> 24) < 32u) ? (uint8_t)x : alphabet[x % (sizeof alphabet - 1u)];
        fcc_can_frame_t f;
        const fcc_status_t st = fcc_slcan_dev_byte(&dev, byte, &f);
        if (st == FCC_OK) {
            ++frames;
            assert_true(f.id <= FCC_CAN_STD_ID_MAX);
            assert_true(f.dlc <= FCC_CAN_MAX_DLC);
        } else {
            assert_int_equal(st, FCC_ERR_AGAIN);
        }
        assert_true(dev.len <= FCC_SLCAN_LINE_MAX);
        l.n = 0u; /* the host reads everything */
    }
    assert_int_equal(frames, dev.cnt.frames_rx);
    assert_true(dev.cnt.line_errors > 1000u);
    assert_true(dev.cnt.noise > 0u);
    assert_true(dev.cnt.overlong > 0u);
    fcc_can_frame_t f;
    assert_int_equal(FEED(&dev, "\rC\rO\rt1231FF\r", &f), 1);
    assert_int_equal(f.id, 0x123u);
    assert_int_equal(f.data[0], 0xFF);
}

/* Z2 (slcan_bridge): while closed only; then every data frame line carries
 * its bus stamp (8 hex digits after the data), handed out in rx_stamp_us, and
 * a line without one is refused -- as a stamped line is without Z2. */
static void test_device_bus_stamps(void **state)
{
    (void)state;
    fcc_slcan_dev_t dev;
    line_t l;
    dev_start(&dev, &l);
    fcc_can_frame_t f;
    assert_int_equal(FEED(&dev, "Z2\rO\r", NULL), 0);
    expect_line(&l, "\r\r");
    assert_int_equal(FEED(&dev, "t0202BEEF89ABCDEF\r", &f), 1);
    assert_int_equal(f.id, 0x020u);
    assert_int_equal(f.data[1], 0xEF);
    assert_int_equal(dev.rx_stamp_us, 0x89ABCDEFu);
    assert_int_equal(FEED(&dev, "t0000000000FF\r", &f), 1); /* DLC 0, stamp 0xFF */
    assert_int_equal(dev.rx_stamp_us, 0xFFu);
    assert_int_equal(l.n, 0u);
    const uint32_t errors = dev.cnt.line_errors;
    assert_int_equal(FEED(&dev, "t0202BEEF\r", NULL), 0);     /* unstamped under Z2 */
    assert_int_equal(FEED(&dev, "t0202BEEF89ABCDE\r", NULL), 0); /* 7 digits */
    assert_int_equal(FEED(&dev, "t0202BEEF89ABCDEG\r", NULL), 0); /* not hex */
    assert_int_equal(FEED(&dev, "Z2\r", NULL), 0);             /* not while open */
    expect_line(&l, "\a\a\a\a");
    assert_int_equal(dev.cnt.line_errors, errors + 4u);
    assert_int_equal(FEED(&dev, "C\rZ0\rO\rt0202BEEF89ABCDEF\rt0200\r", &f), 1); /* Z0: off */
    expect_line(&l, "\r\r\r\a");
    assert_int_equal(f.dlc, 0u);
    fcc_slcan_msg_t m;
    assert_int_equal(fcc_slcan_parse("r0202BEEF89AB", 13u, &m), FCC_ERR_FORMAT); /* remote: none */
}

/* Each refusal decided by one argument or one character on its own (scripts/test coverage). */
static void test_each_refusal_alone(void **state)
{
    (void)state;
    fcc_slcan_msg_t m;
    char longline[FCC_SLCAN_LINE_MAX + 1u];
    memset(longline, 'O', sizeof longline);
    assert_int_equal(fcc_slcan_parse(longline, sizeof longline, &m), FCC_ERR_FORMAT);
    /* S and Z: two characters, a digit in range */
    assert_int_equal(fcc_slcan_parse("S", 1u, &m), FCC_ERR_FORMAT);
    assert_int_equal(fcc_slcan_parse("S/", 2u, &m), FCC_ERR_FORMAT);
    assert_int_equal(fcc_slcan_parse("S9", 2u, &m), FCC_ERR_FORMAT);
    assert_int_equal(fcc_slcan_parse("Z3", 2u, &m), FCC_ERR_FORMAT);
    assert_int_equal(fcc_slcan_parse("S8", 2u, &m), FCC_OK);
    assert_int_equal(m.cmd, FCC_SLCAN_CMD_BITRATE);
    assert_int_equal(m.arg, 8u);
    assert_int_equal(fcc_slcan_parse("Z1", 2u, &m), FCC_OK);
    assert_int_equal(m.cmd, FCC_SLCAN_CMD_TIMESTAMP);
    assert_int_equal(m.arg, 1u);
    /* encode */
    fcc_can_frame_t f;
    memset(&f, 0, sizeof f);
    char out[32];
    size_t n = 0u;
    assert_int_equal(fcc_slcan_encode(NULL, false, out, sizeof out, &n), FCC_ERR_ARG);
    assert_int_equal(fcc_slcan_encode(&f, false, NULL, sizeof out, &n), FCC_ERR_ARG);
    assert_int_equal(fcc_slcan_encode(&f, false, out, sizeof out, NULL), FCC_ERR_ARG);
    /* the device: each argument of init, then of byte and send */
    fcc_slcan_dev_t dev;
    line_t l;
    memset(&l, 0, sizeof l);
    assert_int_equal(fcc_slcan_dev_init(NULL, line_write, &l, "V0110", "NFCC1"), FCC_ERR_ARG);
    assert_int_equal(fcc_slcan_dev_init(&dev, NULL, &l, "V0110", "NFCC1"), FCC_ERR_ARG);
    assert_int_equal(fcc_slcan_dev_init(&dev, line_write, &l, NULL, "NFCC1"), FCC_ERR_ARG);
    assert_int_equal(fcc_slcan_dev_init(&dev, line_write, &l, "V0110", NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_slcan_dev_init(&dev, line_write, &l, "V011", "NFCC1"), FCC_ERR_ARG);
    assert_int_equal(fcc_slcan_dev_init(&dev, line_write, &l, "X0110", "NFCC1"), FCC_ERR_ARG);
    assert_int_equal(fcc_slcan_dev_init(&dev, line_write, &l, "V0110", "NFCC"), FCC_ERR_ARG);
    assert_int_equal(fcc_slcan_dev_init(&dev, line_write, &l, "V0110", "MFCC1"), FCC_ERR_ARG);
    dev_start(&dev, &l);
    assert_int_equal(fcc_slcan_dev_byte(NULL, 'O', &f), FCC_ERR_ARG);
    assert_int_equal(fcc_slcan_dev_byte(&dev, 'O', NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_slcan_dev_send(NULL, &f), FCC_ERR_ARG);
    assert_int_equal(fcc_slcan_dev_send(&dev, NULL), FCC_ERR_ARG);
    assert_false(fcc_slcan_dev_take_opened(NULL));
    /* an LF is skipped only where it ends a CR LF pair: after noise it is noise too */
    assert_int_equal(FEED(&dev, "\n", NULL), 0);
    assert_int_equal(l.n, 0u);
    static const char noisy_lf[] = {'\x01', '\n', '\r'};
    assert_int_equal(feed(&dev, noisy_lf, sizeof noisy_lf, NULL), 0);
    expect_line(&l, "\a");
    assert_int_equal(FEED(&dev, "V\nx\r", NULL), 0); /* inside a line: noise */
    expect_line(&l, "\a");
    assert_int_equal(dev.cnt.noise, 2u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parse_frames),        cmocka_unit_test(test_parse_commands),
        cmocka_unit_test(test_parse_rejects),       cmocka_unit_test(test_encode_round_trip),
        cmocka_unit_test(test_device_session),      cmocka_unit_test(test_device_garbage),
        cmocka_unit_test(test_device_writer_full),  cmocka_unit_test(test_device_random_bytes),
        cmocka_unit_test(test_each_refusal_alone),  cmocka_unit_test(test_device_bus_stamps),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
