/*
 * fcc_report.h -- the port's event sink on Linux: one stderr line per event
 * class, rate-limited.
 *
 * A babbling node can produce thousands of bad frames a second; the log must
 * stay readable and the program must not spend its time writing.  The first
 * event of a class is printed at once, then at most one line per class per
 * interval, each saying how many of that class were not printed since the
 * previous line.  Totals per class are kept for the exit summary.
 */
#ifndef FCC_REPORT_H
#define FCC_REPORT_H

#include <stdint.h>
#include <stdio.h>

#include "fcc_event.h"

#define FCC_REPORT_DEFAULT_INTERVAL_US 1000000u

typedef struct {
    FILE *out;
    uint64_t interval_us;
    uint64_t (*now_us)(void);
    uint64_t last_us[FCC_EV_COUNT];
    uint32_t suppressed[FCC_EV_COUNT]; /* since the last line of the class */
    uint32_t total[FCC_EV_COUNT];
    uint32_t printed[FCC_EV_COUNT];
} fcc_report_t;

void fcc_report_init(fcc_report_t *r, FILE *out, uint64_t interval_us, uint64_t (*now_us)(void));

/* The fcc_port_t.event callback (ctx = fcc_report_t *). */
void fcc_report_event(void *ctx, const fcc_event_t *ev);

/* One line per class with events not printed yet (at exit). */
void fcc_report_flush(fcc_report_t *r);

/* "events unknown_can_id=3 ..." for the classes seen, into buf. */
void fcc_report_totals(const fcc_report_t *r, char *buf, size_t len);

#endif /* FCC_REPORT_H */
