/* volume_histogram.h: a volume's value histogram and what a transfer function needs from it: the background, percentiles, and the window the object's values fill.
 *
 * The histogram has VOLUME_HISTOGRAM_BINS equal bins over [min, max];
 * percentiles interpolate linearly inside a bin, so they are exact to a
 * fraction of (max - min) / VOLUME_HISTOGRAM_BINS.
 *
 * Background: scanned volumes and phantoms hold a large mass of "nothing"
 * (air, zero padding) at the low end.  When the tallest bin lies in the
 * lowest eighth of the range, the background is that peak and the falling
 * side above it, up to the first bin (of the 5-bin moving average) that no
 * longer falls, at most a quarter of the range; otherwise it is only the
 * voxels at the minimum.  The foreground is every voxel above it, and its
 * window is its 1st to 99th percentile. */
#ifndef PP5_VOLUME_HISTOGRAM_H
#define PP5_VOLUME_HISTOGRAM_H

#include <stdint.h>
#include <stdio.h>
#include "volume.h"

#define VOLUME_HISTOGRAM_BINS 4096

typedef struct {
    double min, max;
    uint64_t count;
    uint64_t bins[VOLUME_HISTOGRAM_BINS];
    double background_max;        /* values <= this are background */
    int first_foreground_bin;     /* bins from here on are the foreground */
    double background_peak;       /* centre of the tallest background bin */
    uint64_t n_background, n_foreground;
    double p1, p50, p99;          /* percentiles of all voxels */
    double fg_p1, fg_p50, fg_p99; /* percentiles of the foreground (NaN when empty) */
    double mean;
} volume_histogram_t;

/* Fills *h from the volume (every voxel; deterministic). */
void volume_histogram_compute(const volume_t *v, volume_histogram_t *h);
/* The value below which a fraction q (0..1) of the voxels lie; from_value
 * limits the count to voxels above it (the foreground), or -INFINITY. */
double volume_histogram_quantile(const volume_histogram_t *h, double q, double from_value);
/* A summary in a few lines: range, background, percentiles and a coarse
 * bar chart of the foreground, each line starting with `indent`. */
void volume_histogram_print(const volume_histogram_t *h, const char *indent, FILE *out);

#endif
