/* events_tsv.c: events as a BIDS-style events.tsv and its JSON sidecar
 * (BIDS common principles: tab-separated, one header line, onset and
 * duration in seconds first, "n/a" for a missing value; gaze-facts §4.4).
 *
 * Columns, in this order (the reader insists on it):
 *   onset          s, time of the event's first sample in the trace
 *   duration       s, to the next sample (one interval at a pause or the end)
 *   trial_type     fixation | saccade | pso | pursuit | blink | undefined | gap
 *   sample         index of the first sample in the trace (0-based)
 *   n_samples      samples in the event
 *   amplitude      deg, first to last valid sample (per-axis angles)
 *   peak_velocity  deg/s, highest central-difference speed inside
 *   start_x start_y end_x end_y   px of the trace's screen, first/last valid sample
 * Written with 6 decimals for times (us), 4 for degrees, 2 for deg/s and 3
 * for pixels, so a file read back and written again is the same bytes. */
#include "events.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"

#define EVENTS_TSV_HEADER "onset\tduration\ttrial_type\tsample\tn_samples\tamplitude\t" \
                          "peak_velocity\tstart_x\tstart_y\tend_x\tend_y"
#define EVENTS_TSV_COLUMNS 11
#define EVENTS_TSV_MAX_BYTES ((size_t)1 << 30)

static void put_number(FILE *f, const char *fmt, double v, bool last)
{
    if (isnan(v))
        fputs("n/a", f);
    else
        fprintf(f, fmt, v);
    fputc(last ? '\n' : '\t', f);
}

pp5_status_t events_write_tsv(const char *path, const events_list_t *l)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return pp5_fail(PP5_E_IO, "%s: cannot create", path);
    fprintf(f, "%s\n", EVENTS_TSV_HEADER);
    for (size_t i = 0; i < l->count; i++) {
        const gaze_event_t *e = &l->events[i];
        const char *name = events_class_name(e->cls);
        fprintf(f, "%.6f\t%.6f\t%s\t%zu\t%zu\t", e->onset_s, e->duration_s, name ? name : "n/a",
                e->first, e->last - e->first + 1);
        put_number(f, "%.4f", e->amplitude_deg, false);
        put_number(f, "%.2f", e->peak_velocity_dps, false);
        put_number(f, "%.3f", e->start_x_px, false);
        put_number(f, "%.3f", e->start_y_px, false);
        put_number(f, "%.3f", e->end_x_px, false);
        put_number(f, "%.3f", e->end_y_px, true);
    }
    if (ferror(f) | (fclose(f) != 0))
        return pp5_fail(PP5_E_IO, "%s: write failed", path);
    return PP5_OK;
}

static void column(json_writer_t *j, const char *name, const char *description, const char *unit)
{
    json_key(j, name);
    json_begin_object(j);
    json_kv_string(j, "Description", description);
    if (unit)
        json_kv_string(j, "Units", unit);
    json_end_object(j);
}

pp5_status_t events_write_sidecar(const char *path, const events_params_t *p,
                                  const events_result_t *r, const char *source)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return pp5_fail(PP5_E_IO, "%s: cannot create", path);
    json_writer_t j;
    json_init(&j, f, true);
    json_begin_object(&j);
    column(&j, "onset", "time of the event's first sample, from the start of the trace", "s");
    column(&j, "duration", "until the next sample (one sample interval at a pause or the end)",
           "s");
    column(&j, "trial_type", "fixation, saccade, pso (post-saccadic oscillation), pursuit, "
           "blink, undefined, gap (lost data that is not a blink)", NULL);
    column(&j, "sample", "index of the event's first sample in the trace, 0-based", NULL);
    column(&j, "n_samples", "number of samples in the event", NULL);
    column(&j, "amplitude", "visual angle from the first to the last valid sample", "deg");
    column(&j, "peak_velocity", "highest central-difference speed of a sample inside", "deg/s");
    column(&j, "start_x", "gaze at the first valid sample, screen pixels from the left", "pixel");
    column(&j, "start_y", "gaze at the first valid sample, screen pixels from the top", "pixel");
    column(&j, "end_x", "gaze at the last valid sample, screen pixels from the left", "pixel");
    column(&j, "end_y", "gaze at the last valid sample, screen pixels from the top", "pixel");
    if (source)
        json_kv_string(&j, "Source", source);
    if (p) {
        json_key(&j, "Detection");
        json_begin_object(&j);
        json_kv_string(&j, "Method", events_method_name(p->method));
        json_kv_double(&j, "EffectiveSamplingFrequency", r ? r->rate_hz : NAN);
        if (p->method == EVENTS_IVT)
            json_kv_double(&j, "VelocityThreshold", p->ivt_threshold_dps);
        if (p->method == EVENTS_IDT) {
            json_kv_double(&j, "DispersionThreshold", p->idt_dispersion_deg);
            json_kv_double(&j, "WindowSeconds", p->idt_window_s);
        }
        if (p->method == EVENTS_ADAPTIVE && r) {
            json_kv_double(&j, "PeakVelocityThreshold", r->peak_threshold_dps);
            json_kv_double(&j, "OnsetVelocityThreshold", r->onset_threshold_dps);
            json_kv_bool(&j, "PostSaccadicOscillations", r->pso_detected);
        }
        json_end_object(&j);
    }
    json_end_object(&j);
    fputc('\n', f);
    if (ferror(f) | (fclose(f) != 0))
        return pp5_fail(PP5_E_IO, "%s: write failed", path);
    return PP5_OK;
}

/* ------------------------------------------------------------------ reader */

static bool parse_number(const char *text, bool allow_na, double *v)
{
    if (allow_na && strcmp(text, "n/a") == 0) {
        *v = NAN;
        return true;
    }
    char *end;
    errno = 0;
    *v = strtod(text, &end);
    return end != text && *end == '\0' && errno != ERANGE && isfinite(*v);
}

static bool parse_count(const char *text, size_t *v)
{
    double d;
    if (!parse_number(text, false, &d) || d < 0 || d > 1e15 || d != floor(d))
        return false;
    *v = (size_t)d;
    return true;
}

/* Splits a line at tabs in place; returns the number of fields (at most max). */
static int split_tabs(char *line, char **fields, int max)
{
    int n = 0;
    for (char *p = line;; p++) {
        if (n == max)
            return max + 1;
        fields[n++] = p;
        p = strchr(p, '\t');
        if (!p)
            return n;
        *p = '\0';
    }
}

static pp5_status_t parse_row(char *line, const char *name, int lineno, gaze_event_t *e)
{
    char *f[EVENTS_TSV_COLUMNS + 1];
    int n = split_tabs(line, f, EVENTS_TSV_COLUMNS);
    if (n != EVENTS_TSV_COLUMNS)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: %d fields, the header has %d", name, lineno, n,
                        EVENTS_TSV_COLUMNS);
    memset(e, 0, sizeof *e);
    size_t count;
    if (!parse_number(f[0], false, &e->onset_s) || e->onset_s < 0 ||
        !parse_number(f[1], false, &e->duration_s) || e->duration_s < 0)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: onset '%s' and duration '%s' must be numbers >= 0",
                        name, lineno, f[0], f[1]);
    if (!events_class_parse(f[2], &e->cls))
        return pp5_fail(PP5_E_FORMAT, "%s:%d: unknown trial_type '%s'", name, lineno, f[2]);
    if (!parse_count(f[3], &e->first) || !parse_count(f[4], &count) || count == 0)
        return pp5_fail(PP5_E_FORMAT, "%s:%d: sample '%s' / n_samples '%s' are not counts "
                        "(n_samples >= 1)", name, lineno, f[3], f[4]);
    e->last = e->first + count - 1;
    double *num[6] = {&e->amplitude_deg, &e->peak_velocity_dps, &e->start_x_px, &e->start_y_px,
                      &e->end_x_px, &e->end_y_px};
    for (int k = 0; k < 6; k++)
        if (!parse_number(f[5 + k], true, num[k]))
            return pp5_fail(PP5_E_FORMAT, "%s:%d: '%s' is neither a number nor n/a", name, lineno,
                            f[5 + k]);
    return PP5_OK;
}

pp5_status_t events_parse_tsv(const char *text, size_t len, const char *name,
                              events_list_t *out)
{
    memset(out, 0, sizeof *out);
    events_list_t l;
    memset(&l, 0, sizeof l);
    pp5_status_t st = PP5_OK;
    size_t pos = 0;
    int lineno = 0;
    char line[1024];
    double last_onset = 0;
    while (st == PP5_OK && pos < len) {
        const char *nl = memchr(text + pos, '\n', len - pos);
        if (!nl) {
            st = pp5_fail(PP5_E_FORMAT, "%s:%d: truncated (the last line has no newline)", name,
                          lineno + 1);
            break;
        }
        size_t n = (size_t)(nl - (text + pos));
        lineno++;
        if (n > 0 && text[pos + n - 1] == '\r')
            n--;
        if (n >= sizeof line) {
            st = pp5_fail(PP5_E_FORMAT, "%s:%d: line too long", name, lineno);
            break;
        }
        memcpy(line, text + pos, n);
        line[n] = '\0';
        pos = (size_t)(nl - text) + 1;
        if (lineno == 1) {
            if (strcmp(line, EVENTS_TSV_HEADER) != 0)
                st = pp5_fail(PP5_E_FORMAT, "%s:1: not a pp5 events.tsv (the header must be the "
                              "columns onset, duration, trial_type, ... of tracker/events_tsv.c)",
                              name);
            continue;
        }
        if (n == 0)
            continue;
        gaze_event_t e;
        st = parse_row(line, name, lineno, &e);
        if (st == PP5_OK && e.onset_s < last_onset)
            st = pp5_fail(PP5_E_FORMAT, "%s:%d: onset %.6f s is before the previous event's",
                          name, lineno, e.onset_s);
        if (st == PP5_OK) {
            last_onset = e.onset_s;
            st = events_list_append(&l, &e);
        }
    }
    if (st == PP5_OK && lineno == 0)
        st = pp5_fail(PP5_E_FORMAT, "%s: empty file (no header line)", name);
    if (st != PP5_OK) {
        events_list_free(&l);
        return st;
    }
    *out = l;
    return PP5_OK;
}

pp5_status_t events_read_tsv(const char *path, events_list_t *out)
{
    char *text;
    size_t len;
    pp5_status_t st = trace_slurp(path, EVENTS_TSV_MAX_BYTES, &text, &len);
    if (st != PP5_OK)
        return st;
    st = events_parse_tsv(text, len, path, out);
    free(text);
    return st;
}
