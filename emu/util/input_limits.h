/* input_limits.h: the named limits on what pp5 accepts from input files, each a
 * default that the user can raise through an environment variable of the same
 * name (PP5_MAX_VOXELS=2000000000 pp5 render ...).
 *
 * Every size read from a file is checked against one of these before any
 * allocation, and the message names the limit and how to raise it, so an
 * absurd header costs nothing and a genuinely huge data set is one variable
 * away.  `pp5 help` lists them with their values. */
#ifndef PP5_INPUT_LIMITS_H
#define PP5_INPUT_LIMITS_H

#include <stdint.h>
#include "status.h"

typedef enum {
    PP5_LIMIT_VOXELS,        /* voxels in one volume (each becomes a 4-byte float) */
    PP5_LIMIT_TEXT_BYTES,    /* bytes of a text trace or gaze recording read whole */
    PP5_LIMIT_LINE_BYTES,    /* longest line in a trace or gaze recording */
    PP5_LIMIT_TRACE_SAMPLES, /* samples in one trace */
    PP5_LIMIT_HEADER_BYTES,  /* bytes of a volume header (NRRD .nhdr / attached header) */
    PP5_LIMIT_DATA_FILES,    /* detached data files one NRRD header may name */
    PP5_LIMIT_COUNT
} pp5_limit_t;

/* The limit in force: the environment variable when it holds a whole number
 * >= 1, otherwise the default (a malformed value is ignored with a warning
 * on stderr, once per limit). */
uint64_t pp5_limit(pp5_limit_t which);
/* Its environment variable ("PP5_MAX_VOXELS"), default and description. */
const char *pp5_limit_name(pp5_limit_t which);
uint64_t pp5_limit_default(pp5_limit_t which);
const char *pp5_limit_what(pp5_limit_t which);
/* PP5_E_RANGE when value > pp5_limit(which):
 * "<what>: 3000000000 voxels is over the limit of 268435456 (PP5_MAX_VOXELS;
 *  raise it in the environment, e.g. PP5_MAX_VOXELS=3000000000)". */
pp5_status_t pp5_limit_check(pp5_limit_t which, uint64_t value, const char *what);
/* PP5_E_RANGE for an input found to exceed the limit before its size is known
 * (a line still being read, a compressed file): "<what> is longer than the
 * limit of 65536 bytes (PP5_MAX_LINE_BYTES; raise it in the environment)". */
pp5_status_t pp5_limit_exceeded(pp5_limit_t which, const char *what);

#endif
