/* quality.c: PSNR and the acuity-weighted error (formulas in quality.h). */
#include "quality.h"

#include <math.h>
#include <stdlib.h>

double quality_psnr_from_mse(double mse)
{
    return mse > 0.0 ? 10.0 * log10(255.0 * 255.0 / mse) : INFINITY;
}

pp5_status_t quality_compare(const image8_t *test, const image8_t *ref, const gaze_model_t *g,
                             double gaze_x, double gaze_y, quality_t *q)
{
    if (test->width != ref->width || test->height != ref->height ||
        test->channels != ref->channels)
        return pp5_fail(PP5_E_RANGE, "quality: images differ in size (%dx%dx%d vs %dx%dx%d)",
                        test->width, test->height, test->channels, ref->width, ref->height,
                        ref->channels);
    int c = test->channels;
    double sum = 0.0, wsum = 0.0, wsq = 0.0, max_abs = 0.0;
    for (int y = 0; y < test->height; y++) {
        for (int x = 0; x < test->width; x++) {
            double e2 = 0.0;
            size_t off = ((size_t)y * test->width + x) * c;
            for (int k = 0; k < c; k++) {
                double d = (double)test->pixels[off + k] - (double)ref->pixels[off + k];
                e2 += d * d;
                if (fabs(d) > max_abs)
                    max_abs = fabs(d);
            }
            double dx = x - gaze_x, dy = y - gaze_y;
            double w = sqrt(gaze_target_rays_per_px(g, gaze_eccentricity_deg(g, sqrt(dx * dx +
                                                                                 dy * dy))));
            sum += e2;
            wsq += w * e2;
            wsum += w;
        }
    }
    double n = (double)test->width * test->height * c;
    q->mse = sum / n;
    q->psnr_db = quality_psnr_from_mse(q->mse);
    q->aw_mse = wsum > 0.0 ? wsq / (wsum * c) : 0.0;
    q->aw_psnr_db = quality_psnr_from_mse(q->aw_mse);
    q->max_abs = max_abs;
    return PP5_OK;
}
