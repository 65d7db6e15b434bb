/* data_quality.c: precision, data loss and rate of a trace (data_quality.h). */
#include "data_quality.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "angles.h"

void data_quality_defaults(data_quality_params_t *p)
{
    p->min_fixation_s = 0.100;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median_of(double *v, size_t n)
{
    if (n == 0)
        return NAN;
    qsort(v, n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* RMS-S2S and STD of one fixation [a, b]; false when it has too few samples. */
static bool fixation_precision(const trace_t *t, const gaze_geometry_t *g, size_t a, size_t b,
                               double pause_s, double *rms, double *std)
{
    double sx = 0, sy = 0, sxx = 0, syy = 0, s2s = 0, px = NAN, py = NAN;
    size_t n = 0, pairs = 0;
    for (size_t i = a; i <= b; i++) {
        const gaze_sample_t *s = &t->samples[i];
        if (!(s->flags & GAZE_FLAG_VALID)) {
            px = NAN;
            continue;
        }
        double x, y;
        angles_px_to_deg(g, s->x_px, s->y_px, &x, &y);
        if (!isnan(px) && (s->t_ns - t->samples[i - 1].t_ns) / 1e9 <= pause_s) {
            s2s += (x - px) * (x - px) + (y - py) * (y - py);
            pairs++;
        }
        px = x;
        py = y;
        sx += x;
        sy += y;
        sxx += x * x;
        syy += y * y;
        n++;
    }
    if (n < 10 || pairs < 9)
        return false;
    double mx = sx / (double)n, my = sy / (double)n;
    double var = sxx / (double)n - mx * mx + syy / (double)n - my * my;
    *rms = sqrt(s2s / (double)pairs);
    *std = var > 0 ? sqrt(var) : 0;
    return true;
}

static void rates(const trace_t *t, data_quality_t *q)
{
    size_t n = t->count, m = 0;
    double *d = n > 1 ? malloc((n - 1) * sizeof *d) : NULL;
    for (size_t i = 1; d && i < n; i++)
        if (t->samples[i].t_ns > t->samples[i - 1].t_ns)
            d[m++] = (double)(t->samples[i].t_ns - t->samples[i - 1].t_ns) / 1e9;
    q->median_interval_s = d ? median_of(d, m) : NAN;
    free(d);
    q->effective_rate_hz = q->median_interval_s > 0 ? 1.0 / q->median_interval_s : NAN;
    double span = n > 1 ? (double)(t->samples[n - 1].t_ns - t->samples[0].t_ns) / 1e9 : 0;
    q->delivered_rate_hz = span > 0 ? (double)(n - 1) / span : NAN;
    q->nominal_rate_hz = t->header.sample_rate_hz;
    double expected = floor(span * q->nominal_rate_hz + 0.5) + 1;
    q->expected_samples = expected > (double)n ? (size_t)expected : n;
}

pp5_status_t data_quality_measure(const trace_t *t, const int *labels,
                                  const data_quality_params_t *p, data_quality_t *out)
{
    memset(out, 0, sizeof *out);
    gaze_geometry_t g;
    pp5_status_t st = angles_resolve(&t->header.geometry, &g);
    if (st != PP5_OK)
        return st;
    if (t->count == 0)
        return pp5_fail(PP5_E_RANGE, "data quality: the trace has no samples");
    rates(t, out);
    size_t valid = 0, n = t->count;
    for (size_t i = 0; i < n; i++)
        valid += (t->samples[i].flags & GAZE_FLAG_VALID) != 0;
    out->invalid_fraction = (double)(n - valid) / (double)n;
    out->data_loss = 1.0 - (double)valid / (double)out->expected_samples;
    double *rms = malloc(n * sizeof *rms), *std = malloc(n * sizeof *std);
    if (!rms || !std) {
        free(rms);
        free(std);
        return pp5_fail(PP5_E_NOMEM, "data quality: out of memory");
    }
    double pause = 3.0 * (out->median_interval_s > 0 ? out->median_interval_s
                                                      : 1.0 / t->header.sample_rate_hz);
    size_t k = 0;
    for (size_t i = 0; i < n; i++) {
        if (labels[i] != GAZE_LABEL_FIXATION)
            continue;
        size_t b = i;
        while (b + 1 < n && labels[b + 1] == GAZE_LABEL_FIXATION)
            b++;
        double len = (double)(t->samples[b].t_ns - t->samples[i].t_ns) / 1e9;
        if (len >= p->min_fixation_s &&
            fixation_precision(t, &g, i, b, pause, &rms[k], &std[k]))
            k++;
        i = b;
    }
    out->fixations_used = k;
    out->std_deg = median_of(std, k);
    out->rms_s2s_deg = median_of(rms, k);
    free(rms);
    free(std);
    return PP5_OK;
}
