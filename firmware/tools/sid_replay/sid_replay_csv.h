/*
 * sid_replay_csv.h -- the flight CSV that sid_replay reads.
 *
 * Header line with column names, in any order: t, alpha, q, de (s, rad,
 * rad/s, rad) are required, fault (0/1, for the oracle detector) optional,
 * any other column ignored (so a simulator log with truth columns can be fed
 * as it is).  Every value must be a finite number within the plausibility
 * limits, time strictly increasing.  The rows are kept in static arrays
 * (host tool, no heap): at most SID_CSV_MAX_ROWS.
 */
#ifndef SID_REPLAY_CSV_H
#define SID_REPLAY_CSV_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#define SID_CSV_MAX_ROWS 200000u
#define SID_CSV_MAX_LINE 4096u
#define SID_CSV_ERR_LEN 256u

typedef struct {
    double t[SID_CSV_MAX_ROWS];
    double alpha[SID_CSV_MAX_ROWS];
    double q[SID_CSV_MAX_ROWS];
    double de[SID_CSV_MAX_ROWS];
    unsigned char fault[SID_CSV_MAX_ROWS];
    size_t n;
    bool has_fault;
} sid_flight_t;

typedef struct {
    double alpha_limit; /* |alpha| above is refused */
    double q_limit;
    double de_limit;
} sid_csv_limits_t;

/* Reads the whole stream into flight.  Returns 0, or -1 with one
 * human-readable line (no newline) in err. */
int sid_csv_read(FILE *in, const sid_csv_limits_t *lim, sid_flight_t *flight, char *err,
                 size_t err_len);

#endif /* SID_REPLAY_CSV_H */
