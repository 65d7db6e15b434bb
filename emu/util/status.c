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
    }
    return "unknown status";
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
