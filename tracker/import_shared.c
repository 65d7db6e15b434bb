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

#define MAX_FIELDS 64

enum { K_SOURCE = 1, K_RATE = 2, K_PX = 4, K_MM = 8, K_DIST = 16 };

/* The reader's state while it walks one file. */
typedef struct {
    const char *text, *name;
    const char *label_column;      /* the column whose labels are read (default "label") */
    size_t len, pos;
    char *line;
    size_t line_size;
    int lineno;
    unsigned seen;                 /* K_* header keys read */
    char their_source[200];
    int col_label, ncols;
    trace_t t;
} shared_reader_t;

/* Leading finite number of a value such as "250 (nominal; ...)". */
static bool lead_number(const char *v, double *out)
{
    char *end;
    double x = strtod(v, &end);
    if (end == v || !isfinite(x))
        return false;
    *out = x;
    return true;
}

/* Two finite numbers "W H ...". */
static bool two_numbers(const char *v, double *a, double *b)
{
    char *end, *end2;
    double x = strtod(v, &end);
    if (end == v)
        return false;
    double y = strtod(end, &end2);
    if (end2 == end || !isfinite(x) || !isfinite(y))
        return false;
    *a = x;
    *b = y;
    return true;
}

/* "W H" or "unknown" (0 0) for screen_mm; a number or "unknown" (0) for
 * distance_mm.  Ranges are checked by trace_header_check. */
static bool mm_or_unknown(const char *v, int count, double *a, double *b)
{
    if (strncmp(v, "unknown", 7) == 0) {
        *a = 0;
        if (b)
            *b = 0;
        return true;
    }
    double x = 0, y = 0;
    bool ok = count == 2 ? two_numbers(v, &x, &y) : lead_number(v, &x);
    if (!ok || !(x > 0) || (count == 2 && !(y > 0)))
        return false;
    *a = x;
    if (b)
        *b = y;
    return true;
}

/* One "# key: value" header line. */
static pp5_status_t parse_header_key(shared_reader_t *r, const char *key, const char *v)
{
    gaze_geometry_t *g = &r->t.header.geometry;
    double a = 0, b = 0;
    if (strcmp(key, "source") == 0) {
        snprintf(r->their_source, sizeof r->their_source, "%s", v);
        r->seen |= K_SOURCE;
    } else if (strcmp(key, "tracker") == 0) {
        snprintf(r->t.header.tracker, sizeof r->t.header.tracker, "%s", v);
    } else if (strcmp(key, "sample_rate_hz") == 0) {
        if (!lead_number(v, &a) || !(a > 0))
            return pp5_fail(PP5_E_FORMAT, "%s:%d: sample_rate_hz '%s' has no positive number",
                            r->name, r->lineno, v);
        r->t.header.sample_rate_hz = a;
        r->seen |= K_RATE;
    } else if (strcmp(key, "screen_px") == 0) {
        /* Negated ranges, so that a NaN fails them too. */
        if (!two_numbers(v, &a, &b) || !(a >= 1 && a <= 100000) || !(b >= 1 && b <= 100000))
            return pp5_fail(PP5_E_FORMAT, "%s:%d: screen_px '%s' is not 'W H' (1..100000)",
                            r->name, r->lineno, v);
        g->width_px = (int)a;
        g->height_px = (int)b;
        r->seen |= K_PX;
    } else if (strcmp(key, "screen_mm") == 0) {
        if (!mm_or_unknown(v, 2, &g->width_mm, &g->height_mm))
            return pp5_fail(PP5_E_FORMAT, "%s:%d: screen_mm '%s' is not 'W H' or unknown",
                            r->name, r->lineno, v);
        r->seen |= K_MM;
    } else if (strcmp(key, "distance_mm") == 0) {
        if (!mm_or_unknown(v, 1, &g->distance_mm, NULL))
            return pp5_fail(PP5_E_FORMAT, "%s:%d: distance_mm '%s' is not a number or "
                            "unknown", r->name, r->lineno, v);
        r->seen |= K_DIST;
    } else if (strcmp(key, "px_per_deg") == 0 || strcmp(key, "eyelink_res_px_per_deg") == 0) {
        if (lead_number(v, &a) && a > 0 && !(g->px_per_deg > 0))
            g->px_per_deg = a;          /* horizontal value (the first) */
    }
    return PP5_OK;
}

/* Next line into r->line; false at the end, or with *st set for a line over
 * the limit. */
static bool next_line(shared_reader_t *r, pp5_status_t *st)
{
    bool too_long;
    if (!import_next_line(r->text, r->len, &r->pos, r->line, r->line_size, &too_long))
        return false;
    r->lineno++;
    if (too_long) {
        *st = import_line_too_long(r->name, r->lineno);
        return false;
    }
    return true;
}

/* The "# key: value" lines; leaves the column line in r->line. */
static pp5_status_t read_header(shared_reader_t *r)
{
    pp5_status_t st = PP5_OK;
    for (;;) {
        if (!next_line(r, &st))
            return st != PP5_OK ? st : pp5_fail(PP5_E_FORMAT, "%s: truncated: no column line",
                                                r->name);
        if (r->line[0] != '#')
            break;
        char *colon = strstr(r->line, ": ");
        if (strncmp(r->line, "# ", 2) != 0 || !colon)
            continue;                       /* a free comment */
        *colon = '\0';
        if ((st = parse_header_key(r, r->line + 2, colon + 2)) != PP5_OK)
            return st;
    }
    static const struct { unsigned bit; const char *key; } req[] = {
        {K_SOURCE, "source"}, {K_RATE, "sample_rate_hz"}, {K_PX, "screen_px"},
        {K_MM, "screen_mm"}, {K_DIST, "distance_mm"}};
    for (size_t i = 0; i < sizeof req / sizeof req[0]; i++)
        if (!(r->seen & req[i].bit))
            return pp5_fail(PP5_E_FORMAT, "%s: header key '%s' is missing", r->name, req[i].key);
    return PP5_OK;
}

static pp5_status_t parse_columns(shared_reader_t *r)
{
    char *f[MAX_FIELDS];
    r->ncols = import_split(r->line, '\t', f, MAX_FIELDS);
    if (r->ncols < 3 || strcmp(f[0], "t_ms") != 0)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: column line must start t_ms x_px y_px", r->name,
                        r->lineno);
    if (strcmp(f[1], "x_px") != 0 || strcmp(f[2], "y_px") != 0)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: columns 2 and 3 must be x_px and y_px", r->name,
                        r->lineno);
    r->col_label = -1;
    const char *want = r->label_column ? r->label_column : "label";
    for (int i = 3; i < r->ncols; i++)
        if (strcmp(f[i], want) == 0)
            r->col_label = i;
    if (r->label_column && r->col_label < 0)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: no label column '%s'", r->name, r->lineno,
                        r->label_column);
    return PP5_OK;
}

/* One data line into *s. */
static pp5_status_t parse_sample(shared_reader_t *r, gaze_sample_t *s)
{
    char *f[MAX_FIELDS];
    int n = import_split(r->line, '\t', f, MAX_FIELDS);
    if (n != r->ncols)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: %d fields, the column line has %d", r->name,
                        r->lineno, n, r->ncols);
    double tm, x, y;
    if (!import_parse_double(f[0], &tm) || !(tm >= 0 && tm <= 1e12))
        return pp5_fail(PP5_E_FORMAT, "%s:%d: t_ms '%s' is not a finite time (NaN is not "
                        "allowed)", r->name, r->lineno, f[0]);
    if (!import_parse_double(f[1], &x) || !import_parse_double(f[2], &y) || isinf(x) ||
        isinf(y))
        return pp5_fail(PP5_E_FORMAT, "%s:%d: gaze '%s' '%s' is not a number or nan", r->name,
                        r->lineno, f[1], f[2]);
    gaze_sample_invalid(s, llround(tm * 1e6));
    double lab;
    if (r->col_label >= 0 && import_parse_double(f[r->col_label], &lab) && lab >= 0 &&
        lab <= GAZE_LABEL_MAX && lab == floor(lab))
        s->label = (int)lab;
    if (!isnan(x) && !isnan(y)) {
        s->x_px = x;
        s->y_px = y;
        s->flags = GAZE_FLAG_VALID;
    } else if (s->label == GAZE_LABEL_BLINK) {
        s->flags = GAZE_FLAG_BLINK;
    }
    if (r->t.count > 0 && s->t_ns < r->t.samples[r->t.count - 1].t_ns)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: time goes backwards (%s ms)", r->name, r->lineno,
                        f[0]);
    return PP5_OK;
}

static pp5_status_t read_samples(shared_reader_t *r)
{
    pp5_status_t st = PP5_OK;
    while (st == PP5_OK && next_line(r, &st)) {
        if (r->line[0] == '\0' || r->line[0] == '#')
            continue;
        gaze_sample_t s;
        st = parse_sample(r, &s);
        if (st == PP5_OK)
            st = trace_append(&r->t, &s);
    }
    if (st == PP5_OK && r->t.count == 0)
        st = pp5_fail(PP5_E_FORMAT, "%s: no samples", r->name);
    return st;
}

pp5_status_t import_shared(const char *text, size_t len, const char *name,
                           const import_options_t *o, trace_t *out)
{
    shared_reader_t r = {.text = text, .name = name, .len = len, .label_column = o->label_column};
    trace_init(&r.t);
    r.line = import_line_buffer(&r.line_size);
    if (!r.line)
        return PP5_E_NOMEM;
    pp5_status_t st = PP5_OK;
    if (!next_line(&r, &st) || strcmp(r.line, "# gaze-trace v1") != 0)
        st = pp5_fail(PP5_E_FORMAT, "%s: not a gaze-trace v1 file (line 1 must be "
                      "'# gaze-trace v1')", name);
    if (st == PP5_OK)
        st = read_header(&r);
    if (st == PP5_OK)
        st = parse_columns(&r);
    if (st == PP5_OK) {
        import_apply_geometry(o, &r.t.header.geometry);
        if ((st = trace_header_check(&r.t.header)) != PP5_OK)
            st = pp5_fail(st, "%s: %s", name, pp5_error_text());
    }
    snprintf(r.t.header.source, sizeof r.t.header.source, "gaze-trace v1 %s (original: %s)",
             name, r.their_source);
    if (st == PP5_OK)
        st = read_samples(&r);
    free(r.line);
    return import_commit(&r.t, st, out);
}
