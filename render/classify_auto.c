/* classify_auto.c: the histogram-driven default transfer function (classify_auto.h). */
#include "classify_auto.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static void contour(classify_contour_t *c, double value, float opacity, float r, float g, float b)
{
    memset(c, 0, sizeof *c);
    c->value = (float)value;
    c->opacity = opacity;
    c->width_vox = 2.0f;          /* as the presets: a surface about two voxels thick */
    c->rgb[0] = r;
    c->rgb[1] = g;
    c->rgb[2] = b;
}

pp5_status_t classify_tf_auto(const volume_histogram_t *h, classify_tf_t *tf,
                              classify_auto_info_t *info)
{
    memset(info, 0, sizeof *info);
    info->background_max = h->background_max;
    info->background_peak = h->background_peak;
    info->n_background = h->n_background;
    info->n_foreground = h->n_foreground;
    info->window_lo = h->fg_p1;
    info->window_hi = h->fg_p99;
    info->median = h->fg_p50;
    if (h->n_foreground == 0 || !isfinite(h->fg_p50))
        return pp5_fail(PP5_E_RANGE, "every voxel lies in the background (values %g .. %g): no "
                        "object to show; give a transfer function with --tf", h->min, h->max);
    memset(tf, 0, sizeof *tf);
    snprintf(tf->name, sizeof tf->name, "auto");
    double outer = 0.5 * (h->background_peak + h->fg_p50);
    double dense = 0.5 * (h->fg_p50 + h->fg_p99);
    double window = h->fg_p99 - h->fg_p1;
    bool two = dense - h->fg_p50 > 0.02 * window && window > 0;
    contour(&tf->contour[0], outer, two ? 0.3f : 0.8f, 0.92f, 0.80f, 0.70f);
    tf->count = 1;
    if (two) {
        contour(&tf->contour[1], dense, 0.85f, 1.0f, 1.0f, 0.95f);
        tf->count = 2;
    }
    /* As the real-data presets: faint noise voxels would fill the octree. */
    tf->min_opacity = 0.02f;
    return PP5_OK;
}

void classify_auto_describe(const classify_auto_info_t *info, char *buf, size_t n)
{
    double total = (double)(info->n_background + info->n_foreground);
    snprintf(buf, n, "chosen from the histogram: background <= %.4g (%.1f %% of the voxels, peak "
             "at %.4g); the other voxels' 1st-99th percentile window %.4g .. %.4g, median %.4g",
             info->background_max, total > 0 ? 100.0 * (double)info->n_background / total : 0.0,
             info->background_peak, info->window_lo, info->window_hi, info->median);
}
