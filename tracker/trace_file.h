/* trace_file.h: pp5's gaze trace format (traces/FORMAT.md): an in-memory trace,
 * a strict validate-then-commit reader, a whole-file writer, a flush-as-you-go
 * writer for live recording, and a gaze_source_t that plays a trace back.
 *
 * Strict about the format (magic, header keys, column names, numbers, time
 * order, NaN where a number is required); tolerant of what real recordings
 * contain (gaps in time, gaze off the screen, blinks and track loss). */
#ifndef PP5_TRACE_FILE_H
#define PP5_TRACE_FILE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "gaze.h"
#include "status.h"

#define TRACE_MAGIC "# pp5-trace v1"
#define TRACE_TEXT_MAX 256
/* A trace holds at most the PP5_MAX_TRACE_SAMPLES limit of samples, and a
 * file read whole at most PP5_MAX_TEXT_BYTES with lines of at most
 * PP5_MAX_LINE_BYTES (input_limits.h). */

typedef struct {
    char source[TRACE_TEXT_MAX];   /* where the samples came from (file, device, synth command) */
    char tracker[TRACE_TEXT_MAX];  /* tracker model, or "synthetic"; may be empty */
    double sample_rate_hz;         /* nominal, > 0 */
    gaze_geometry_t geometry;      /* screen the pixels refer to */
} trace_header_t;

typedef struct {
    trace_header_t header;
    gaze_sample_t *samples;
    size_t count, capacity;
    bool has_head, has_hand;       /* pose columns present */
    bool complete;                 /* the file ended with its "# end" line (a killed
                                      recording is valid up to its last flush, but not complete) */
} trace_t;

void trace_init(trace_t *t);
void trace_free(trace_t *t);
/* Appends a sample (time must not go backwards: PP5_E_FORMAT). */
pp5_status_t trace_append(trace_t *t, const gaze_sample_t *s);
/* Checks a header: rate > 0, screen size, geometry usable for angles. */
pp5_status_t trace_header_check(const trace_header_t *h);

/* Parses a whole trace from memory.  On error *out is untouched and
 * pp5_error_text() names the line. */
pp5_status_t trace_parse(const char *text, size_t len, const char *name, trace_t *out);
/* Reads a trace file (plain or gzip-compressed). */
pp5_status_t trace_read_file(const char *path, trace_t *out);
/* Writes a whole trace (with its "# end" line). */
pp5_status_t trace_write_file(const char *path, const trace_t *t);

/* Reads a whole file, transparently gunzipping, into a NUL-terminated malloc'd
 * buffer of at most max_bytes (0: the PP5_MAX_TEXT_BYTES limit), refusing a
 * line longer than PP5_MAX_LINE_BYTES as soon as it is read.  Shared by the
 * importers. */
pp5_status_t trace_slurp(const char *path, size_t max_bytes, char **text, size_t *len);

/* ---- flush-as-you-go writer (live recording; devices use this) ----
 * Lines are built in a private buffer and reach the file only whole, by
 * write(2) in trace_writer_flush (or when the buffer fills), so a process
 * killed at any moment leaves a file that reads as valid up to the last
 * flush (complete = false until trace_writer_close writes the "# end" line). */
typedef struct {
    int fd;
    char *buf;
    size_t len, cap;
    bool has_head, has_hand;
    int64_t last_t_ns;
    double limit_px;        /* |gaze| above this is refused, as the reader does */
    size_t samples;
    bool started;
    char path[TRACE_TEXT_MAX];
} trace_writer_t;

pp5_status_t trace_writer_open(trace_writer_t *w, const char *path, const trace_header_t *h,
                               bool has_head, bool has_hand);
pp5_status_t trace_writer_append(trace_writer_t *w, const gaze_sample_t *s);
pp5_status_t trace_writer_flush(trace_writer_t *w);    /* write(2) + fsync-free; whole lines only */
pp5_status_t trace_writer_close(trace_writer_t *w);    /* flush, "# end" line, close */
/* After an error (device lost, timeout): flush what arrived and close WITHOUT
 * the "# end" line, so the file reads as valid but not complete.  Returns the
 * flush's status; the writer is closed either way. */
pp5_status_t trace_writer_abandon(trace_writer_t *w);

/* ---- a trace as a gaze_source_t ----
 * trace_source_open takes ownership of *t (it is freed by gaze_source_close). */
pp5_status_t trace_source_open(trace_t *t, const char *name, gaze_source_t **out);

/* Drains a source into a trace (until its end, or max_samples; 0 = no limit):
 * how a live device's samples become something replay can read.  The header
 * takes the source's name, rate and geometry. */
pp5_status_t trace_collect(gaze_source_t *src, size_t max_samples, trace_t *out);

/* Text of a label/status for the file's status column. */
const char *trace_status_name(uint32_t flags);

#endif
