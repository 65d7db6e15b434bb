/* status.h: pp5_status_t, the error-text buffer, and checked size arithmetic.
 *
 * Library code in emu/, render/, firmware/ and tracker/ returns a status and
 * leaves a one-line explanation in a per-thread buffer (pp5_error_text()).
 * Only a command's entry point turns a status into a message and exit code.
 * Bad *input* is reported this way; a broken *invariant* (a bug in pp5) uses
 * PP5_ASSERT, which aborts with file:line. */
#ifndef PP5_STATUS_H
#define PP5_STATUS_H

#include <stddef.h>
#include <stdint.h>
#include <stdbool.h>

typedef enum {
    PP5_OK = 0,
    PP5_E_IO,        /* a file or device could not be read or written */
    PP5_E_FORMAT,    /* malformed or truncated input */
    PP5_E_RANGE,     /* a value or dimension outside what is allowed */
    PP5_E_NOMEM,     /* allocation failed or would be absurdly large */
    PP5_E_DEVICE,    /* a tracker device failed, timed out or disconnected */
    PP5_E_FIRMWARE,  /* a GP/PP program broke a rule of the machine */
    PP5_E_CONFIG,    /* a bad machine parameter or command-line option */
    PP5_E_UNSUPPORTED /* a feature not built in (optional library absent) */
} pp5_status_t;

/* Record an explanation for the status about to be returned; returns `st` so
 * callers can write `return pp5_fail(PP5_E_RANGE, "...", ...)`. */
pp5_status_t pp5_fail(pp5_status_t st, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
/* The text of the most recent pp5_fail on this thread ("" if none). */
const char *pp5_error_text(void);
const char *pp5_status_name(pp5_status_t st);

/* Checked size helpers: false when the product/sum overflows size_t. */
bool pp5_mul_size(size_t a, size_t b, size_t *out);
bool pp5_mul3_size(size_t a, size_t b, size_t c, size_t *out);
/* Room for one more item in a growing array: when count == *capacity, the
 * capacity doubles (first 64) and *items is reallocated.  PP5_E_NOMEM naming
 * `what` when the size overflows or realloc fails (*items is then as it was). */
pp5_status_t pp5_grow(void **items, size_t *capacity, size_t count, size_t item_size,
                      const char *what);

void pp5_assert_fail(const char *cond, const char *msg, const char *file, int line)
    __attribute__((noreturn));
#define PP5_ASSERT(cond, msg) \
    do { if (!(cond)) pp5_assert_fail(#cond, (msg), __FILE__, __LINE__); } while (0)

#endif
