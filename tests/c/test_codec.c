/*
 * test_codec.c -- the C codec against the golden frames cantools wrote
 * (tests/vectors/bus/, tests/gen_bus_vectors.py): decode every frame to the
 * physical values cantools decoded, re-encode byte for byte (from the decoded
 * values and from the values as written), and reject every bad frame with the
 * expected verdict and counter.
 */
#include "fcc_test.h"

#include <stdlib.h>
#include <string.h>

#include "fcc_bus.h"

#define VEC_DIR FCC_SOURCE_DIR "/tests/vectors/bus/"
#define ALL_MSGS ((uint64_t)((1uLL << FCC_MSG_COUNT) - 1u))

static size_t parse_hex(const char *hex, uint8_t *out, size_t max)
{
    size_t n = 0u;
    while (hex[0] != '\0' && hex[1] != '\0' && n < max) {
        char byte[3] = {hex[0], hex[1], '\0'};
        out[n++] = (uint8_t)strtoul(byte, NULL, 16);
        hex += 2;
    }
    return n;
}

static int signal_index(const fcc_bus_msg_desc_t *d, const char *name)
{
    for (uint32_t i = 0u; i < d->n_signals; ++i) {
        if (strcmp(d->signals[i].name, name) == 0) {
            return (int)i;
        }
    }
    fail_msg("%s has no signal %s", d->name, name);
    return -1;
}

typedef struct {
    unsigned int id;
    int counter; /* -1: unprotected */
    uint8_t bytes[8];
    char name[48];
    char *pairs; /* "sig=value sig=value ..." */
} vec_t;

static int parse_frame_line(char *line, vec_t *v)
{
    char counter[8], hex[32];
    int used = 0;
    if (line[0] == '#' ||
        sscanf(line, "%x %7s %31s %47s %n", &v->id, counter, hex, v->name, &used) != 4) {
        return 0;
    }
    v->counter = (strcmp(counter, "-") == 0) ? -1 : atoi(counter);
    assert_int_equal(parse_hex(hex, v->bytes, 8u), 8u);
    v->pairs = line + used;
    return 1;
}

/* Compare the decoded values with the line's, and fill `from_text` with them. */
static void check_values(fcc_msg_t msg, const fcc_msg_data_t *decoded, char *pairs,
                         fcc_msg_data_t *from_text)
{
    const fcc_bus_msg_desc_t *d = fcc_bus_desc(msg);
    unsigned int seen = 0u;
    for (char *tok = strtok(pairs, " \n"); tok != NULL; tok = strtok(NULL, " \n")) {
        char *eq = strchr(tok, '=');
        assert_non_null(eq);
        *eq = '\0';
        const int s = signal_index(d, tok);
        fcc_real_t real;
        int64_t integer;
        fcc_assert_ok(fcc_bus_signal_get(msg, (uint32_t)s, decoded, &real, &integer));
        if (d->signals[s].phys_type == FCC_FIELD_REAL) {
            const double expected = strtod(eq + 1, NULL);
            const double lsb = 1.0 / (double)d->signals[s].inv_scale;
            /* float: the decoded value is the nearest float, within 0.25 LSB by design */
            fcc_assert_close(real, expected, 0.0, FCC_TEST_TOL(1e-6, 0.25) * lsb);
            fcc_assert_ok(fcc_bus_signal_set(msg, (uint32_t)s, from_text, (fcc_real_t)expected, 0));
        } else {
            const long long expected = strtoll(eq + 1, NULL, 10);
            assert_true(integer == expected);
            fcc_assert_ok(fcc_bus_signal_set(msg, (uint32_t)s, from_text, FCC_R(0.0), expected));
        }
        ++seen;
    }
    assert_int_equal(seen, d->n_signals);
}

static void reencode_and_compare(fcc_msg_t msg, const fcc_msg_data_t *data, const vec_t *v)
{
    uint8_t out[8];
    fcc_assert_ok(fcc_bus_pack(msg, data, out));
    if (v->counter >= 0) {
        fcc_assert_ok(fcc_e2e_protect(fcc_bus_desc(msg)->data_id, (uint8_t)v->counter, out));
    }
    assert_memory_equal(out, v->bytes, 8);
}

static void test_golden_frames(void **state)
{
    (void)state;
    FILE *f = fopen(VEC_DIR "frames.txt", "r");
    assert_non_null(f);
    char line[1024];
    int n = 0;
    uint64_t seen_msgs = 0u;
    vec_t v;
    while (fgets(line, sizeof line, f) != NULL) {
        if (!parse_frame_line(line, &v)) {
            continue;
        }
        fcc_msg_t msg;
        fcc_assert_ok(fcc_bus_find(v.id, &msg));
        const fcc_bus_msg_desc_t *d = fcc_bus_desc(msg);
        assert_string_equal(d->name, v.name);
        assert_int_equal(v.counter >= 0, d->data_id != 0u);
        if (v.counter >= 0) {
            assert_int_equal(v.bytes[0], fcc_e2e_frame_crc(d->data_id, v.bytes));
            assert_int_equal(v.bytes[1] & 0x0Fu, v.counter);
        }
        fcc_msg_data_t decoded, from_text;
        memset(&from_text, 0, sizeof from_text);
        fcc_assert_ok(fcc_bus_decode(msg, v.bytes, &decoded));
        check_values(msg, &decoded, v.pairs, &from_text);
        reencode_and_compare(msg, &decoded, &v);
        reencode_and_compare(msg, &from_text, &v);
        seen_msgs |= (uint64_t)1u << (uint32_t)msg;
        ++n;
    }
    fclose(f);
    assert_int_equal(seen_msgs, ALL_MSGS); /* every message of the DBC is covered */
    assert_true(n >= 6 * (int)FCC_MSG_COUNT);
}

static fcc_bus_verdict_t verdict_of(const char *s)
{
    static const char *const names[] = {"PASS", "UNKNOWN_ID", "WRONG_DLC", "E2E", "OUT_OF_RANGE"};
    for (unsigned int i = 0u; i < 5u; ++i) {
        if (strcmp(s, names[i]) == 0) {
            return (fcc_bus_verdict_t)i;
        }
    }
    fail_msg("unknown verdict %s", s);
    return FCC_BUS_PASS;
}

static uint32_t rejected_total(const fcc_bus_counters_t *c)
{
    return c->unknown_id + c->wrong_dlc + c->out_of_range + c->e2e[FCC_E2E_ERROR];
}

static void test_rejects(void **state)
{
    (void)state;
    FILE *f = fopen(VEC_DIR "rejects.txt", "r");
    assert_non_null(f);
    char line[256];
    int n = 0;
    while (fgets(line, sizeof line, f) != NULL) {
        unsigned int id, dlc;
        char hex[32], verdict[32], e2e[32];
        if (line[0] == '#' || sscanf(line, "%x %u %31s %31s %31s", &id, &dlc, hex, verdict, e2e) != 5) {
            continue;
        }
        fcc_bus_t bus;
        fcc_assert_ok(fcc_bus_init_masks(&bus, ALL_MSGS, 0u));
        fcc_can_frame_t fr;
        memset(&fr, 0, sizeof fr);
        fr.id = id;
        fr.dlc = (uint8_t)dlc;
        assert_int_equal(parse_hex(hex, fr.data, 8u), dlc);
        fcc_bus_rx_msg_t m;
        const fcc_status_t st = fcc_bus_receive(&bus, &fr, &m);
        const fcc_bus_verdict_t want = verdict_of(verdict);
        assert_int_equal(m.verdict, want);
        assert_string_equal(fcc_e2e_status_str(m.e2e), e2e);
        fcc_bus_counters_t c;
        fcc_assert_ok(fcc_bus_get_counters(&bus, &c));
        if (want == FCC_BUS_PASS) {
            fcc_assert_ok(st);
            assert_int_equal(rejected_total(&c), 0u);
        } else {
            assert_int_not_equal(st, FCC_OK);
            assert_int_equal(rejected_total(&c), 1u); /* exactly one counter moved */
        }
        assert_int_equal(c.unknown_id, want == FCC_BUS_UNKNOWN_ID);
        assert_int_equal(c.wrong_dlc, want == FCC_BUS_WRONG_DLC);
        assert_int_equal(c.out_of_range, want == FCC_BUS_OUT_OF_RANGE);
        ++n;
    }
    fclose(f);
    assert_true(n >= 3 * (int)FCC_MSG_COUNT);
}

static void test_table_is_sorted_and_consistent(void **state)
{
    (void)state;
    for (unsigned int i = 0u; i < (unsigned int)FCC_MSG_COUNT; ++i) {
        const fcc_bus_msg_desc_t *d = &fcc_bus_msg_table[i];
        if (i > 0u) {
            assert_true(fcc_bus_msg_table[i - 1u].id < d->id);
        }
        fcc_msg_t m;
        fcc_assert_ok(fcc_bus_find(d->id, &m));
        assert_int_equal(m, i);
        assert_true(d->n_signals > 0u);
        assert_true(d->senders != 0u);
        for (uint32_t s = 0u; s < d->n_signals; ++s) {
            assert_true(d->signals[s].raw_min <= d->signals[s].raw_max);
            if (d->signals[s].phys_type == FCC_FIELD_REAL) {
                /* float exactness by design: |raw| <= 2^21 for every scaled signal */
                assert_true(d->signals[s].raw_max <= (1 << 21));
                assert_true(d->signals[s].raw_min >= -(1 << 21));
            }
        }
    }
    fcc_msg_t m;
    assert_int_equal(fcc_bus_find(0x124u, &m), FCC_ERR_RANGE);
    assert_int_equal(fcc_bus_find(0x7F0u, NULL), FCC_ERR_ARG);
    assert_null(fcc_bus_desc(FCC_MSG_COUNT));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_table_is_sorted_and_consistent),
        cmocka_unit_test(test_golden_frames),
        cmocka_unit_test(test_rejects),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
