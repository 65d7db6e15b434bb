/* poly_phong_pp.h: the PP stream that Phong-shades a region once its triangles are in (deferred shading in the PPs).
 *
 * Every covered pixel holds its interpolated normal N (three signed 16-bit
 * fields, 2^14 = 1) and whether its triangle was seen from behind (the
 * normal already reversed then, as mesh_raster lights a back face).  The
 * stream computes, per pixel and all 16384 at once:
 *   D = N.L (2^28 = 1; constants round(L 2^14), MULI by |L| and add or
 *       subtract), S = |N|^2 (2^14 = 1, clamped to >= 0.25 + 2^-14),
 *   r = 1/|N| by three Newton steps r <- r (3/2 - S r^2 / 2) from the
 *       tangent r0 = 3/2 - S/2 (below 1/sqrt(S), so r rises to it and stays
 *       below 2),
 *   c = max(0, D) r (2^28 = 1, kept as 2^14 = 1),
 *   each channel min(255, floor(c Kd + Ka)) with Kd = round(rgb diffuse 2^8),
 *       Ka = round((rgb ambient + 0.5) 2^22): the front colour where the back
 *       bit is clear, the back colour where it is set; or, with colours per
 *       pixel (each triangle wrote its side's colour into R, G, B), each
 *       channel min(255, floor(I ch + 0.5)) with I = c diffuse + ambient.
 * Fields: common/poly_config.h (POLY_PP_*). */
#ifndef PP5_POLY_PHONG_PP_H
#define PP5_POLY_PHONG_PP_H

#include <stdbool.h>

#include "poly_config.h"
#include "pp_encode.h"

/* Appends the shading stream for light `light` (camera space, unit). */
void poly_phong_stream(pp_stream_t *s, const float light[3], float ambient, float diffuse,
                       const int32_t front_rgb[3], const int32_t back_rgb[3], bool per_pixel);

#endif
