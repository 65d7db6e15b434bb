/* predict_landing.c: the saccade-landing predictor and its scoring
 * (predict_landing.h). */
#include "predict_landing.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "angles.h"
#include "synth.h"

void landing_defaults(landing_params_t *p)
{
    p->onset_dps = 60.0;
    p->onset_noise = 6.0;
    p->vmax_dps = 563.0;
    p->c_deg = 4.31;
    p->velocity_spread = 0.15;
    p->profile_spread = 0.10;
    p->duration_ms_per_deg = 2.55;
    p->duration_ms = 17.6;
    p->peak_drop = 0.85;
    p->max_flight_s = 0.150;
}

void landing_reset(landing_state_t *s)
{
    memset(s, 0, sizeof *s);
}

void landing_lost(landing_state_t *s)
{
    s->in_flight = s->have_estimate = s->peak_passed = false;
    s->fast = s->slow = s->falling = 0;
    s->nsamples = 0;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double recent_median(const landing_state_t *s)
{
    if (s->nrecent == 0)
        return 0;
    double v[LANDING_HISTORY];
    memcpy(v, s->recent, (size_t)s->nrecent * sizeof v[0]);
    qsort(v, (size_t)s->nrecent, sizeof v[0], cmp_double);
    return v[s->nrecent / 2];
}

static void remember_speed(landing_state_t *s, double v)
{
    s->recent[s->recent_head] = v;
    s->recent_head = (s->recent_head + 1) % LANDING_HISTORY;
    if (s->nrecent < LANDING_HISTORY)
        s->nrecent++;
}

/* The profile u^2 (1-u)^3 relative to its peak at u = 0.4. */
static double profile_speed(double u)
{
    return u * u * (1 - u) * (1 - u) * (1 - u) / (0.16 * 0.216);
}

/* u in [0.4, 1) where the decelerating profile has fallen to ratio r. */
static double u_after_peak(double r)
{
    if (r >= 1)
        return 0.4;
    double lo = 0.4, hi = 1.0;
    for (int i = 0; i < 40; i++) {
        double mid = 0.5 * (lo + hi);
        if (profile_speed(mid) > r)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

/* Amplitude from the main sequence and from the profile, weighed by their
 * expected errors (predict_landing.h). */
static double estimate_amplitude(const landing_state_t *s, const landing_params_t *p, double v,
                                 double covered)
{
    double V = s->peak_dps, ratio = V / p->vmax_dps;
    double a_ms = ratio < 0.99 ? -p->c_deg * log(1 - ratio) : INFINITY;
    double sd_ms = ratio < 0.99 ? p->c_deg * p->velocity_spread * ratio / (1 - ratio) : INFINITY;
    if (!s->peak_passed) {
        /* The peak is not known yet: the main sequence of the fastest speed
         * so far is a lower bound (the profile says nothing before the peak). */
        return isfinite(a_ms) && a_ms > covered ? a_ms : covered;
    }
    double u = u_after_peak(v / V), f = synth_saccade_profile(u);
    double a_kin = covered / f;
    double sd_kin = a_kin * p->profile_spread * (1 - f) + 0.05 / f;
    double a = a_kin;
    if (isfinite(sd_ms) && sd_ms > 0) {
        double w_ms = 1 / (sd_ms * sd_ms), w_kin = 1 / (sd_kin * sd_kin);
        a = (a_ms * w_ms + a_kin * w_kin) / (w_ms + w_kin);
    }
    if (a > 60)
        a = 60;
    return a > covered ? a : covered;
}

/* c: the sample the speed is centred on. */
static void update_flight(landing_state_t *s, const landing_params_t *p, double v, int c)
{
    if (v > s->peak_dps) {
        s->peak_dps = v;
        s->peak_passed = false;
        s->falling = 0;
    } else if (v < p->peak_drop * s->peak_dps && ++s->falling >= 2) {
        s->peak_passed = true;
    }
    double cx = s->x[c] - s->x0, cy = s->y[c] - s->y0;
    double dx = s->x[0] - s->x0, dy = s->y[0] - s->y0, d = hypot(dx, dy);
    if (!(d > 0))
        return;
    s->amp_deg = estimate_amplitude(s, p, v, hypot(cx, cy));
    s->land_x = s->x0 + s->amp_deg * dx / d;
    s->land_y = s->y0 + s->amp_deg * dy / d;
    s->t_end = s->t0 + (p->duration_ms_per_deg * s->amp_deg + p->duration_ms) / 1e3;
    s->have_estimate = true;
}

/* The speed baseline: 2 samples, or as many as span 3.5 ms; 0 if there are
 * not enough samples yet. */
static int baseline(const landing_state_t *s)
{
    for (int k = 2; k < s->nsamples; k++)
        if (k + 1 >= LANDING_SAMPLES || s->t[0] - s->t[k] >= 0.0035)
            return s->t[0] > s->t[k] ? k : 0;
    return 0;
}

void landing_update(landing_state_t *s, const landing_params_t *p, double t_s, double x_deg,
                    double y_deg)
{
    for (int k = LANDING_SAMPLES - 1; k > 0; k--) {
        s->t[k] = s->t[k - 1];
        s->x[k] = s->x[k - 1];
        s->y[k] = s->y[k - 1];
    }
    s->t[0] = t_s;
    s->x[0] = x_deg;
    s->y[0] = y_deg;
    if (s->nsamples < LANDING_SAMPLES)
        s->nsamples++;
    int k = baseline(s);
    if (k == 0)
        return;
    double v = hypot(s->x[0] - s->x[k], s->y[0] - s->y[k]) / (s->t[0] - s->t[k]);
    int c = k / 2;
    if (!s->in_flight) {
        double noise = p->onset_noise * recent_median(s);
        s->threshold_dps = noise > p->onset_dps ? noise : p->onset_dps;
        if (!(v > s->threshold_dps)) {
            s->fast = 0;
            remember_speed(s, v);
            return;
        }
        /* The first fast speed was centred c samples before the previous
         * sample: the eye left from the sample before that. */
        if (++s->fast < 2 || c + 2 >= s->nsamples)
            return;
        s->in_flight = true;
        s->have_estimate = s->peak_passed = false;
        s->slow = s->falling = 0;
        s->t0 = s->t[c + 2];
        s->x0 = s->x[c + 2];
        s->y0 = s->y[c + 2];
        s->peak_dps = 0;
    }
    s->slow = v < 0.5 * s->threshold_dps ? s->slow + 1 : 0;
    if (s->slow >= 2 || t_s - s->t0 > p->max_flight_s) {
        int keep = s->nsamples;
        landing_lost(s);
        s->nsamples = keep;         /* the samples are fine, only the flight is over */
        return;
    }
    update_flight(s, p, v, c);
}

bool landing_estimate(const landing_state_t *s, double *x_deg, double *y_deg, double *t_end_s,
                      double *amp_deg)
{
    if (!s->in_flight || !s->have_estimate)
        return false;
    *x_deg = s->land_x;
    *y_deg = s->land_y;
    *t_end_s = s->t_end;
    *amp_deg = s->amp_deg;
    return true;
}
