/*
 * test_canbus.c -- canbus's model (firmware/tools/canbus): frame lengths
 * against hil.bus.busload.frame_bits (tests/vectors/canbus/frame_bits.txt,
 * tests/gen_canbus_vectors.py), arbitration between nodes in time, the two
 * queue policies, determinism; the histogram's percentiles, the JSON line,
 * the command line.
 */
#include "fcc_test.h"

#include <string.h>

#include "canbus_core.h"
#include "canbus_frame.h"
#include "canbus_hist.h"
#include "canbus_opts.h"
#include "canbus_stats.h"

#define VEC_FILE FCC_SOURCE_DIR "/tests/vectors/canbus/frame_bits.txt"
#define BIT_500K 2000u /* ns */

static canbus_frame_t frame(uint32_t id, bool ext, uint8_t dlc, uint8_t fill)
{
    canbus_frame_t f;
    memset(&f, 0, sizeof f);
    f.id = id;
    f.ext = ext;
    f.dlc = dlc;
    memset(f.data, fill, dlc);
    return f;
}

static void init_bus(canbus_core_t *c, uint32_t nodes, const canbus_policy_t *policy)
{
    assert_int_equal(canbus_core_init(c, 500000u, nodes, policy), FCC_OK);
}

static void queue(canbus_core_t *c, uint32_t node, const canbus_frame_t *f, uint64_t t)
{
    assert_int_equal(canbus_core_queue(c, node, f, t), FCC_OK);
}

/* Every frame that ends by t, into out (at most max): how many. */
static size_t run_until(canbus_core_t *c, uint64_t t, canbus_done_t *out, size_t max)
{
    size_t n = 0u;
    canbus_done_t d;
    while (canbus_core_advance(c, t, &d)) {
        assert_true(n < max);
        out[n++] = d;
    }
    return n;
}

/* ---- frame length and arbitration ------------------------------------------------------- */

static void test_frame_bits_match_python(void **state)
{
    (void)state;
    FILE *f = fopen(VEC_FILE, "r");
    assert_non_null(f);
    char line[160];
    unsigned checked = 0u;
    unsigned seen[2][2][9];
    memset(seen, 0, sizeof seen);
    while (fgets(line, sizeof line, f) != NULL) {
        if (line[0] == '#') {
            continue;
        }
        unsigned width, remote, dlc, bits;
        unsigned long id;
        char data[40];
        assert_int_equal(sscanf(line, "%u %u %lx %u %39s %u", &width, &remote, &id, &dlc, data,
                                &bits), 6);
        canbus_frame_t fr = frame((uint32_t)id, width == 29u, (uint8_t)dlc, 0u);
        fr.rtr = remote == 1u;
        if (!fr.rtr && dlc > 0u) {
            assert_int_equal(fcc_test_hex(data, fr.data, sizeof fr.data), dlc);
        }
        if (canbus_frame_bits(&fr) != bits) {
            print_error("%s", line);
        }
        assert_int_equal(canbus_frame_bits(&fr), bits);
        ++seen[width == 29u][remote][dlc];
        ++checked;
    }
    assert_int_equal(fclose(f), 0);
    assert_true(checked >= 500u);
    for (unsigned e = 0u; e < 2u; ++e) {
        for (unsigned r = 0u; r < 2u; ++r) {
            for (unsigned d = 0u; d <= 8u; ++d) {
                assert_true(seen[e][r][d] > 0u); /* every class is in the file */
            }
        }
    }
}

static void test_frame_bits_examples_and_bounds(void **state)
{
    (void)state;
    /* docs/bus-timing.md: frame_bits(0x020, 0011223344556677) = 116, (0x123, zeros) = 125 */
    canbus_frame_t f = frame(0x020u, false, 8u, 0u);
    memcpy(f.data, "\x00\x11\x22\x33\x44\x55\x66\x77", 8u);
    assert_int_equal(canbus_frame_bits(&f), 116u);
    f = frame(0x123u, false, 8u, 0u);
    assert_int_equal(canbus_frame_bits(&f), 125u);
    /* between the unstuffed length and the worst case of SPEC §8, every DLC */
    for (uint8_t dlc = 0u; dlc <= 8u; ++dlc) {
        for (unsigned ext = 0u; ext < 2u; ++ext) {
            const uint32_t g = ext ? 54u : 34u;
            const canbus_frame_t z = frame(0u, ext != 0u, dlc, 0u);
            const uint32_t bits = canbus_frame_bits(&z);
            assert_true(bits >= g + 8u * dlc + 13u);
            assert_true(bits <= g + 8u * dlc + 13u + (g + 8u * dlc - 1u) / 4u);
        }
    }
    /* invalid frames have no length */
    f = frame(0x800u, false, 1u, 0u);
    assert_int_equal(canbus_frame_bits(&f), 0u);
    f = frame(0x20000000u, true, 1u, 0u);
    assert_int_equal(canbus_frame_bits(&f), 0u);
    f = frame(0x1u, false, 0u, 0u);
    f.dlc = 9u;
    assert_int_equal(canbus_frame_bits(&f), 0u);
}

static void test_arbitration_field_order(void **state)
{
    (void)state;
    canbus_frame_t std = frame(0x100u, false, 8u, 0u);
    canbus_frame_t ext = frame(0x100u << 18, true, 8u, 0u); /* the same base, extension 0 */
    canbus_frame_t remote = std;
    remote.rtr = true;
    canbus_frame_t lower_ext = frame((0x0FFu << 18) | 0x3FFFFu, true, 0u, 0u);
    assert_true(canbus_frame_arbitration(&std) < canbus_frame_arbitration(&remote));
    assert_true(canbus_frame_arbitration(&remote) < canbus_frame_arbitration(&ext));
    assert_true(canbus_frame_arbitration(&lower_ext) < canbus_frame_arbitration(&std));
    canbus_frame_t ext_remote = ext;
    ext_remote.rtr = true;
    assert_true(canbus_frame_arbitration(&ext) < canbus_frame_arbitration(&ext_remote));
}

/* ---- the bus in time ---------------------------------------------------------------------- */

static void test_three_nodes_at_once_in_arbitration_order(void **state)
{
    (void)state;
    const canbus_policy_t prio[3] = {CANBUS_PRIO, CANBUS_PRIO, CANBUS_PRIO};
    canbus_core_t c;
    init_bus(&c, 3u, prio);
    const canbus_frame_t f[3] = {frame(0x100u, false, 8u, 0x11u), frame(0x050u, false, 3u, 0xA5u),
                                 frame(0x200u, false, 0u, 0u)};
    const uint64_t t0 = 1000000u;
    for (uint32_t i = 0u; i < 3u; ++i) {
        queue(&c, i, &f[i], t0);
    }
    canbus_done_t d[4];
    assert_int_equal(run_until(&c, t0 + 10000000u, d, 4u), 3u);
    const uint32_t order[3] = {1u, 0u, 2u}; /* 0x050, 0x100, 0x200 */
    uint64_t sof = t0;
    for (unsigned k = 0u; k < 3u; ++k) {
        const uint32_t bits = canbus_frame_bits(&f[order[k]]);
        assert_int_equal(d[k].node, order[k]);
        assert_int_equal(d[k].frame.id, f[order[k]].id);
        assert_int_equal(d[k].bits, bits);
        assert_int_equal(d[k].t_queued, t0);
        assert_int_equal(d[k].t_sof, sof);
        /* the end of frame: the frame's bits less the interframe space after it */
        assert_int_equal(d[k].t_eof, sof + (uint64_t)(bits - 3u) * BIT_500K);
        sof += (uint64_t)bits * BIT_500K; /* the next one starts when the bus is idle */
    }
    /* so the ends of frame are the cumulative exact lengths, less 3 bits */
    assert_int_equal(d[2].t_eof, t0 + (uint64_t)(canbus_frame_bits(&f[0]) +
                                                canbus_frame_bits(&f[1]) +
                                                canbus_frame_bits(&f[2]) - 3u) * BIT_500K);
    uint64_t t;
    bool is_eof;
    assert_false(canbus_core_next(&c, &t, &is_eof)); /* nothing left */
}

static void test_frame_queued_while_busy_waits_for_idle(void **state)
{
    (void)state;
    const canbus_policy_t prio[2] = {CANBUS_PRIO, CANBUS_PRIO};
    canbus_core_t c;
    init_bus(&c, 2u, prio);
    const canbus_frame_t slow = frame(0x700u, false, 8u, 0u);
    const canbus_frame_t urgent = frame(0x001u, false, 8u, 0u);
    const uint32_t bits = canbus_frame_bits(&slow);
    queue(&c, 0u, &slow, 0u);
    canbus_done_t d[2];
    assert_int_equal(run_until(&c, 10000u, d, 2u), 0u); /* 0x700 is on the bus */
    uint64_t t;
    bool is_eof;
    assert_true(canbus_core_next(&c, &t, &is_eof));
    assert_true(is_eof);
    assert_int_equal(t, (uint64_t)(bits - 3u) * BIT_500K);
    queue(&c, 1u, &urgent, 10000u); /* higher priority, but the bus is busy */
    assert_int_equal(run_until(&c, t, d, 2u), 1u);
    assert_int_equal(d[0].frame.id, 0x700u);
    /* after the end of frame: arbitration when the interframe space is over */
    assert_true(canbus_core_next(&c, &t, &is_eof));
    assert_false(is_eof);
    assert_int_equal(t, (uint64_t)bits * BIT_500K);
    assert_int_equal(run_until(&c, 1000000u, d, 2u), 1u);
    assert_int_equal(d[0].frame.id, 0x001u);
    assert_int_equal(d[0].t_queued, 10000u);
    assert_int_equal(d[0].t_sof, (uint64_t)bits * BIT_500K);
    /* on an idle bus a frame starts when it is queued */
    queue(&c, 0u, &slow, 2000000u);
    assert_true(canbus_core_next(&c, &t, &is_eof));
    assert_false(is_eof);
    assert_int_equal(t, 2000000u);
    assert_int_equal(run_until(&c, 3000000u, d, 2u), 1u);
    assert_int_equal(d[0].t_sof, 2000000u);
    assert_int_equal(c.late, 0u);
}

/* Node 0 queues 0x300 then 0x010, node 1 0x100, all at t = 0: the order on the bus. */
static void order_with_policy(canbus_policy_t node0, uint32_t want[3])
{
    const canbus_policy_t policy[2] = {node0, CANBUS_PRIO};
    canbus_core_t c;
    init_bus(&c, 2u, policy);
    const canbus_frame_t a = frame(0x300u, false, 8u, 0u);
    const canbus_frame_t b = frame(0x010u, false, 8u, 0u);
    const canbus_frame_t other = frame(0x100u, false, 8u, 0u);
    queue(&c, 0u, &a, 0u);
    queue(&c, 0u, &b, 0u);
    queue(&c, 1u, &other, 0u);
    canbus_done_t d[3];
    assert_int_equal(run_until(&c, 1000000u, d, 3u), 3u);
    for (unsigned k = 0u; k < 3u; ++k) {
        want[k] = d[k].frame.id;
    }
}

static void test_fifo_inverts_priority(void **state)
{
    (void)state;
    uint32_t ids[3];
    order_with_policy(CANBUS_FIFO, ids);
    /* the FIFO's head 0x300 blocks its 0x010: node 1's 0x100 goes first */
    assert_int_equal(ids[0], 0x100u);
    assert_int_equal(ids[1], 0x300u);
    assert_int_equal(ids[2], 0x010u);
}

static void test_priority_mailboxes_do_not_invert(void **state)
{
    (void)state;
    uint32_t ids[3];
    order_with_policy(CANBUS_PRIO, ids);
    assert_int_equal(ids[0], 0x010u);
    assert_int_equal(ids[1], 0x100u);
    assert_int_equal(ids[2], 0x300u);
}

static void test_11_bit_beats_29_bit_with_the_same_base(void **state)
{
    (void)state;
    const canbus_policy_t prio[3] = {CANBUS_PRIO, CANBUS_PRIO, CANBUS_PRIO};
    canbus_core_t c;
    init_bus(&c, 3u, prio);
    const canbus_frame_t ext = frame(0x100u << 18, true, 8u, 0u);
    canbus_frame_t remote = frame(0x100u, false, 8u, 0u);
    remote.rtr = true;
    const canbus_frame_t data = frame(0x100u, false, 8u, 0u);
    queue(&c, 0u, &ext, 0u);
    queue(&c, 1u, &remote, 0u);
    queue(&c, 2u, &data, 0u);
    canbus_done_t d[3];
    assert_int_equal(run_until(&c, 1000000u, d, 3u), 3u);
    assert_int_equal(d[0].node, 2u); /* 11-bit data */
    assert_int_equal(d[1].node, 1u); /* 11-bit remote */
    assert_int_equal(d[2].node, 0u); /* 29-bit */
    assert_true(d[2].frame.ext);
    assert_int_equal(d[2].bits, canbus_frame_bits(&ext));
}

/* A pseudo-random workload: 4 nodes of both policies, frames queued at random times between
 * advances to random times.  Everything that ended, in order. */
static size_t workload(canbus_done_t *out, size_t max, uint64_t *late)
{
    const canbus_policy_t policy[4] = {CANBUS_PRIO, CANBUS_FIFO, CANBUS_PRIO, CANBUS_FIFO};
    static canbus_core_t c;
    assert_int_equal(canbus_core_init(&c, 250000u, 4u, policy), FCC_OK);
    uint32_t x = 12345u;
    uint64_t now = 0u;
    size_t n = 0u;
    for (unsigned step = 0u; step < 400u; ++step) {
        x = x * 1103515245u + 12345u;
        const uint32_t node = (x >> 16) % 4u;
        canbus_frame_t f = frame((x >> 8) & 0x7FFu, (x & 1u) != 0u, (uint8_t)((x >> 4) % 9u),
                                 (uint8_t)(x >> 24));
        f.id = f.ext ? x & 0x1FFFFFFFu : f.id;
        (void)canbus_core_queue(&c, node, &f, now + (x % 50000u));
        now += (x >> 8) % 800000u;
        canbus_done_t d;
        while (canbus_core_advance(&c, now, &d)) {
            assert_true(n < max);
            out[n++] = d;
        }
    }
    *late = c.late;
    return n;
}

static void test_same_inputs_same_outputs(void **state)
{
    (void)state;
    static canbus_done_t first[512];
    static canbus_done_t second[512];
    memset(first, 0, sizeof first);
    memset(second, 0, sizeof second);
    uint64_t late1, late2;
    const size_t n1 = workload(first, 512u, &late1);
    const size_t n2 = workload(second, 512u, &late2);
    assert_true(n1 > 100u);
    assert_int_equal(n1, n2);
    assert_int_equal(late1, late2);
    assert_memory_equal(first, second, n1 * sizeof first[0]);
    /* and the bus never carries two frames at once, nor starts one before it was queued */
    for (size_t k = 0u; k < n1; ++k) {
        assert_true(first[k].t_sof >= first[k].t_queued);
        assert_int_equal(first[k].t_eof - first[k].t_sof, (uint64_t)(first[k].bits - 3u) * 4000u);
        if (k > 0u) {
            assert_true(first[k].t_sof >= first[k - 1u].t_eof + 3u * 4000u);
        }
    }
}

static void test_late_frame_is_counted_and_kept(void **state)
{
    (void)state;
    const canbus_policy_t prio[2] = {CANBUS_PRIO, CANBUS_PRIO};
    canbus_core_t c;
    init_bus(&c, 2u, prio);
    const canbus_frame_t a = frame(0x200u, false, 8u, 0u);
    const canbus_frame_t b = frame(0x100u, false, 8u, 0u);
    queue(&c, 0u, &a, 1000u);
    canbus_done_t d[2];
    assert_int_equal(run_until(&c, 2000u, d, 2u), 0u); /* 0x200 won at 1000 */
    queue(&c, 1u, &b, 500u); /* said to be queued before that arbitration */
    assert_int_equal(c.late, 1u);
    assert_int_equal(run_until(&c, 1000000u, d, 2u), 2u);
    assert_int_equal(d[1].frame.id, 0x100u);
    assert_int_equal(d[1].t_queued, 500u); /* its response time counts the wait */
}

static void test_refusals(void **state)
{
    (void)state;
    const canbus_policy_t prio[2] = {CANBUS_PRIO, CANBUS_PRIO};
    canbus_core_t c;
    assert_int_equal(canbus_core_init(NULL, 500000u, 2u, prio), FCC_ERR_ARG);
    assert_int_equal(canbus_core_init(&c, 300000u, 2u, prio), FCC_ERR_RANGE); /* 3333.3 ns */
    assert_int_equal(canbus_core_init(&c, 500000u, 0u, prio), FCC_ERR_RANGE);
    assert_int_equal(canbus_core_init(&c, 500000u, CANBUS_NODES_MAX + 1u, prio), FCC_ERR_RANGE);
    init_bus(&c, 2u, prio);
    canbus_frame_t f = frame(0x800u, false, 8u, 0u);
    assert_int_equal(canbus_core_queue(&c, 0u, &f, 0u), FCC_ERR_ARG);
    f.id = 0x100u;
    assert_int_equal(canbus_core_queue(&c, 2u, &f, 0u), FCC_ERR_ARG);
    for (unsigned k = 0u; k < CANBUS_QUEUE_LEN; ++k) {
        queue(&c, 0u, &f, 0u);
    }
    assert_int_equal(canbus_core_queue(&c, 0u, &f, 0u), FCC_ERR_AGAIN);
    assert_int_equal(canbus_core_pending(&c, 0u), CANBUS_QUEUE_LEN);
    canbus_done_t d;
    assert_false(canbus_core_advance(NULL, 0u, &d));
}

/* ---- statistics --------------------------------------------------------------------------- */

static void test_histogram_percentiles(void **state)
{
    (void)state;
    static canbus_hist_t h;
    canbus_hist_init(&h);
    assert_int_equal(canbus_hist_quantile(&h, 50u, 100u), 0u);
    for (uint64_t v = 1u; v <= 100u; ++v) {
        canbus_hist_add(&h, v); /* exact below 128 */
    }
    assert_int_equal(canbus_hist_quantile(&h, 50u, 100u), 50u);
    assert_int_equal(canbus_hist_quantile(&h, 99u, 100u), 99u);
    assert_int_equal(h.min, 1u);
    assert_int_equal(h.max, 100u);
    canbus_hist_init(&h);
    for (uint64_t v = 1u; v <= 100000u; ++v) {
        canbus_hist_add(&h, v * 1000u); /* 1 us .. 100 ms */
    }
    const uint64_t p50 = canbus_hist_quantile(&h, 50u, 100u);
    const uint64_t p99 = canbus_hist_quantile(&h, 99u, 100u);
    assert_true(p50 >= 50000000u && p50 <= 50000000u + 50000000u / 64u);
    assert_true(p99 >= 99000000u && p99 <= 99000000u + 99000000u / 64u);
    assert_int_equal(canbus_hist_quantile(&h, 100u, 100u), 100000000u);
    canbus_hist_add(&h, UINT64_MAX); /* beyond the last bucket: kept as the maximum */
    assert_int_equal(h.max, UINT64_MAX);
    assert_int_equal(canbus_hist_quantile(&h, 100u, 100u), UINT64_MAX);
}

static void test_stats_json_line(void **state)
{
    (void)state;
    static canbus_stats_t s;
    canbus_stats_init(&s, 500000u);
    s.nodes = 2u;
    s.node[0].iface = "vxcan0b";
    s.node[1].iface = "vxcan1b";
    s.node[1].policy = CANBUS_FIFO;
    canbus_done_t d;
    memset(&d, 0, sizeof d);
    d.frame = frame(0x050u, false, 8u, 0u);
    d.bits = 120u;
    d.t_queued = 1000u;
    d.t_eof = 1000u + 234000u;
    canbus_stats_frame(&s, &d, BIT_500K);
    d.frame = frame(0x18FF0001u, true, 8u, 0u);
    d.node = 1u;
    canbus_stats_frame(&s, &d, BIT_500K);
    canbus_stats_delivery(&s, 5000u, 17000u);
    canbus_stats_delivery(&s, 5000u, 4000u); /* early: counted, as 0 */
    s.node[1].lost = 2u;
    s.node[1].confine.tec_max = 256u;
    s.node[1].confine.rec_max = 3u;
    s.node[1].confine.tx_errors = 32u;
    s.node[1].confine.passive_episodes = 1u;
    s.node[1].confine.bus_off_episodes = 1u;
    s.node[1].confine.dropped = 4u;
    s.node[1].error_frames = 37u;
    canbus_stats_recovery(&s, 1u, 1000u, 1000u + 2816000u);
    s.error_frames = 32u;
    FILE *f = tmpfile();
    assert_non_null(f);
    assert_int_equal(canbus_stats_json(&s, f), FCC_OK);
    rewind(f);
    char line[2048];
    assert_non_null(fgets(line, sizeof line, f));
    assert_int_equal(fclose(f), 0);
    assert_string_equal(
        line,
        "{\"bitrate\": 500000, \"frames\": 2, \"busy_s\": 0.000480000, \"load\": 0.0000, "
        "\"wall_s\": 0.000000, \"cpu_s\": 0.000000, \"pending\": 0, \"lost\": 2, "
        "\"late_queued\": 0, \"delivery_error\": {\"n\": 2, \"p50_s\": 0.000000000, "
        "\"p99_s\": 0.000012000, \"max_s\": 0.000012000, \"early\": 1}, \"nodes\": "
        "[{\"iface\": \"vxcan0b\", \"policy\": \"prio\", \"sent\": 1, \"received\": 0, "
        "\"lost\": 0, \"tec_max\": 0, \"rec_max\": 0, \"tx_errors\": 0, \"rx_errors\": 0, "
        "\"error_frames\": 0, \"error_passive\": 0, \"bus_off\": 0, \"bus_off_dropped\": 0, "
        "\"recovery_s\": []}, {\"iface\": \"vxcan1b\", \"policy\": \"fifo\", \"sent\": 1, "
        "\"received\": 0, \"lost\": 2, \"tec_max\": 256, \"rec_max\": 3, \"tx_errors\": 32, "
        "\"rx_errors\": 0, \"error_frames\": 37, \"error_passive\": 1, \"bus_off\": 1, "
        "\"bus_off_dropped\": 4, \"recovery_s\": [0.002816000]}], \"ids\": {\"0x050\": {\"n\": 1, \"p50_s\": "
        "0.000234000, \"p99_s\": 0.000234000, \"max_s\": 0.000234000}, \"0x18FF0001\": "
        "{\"n\": 1, \"p50_s\": 0.000234000, \"p99_s\": 0.000234000, \"max_s\": 0.000234000}}, "
        "\"ids_untracked\": 0, \"error_frames\": 32, \"babble_dropped\": 0, "
        "\"events_lost\": 0, \"load_streams\": [], \"load_dropped\": 0}\n");
}

/* ---- command line ------------------------------------------------------------------------- */

static int parse(canbus_opts_t *o, char *err, int argc, ...)
{
    char *argv[16];
    va_list ap;
    va_start(ap, argc);
    argv[0] = "canbus";
    for (int i = 1; i < argc; ++i) {
        argv[i] = va_arg(ap, char *);
    }
    va_end(ap);
    err[0] = '\0';
    FILE *out = tmpfile();
    assert_non_null(out);
    const int rc = canbus_opts_parse(argc, argv, o, out, err, 256u);
    assert_int_equal(fclose(out), 0);
    return rc;
}

static void test_command_line(void **state)
{
    (void)state;
    static canbus_opts_t o;
    char err[256];
    assert_int_equal(parse(&o, err, 4, "--node", "vxcan0b", "--node=vxcan1b:fifo"), 0);
    assert_int_equal(o.bitrate, 500000u);
    assert_int_equal(o.nodes, 2u);
    assert_string_equal(o.node[0].iface, "vxcan0b");
    assert_int_equal(o.node[0].policy, CANBUS_PRIO);
    assert_string_equal(o.node[1].iface, "vxcan1b");
    assert_int_equal(o.node[1].policy, CANBUS_FIFO);
    assert_int_equal(parse(&o, err, 7, "--bitrate", "125k", "--node", "a:prio", "--node", "b"), 0);
    assert_int_equal(o.bitrate, 125000u);
    assert_int_equal(parse(&o, err, 6, "--bitrate=1M", "--node", "a", "--node", "b"), 0);
    assert_int_equal(o.bitrate, 1000000u);
    assert_int_equal(parse(&o, err, 6, "--bitrate=200000", "--node", "a", "--node", "b"), 0);
    assert_int_equal(o.bitrate, 200000u);
    assert_int_equal(parse(&o, err, 2, "--help"), 1);
    /* faults: times in ns from the first frame, the sender resolved to its node's index */
    assert_int_equal(parse(&o, err, 11, "--node", "a", "--error",
                           "id=0x100-0x1FF,node=b,from=1.5,to=2,every=3,count=4,bit=7,superposed=6",
                           "--node", "b", "--bus-off", "b@2.25", "--babble",
                           "id=0x80,dlc=2,period=0.001,to=3"), 0);
    assert_int_equal(o.faults.errors, 2u);
    const canbus_fault_t *f = &o.faults.error[0].fault;
    assert_int_equal(f->id_min, 0x100u);
    assert_int_equal(f->id_max, 0x1FFu);
    assert_int_equal(f->node, 1u);
    assert_int_equal(f->t_from, 1500000000u);
    assert_int_equal(f->t_to, 2000000000u);
    assert_int_equal(f->every, 3u);
    assert_int_equal(f->count, 4u);
    assert_int_equal(f->bit, 7u);
    assert_int_equal(f->superposed, 6u);
    assert_false(f->until_bus_off);
    f = &o.faults.error[1].fault;
    assert_true(f->until_bus_off);
    assert_int_equal(f->node, 1u);
    assert_int_equal(f->t_from, 2250000000u);
    assert_int_equal(f->bit, CANBUS_BIT_CRC_DELIM);
    assert_int_equal(o.faults.babbles, 1u);
    assert_int_equal(o.faults.babble[0].frame.id, 0x80u);
    assert_int_equal(o.faults.babble[0].frame.dlc, 2u);
    assert_int_equal(o.faults.babble[0].period_ns, 1000000u);
    assert_int_equal(o.faults.babble[0].t_to, 3000000000u);
    /* a background load: its defaults, and every field */
    assert_int_equal(parse(&o, err, 9, "--node", "a", "--node", "b", "--load", "util=0.25",
                           "--load", "util=1,id=0x10-0x1F,seed=18446744073709551615,from=1,to=2"),
                     0);
    assert_int_equal(o.faults.loads, 2u);
    assert_int_equal(o.faults.load[0].ppm, 250000u);
    assert_int_equal(o.faults.load[0].id_lo, 0x200u);
    assert_int_equal(o.faults.load[0].id_hi, 0x6FFu);
    assert_int_equal(o.faults.load[0].seed, 0u);
    assert_int_equal(o.faults.load[0].start_ns, 0u);
    assert_true(o.faults.load[0].end_ns == UINT64_MAX);
    assert_int_equal(o.faults.load[1].ppm, CANBUS_LOAD_PPM_MAX);
    assert_int_equal(o.faults.load[1].id_lo, 0x10u);
    assert_int_equal(o.faults.load[1].id_hi, 0x1Fu);
    assert_true(o.faults.load[1].seed == UINT64_MAX);
    assert_int_equal(o.faults.load[1].start_ns, 1000000000u);
    assert_int_equal(o.faults.load[1].end_ns, 2000000000u);
}

static void expect_refused(const char *want, int argc, char *a1, char *a2, char *a3, char *a4,
                           char *a5)
{
    static canbus_opts_t o;
    char err[256];
    assert_int_equal(parse(&o, err, argc, a1, a2, a3, a4, a5), -1);
    if (strstr(err, want) == NULL) {
        print_error("'%s' does not say '%s'\n", err, want);
        fail();
    }
}

static void test_command_line_refusals(void **state)
{
    (void)state;
    expect_refused("at least 2 nodes, 1 given", 3, "--node", "a", NULL, NULL, NULL);
    expect_refused("at least 2 nodes, 0 given", 1, NULL, NULL, NULL, NULL, NULL);
    expect_refused("whole number of nanoseconds", 6, "--bitrate", "300000", "--node", "a",
                   "--node=b");
    expect_refused("--bitrate", 6, "--bitrate", "2M", "--node", "a", "--node=b");
    expect_refused("given twice", 5, "--node", "a", "--node", "a:fifo", NULL);
    expect_refused("'lifo'", 5, "--node", "a:lifo", "--node", "b", NULL);
    expect_refused("not an interface name", 5, "--node", "a\"b", "--node", "b", NULL);
    expect_refused("not an interface name", 5, "--node", "averyverylongname", "--node", "b",
                   NULL);
    expect_refused("not an interface name", 5, "--node", ":fifo", "--node", "b", NULL);
    expect_refused("unexpected argument 'vxcan0'", 2, "vxcan0", NULL, NULL, NULL, NULL);
    expect_refused("unknown option '--speed'", 3, "--speed", "1", NULL, NULL, NULL);
    expect_refused("needs a value", 2, "--node", NULL, NULL, NULL, NULL);
    expect_refused("--error: 43 is outside 0..42", 6, "--node", "a", "--node", "b",
                   "--error=bit=43");
    expect_refused("--error: unknown field 'rate'", 6, "--node", "a", "--node", "b",
                   "--error=rate=3");
    expect_refused("not in order", 6, "--node", "a", "--node", "b", "--error=id=0x200-0x100");
    expect_refused("from is after to", 6, "--node", "a", "--node", "b", "--error=from=2,to=1");
    expect_refused("--bus-off: c is not a --node", 6, "--node", "a", "--node", "b",
                   "--bus-off=c@1");
    expect_refused("--babble: id=ID is needed", 6, "--node", "a", "--node", "b",
                   "--babble=period=0.1");
    expect_refused("not a CAN identifier", 6, "--node", "a", "--node", "b",
                   "--babble=id=0x20000000");
    expect_refused("--load: 11-bit identifiers", 6, "--node", "a", "--node", "b",
                   "--load=id=0x100-0x800");
    expect_refused("--load", 6, "--node", "a", "--node", "b", "--load=util=1.5");
    expect_refused("--load: from is not before to", 6, "--node", "a", "--node", "b",
                   "--load=from=2,to=2");
    expect_refused("--load: unknown field 'rate'", 6, "--node", "a", "--node", "b",
                   "--load=rate=3");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_frame_bits_match_python),
        cmocka_unit_test(test_frame_bits_examples_and_bounds),
        cmocka_unit_test(test_arbitration_field_order),
        cmocka_unit_test(test_three_nodes_at_once_in_arbitration_order),
        cmocka_unit_test(test_frame_queued_while_busy_waits_for_idle),
        cmocka_unit_test(test_fifo_inverts_priority),
        cmocka_unit_test(test_priority_mailboxes_do_not_invert),
        cmocka_unit_test(test_11_bit_beats_29_bit_with_the_same_base),
        cmocka_unit_test(test_same_inputs_same_outputs),
        cmocka_unit_test(test_late_frame_is_counted_and_kept),
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_histogram_percentiles),
        cmocka_unit_test(test_stats_json_line),
        cmocka_unit_test(test_command_line),
        cmocka_unit_test(test_command_line_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
