/* events_adaptive.c: the noise-adaptive detector of Nystrom & Holmqvist 2010,
 * "An adaptive algorithm for fixation, saccade, and glissade detection in
 * eyetracking data", Behavior Research Methods 42(1):188-204.  Written here
 * from the paper's description (§"Method"), not from any implementation:
 *  1. Speed and acceleration from a Savitzky-Golay filter (quadratic; the
 *     paper's window is twice the shortest saccade, 20 ms).  Samples faster than 1000 deg/s or
 *     accelerating above 100000 deg/s^2 are noise.
 *  2. Peak threshold, found from the data: start at 100 deg/s; take the mean
 *     and standard deviation of the samples slower than the threshold; the new
 *     threshold is mean + 6 sd; repeat until it moves by less than 1 deg/s.
 *     The onset threshold is mean + 3 sd.  So the thresholds rise with the
 *     noise of the recording, which is what makes the method noise-robust.
 *  3. Every run faster than the peak threshold is a saccade candidate: its
 *     onset is found going back from the peak to below the onset threshold
 *     and on to the velocity minimum; its offset going forward to below the
 *     offset threshold (0.7 x onset threshold + 0.3 x the local noise, mean +
 *     3 sd of the 40 ms before the onset) and on to the minimum.  Saccades
 *     shorter than 10 ms are dropped.
 *  4. A glissade (PSO) follows when, within 40 ms after the offset, the speed
 *     rises above the peak threshold (a "high-velocity" glissade) or above the
 *     offset threshold (a "low-velocity" one); it ends at the velocity minimum
 *     after the last sample above that threshold.  Only at rates >=
 *     pso_min_rate_hz (events.c).
 *  5. The rest is fixation (noise samples are "undefined"); fixations shorter
 *     than 40 ms are dropped (events.c).
 * Deviations: the filter window is 10 ms (chosen on the lund2013 tuning
 * files, events.c); the thresholds are computed once per trace, not per trial
 * (pp5 traces hold one trial or one recording); the filter assumes uniform
 * sampling at the effective rate; afterwards the saccade edges settle on the
 * unfiltered speed (events_settle_saccade_edges), since the filter spreads a
 * saccade by half its window on each side.  Optional (nh_robust, off): median
 * and MAD in place of mean and sd; it scored lower on the tuning files. */
#include "events_internal.h"

#include <stdlib.h>
#include <string.h>

typedef struct {
    double *v;          /* filtered speed, deg/s; NaN where the window is incomplete */
    bool *noise;        /* valid but implausible (or no full window) */
    double *scratch;    /* n doubles for the statistics */
} nh_signal_t;

/* Savitzky-Golay first and second derivative of a quadratic fit over 2m+1
 * evenly spaced samples, at the centre: the first derivative is the slope of
 * the least-squares line, sum k y_k / sum k^2; the second is twice the
 * quadratic coefficient, sum (k^2 - q) y_k / sum (k^2 - q)^2 with q the mean
 * of k^2 = m(m+1)/3. */
static pp5_status_t nh_filter(const events_signal_t *s, const events_params_t *p, nh_signal_t *f)
{
    size_t n = s->n;
    f->v = malloc(n * sizeof *f->v);
    f->noise = calloc(n, sizeof *f->noise);
    f->scratch = malloc(n * sizeof *f->scratch);
    if (!f->v || !f->noise || !f->scratch)
        return pp5_fail(PP5_E_NOMEM, "adaptive detection: out of memory");
    long m = (long)floor(p->nh_filter_s * s->rate_hz / 2.0 + 0.5);
    if (m < 1)
        m = 1;
    double s2 = 0, s4 = 0, q = (double)m * (m + 1) / 3.0;
    for (long k = -m; k <= m; k++) {
        s2 += (double)k * k;
        s4 += ((double)k * k - q) * ((double)k * k - q);
    }
    double pause = 3.0 / s->rate_hz, dt = 1.0 / s->rate_hz;
    for (size_t i = 0; i < n; i++) {
        f->v[i] = NAN;
        if (!events_sample_ok(s, i))
            continue;
        bool full = i >= (size_t)m && i + (size_t)m < n;
        for (long k = -m; full && k <= m; k++) {
            size_t j = (size_t)((long)i + k);
            full = events_sample_ok(s, j) && (k == -m || s->t_s[j] - s->t_s[j - 1] <= pause);
        }
        if (!full) {
            f->noise[i] = true;
            continue;
        }
        double vx = 0, vy = 0, axx = 0, ayy = 0;
        for (long k = -m; k <= m; k++) {
            size_t j = (size_t)((long)i + k);
            vx += k * s->ax[j];
            vy += k * s->ay[j];
            axx += ((double)k * k - q) * s->ax[j];
            ayy += ((double)k * k - q) * s->ay[j];
        }
        double speed = hypot(vx, vy) / s2 / dt;
        double accel = 2.0 * hypot(axx, ayy) / s4 / (dt * dt);
        f->v[i] = speed;
        f->noise[i] = speed > p->nh_max_speed_dps || accel > p->nh_max_accel_dps2;
    }
    return PP5_OK;
}

static bool usable(const nh_signal_t *f, size_t i)
{
    return !isnan(f->v[i]) && !f->noise[i];
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median and 1.4826 x median absolute deviation of v[0..k) (sorts v): the
 * normal-consistent robust stand-ins for mean and sd. */
static void robust_stats(double *v, size_t k, double *centre, double *spread)
{
    qsort(v, k, sizeof *v, cmp_double);
    *centre = k % 2 ? v[k / 2] : 0.5 * (v[k / 2 - 1] + v[k / 2]);
    for (size_t i = 0; i < k; i++)
        v[i] = fabs(v[i] - *centre);
    qsort(v, k, sizeof *v, cmp_double);
    *spread = 1.4826 * (k % 2 ? v[k / 2] : 0.5 * (v[k / 2 - 1] + v[k / 2]));
}

/* Mean and sd (or their robust stand-ins) of the usable speeds below `below`
 * in [a, b), skipping labelled samples when labels is given; false if fewer
 * than 3.  scratch holds b - a doubles. */
static bool speed_stats(const nh_signal_t *f, const int *labels, size_t a, size_t b, double below,
                        bool robust, double *scratch, double *mean, double *sd)
{
    double sum = 0, sum2 = 0;
    size_t k = 0;
    for (size_t i = a; i < b; i++)
        if (usable(f, i) && f->v[i] < below && (!labels || labels[i] == GAZE_LABEL_NONE)) {
            sum += f->v[i];
            sum2 += f->v[i] * f->v[i];
            scratch[k++] = f->v[i];
        }
    if (k < 3)
        return false;
    if (robust) {
        robust_stats(scratch, k, mean, sd);
        return true;
    }
    *mean = sum / (double)k;
    double var = sum2 / (double)k - *mean * *mean;
    *sd = var > 0 ? sqrt(var) : 0;
    return true;
}

static void nh_thresholds(const nh_signal_t *f, size_t n, const events_params_t *p, double *peak,
                          double *onset)
{
    double pt = p->nh_peak_start_dps, mean = 0, sd = 0;
    for (int it = 0; it < 200; it++) {
        if (!speed_stats(f, NULL, 0, n, pt, p->nh_robust, f->scratch, &mean, &sd))
            break;
        double next = mean + p->nh_peak_sigmas * sd;
        bool done = fabs(next - pt) < 1.0;
        pt = next;
        if (done)
            break;
    }
    *peak = pt;
    *onset = mean + p->nh_onset_sigmas * sd;
    if (!(*onset > 0) || *onset > pt)
        *onset = pt / 2;
}

/* PSO after a saccade ending at b: returns its last sample, or b if none. */
static size_t nh_pso(const events_signal_t *s, const nh_signal_t *f, const events_params_t *p,
                     size_t b, double peak, double offset)
{
    size_t n = s->n, w = events_samples_for(s, p->nh_pso_window_s), last = b;
    double top = 0;
    for (size_t k = b + 1; k < n && k <= b + w && usable(f, k); k++)
        if (f->v[k] > top)
            top = f->v[k];
    double thr = top > peak ? peak : top > offset ? offset : NAN;
    if (isnan(thr))
        return b;
    for (size_t k = b + 1; k < n && k <= b + w && usable(f, k); k++)
        if (f->v[k] > thr)
            last = k;
    while (last + 1 < n && last + 1 <= b + 2 * w && usable(f, last + 1) &&
           f->v[last + 1] < f->v[last])
        last++;
    return last;
}

/* One saccade candidate around the peak run [i, peak_end]; lo is the first
 * sample after the previous event.  Returns the last sample it labelled (or
 * peak_end when the candidate was dropped). */
static size_t nh_saccade(const events_signal_t *s, const nh_signal_t *f, const events_params_t *p,
                         size_t lo, size_t i, size_t peak_end, double peak, double onset,
                         bool pso, int *labels)
{
    size_t a = i, b = peak_end, n = s->n;
    while (a > lo && usable(f, a - 1) && (f->v[a] > onset || f->v[a - 1] < f->v[a]))
        a--;
    double offset = onset, mean, sd;
    size_t w = events_samples_for(s, p->nh_noise_window_s);
    if (speed_stats(f, labels, a > w ? a - w : 0, a, INFINITY, p->nh_robust, f->scratch, &mean,
                    &sd))
        offset = p->nh_offset_weight * onset +
                 (1.0 - p->nh_offset_weight) * (mean + p->nh_onset_sigmas * sd);
    while (b + 1 < n && usable(f, b + 1) && (f->v[b] > offset || f->v[b + 1] < f->v[b]))
        b++;
    if (s->t_s[b] - s->t_s[a] + 1.0 / s->rate_hz < p->min_saccade_s)
        return peak_end;
    for (size_t k = a; k <= b; k++)
        labels[k] = GAZE_LABEL_SACCADE;
    if (!pso)
        return b;
    size_t c = nh_pso(s, f, p, b, peak, offset);
    for (size_t k = b + 1; k <= c; k++)
        labels[k] = GAZE_LABEL_PSO;
    return c;
}

pp5_status_t events_adaptive(const events_signal_t *s, const events_params_t *p, int *labels,
                             events_result_t *r)
{
    nh_signal_t f;
    memset(&f, 0, sizeof f);
    pp5_status_t st = nh_filter(s, p, &f);
    if (st != PP5_OK) {
        free(f.v);
        free(f.noise);
        free(f.scratch);
        return st;
    }
    size_t n = s->n;
    double peak, onset;
    nh_thresholds(&f, n, p, &peak, &onset);
    bool pso = s->rate_hz >= p->pso_min_rate_hz;
    size_t lo = 0;
    for (size_t i = 0; i < n; i++) {
        if (!usable(&f, i) || f.v[i] <= peak || labels[i] != GAZE_LABEL_NONE)
            continue;
        size_t e = i;
        while (e + 1 < n && usable(&f, e + 1) && f.v[e + 1] > peak)
            e++;
        size_t last = nh_saccade(s, &f, p, lo, i, e, peak, onset, pso, labels);
        if (labels[last] != GAZE_LABEL_NONE)
            lo = last + 1;
        i = last;
    }
    for (size_t i = 0; i < n; i++)
        if (events_sample_ok(s, i) && labels[i] == GAZE_LABEL_NONE)
            labels[i] = f.noise[i] ? GAZE_LABEL_NOISE : GAZE_LABEL_FIXATION;
    events_settle_saccade_edges(s, p, labels);
    r->peak_threshold_dps = peak;
    r->onset_threshold_dps = onset;
    r->pso_detected = pso;
    free(f.v);
    free(f.noise);
    free(f.scratch);
    return PP5_OK;
}
