#include "sid_replay_csv.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fcc_opt.h"

#define MAX_FIELDS 64u

enum { COL_T, COL_ALPHA, COL_Q, COL_DE, COL_FAULT, N_COLS };
static const char *const col_names[N_COLS] = {"t", "alpha", "q", "de", "fault"};

/* Strips leading and trailing blanks (and the CR of CRLF files) in place. */
static char *trim(char *s)
{
    while (*s != '\0' && isspace((unsigned char)*s)) {
        ++s;
    }
    size_t n = strlen(s);
    while (n > 0u && isspace((unsigned char)s[n - 1u])) {
        s[--n] = '\0';
    }
    return s;
}

/* Splits line at commas into at most MAX_FIELDS trimmed fields; returns
 * the count, or MAX_FIELDS + 1 when there are more. */
static size_t split(char *line, char *fields[MAX_FIELDS])
{
    size_t n = 0u;
    char *p = line;
    for (;;) {
        char *comma = strchr(p, ',');
        if (comma != NULL) {
            *comma = '\0';
        }
        if (n == MAX_FIELDS) {
            return MAX_FIELDS + 1u;
        }
        fields[n++] = trim(p);
        if (comma == NULL) {
            return n;
        }
        p = comma + 1;
    }
}

/* Reads one line; 1 = got one, 0 = end of file, -1 = too long, -2 = it holds a NUL byte
 * (which would end the C string early: a NUL-led line looked blank and was skipped). */
static int read_line(FILE *in, char *buf, size_t size)
{
    size_t n = 0u;
    bool nul = false;
    int c = EOF;
    while ((c = getc(in)) != EOF) {
        if (n + 1u == size) {
            return -1;
        }
        nul = nul || c == '\0';
        buf[n++] = (char)c;
        if (c == '\n') {
            break;
        }
    }
    buf[n] = '\0';
    if (n == 0u) {
        return 0;
    }
    return nul ? -2 : 1;
}

static int parse_header(char *line, int col_of[N_COLS], size_t *n_fields, char *err, size_t len)
{
    char *fields[MAX_FIELDS];
    const size_t n = split(line, fields);
    if (n > MAX_FIELDS) {
        return fcc_opt_fail(err, len, "header: more than %u columns", MAX_FIELDS);
    }
    for (size_t c = 0; c < N_COLS; ++c) {
        col_of[c] = -1;
    }
    for (size_t i = 0; i < n; ++i) {
        for (size_t c = 0; c < N_COLS; ++c) {
            if (strcmp(fields[i], col_names[c]) == 0) {
                if (col_of[c] >= 0) {
                    return fcc_opt_fail(err, len, "header: column '%s' appears twice",
                                        col_names[c]);
                }
                col_of[c] = (int)i;
            }
        }
    }
    for (size_t c = 0; c < COL_FAULT; ++c) {
        if (col_of[c] < 0) {
            return fcc_opt_fail(err, len, "header: missing column '%s' (need t,alpha,q,de)",
                                col_names[c]);
        }
    }
    *n_fields = n;
    return 0;
}

static int parse_number(const char *s, double *v)
{
    if (*s == '\0') {
        return -1;
    }
    char *end = NULL;
    errno = 0;
    *v = strtod(s, &end);
    return (end == s || *end != '\0' || errno == ERANGE) ? -1 : 0;
}

/* Parses the value of column c on line `lineno`, and checks it. */
static int field_value(char *fields[MAX_FIELDS], const int col_of[N_COLS], size_t c,
                       size_t lineno, const sid_csv_limits_t *lim, double *v, char *err,
                       size_t len)
{
    const char *s = fields[col_of[c]];
    if (parse_number(s, v) != 0) {
        return fcc_opt_fail(err, len, "line %zu: %s '%s' is not a number", lineno, col_names[c],
                            s);
    }
    if (!isfinite(*v)) {
        return fcc_opt_fail(err, len, "line %zu: %s is not finite (%s)", lineno, col_names[c], s);
    }
    const double limit = c == COL_ALPHA ? lim->alpha_limit
                         : c == COL_Q   ? lim->q_limit
                         : c == COL_DE  ? lim->de_limit
                                        : HUGE_VAL;
    if (fabs(*v) > limit) {
        return fcc_opt_fail(err, len, "line %zu: %s = %s is outside +/-%g", lineno, col_names[c],
                            s, limit);
    }
    return 0;
}

static int parse_row(char *line, size_t lineno, const int col_of[N_COLS], size_t n_fields,
                     const sid_csv_limits_t *lim, sid_flight_t *f, char *err, size_t len)
{
    char *fields[MAX_FIELDS];
    const size_t n = split(line, fields);
    if (n != n_fields) {
        return fcc_opt_fail(err, len, "line %zu: %zu fields, the header has %zu", lineno, n,
                            n_fields);
    }
    double v[N_COLS] = {0.0, 0.0, 0.0, 0.0, 0.0};
    for (size_t c = 0; c < N_COLS; ++c) {
        if (col_of[c] >= 0 && field_value(fields, col_of, c, lineno, lim, &v[c], err, len) != 0) {
            return -1;
        }
    }
    if (col_of[COL_FAULT] >= 0 && v[COL_FAULT] != 0.0 && v[COL_FAULT] != 1.0) {
        return fcc_opt_fail(err, len, "line %zu: fault must be 0 or 1", lineno);
    }
    const size_t k = f->n;
    if (k > 0u && !(v[COL_T] > f->t[k - 1u])) {
        return fcc_opt_fail(err, len, "line %zu: time %.17g does not increase (previous %.17g)",
                            lineno, v[COL_T], f->t[k - 1u]);
    }
    f->t[k] = v[COL_T];
    f->alpha[k] = v[COL_ALPHA];
    f->q[k] = v[COL_Q];
    f->de[k] = v[COL_DE];
    f->fault[k] = (unsigned char)(v[COL_FAULT] != 0.0);
    f->n = k + 1u;
    return 0;
}

int sid_csv_read(FILE *in, const sid_csv_limits_t *lim, sid_flight_t *flight, char *err,
                 size_t err_len)
{
    static char line[SID_CSV_MAX_LINE];
    int col_of[N_COLS];
    size_t n_fields = 0u;
    size_t lineno = 0u;
    bool have_header = false;
    flight->n = 0u;
    for (;;) {
        const int r = read_line(in, line, sizeof line);
        if (r == 0) {
            break;
        }
        ++lineno;
        if (r == -2) {
            return fcc_opt_fail(err, err_len, "line %zu: contains a NUL byte (not a text CSV)",
                                lineno);
        }
        if (r < 0) {
            return fcc_opt_fail(err, err_len, "line %zu: longer than %u characters", lineno,
                                SID_CSV_MAX_LINE - 2u);
        }
        char *s = trim(line);
        if (*s == '\0') {
            continue; /* blank lines are allowed */
        }
        if (!have_header) {
            if (parse_header(s, col_of, &n_fields, err, err_len) != 0) {
                return -1;
            }
            have_header = true;
            continue;
        }
        if (flight->n == SID_CSV_MAX_ROWS) {
            return fcc_opt_fail(err, err_len, "more than %u data rows", SID_CSV_MAX_ROWS);
        }
        if (parse_row(s, lineno, col_of, n_fields, lim, flight, err, err_len) != 0) {
            return -1;
        }
    }
    if (ferror(in)) {
        return fcc_opt_fail(err, err_len, "read error");
    }
    if (!have_header) {
        return fcc_opt_fail(err, err_len, "empty input: no header line (need t,alpha,q,de)");
    }
    if (flight->n == 0u) {
        return fcc_opt_fail(err, err_len, "no data rows after the header");
    }
    flight->has_fault = col_of[COL_FAULT] >= 0;
    return 0;
}
