/*
 * canbus_hist.h -- a histogram of durations in nanoseconds, fixed size, for
 * percentiles without keeping every sample.
 *
 * Buckets: exact below 128 ns, then 64 to each power of two (a bucket is at
 * most 1/64 = 1.6 % of its values wide) up to 2^42 ns (73 min; longer ones
 * fall into the last bucket).  The count, minimum and maximum are exact; a
 * percentile is the upper edge of the bucket holding it (at most the
 * maximum), so it is never below the true one and at most 1.6 % above.
 */
#ifndef CANBUS_HIST_H
#define CANBUS_HIST_H

#include <stdint.h>

#define CANBUS_HIST_SUB 64u
#define CANBUS_HIST_SHIFT_MAX 35u
#define CANBUS_HIST_BUCKETS ((CANBUS_HIST_SHIFT_MAX + 2u) * CANBUS_HIST_SUB)

typedef struct {
    uint32_t count[CANBUS_HIST_BUCKETS];
    uint64_t n;
    uint64_t min;
    uint64_t max;
} canbus_hist_t;

void canbus_hist_init(canbus_hist_t *h);
void canbus_hist_add(canbus_hist_t *h, uint64_t v);

/* The num/den quantile (e.g. 99/100), 0 for an empty histogram. */
uint64_t canbus_hist_quantile(const canbus_hist_t *h, uint64_t num, uint64_t den);

#endif /* CANBUS_HIST_H */
