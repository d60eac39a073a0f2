/*
 * test_socketcan.c -- the SocketCAN port's bad-input paths, which need no CAN
 * interface: a missing interface, bad names, bad filters, a closed port.  The
 * port's traffic is tested over vcan0 by tests/python/test_bus_vcan.py (can_echo).
 */
#include "fcc_test.h"

#include <string.h>

#include "fcc_socketcan.h"

static void test_open_bad_names(void **state)
{
    (void)state;
    fcc_socketcan_t s;
    assert_int_equal(fcc_socketcan_open(NULL, "vcan0"), FCC_ERR_ARG);
    assert_int_equal(fcc_socketcan_open(&s, NULL), FCC_ERR_ARG);
    assert_int_equal(s.fd, -1);
    assert_int_equal(fcc_socketcan_open(&s, ""), FCC_ERR_ARG);
    assert_int_equal(fcc_socketcan_open(&s, "a_name_longer_than_ifnamsiz"), FCC_ERR_ARG);
    /* No such interface (or no CAN in this kernel at all): an I/O error, no crash. */
    assert_int_equal(fcc_socketcan_open(&s, "nocan7"), FCC_ERR_IO);
    assert_int_equal(s.fd, -1);
}

static void test_closed_port_refuses_everything(void **state)
{
    (void)state;
    fcc_socketcan_t s;
    assert_int_equal(fcc_socketcan_open(&s, "nocan7"), FCC_ERR_IO);
    fcc_can_frame_t f;
    memset(&f, 0, sizeof f);
    const uint32_t ids[1] = {0x50u};
    assert_int_equal(fcc_socketcan_recv(&s, &f), FCC_ERR_ARG);
    assert_int_equal(fcc_socketcan_send(&s, &f), FCC_ERR_ARG);
    assert_int_equal(fcc_socketcan_wait(&s, 0), FCC_ERR_ARG);
    assert_int_equal(fcc_socketcan_set_filters(&s, ids, 1u), FCC_ERR_ARG);
    fcc_can_port_counters_t c;
    fcc_assert_ok(fcc_socketcan_counters(&s, &c));
    assert_int_equal(c.tx_frames, 0u);
    assert_int_equal(fcc_socketcan_counters(NULL, &c), FCC_ERR_ARG);
    fcc_socketcan_close(&s);
    fcc_socketcan_close(&s); /* twice is harmless */
    fcc_socketcan_close(NULL);

    /* The port interface forwards to the same functions. */
    fcc_can_port_t port = fcc_socketcan_port(&s);
    assert_ptr_equal(port.ctx, &s);
    assert_int_equal(port.send(port.ctx, &f), FCC_ERR_ARG);
    assert_int_equal(port.recv(port.ctx, &f), FCC_ERR_ARG);
    fcc_assert_ok(port.counters(port.ctx, &c));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_open_bad_names),
        cmocka_unit_test(test_closed_port_refuses_everything),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
