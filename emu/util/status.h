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
    PP5_E_UNSUPPORTED, /* a feature not built in (optional library absent) */
    PP5_E_MACHINE    /* the emulated machine stopped short: a time budget ran out */
} pp5_status_t;

/* Exit codes of every pp5 command, one per kind of failure, so that scripts
 * can tell a typo from a bad file from a full disk.  `pp5 help` and the
 * README list them (pp5_exit_codes_help). */
enum {
    PP5_EXIT_OK = 0,
    PP5_EXIT_FAILURE = 1,     /* anything else (out of memory, a failed check) */
    PP5_EXIT_USAGE = 2,       /* bad command line: unknown option, bad value, bad parameter */
    PP5_EXIT_INPUT = 3,       /* bad input: malformed or truncated file, value out of range,
                                 over a PP5_MAX_* limit */
    PP5_EXIT_IO = 4,          /* a file or folder could not be read or written */
    PP5_EXIT_MACHINE = 5,     /* the emulated machine or its firmware failed (firmware error,
                                 time budget exceeded) */
    PP5_EXIT_DEVICE = 6,      /* a tracker device failed, timed out or disconnected */
    PP5_EXIT_UNSUPPORTED = 7, /* not built into this pp5, or a format variant it does not read */
    PP5_EXIT_UNITS_FAILED = 8 /* a batch (sweep, replay --batch, merge) finished, but some of its
                                 units failed: their ids and errors are in the output */
};
/* The exit code for a status (PP5_OK: 0). */
int pp5_exit_code(pp5_status_t st);
/* The table of exit codes, one "  N  meaning" line each, for help texts. */
const char *pp5_exit_codes_help(void);

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
