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

pp5_status_t import_pupil(const char *text, size_t len, const char *name,
                          const import_options_t *o, trace_t *out)
{
    if (!(o->source_width_px > 0 && o->source_height_px > 0))
        return pp5_fail(PP5_E_CONFIG, "%s: Pupil Labs gaze is normalised: pass --source-px WxH "
                        "(the surface or scene image size) and its mm + distance", name);
    size_t line_size;
    char *line = import_line_buffer(&line_size), *header = import_line_buffer(&line_size);
    char **names = malloc(MAX_FIELDS * sizeof *names), **f = malloc(MAX_FIELDS * sizeof *f);
    trace_t t;
    trace_init(&t);
    pp5_status_t st = PP5_OK;
    size_t pos = 0;
    bool too_long;
    int lineno = 1;
    double t0 = NAN, prev = NAN;
    if (!line || !header || !names || !f) {
        st = pp5_fail(PP5_E_NOMEM, "out of memory");
        goto done;
    }
    if (!import_next_line(text, len, &pos, header, line_size, &too_long) || too_long) {
        st = pp5_fail(PP5_E_FORMAT, "%s: empty file or header too long", name);
        goto done;
    }
    int ncols = import_split(header, ',', names, MAX_FIELDS);
    int c_t = col(names, ncols, "gaze_timestamp");
    int c_conf = col(names, ncols, "confidence");
    int c_x = col(names, ncols, "norm_pos_x"), c_y = col(names, ncols, "norm_pos_y");
    int c_on = -1;
    bool surface = false;
    if (c_x < 0 && col(names, ncols, "x_norm") >= 0) {
        surface = true;
        c_x = col(names, ncols, "x_norm");
        c_y = col(names, ncols, "y_norm");
        c_on = col(names, ncols, "on_surf");
    }
    if (ncols < 3 || c_t < 0 || c_x < 0 || c_y < 0) {
        st = pp5_fail(PP5_E_FORMAT, "%s: missing column '%s' (gaze_positions.csv needs "
                      "gaze_timestamp, norm_pos_x, norm_pos_y)", name,
                      c_t < 0 ? "gaze_timestamp" : c_x < 0 ? "norm_pos_x" : "norm_pos_y");
        goto done;
    }
    double W = o->source_width_px, H = o->source_height_px;
    while (st == PP5_OK && import_next_line(text, len, &pos, line, line_size, &too_long)) {
        lineno++;
        if (too_long) {
            st = import_line_too_long(name, lineno);
            break;
        }
        if (line[0] == '\0')
            continue;
        int n = import_split(line, ',', f, MAX_FIELDS);
        if (n != ncols) {
            st = pp5_fail(PP5_E_FORMAT, "%s:%d: %d fields, the header has %d (truncated?)", name,
                          lineno, n, ncols);
            break;
        }
        double ts, nx, ny, conf = 1.0;
        if (!import_parse_double(f[c_t], &ts) || !isfinite(ts)) {
            st = pp5_fail(PP5_E_FORMAT, "%s:%d: gaze_timestamp '%s' is not a finite number (NaN "
                          "is not allowed)", name, lineno, f[c_t]);
            break;
        }
        if (!isnan(prev) && ts < prev) {
            st = pp5_fail(PP5_E_FORMAT, "%s:%d: gaze_timestamp %.6f is before the previous "
                          "one (%.6f): out-of-order time", name, lineno, ts, prev);
            break;
        }
        prev = ts;
        if (isnan(t0))
            t0 = ts;
        if ((ts - t0) * 1e9 > 1e17) {
            st = pp5_fail(PP5_E_RANGE, "%s:%d: timestamps span more than 3 years", name, lineno);
            break;
        }
        bool ok = import_parse_double(f[c_x], &nx) && import_parse_double(f[c_y], &ny);
        if (!ok) {
            st = pp5_fail(PP5_E_FORMAT, "%s:%d: gaze '%s','%s' is not a number", name, lineno,
                          f[c_x], f[c_y]);
            break;
        }
        if (c_conf >= 0 && (!import_parse_double(f[c_conf], &conf) || !(conf >= 0 && conf <= 1))) {
            st = pp5_fail(PP5_E_FORMAT, "%s:%d: confidence '%s' is not in 0..1", name, lineno,
                          f[c_conf]);
            break;
        }
        gaze_sample_t s;
        gaze_sample_invalid(&s, llround((ts - t0) * 1e9));
        bool on = c_on < 0 || strcmp(f[c_on], "True") == 0 || strcmp(f[c_on], "true") == 0 ||
                  strcmp(f[c_on], "1") == 0;
        if (conf >= o->pupil_min_confidence && on && isfinite(nx) && isfinite(ny)) {
            s.x_px = nx * W;
            s.y_px = (1.0 - ny) * H;
            s.flags = GAZE_FLAG_VALID;
        }
        st = trace_append(&t, &s);
    }
    if (st == PP5_OK && t.count < 2)
        st = pp5_fail(PP5_E_FORMAT, "%s: fewer than 2 gaze rows", name);
    if (st == PP5_OK) {
        int64_t *d = malloc((t.count - 1) * sizeof *d);
        size_t k = 0;
        if (!d) {
            st = pp5_fail(PP5_E_NOMEM, "out of memory");
            goto done;
        }
        for (size_t i = 1; i < t.count; i++)
            if (t.samples[i].t_ns > t.samples[i - 1].t_ns)
                d[k++] = t.samples[i].t_ns - t.samples[i - 1].t_ns;
        if (k == 0) {
            free(d);
            st = pp5_fail(PP5_E_FORMAT, "%s: timestamps never advance", name);
            goto done;
        }
        qsort(d, k, sizeof *d, cmp_i64);
        t.header.sample_rate_hz = 1e9 / (double)d[k / 2];
        free(d);
        import_apply_geometry(o, &t.header.geometry);
        snprintf(t.header.source, sizeof t.header.source, "Pupil Labs %s %s",
                 surface ? "surface gaze" : "gaze_positions", name);
        snprintf(t.header.tracker, sizeof t.header.tracker, "Pupil Labs Core (confidence >= %g)",
                 o->pupil_min_confidence);
        if ((st = trace_header_check(&t.header)) != PP5_OK)
            st = pp5_fail(st, "%s: %s", name, pp5_error_text());
    }
done:
    free(line);
    free(header);
    free(names);
    free(f);
    return import_commit(&t, st, out);
}
