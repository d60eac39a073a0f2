/*
 * test_canbus_sim.c -- the bus model in simulated time (firmware/tools/canbus
 * canbus_sim.c) and its background nodes (canbus_load.c): the load's streams,
 * periods and determinism by hand; SocketCAN frames taken as bytes, the
 * worst-case length, the load's frames counted but not handed out.
 */
#include "fcc_test.h"

#include <stdio.h>
#include <string.h>

#include "canbus_load.h"
#include "canbus_sim.h"

#define BIT_500K 2000u /* ns */

static canbus_load_cfg_t cfg(uint32_t lo, uint32_t hi, uint32_t ppm)
{
    canbus_load_cfg_t c;
    memset(&c, 0, sizeof c);
    c.id_lo = lo;
    c.id_hi = hi;
    c.ppm = ppm;
    c.start_ns = 0u;
    c.end_ns = 1000000000u;
    c.seed = 7u;
    return c;
}

static void test_load_refuses_what_it_cannot_send(void **state)
{
    (void)state;
    canbus_load_t l;
    canbus_load_cfg_t c = cfg(0x300u, 0x2FFu, 400000u);
    assert_int_equal(canbus_load_init(&l, &c, BIT_500K), FCC_ERR_RANGE); /* lo > hi */
    c = cfg(0x300u, 0x800u, 400000u);
    assert_int_equal(canbus_load_init(&l, &c, BIT_500K), FCC_ERR_RANGE); /* not 11-bit */
    c = cfg(0x300u, 0x30Fu, 0u);
    assert_int_equal(canbus_load_init(&l, &c, BIT_500K), FCC_ERR_RANGE);
    c = cfg(0x300u, 0x30Fu, 1000001u);
    assert_int_equal(canbus_load_init(&l, &c, BIT_500K), FCC_ERR_RANGE);
    c = cfg(0x300u, 0x30Fu, 400000u);
    c.end_ns = 0u;
    assert_int_equal(canbus_load_init(&l, &c, BIT_500K), FCC_ERR_RANGE); /* empty window */
    assert_int_equal(canbus_load_init(NULL, &c, BIT_500K), FCC_ERR_ARG);
}

static void test_load_streams_and_period_by_hand(void **state)
{
    (void)state;
    canbus_load_t l;
    /* 16 streams over 0x300-0x30F; period = 16 x 135 bits x 2000 ns / 0.4 = 10.8 ms */
    canbus_load_cfg_t c = cfg(0x300u, 0x30Fu, 400000u);
    assert_int_equal(canbus_load_init(&l, &c, BIT_500K), FCC_OK);
    uint32_t id;
    uint64_t period;
    for (uint32_t i = 0u; i < 16u; ++i) {
        assert_true(canbus_load_stream(&l, i, &id, &period));
        assert_int_equal(id, 0x300u + i);
        assert_int_equal(period, 10800000u);
    }
    assert_false(canbus_load_stream(&l, 16u, &id, &period));
    /* three identifiers: three streams, the ends and the middle */
    c = cfg(0x100u, 0x102u, 1000000u);
    assert_int_equal(canbus_load_init(&l, &c, BIT_500K), FCC_OK);
    assert_true(canbus_load_stream(&l, 2u, &id, &period));
    assert_int_equal(id, 0x102u);
    assert_int_equal(period, 3u * 135u * BIT_500K);
    assert_false(canbus_load_stream(&l, 3u, &id, &period));
    /* a whole range: 16 streams spread evenly, the last at its top */
    c = cfg(0x000u, 0x7FFu, 500000u);
    assert_int_equal(canbus_load_init(&l, &c, BIT_500K), FCC_OK);
    assert_true(canbus_load_stream(&l, 15u, &id, &period));
    assert_int_equal(id, 0x7FFu);
}

static void test_load_is_periodic_and_deterministic(void **state)
{
    (void)state;
    canbus_load_t a;
    canbus_load_t b;
    const canbus_load_cfg_t c = cfg(0x300u, 0x30Fu, 400000u);
    assert_int_equal(canbus_load_init(&a, &c, BIT_500K), FCC_OK);
    assert_int_equal(canbus_load_init(&b, &c, BIT_500K), FCC_OK);
    uint64_t last[16];
    memset(last, 0, sizeof last);
    uint32_t n = 0u;
    uint64_t ta;
    while (canbus_load_next(&a, &ta)) {
        uint64_t tb;
        assert_true(canbus_load_next(&b, &tb));
        canbus_frame_t fa;
        canbus_frame_t fb;
        canbus_load_take(&a, &fa);
        canbus_load_take(&b, &fb);
        assert_int_equal(ta, tb);
        assert_memory_equal(&fa, &fb, sizeof fa);
        assert_true(fa.id >= 0x300u && fa.id <= 0x30Fu && fa.dlc == 8u && !fa.ext);
        const uint32_t s = fa.id - 0x300u;
        if (last[s] != 0u) {
            assert_int_equal(ta - last[s], 10800000u); /* each stream exactly periodic */
        }
        last[s] = ta;
        assert_true(ta < 1000000000u); /* only in the window */
        ++n;
    }
    /* 1 s / 10.8 ms = 92.6 releases a stream */
    assert_true(n >= 16u * 92u && n <= 16u * 93u);
}

static canbus_sim_t sim; /* 2.4 MB of statistics: not on the stack */
static canbus_sim_t twin; /* the same calls one at a time (test_sim_steps_...) */

static void raw_frame(uint8_t *raw, uint32_t can_id, uint8_t dlc, uint8_t fill)
{
    memset(raw, 0, CANBUS_SIM_RAW_LEN);
    memcpy(raw, &can_id, sizeof can_id);
    raw[4] = dlc;
    memset(raw + 8, fill, dlc);
}

static void test_sim_takes_socketcan_frames_and_the_worst_case(void **state)
{
    (void)state;
    const canbus_policy_t pol[2] = {CANBUS_PRIO, CANBUS_FIFO};
    const char *const names[2] = {"sim", "fcc"};
    assert_int_equal(canbus_sim_init(&sim, 500000u, 2u, pol, names, NULL, 0u), FCC_OK);
    const uint32_t worst[1] = {0x021u};
    assert_int_equal(canbus_sim_worst(&sim, worst, 1u), FCC_OK);
    uint8_t raw[2 * CANBUS_SIM_RAW_LEN];
    raw_frame(raw, 0x021u, 8u, 0x55u);                       /* worst case: 135 bits */
    raw_frame(raw + CANBUS_SIM_RAW_LEN, 0x98FF0001u, 0u, 0u); /* 29-bit 0x18FF0001: base 0x63F */
    assert_int_equal(canbus_sim_queue_raw(&sim, 0u, raw, 2u, 1000u), 2u);
    canbus_done_t out[4];
    assert_int_equal(canbus_sim_run(&sim, 10000000u, out, 4u, 0u, 0u, 0u, NULL), 2u);
    assert_int_equal(out[0].frame.id, 0x021u);
    assert_int_equal(out[0].t_eof, 1000u + (135u - 3u) * BIT_500K);
    assert_true(out[1].frame.ext);
    assert_int_equal(out[1].frame.id, 0x18FF0001u);
    assert_int_equal(out[1].t_sof, out[0].t_eof + 3u * BIT_500K);
    /* an error frame is no classic frame: lost, with what follows it */
    raw_frame(raw, 0x20000001u, 8u, 0u);
    assert_int_equal(canbus_sim_queue_raw(&sim, 1u, raw, 2u, 20000000u), 0u);
    assert_int_equal(sim.stats.node[1].lost, 2u);
}

/* canbus's fault options given to the model (the realtime process's builder): an error
 * frame on one frame delays its end of frame by the error's bits, (bit + 1 + 6 + 8 + 3),
 * docs/bus-timing.md; a forced bus-off of a node recovers 128 x 11 recessive bits after its
 * error flag (6 + 128 x 11 bits on an idle bus), in the statistics. */
static void test_sim_takes_canbus_fault_options(void **state)
{
    (void)state;
    const canbus_policy_t pol[2] = {CANBUS_PRIO, CANBUS_FIFO};
    const char *const names[2] = {"sim", "fcc"};
    const char *const opts[4] = {"--error", "id=0x021,node=sim,count=1", "--bus-off", "fcc@0.01"};
    char err[128] = "";
    assert_int_equal(canbus_sim_setup(&sim, 500000u, 2u, pol, names, NULL, 0u, opts, 2u, err,
                                      sizeof err), FCC_OK);
    const uint32_t worst[1] = {0x021u};
    assert_int_equal(canbus_sim_worst(&sim, worst, 1u), FCC_OK);
    uint8_t raw[CANBUS_SIM_RAW_LEN];
    raw_frame(raw, 0x021u, 8u, 0x55u);                 /* 135 bits, CRC delimiter at 122 */
    assert_int_equal(canbus_sim_queue_raw(&sim, 0u, raw, 1u, 0u), 1u);
    canbus_done_t out[4];
    assert_int_equal(canbus_sim_run(&sim, 5000000u, out, 4u, 0u, 0u, 0u, NULL), 1u);
    /* corrupted at bit 122, idle at 122 + 1 + 6 + 8 + 3 = 140, then 132 bits to its EOF */
    assert_int_equal(out[0].t_eof, (140u + 132u) * BIT_500K);
    assert_int_equal(sim.core.confine[0].tx_errors, 1u);
    /* fcc from 10 ms on: its frame corrupted 32 times, bus-off, back after 128 x 11 bits */
    raw_frame(raw, 0x100u, 0u, 0u);
    assert_int_equal(canbus_sim_queue_raw(&sim, 1u, raw, 1u, 10000000u), 1u);
    assert_int_equal(canbus_sim_run(&sim, 20000000u, out, 4u, 0u, 0u, 0u, NULL), 0u);
    assert_int_equal(sim.stats.node[1].recoveries, 1u);
    const uint64_t recovery = sim.stats.node[1].recovery_ns[0];
    /* from the error flag's start (bus_off_at) to the recovery: the flag, then 128 runs */
    assert_int_equal(recovery, (CANBUS_FLAG_BITS + 128u * 11u) * BIT_500K);
    /* a node the options name must be one of the caller's */
    const char *const bad[2] = {"--bus-off", "nobody"};
    assert_int_equal(canbus_sim_setup(&sim, 500000u, 2u, pol, names, NULL, 0u, bad, 1u, err,
                                      sizeof err), FCC_ERR_ARG);
    assert_non_null(strstr(err, "nobody"));
}

static void test_sim_stops_at_a_nodes_frames_and_hides_the_load(void **state)
{
    (void)state;
    const canbus_policy_t pol[1] = {CANBUS_PRIO};
    const char *const names[1] = {"sim"};
    const canbus_load_cfg_t c = cfg(0x004u, 0x00Fu, 500000u);
    const canbus_load_cfg_t five[5] = {c, c, c, c, c};
    assert_int_equal(canbus_sim_init(&sim, 500000u, 1u, pol, names, five, 5u), FCC_ERR_SIZE);
    assert_int_equal(canbus_sim_init(&sim, 500000u, 1u, pol, names, &c, 1u), FCC_OK);
    uint8_t raw[3 * CANBUS_SIM_RAW_LEN];
    for (uint32_t i = 0u; i < 3u; ++i) {
        raw_frame(raw + i * CANBUS_SIM_RAW_LEN, 0x040u + i, 8u, (uint8_t)i);
    }
    const uint64_t t = 50000000u;
    assert_int_equal(canbus_sim_queue_raw(&sim, 0u, raw, 3u, t), 3u);
    canbus_done_t out[8];
    uint32_t seen = 0u;
    /* up to the second of them: the third is still to come */
    const uint32_t n = canbus_sim_run(&sim, t + 100000000u, out, 8u, 0u, t, 2u, &seen);
    assert_int_equal(seen, 2u);
    assert_int_equal(n, 2u); /* the load's frames ran too, but are not handed out */
    assert_int_equal(out[1].frame.id, 0x041u);
    assert_int_equal(canbus_sim_pending(&sim, 0u), 1u);
    assert_true(sim.stats.node[1].sent > 0u); /* the load node: 12 streams at 0.5 */
    assert_int_equal(canbus_sim_json(&sim, "/nonexistent-dir/stats.json"), FCC_ERR_IO);
}

#define EVENT_ID 0x7F0u /* the simulator's last_id in these tests */
#define STEPS 40u

/* Step k's frames: the simulator's three readings and an event (every third step), fcc's
 * answer of 13 (every fifth step none), data varying with k (their stuffed lengths too). */
static uint32_t step_frames(uint8_t *raw, uint32_t k, bool answer)
{
    uint32_t n = 0u;
    if (answer) {
        for (uint32_t i = 0u; i < (k % 5u == 4u ? 0u : 13u); ++i) {
            raw_frame(raw + (size_t)n++ * CANBUS_SIM_RAW_LEN, 0x110u + i, 8u, (uint8_t)(k * 7u + i));
        }
        return n;
    }
    if (k % 3u == 0u) {
        raw_frame(raw + (size_t)n++ * CANBUS_SIM_RAW_LEN, EVENT_ID, 2u, (uint8_t)k);
    }
    for (uint32_t i = 0u; i < 3u; ++i) {
        raw_frame(raw + (size_t)n++ * CANBUS_SIM_RAW_LEN, 0x050u + i, 4u, (uint8_t)(k + i));
    }
    return n;
}

static void setup_pair(uint32_t bitrate)
{
    const canbus_policy_t pol[2] = {CANBUS_PRIO, CANBUS_FIFO};
    const char *const names[2] = {"sim", "fcc"};
    const canbus_load_cfg_t c = cfg(0x200u, 0x20Fu, 300000u);
    canbus_sim_t *both[2] = {&sim, &twin};
    for (uint32_t i = 0u; i < 2u; ++i) {
        assert_int_equal(canbus_sim_init(both[i], bitrate, 2u, pol, names, &c, 1u), FCC_OK);
        assert_int_equal(canbus_sim_roles(both[i], 0u, 1u, EVENT_ID, 0u), FCC_OK);
    }
}

/* The exchange as the rig made it before canbus_sim_steps(), one call at a time: run to t,
 * queue the inputs, then the events, run until the inputs ended, queue the answer then. */
static uint64_t one_by_one(canbus_sim_t *s, uint64_t t, uint64_t horizon, const uint8_t *in,
                           uint32_t n, const uint8_t *answer, uint32_t m, uint64_t *eof,
                           uint32_t *ended)
{
    canbus_done_t out[64];
    uint8_t inputs[8 * CANBUS_SIM_RAW_LEN];
    uint8_t events[8 * CANBUS_SIM_RAW_LEN];
    uint32_t ni = 0u;
    uint32_t ne = 0u;
    for (uint32_t i = 0u; i < n; ++i) {
        const uint8_t *r = in + (size_t)i * CANBUS_SIM_RAW_LEN;
        uint32_t id;
        memcpy(&id, r, sizeof id);
        memcpy(id == EVENT_ID ? events + (size_t)ne++ * CANBUS_SIM_RAW_LEN
                              : inputs + (size_t)ni++ * CANBUS_SIM_RAW_LEN, r, CANBUS_SIM_RAW_LEN);
    }
    uint32_t got = canbus_sim_run(s, t, out, 64u, 0u, 0u, 0u, NULL);
    const uint32_t queued = canbus_sim_queue_raw(s, 0u, inputs, ni, t);
    (void)canbus_sim_queue_raw(s, 0u, events, ne, t);
    uint32_t seen = 0u;
    uint64_t t_in = queued == 0u ? t : horizon;
    got += canbus_sim_run(s, horizon, out + got, 64u - got, 0u, t, queued, &seen);
    for (uint32_t i = 0u; i < got; ++i) {
        if (out[i].node == 1u) {
            eof[(*ended)++] = out[i].t_eof;
        } else if (queued > 0u && seen >= queued && out[i].t_queued == t) {
            t_in = out[i].t_eof; /* the last of them */
        }
    }
    if (m > 0u) {
        assert_int_equal(canbus_sim_queue_raw(s, 1u, answer, m, t_in), m);
    }
    return t_in;
}

/* canbus_sim_steps() gives what the calls one at a time gave: the same t_in, fcc's frames
 * ending at the same times, the same statistics; in one batch or one step a call. */
static void test_sim_steps_are_the_calls_one_at_a_time(void **state)
{
    (void)state;
    for (uint32_t batch = 1u; batch <= STEPS; batch *= STEPS) {
        setup_pair(250000u);
        static uint8_t raw[STEPS * 17u * CANBUS_SIM_RAW_LEN];
        static canbus_sim_step_t step[STEPS];
        static uint64_t want[STEPS * 13u];
        static canbus_done_t out[STEPS * 13u + CANBUS_QUEUE_LEN];
        uint32_t at = 0u;
        uint32_t ended = 0u;
        uint32_t reported = 0u;
        for (uint32_t k = 0u; k < STEPS; ++k) {
            canbus_sim_step_t *x = &step[k];
            x->t = (uint64_t)k * 20000000u;
            x->horizon = x->t + 20000000u;
            x->inputs_at = at;
            x->inputs = step_frames(raw + (size_t)at * CANBUS_SIM_RAW_LEN, k, false);
            x->answer_at = at + x->inputs;
            x->answer = step_frames(raw + (size_t)x->answer_at * CANBUS_SIM_RAW_LEN, k, true);
            at = x->answer_at + x->answer;
            const uint64_t t_in = one_by_one(&twin, x->t, x->horizon,
                                             raw + (size_t)x->inputs_at * CANBUS_SIM_RAW_LEN,
                                             x->inputs, raw + (size_t)x->answer_at * CANBUS_SIM_RAW_LEN,
                                             x->answer, want, &ended);
            if ((k + 1u) % batch == 0u) {
                uint32_t got = 0u;
                assert_int_equal(canbus_sim_steps(&sim, &step[k + 1u - batch], batch, raw, at,
                                                  out + reported, STEPS * 13u, &got), FCC_OK);
                reported += got;
            }
            if (batch == 1u) {
                assert_int_equal(x->t_in, t_in);
                assert_int_equal(x->queued, 3u);
                assert_int_equal(x->answered, x->answer);
                assert_true(t_in > x->t && t_in < x->horizon);
            }
        }
        assert_int_equal(reported, ended);
        for (uint32_t i = 0u; i < ended; ++i) {
            assert_int_equal(out[i].t_eof, want[i]);
            assert_int_equal(out[i].node, 1u);
        }
        assert_int_equal(sim.core.now, twin.core.now);
        assert_memory_equal(&sim.stats.node[0], &twin.stats.node[0], sizeof sim.stats.node[0]);
        assert_memory_equal(&sim.stats.node[1], &twin.stats.node[1], sizeof sim.stats.node[1]);
        assert_true(sim.stats.node[2].sent > 0u && sim.stats.node[2].sent == twin.stats.node[2].sent);
    }
}

/* No input: t_in is t; inputs the horizon cuts off: t_in is the horizon; the events go after
 * the inputs whatever their order; steps outside the frames given are refused; more of fcc's
 * frames than out holds: FCC_ERR_SIZE, the steps run all the same. */
static void test_sim_steps_edges(void **state)
{
    (void)state;
    setup_pair(500000u);
    uint8_t raw[4 * CANBUS_SIM_RAW_LEN];
    raw_frame(raw, EVENT_ID, 8u, 1u);
    raw_frame(raw + CANBUS_SIM_RAW_LEN, 0x060u, 8u, 2u);
    raw_frame(raw + 2u * CANBUS_SIM_RAW_LEN, 0x100u, 8u, 3u);
    raw_frame(raw + 3u * CANBUS_SIM_RAW_LEN, 0x101u, 8u, 4u);
    canbus_sim_step_t x[2];
    memset(x, 0, sizeof x);
    x[0].t = 1000000u;
    x[0].horizon = 2000000u;
    x[0].answer_at = 2u;
    x[0].answer = 2u;
    x[1].t = 3000000u;
    x[1].horizon = x[1].t + 100000u; /* shorter than the two frames */
    x[1].inputs = 2u;
    canbus_done_t out[1];
    uint32_t got = 0u;
    assert_int_equal(canbus_sim_steps(&sim, x, 2u, raw, 4u, out, 1u, &got), FCC_ERR_SIZE);
    assert_int_equal(got, 1u);
    assert_int_equal(x[0].t_in, x[0].t);
    assert_int_equal(x[0].queued, 0u);
    assert_int_equal(x[0].answered, 2u);
    assert_int_equal(out[0].frame.id, 0x100u);
    assert_int_equal(out[0].t_queued, x[0].t);
    assert_int_equal(x[1].queued, 1u);
    assert_int_equal(x[1].t_in, x[1].horizon);
    assert_int_equal(canbus_sim_pending(&sim, 0u), 2u); /* the input on the bus, the event after */
    x[1].t = 5000000u; /* later: the answer of step 0 goes, not handed out */
    x[1].horizon = x[1].t + 10000000u;
    x[1].inputs = 0u;
    assert_int_equal(canbus_sim_steps(&sim, &x[1], 1u, raw, 4u, NULL, 0u, &got), FCC_OK);
    assert_int_equal(got, 0u);
    assert_int_equal(x[1].t_in, x[1].t);
    assert_int_equal(canbus_sim_pending(&sim, 1u), 0u);
    x[1].inputs_at = 3u; /* frames 3 and 4 of 4 */
    x[1].inputs = 2u;
    assert_int_equal(canbus_sim_steps(&sim, x, 2u, raw, 4u, NULL, 0u, &got), FCC_ERR_ARG);
    assert_int_equal(canbus_sim_steps(NULL, x, 2u, raw, 4u, NULL, 0u, &got), FCC_ERR_ARG);
    assert_int_equal(canbus_sim_roles(&sim, 0u, 2u, EVENT_ID, 0u), FCC_ERR_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_load_refuses_what_it_cannot_send),
        cmocka_unit_test(test_load_streams_and_period_by_hand),
        cmocka_unit_test(test_sim_takes_canbus_fault_options),
        cmocka_unit_test(test_load_is_periodic_and_deterministic),
        cmocka_unit_test(test_sim_takes_socketcan_frames_and_the_worst_case),
        cmocka_unit_test(test_sim_stops_at_a_nodes_frames_and_hides_the_load),
        cmocka_unit_test(test_sim_steps_are_the_calls_one_at_a_time),
        cmocka_unit_test(test_sim_steps_edges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
