/* import_pupil.c: Pupil Labs Core exports (gaze-facts.md §4.3):
 *   gaze_positions.csv (Pupil Player raw-data export): comma-separated with a
 *   header; gaze_timestamp (s, Pupil Time), confidence (0..1), norm_pos_x,
 *   norm_pos_y (normalised, origin bottom-left, y up) in the scene camera image;
 *   gaze_positions_on_surface_<name>.csv: gaze_timestamp, x_norm, y_norm (0..1
 *   of the surface, origin bottom-left), on_surf.
 * Columns are found by name; other columns (base_data, 3D gaze) are skipped.
 * Gaze with confidence below o->pupil_min_confidence (default 0.6, the docs'
 * "useful data" level) is track loss; so is on_surf False.  The surface (or
 * scene image) size in pixels must be given (--source-px).  Pixels:
 * x = nx * W, y = (1 - ny) * H.  Pupil Core gives two gaze streams (one per
 * eye, and binocular) that may share a timestamp; equal times are kept in
 * file order; earlier times are an error.  The rate is the median interval. */
#include "import.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_FIELDS 256

static int col(char **names, int n, const char *want)
{
    for (int i = 0; i < n; i++)
        if (strcmp(names[i], want) == 0)
            return i;
    return -1;
}

static int cmp_i64(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

/* The reader's state while it walks one file. */
typedef struct {
    const import_options_t *o;
    const char *name;
    int lineno, ncols;
    int c_t, c_conf, c_x, c_y, c_on;   /* columns (-1 when absent) */
    bool surface;                       /* gaze_positions_on_surface_<name>.csv */
    double t0, prev;
    trace_t t;
} pupil_reader_t;

static pp5_status_t parse_header_row(pupil_reader_t *r, char *header, char **names)
{
    int n = import_split(header, ',', names, MAX_FIELDS);
    r->ncols = n;
    r->c_t = col(names, n, "gaze_timestamp");
    r->c_conf = col(names, n, "confidence");
    r->c_x = col(names, n, "norm_pos_x");
    r->c_y = col(names, n, "norm_pos_y");
    r->c_on = -1;
    if (r->c_x < 0 && col(names, n, "x_norm") >= 0) {
        r->surface = true;
        r->c_x = col(names, n, "x_norm");
        r->c_y = col(names, n, "y_norm");
        r->c_on = col(names, n, "on_surf");
    }
    if (n < 3 || r->c_t < 0 || r->c_x < 0 || r->c_y < 0)
        return pp5_fail(PP5_E_FORMAT, "%s: missing column '%s' (gaze_positions.csv needs "
                        "gaze_timestamp, norm_pos_x, norm_pos_y)", r->name,
                        r->c_t < 0 ? "gaze_timestamp" : r->c_x < 0 ? "norm_pos_x" : "norm_pos_y");
    return PP5_OK;
}

/* The row's time in s (Pupil Time), never going back. */
static pp5_status_t row_time(pupil_reader_t *r, const char *field, double *ts)
{
    if (!import_parse_double(field, ts) || !isfinite(*ts))
        return pp5_fail(PP5_E_FORMAT, "%s:%d: gaze_timestamp '%s' is not a finite number (NaN "
                        "is not allowed)", r->name, r->lineno, field);
    if (!isnan(r->prev) && *ts < r->prev)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: gaze_timestamp %.6f is before the previous one "
                        "(%.6f): out-of-order time", r->name, r->lineno, *ts, r->prev);
    r->prev = *ts;
    if (isnan(r->t0))
        r->t0 = *ts;
    if ((*ts - r->t0) * 1e9 > 1e17)
        return pp5_fail(PP5_E_RANGE, "%s:%d: timestamps span more than 3 years", r->name,
                        r->lineno);
    return PP5_OK;
}

/* One data row (split into f) as a sample. */
static pp5_status_t parse_row(pupil_reader_t *r, char **f, int n)
{
    if (n != r->ncols)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: %d fields, the header has %d (truncated?)",
                        r->name, r->lineno, n, r->ncols);
    double ts, nx, ny, conf = 1.0;
    pp5_status_t st = row_time(r, f[r->c_t], &ts);
    if (st != PP5_OK)
        return st;
    if (!import_parse_double(f[r->c_x], &nx) || !import_parse_double(f[r->c_y], &ny))
        return pp5_fail(PP5_E_FORMAT, "%s:%d: gaze '%s','%s' is not a number", r->name,
                        r->lineno, f[r->c_x], f[r->c_y]);
    if (r->c_conf >= 0 && (!import_parse_double(f[r->c_conf], &conf) || !(conf >= 0 && conf <= 1)))
        return pp5_fail(PP5_E_FORMAT, "%s:%d: confidence '%s' is not in 0..1", r->name,
                        r->lineno, f[r->c_conf]);
    gaze_sample_t s;
    gaze_sample_invalid(&s, llround((ts - r->t0) * 1e9));
    const char *on_text = r->c_on >= 0 ? f[r->c_on] : "True";
    bool on = strcmp(on_text, "True") == 0 || strcmp(on_text, "true") == 0 ||
              strcmp(on_text, "1") == 0;
    if (conf >= r->o->pupil_min_confidence && on && isfinite(nx) && isfinite(ny)) {
        s.x_px = nx * r->o->source_width_px;
        s.y_px = (1.0 - ny) * r->o->source_height_px;
        s.flags = GAZE_FLAG_VALID;
    }
    return trace_append(&r->t, &s);
}

/* The rate from the median interval, then the header. */
static pp5_status_t finish(pupil_reader_t *r)
{
    trace_t *t = &r->t;
    if (t->count < 2)
        return pp5_fail(PP5_E_FORMAT, "%s: fewer than 2 gaze rows", r->name);
    int64_t *d = malloc((t->count - 1) * sizeof *d);
    if (!d)
        return pp5_fail(PP5_E_NOMEM, "out of memory");
    size_t k = 0;
    for (size_t i = 1; i < t->count; i++)
        if (t->samples[i].t_ns > t->samples[i - 1].t_ns)
            d[k++] = t->samples[i].t_ns - t->samples[i - 1].t_ns;
    if (k == 0) {
        free(d);
        return pp5_fail(PP5_E_FORMAT, "%s: timestamps never advance", r->name);
    }
    qsort(d, k, sizeof *d, cmp_i64);
    t->header.sample_rate_hz = 1e9 / (double)d[k / 2];
    free(d);
    import_apply_geometry(r->o, &t->header.geometry);
    snprintf(t->header.source, sizeof t->header.source, "Pupil Labs %s %s",
             r->surface ? "surface gaze" : "gaze_positions", r->name);
    snprintf(t->header.tracker, sizeof t->header.tracker, "Pupil Labs Core (confidence >= %g)",
             r->o->pupil_min_confidence);
    pp5_status_t st = trace_header_check(&t->header);
    return st == PP5_OK ? st : pp5_fail(st, "%s: %s", r->name, pp5_error_text());
}

pp5_status_t import_pupil(const char *text, size_t len, const char *name,
                          const import_options_t *o, trace_t *out)
{
    if (!(o->source_width_px > 0 && o->source_height_px > 0))
        return pp5_fail(PP5_E_CONFIG, "%s: Pupil Labs gaze is normalised: pass --source-px WxH "
                        "(the surface or scene image size) and its mm + distance", name);
    pupil_reader_t r = {.o = o, .name = name, .lineno = 1, .t0 = NAN, .prev = NAN};
    trace_init(&r.t);
    size_t size, pos = 0;
    char *line = import_line_buffer(&size), *header = import_line_buffer(&size);
    char **names = malloc(MAX_FIELDS * sizeof *names), **f = malloc(MAX_FIELDS * sizeof *f);
    pp5_status_t st = PP5_OK;
    bool too_long;
    if (!line || !header || !names || !f)
        st = pp5_fail(PP5_E_NOMEM, "out of memory");
    else if (!import_next_line(text, len, &pos, header, size, &too_long) || too_long)
        st = pp5_fail(PP5_E_FORMAT, "%s: empty file or header too long", name);
    else
        st = parse_header_row(&r, header, names);
    while (st == PP5_OK && import_next_line(text, len, &pos, line, size, &too_long)) {
        r.lineno++;
        if (too_long)
            st = import_line_too_long(name, r.lineno);
        else if (line[0] != '\0')
            st = parse_row(&r, f, import_split(line, ',', f, MAX_FIELDS));
    }
    if (st == PP5_OK)
        st = finish(&r);
    free(line);
    free(header);
    free(names);
    free(f);
    return import_commit(&r.t, st, out);
}
