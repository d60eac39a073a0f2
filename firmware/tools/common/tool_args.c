/*
 * tool_args.c -- the short-option command line of the host tools (see tool_args.h).
 */
#include "tool_args.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The option arg names ("-X", X in opts), or NULL. */
static const tool_args_opt_t *find_option(const tool_args_opt_t *opts, size_t n_opts,
                                          const char *arg)
{
    if (arg[0] != '-' || arg[1] == '\0' || arg[2] != '\0') {
        return NULL;
    }
    for (size_t k = 0u; k < n_opts; ++k) {
        if (opts[k].letter == arg[1]) {
            return &opts[k];
        }
    }
    return NULL;
}

/* val into opt's text or number: 0, or -1 after the usage-error line. */
static int take_value(const tool_args_t *tool, const tool_args_opt_t *opt, const char *val)
{
    if (opt->text != NULL) {
        *opt->text = val;
        return 0;
    }
    if (tool_args_ulong(val, opt->min, opt->max, opt->number) != 0) {
        tool_args_usage_error(tool, opt->what, val);
        return -1;
    }
    return 0;
}

tool_args_result_t tool_args_parse(const tool_args_t *tool, const tool_args_opt_t *opts,
                                   size_t n_opts, int argc, char *const *argv)
{
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            (void)printf("usage: %s\n%s", tool->usage, tool->help);
            return TOOL_ARGS_HELP;
        }
        const tool_args_opt_t *const opt = find_option(opts, n_opts, a);
        if (opt == NULL) {
            tool_args_usage_error(tool, "unknown option", a);
            return TOOL_ARGS_BAD;
        }
        if (opt->flag != NULL) {
            *opt->flag = 1;
        } else if (i + 1 >= argc) {
            tool_args_usage_error(tool, "a value is missing after", a);
            return TOOL_ARGS_BAD;
        } else {
            ++i; /* the value is the next argument, whatever it looks like ("-i -h") */
            if (take_value(tool, opt, argv[i]) != 0) {
                return TOOL_ARGS_BAD;
            }
        }
    }
    return TOOL_ARGS_RUN;
}

void tool_args_usage_error(const tool_args_t *tool, const char *what, const char *arg)
{
    (void)fprintf(stderr, "%s: %s '%s' (usage: %s)\n", tool->prog, what, arg, tool->usage);
}

int tool_args_ulong(const char *s, unsigned long min, unsigned long max, unsigned long *out)
{
    char *end = NULL;
    /* strtoul would take "-1" as ULONG_MAX */
    if (s == NULL || s[0] == '\0' || s[0] == '-') {
        return -1;
    }
    errno = 0;
    const unsigned long v = strtoul(s, &end, 0);
    if (errno != 0 || *end != '\0' || v < min || v > max) {
        return -1;
    }
    *out = v;
    return 0;
}
