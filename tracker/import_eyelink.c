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

#define LINE_MAX_BYTES 4096
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

pp5_status_t import_eyelink(const char *text, size_t len, const char *name,
                            const import_options_t *o, trace_t *out)
{
    char line[LINE_MAX_BYTES];
    size_t pos = 0;
    bool too_long;
    int lineno = 0;
    trace_t t;
    trace_init(&t);
    intervals_t ev = {0};
    double *tracker_ms = NULL;       /* per sample: tracker time (for labels) */
    size_t tcap = 0;
    bool left = false, right = false, eyes_known = false, in_block = false, gaze_samples = true;
    double rate = 0, res_sum = 0, t0 = NAN, prev_ms = NAN;
    int res_n = 0, disp_w = 0, disp_h = 0, same_stamp = 0;
    pp5_status_t st = PP5_OK;

    while (st == PP5_OK && import_next_line(text, len, &pos, line, sizeof line, &too_long)) {
        lineno++;
        if (too_long) {
            st = pp5_fail(PP5_E_FORMAT, "%s:%d: line longer than %d bytes", name, lineno,
                          LINE_MAX_BYTES);
            break;
        }
        char *f[MAX_FIELDS];
        if (isdigit((unsigned char)line[0])) {
            /* ---- a sample line ---- */
            if (!in_block || !eyes_known) {
                st = pp5_fail(PP5_E_FORMAT, "%s:%d: sample line outside a START ... END block "
                              "(or before its eyes are known)", name, lineno);
                break;
            }
            if (!gaze_samples) {
                st = pp5_fail(PP5_E_UNSUPPORTED, "%s:%d: samples are not GAZE (HREF/PUPIL "
                              "samples are not screen pixels; re-export with edf2asc)", name,
                              lineno);
                break;
            }
            int n = split_ws(line, f, MAX_FIELDS);
            bool bino = left && right;
            if (n < (bino ? 7 : 4)) {
                st = pp5_fail(PP5_E_FORMAT, "%s:%d: %s sample line has %d fields, needs %d "
                              "(truncated?)", name, lineno, bino ? "binocular" : "monocular", n,
                              bino ? 7 : 4);
                break;
            }
            double ms;
            if (!import_parse_double(f[0], &ms) || !isfinite(ms)) {
                st = pp5_fail(PP5_E_FORMAT, "%s:%d: bad time '%s'", name, lineno, f[0]);
                break;
            }
            double eyes[2][2];
            bool have[2] = {false, false};
            int idx[2][2] = {{1, 2}, {4, 5}};
            int use_eyes = bino ? 2 : 1;
            bool bad = false;
            for (int e = 0; e < use_eyes; e++) {
                const char *xs = f[idx[e][0]], *ys = f[idx[e][1]];
                if (is_missing(xs) || is_missing(ys))
                    continue;
                if (!import_parse_double(xs, &eyes[e][0]) || !import_parse_double(ys, &eyes[e][1])) {
                    bad = true;
                    break;
                }
                /* `edf2asc -miss NaN` writes NaN for missing data. */
                have[e] = isfinite(eyes[e][0]) && isfinite(eyes[e][1]);
            }
            if (bad) {
                st = pp5_fail(PP5_E_FORMAT, "%s:%d: gaze is neither a number nor '.'", name,
                              lineno);
                break;
            }
            /* Pick the eye(s). Binocular: column group 0 is left, 1 right. */
            double x = 0, y = 0;
            int k = 0;
            for (int e = 0; e < use_eyes; e++) {
                char which = bino ? (e == 0 ? 'L' : 'R') : (left ? 'L' : 'R');
                if (!have[e] || (o->eye && bino && o->eye != which))
                    continue;
                x += eyes[e][0];
                y += eyes[e][1];
                k++;
            }
            /* Time, with the 2000 Hz half-millisecond rule. */
            if (!isnan(prev_ms) && ms < prev_ms) {
                st = pp5_fail(PP5_E_FORMAT, "%s:%d: time %.1f ms is before the previous sample "
                              "(%.1f ms): out-of-order time", name, lineno, ms, prev_ms);
                break;
            }
            double sample_ms = ms;
            if (!isnan(prev_ms) && ms == prev_ms && rate > 1000 && !same_stamp) {
                sample_ms = ms + 0.5;
                same_stamp = 1;
            } else {
                same_stamp = 0;
            }
            prev_ms = ms;
            if (isnan(t0))
                t0 = sample_ms;
            if ((sample_ms - t0) * 1e6 > 1e17) {
                st = pp5_fail(PP5_E_RANGE, "%s:%d: timestamps span more than 3 years", name,
                              lineno);
                break;
            }
            gaze_sample_t s;
            gaze_sample_invalid(&s, llround((sample_ms - t0) * 1e6));
            if (k > 0) {
                s.x_px = x / k;
                s.y_px = y / k;
                s.flags = GAZE_FLAG_VALID;
            }
            if (t.count == tcap) {
                size_t cap = tcap ? tcap * 2 : 4096;
                double *p = realloc(tracker_ms, cap * sizeof *p);
                if (!p) {
                    st = pp5_fail(PP5_E_NOMEM, "out of memory");
                    break;
                }
                tracker_ms = p;
                tcap = cap;
            }
            tracker_ms[t.count] = ms;
            st = trace_append(&t, &s);
            continue;
        }
        /* ---- keyword lines ---- */
        if (line[0] == '*' || line[0] == '#' || line[0] == '/' || line[0] == ';')
            continue;
        int n = split_ws(line, f, MAX_FIELDS);
        if (n == 0)
            continue;
        if (strcmp(f[0], "START") == 0) {
            in_block = true;
            left = right = false;
            for (int i = 2; i < n; i++) {
                left |= strcmp(f[i], "LEFT") == 0;
                right |= strcmp(f[i], "RIGHT") == 0;
            }
            eyes_known = left || right;
        } else if (strcmp(f[0], "SAMPLES") == 0) {
            bool l = false, r = false;
            gaze_samples = n > 1 && strcmp(f[1], "GAZE") == 0;
            for (int i = 1; i < n; i++) {
                l |= strcmp(f[i], "LEFT") == 0;
                r |= strcmp(f[i], "RIGHT") == 0;
                if (strcmp(f[i], "RATE") == 0 && i + 1 < n) {
                    double v;
                    if (!import_parse_double(f[i + 1], &v) || !(v > 0 && v <= 100000)) {
                        st = pp5_fail(PP5_E_FORMAT, "%s:%d: bad RATE '%s'", name, lineno, f[i + 1]);
                        break;
                    }
                    if (rate > 0 && v != rate && t.count > 0) {
                        st = pp5_fail(PP5_E_UNSUPPORTED, "%s:%d: the sample rate changes from "
                                      "%g to %g Hz between blocks", name, lineno, rate, v);
                        break;
                    }
                    rate = v;
                }
            }
            if (l || r) {
                left = l;
                right = r;
                eyes_known = true;
            }
        } else if (strcmp(f[0], "END") == 0) {
            in_block = false;
            for (int i = 1; i + 2 < n; i++)
                if (strcmp(f[i], "RES") == 0) {
                    double v;
                    if (import_parse_double(f[i + 1], &v) && v > 0 && isfinite(v)) {
                        res_sum += v;
                        res_n++;
                    }
                }
        } else if (strcmp(f[0], "MSG") == 0 && n >= 7 &&
                   (strcmp(f[2], "DISPLAY_COORDS") == 0 || strcmp(f[2], "GAZE_COORDS") == 0)) {
            double c[4];
            bool ok = true;
            for (int i = 0; i < 4; i++)
                ok = ok && import_parse_double(f[3 + i], &c[i]) && isfinite(c[i]);
            if (!ok || c[2] <= c[0] || c[3] <= c[1] || c[2] - c[0] > 100000 || c[3] - c[1] > 100000) {
                st = pp5_fail(PP5_E_FORMAT, "%s:%d: bad %s", name, lineno, f[2]);
                break;
            }
            /* Odd last coordinate: inclusive (1023 -> 1024); even: a size. */
            double w = c[2] - c[0], h = c[3] - c[1];
            disp_w = (int)w + ((long)c[2] % 2 != 0 ? 1 : 0);
            disp_h = (int)h + ((long)c[3] % 2 != 0 ? 1 : 0);
        } else if ((strcmp(f[0], "EFIX") == 0 || strcmp(f[0], "ESACC") == 0 ||
                    strcmp(f[0], "EBLINK") == 0) && n >= 4) {
            double a, b;
            if (!import_parse_double(f[2], &a) || !import_parse_double(f[3], &b)) {
                st = pp5_fail(PP5_E_FORMAT, "%s:%d: bad %s times", name, lineno, f[0]);
                break;
            }
            if (b < a)
                continue;   /* EyeLink I writes empty blinks ("EBLINK R 419788 419784 0"):
                               they cover no sample */
            int label = f[0][1] == 'F' ? GAZE_LABEL_FIXATION :
                        f[0][1] == 'S' ? GAZE_LABEL_SACCADE : GAZE_LABEL_BLINK;
            st = intervals_add(&ev, a, b, label);
        }
    }
    if (st == PP5_OK && t.count == 0)
        st = pp5_fail(PP5_E_FORMAT, "%s: no sample lines (is this an EyeLink ASC file with "
                      "samples?)", name);
    if (st == PP5_OK && !(rate > 0))
        st = pp5_fail(PP5_E_FORMAT, "%s: no 'SAMPLES ... RATE <hz>' line: sample rate unknown",
                      name);
    if (st == PP5_OK) {
        /* Labels: events in time order per eye; apply by rank. */
        for (size_t e = 0; e < ev.n; e++) {
            const interval_t *iv = &ev.v[e];
            /* binary search for the first sample at or after the start */
            size_t lo = 0, hi = t.count;
            while (lo < hi) {
                size_t mid = (lo + hi) / 2;
                if (tracker_ms[mid] < iv->t0_ms)
                    lo = mid + 1;
                else
                    hi = mid;
            }
            for (size_t i = lo; i < t.count && tracker_ms[i] <= iv->t1_ms; i++) {
                gaze_sample_t *s = &t.samples[i];
                if (label_rank(iv->label) > label_rank(s->label))
                    s->label = iv->label;
            }
        }
        for (size_t i = 0; i < t.count; i++)
            if (!(t.samples[i].flags & GAZE_FLAG_VALID) && t.samples[i].label == GAZE_LABEL_BLINK)
                t.samples[i].flags = GAZE_FLAG_BLINK;
        gaze_geometry_t *g = &t.header.geometry;
        g->width_px = disp_w;
        g->height_px = disp_h;
        g->px_per_deg = res_n ? res_sum / res_n : 0;
        import_apply_geometry(o, g);
        t.header.sample_rate_hz = rate;
        snprintf(t.header.source, sizeof t.header.source, "EyeLink ASC %s", name);
        snprintf(t.header.tracker, sizeof t.header.tracker, "SR Research EyeLink (%s)",
                 left && right ? (o->eye ? (o->eye == 'L' ? "left eye" : "right eye")
                                         : "binocular, mean of the eyes")
                               : left ? "left eye" : "right eye");
        if (g->width_px < 1)
            st = pp5_fail(PP5_E_FORMAT, "%s: no DISPLAY_COORDS or GAZE_COORDS message: pass "
                          "--source-px WxH", name);
        else if ((st = trace_header_check(&t.header)) != PP5_OK)
            st = pp5_fail(st, "%s: %s (no END ... RES line: pass --source-mm and "
                          "--source-distance-mm, or --source-px-per-deg)", name, pp5_error_text());
    }
    free(ev.v);
    free(tracker_ms);
    return import_commit(&t, st, out);
}
