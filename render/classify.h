/* classify.h: voxel opacity and colour from value and gradient magnitude
 * (Levoy 1988, the gaze paper's [12]: iso-value contour surfaces).
 *
 * Each contour i has an iso-value v_i, an opacity a_i, a transition thickness
 * r_i (in voxels of the finest spacing) and a colour.  At a voxel with value f
 * and gradient magnitude |g| (value units per voxel) the contour's opacity is
 *
 *     a_i(f, g) = a_i * (1 - |v_i - f| / (r_i * |g|))   if |g| > 0 and that is > 0
 *               = a_i                                    if |g| == 0 and f == v_i
 *               = 0                                      otherwise,
 *
 * i.e. opacity falls off linearly with the estimated distance |v_i - f| / |g|
 * from the iso-surface.  Several contours combine as independent layers:
 * alpha = 1 - prod(1 - a_i), colour = sum(a_i * rgb_i) / sum(a_i).  (Levoy 1988
 * instead interpolates opacity between adjacent contour values; the layered
 * combination is our simplification and keeps contours independent.)
 * A combined opacity below the preset's min_opacity is set to 0.
 *
 * A transfer function may instead be a table (the users' own, from a file:
 * classify_io.h): opacity and colour are piecewise linear in the value
 * between control points and held beyond the first and last, with no
 * gradient term: the 1D transfer functions of ParaView, VTK and VolPack.
 * Opacity is per sample at the full-resolution step (one voxel by default).
 * A function has contours or a table, never both. */
#ifndef PP5_CLASSIFY_H
#define PP5_CLASSIFY_H

#include <stdbool.h>
#include "status.h"

#define CLASSIFY_MAX_CONTOURS 4
#define CLASSIFY_MAX_POINTS 256

typedef struct {
    float value;        /* iso-value, in the volume's own units */
    float opacity;      /* 0..1 at the surface */
    float width_vox;    /* transition thickness r, voxels */
    float rgb[3];       /* material colour 0..1 */
    /* > 0: not a contour but a value ramp (the 1D transfer functions of VTK
     * and VolPack, for like-for-like peer comparisons): opacity rises
     * linearly from 0 at value - ramp_width/2 to `opacity` at
     * value + ramp_width/2 and stays there; gradient and width_vox unused. */
    float ramp_width;
} classify_contour_t;

typedef struct {
    float value, opacity;
} classify_alpha_point_t;

typedef struct {
    float value, rgb[3];
} classify_rgb_point_t;

typedef struct {
    char name[32];
    int count;
    classify_contour_t contour[CLASSIFY_MAX_CONTOURS];
    /* The table form (count == 0): points in increasing value order.  No
     * colour points: white. */
    int n_alpha, n_rgb;
    classify_alpha_point_t alpha[CLASSIFY_MAX_POINTS];
    classify_rgb_point_t rgb[CLASSIFY_MAX_POINTS];
    /* Voxels whose combined opacity is below this are made fully transparent
     * (VolPack's VP_MIN_VOXEL_OPACITY idea): faint wisps from noise would
     * otherwise fill the octree.  0 keeps every voxel. */
    float min_opacity;
} classify_tf_t;

/* Presets: "ct-skin", "ct-bone" (CThead units, 0..3272: air ~0, soft tissue
 * ~1000-1100, bone ~1600-3000), "mr" (8-bit brainsmall: background < 15, tissue
 * 40-90), "shepp-logan", "marschner-lobb", "sphere-shell" (the phantoms'
 * value ranges documented in render/phantom.c). */
pp5_status_t classify_preset(const char *name, classify_tf_t *tf);
const char *classify_preset_names(void);

/* True for the table form (n_alpha > 0). */
static inline bool classify_tf_is_table(const classify_tf_t *tf)
{
    return tf->n_alpha > 0;
}

/* Opacity (0..1) of one voxel; writes its colour (not opacity-weighted) to rgb. */
float classify_voxel(const classify_tf_t *tf, float value, float grad_mag, float rgb[3]);

#endif
