/*
 * sid_replay_opts.c -- command line of sid_replay (see sid_replay_opts.h).
 */
#include "sid_replay_opts.h"

#include <stdio.h>
#include <string.h>

#include "fcc_opt.h"
#include "fcc_opt_sid.h"

typedef struct {
    sid_opts_t *o;
    fcc_opt_sid_t sid; /* the identification options, into o->cfg */
} parse_t;

void sid_opts_usage(const char *prog)
{
    printf("usage: %s [options] [FILE|-]\n"
           "Replays a flight CSV (t,alpha,q,de[,fault]) through MLS-KF, MLS-ZKF and MLS-AZKF\n"
           "and writes one row per step per filter:\n"
           "  t,filter,alpha_hat,q_hat,alpha_lo,alpha_hi,q_lo,q_hi,gain_norm,order,fault,\n"
           "  a11,a12,a21,a22,b1,b2,rho   (and c1,c2 with --mls-intercept)\n"
           "replay options:\n"
           "  --filter kf|zkf|azkf|all      filters to run (all)\n"
           "  --mls-only                    input states are exact: print the MLS fit per step\n"
           "  --fixed-model a11,...,b2[,c1,c2]  MLS off: this model every step\n"
           "  --all-rows                    every row mode (paper, prior, posterior) in one\n"
           "                                pass; the filter column reads MODE/FILTER\n"
           "  --estimates                   only t,filter,alpha_hat,q_hat,alpha_lo,alpha_hi,\n"
           "                                q_lo,q_hi (what the rig reads; less to print)\n"
           "  --binary                      with --estimates: each row as 9 native-endian\n"
           "                                IEEE 754 binary64 values, no header: t, the\n"
           "                                filter (0 kf, 1 zkf, 2 azkf; --all-rows: + 3 x the\n"
           "                                mode, 0 paper, 1 prior, 2 posterior), the six\n"
           "                                estimates (exact, nothing to format or parse),\n"
           "                                the fault flag (0 or 1)\n"
           "  --help                        this text\n",
           prog);
    fcc_opt_sid_usage(stdout);
    printf("Exit: 0 done; 1 bad or unreadable input; 2 bad command line or configuration.\n");
}

/* The replay's own options, then the shared identification options. */
static fcc_opt_result_t apply(void *ctx, const char *name, const char *val, char *err,
                              size_t len)
{
    static const char *const filters[] = {"kf", "zkf", "azkf", "all"};
    parse_t *p = ctx;
    sid_opts_t *o = p->o;
    if (strcmp(name, "--filter") == 0) {
        int f = 0;
        const fcc_opt_result_t r = fcc_opt_choice(name, val, filters, 4, &f, err, len);
        for (int i = 0; r == FCC_OPT_DONE && i < 3; ++i) {
            o->run[i] = (f == 3) || (f == i);
        }
        return r;
    }
    if (strcmp(name, "--fixed-model") == 0) {
        const fcc_opt_result_t r = fcc_opt_sid_model(&p->sid, name, val, err, len);
        if (r == FCC_OPT_DONE) {
            o->fixed_model = true;
            o->cfg.mls_enabled = false;
        }
        return r;
    }
    if (strcmp(name, "--all-rows") == 0) {
        return fcc_opt_flag(name, val, &o->all_rows, true, err, len);
    }
    if (strcmp(name, "--estimates") == 0) {
        return fcc_opt_flag(name, val, &o->estimates_only, true, err, len);
    }
    if (strcmp(name, "--binary") == 0) {
        return fcc_opt_flag(name, val, &o->binary, true, err, len);
    }
    if (strcmp(name, "--mls-only") == 0) {
        return fcc_opt_flag(name, val, &o->mls_only, true, err, len);
    }
    return fcc_opt_sid_apply(&p->sid, name, val, err, len);
}

int sid_opts_parse(int argc, char **argv, sid_opts_t *o, char *err, size_t len)
{
    memset(o, 0, sizeof *o);
    fcc_sid_config_default(&o->cfg, FCC_SID_KF);
    o->run[0] = o->run[1] = o->run[2] = true;
    parse_t p = {o, {NULL, false, false}};
    fcc_opt_sid_begin(&p.sid, &o->cfg);
    for (int i = 1; i < argc; ++i) {
        const char *arg = argv[i];
        if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
            sid_opts_usage(argv[0]);
            return 1;
        }
        if (strncmp(arg, "--", 2) != 0 || strcmp(arg, "-") == 0) {
            if (o->input != NULL) {
                return fcc_opt_fail(err, len, "more than one input file ('%s', '%s')", o->input,
                                    arg);
            }
            o->input = arg;
            continue;
        }
        if (fcc_opt_take(argc, argv, &i, apply, &p, "see --help", err, len) != FCC_OPT_DONE) {
            return -1;
        }
    }
    fcc_opt_sid_end(&p.sid);
    if (o->all_rows && o->mls_only) {
        return fcc_opt_fail(err, len, "--all-rows replays the filters: not with --mls-only");
    }
    if (o->estimates_only && o->mls_only) {
        return fcc_opt_fail(err, len, "--estimates prints the filters' estimates: not with --mls-only");
    }
    if (o->binary && !o->estimates_only) {
        return fcc_opt_fail(err, len, "--binary writes the estimates' rows: give --estimates too");
    }
    return 0;
}
