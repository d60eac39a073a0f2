/*
 * fcc_hist.h -- a fixed-size log-linear histogram of microsecond durations.
 *
 * Step times, start jitter and latencies are measured for every step of runs
 * that may last hours; storing samples would need the heap or a cap.  This
 * keeps exact counts below 128 us and 64 buckets per octave above (1.6 %
 * resolution) in ~7 kB, so p50/p99 are exact to that resolution whatever the
 * run length, and the maximum is exact.
 */
#ifndef FCC_HIST_H
#define FCC_HIST_H

#include <stdint.h>

#define FCC_HIST_LINEAR 128u
#define FCC_HIST_SUB 64u
#define FCC_HIST_BUCKETS (FCC_HIST_LINEAR + 25u * FCC_HIST_SUB)

typedef struct {
    uint32_t bucket[FCC_HIST_BUCKETS];
    uint64_t n;
    uint64_t max;
    uint64_t sum;
} fcc_hist_t;

void fcc_hist_init(fcc_hist_t *h);
void fcc_hist_add(fcc_hist_t *h, uint64_t value_us);
/* The p-quantile (0 < p <= 1): the lower edge of the bucket that holds it
 * (exact below 128), the maximum for p = 1; 0 when empty. */
uint64_t fcc_hist_quantile(const fcc_hist_t *h, double p);

#endif /* FCC_HIST_H */
