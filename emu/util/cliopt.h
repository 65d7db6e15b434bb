/* cliopt.h: strict parsing of command-line values, with messages that name
 * the option ("--size: expected WxH, got '12'"). Each returns PP5_OK or
 * PP5_E_CONFIG with pp5_error_text() set. */
#ifndef PP5_CLIOPT_H
#define PP5_CLIOPT_H

#include "status.h"

pp5_status_t cliopt_long(const char *opt, const char *text, long min, long max, long *out);
pp5_status_t cliopt_double(const char *opt, const char *text, double min, double max,
                           double *out);
/* "WxH", each in [min, max]. */
pp5_status_t cliopt_size2(const char *opt, const char *text, long min, long max, int *w, int *h);
/* "X,Y" as two finite doubles. */
pp5_status_t cliopt_pair(const char *opt, const char *text, double *x, double *y);
/* Prints "pp5 CMD: <error text>" to stderr and returns the exit code of the
 * status (pp5_exit_code: 2 usage, 3 bad input, 4 i/o, 5 machine, 6 device,
 * 7 not built in, 1 other): the one place a status becomes an exit code. */
int cliopt_report(const char *cmd, pp5_status_t st);
/* For a command with no options of its own beyond those in `allowed` (a
 * NULL-terminated list, or NULL): argv[1..argc-1] holding --help or -h prints
 * `help` and gives 0; any other argument not allowed is reported as a usage
 * error (exit 2); otherwise -1, meaning "go on". */
int cliopt_only(int argc, char **argv, const char *cmd, const char *help,
                const char *const *allowed);

#endif
