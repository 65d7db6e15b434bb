/* status.c: the per-thread error-text buffer and checked size arithmetic. */
#include "status.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static _Thread_local char error_text[1024];

pp5_status_t pp5_fail(pp5_status_t st, const char *fmt, ...)
{
    /* Format into a scratch buffer first: callers often wrap the previous
     * message, as in pp5_fail(st, "%s: %s", path, pp5_error_text()). */
    char scratch[sizeof error_text];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(scratch, sizeof scratch, fmt, ap);
    va_end(ap);
    memcpy(error_text, scratch, sizeof error_text);
    return st;
}

const char *pp5_error_text(void)
{
    return error_text;
}

const char *pp5_status_name(pp5_status_t st)
{
    switch (st) {
    case PP5_OK: return "ok";
    case PP5_E_IO: return "i/o error";
    case PP5_E_FORMAT: return "format error";
    case PP5_E_RANGE: return "out of range";
    case PP5_E_NOMEM: return "out of memory";
    case PP5_E_DEVICE: return "device error";
    case PP5_E_FIRMWARE: return "firmware error";
    case PP5_E_CONFIG: return "configuration error";
    case PP5_E_UNSUPPORTED: return "not supported in this build";
    case PP5_E_MACHINE: return "machine stopped";
    }
    return "unknown status";
}

int pp5_exit_code(pp5_status_t st)
{
    switch (st) {
    case PP5_OK: return PP5_EXIT_OK;
    case PP5_E_CONFIG: return PP5_EXIT_USAGE;
    case PP5_E_FORMAT: case PP5_E_RANGE: return PP5_EXIT_INPUT;
    case PP5_E_IO: return PP5_EXIT_IO;
    case PP5_E_FIRMWARE: case PP5_E_MACHINE: return PP5_EXIT_MACHINE;
    case PP5_E_DEVICE: return PP5_EXIT_DEVICE;
    case PP5_E_UNSUPPORTED: return PP5_EXIT_UNSUPPORTED;
    case PP5_E_NOMEM: return PP5_EXIT_FAILURE;
    }
    return PP5_EXIT_FAILURE;
}

const char *pp5_exit_codes_help(void)
{
    return "  0  success\n"
           "  1  other failure (out of memory, a failed comparison)\n"
           "  2  usage: unknown option, bad option value or machine parameter\n"
           "  3  bad input: malformed, truncated or out-of-range file contents, or over a\n"
           "     PP5_MAX_* limit\n"
           "  4  i/o: a file or folder could not be read or written\n"
           "  5  machine: a firmware error, or the emulated machine ran past its time budget\n"
           "  6  device: a tracker failed, timed out or was unplugged\n"
           "  7  not supported: a feature not built into this pp5 (optional library absent),\n"
           "     or a variant of a format pp5 does not read\n"
           "  8  units failed: a batch (sweep, replay --batch, merge) finished and wrote its\n"
           "     outputs, but some units failed (their ids and errors are in them)\n";
}

bool pp5_mul_size(size_t a, size_t b, size_t *out)
{
    if (a != 0 && b > SIZE_MAX / a)
        return false;
    *out = a * b;
    return true;
}

bool pp5_mul3_size(size_t a, size_t b, size_t c, size_t *out)
{
    size_t ab;
    return pp5_mul_size(a, b, &ab) && pp5_mul_size(ab, c, out);
}

void pp5_assert_fail(const char *cond, const char *msg, const char *file, int line)
{
    fprintf(stderr, "pp5: internal error at %s:%d: %s (%s)\n", file, line, msg, cond);
    abort();
}

pp5_status_t pp5_grow(void **items, size_t *capacity, size_t count, size_t item_size,
                      const char *what)
{
    if (count < *capacity)
        return PP5_OK;
    size_t cap = *capacity ? 2 * *capacity : 64, bytes;
    if (cap <= *capacity || !pp5_mul_size(cap, item_size, &bytes))
        return pp5_fail(PP5_E_NOMEM, "too many %s", what);
    void *grown = realloc(*items, bytes);
    if (!grown)
        return pp5_fail(PP5_E_NOMEM, "out of memory for %zu %s", cap, what);
    *items = grown;
    *capacity = cap;
    return PP5_OK;
}
