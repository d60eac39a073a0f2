/*
 * fcc_opt_sid.h -- the identification options (MLS, filters, fault detector)
 * of the host programs, applied to an fcc_sid_config_t.
 *
 * fcc (on the bus) and sid_replay (offline) take these options with the same
 * names, value ranges, error texts and usage text, so that a replayed flight
 * and a bus flight can be compared option for option; this is the only copy.
 * Options that belong to one program stay in that program (sid_replay:
 * --filter, --mls-only, --fixed-model; fcc: --iface, --mode, --lqg-*, ...).
 *
 * Value ranges are those of the firmware's configuration checks (e.g. the
 * compile-time bounds FCC_MLS_MAX_WINDOW, FCC_ZONO_MAX_ORDER), plus sanity
 * bounds on the reals, so a wrong value is refused by name at parse time.
 * Cross-field checks (min-transitions <= window, P0 positive definite, F
 * invertible) remain the firmware's (fcc_sid_config_check).
 */
#ifndef FCC_OPT_SID_H
#define FCC_OPT_SID_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "fcc_opt.h"
#include "fcc_sid.h"

typedef struct {
    fcc_sid_config_t *cfg;       /* the caller's configuration, holding its defaults */
    bool prior_given;            /* a model option was applied (else the default prior) */
    bool min_transitions_given;  /* --min-transitions given (else clamped to the window) */
} fcc_opt_sid_t;

/* Starts a parse into cfg, which already holds the defaults
 * (fcc_sid_config_default or the application's). */
void fcc_opt_sid_begin(fcc_opt_sid_t *s, fcc_sid_config_t *cfg);

/* One identification option or flag (an fcc_opt_handler_t protocol, see
 * fcc_opt.h): FCC_OPT_DONE, FCC_OPT_NOT_MINE, FCC_OPT_NEED_VALUE, or
 * FCC_OPT_ERROR with one line in err. */
fcc_opt_result_t fcc_opt_sid_apply(fcc_opt_sid_t *s, const char *name, const char *val,
                                   char *err, size_t err_len);

/* A model a11,a12,a21,a22,b1,b2 (c = 0, the paper's form) or with c1,c2
 * (which turns the MLS intercept on) into cfg->mls.prior: --prior, and the
 * model options of a program (sid_replay's --fixed-model). */
fcc_opt_result_t fcc_opt_sid_model(fcc_opt_sid_t *s, const char *name, const char *val,
                                   char *err, size_t err_len);

/* Ends the parse: the defaults that depend on other options (min-transitions
 * at most the window unless given; with the intercept and no model given,
 * the affine wind-tunnel prior). */
void fcc_opt_sid_end(fcc_opt_sid_t *s);

/* The usage text of these options: a header line "identification options..."
 * then one indented block, the same in every program. */
void fcc_opt_sid_usage(FILE *out);

#endif /* FCC_OPT_SID_H */
