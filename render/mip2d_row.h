/* mip2d_row.h: row-at-a-time fast paths of the gaze renderer's per-pixel
 * work (2DLevel, texel marking, RenderPixel), each bit-identical to the
 * straightforward per-pixel reference kept beside it (tests/test_pixel_*.c
 * compares them byte for byte). */
#ifndef PP5_MIP2D_ROW_H
#define PP5_MIP2D_ROW_H

#include <stdbool.h>
#include <stdint.h>
#include "gaze2d.h"

/* 2DLevel of pixels (0..width-1, y) for a gaze at (gaze_x, gaze_y) with the
 * sweet spot scaled by `scale` (progressive refinement; 1 = none).  The
 * reference evaluates gaze_level(sqrt(dx^2 + dy^2) / scale) per pixel. */
void gaze_level_row(const gaze_model_t *g, int y, int width, double gaze_x, double gaze_y,
                    double scale, float *levels);
void gaze_level_row_reference(const gaze_model_t *g, int y, int width, double gaze_x,
                              double gaze_y, double scale, float *levels);

/* Same flags and result as mip2d_mark_row (the reference), but one span
 * write per run of equal levels instead of one call per pixel. */
bool mip2d_mark_row_runs(mip2d_t *m, int y, const float *levels, int width);

/* RenderPixel for pixels (0..width-1, y) into 8-bit RGB (render_to_u8).
 * The reference calls mip2d_pixel per pixel. */
void mip2d_render_row(const mip2d_t *m, int y, const float *levels, int width, uint8_t *rgb);
void mip2d_render_row_reference(const mip2d_t *m, int y, const float *levels, int width,
                                uint8_t *rgb);

#endif
