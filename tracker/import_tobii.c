/* import_tobii.c: Tobii tab-separated exports (gaze-facts.md §4.2), two kinds:
 *
 * Tobii Pro Lab data export: one header row of column names (the user picks
 * the columns, so they are found by name; newer versions append units such as
 * "Recording timestamp [ms]" or "[μs]").  Used: Recording timestamp (or
 * Eyetracker timestamp, µs), Gaze point X / Y (display pixels), Sensor (rows of
 * other sensors skipped), Event (event-only rows skipped), Validity left/right
 * and Eye movement type (EyesNotFound) for missing data.  Without a unit
 * suffix the timestamp unit is taken as ms unless the median step between
 * samples exceeds 100 (then µs: a glasses export without suffix stepped
 * 20 000 per 50 Hz sample, §4.2).
 *
 * Tobii SDK 3 text (the TX300 files of I2MC, PROVENANCE i2mc_tx300): columns
 * Time (µs), LGazePos2dx/y, LValidity, RGazePos2dx/y, RValidity; gaze is
 * normalised to the display (origin top-left); an eye counts when its
 * validity code is 0 or 1 (as I2MC's importTobiiTX300.m); x,y = mean of the
 * valid eyes times the screen size.
 *
 * Neither records the screen: --source-px is required (and mm + distance, or
 * px per degree, for angles).  The sample rate is the median sample interval. */
#include "import.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_FIELDS 512

/* Column `base` with or without a " [unit]" suffix; returns its index or -1,
 * and the unit text (without brackets) in unit. */
static int find_col(char **names, int n, const char *base, char *unit, size_t usize)
{
    size_t bl = strlen(base);
    for (int i = 0; i < n; i++) {
        if (strncmp(names[i], base, bl) != 0)
            continue;
        const char *rest = names[i] + bl;
        if (*rest == '\0') {
            if (unit)
                unit[0] = '\0';
            return i;
        }
        if (rest[0] == ' ' && rest[1] == '[') {
            if (unit) {
                snprintf(unit, usize, "%s", rest + 2);
                char *close = strchr(unit, ']');
                if (close)
                    *close = '\0';
            }
            return i;
        }
    }
    return -1;
}

/* Decimal comma (some locales) to point, in place. */
static void fix_decimal(char *s)
{
    if (!strchr(s, '.'))
        for (char *p = s; *p; p++)
            if (*p == ',')
                *p = '.';
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median positive step of the raw times (0 if none). */
static double median_step(const double *v, size_t n)
{
    if (n < 2)
        return 0;
    double *d = malloc((n - 1) * sizeof *d);
    if (!d)
        return 0;
    size_t k = 0;
    for (size_t i = 1; i < n; i++)
        if (v[i] > v[i - 1])
            d[k++] = v[i] - v[i - 1];
    double m = 0;
    if (k) {
        qsort(d, k, sizeof *d, cmp_double);
        m = d[k / 2];
    }
    free(d);
    return m;
}

/* The columns found in the header row (-1 when absent). */
typedef struct {
    bool sdk3;
    int time, x, y, lx, ly, lv, rx, ry, rv, sensor, event, val_l, val_r, move;
    double time_scale_ns;   /* raw time unit in ns (µs = 1000, ms = 1e6); 0 = decide later */
} tobii_columns_t;

/* Tobii SDK 3 text: Time (µs), L/RGazePos2dx/y, L/RValidity. */
static pp5_status_t sdk3_columns(char **names, int n, const char *name, tobii_columns_t *c)
{
    c->time = find_col(names, n, "Time", NULL, 0);
    c->lx = find_col(names, n, "LGazePos2dx", NULL, 0);
    c->ly = find_col(names, n, "LGazePos2dy", NULL, 0);
    c->lv = find_col(names, n, "LValidity", NULL, 0);
    c->rx = find_col(names, n, "RGazePos2dx", NULL, 0);
    c->ry = find_col(names, n, "RGazePos2dy", NULL, 0);
    c->rv = find_col(names, n, "RValidity", NULL, 0);
    if (c->time < 0 || c->ly < 0 || c->lv < 0 || c->rx < 0 || c->ry < 0 || c->rv < 0)
        return pp5_fail(PP5_E_FORMAT, "%s: Tobii SDK 3 text needs columns Time, "
                        "L/RGazePos2dx/y and L/RValidity", name);
    c->time_scale_ns = 1000.0;
    return PP5_OK;
}

/* Tobii Pro Lab export: columns by name, the timestamp's unit from its suffix. */
static pp5_status_t pro_lab_columns(char **names, int n, const char *name, tobii_columns_t *c)
{
    char unit[32] = "";
    c->time = find_col(names, n, "Recording timestamp", unit, sizeof unit);
    c->time_scale_ns = 0;
    if (c->time < 0) {
        c->time = find_col(names, n, "Eyetracker timestamp", unit, sizeof unit);
        c->time_scale_ns = 1000.0;
    }
    c->x = find_col(names, n, "Gaze point X", NULL, 0);
    c->y = find_col(names, n, "Gaze point Y", NULL, 0);
    if (c->time < 0 || c->x < 0 || c->y < 0)
        return pp5_fail(PP5_E_FORMAT, "%s: missing column '%s' (a Tobii Pro Lab export needs "
                        "Recording timestamp, Gaze point X and Gaze point Y)", name,
                        c->time < 0 ? "Recording timestamp" : c->x < 0 ? "Gaze point X" :
                        "Gaze point Y");
    if (strcmp(unit, "ms") == 0)
        c->time_scale_ns = 1e6;
    else if (strcmp(unit, "μs") == 0 || strcmp(unit, "us") == 0 || strcmp(unit, "µs") == 0)
        c->time_scale_ns = 1000.0;
    else if (unit[0])
        return pp5_fail(PP5_E_FORMAT, "%s: unknown timestamp unit '[%s]'", name, unit);
    c->sensor = find_col(names, n, "Sensor", NULL, 0);
    c->event = find_col(names, n, "Event", NULL, 0);
    c->val_l = find_col(names, n, "Validity left", NULL, 0);
    c->val_r = find_col(names, n, "Validity right", NULL, 0);
    c->move = find_col(names, n, "Eye movement type", NULL, 0);
    return PP5_OK;
}

/* SDK 3 gaze: the mean of the eyes whose validity is 0 or 1, times the screen. */
static pp5_status_t sdk3_gaze(const tobii_columns_t *c, char **f, double w, double h,
                              double *x, double *y)
{
    int k = 0;
    double sx = 0, sy = 0;
    const int cols[2][3] = {{c->lx, c->ly, c->lv}, {c->rx, c->ry, c->rv}};
    for (int e = 0; e < 2; e++) {
        double ex, ey, v;
        if (!import_parse_double(f[cols[e][0]], &ex) || !import_parse_double(f[cols[e][1]], &ey) ||
            !import_parse_double(f[cols[e][2]], &v))
            return PP5_E_FORMAT;
        if (v <= 1 && isfinite(ex) && isfinite(ey)) {
            sx += ex;
            sy += ey;
            k++;
        }
    }
    if (k) {
        *x = sx / k * w;
        *y = sy / k * h;
    }
    return PP5_OK;
}

/* Pro Lab gaze in display pixels, unless the row says the eyes were not found. */
static pp5_status_t pro_lab_gaze(const tobii_columns_t *c, char **f, double *x, double *y)
{
    bool invalid = (c->move >= 0 && strcmp(f[c->move], "EyesNotFound") == 0) ||
                   (c->val_l >= 0 && c->val_r >= 0 && strcmp(f[c->val_l], "Invalid") == 0 &&
                    strcmp(f[c->val_r], "Invalid") == 0);
    if (!f[c->x][0] || !f[c->y][0] || invalid)
        return PP5_OK;
    fix_decimal(f[c->x]);
    fix_decimal(f[c->y]);
    if (!import_parse_double(f[c->x], x) || !import_parse_double(f[c->y], y) || !isfinite(*x) ||
        !isfinite(*y))
        return PP5_E_FORMAT;
    return PP5_OK;
}

/* The reader's state while it walks one file. */
typedef struct {
    const char *name;
    int lineno, ncols;
    tobii_columns_t c;
    double w, h;                  /* --source-px */
    trace_t t;
    double *raw;                  /* per sample: the file's time stamp */
    size_t rawcap;
} tobii_reader_t;

/* One data row (split into f): skipped, or appended as a sample. */
static pp5_status_t parse_row(tobii_reader_t *r, char **f, int n)
{
    const tobii_columns_t *c = &r->c;
    if (n != r->ncols)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: %d fields, the header has %d (truncated?)",
                        r->name, r->lineno, n, r->ncols);
    if (c->sensor >= 0 && f[c->sensor][0] && strcmp(f[c->sensor], "Eye Tracker") != 0)
        return PP5_OK;                         /* gyroscope, accelerometer, ... */
    if (c->event >= 0 && f[c->event][0] && (c->sensor < 0 || !f[c->sensor][0]) && !f[c->x][0])
        return PP5_OK;                         /* an event row, not a sample */
    fix_decimal(f[c->time]);
    double tr, x = NAN, y = NAN;
    if (!import_parse_double(f[c->time], &tr) || !isfinite(tr))
        return pp5_fail(PP5_E_FORMAT, "%s:%d: timestamp '%s' is not a number", r->name,
                        r->lineno, f[c->time]);
    if (c->sdk3 && sdk3_gaze(c, f, r->w, r->h, &x, &y) != PP5_OK)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: gaze or validity is not a number", r->name,
                        r->lineno);
    if (!c->sdk3 && pro_lab_gaze(c, f, &x, &y) != PP5_OK)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: gaze '%s' '%s' is not a number", r->name,
                        r->lineno, f[c->x], f[c->y]);
    gaze_sample_t s;
    gaze_sample_invalid(&s, 0);
    if (!isnan(x)) {
        s.x_px = x;
        s.y_px = y;
        s.flags = GAZE_FLAG_VALID;
    }
    if (r->t.count > 0 && tr < r->raw[r->t.count - 1])
        return pp5_fail(PP5_E_FORMAT, "%s:%d: timestamp %s is before the previous sample: "
                        "out-of-order time", r->name, r->lineno, f[c->time]);
    if (r->t.count == r->rawcap) {
        size_t cap = r->rawcap ? r->rawcap * 2 : 4096;
        double *p = realloc(r->raw, cap * sizeof *p);
        if (!p)
            return pp5_fail(PP5_E_NOMEM, "out of memory");
        r->raw = p;
        r->rawcap = cap;
    }
    r->raw[r->t.count] = tr;
    return trace_append(&r->t, &s);
}

/* Times from the raw stamps, the rate from their median step, the header. */
static pp5_status_t finish(tobii_reader_t *r, const import_options_t *o)
{
    trace_t *t = &r->t;
    if (t->count < 2)
        return pp5_fail(PP5_E_FORMAT, "%s: fewer than 2 gaze samples", r->name);
    double step = median_step(r->raw, t->count), scale = r->c.time_scale_ns;
    if (scale == 0)
        scale = step > 100 ? 1000.0 : 1e6;
    if (!(step > 0))
        return pp5_fail(PP5_E_FORMAT, "%s: timestamps never advance", r->name);
    if ((r->raw[t->count - 1] - r->raw[0]) * scale > 1e17)
        return pp5_fail(PP5_E_RANGE, "%s: timestamps span more than 3 years", r->name);
    for (size_t i = 0; i < t->count; i++)
        t->samples[i].t_ns = llround((r->raw[i] - r->raw[0]) * scale);
    t->header.sample_rate_hz = 1e9 / (step * scale);
    import_apply_geometry(o, &t->header.geometry);
    snprintf(t->header.source, sizeof t->header.source, "%s %s",
             r->c.sdk3 ? "Tobii SDK 3 text" : "Tobii Pro Lab TSV", r->name);
    snprintf(t->header.tracker, sizeof t->header.tracker, "Tobii%s",
             r->c.sdk3 ? " (SDK 3 gaze data, mean of valid eyes)" : " (Pro Lab export)");
    pp5_status_t st = trace_header_check(&t->header);
    return st == PP5_OK ? st : pp5_fail(st, "%s: %s", r->name, pp5_error_text());
}

/* The header row: which kind of export, and where its columns are. */
static pp5_status_t parse_header_row(tobii_reader_t *r, char *header, char **names)
{
    r->ncols = import_split(header, '\t', names, MAX_FIELDS);
    if (r->ncols < 2)
        return pp5_fail(PP5_E_FORMAT, "%s: header row is not tab-separated column names",
                        r->name);
    tobii_columns_t *c = &r->c;
    *c = (tobii_columns_t){.x = -1, .y = -1, .lx = -1, .ly = -1, .lv = -1, .rx = -1, .ry = -1,
                           .rv = -1, .sensor = -1, .event = -1, .val_l = -1, .val_r = -1,
                           .move = -1};
    c->sdk3 = find_col(names, r->ncols, "LGazePos2dx", NULL, 0) >= 0;
    return c->sdk3 ? sdk3_columns(names, r->ncols, r->name, c)
                   : pro_lab_columns(names, r->ncols, r->name, c);
}

pp5_status_t import_tobii(const char *text, size_t len, const char *name,
                          const import_options_t *o, trace_t *out)
{
    if (!(o->source_width_px > 0 && o->source_height_px > 0))
        return pp5_fail(PP5_E_CONFIG, "%s: Tobii exports do not record the screen size: pass "
                        "--source-px WxH (and --source-mm WxH --source-distance-mm D)", name);
    tobii_reader_t r = {.name = name, .lineno = 1, .w = o->source_width_px,
                        .h = o->source_height_px};
    trace_init(&r.t);
    size_t size, pos = 0;
    char *line = import_line_buffer(&size), *header = import_line_buffer(&size);
    char **names = malloc(MAX_FIELDS * sizeof *names), **f = malloc(MAX_FIELDS * sizeof *f);
    pp5_status_t st = PP5_OK;
    bool too_long;
    if (!line || !header || !names || !f)
        st = pp5_fail(PP5_E_NOMEM, "out of memory");
    else if (!import_next_line(text, len, &pos, header, size, &too_long) || too_long)
        st = pp5_fail(PP5_E_FORMAT, "%s: empty file or header row too long", name);
    else
        st = parse_header_row(&r, header, names);
    while (st == PP5_OK && import_next_line(text, len, &pos, line, size, &too_long)) {
        r.lineno++;
        if (too_long)
            st = import_line_too_long(name, r.lineno);
        else if (line[0] != '\0')
            st = parse_row(&r, f, import_split(line, '\t', f, MAX_FIELDS));
    }
    if (st == PP5_OK)
        st = finish(&r, o);
    free(line);
    free(header);
    free(names);
    free(f);
    free(r.raw);
    return import_commit(&r.t, st, out);
}
