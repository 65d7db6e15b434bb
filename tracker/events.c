/* events.c: what the three detectors share (events.h): the signal, the
 * post-processing of blinks, gaps and short fixations, and events built from
 * label sequences. */
#include "events_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "angles.h"

void events_defaults(events_params_t *p, events_method_t method)
{
    memset(p, 0, sizeof *p);
    p->method = method;
    /* ivt and idt thresholds: the best of a grid on the tuning files of
     * lund2013 only (`pp5 reproduce events --tune`; the split is in
     * reproduce_events_lund.c and tracker/ARCHITECTURE.md). */
    p->ivt_threshold_dps = 65.0;
    p->idt_dispersion_deg = 1.0;
    p->idt_window_s = 0.040;
    /* Nystrom & Holmqvist 2010's values, except the filter window: 10 ms
     * scored better than their 20 ms on the tuning files (mean kappa 0.542
     * against 0.503), and their mean/sd better than median/MAD (0.422). */
    p->nh_filter_s = 0.010;
    p->nh_peak_start_dps = 100.0;
    p->nh_peak_sigmas = 6.0;
    p->nh_onset_sigmas = 3.0;
    p->nh_offset_weight = 0.7;
    p->nh_noise_window_s = 0.040;
    p->nh_pso_window_s = 0.040;
    p->nh_max_speed_dps = 1000.0;
    p->nh_max_accel_dps2 = 100000.0;
    p->min_saccade_s = 0.010;
    p->min_fixation_s = 0.040;
    /* A 20 ms PSO (gaze-facts §1: Lund median 22 ms) is 5 samples at 250 Hz,
     * no more than the 20 ms filter window: too few to tell its wobble from
     * the saccade's tail [assumption]. */
    p->pso_min_rate_hz = 400.0;
    p->blink_min_s = 0.080;
    p->blink_max_s = 0.900;
    p->edge_search_s = 0.020;
    /* One value for every method: k = 1 has the best mean over the three on
     * the tuning files (0.453, 0.440, 0.542; k = 2: 0.449, 0.430, 0.545). */
    p->edge_noise_sigmas = 1.0;
}

static const char *const method_names[] = {"ivt", "idt", "adaptive"};

bool events_method_parse(const char *name, events_method_t *m)
{
    for (int i = 0; i < 3; i++)
        if (strcmp(name, method_names[i]) == 0) {
            *m = (events_method_t)i;
            return true;
        }
    return false;
}

const char *events_method_name(events_method_t m)
{
    return (unsigned)m < 3 ? method_names[m] : "?";
}

static const char *const class_names[EVENTS_CLASS_MAX + 1] = {
    NULL, "fixation", "saccade", "pso", "pursuit", "blink", "undefined", "gap"};

const char *events_class_name(int cls)
{
    return cls >= 0 && cls <= EVENTS_CLASS_MAX ? class_names[cls] : NULL;
}

bool events_class_parse(const char *name, int *cls)
{
    for (int i = 1; i <= EVENTS_CLASS_MAX; i++)
        if (strcmp(name, class_names[i]) == 0) {
            *cls = i;
            return true;
        }
    return false;
}

/* ---------------------------------------------------------------- signal */

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* 1 / median positive interval; the header's rate when there is none. */
static double effective_rate(const trace_t *t)
{
    size_t n = t->count, m = 0;
    double *d = n > 1 ? malloc((n - 1) * sizeof *d) : NULL;
    if (!d)
        return t->header.sample_rate_hz;
    for (size_t i = 1; i < n; i++)
        if (t->samples[i].t_ns > t->samples[i - 1].t_ns)
            d[m++] = (double)(t->samples[i].t_ns - t->samples[i - 1].t_ns) / 1e9;
    double rate = t->header.sample_rate_hz;
    if (m) {
        qsort(d, m, sizeof *d, cmp_double);
        rate = 1.0 / d[m / 2];
    }
    free(d);
    return rate;
}

void events_signal_free(events_signal_t *s)
{
    free(s->t_s);
    free(s->ax);
    free(s->ay);
    free(s->speed);
    memset(s, 0, sizeof *s);
}

static double pair_speed(const events_signal_t *s, size_t a, size_t b)
{
    double dt = s->t_s[b] - s->t_s[a];
    if (!(dt > 0) || !events_sample_ok(s, a) || !events_sample_ok(s, b))
        return NAN;
    return hypot(s->ax[b] - s->ax[a], s->ay[b] - s->ay[a]) / dt;
}

pp5_status_t events_signal_build(const trace_t *t, events_signal_t *s)
{
    memset(s, 0, sizeof *s);
    pp5_status_t st = angles_resolve(&t->header.geometry, &s->geometry);
    if (st != PP5_OK)
        return st;
    size_t n = t->count, bytes;
    if (n == 0)
        return pp5_fail(PP5_E_RANGE, "event detection: the trace has no samples");
    if (!pp5_mul_size(n, sizeof(double), &bytes))
        return pp5_fail(PP5_E_NOMEM, "event detection: trace too long");
    s->t_s = malloc(bytes);
    s->ax = malloc(bytes);
    s->ay = malloc(bytes);
    s->speed = malloc(bytes);
    if (!s->t_s || !s->ax || !s->ay || !s->speed) {
        events_signal_free(s);
        return pp5_fail(PP5_E_NOMEM, "event detection: out of memory for %zu samples", n);
    }
    s->n = n;
    for (size_t i = 0; i < n; i++) {
        const gaze_sample_t *g = &t->samples[i];
        s->t_s[i] = g->t_ns / 1e9;
        if (g->flags & GAZE_FLAG_VALID)
            angles_px_to_deg(&s->geometry, g->x_px, g->y_px, &s->ax[i], &s->ay[i]);
        else
            s->ax[i] = s->ay[i] = NAN;
    }
    for (size_t i = 0; i < n; i++) {
        double v = NAN;
        if (events_sample_ok(s, i)) {
            bool prev = i > 0 && events_sample_ok(s, i - 1);
            bool next = i + 1 < n && events_sample_ok(s, i + 1);
            if (prev && next)
                v = pair_speed(s, i - 1, i + 1);
            else if (next)
                v = pair_speed(s, i, i + 1);
            else if (prev)
                v = pair_speed(s, i - 1, i);
        }
        s->speed[i] = v;
    }
    s->rate_hz = effective_rate(t);
    if (!(s->rate_hz > 0) || !isfinite(s->rate_hz)) {
        events_signal_free(s);
        return pp5_fail(PP5_E_RANGE, "event detection: no usable sample rate");
    }
    return PP5_OK;
}

size_t events_samples_for(const events_signal_t *s, double d)
{
    double k = floor(d * s->rate_hz + 0.5);
    return k < 1 ? 1 : (size_t)k;
}

/* -------------------------------------------------------- post-processing */

/* The time a run of samples [a, b] covers: to the next sample, unless that is
 * across a pause (more than 3 intervals), then one interval past the last. */
static double run_seconds(const events_signal_t *s, size_t a, size_t b)
{
    double interval = 1.0 / s->rate_hz;
    double end = s->t_s[b] + interval;
    if (b + 1 < s->n && s->t_s[b + 1] - s->t_s[b] <= 3.0 * interval)
        end = s->t_s[b + 1];
    return end - s->t_s[a];
}

/* Mean + k sd of the speeds of the fixation samples (NaN with fewer than 10). */
static double fixation_noise_floor(const events_signal_t *s, const int *labels, double k_sd)
{
    double sum = 0, sum2 = 0;
    size_t k = 0;
    for (size_t i = 0; i < s->n; i++)
        if (labels[i] == GAZE_LABEL_FIXATION && !isnan(s->speed[i])) {
            sum += s->speed[i];
            sum2 += s->speed[i] * s->speed[i];
            k++;
        }
    if (k < 10)
        return NAN;
    double mean = sum / (double)k, var = sum2 / (double)k - mean * mean;
    return mean + k_sd * (var > 0 ? sqrt(var) : 0);
}

/* One edge of the saccade [*a, *b]: step = -1 moves the onset, +1 the end. */
static void settle_edge(const events_signal_t *s, int *labels, size_t *a, size_t *b, int step,
                        double floor_dps, size_t reach)
{
    size_t *edge = step < 0 ? a : b;
    size_t inner = *edge - (size_t)(long)step;
    if (s->speed[*edge] > floor_dps && (*a == *b || s->speed[inner] > floor_dps)) {
        for (size_t k = 0; k < reach; k++) {
            size_t next = *edge + (size_t)(long)step;
            if ((step < 0 && *edge == 0) || (step > 0 && next >= s->n) ||
                labels[next] != GAZE_LABEL_FIXATION || !(s->speed[next] < s->speed[*edge]) ||
                !(s->speed[next] > floor_dps))
                break;
            labels[next] = GAZE_LABEL_SACCADE;
            *edge = next;
        }
        return;
    }
    /* Inwards to the first of two samples above the floor: one noisy sample
     * above it is not yet the eye moving. */
    for (size_t k = 0; k < reach && *a + 1 < *b; k++) {
        inner = *edge - (size_t)(long)step;
        if (s->speed[*edge] > floor_dps && s->speed[inner] > floor_dps)
            break;
        labels[*edge] = GAZE_LABEL_FIXATION;
        *edge = inner;
    }
}

void events_settle_saccade_edges(const events_signal_t *s, const events_params_t *p,
                                 int *labels)
{
    size_t reach = p->edge_search_s > 0 ? events_samples_for(s, p->edge_search_s) : 0;
    double floor_dps = fixation_noise_floor(s, labels, p->edge_noise_sigmas);
    if (!reach || isnan(floor_dps))
        return;
    for (size_t i = 0; i < s->n; i++) {
        if (labels[i] != GAZE_LABEL_SACCADE || (i > 0 && labels[i - 1] == GAZE_LABEL_SACCADE))
            continue;
        size_t a = i, b = i;
        while (b + 1 < s->n && labels[b + 1] == GAZE_LABEL_SACCADE)
            b++;
        settle_edge(s, labels, &a, &b, -1, floor_dps, reach);
        if (!(b + 1 < s->n && labels[b + 1] == GAZE_LABEL_PSO))
            settle_edge(s, labels, &a, &b, +1, floor_dps, reach);
        i = b;
    }
}

static bool lid_artefact(int label)
{
    return label == GAZE_LABEL_SACCADE || label == GAZE_LABEL_PSO || label == GAZE_LABEL_NOISE;
}

/* Missing runs become blinks or gaps; a blink swallows the saccade-like
 * samples on either side of it (the lid moving over the pupil). */
static void label_missing(const events_signal_t *s, const events_params_t *p, int *labels)
{
    for (size_t i = 0; i < s->n; i++) {
        if (events_sample_ok(s, i))
            continue;
        size_t a = i, b = i;
        while (b + 1 < s->n && !events_sample_ok(s, b + 1))
            b++;
        double d = run_seconds(s, a, b);
        bool blink = d >= p->blink_min_s && d <= p->blink_max_s;
        for (size_t k = a; k <= b; k++)
            labels[k] = blink ? GAZE_LABEL_BLINK : GAZE_LABEL_NONE;
        if (blink) {
            while (a > 0 && lid_artefact(labels[a - 1]))
                labels[--a] = GAZE_LABEL_BLINK;
            while (b + 1 < s->n && lid_artefact(labels[b + 1]))
                labels[++b] = GAZE_LABEL_BLINK;
        }
        i = b;
    }
}

static void drop_short_fixations(const events_signal_t *s, const events_params_t *p, int *labels)
{
    for (size_t i = 0; i < s->n; i++) {
        if (labels[i] != GAZE_LABEL_FIXATION)
            continue;
        size_t b = i;
        while (b + 1 < s->n && labels[b + 1] == GAZE_LABEL_FIXATION)
            b++;
        if (run_seconds(s, i, b) < p->min_fixation_s)
            for (size_t k = i; k <= b; k++)
                labels[k] = GAZE_LABEL_NOISE;
        i = b;
    }
}

static pp5_status_t check_params(const events_params_t *p)
{
    bool ok = p->ivt_threshold_dps > 0 && p->ivt_threshold_dps < 1e5 &&
              p->idt_dispersion_deg > 0 && p->idt_dispersion_deg < 180 &&
              p->idt_window_s > 0 && p->idt_window_s < 10 && p->nh_filter_s > 0 &&
              p->nh_filter_s < 1 && p->nh_peak_start_dps > 0 && p->nh_peak_sigmas > 0 &&
              p->nh_onset_sigmas > 0 && p->nh_offset_weight >= 0 && p->nh_offset_weight <= 1 &&
              p->nh_noise_window_s > 0 && p->nh_pso_window_s >= 0 && p->nh_max_speed_dps > 0 &&
              p->nh_max_accel_dps2 > 0 && p->min_saccade_s >= 0 && p->min_fixation_s >= 0 &&
              p->pso_min_rate_hz >= 0 && p->blink_min_s >= 0 && p->blink_max_s >= p->blink_min_s &&
              p->edge_search_s >= 0 && p->edge_search_s < 1 && p->edge_noise_sigmas >= 0 &&
              p->edge_noise_sigmas <= 10;
    return ok ? PP5_OK : pp5_fail(PP5_E_CONFIG, "event detection: a parameter is out of range");
}

void events_result_free(events_result_t *r)
{
    free(r->labels);
    events_list_free(&r->list);
    memset(r, 0, sizeof *r);
}

pp5_status_t events_detect(const trace_t *t, const events_params_t *p, events_result_t *out)
{
    memset(out, 0, sizeof *out);
    pp5_status_t st = check_params(p);
    if (st != PP5_OK)
        return st;
    events_signal_t s;
    if ((st = events_signal_build(t, &s)) != PP5_OK)
        return st;
    events_result_t r;
    memset(&r, 0, sizeof r);
    r.n = s.n;
    r.rate_hz = s.rate_hz;
    r.labels = calloc(s.n, sizeof *r.labels);
    if (!r.labels)
        st = pp5_fail(PP5_E_NOMEM, "event detection: out of memory");
    if (st == PP5_OK) {
        switch (p->method) {
        case EVENTS_IVT: st = events_ivt(&s, p, r.labels, &r); break;
        case EVENTS_IDT: st = events_idt(&s, p, r.labels, &r); break;
        case EVENTS_ADAPTIVE: st = events_adaptive(&s, p, r.labels, &r); break;
        default: st = pp5_fail(PP5_E_CONFIG, "event detection: unknown method"); break;
        }
    }
    if (st == PP5_OK) {
        label_missing(&s, p, r.labels);
        drop_short_fixations(&s, p, r.labels);
        st = events_from_labels(t, r.labels, &r.list);
    }
    events_signal_free(&s);
    if (st != PP5_OK) {
        events_result_free(&r);
        return st;
    }
    *out = r;
    return PP5_OK;
}

/* ----------------------------------------------------------------- events */

void events_list_free(events_list_t *l)
{
    free(l->events);
    memset(l, 0, sizeof *l);
}

pp5_status_t events_list_append(events_list_t *l, const gaze_event_t *e)
{
    void *items = l->events;
    pp5_status_t st = pp5_grow(&items, &l->capacity, l->count, sizeof *l->events, "events");
    l->events = items;
    if (st == PP5_OK)
        l->events[l->count++] = *e;
    return st;
}

static void describe_event(const trace_t *t, const events_signal_t *s, gaze_event_t *e)
{
    size_t a = e->first, b = e->last;
    e->onset_s = s->t_s[a];
    e->duration_s = run_seconds(s, a, b);
    e->start_x_px = e->start_y_px = e->end_x_px = e->end_y_px = NAN;
    e->amplitude_deg = e->peak_velocity_dps = NAN;
    if (e->cls == GAZE_LABEL_BLINK || e->cls == EVENTS_GAP)
        return;
    size_t first_ok = a, last_ok = b;
    while (first_ok <= b && !events_sample_ok(s, first_ok))
        first_ok++;
    while (last_ok > first_ok && !events_sample_ok(s, last_ok))
        last_ok--;
    if (first_ok > b)
        return;
    e->start_x_px = t->samples[first_ok].x_px;
    e->start_y_px = t->samples[first_ok].y_px;
    e->end_x_px = t->samples[last_ok].x_px;
    e->end_y_px = t->samples[last_ok].y_px;
    e->amplitude_deg = hypot(s->ax[last_ok] - s->ax[first_ok], s->ay[last_ok] - s->ay[first_ok]);
    for (size_t k = a; k <= b; k++)
        if (!isnan(s->speed[k]) && !(s->speed[k] <= e->peak_velocity_dps))
            e->peak_velocity_dps = s->speed[k];
}

static int event_class_of(const events_signal_t *s, const int *labels, size_t i)
{
    int l = labels[i];
    if (l == GAZE_LABEL_NONE)
        return events_sample_ok(s, i) ? 0 : EVENTS_GAP;
    return l >= 1 && l <= GAZE_LABEL_MAX ? l : 0;
}

pp5_status_t events_from_labels(const trace_t *t, const int *labels, events_list_t *out)
{
    memset(out, 0, sizeof *out);
    events_signal_t s;
    pp5_status_t st = events_signal_build(t, &s);
    if (st != PP5_OK)
        return st;
    double pause = 3.0 / s.rate_hz;
    events_list_t l;
    memset(&l, 0, sizeof l);
    for (size_t i = 0; i < s.n && st == PP5_OK; i++) {
        int cls = event_class_of(&s, labels, i);
        size_t b = i;
        while (b + 1 < s.n && event_class_of(&s, labels, b + 1) == cls &&
               s.t_s[b + 1] - s.t_s[b] <= pause)
            b++;
        if (cls != 0) {
            gaze_event_t e;
            memset(&e, 0, sizeof e);
            e.cls = cls;
            e.first = i;
            e.last = b;
            describe_event(t, &s, &e);
            st = events_list_append(&l, &e);
        }
        i = b;
    }
    events_signal_free(&s);
    if (st != PP5_OK) {
        events_list_free(&l);
        return st;
    }
    *out = l;
    return PP5_OK;
}
