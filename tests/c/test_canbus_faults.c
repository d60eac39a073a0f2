/*
 * test_canbus_faults.c -- canbus's bus faults (firmware/tools/canbus/canbus_faults.h):
 * an error frame's time on the bus and the retransmission, fault confinement
 * (error-passive at the 16th consecutive transmit error, bus-off at the
 * 32nd), bus-off recovery after 128 x 11 recessive bits, a babbling node.
 * Every expected time is the formula written out, in bit times at 500 kbit/s.
 */
#include "fcc_test.h"

#include <string.h>

#include "canbus_core.h"
#include "canbus_faults.h"
#include "canbus_frame.h"

#define BIT_NS 2000u /* 500 kbit/s */
#define MS 1000000u

static canbus_frame_t frame(uint32_t id)
{
    canbus_frame_t f;
    memset(&f, 0, sizeof f);
    f.id = id;
    f.dlc = 8u;
    memset(f.data, 0x55, 8u);
    return f;
}

static void init_bus(canbus_core_t *c, uint32_t nodes)
{
    const canbus_policy_t policy[4] = {CANBUS_PRIO, CANBUS_PRIO, CANBUS_PRIO, CANBUS_FIFO};
    assert_true(nodes <= 4u);
    assert_int_equal(canbus_core_init(c, 500000u, nodes, policy), FCC_OK);
}

static canbus_fault_t fault_on(uint32_t id, uint32_t node, uint32_t count)
{
    canbus_fault_t f;
    memset(&f, 0, sizeof f);
    f.id_min = id;
    f.id_max = id;
    f.node = node;
    f.t_to = UINT64_MAX;
    f.every = 1u;
    f.count = count;
    f.bit = CANBUS_BIT_CRC_DELIM;
    return f;
}

static void queue(canbus_core_t *c, uint32_t node, uint32_t id, uint64_t t)
{
    const canbus_frame_t f = frame(id);
    assert_int_equal(canbus_core_queue(c, node, &f, t), FCC_OK);
}

/* The next frame that ends by t (one must). */
static canbus_done_t next_done(canbus_core_t *c, uint64_t t)
{
    canbus_done_t d;
    assert_true(canbus_core_advance(c, t, &d));
    return d;
}

/* The first event of kind for node, taking the others before it. */
static canbus_event_t find_event(canbus_core_t *c, uint32_t node, canbus_event_kind_t kind,
                                 canbus_state_t state)
{
    canbus_event_t e;
    while (canbus_core_event(c, &e)) {
        if (e.node == node && e.kind == kind && (kind != CANBUS_EV_STATE || e.state == state)) {
            return e;
        }
    }
    fail_msg("no such event");
    return e;
}

/* An error frame's bits from its corrupted frame's SOF: through the error's bit (P + 1),
 * error flag 6, superposed flags E, error delimiter 8, interframe space 3. */
static uint64_t error_bits(uint32_t p, uint32_t e)
{
    return (uint64_t)p + 1u + 6u + e + 8u + 3u;
}

static void test_retransmission_ends_at_the_formula(void **state)
{
    (void)state;
    static const struct {
        uint32_t bit, superposed;
    } cases[] = {{CANBUS_BIT_CRC_DELIM, 0u}, {CANBUS_BIT_CRC_DELIM, 6u}, {20u, 3u}, {0u, 0u}};
    const canbus_frame_t f = frame(0x100u);
    const uint32_t b = canbus_frame_bits(&f);
    for (size_t k = 0u; k < sizeof cases / sizeof cases[0]; ++k) {
        canbus_core_t c;
        init_bus(&c, 2u);
        canbus_fault_t fault = fault_on(0x100u, CANBUS_ANY_NODE, 1u);
        fault.bit = cases[k].bit;
        fault.superposed = cases[k].superposed;
        assert_int_equal(canbus_core_add_fault(&c, &fault), FCC_OK);
        queue(&c, 0u, 0x100u, 0u);
        /* P: the CRC delimiter is the first bit after the stuffed region, b - 13 */
        const uint32_t p = cases[k].bit == CANBUS_BIT_CRC_DELIM ? b - 13u : cases[k].bit;
        const uint64_t sof = error_bits(p, cases[k].superposed) * BIT_NS;
        uint64_t t;
        bool is_eof;
        assert_true(canbus_core_next(&c, &t, &is_eof)); /* the first SOF, at once */
        const canbus_done_t d = next_done(&c, MS);
        assert_int_equal(d.t_sof, sof);
        assert_int_equal(d.t_eof, sof + (uint64_t)(b - 3u) * BIT_NS);
        assert_int_equal(d.t_queued, 0u);
        assert_int_equal(c.error_frames, 1u);
        const canbus_event_t tx = find_event(&c, 0u, CANBUS_EV_TX_ERROR, CANBUS_ERROR_ACTIVE);
        assert_int_equal(tx.t, (uint64_t)(p + 1u) * BIT_NS);
        assert_int_equal(tx.tec, 8u);
        assert_int_equal(tx.bit, p);
        assert_int_equal(tx.id, 0x100u);
        /* after the good retransmission: TEC 8 - 1, REC 1 - 1 */
        assert_int_equal(canbus_core_confine(&c, 0u)->tec, 7u);
        assert_int_equal(canbus_core_confine(&c, 0u)->tec_max, 8u);
        assert_int_equal(canbus_core_confine(&c, 1u)->rec, 0u);
        assert_int_equal(canbus_core_confine(&c, 1u)->rec_max, 1u);
    }
}

static void test_error_frame_lets_a_higher_frame_win_the_retry(void **state)
{
    (void)state;
    canbus_core_t c;
    init_bus(&c, 2u);
    const canbus_fault_t fault = fault_on(0x100u, CANBUS_ANY_NODE, 1u);
    assert_int_equal(canbus_core_add_fault(&c, &fault), FCC_OK);
    queue(&c, 0u, 0x100u, 0u);
    queue(&c, 1u, 0x050u, 10u * BIT_NS); /* during the corrupted frame */
    const canbus_done_t first = next_done(&c, MS);
    assert_int_equal(first.frame.id, 0x050u);
    const canbus_done_t second = next_done(&c, MS);
    assert_int_equal(second.frame.id, 0x100u);
    assert_int_equal(second.t_sof, first.t_eof + 3u * BIT_NS);
}

static void test_every_nth_counts_frames_not_retransmissions(void **state)
{
    (void)state;
    canbus_core_t c;
    init_bus(&c, 2u);
    canbus_fault_t fault = fault_on(0x100u, CANBUS_ANY_NODE, 0u);
    fault.every = 2u;
    assert_int_equal(canbus_core_add_fault(&c, &fault), FCC_OK);
    for (uint32_t k = 0u; k < 6u; ++k) {
        queue(&c, 0u, 0x100u, (uint64_t)k * MS);
    }
    canbus_done_t d;
    uint32_t done = 0u;
    while (canbus_core_advance(&c, 10u * MS, &d)) {
        /* the 2nd, 4th, 6th frames: one error each, then sent again at the formula's time */
        const uint64_t extra = (done % 2u == 1u) ? error_bits(d.bits - 13u, 0u) * BIT_NS : 0u;
        assert_int_equal(d.t_sof, (uint64_t)done * MS + extra);
        ++done;
    }
    assert_int_equal(done, 6u);
    assert_int_equal(c.error_frames, 3u);
}

/* Attempt k (1-based) of a frame every attempt of which is corrupted at bit p: attempts are
 * error_bits(p, 0) apart, and from the 16th error on (TEC >= 128, error-passive) the
 * transmitter suspends 8 bits before the next. */
static uint64_t attempt_sof(uint32_t k, uint32_t p)
{
    const uint32_t suspended = k > 16u ? k - 16u : 0u;
    return ((uint64_t)(k - 1u) * error_bits(p, 0u) + 8u * suspended) * BIT_NS;
}

static void test_error_passive_at_the_16th_transmit_error(void **state)
{
    (void)state;
    canbus_core_t c;
    init_bus(&c, 2u);
    const canbus_fault_t fault = fault_on(0x100u, 0u, 16u);
    assert_int_equal(canbus_core_add_fault(&c, &fault), FCC_OK);
    queue(&c, 0u, 0x100u, 0u);
    const uint32_t b = canbus_frame_bits(&(canbus_frame_t){.id = 0x100u, .dlc = 8u,
                                                           .data = {0x55, 0x55, 0x55, 0x55,
                                                                    0x55, 0x55, 0x55, 0x55}});
    const uint32_t p = b - 13u;
    const canbus_done_t d = next_done(&c, 100u * MS);
    const canbus_event_t warn = find_event(&c, 0u, CANBUS_EV_STATE, CANBUS_ERROR_WARNING);
    assert_int_equal(warn.tec, 96u); /* the 12th error */
    assert_int_equal(warn.t, attempt_sof(12u, p) + (uint64_t)(p + 1u) * BIT_NS);
    const canbus_event_t passive = find_event(&c, 0u, CANBUS_EV_STATE, CANBUS_ERROR_PASSIVE);
    assert_int_equal(passive.tec, 128u);
    assert_int_equal(passive.t, attempt_sof(16u, p) + (uint64_t)(p + 1u) * BIT_NS);
    /* the 17th attempt succeeds, after the suspend transmission of an error-passive node */
    assert_int_equal(d.t_sof, attempt_sof(17u, p));
    assert_int_equal(d.t_sof, (16u * (p + 18u) + 8u) * (uint64_t)BIT_NS);
    const canbus_confine_t *n = canbus_core_confine(&c, 0u);
    assert_int_equal(n->tec, 127u);
    assert_int_equal(n->passive_episodes, 1u);
    assert_int_equal(n->state, CANBUS_ERROR_WARNING);
    assert_int_equal(canbus_core_confine(&c, 1u)->rec, 15u);
}

static void test_bus_off_at_the_32nd_and_recovery_after_128_x_11_bits(void **state)
{
    (void)state;
    canbus_core_t c;
    init_bus(&c, 2u);
    canbus_fault_t fault = fault_on(0u, 0u, 0u);
    fault.id_max = CANBUS_EXT_ID_MAX; /* a forced bus-off: every frame of node 0 */
    fault.until_bus_off = true;
    assert_int_equal(canbus_core_add_fault(&c, &fault), FCC_OK);
    queue(&c, 0u, 0x100u, 0u);
    queue(&c, 0u, 0x200u, 0u);
    const uint32_t b = canbus_frame_bits(&(canbus_frame_t){.id = 0x100u, .dlc = 8u,
                                                           .data = {0x55, 0x55, 0x55, 0x55,
                                                                    0x55, 0x55, 0x55, 0x55}});
    const uint32_t p = b - 13u;
    canbus_done_t d;
    assert_false(canbus_core_advance(&c, 100u * MS, &d)); /* nothing of node 0 gets through */
    const canbus_event_t off = find_event(&c, 0u, CANBUS_EV_STATE, CANBUS_BUS_OFF);
    const uint64_t t_off = attempt_sof(32u, p) + (uint64_t)(p + 1u) * BIT_NS;
    assert_int_equal(off.t, t_off);
    assert_int_equal(off.tec, 256u);
    const canbus_confine_t *n = canbus_core_confine(&c, 0u);
    assert_int_equal(n->tx_errors, 32u);
    assert_int_equal(n->bus_off_episodes, 1u);
    assert_int_equal(n->dropped, 2u); /* its queue: SocketCAN's at bus-off */
    /* recovery: the run starts after the 32nd error flag (6 bits), 128 x 11 recessive bits */
    const canbus_event_t back = find_event(&c, 0u, CANBUS_EV_RESTARTED, CANBUS_ERROR_ACTIVE);
    const uint64_t flag_end = t_off + 6u * BIT_NS;
    assert_int_equal(back.t, flag_end + 128u * 11u * BIT_NS);
    assert_int_equal(back.tec, 0u);
    assert_int_equal(back.rec, 0u);
    assert_int_equal(n->state, CANBUS_ERROR_ACTIVE);
    assert_int_equal(n->recovery_ns_max, back.t - t_off);
    /* the fault is spent: the node sends again */
    queue(&c, 0u, 0x100u, 100u * MS);
    d = next_done(&c, 101u * MS);
    assert_int_equal(d.t_sof, 100u * MS);
}

static void test_bus_off_node_refuses_frames_and_counts_runs_on_a_busy_bus(void **state)
{
    (void)state;
    canbus_core_t c;
    init_bus(&c, 2u);
    canbus_fault_t fault = fault_on(0x100u, 0u, 0u);
    fault.until_bus_off = true;
    assert_int_equal(canbus_core_add_fault(&c, &fault), FCC_OK);
    queue(&c, 0u, 0x100u, 0u);
    const canbus_frame_t f = frame(0x100u);
    const uint32_t p = canbus_frame_bits(&f) - 13u;
    const uint64_t flag_end = attempt_sof(32u, p) + (uint64_t)(p + 1u + 6u) * BIT_NS;
    /* node 1 babbles back to back from the bus-off error's end (delimiter 8 + IFS 3 after the
     * flag: the first 11 recessive bits); each of its frames' tails (ACK delimiter, EOF 7,
     * IFS 3) is 11 more, one occurrence each: the 128th is the tail of its 127th frame */
    canbus_babble_t bab;
    memset(&bab, 0, sizeof bab);
    bab.node = 1u;
    bab.frame = frame(0x300u);
    bab.t_from = flag_end + 11u * BIT_NS;
    bab.t_to = UINT64_MAX;
    assert_int_equal(canbus_core_add_babble(&c, &bab), FCC_OK);
    const uint64_t bb = canbus_frame_bits(&bab.frame) * (uint64_t)BIT_NS;
    canbus_done_t d;
    uint32_t frames = 0u;
    while (canbus_core_advance(&c, 200u * MS, &d) &&
           canbus_core_confine(&c, 0u)->state == CANBUS_BUS_OFF) {
        assert_int_equal(d.t_sof, bab.t_from + frames * bb);
        ++frames;
        if (frames == 1u) {
            assert_int_equal(canbus_core_queue(&c, 0u, &f, d.t_eof), FCC_ERR_IO);
            /* the frame in its queue at bus-off, and this one */
            assert_int_equal(canbus_core_confine(&c, 0u)->dropped, 2u);
        }
    }
    const canbus_event_t off = find_event(&c, 0u, CANBUS_EV_STATE, CANBUS_BUS_OFF);
    assert_int_equal(off.t + 6u * BIT_NS, flag_end);
    const canbus_event_t back = find_event(&c, 0u, CANBUS_EV_RESTARTED, CANBUS_ERROR_ACTIVE);
    assert_int_equal(back.t, bab.t_from + 127u * bb);
    assert_int_equal(frames, 127u); /* the 128th started as it recovered */
}

static void test_babbling_node_starves_lower_identifiers_not_higher(void **state)
{
    (void)state;
    canbus_core_t c;
    init_bus(&c, 3u);
    canbus_babble_t bab;
    memset(&bab, 0, sizeof bab);
    bab.node = 2u;
    bab.frame = frame(0x080u);
    bab.t_from = 0u;
    bab.t_to = 10u * MS; /* back to back for 10 ms */
    assert_int_equal(canbus_core_add_babble(&c, &bab), FCC_OK);
    queue(&c, 0u, 0x040u, 1u * MS);
    queue(&c, 1u, 0x100u, 1u * MS);
    const uint64_t b = canbus_frame_bits(&bab.frame) * (uint64_t)BIT_NS;
    canbus_done_t d;
    uint64_t higher_eof = 0u, lower_sof = 0u;
    uint32_t babbled = 0u;
    while (canbus_core_advance(&c, 20u * MS, &d)) {
        if (d.frame.id == 0x040u) {
            higher_eof = d.t_eof;
        } else if (d.frame.id == 0x100u) {
            lower_sof = d.t_sof;
        } else {
            ++babbled;
        }
    }
    /* 0x040 waits for the babbler's frame on the wire at 1 ms only */
    const canbus_frame_t higher = frame(0x040u);
    const uint64_t on_wire_end = (1u * MS / b + 1u) * b;
    assert_int_equal(higher_eof, on_wire_end + (canbus_frame_bits(&higher) - 3u) * BIT_NS);
    /* 0x100 only after the babbler's last frame, queued before 10 ms */
    assert_true(lower_sof >= 10u * MS);
    assert_true(lower_sof < 10u * MS + 2u * b);
    /* the babbler held the bus all the while, but for 0x040's frame */
    assert_int_equal(babbled * b + canbus_frame_bits(&higher) * (uint64_t)BIT_NS, lower_sof);
}

static void test_periodic_babble_and_refusals(void **state)
{
    (void)state;
    canbus_core_t c;
    init_bus(&c, 2u);
    canbus_babble_t bab;
    memset(&bab, 0, sizeof bab);
    bab.node = 1u;
    bab.frame = frame(0x7FFu);
    bab.period_ns = 1u * MS;
    bab.t_from = 2u * MS;
    bab.t_to = 5u * MS;
    assert_int_equal(canbus_core_add_babble(&c, &bab), FCC_OK);
    uint64_t t;
    bool is_eof = true;
    assert_true(canbus_core_next(&c, &t, &is_eof));
    assert_int_equal(t, 2u * MS);
    assert_false(is_eof);
    canbus_done_t d;
    for (uint32_t k = 0u; k < 3u; ++k) {
        d = next_done(&c, 10u * MS);
        assert_int_equal(d.t_sof, (2u + k) * (uint64_t)MS);
    }
    assert_false(canbus_core_advance(&c, 10u * MS, &d)); /* none from 5 ms */
    /* refusals */
    canbus_fault_t bad = fault_on(0x100u, CANBUS_ANY_NODE, 0u);
    bad.every = 0u;
    assert_int_equal(canbus_core_add_fault(&c, &bad), FCC_ERR_ARG);
    bad = fault_on(0x100u, 2u, 0u);
    assert_int_equal(canbus_core_add_fault(&c, &bad), FCC_ERR_ARG); /* no node 2 */
    bad = fault_on(0x100u, CANBUS_ANY_NODE, 0u);
    bad.bit = CANBUS_BIT_MAX + 1u;
    assert_int_equal(canbus_core_add_fault(&c, &bad), FCC_ERR_ARG);
    bad.bit = 0u;
    bad.superposed = 7u;
    assert_int_equal(canbus_core_add_fault(&c, &bad), FCC_ERR_ARG);
    bad.superposed = 0u;
    bad.until_bus_off = true; /* needs a node */
    assert_int_equal(canbus_core_add_fault(&c, &bad), FCC_ERR_ARG);
    bab.node = 2u;
    assert_int_equal(canbus_core_add_babble(&c, &bab), FCC_ERR_ARG);
    assert_true(canbus_core_size() == sizeof(canbus_core_t));
}

/* The same calls give the same frames and events (faults, babbling, bus-off included). */
static void run_faulty(canbus_core_t *c, canbus_done_t *done, size_t *n, canbus_event_t *ev,
                       size_t *m)
{
    init_bus(c, 4u);
    canbus_fault_t f = fault_on(0x100u, CANBUS_ANY_NODE, 0u);
    f.id_max = 0x1FFu;
    f.every = 3u;
    assert_int_equal(canbus_core_add_fault(c, &f), FCC_OK);
    f = fault_on(0u, 3u, 0u);
    f.id_max = CANBUS_EXT_ID_MAX;
    f.until_bus_off = true;
    f.t_from = 5u * MS;
    assert_int_equal(canbus_core_add_fault(c, &f), FCC_OK);
    canbus_babble_t bab = {.node = 2u, .frame = frame(0x180u), .period_ns = 700000u,
                           .t_from = 0u, .t_to = 30u * MS};
    assert_int_equal(canbus_core_add_babble(c, &bab), FCC_OK);
    *n = 0u;
    *m = 0u;
    for (uint32_t k = 0u; k < 120u; ++k) {
        const uint64_t t = (uint64_t)k * 250000u;
        (void)canbus_core_queue(c, k % 4u == 2u ? 0u : k % 4u, &(canbus_frame_t){.id = 0x0F0u + (k * 7u) % 0x40u, .dlc = 8u}, t);
        canbus_done_t d;
        while (canbus_core_advance(c, t, &d)) {
            done[(*n)++] = d;
        }
        canbus_event_t e;
        while (canbus_core_event(c, &e)) {
            ev[(*m)++] = e;
        }
    }
}

static void test_same_faults_same_outputs(void **state)
{
    (void)state;
    static canbus_core_t a, b;
    static canbus_done_t da[400], db[400];
    static canbus_event_t ea[4000], eb[4000];
    size_t na, nb, ma, mb;
    run_faulty(&a, da, &na, ea, &ma);
    run_faulty(&b, db, &nb, eb, &mb);
    assert_true(na > 50u);
    assert_true(ma > 50u);
    assert_int_equal(na, nb);
    assert_int_equal(ma, mb);
    assert_memory_equal(da, db, na * sizeof da[0]);
    assert_memory_equal(ea, eb, ma * sizeof ea[0]);
    assert_int_equal(canbus_core_confine(&a, 3u)->bus_off_episodes, 1u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_retransmission_ends_at_the_formula),
        cmocka_unit_test(test_error_frame_lets_a_higher_frame_win_the_retry),
        cmocka_unit_test(test_every_nth_counts_frames_not_retransmissions),
        cmocka_unit_test(test_error_passive_at_the_16th_transmit_error),
        cmocka_unit_test(test_bus_off_at_the_32nd_and_recovery_after_128_x_11_bits),
        cmocka_unit_test(test_bus_off_node_refuses_frames_and_counts_runs_on_a_busy_bus),
        cmocka_unit_test(test_babbling_node_starves_lower_identifiers_not_higher),
        cmocka_unit_test(test_periodic_babble_and_refusals),
        cmocka_unit_test(test_same_faults_same_outputs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
