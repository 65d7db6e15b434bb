/* volume_histogram.c: the value histogram, its background and percentiles (volume_histogram.h). */
#include "volume_histogram.h"

#include <math.h>
#include <string.h>

static double bin_width(const volume_histogram_t *h)
{
    return (h->max - h->min) / VOLUME_HISTOGRAM_BINS;
}

static int bin_of(const volume_histogram_t *h, double v)
{
    if (!(h->max > h->min))
        return 0;
    double f = (v - h->min) / (h->max - h->min) * VOLUME_HISTOGRAM_BINS;
    int b = f <= 0 ? 0 : (int)f;
    return b >= VOLUME_HISTOGRAM_BINS ? VOLUME_HISTOGRAM_BINS - 1 : b;
}

/* Mean of the bins within 2 of i (fewer at the ends). */
static double smoothed(const volume_histogram_t *h, int i)
{
    double sum = 0;
    int n = 0;
    for (int k = i - 2; k <= i + 2; k++)
        if (k >= 0 && k < VOLUME_HISTOGRAM_BINS) {
            sum += (double)h->bins[k];
            n++;
        }
    return sum / n;
}

/* The last bin of the background (see the header), or -1 for none. */
static int background_end(const volume_histogram_t *h)
{
    int peak = 0;
    for (int i = 1; i < VOLUME_HISTOGRAM_BINS; i++)
        if (h->bins[i] > h->bins[peak])
            peak = i;
    if (peak >= VOLUME_HISTOGRAM_BINS / 8)
        return 0;
    int end = peak, limit = VOLUME_HISTOGRAM_BINS / 4;
    while (end + 1 < limit && smoothed(h, end + 1) < smoothed(h, end))
        end++;
    return end;
}

/* The value below which a fraction q of the voxels in bins first.. lie,
 * linear inside the bin that holds it. */
static double quantile_from_bin(const volume_histogram_t *h, double q, int first)
{
    uint64_t total = 0;
    for (int i = first; i < VOLUME_HISTOGRAM_BINS; i++)
        total += h->bins[i];
    if (total == 0)
        return NAN;
    double want = q * (double)total, seen = 0;
    double w = bin_width(h);
    for (int i = first; i < VOLUME_HISTOGRAM_BINS; i++) {
        double c = (double)h->bins[i];
        if (c > 0 && seen + c >= want) {
            double f = (want - seen) / c;
            double v = h->min + (i + f) * w;
            return v > h->max ? h->max : v;
        }
        seen += c;
    }
    return h->max;
}

double volume_histogram_quantile(const volume_histogram_t *h, double q, double from_value)
{
    int first = 0;
    if (from_value == h->background_max)
        first = h->first_foreground_bin;
    else if (isfinite(from_value))
        first = bin_of(h, from_value) + 1;   /* whole bins above the one holding it */
    return first >= VOLUME_HISTOGRAM_BINS ? NAN : quantile_from_bin(h, q, first);
}

void volume_histogram_compute(const volume_t *v, volume_histogram_t *h)
{
    memset(h, 0, sizeof *h);
    h->min = v->min_value;
    h->max = v->max_value;
    size_t n = volume_voxel_count(v);
    double sum = 0;
    for (size_t i = 0; i < n; i++) {
        h->bins[bin_of(h, v->data[i])]++;
        sum += v->data[i];
    }
    h->count = n;
    h->mean = n ? sum / (double)n : NAN;
    int end = background_end(h);
    h->first_foreground_bin = end + 1;
    int peak = 0;
    for (int i = 1; i <= end; i++)
        peak = h->bins[i] > h->bins[peak] ? i : peak;
    h->background_peak = h->min + (peak + 0.5) * bin_width(h);
    h->background_max = h->max > h->min ? h->min + (end + 1) * bin_width(h) : h->max;
    for (int i = 0; i <= end; i++)
        h->n_background += h->bins[i];
    h->n_foreground = h->count - h->n_background;
    h->p1 = quantile_from_bin(h, 0.01, 0);
    h->p50 = quantile_from_bin(h, 0.50, 0);
    h->p99 = quantile_from_bin(h, 0.99, 0);
    h->fg_p1 = quantile_from_bin(h, 0.01, end + 1);
    h->fg_p50 = quantile_from_bin(h, 0.50, end + 1);
    h->fg_p99 = quantile_from_bin(h, 0.99, end + 1);
}

void volume_histogram_print(const volume_histogram_t *h, const char *indent, FILE *out)
{
    double pct = h->count ? 100.0 / (double)h->count : 0;
    fprintf(out, "%svalues:      %g .. %g, mean %.4g, over %llu voxels\n", indent, h->min, h->max,
            h->mean, (unsigned long long)h->count);
    fprintf(out, "%spercentiles: 1%% %.4g, 50%% %.4g, 99%% %.4g\n", indent, h->p1, h->p50, h->p99);
    fprintf(out, "%sbackground:  values <= %.4g: %llu voxels (%.1f %%)\n", indent, h->background_max,
            (unsigned long long)h->n_background, pct * (double)h->n_background);
    if (h->n_foreground == 0) {
        fprintf(out, "%sforeground:  none (every voxel is background)\n", indent);
        return;
    }
    fprintf(out, "%sforeground:  %llu voxels (%.1f %%); 1%% %.4g, 50%% %.4g, 99%% %.4g\n", indent,
            (unsigned long long)h->n_foreground, pct * (double)h->n_foreground, h->fg_p1,
            h->fg_p50, h->fg_p99);
    /* 16 rows over the foreground's range, bars scaled to the fullest. */
    enum { ROWS = 16, BAR = 40 };
    uint64_t row[ROWS] = {0}, most = 0;
    int first = h->first_foreground_bin;
    int span = VOLUME_HISTOGRAM_BINS - first;
    for (int i = first; i < VOLUME_HISTOGRAM_BINS; i++)
        row[(int64_t)(i - first) * ROWS / span] += h->bins[i];
    for (int r = 0; r < ROWS; r++)
        most = row[r] > most ? row[r] : most;
    double lo = h->min + first * bin_width(h), step = (h->max - lo) / ROWS;
    for (int r = 0; r < ROWS; r++) {
        int len = most ? (int)((double)row[r] * BAR / (double)most + 0.5) : 0;
        fprintf(out, "%s  %10.4g .. %-10.4g %-*.*s %5.1f %%\n", indent, lo + r * step,
                lo + (r + 1) * step, BAR, len, "########################################",
                pct * (double)row[r]);
    }
}
