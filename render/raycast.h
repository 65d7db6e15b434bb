/* raycast.h: cameras and the per-ray TraceRay of the gaze paper §4.
 *
 * Coordinates: "object space" has the volume's axes with one unit per
 * smallest voxel spacing; voxel (i,j,k) sits at (i*sx, j*sy, k*sz) where
 * (sx,sy,sz) = mip3d_t.spacing.  Images have pixel (x,y) covering
 * [x, x+1) x [y, y+1), row 0 at the top; image point (px,py) is continuous.
 *
 * One ray = raycast_trace(): clip to the volume, march front to back with
 * the sample spacing tied to the ray's 2D mip level (spacing = step * 2^level
 * object units: 1 ray per 2^level pixels <-> 1 sample per 2^level voxels,
 * paper §6), draw each sample from the 3D mip map at
 * 3DLevel = log2(mask volume in voxels) / 3 with the mask's extent
 * proportional to the sample spacing, the constant chosen so that the
 * full-resolution spacing `sample_step` is a one-voxel mask:
 * 3DLevel = log2(spacing / sample_step).  This gives the paper's pairing of
 * "1 ray per 16 pixels" with "1 sample per 64 voxels" (level 2 in both) and
 * integer levels (one trilinear lookup) under parallel projection; the mip
 * map is built in voxel-index space, so anisotropic voxels stay anisotropic
 * at every level.  Perspective spacing grows with distance, so its levels
 * are fractional and blend two levels.  Then shade the viewpoint-dependent part, and
 * composite with early ray termination.  Opacity is corrected for the sample
 * spacing (a' = 1 - (1 - a)^spacing), which the paper does not mention: without
 * it coarse rays would come out more transparent than fine ones. */
#ifndef PP5_RAYCAST_H
#define PP5_RAYCAST_H

#include <stdbool.h>
#include <stdint.h>
#include "mip3d.h"
#include "octree.h"
#include "shade.h"

typedef enum { PROJECTION_PARALLEL, PROJECTION_PERSPECTIVE } projection_t;

typedef struct {
    projection_t projection;
    /* Camera orientation: basis = Rz(rot_z) * Rx(rot_x) * Ry(rot_y) applied to
     * (right, down, forward) = (x, y, z).  rot_y orbits about the image's
     * vertical axis; 0,0,0 looks along +z with +x right and +y down. */
    float rot_x_deg, rot_y_deg, rot_z_deg;
    float zoom;               /* 1: the largest object-space extent spans the smaller image side */
    float eye_distance;       /* perspective: eye to volume centre, in volume bounding radii */
    float sample_step;        /* object-space units between samples of a level-0 ray */
    float early_termination;  /* stop a ray when its opacity reaches this */
    bool use_octree;
    /* The length (object units) over which a voxel's classified opacity
     * applies (1 = one voxel): a sample standing for `spacing` units gets
     * 1 - (1 - a)^(spacing / opacity_unit).  The scaling benchmark sets it
     * so that a resampled volume is as opaque per millimetre as the one it
     * came from; the command line and the machine keep 1. */
    float opacity_unit;
} view_params_t;

void view_defaults(view_params_t *v);
const char *projection_name(projection_t p);

typedef struct {
    int width, height;
    projection_t projection;
    float right[3], down[3], forward[3]; /* object-space unit vectors */
    float centre[3];                     /* object-space volume centre */
    float pixel_size;                    /* object units per pixel (plane through the centre) */
    float eye[3];                        /* perspective eye position */
    float eye_distance;                  /* object units */
    float radius;                        /* bounding-sphere radius of the volume */
    float box_hi[3];                     /* sampled region [0, box_hi] in object space */
    float inv_spacing[3];                /* object units -> level-0 voxel coordinates */
} camera_t;

void camera_setup(camera_t *c, const view_params_t *v, const mip3d_t *m, int width, int height);
/* The camera axes (object-space unit vectors) for the view's angles. */
void view_basis(const view_params_t *v, float right[3], float down[3], float forward[3]);
/* Ray through image point (px, py): origin and unit direction in object space. */
void camera_ray(const camera_t *c, float px, float py, float origin[3], float dir[3]);

typedef struct {
    uint64_t rays;
    uint64_t samples;          /* 3D samples drawn (each may blend two mip levels) */
    /* Sample positions the octree let the ray pass without drawing: those a
     * ray without skipping would visit (all in the volume, or up to early
     * termination) minus those drawn, so samples + samples_skipped with the
     * octree on equals samples with it off.  In brick order (MIP and DEMIP
     * in the renderer, blend_bricks.h) a MIP ray has no early stop: its
     * whole window is the base. */
    uint64_t samples_skipped;
    /* MIP and DEMIP rays (blend_trace.h) first try a threshold guessed from
     * their neighbour; when it was too high the ray is traced again and the
     * first attempt's samples are counted here as well as in `samples`, so
     * samples - samples_retraced + samples_skipped equals the samples of a
     * ray without skipping.  Always 0 for compositing and in brick order. */
    uint64_t samples_retraced;
} raycast_counts_t;

#define RAYCAST_LUT_LEVELS 8
#define RAYCAST_LUT_SIZE 1024

typedef struct {
    const mip3d_t *mip;
    const octree_t *octree;    /* NULL: no empty-space skipping */
    const camera_t *camera;
    const shade_params_t *shade;
    float sample_step;
    float level3d_offset;      /* log2(sample_step): 3DLevel = log2(spacing) - this */
    float early_termination;
    float opacity_unit;        /* view_params_t's (> 0) */
    /* Parallel rays walk eight positions at a time with AVX2 (set by
     * raycast_ctx_init when the host has it; false: the portable walk, the
     * same samples either way). */
    bool simd_walk;
    float light_obj[3];        /* light direction in object space for this frame */
    /* Parallel projection: opacity correction 1 - (1 - a)^spacing tabulated
     * per 2D level (spacing = step * 2^level), linear between entries. */
    float alpha_lut[RAYCAST_LUT_LEVELS][RAYCAST_LUT_SIZE + 1];
    /* Perspective projection: the spacings where the floor 3D level reaches
     * n (persp_lo) and up to which it is exactly n (persp_eq_hi), so that
     * positions need no log2f (raycast_perspective.c); persp_tables false:
     * not usable on this host's libm. */
    float persp_lo[MIP3D_MAX_LEVELS + 1], persp_eq_hi[MIP3D_MAX_LEVELS];
    bool persp_tables;
} raycast_ctx_t;

void raycast_ctx_init(raycast_ctx_t *r, const mip3d_t *m, const octree_t *o, const camera_t *c,
                      const shade_params_t *s, const view_params_t *v);

/* TraceRay: colour (0..1, black background) of the ray through image point
 * (px, py) cast for 2D mip level `level2d`. */
void raycast_trace(const raycast_ctx_t *r, float px, float py, int level2d, float rgb[3],
                   raycast_counts_t *counts);

/* The straightforward tracer the fast paths must match bit for bit: one
 * octree query per visited sample position (octree.h), as described above.
 * raycast_trace uses a faster traversal under parallel projection (see
 * ARCHITECTURE.md, "Speed") that draws exactly the same samples; this one is
 * kept as the yardstick for the tests. */
void raycast_trace_reference(const raycast_ctx_t *r, float px, float py, int level2d,
                             float rgb[3], raycast_counts_t *counts);

/* The same for `count` (<= RAYCAST_BATCH) rays of one 2D level, advanced in
 * turns so that their latency chains overlap; each result is bit-identical to
 * raycast_trace's. */
#define RAYCAST_BATCH 8
void raycast_trace_batch(const raycast_ctx_t *r, int count, const float *px, const float *py,
                         int level2d, float (*rgb)[3], raycast_counts_t *counts);

/* The same for any number of rays of one 2D level (a texel row): parallel
 * rays go RAYCAST_CHUNK at a time through the fast tracer, whose lanes take
 * a new ray as soon as one ends; each result is still raycast_trace's. */
#define RAYCAST_CHUNK 64
void raycast_trace_rays(const raycast_ctx_t *r, int count, const float *px, const float *py,
                        int level2d, float (*rgb)[3], raycast_counts_t *counts);

/* Front-to-back compositing of one opacity-weighted sample (c = a*colour). */
static inline void raycast_composite(float acc_rgb[3], float *acc_a, const float c[3], float a)
{
    float t = 1.0f - *acc_a;
    acc_rgb[0] += t * c[0];
    acc_rgb[1] += t * c[1];
    acc_rgb[2] += t * c[2];
    *acc_a += t * a;
}

#endif
