/* import_eyelink.c: SR Research EyeLink ASC files (edf2asc text; .gz read
 * through zlib by import_file), following gaze-facts.md §4.1:
 *   - sample lines start with a digit: "<time> <x> <y> <pupil> ..." (monocular)
 *     or "<time> <xl> <yl> <pl> <xr> <yr> <pr> ..." (binocular); velocity,
 *     resolution, CR flags and Remote columns may follow and are ignored;
 *     "." is missing data (as is NaN, which `edf2asc -miss NaN` writes);
 *   - which eyes: the "START <t> [LEFT] [RIGHT] SAMPLES ..." and "SAMPLES GAZE
 *     <eyes> ... RATE <hz>" lines of each recording block;
 *   - time: integer ms of the tracker clock; at 2000 Hz two consecutive samples
 *     share a stamp and the second is 0.5 ms later (seen in mono2000);
 *   - screen: "MSG <t> DISPLAY_COORDS x0 y0 x1 y1" or "GAZE_COORDS ..."; the
 *     last pixel is inclusive (1023 767 = 1024 x 768), but some programs write
 *     the size (640 480): we take odd values as inclusive and even ones as
 *     sizes, which fits every file in shared/data/gaze;
 *   - "END <t> SAMPLES EVENTS RES <xres> <yres>": pixels per degree at the
 *     screen centre, used when the physical geometry is not given;
 *   - EFIX / ESACC / EBLINK events label the samples between their start and
 *     end time (blink over saccade over fixation, for any eye); samples with no
 *     gaze inside an EBLINK are blinks, other missing samples track loss.
 * Only GAZE samples are accepted (HREF and PUPIL samples are not screen pixels). */
#include "import.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_FIELDS 48

typedef struct {
    double t0_ms, t1_ms;
    int label;
} interval_t;

typedef struct {
    interval_t *v;
    size_t n, cap;
} intervals_t;

static pp5_status_t intervals_add(intervals_t *iv, double a, double b, int label)
{
    if (iv->n == iv->cap) {
        size_t cap = iv->cap ? iv->cap * 2 : 256;
        interval_t *p = realloc(iv->v, cap * sizeof *p);
        if (!p)
            return pp5_fail(PP5_E_NOMEM, "out of memory for events");
        iv->v = p;
        iv->cap = cap;
    }
    iv->v[iv->n++] = (interval_t){a, b, label};
    return PP5_OK;
}

static int label_rank(int label)
{
    return label == GAZE_LABEL_BLINK ? 3 : label == GAZE_LABEL_SACCADE ? 2 :
           label == GAZE_LABEL_FIXATION ? 1 : 0;
}

/* Splits at runs of spaces and tabs. */
static int split_ws(char *line, char **f, int max)
{
    int n = 0;
    char *p = line;
    for (;;) {
        while (*p == ' ' || *p == '\t')
            p++;
        if (!*p)
            return n;
        if (n == max)
            return n;       /* extra columns (Remote data) are ignored */
        f[n++] = p;
        while (*p && *p != ' ' && *p != '\t')
            p++;
        if (*p)
            *p++ = '\0';
    }
}

static bool is_missing(const char *s)
{
    return strcmp(s, ".") == 0;
}

/* The reader's state while it walks one file. */
typedef struct {
    const import_options_t *o;
    const char *name;
    int lineno;
    trace_t t;
    intervals_t ev;
    double *tracker_ms;              /* per sample: tracker time (for labels) */
    size_t tcap;
    bool left, right, eyes_known, in_block, gaze_samples;
    double rate, res_sum, t0, prev_ms;
    int res_n, disp_w, disp_h, same_stamp;
} eyelink_reader_t;

/* The gaze of one sample line: the mean of the eyes with data (or the eye
 * the options ask for); k = 0 when no eye has data. */
static pp5_status_t sample_gaze(eyelink_reader_t *r, char **f, double *x, double *y, int *k)
{
    bool bino = r->left && r->right;
    double eyes[2][2];
    bool have[2] = {false, false};
    static const int idx[2][2] = {{1, 2}, {4, 5}};
    int use_eyes = bino ? 2 : 1;
    for (int e = 0; e < use_eyes; e++) {
        const char *xs = f[idx[e][0]], *ys = f[idx[e][1]];
        if (is_missing(xs) || is_missing(ys))
            continue;
        if (!import_parse_double(xs, &eyes[e][0]) || !import_parse_double(ys, &eyes[e][1]))
            return pp5_fail(PP5_E_FORMAT, "%s:%d: gaze is neither a number nor '.'", r->name,
                            r->lineno);
        /* `edf2asc -miss NaN` writes NaN for missing data. */
        have[e] = isfinite(eyes[e][0]) && isfinite(eyes[e][1]);
    }
    /* Pick the eye(s). Binocular: column group 0 is left, 1 right. */
    *x = *y = 0;
    *k = 0;
    for (int e = 0; e < use_eyes; e++) {
        char which = bino ? (e == 0 ? 'L' : 'R') : (r->left ? 'L' : 'R');
        if (!have[e] || (r->o->eye && bino && r->o->eye != which))
            continue;
        *x += eyes[e][0];
        *y += eyes[e][1];
        (*k)++;
    }
    return PP5_OK;
}

/* Sample time in ms from the tracker's, with the 2000 Hz rule: the second of
 * two samples sharing a stamp is half a millisecond later. */
static pp5_status_t sample_time(eyelink_reader_t *r, double ms, double *sample_ms)
{
    if (!isnan(r->prev_ms) && ms < r->prev_ms)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: time %.1f ms is before the previous sample "
                        "(%.1f ms): out-of-order time", r->name, r->lineno, ms, r->prev_ms);
    *sample_ms = ms;
    if (!isnan(r->prev_ms) && ms == r->prev_ms && r->rate > 1000 && !r->same_stamp) {
        *sample_ms = ms + 0.5;
        r->same_stamp = 1;
    } else {
        r->same_stamp = 0;
    }
    r->prev_ms = ms;
    if (isnan(r->t0))
        r->t0 = *sample_ms;
    if ((*sample_ms - r->t0) * 1e6 > 1e17)
        return pp5_fail(PP5_E_RANGE, "%s:%d: timestamps span more than 3 years", r->name,
                        r->lineno);
    return PP5_OK;
}

static pp5_status_t parse_sample_line(eyelink_reader_t *r, char *line)
{
    if (!r->in_block || !r->eyes_known)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: sample line outside a START ... END block (or "
                        "before its eyes are known)", r->name, r->lineno);
    if (!r->gaze_samples)
        return pp5_fail(PP5_E_UNSUPPORTED, "%s:%d: samples are not GAZE (HREF/PUPIL samples "
                        "are not screen pixels; re-export with edf2asc)", r->name, r->lineno);
    char *f[MAX_FIELDS];
    int n = split_ws(line, f, MAX_FIELDS);
    bool bino = r->left && r->right;
    if (n < (bino ? 7 : 4))
        return pp5_fail(PP5_E_FORMAT, "%s:%d: %s sample line has %d fields, needs %d "
                        "(truncated?)", r->name, r->lineno, bino ? "binocular" : "monocular", n,
                        bino ? 7 : 4);
    double ms, x = 0, y = 0, sample_ms = 0;
    int k = 0;
    if (!import_parse_double(f[0], &ms) || !isfinite(ms))
        return pp5_fail(PP5_E_FORMAT, "%s:%d: bad time '%s'", r->name, r->lineno, f[0]);
    pp5_status_t st = sample_gaze(r, f, &x, &y, &k);
    if (st == PP5_OK)
        st = sample_time(r, ms, &sample_ms);
    if (st != PP5_OK)
        return st;
    gaze_sample_t s;
    gaze_sample_invalid(&s, llround((sample_ms - r->t0) * 1e6));
    if (k > 0) {
        s.x_px = x / k;
        s.y_px = y / k;
        s.flags = GAZE_FLAG_VALID;
    }
    if (r->t.count == r->tcap) {
        size_t cap = r->tcap ? r->tcap * 2 : 4096;
        double *p = realloc(r->tracker_ms, cap * sizeof *p);
        if (!p)
            return pp5_fail(PP5_E_NOMEM, "out of memory");
        r->tracker_ms = p;
        r->tcap = cap;
    }
    r->tracker_ms[r->t.count] = ms;
    return trace_append(&r->t, &s);
}

/* "SAMPLES GAZE LEFT RIGHT RATE 500.00 ...": sample kind, eyes and rate. */
static pp5_status_t parse_samples_keyword(eyelink_reader_t *r, char **f, int n)
{
    bool l = false, rt = false;
    r->gaze_samples = n > 1 && strcmp(f[1], "GAZE") == 0;
    for (int i = 1; i < n; i++) {
        l |= strcmp(f[i], "LEFT") == 0;
        rt |= strcmp(f[i], "RIGHT") == 0;
        if (strcmp(f[i], "RATE") != 0 || i + 1 >= n)
            continue;
        double v;
        if (!import_parse_double(f[i + 1], &v) || !(v > 0 && v <= 100000))
            return pp5_fail(PP5_E_FORMAT, "%s:%d: bad RATE '%s'", r->name, r->lineno, f[i + 1]);
        if (r->rate > 0 && v != r->rate && r->t.count > 0)
            return pp5_fail(PP5_E_UNSUPPORTED, "%s:%d: the sample rate changes from %g to %g "
                            "Hz between blocks", r->name, r->lineno, r->rate, v);
        r->rate = v;
    }
    if (l || rt) {
        r->left = l;
        r->right = rt;
        r->eyes_known = true;
    }
    return PP5_OK;
}

/* "MSG <t> DISPLAY_COORDS x0 y0 x1 y1" (or GAZE_COORDS). */
static pp5_status_t parse_display_coords(eyelink_reader_t *r, char **f)
{
    double c[4];
    bool ok = true;
    for (int i = 0; i < 4; i++)
        ok = ok && import_parse_double(f[3 + i], &c[i]) && isfinite(c[i]);
    if (!ok || c[2] <= c[0] || c[3] <= c[1] || c[2] - c[0] > 100000 || c[3] - c[1] > 100000)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: bad %s", r->name, r->lineno, f[2]);
    /* Odd last coordinate: inclusive (1023 -> 1024); even: a size. */
    double w = c[2] - c[0], h = c[3] - c[1];
    r->disp_w = (int)w + ((long)c[2] % 2 != 0 ? 1 : 0);
    r->disp_h = (int)h + ((long)c[3] % 2 != 0 ? 1 : 0);
    return PP5_OK;
}

/* "EFIX|ESACC|EBLINK <eye> <start> <end> ...": a labelled interval. */
static pp5_status_t parse_event(eyelink_reader_t *r, char **f)
{
    double a, b;
    if (!import_parse_double(f[2], &a) || !import_parse_double(f[3], &b))
        return pp5_fail(PP5_E_FORMAT, "%s:%d: bad %s times", r->name, r->lineno, f[0]);
    if (b < a)
        return PP5_OK;   /* EyeLink I writes empty blinks ("EBLINK R 419788 419784 0"):
                            they cover no sample */
    int label = f[0][1] == 'F' ? GAZE_LABEL_FIXATION :
                f[0][1] == 'S' ? GAZE_LABEL_SACCADE : GAZE_LABEL_BLINK;
    return intervals_add(&r->ev, a, b, label);
}

static pp5_status_t parse_keyword_line(eyelink_reader_t *r, char *line)
{
    if (line[0] == '*' || line[0] == '#' || line[0] == '/' || line[0] == ';')
        return PP5_OK;
    char *f[MAX_FIELDS];
    int n = split_ws(line, f, MAX_FIELDS);
    if (n == 0)
        return PP5_OK;
    if (strcmp(f[0], "START") == 0) {
        r->in_block = true;
        r->left = r->right = false;
        for (int i = 2; i < n; i++) {
            r->left |= strcmp(f[i], "LEFT") == 0;
            r->right |= strcmp(f[i], "RIGHT") == 0;
        }
        r->eyes_known = r->left || r->right;
    } else if (strcmp(f[0], "SAMPLES") == 0) {
        return parse_samples_keyword(r, f, n);
    } else if (strcmp(f[0], "END") == 0) {
        r->in_block = false;
        for (int i = 1; i + 2 < n; i++) {
            double v;
            if (strcmp(f[i], "RES") == 0 && import_parse_double(f[i + 1], &v) && v > 0 &&
                isfinite(v)) {
                r->res_sum += v;
                r->res_n++;
            }
        }
    } else if (strcmp(f[0], "MSG") == 0 && n >= 7 &&
               (strcmp(f[2], "DISPLAY_COORDS") == 0 || strcmp(f[2], "GAZE_COORDS") == 0)) {
        return parse_display_coords(r, f);
    } else if ((strcmp(f[0], "EFIX") == 0 || strcmp(f[0], "ESACC") == 0 ||
                strcmp(f[0], "EBLINK") == 0) && n >= 4) {
        return parse_event(r, f);
    }
    return PP5_OK;
}

/* Labels: each event labels the samples inside it, higher ranks winning
 * (blink over saccade over fixation); missing samples inside a blink are blinks. */
static void apply_labels(eyelink_reader_t *r)
{
    for (size_t e = 0; e < r->ev.n; e++) {
        const interval_t *iv = &r->ev.v[e];
        /* binary search for the first sample at or after the start */
        size_t lo = 0, hi = r->t.count;
        while (lo < hi) {
            size_t mid = (lo + hi) / 2;
            if (r->tracker_ms[mid] < iv->t0_ms)
                lo = mid + 1;
            else
                hi = mid;
        }
        for (size_t i = lo; i < r->t.count && r->tracker_ms[i] <= iv->t1_ms; i++) {
            gaze_sample_t *s = &r->t.samples[i];
            if (label_rank(iv->label) > label_rank(s->label))
                s->label = iv->label;
        }
    }
    for (size_t i = 0; i < r->t.count; i++)
        if (!(r->t.samples[i].flags & GAZE_FLAG_VALID) && r->t.samples[i].label == GAZE_LABEL_BLINK)
            r->t.samples[i].flags = GAZE_FLAG_BLINK;
}

/* The header from what the file said, with the options over it. */
static pp5_status_t finish_header(eyelink_reader_t *r)
{
    if (r->t.count == 0)
        return pp5_fail(PP5_E_FORMAT, "%s: no sample lines (is this an EyeLink ASC file with "
                        "samples?)", r->name);
    if (!(r->rate > 0))
        return pp5_fail(PP5_E_FORMAT, "%s: no 'SAMPLES ... RATE <hz>' line: sample rate "
                        "unknown", r->name);
    apply_labels(r);
    gaze_geometry_t *g = &r->t.header.geometry;
    g->width_px = r->disp_w;
    g->height_px = r->disp_h;
    g->px_per_deg = r->res_n ? r->res_sum / r->res_n : 0;
    import_apply_geometry(r->o, g);
    r->t.header.sample_rate_hz = r->rate;
    snprintf(r->t.header.source, sizeof r->t.header.source, "EyeLink ASC %s", r->name);
    const char *eye = r->left && r->right
                          ? (r->o->eye ? (r->o->eye == 'L' ? "left eye" : "right eye")
                                       : "binocular, mean of the eyes")
                          : r->left ? "left eye" : "right eye";
    snprintf(r->t.header.tracker, sizeof r->t.header.tracker, "SR Research EyeLink (%s)", eye);
    if (g->width_px < 1)
        return pp5_fail(PP5_E_FORMAT, "%s: no DISPLAY_COORDS or GAZE_COORDS message: pass "
                        "--source-px WxH", r->name);
    pp5_status_t st = trace_header_check(&r->t.header);
    if (st != PP5_OK)
        return pp5_fail(st, "%s: %s (no END ... RES line: pass --source-mm and "
                        "--source-distance-mm, or --source-px-per-deg)", r->name,
                        pp5_error_text());
    return PP5_OK;
}

pp5_status_t import_eyelink(const char *text, size_t len, const char *name,
                            const import_options_t *o, trace_t *out)
{
    eyelink_reader_t r = {.o = o, .name = name, .gaze_samples = true, .t0 = NAN,
                          .prev_ms = NAN};
    trace_init(&r.t);
    size_t line_size, pos = 0;
    char *line = import_line_buffer(&line_size);
    if (!line)
        return PP5_E_NOMEM;
    bool too_long;
    pp5_status_t st = PP5_OK;
    while (st == PP5_OK && import_next_line(text, len, &pos, line, line_size, &too_long)) {
        r.lineno++;
        if (too_long)
            st = import_line_too_long(name, r.lineno);
        else if (isdigit((unsigned char)line[0]))
            st = parse_sample_line(&r, line);
        else
            st = parse_keyword_line(&r, line);
    }
    if (st == PP5_OK)
        st = finish_header(&r);
    free(line);
    free(r.ev.v);
    free(r.tracker_ms);
    return import_commit(&r.t, st, out);
}
