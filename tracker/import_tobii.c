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

#define LINE_MAX_BYTES 65536
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

pp5_status_t import_tobii(const char *text, size_t len, const char *name,
                          const import_options_t *o, trace_t *out)
{
    if (!(o->source_width_px > 0 && o->source_height_px > 0))
        return pp5_fail(PP5_E_CONFIG, "%s: Tobii exports do not record the screen size: pass "
                        "--source-px WxH (and --source-mm WxH --source-distance-mm D)", name);
    char *line = malloc(LINE_MAX_BYTES), *header = malloc(LINE_MAX_BYTES);
    char **names = malloc(MAX_FIELDS * sizeof *names), **f = malloc(MAX_FIELDS * sizeof *f);
    trace_t t;
    trace_init(&t);
    double *raw = NULL;
    size_t rawcap = 0;
    pp5_status_t st = PP5_OK;
    size_t pos = 0;
    bool too_long;
    int lineno = 1;
    if (!line || !header || !names || !f) {
        st = pp5_fail(PP5_E_NOMEM, "out of memory");
        goto done;
    }
    if (!import_next_line(text, len, &pos, header, LINE_MAX_BYTES, &too_long) || too_long) {
        st = pp5_fail(PP5_E_FORMAT, "%s: empty file or header row too long", name);
        goto done;
    }
    int ncols = import_split(header, '\t', names, MAX_FIELDS);
    if (ncols < 2) {
        st = pp5_fail(PP5_E_FORMAT, "%s: header row is not tab-separated column names", name);
        goto done;
    }
    char unit[32] = "";
    bool sdk3 = find_col(names, ncols, "LGazePos2dx", NULL, 0) >= 0;
    int c_time, c_x = -1, c_y = -1, c_lx = -1, c_ly = -1, c_lv = -1, c_rx = -1, c_ry = -1,
        c_rv = -1, c_sensor = -1, c_event = -1, c_vall = -1, c_valr = -1, c_move = -1;
    double time_scale_ns;   /* raw time unit in ns (µs = 1000, ms = 1e6); 0 = decide later */
    if (sdk3) {
        c_time = find_col(names, ncols, "Time", NULL, 0);
        c_lx = find_col(names, ncols, "LGazePos2dx", NULL, 0);
        c_ly = find_col(names, ncols, "LGazePos2dy", NULL, 0);
        c_lv = find_col(names, ncols, "LValidity", NULL, 0);
        c_rx = find_col(names, ncols, "RGazePos2dx", NULL, 0);
        c_ry = find_col(names, ncols, "RGazePos2dy", NULL, 0);
        c_rv = find_col(names, ncols, "RValidity", NULL, 0);
        if (c_time < 0 || c_ly < 0 || c_lv < 0 || c_rx < 0 || c_ry < 0 || c_rv < 0) {
            st = pp5_fail(PP5_E_FORMAT, "%s: Tobii SDK 3 text needs columns Time, "
                          "L/RGazePos2dx/y and L/RValidity", name);
            goto done;
        }
        time_scale_ns = 1000.0;
    } else {
        c_time = find_col(names, ncols, "Recording timestamp", unit, sizeof unit);
        time_scale_ns = 0;
        if (c_time < 0) {
            c_time = find_col(names, ncols, "Eyetracker timestamp", unit, sizeof unit);
            time_scale_ns = 1000.0;
        }
        c_x = find_col(names, ncols, "Gaze point X", NULL, 0);
        c_y = find_col(names, ncols, "Gaze point Y", NULL, 0);
        if (c_time < 0 || c_x < 0 || c_y < 0) {
            st = pp5_fail(PP5_E_FORMAT, "%s: missing column '%s' (a Tobii Pro Lab export needs "
                          "Recording timestamp, Gaze point X and Gaze point Y)", name,
                          c_time < 0 ? "Recording timestamp" : c_x < 0 ? "Gaze point X" :
                          "Gaze point Y");
            goto done;
        }
        if (strcmp(unit, "ms") == 0)
            time_scale_ns = 1e6;
        else if (strcmp(unit, "μs") == 0 || strcmp(unit, "us") == 0 || strcmp(unit, "µs") == 0)
            time_scale_ns = 1000.0;
        else if (unit[0])
            { st = pp5_fail(PP5_E_FORMAT, "%s: unknown timestamp unit '[%s]'", name, unit); goto done; }
        c_sensor = find_col(names, ncols, "Sensor", NULL, 0);
        c_event = find_col(names, ncols, "Event", NULL, 0);
        c_vall = find_col(names, ncols, "Validity left", NULL, 0);
        c_valr = find_col(names, ncols, "Validity right", NULL, 0);
        c_move = find_col(names, ncols, "Eye movement type", NULL, 0);
    }
    double W = o->source_width_px, H = o->source_height_px;
    while (st == PP5_OK && import_next_line(text, len, &pos, line, LINE_MAX_BYTES, &too_long)) {
        lineno++;
        if (too_long) {
            st = pp5_fail(PP5_E_FORMAT, "%s:%d: line too long", name, lineno);
            break;
        }
        if (line[0] == '\0')
            continue;
        int n = import_split(line, '\t', f, MAX_FIELDS);
        if (n != ncols) {
            st = pp5_fail(PP5_E_FORMAT, "%s:%d: %d fields, the header has %d (truncated?)", name,
                          lineno, n, ncols);
            break;
        }
        if (c_sensor >= 0 && f[c_sensor][0] && strcmp(f[c_sensor], "Eye Tracker") != 0)
            continue;                          /* gyroscope, accelerometer, ... */
        if (c_event >= 0 && f[c_event][0] && (c_sensor < 0 || !f[c_sensor][0]) &&
            !f[c_x][0])
            continue;                          /* an event row, not a sample */
        fix_decimal(f[c_time]);
        double tr;
        if (!import_parse_double(f[c_time], &tr) || !isfinite(tr)) {
            st = pp5_fail(PP5_E_FORMAT, "%s:%d: timestamp '%s' is not a number", name, lineno,
                          f[c_time]);
            break;
        }
        gaze_sample_t s;
        gaze_sample_invalid(&s, 0);
        double x = NAN, y = NAN;
        if (sdk3) {
            int k = 0;
            double sx = 0, sy = 0;
            int cols[2][3] = {{c_lx, c_ly, c_lv}, {c_rx, c_ry, c_rv}};
            for (int e = 0; e < 2; e++) {
                double ex, ey, v;
                if (!import_parse_double(f[cols[e][0]], &ex) || !import_parse_double(f[cols[e][1]], &ey) ||
                    !import_parse_double(f[cols[e][2]], &v)) {
                    st = pp5_fail(PP5_E_FORMAT, "%s:%d: gaze or validity is not a number", name,
                                  lineno);
                    break;
                }
                if (v <= 1 && isfinite(ex) && isfinite(ey)) {
                    sx += ex;
                    sy += ey;
                    k++;
                }
            }
            if (st != PP5_OK)
                break;
            if (k) {
                x = sx / k * W;
                y = sy / k * H;
            }
        } else {
            bool invalid = (c_move >= 0 && strcmp(f[c_move], "EyesNotFound") == 0) ||
                           (c_vall >= 0 && c_valr >= 0 && strcmp(f[c_vall], "Invalid") == 0 &&
                            strcmp(f[c_valr], "Invalid") == 0);
            if (f[c_x][0] && f[c_y][0] && !invalid) {
                fix_decimal(f[c_x]);
                fix_decimal(f[c_y]);
                if (!import_parse_double(f[c_x], &x) || !import_parse_double(f[c_y], &y) ||
                    !isfinite(x) || !isfinite(y)) {
                    st = pp5_fail(PP5_E_FORMAT, "%s:%d: gaze '%s' '%s' is not a number", name,
                                  lineno, f[c_x], f[c_y]);
                    break;
                }
            }
        }
        if (!isnan(x)) {
            s.x_px = x;
            s.y_px = y;
            s.flags = GAZE_FLAG_VALID;
        }
        if (t.count > 0 && tr < raw[t.count - 1]) {
            st = pp5_fail(PP5_E_FORMAT, "%s:%d: timestamp %s is before the previous sample: "
                          "out-of-order time", name, lineno, f[c_time]);
            break;
        }
        if (t.count == rawcap) {
            size_t cap = rawcap ? rawcap * 2 : 4096;
            double *p = realloc(raw, cap * sizeof *p);
            if (!p) {
                st = pp5_fail(PP5_E_NOMEM, "out of memory");
                break;
            }
            raw = p;
            rawcap = cap;
        }
        raw[t.count] = tr;
        st = trace_append(&t, &s);
    }
    if (st == PP5_OK && t.count < 2)
        st = pp5_fail(PP5_E_FORMAT, "%s: fewer than 2 gaze samples", name);
    if (st == PP5_OK) {
        double step = median_step(raw, t.count);
        if (time_scale_ns == 0)
            time_scale_ns = step > 100 ? 1000.0 : 1e6;
        if (!(step > 0)) {
            st = pp5_fail(PP5_E_FORMAT, "%s: timestamps never advance", name);
            goto done;
        }
        if ((raw[t.count - 1] - raw[0]) * time_scale_ns > 1e17) {
            st = pp5_fail(PP5_E_RANGE, "%s: timestamps span more than 3 years", name);
            goto done;
        }
        for (size_t i = 0; i < t.count; i++)
            t.samples[i].t_ns = llround((raw[i] - raw[0]) * time_scale_ns);
        t.header.sample_rate_hz = 1e9 / (step * time_scale_ns);
        gaze_geometry_t *g = &t.header.geometry;
        import_apply_geometry(o, g);
        snprintf(t.header.source, sizeof t.header.source, "%s %s",
                 sdk3 ? "Tobii SDK 3 text" : "Tobii Pro Lab TSV", name);
        snprintf(t.header.tracker, sizeof t.header.tracker, "Tobii%s",
                 sdk3 ? " (SDK 3 gaze data, mean of valid eyes)" : " (Pro Lab export)");
        if ((st = trace_header_check(&t.header)) != PP5_OK)
            st = pp5_fail(st, "%s: %s", name, pp5_error_text());
    }
done:
    free(line);
    free(header);
    free(names);
    free(f);
    free(raw);
    return import_commit(&t, st, out);
}
