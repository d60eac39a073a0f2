/*
 * tool_args.h -- the command line of the small host tools with short options
 * (can_echo, slcan_bridge), one copy so that they take the same numbers and
 * refuse a bad argument with the same line:
 *
 *   PROG: WHAT 'ARG' (usage: USAGE)      on stderr, and the tool exits 2
 *
 * An argument is "-h"/"--help", a flag ("-q"), or an option and its value as
 * the next argument ("-r 0x7F0"); a tool describes its options in a table.
 * Numbers are unsigned, decimal, 0x hex or 0 octal (strtoul's base 0), within
 * min..max.  Host only (stdio).  The programs with "--name value" options use
 * fcc_opt (firmware/cli) instead.
 */
#ifndef TOOL_ARGS_H
#define TOOL_ARGS_H

#include <stddef.h>

/* A tool's words: its name and usage line (the error line's first and last words) and its
 * help, printed on stdout as "usage: USAGE", a newline, then HELP. */
typedef struct {
    const char *prog;  /* e.g. "can_echo" */
    const char *usage; /* e.g. "can_echo [-i IFACE] [-q]" */
    const char *help;  /* what it does and each option, lines ending in '\n' */
} tool_args_t;

/* One option: its letter and where it goes, through exactly one of
 *   flag    "-X": *flag = 1
 *   text    "-X TEXT": *text = TEXT (argv's own string)
 *   number  "-X N": N in min..max into *number; a bad N is the usage error "WHAT 'N'". */
typedef struct {
    char letter;
    int *flag;
    const char **text;
    unsigned long *number;
    unsigned long min;
    unsigned long max;
    const char *what;
} tool_args_opt_t;

/* What the command line asks for (the tools' exit status: HELP 0, BAD 2). */
typedef enum {
    TOOL_ARGS_RUN = 0,  /* every argument applied */
    TOOL_ARGS_HELP = 1, /* -h or --help: the help is printed */
    TOOL_ARGS_BAD = 2   /* a usage error: its one line is printed */
} tool_args_result_t;

/* Applies argv[1..argc-1] in order through opts[0..n_opts-1], up to the first help (printed)
 * or usage error (its line printed): an argument not in opts is "unknown option 'ARG'", an
 * option without its value "a value is missing after 'ARG'". */
tool_args_result_t tool_args_parse(const tool_args_t *tool, const tool_args_opt_t *opts,
                                   size_t n_opts, int argc, char *const *argv);

/* Prints the usage-error line "PROG: WHAT 'ARG' (usage: USAGE)". */
void tool_args_usage_error(const tool_args_t *tool, const char *what, const char *arg);

/* s as an unsigned number in min..max into *out: 0, or -1 (NULL, empty, a minus sign, not a
 * whole number, out of range; *out then unchanged).  Leading blanks and '+' are strtoul's. */
int tool_args_ulong(const char *s, unsigned long min, unsigned long max, unsigned long *out);

#endif /* TOOL_ARGS_H */
