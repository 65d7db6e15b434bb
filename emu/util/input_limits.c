/* input_limits.c: input limits with environment overrides (see input_limits.h). */
#include "input_limits.h"

#include <errno.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>

typedef struct {
    const char *env;
    uint64_t value;
    const char *unit;        /* what the number counts, for messages */
    const char *what;
} limit_row_t;

/* Defaults: far above any data pp5 is meant for (CThead is 7.4 M voxels, a
 * 10-minute 1000 Hz recording 600 k samples and ~30 MB of text), low enough
 * that a hostile header is refused before it costs memory. */
static const limit_row_t rows[PP5_LIMIT_COUNT] = {
    [PP5_LIMIT_VOXELS] = {"PP5_MAX_VOXELS", 1ull << 28, "voxels",
                          "voxels in one volume (1 GiB as float)"},
    [PP5_LIMIT_TEXT_BYTES] = {"PP5_MAX_TEXT_BYTES", 1ull << 30, "bytes",
                              "bytes of a trace or gaze recording (after gunzip)"},
    [PP5_LIMIT_LINE_BYTES] = {"PP5_MAX_LINE_BYTES", 1ull << 16, "bytes",
                              "bytes in one line of a trace or gaze recording"},
    [PP5_LIMIT_TRACE_SAMPLES] = {"PP5_MAX_TRACE_SAMPLES", 200000000ull, "samples",
                                 "samples in one trace (a day at 1000 Hz is 86.4 M)"},
    [PP5_LIMIT_HEADER_BYTES] = {"PP5_MAX_HEADER_BYTES", 1ull << 20, "bytes",
                                "bytes of a NRRD header"},
    [PP5_LIMIT_DATA_FILES] = {"PP5_MAX_DATA_FILES", 4096, "data files",
                              "detached data files named by one NRRD header"},
};

static atomic_bool warned[PP5_LIMIT_COUNT];

uint64_t pp5_limit(pp5_limit_t which)
{
    const limit_row_t *r = &rows[which];
    const char *text = getenv(r->env);
    if (!text || !*text)
        return r->value;
    char *end;
    errno = 0;
    unsigned long long v = strtoull(text, &end, 10);
    if (*text == '-' || end == text || *end != '\0' || errno == ERANGE || v == 0) {
        if (!atomic_exchange(&warned[which], true))
            fprintf(stderr, "pp5: ignoring %s='%s' (expected a whole number >= 1); using %llu\n",
                    r->env, text, (unsigned long long)r->value);
        return r->value;
    }
    return v;
}

const char *pp5_limit_name(pp5_limit_t which)
{
    return rows[which].env;
}

uint64_t pp5_limit_default(pp5_limit_t which)
{
    return rows[which].value;
}

const char *pp5_limit_what(pp5_limit_t which)
{
    return rows[which].what;
}

pp5_status_t pp5_limit_check(pp5_limit_t which, uint64_t value, const char *what)
{
    uint64_t limit = pp5_limit(which);
    if (value <= limit)
        return PP5_OK;
    const limit_row_t *r = &rows[which];
    return pp5_fail(PP5_E_RANGE, "%s: %llu %s is over the limit of %llu (%s; raise it in the "
                    "environment, e.g. %s=%llu)", what, (unsigned long long)value, r->unit,
                    (unsigned long long)limit, r->env, r->env, (unsigned long long)value);
}

pp5_status_t pp5_limit_exceeded(pp5_limit_t which, const char *what)
{
    const limit_row_t *r = &rows[which];
    return pp5_fail(PP5_E_RANGE, "%s is longer than the limit of %llu %s (%s; raise it in the "
                    "environment)", what, (unsigned long long)pp5_limit(which), r->unit, r->env);
}
