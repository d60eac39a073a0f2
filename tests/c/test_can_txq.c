/*
 * test_can_txq.c -- the transmit queue (firmware/bus/fcc_can_txq.h): frames
 * held until a flush hands them to the port's send_many in one call, in order,
 * each reported with the port's own status and the caller's tag; a full queue
 * flushed before the next frame; a port without send_many sent frame by frame.
 * The port here records every call; the node's use of the queue is tested in
 * test_app_node.c, the Linux port's sendmmsg in test_socketcan.c.
 */
#include "fcc_test.h"

#include <stdbool.h>
#include <string.h>

#include "fcc_can_txq.h"

#define REC_MAX 64u

typedef struct {
    fcc_can_frame_t sent[REC_MAX]; /* every frame the port took, in order */
    uint32_t n_sent;
    uint32_t send_calls;
    uint32_t many_calls;
    uint32_t many_len[REC_MAX];    /* frames in each send_many call */
    uint32_t refuse_id;            /* frames with this id get refuse_st */
    fcc_status_t refuse_st;
    bool silent;                   /* send_many writes no status at all */
} rec_port_t;

typedef struct {
    uint32_t n;
    uint32_t id[REC_MAX];
    uint8_t tag[REC_MAX];
    fcc_status_t st[REC_MAX];
    fcc_can_txq_t *resend_q;       /* non-NULL: the first report queues one more frame */
    const fcc_can_port_t *resend_port;
} reports_t;

static fcc_status_t rec_one(rec_port_t *p, const fcc_can_frame_t *f)
{
    if (p->refuse_st != FCC_OK && f->id == p->refuse_id) {
        return p->refuse_st;
    }
    if (p->n_sent < REC_MAX) {
        p->sent[p->n_sent++] = *f;
    }
    return FCC_OK;
}

static fcc_status_t rec_send(void *ctx, const fcc_can_frame_t *f)
{
    rec_port_t *p = ctx;
    ++p->send_calls;
    return rec_one(p, f);
}

static fcc_status_t rec_send_many(void *ctx, const fcc_can_frame_t *f, uint32_t n,
                                  fcc_status_t *st)
{
    rec_port_t *p = ctx;
    p->many_len[p->many_calls++ % REC_MAX] = n;
    fcc_status_t first = FCC_OK;
    for (uint32_t i = 0u; i < n && !p->silent; ++i) {
        st[i] = rec_one(p, &f[i]);
        first = (first == FCC_OK) ? st[i] : first;
    }
    return p->silent ? FCC_ERR_IO : first;
}

static void on_done(void *ctx, const fcc_can_frame_t *f, uint8_t tag, fcc_status_t st)
{
    reports_t *r = ctx;
    if (r->n < REC_MAX) {
        r->id[r->n] = f->id;
        r->tag[r->n] = tag;
        r->st[r->n] = st;
        ++r->n;
    }
    if (r->resend_q != NULL) {
        fcc_can_txq_t *q = r->resend_q;
        r->resend_q = NULL;
        fcc_can_frame_t again = *f;
        again.id = 0x7FFu;
        fcc_assert_ok(fcc_can_txq_send(q, r->resend_port, &again, 9u, on_done, r));
    }
}

static fcc_can_frame_t frame(uint32_t id)
{
    fcc_can_frame_t f;
    memset(&f, 0, sizeof f);
    f.id = id;
    f.dlc = 8u;
    for (uint8_t i = 0u; i < 8u; ++i) {
        f.data[i] = (uint8_t)(id + i);
    }
    return f;
}

/* What every test starts from: a recording port (batched: with send_many), an
 * empty queue, no reports. */
typedef struct {
    rec_port_t p;
    fcc_can_port_t port;
    fcc_can_txq_t q;
    reports_t r;
} fixture_t;

static fixture_t t;

static void fixture(fixture_t *f, bool batched)
{
    memset(f, 0, sizeof *f);
    f->port.ctx = &f->p;
    f->port.send = rec_send;
    f->port.send_many = batched ? rec_send_many : NULL;
    fcc_assert_ok(fcc_can_txq_init(&f->q));
}

static void test_frames_wait_for_the_flush_and_leave_in_order(void **state)
{
    (void)state;
    fixture(&t, true);
    for (uint32_t i = 0u; i < 13u; ++i) {
        const fcc_can_frame_t f = frame(0x100u + i);
        fcc_assert_ok(fcc_can_txq_send(&t.q, &t.port, &f, (uint8_t)(i % 3u), on_done, &t.r));
    }
    assert_int_equal(t.p.many_calls + t.p.send_calls, 0u); /* nothing left yet */
    assert_int_equal(t.r.n, 0u);
    assert_int_equal(t.q.n, 13u);
    fcc_assert_ok(fcc_can_txq_flush(&t.q, &t.port, on_done, &t.r));
    assert_int_equal(t.p.many_calls, 1u); /* one call for the whole step */
    assert_int_equal(t.p.many_len[0], 13u);
    assert_int_equal(t.p.send_calls, 0u);
    assert_int_equal(t.q.n, 0u);
    assert_int_equal(t.p.n_sent, 13u);
    assert_int_equal(t.r.n, 13u);
    for (uint32_t i = 0u; i < 13u; ++i) {
        const fcc_can_frame_t f = frame(0x100u + i);
        assert_int_equal(t.p.sent[i].id, f.id); /* the same bytes, in order */
        assert_int_equal(t.p.sent[i].dlc, f.dlc);
        assert_memory_equal(t.p.sent[i].data, f.data, sizeof f.data);
        assert_int_equal(t.r.id[i], 0x100u + i);
        assert_int_equal(t.r.tag[i], i % 3u);
        assert_int_equal(t.r.st[i], FCC_OK);
    }
    /* an empty queue: no call at all */
    fcc_assert_ok(fcc_can_txq_flush(&t.q, &t.port, on_done, &t.r));
    assert_int_equal(t.p.many_calls, 1u);
    assert_int_equal(t.r.n, 13u);
}

static void test_a_full_queue_is_flushed_before_the_next_frame(void **state)
{
    (void)state;
    fixture(&t, true);
    const uint32_t n = 2u * FCC_CAN_TXQ_LEN + 3u;
    for (uint32_t i = 0u; i < n; ++i) {
        const fcc_can_frame_t f = frame(0x200u + i);
        fcc_assert_ok(fcc_can_txq_send(&t.q, &t.port, &f, 1u, on_done, &t.r));
        assert_true(t.q.n >= 1u && t.q.n <= FCC_CAN_TXQ_LEN);
    }
    assert_int_equal(t.p.many_calls, 2u);
    assert_int_equal(t.p.many_len[0], FCC_CAN_TXQ_LEN);
    assert_int_equal(t.p.many_len[1], FCC_CAN_TXQ_LEN);
    assert_int_equal(t.q.n, 3u);
    fcc_assert_ok(fcc_can_txq_flush(&t.q, &t.port, on_done, &t.r));
    assert_int_equal(t.p.many_len[2], 3u);
    assert_int_equal(t.p.n_sent, n);
    assert_int_equal(t.r.n, n);
    for (uint32_t i = 0u; i < n; ++i) {
        assert_int_equal(t.p.sent[i].id, 0x200u + i);
        assert_int_equal(t.r.id[i], 0x200u + i);
    }
}

static void test_each_frame_reported_with_the_ports_status(void **state)
{
    (void)state;
    fixture(&t, true);
    t.p.refuse_id = 0x302u;
    t.p.refuse_st = FCC_ERR_AGAIN; /* dropped after the port's bounded retry */
    for (uint32_t i = 0u; i < 5u; ++i) {
        const fcc_can_frame_t f = frame(0x300u + i);
        fcc_assert_ok(fcc_can_txq_send(&t.q, &t.port, &f, (uint8_t)i, on_done, &t.r));
    }
    assert_int_equal(fcc_can_txq_flush(&t.q, &t.port, on_done, &t.r), FCC_ERR_AGAIN);
    assert_int_equal(t.r.n, 5u);
    for (uint32_t i = 0u; i < 5u; ++i) {
        assert_int_equal(t.r.st[i], (i == 2u) ? FCC_ERR_AGAIN : FCC_OK);
        assert_int_equal(t.r.tag[i], i);
    }
    assert_int_equal(t.p.n_sent, 4u); /* the frames after the dropped one still went */
    assert_int_equal(t.p.sent[2].id, 0x303u);

    /* a port that reports nothing: every frame counts as not sent */
    t.p.silent = true;
    memset(&t.r, 0, sizeof t.r);
    const fcc_can_frame_t f = frame(0x310u);
    fcc_assert_ok(fcc_can_txq_send(&t.q, &t.port, &f, 0u, on_done, &t.r));
    fcc_assert_ok(fcc_can_txq_send(&t.q, &t.port, &f, 0u, on_done, &t.r));
    assert_int_equal(fcc_can_txq_flush(&t.q, &t.port, on_done, &t.r), FCC_ERR_IO);
    assert_int_equal(t.r.n, 2u);
    assert_int_equal(t.r.st[0], FCC_ERR_IO);
    assert_int_equal(t.r.st[1], FCC_ERR_IO);
    assert_int_equal(t.q.n, 0u);
}

static void test_a_report_may_send_again(void **state)
{
    (void)state;
    fixture(&t, true);
    t.r.resend_q = &t.q;
    t.r.resend_port = &t.port;
    const fcc_can_frame_t a = frame(0x400u);
    const fcc_can_frame_t b = frame(0x401u);
    fcc_assert_ok(fcc_can_txq_send(&t.q, &t.port, &a, 0u, on_done, &t.r));
    fcc_assert_ok(fcc_can_txq_send(&t.q, &t.port, &b, 0u, on_done, &t.r));
    fcc_assert_ok(fcc_can_txq_flush(&t.q, &t.port, on_done, &t.r));
    assert_int_equal(t.r.n, 2u);      /* both of the first batch reported ... */
    assert_int_equal(t.q.n, 1u);      /* ... and the frame sent from a report waits for the next */
    assert_int_equal(t.q.frame[0].id, 0x7FFu);
    fcc_assert_ok(fcc_can_txq_flush(&t.q, &t.port, on_done, &t.r));
    assert_int_equal(t.p.n_sent, 3u);
    assert_int_equal(t.p.sent[2].id, 0x7FFu);
}

static void test_a_port_without_send_many_sends_at_once(void **state)
{
    (void)state;
    fixture(&t, false);
    t.p.refuse_id = 0x501u;
    t.p.refuse_st = FCC_ERR_IO;
    const fcc_can_frame_t a = frame(0x500u);
    const fcc_can_frame_t b = frame(0x501u);
    fcc_assert_ok(fcc_can_txq_send(&t.q, &t.port, &a, 4u, on_done, &t.r));
    assert_int_equal(t.p.send_calls, 1u);
    assert_int_equal(t.r.n, 1u);
    assert_int_equal(fcc_can_txq_send(&t.q, &t.port, &b, 5u, on_done, &t.r), FCC_ERR_IO);
    assert_int_equal(t.r.n, 2u);
    assert_int_equal(t.r.st[1], FCC_ERR_IO);
    assert_int_equal(t.r.tag[1], 5u);
    assert_int_equal(t.q.n, 0u);
    fcc_assert_ok(fcc_can_txq_flush(&t.q, &t.port, on_done, &t.r)); /* nothing waits */
    assert_int_equal(t.p.send_calls, 2u);
    assert_int_equal(t.p.many_calls, 0u);
}

static void test_bad_arguments(void **state)
{
    (void)state;
    fixture(&t, true);
    const fcc_can_frame_t f = frame(0x600u);
    assert_int_equal(fcc_can_txq_init(NULL), FCC_ERR_ARG);
    assert_int_equal(fcc_can_txq_send(NULL, &t.port, &f, 0u, on_done, &t.r), FCC_ERR_ARG);
    assert_int_equal(fcc_can_txq_send(&t.q, NULL, &f, 0u, on_done, &t.r), FCC_ERR_ARG);
    assert_int_equal(fcc_can_txq_send(&t.q, &t.port, NULL, 0u, on_done, &t.r), FCC_ERR_ARG);
    assert_int_equal(fcc_can_txq_send(&t.q, &t.port, &f, 0u, NULL, &t.r), FCC_ERR_ARG);
    assert_int_equal(fcc_can_txq_flush(NULL, &t.port, on_done, &t.r), FCC_ERR_ARG);
    assert_int_equal(fcc_can_txq_flush(&t.q, NULL, on_done, &t.r), FCC_ERR_ARG);
    assert_int_equal(fcc_can_txq_flush(&t.q, &t.port, NULL, &t.r), FCC_ERR_ARG);
    t.port.send = NULL;
    assert_int_equal(fcc_can_txq_send(&t.q, &t.port, &f, 0u, on_done, &t.r), FCC_ERR_ARG);
    assert_int_equal(t.q.n, 0u);
    assert_int_equal(t.r.n, 0u);
    assert_int_equal(t.p.many_calls + t.p.send_calls, 0u);
}

/* Frames queued for a batching port are not flushed through one without send_many:
 * refused, they stay queued and leave with the next flush through the right port. */
static void test_queued_frames_need_send_many(void **state)
{
    (void)state;
    fixture(&t, true);
    const fcc_can_frame_t f = frame(0x610u);
    fcc_assert_ok(fcc_can_txq_send(&t.q, &t.port, &f, 1u, on_done, &t.r));
    fcc_can_port_t single = t.port;
    single.send_many = NULL;
    assert_int_equal(fcc_can_txq_flush(&t.q, &single, on_done, &t.r), FCC_ERR_ARG);
    assert_int_equal(t.q.n, 1u);
    assert_int_equal(t.r.n, 0u);
    fcc_assert_ok(fcc_can_txq_flush(&t.q, &t.port, on_done, &t.r));
    assert_int_equal(t.q.n, 0u);
    assert_int_equal(t.p.n_sent, 1u);
    assert_int_equal(t.r.n, 1u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_frames_wait_for_the_flush_and_leave_in_order),
        cmocka_unit_test(test_a_full_queue_is_flushed_before_the_next_frame),
        cmocka_unit_test(test_each_frame_reported_with_the_ports_status),
        cmocka_unit_test(test_a_report_may_send_again),
        cmocka_unit_test(test_a_port_without_send_many_sends_at_once),
        cmocka_unit_test(test_bad_arguments),
        cmocka_unit_test(test_queued_frames_need_send_many),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
