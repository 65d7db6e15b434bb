/* import.h: importers from other gaze formats into pp5 traces (trace_file.h).
 *
 * Each importer reads the source's own timestamps and gaze in the source's
 * screen pixels; the recording's geometry comes from the file where it says
 * so (EyeLink DISPLAY_COORDS / GAZE_COORDS and END ... RES; gaze-trace v1
 * header keys) or from the options (Tobii and Pupil exports do not record the
 * screen).  Options override what the file says.  import_to_display then
 * carries the gaze to another display through visual angle (angles.h). */
#ifndef PP5_IMPORT_H
#define PP5_IMPORT_H

#include <stdbool.h>
#include <stddef.h>
#include "gaze.h"
#include "status.h"
#include "trace_file.h"

typedef enum {
    IMPORT_AUTO, IMPORT_EYELINK, IMPORT_TOBII, IMPORT_PUPIL, IMPORT_SHARED
} import_format_t;

typedef struct {
    /* Source display, overriding the file (0 = not given). */
    int source_width_px, source_height_px;
    double source_width_mm, source_height_mm, source_distance_mm, source_px_per_deg;
    /* Pupil Labs: samples below this confidence are track loss (docs: ~0.6 and up is useful). */
    double pupil_min_confidence;
    /* EyeLink binocular: which eye ('L', 'R', or 0 = mean of the eyes with data). */
    char eye;
    /* gaze-trace v1: the column that holds the labels (NULL = "label"; Lund's
     * second coder is "label_RA"); a named column that is absent is an error. */
    const char *label_column;
} import_options_t;

void import_defaults(import_options_t *o);
bool import_format_parse(const char *name, import_format_t *f);
/* Guesses the format from the first bytes of the (decompressed) text. */
import_format_t import_detect(const char *text, size_t len);

/* Each parses the whole text (already decompressed) named `name`. */
pp5_status_t import_eyelink(const char *text, size_t len, const char *name,
                            const import_options_t *o, trace_t *out);
pp5_status_t import_tobii(const char *text, size_t len, const char *name,
                          const import_options_t *o, trace_t *out);
pp5_status_t import_pupil(const char *text, size_t len, const char *name,
                          const import_options_t *o, trace_t *out);
pp5_status_t import_shared(const char *text, size_t len, const char *name,
                           const import_options_t *o, trace_t *out);

/* Reads a file (plain or .gz) in the given format (IMPORT_AUTO: detect). */
pp5_status_t import_file(const char *path, import_format_t format, const import_options_t *o,
                         trace_t *out);

/* Carries every valid sample to display `to` through visual angle and sets the
 * header's geometry to `to`. */
pp5_status_t import_to_display(trace_t *t, const gaze_geometry_t *to);

/* Helpers shared by the importers (import_common.c). */
/* Applies the options' source geometry over what the file said. */
void import_apply_geometry(const import_options_t *o, gaze_geometry_t *g);
/* The end of every importer (validate, then commit): on success marks `t`
 * complete and moves it into *out; on failure frees it.  Returns `st`. */
pp5_status_t import_commit(trace_t *t, pp5_status_t st, trace_t *out);
/* Next line of text at *pos (NUL-terminated copy in buf, CR stripped); false at the end. */
bool import_next_line(const char *text, size_t len, size_t *pos, char *buf, size_t size,
                      bool *too_long);
/* A malloc'd line buffer of PP5_MAX_LINE_BYTES + 1 bytes (its size in *size);
 * NULL with the error set when out of memory. */
char *import_line_buffer(size_t *size);
/* The error for a line longer than the limit: names the input, line and limit
 * (import_next_line's too_long; trace_slurp refuses such files earlier). */
pp5_status_t import_line_too_long(const char *name, int lineno);
/* Splits at `sep` (and strips quotes for CSV); returns the field count or -1 if > max. */
int import_split(char *line, char sep, char **fields, int max);
bool import_parse_double(const char *s, double *out);

#endif
