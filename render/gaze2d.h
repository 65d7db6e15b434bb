/* gaze2d.h: the 2DLevel function (gaze paper §3, §4, §6) and the partially
 * populated 2D mip map it drives (RenderPixel).
 *
 * Acuity model.  The display geometry gives inches per pixel: the image's
 * horizontal line subtends `image_subtense_deg` at `view_distance_in`, so it is
 * 2 D tan(subtense/2) inches wide (paper §6: 37 degrees at 20 inches = 13.4").
 * A pixel at distance r pixels from the gaze point has eccentricity
 * e = atan(r * inches_per_px / D).  The paper's angles are circle diameters
 * ("4.2 inches in diameter (12 degrees of arc)"), so full resolution holds for
 * e <= 6 degrees and the periphery starts at e = 10 degrees.  Target
 * resolution, in rays per pixel:
 *
 *     rho(e) = 1                                         e <= e_full
 *            = rho_min + (1 - rho_min) exp(-(e - e_full)^2 / (2 sigma^2))
 *                                                        e_full < e < e_edge
 *            = rho_min (1/16)                            e >= e_edge
 *
 * and 2DLevel = log4(1 / rho) in [0, 2] (level m casts one ray per 4^m
 * pixels).  The paper says only "a Gaussian was used"; sigma is derived from
 * its figure-5 description that level 0 is populated out to a circle "roughly
 * 5 inches in diameter", i.e. 2DLevel = 1 at a 2.5" radius:
 * sigma = (e_5 - e_full) / sqrt(2 ln((1 - rho_min) / (1/4 - rho_min))).
 * With the defaults the level-1 span is the annulus between the 4.2" and the
 * 7.0" circles and level 2 lies beyond 5", the spans of figure 5.  When a
 * user geometry puts the 5" circle outside the falloff annulus, sigma is a
 * third of the annulus width instead.
 *
 * 2D mip map.  Level m holds rays cast through the centres of pixels
 * (i 2^m, j 2^m): texel (i, j) lies at image point (i 2^m + 0.5, j 2^m + 0.5).
 * RenderPixel(x, y) bilinearly interpolates the four texels around
 * (x / 2^m, y / 2^m) (the corners of the enclosing level-m mask) in the floor
 * and ceil levels of 2DLevel and blends them linearly.  A flag per texel
 * records that its ray was cast, so shared corners are traced once; corners
 * whose bilinear weight is exactly zero are not cast (they cannot change the
 * pixel).  Flags and colours may be kept between frames (progressive
 * refinement, paper §7). */
#ifndef PP5_GAZE2D_H
#define PP5_GAZE2D_H

#include <stdbool.h>
#include <stdint.h>
#include <math.h>
#include "status.h"

#define MIP2D_MAX_LEVELS 8

typedef struct {
    double monitor_diag_in;      /* 19 (paper §2, §6) */
    double monitor_aspect;       /* width / height: 4/3 for a 1990 television monitor */
    double view_distance_in;     /* 20 */
    double image_subtense_deg;   /* 37; 0 = the image spans the monitor's width */
    double full_res_diameter_deg;/* 12: one ray per pixel inside */
    double periphery_diameter_deg; /* 20: rho_min outside */
    double periphery_rays_per_px;  /* 1/16 */
    double span1_diameter_in;    /* 5: where level 0 stops (sets sigma), see above */
    double sigma_deg;            /* 0 = derived from span1_diameter_in */
} gaze_display_t;

typedef struct {
    gaze_display_t display;
    int width, height;
    double inches_per_px;
    double e_full_deg, e_edge_deg, sigma_deg, rho_min;
    int max_level;               /* log4(1 / rho_min), rounded up */
    /* Radii (px) inside/outside which 2DLevel is exactly 0 / max_level, with a
     * 1e-9 relative margin: lets gaze_level skip the transcendental functions
     * for most pixels without changing any result. */
    double r_zero_px, r_max_px;
    float level_edge;            /* 2DLevel beyond the periphery circle: log4(1 / rho_min) */
    bool fits_monitor;           /* image fits on the stated monitor */
} gaze_model_t;

void gaze_display_defaults(gaze_display_t *d);
pp5_status_t gaze_model_init(gaze_model_t *g, const gaze_display_t *d, int width, int height);
/* Eccentricity (degrees) of a point r pixels from the gaze point. */
double gaze_eccentricity_deg(const gaze_model_t *g, double r_px);
/* Pixels from the gaze point at eccentricity e degrees (inverse of the above). */
double gaze_radius_px(const gaze_model_t *g, double e_deg);
/* Target resolution rho (rays per pixel, 1 .. rho_min) at eccentricity e. */
double gaze_target_rays_per_px(const gaze_model_t *g, double e_deg);
/* 2DLevel at r pixels from the gaze point (0 .. max_level). */
float gaze_level(const gaze_model_t *g, double r_px);

/* 2DLevel by the paper's two lookup tables (seed 004 §4: "a 2D lookup table
 * indexed by X and Y offset" gives the distance to the gaze point, "a 1D
 * lookup table indexed by distance" the level).  Distances are stored in
 * 1/GAZE_TABLE_STEPS pixel; offsets are integer, so the gaze point is taken
 * at the nearest pixel and the levels differ slightly from gaze_level's.  The
 * machine's GP program builds the same tables from the same formula
 * (firmware/common/vr_kernels.h), so render/ with tables compares like for
 * like with the machine. */
#define GAZE_TABLE_STEPS 4
typedef struct {
    int w, h;                    /* offsets |dx| < w, |dy| < h */
    uint16_t *dist;              /* round(sqrt(dx^2 + dy^2) * STEPS), rows of dy */
    float *level;                /* level[k] = gaze_level(k / STEPS), k < n */
    int n;
    float level_far;             /* past the 1D table: the periphery level */
} gaze_level_tables_t;

pp5_status_t gaze_level_tables_init(gaze_level_tables_t *t, const gaze_model_t *g, int w, int h);
void gaze_level_tables_free(gaze_level_tables_t *t);
/* The tables' 2DLevel at integer offset (dx, dy) from the gaze pixel, the
 * distance divided by `scale` (progressive refinement's growing sweet spot). */
static inline float gaze_level_tabled(const gaze_level_tables_t *t, int dx, int dy, double scale)
{
    dx = dx < 0 ? -dx : dx;
    dy = dy < 0 ? -dy : dy;
    /* Offsets past the table (a gaze point off the image): the same
     * rounded distance, computed. */
    double d = dx < t->w && dy < t->h ? (double)t->dist[(size_t)dy * (size_t)t->w + (size_t)dx]
                                      : floor(sqrt((double)dx * dx + (double)dy * dy) *
                                              GAZE_TABLE_STEPS + 0.5);
    if (d >= 4294967295.0)
        return t->level_far;
    unsigned k = (unsigned)d;
    if (scale != 1.0)
        k = (unsigned)((double)k / scale + 0.5);
    return k < (unsigned)t->n ? t->level[k] : t->level_far;
}
/* One row of levels by the tables (the gaze rounded to the nearest pixel). */
void gaze_level_row_tabled(const gaze_level_tables_t *t, int y, int width, double gaze_x,
                           double gaze_y, double scale, float *levels);

typedef struct {
    int levels, width, height;
    int w[MIP2D_MAX_LEVELS], h[MIP2D_MAX_LEVELS];
    float *rgb[MIP2D_MAX_LEVELS];     /* 3 floats per texel, and 1 spare at the end */
    uint8_t *cast[MIP2D_MAX_LEVELS];  /* 1 = ray cast, colour valid (the paper's F) */
    uint8_t *need[MIP2D_MAX_LEVELS];  /* scratch: wanted by this frame */
} mip2d_t;

pp5_status_t mip2d_init(mip2d_t *m, int width, int height, int levels);
void mip2d_free(mip2d_t *m);
void mip2d_clear(mip2d_t *m);          /* forget every cast ray */
void mip2d_clear_need(mip2d_t *m);

/* Image point through which texel (i, j) of level m casts its ray. */
static inline void mip2d_texel_point(int m, int i, int j, float *px, float *py)
{
    *px = (float)(i << m) + 0.5f;
    *py = (float)(j << m) + 0.5f;
}

/* Marks the texels pixel (x, y) needs at 2D level `level` (floor and ceil
 * levels, corners with non-zero weight). */
void mip2d_mark_pixel(mip2d_t *m, int x, int y, float level);
/* mip2d_mark_pixel for pixels (0..width-1, y) with levels[x]; returns false
 * if any level is above 0 (so true means the row is at full resolution). */
bool mip2d_mark_row(mip2d_t *m, int y, const float *levels, int width);
/* RenderPixel's interpolation: colour of pixel (x, y) at `level` from cast
 * texels (all needed texels must have been cast). */
void mip2d_pixel(const mip2d_t *m, int x, int y, float level, float rgb[3]);
/* Number of texels with the flag set, over all levels. */
uint64_t mip2d_count_cast(const mip2d_t *m);

#endif
