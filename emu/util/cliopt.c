/* cliopt.c: strict command-line value parsing (see cliopt.h). */
#include "cliopt.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <stdbool.h>

pp5_status_t cliopt_long(const char *opt, const char *text, long min, long max, long *out)
{
    char *end;
    errno = 0;
    long v = text ? strtol(text, &end, 10) : 0;
    if (!text || end == text || *end != '\0' || errno == ERANGE)
        return pp5_fail(PP5_E_CONFIG, "%s: expected a whole number, got '%s'", opt,
                        text ? text : "");
    if (v < min || v > max)
        return pp5_fail(PP5_E_CONFIG, "%s: %ld is outside %ld..%ld", opt, v, min, max);
    *out = v;
    return PP5_OK;
}

pp5_status_t cliopt_double(const char *opt, const char *text, double min, double max,
                           double *out)
{
    char *end;
    errno = 0;
    double v = text ? strtod(text, &end) : 0;
    if (!text || end == text || *end != '\0' || errno == ERANGE || !isfinite(v))
        return pp5_fail(PP5_E_CONFIG, "%s: expected a finite number, got '%s'", opt,
                        text ? text : "");
    if (v < min || v > max)
        return pp5_fail(PP5_E_CONFIG, "%s: %g is outside %g..%g", opt, v, min, max);
    *out = v;
    return PP5_OK;
}

pp5_status_t cliopt_size2(const char *opt, const char *text, long min, long max, int *w, int *h)
{
    char *end;
    long a, b;
    errno = 0;
    a = strtol(text, &end, 10);
    if (end == text || (*end != 'x' && *end != 'X'))
        return pp5_fail(PP5_E_CONFIG, "%s: expected WxH (e.g. 512x512), got '%s'", opt, text);
    const char *second = end + 1;
    b = strtol(second, &end, 10);
    if (end == second || *end != '\0' || errno == ERANGE)
        return pp5_fail(PP5_E_CONFIG, "%s: expected WxH (e.g. 512x512), got '%s'", opt, text);
    if (a < min || a > max || b < min || b > max)
        return pp5_fail(PP5_E_CONFIG, "%s: %ldx%ld: each side must be in %ld..%ld", opt, a, b,
                        min, max);
    *w = (int)a;
    *h = (int)b;
    return PP5_OK;
}

pp5_status_t cliopt_pair(const char *opt, const char *text, double *x, double *y)
{
    char *end;
    double a = strtod(text, &end);
    if (end == text || *end != ',')
        return pp5_fail(PP5_E_CONFIG, "%s: expected X,Y, got '%s'", opt, text);
    const char *second = end + 1;
    double b = strtod(second, &end);
    if (end == second || *end != '\0' || !isfinite(a) || !isfinite(b))
        return pp5_fail(PP5_E_CONFIG, "%s: expected X,Y (two finite numbers), got '%s'", opt,
                        text);
    *x = a;
    *y = b;
    return PP5_OK;
}

int cliopt_report(const char *cmd, pp5_status_t st)
{
    if (st == PP5_OK)
        return 0;
    fprintf(stderr, "pp5 %s: %s\n", cmd, pp5_error_text()[0] ? pp5_error_text()
                                                             : pp5_status_name(st));
    return pp5_exit_code(st);
}

int cliopt_only(int argc, char **argv, const char *cmd, const char *help,
                const char *const *allowed)
{
    for (int i = 1; i < argc; i++)
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            fputs(help, stdout);
            return 0;
        }
    for (int i = 1; i < argc; i++) {
        bool ok = false;
        for (int k = 0; allowed && allowed[k] && !ok; k++)
            ok = strcmp(argv[i], allowed[k]) == 0;
        if (!ok)
            return cliopt_report(cmd, pp5_fail(PP5_E_CONFIG, "unknown option '%s' (see --help)",
                                               argv[i]));
    }
    return -1;
}
