/* predict_landing_score.c: true landings from labels, and the landing
 * predictor scored against them per amplitude bin (predict_landing.h). */
#include "predict_landing.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "angles.h"

const double landing_bin_edges[LANDING_BINS + 1] = {0, 2, 5, 10, 20, INFINITY};

void landing_truth_free(landing_truth_list_t *l)
{
    free(l->saccades);
    memset(l, 0, sizeof *l);
}

pp5_status_t landing_truth_append(landing_truth_list_t *l, const landing_truth_t *s)
{
    void *items = l->saccades;
    pp5_status_t st = pp5_grow(&items, &l->capacity, l->count, sizeof *l->saccades, "saccades");
    l->saccades = items;
    if (st == PP5_OK)
        l->saccades[l->count++] = *s;
    return st;
}

/* Mean gaze over the 20 ms from sample k on; false if a sample is missing. */
static bool settled_point(const trace_t *t, const gaze_geometry_t *g, size_t k, double *x,
                          double *y)
{
    double sx = 0, sy = 0;
    size_t n = 0;
    for (size_t i = k; i < t->count && t->samples[i].t_ns - t->samples[k].t_ns < 20000000; i++) {
        if (!(t->samples[i].flags & GAZE_FLAG_VALID))
            return false;
        double ax, ay;
        angles_px_to_deg(g, t->samples[i].x_px, t->samples[i].y_px, &ax, &ay);
        sx += ax;
        sy += ay;
        n++;
    }
    if (!n)
        return false;
    *x = sx / (double)n;
    *y = sy / (double)n;
    return true;
}

pp5_status_t landing_truth_from_labels(const trace_t *t, const int *labels,
                                       landing_truth_list_t *out)
{
    memset(out, 0, sizeof *out);
    gaze_geometry_t g;
    pp5_status_t st = angles_resolve(&t->header.geometry, &g);
    for (size_t a = 1; st == PP5_OK && a + 1 < t->count; a++) {
        if (labels[a] != GAZE_LABEL_SACCADE || labels[a - 1] == GAZE_LABEL_SACCADE)
            continue;
        size_t e = a;
        while (e + 1 < t->count && labels[e + 1] == GAZE_LABEL_SACCADE)
            e++;
        while (e + 1 < t->count && labels[e + 1] == GAZE_LABEL_PSO)
            e++;
        bool whole = e + 1 < t->count && (t->samples[a - 1].flags & GAZE_FLAG_VALID);
        for (size_t k = a; whole && k <= e; k++)
            whole = (t->samples[k].flags & GAZE_FLAG_VALID) != 0;
        landing_truth_t s;
        if (whole && settled_point(t, &g, e + 1, &s.x1, &s.y1)) {
            angles_px_to_deg(&g, t->samples[a].x_px, t->samples[a].y_px, &s.x0, &s.y0);
            s.t_start_s = t->samples[a].t_ns / 1e9;
            s.t_end_s = t->samples[e + 1].t_ns / 1e9;
            s.amplitude_deg = hypot(s.x1 - s.x0, s.y1 - s.y0);
            st = landing_truth_append(out, &s);
        }
        a = e;
    }
    if (st != PP5_OK)
        landing_truth_free(out);
    return st;
}

/* ------------------------------------------------------------- evaluation */

typedef struct {
    double t_onset;
    bool first_ok;
    double first_x, first_y, hold_x, hold_y, last_x, last_y;
} flight_t;

typedef struct {
    flight_t *v;
    size_t count, capacity;
} flights_t;

static pp5_status_t push_flight(flights_t *f, const flight_t *x)
{
    void *items = f->v;
    pp5_status_t st = pp5_grow(&items, &f->capacity, f->count, sizeof *f->v, "flights");
    f->v = items;
    if (st == PP5_OK)
        f->v[f->count++] = *x;
    return st;
}

/* Plays the trace through the predictor and records every flight. */
static pp5_status_t record_flights(const trace_t *t, const landing_params_t *p, double gap_reset_s,
                                   flights_t *out)
{
    gaze_geometry_t g;
    pp5_status_t st = angles_resolve(&t->header.geometry, &g);
    landing_state_t s;
    landing_reset(&s);
    flight_t cur;
    bool open = false;
    double last_t = -INFINITY;
    for (size_t i = 0; st == PP5_OK && i <= t->count; i++) {
        bool end = i == t->count;
        const gaze_sample_t *smp = end ? NULL : &t->samples[i];
        if (!end && (smp->flags & GAZE_FLAG_VALID)) {
            double tt = smp->t_ns / 1e9, x, y;
            if (tt - last_t > gap_reset_s)
                landing_lost(&s);
            last_t = tt;
            angles_px_to_deg(&g, smp->x_px, smp->y_px, &x, &y);
            landing_update(&s, p, tt, x, y);
            if (s.in_flight && !open) {
                memset(&cur, 0, sizeof cur);
                cur.t_onset = s.t0;
                open = true;
            }
            double lx, ly, te, amp;
            if (open && s.in_flight && landing_estimate(&s, &lx, &ly, &te, &amp)) {
                if (s.peak_passed && !cur.first_ok) {
                    cur.first_ok = true;
                    cur.first_x = lx;
                    cur.first_y = ly;
                    cur.hold_x = x;
                    cur.hold_y = y;
                }
                cur.last_x = lx;
                cur.last_y = ly;
            }
        } else if (!end) {
            landing_lost(&s);
        }
        if (open && (end || !s.in_flight)) {
            st = push_flight(out, &cur);
            open = false;
        }
    }
    return st;
}

static int bin_of(double amp)
{
    for (int b = 0; b < LANDING_BINS; b++)
        if (amp < landing_bin_edges[b + 1])
            return b;
    return LANDING_BINS - 1;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* 95th percentile by nearest rank (sorts v). */
static double p95(double *v, size_t n)
{
    if (!n)
        return NAN;
    qsort(v, n, sizeof *v, cmp_double);
    size_t rank = (size_t)ceil(0.95 * (double)n);
    return v[(rank < 1 ? 1 : rank) - 1];
}

/* The first flight that started inside saccade k (from 20 ms before its onset
 * to its end) and is not taken yet; SIZE_MAX if none. */
static size_t flight_for(const flights_t *f, const bool *taken, const landing_truth_t *s)
{
    for (size_t i = 0; i < f->count; i++)
        if (!taken[i] && f->v[i].t_onset >= s->t_start_s - 0.020 && f->v[i].t_onset <= s->t_end_s)
            return i;
    return (size_t)-1;
}

pp5_status_t landing_evaluate(const trace_t *t, const landing_params_t *p, double gap_reset_s,
                              const landing_truth_list_t *truth, landing_report_t *out)
{
    memset(out, 0, sizeof *out);
    flights_t f = {0};
    pp5_status_t st = record_flights(t, p, gap_reset_s, &f);
    bool *taken = calloc(f.count + 1, sizeof *taken);
    double *err = malloc((truth->count + 1) * LANDING_BINS * sizeof *err);
    size_t nerr[LANDING_BINS] = {0};
    double last_sum[LANDING_BINS] = {0}, hold_sum[LANDING_BINS] = {0}, sum[LANDING_BINS] = {0};
    if (st == PP5_OK && (!taken || !err))
        st = pp5_fail(PP5_E_NOMEM, "landing evaluation: out of memory");
    for (size_t k = 0; st == PP5_OK && k < truth->count; k++) {
        const landing_truth_t *s = &truth->saccades[k];
        int b = bin_of(s->amplitude_deg);
        out->saccades[b]++;
        size_t i = flight_for(&f, taken, s);
        if (i == (size_t)-1)
            continue;
        taken[i] = true;
        const flight_t *x = &f.v[i];
        if (!x->first_ok)
            continue;
        out->predicted[b]++;
        double e = hypot(x->first_x - s->x1, x->first_y - s->y1);
        err[(size_t)b * (truth->count + 1) + nerr[b]++] = e;
        sum[b] += e;
        last_sum[b] += hypot(x->last_x - s->x1, x->last_y - s->y1);
        hold_sum[b] += hypot(x->hold_x - s->x1, x->hold_y - s->y1);
    }
    for (size_t i = 0; st == PP5_OK && i < f.count; i++)
        out->false_alarms += !taken[i];
    for (int b = 0; st == PP5_OK && b < LANDING_BINS; b++) {
        double n = (double)nerr[b];
        out->mean_err_deg[b] = nerr[b] ? sum[b] / n : NAN;
        out->mean_last_err_deg[b] = nerr[b] ? last_sum[b] / n : NAN;
        out->mean_hold_err_deg[b] = nerr[b] ? hold_sum[b] / n : NAN;
        out->p95_err_deg[b] = p95(err + (size_t)b * (truth->count + 1), nerr[b]);
    }
    free(err);
    free(taken);
    free(f.v);
    return st;
}
