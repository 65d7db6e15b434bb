/* import_shared.c: the converted text traces in ../shared/data/gaze/<source>/trace/
 * ("gaze-trace v1", defined in shared/data/gaze/PROVENANCE.md):
 *   line 1 "# gaze-trace v1"; "# key: value" lines (required here: source,
 *   sample_rate_hz (first token), screen_px "W H ...", screen_mm "W H" or
 *   "unknown", distance_mm or "unknown"; px_per_deg or eyelink_res_px_per_deg
 *   (first number) stand in for unknown physical geometry); one tab-separated
 *   column line starting t_ms x_px y_px; data lines, time never decreasing,
 *   "nan" for missing gaze; optional integer `label` (5 = blink), or the
 *   labels of another column (import_options_t.label_column, e.g. label_RA).
 * Other columns (block, per-eye positions, confidence, pupil) are not needed
 * for replay and are skipped. */
#include "import.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define LINE_MAX_BYTES 4096
#define MAX_FIELDS 64

/* Leading number of a value such as "250 (nominal; ...)". */
static bool lead_number(const char *v, double *out)
{
    char *end;
    double x = strtod(v, &end);
    if (end == v || !isfinite(x))
        return false;
    *out = x;
    return true;
}

static bool two_numbers(const char *v, double *a, double *b)
{
    char *end, *end2;
    *a = strtod(v, &end);
    if (end == v)
        return false;
    *b = strtod(end, &end2);
    return end2 != end && isfinite(*a) && isfinite(*b);
}

enum { K_SOURCE = 1, K_RATE = 2, K_PX = 4, K_MM = 8, K_DIST = 16 };

pp5_status_t import_shared(const char *text, size_t len, const char *name,
                           const import_options_t *o, trace_t *out)
{
    char line[LINE_MAX_BYTES];
    size_t pos = 0;
    bool too_long;
    int lineno = 0;
    if (!import_next_line(text, len, &pos, line, sizeof line, &too_long) ||
        strcmp(line, "# gaze-trace v1") != 0)
        return pp5_fail(PP5_E_FORMAT, "%s: not a gaze-trace v1 file (line 1 must be "
                        "'# gaze-trace v1')", name);
    lineno = 1;
    trace_t t;
    trace_init(&t);
    gaze_geometry_t *g = &t.header.geometry;
    unsigned seen = 0;
    int col_x = -1, col_y = -1, col_label = -1, ncols = 0;
    pp5_status_t st = PP5_OK;
    char their_source[200] = "";
    /* Header. */
    while (st == PP5_OK) {
        if (!import_next_line(text, len, &pos, line, sizeof line, &too_long)) {
            st = pp5_fail(PP5_E_FORMAT, "%s: truncated: no column line", name);
            break;
        }
        lineno++;
        if (line[0] != '#')
            break;
        char *colon = strstr(line, ": ");
        if (strncmp(line, "# ", 2) != 0 || !colon)
            continue;                       /* a free comment */
        *colon = '\0';
        const char *key = line + 2, *v = colon + 2;
        double a = 0, b = 0;
        if (strcmp(key, "source") == 0) {
            snprintf(their_source, sizeof their_source, "%s", v);
            seen |= K_SOURCE;
        } else if (strcmp(key, "tracker") == 0) {
            snprintf(t.header.tracker, sizeof t.header.tracker, "%s", v);
        } else if (strcmp(key, "sample_rate_hz") == 0) {
            if (!lead_number(v, &a) || a <= 0)
                st = pp5_fail(PP5_E_FORMAT, "%s:%d: sample_rate_hz '%s' has no positive number",
                              name, lineno, v);
            t.header.sample_rate_hz = a;
            seen |= K_RATE;
        } else if (strcmp(key, "screen_px") == 0) {
            if (!two_numbers(v, &a, &b) || a < 1 || b < 1 || a > 100000 || b > 100000)
                st = pp5_fail(PP5_E_FORMAT, "%s:%d: screen_px '%s' is not 'W H'", name, lineno, v);
            g->width_px = (int)a;
            g->height_px = (int)b;
            seen |= K_PX;
        } else if (strcmp(key, "screen_mm") == 0) {
            if (strncmp(v, "unknown", 7) == 0)
                g->width_mm = g->height_mm = 0;
            else if (!two_numbers(v, &g->width_mm, &g->height_mm) || g->width_mm <= 0 ||
                     g->height_mm <= 0)
                st = pp5_fail(PP5_E_FORMAT, "%s:%d: screen_mm '%s' is not 'W H' or unknown",
                              name, lineno, v);
            seen |= K_MM;
        } else if (strcmp(key, "distance_mm") == 0) {
            if (strncmp(v, "unknown", 7) == 0)
                g->distance_mm = 0;
            else if (!lead_number(v, &g->distance_mm) || g->distance_mm <= 0)
                st = pp5_fail(PP5_E_FORMAT, "%s:%d: distance_mm '%s' is not a number or unknown",
                              name, lineno, v);
            seen |= K_DIST;
        } else if (strcmp(key, "px_per_deg") == 0 || strcmp(key, "eyelink_res_px_per_deg") == 0) {
            if (lead_number(v, &a) && a > 0 && !(g->px_per_deg > 0))
                g->px_per_deg = a;          /* horizontal value (the first) */
        }
    }
    if (st == PP5_OK) {
        static const struct { unsigned bit; const char *key; } req[] = {
            {K_SOURCE, "source"}, {K_RATE, "sample_rate_hz"}, {K_PX, "screen_px"},
            {K_MM, "screen_mm"}, {K_DIST, "distance_mm"}};
        for (size_t i = 0; i < sizeof req / sizeof req[0] && st == PP5_OK; i++)
            if (!(seen & req[i].bit))
                st = pp5_fail(PP5_E_FORMAT, "%s: header key '%s' is missing", name, req[i].key);
    }
    /* Column line. */
    if (st == PP5_OK) {
        char *f[MAX_FIELDS];
        ncols = import_split(line, '\t', f, MAX_FIELDS);
        if (ncols < 3 || strcmp(f[0], "t_ms") != 0)
            st = pp5_fail(PP5_E_FORMAT, "%s:%d: column line must start t_ms x_px y_px", name,
                          lineno);
        const char *want = o->label_column ? o->label_column : "label";
        for (int i = 0; st == PP5_OK && i < ncols; i++) {
            if (strcmp(f[i], "x_px") == 0) col_x = i;
            if (strcmp(f[i], "y_px") == 0) col_y = i;
            if (strcmp(f[i], want) == 0) col_label = i;
        }
        if (st == PP5_OK && o->label_column && col_label < 0)
            st = pp5_fail(PP5_E_FORMAT, "%s:%d: no label column '%s'", name, lineno,
                          o->label_column);
        if (st == PP5_OK && (col_x != 1 || col_y != 2))
            st = pp5_fail(PP5_E_FORMAT, "%s:%d: columns 2 and 3 must be x_px and y_px", name,
                          lineno);
    }
    if (st == PP5_OK) {
        import_apply_geometry(o, g);
        st = trace_header_check(&t.header);
        if (st != PP5_OK)
            st = pp5_fail(st, "%s: %s", name, pp5_error_text());
    }
    snprintf(t.header.source, sizeof t.header.source, "gaze-trace v1 %s (original: %s)", name,
             their_source);
    /* Data. */
    while (st == PP5_OK && import_next_line(text, len, &pos, line, sizeof line, &too_long)) {
        lineno++;
        if (too_long) {
            st = pp5_fail(PP5_E_FORMAT, "%s:%d: line too long", name, lineno);
            break;
        }
        if (line[0] == '\0' || line[0] == '#')
            continue;
        char *f[MAX_FIELDS];
        int n = import_split(line, '\t', f, MAX_FIELDS);
        if (n != ncols) {
            st = pp5_fail(PP5_E_FORMAT, "%s:%d: %d fields, the column line has %d", name, lineno,
                          n, ncols);
            break;
        }
        double tm, x, y;
        if (!import_parse_double(f[0], &tm) || !isfinite(tm) || tm < 0 || tm > 1e12) {
            st = pp5_fail(PP5_E_FORMAT, "%s:%d: t_ms '%s' is not a finite time (NaN is not "
                          "allowed)", name, lineno, f[0]);
            break;
        }
        if (!import_parse_double(f[col_x], &x) || !import_parse_double(f[col_y], &y) ||
            isinf(x) || isinf(y)) {
            st = pp5_fail(PP5_E_FORMAT, "%s:%d: gaze '%s' '%s' is not a number or nan", name,
                          lineno, f[col_x], f[col_y]);
            break;
        }
        gaze_sample_t s;
        gaze_sample_invalid(&s, llround(tm * 1e6));
        if (col_label >= 0) {
            double lab;
            if (import_parse_double(f[col_label], &lab) && lab >= 0 && lab <= GAZE_LABEL_MAX &&
                lab == floor(lab))
                s.label = (int)lab;
        }
        if (!isnan(x) && !isnan(y)) {
            s.x_px = x;
            s.y_px = y;
            s.flags = GAZE_FLAG_VALID;
        } else if (s.label == GAZE_LABEL_BLINK) {
            s.flags = GAZE_FLAG_BLINK;
        }
        if (t.count > 0 && s.t_ns < t.samples[t.count - 1].t_ns) {
            st = pp5_fail(PP5_E_FORMAT, "%s:%d: time goes backwards (%s ms)", name, lineno, f[0]);
            break;
        }
        st = trace_append(&t, &s);
    }
    if (st == PP5_OK && t.count == 0)
        st = pp5_fail(PP5_E_FORMAT, "%s: no samples", name);
    return import_commit(&t, st, out);
}
