/* quality.h: image-quality figures for trading sweet-spot size against cost.
 *
 * PSNR (dB) between a test image T and a reference R (8-bit, same size,
 * channels c, N pixels):
 *     MSE  = sum over pixels and channels of (T - R)^2 / (N c)
 *     PSNR = 10 log10(255^2 / MSE)            (infinite when MSE = 0)
 *
 * Acuity-weighted error: each pixel's squared error is weighted by the
 * relative linear retinal acuity at its eccentricity from the gaze point,
 * taken from the same display model that drives 2DLevel (gaze2d.h):
 *     w(x, y) = sqrt(rho(e(x, y)))   (1 inside the fovea, 1/4 in the periphery
 *                                     with the paper's 1 ray per 16 pixels)
 *     AW-MSE  = sum w (T - R)^2 / (c sum w),   AW-PSNR = 10 log10(255^2 / AW-MSE)
 * so an error the eye can resolve counts up to four times more than the same
 * error in the periphery.  (rho is the target rays per pixel; its square
 * root is rays per pixel along a line, i.e. resolvable detail.) */
#ifndef PP5_QUALITY_H
#define PP5_QUALITY_H

#include "gaze2d.h"
#include "png_io.h"

typedef struct {
    double mse, psnr_db;              /* psnr_db = INFINITY when identical */
    double aw_mse, aw_psnr_db;
    double max_abs;                   /* largest channel difference */
} quality_t;

pp5_status_t quality_compare(const image8_t *test, const image8_t *ref, const gaze_model_t *g,
                             double gaze_x, double gaze_y, quality_t *q);
double quality_psnr_from_mse(double mse);

#endif
