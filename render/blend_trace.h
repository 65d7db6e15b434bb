/* blend_trace.h: TraceRay for MIP, DEMIP and MIDA (blend.h): where a ray
 * samples the scalar pyramid (scalar_pyramid.h) and which samples it draws.
 * What a ray does with each sample is blend_ray.h's.
 *
 * Geometry is the compositing tracer's (raycast.h): the same camera rays,
 * clipped to the same box, sampled at t0 + k * step * 2^level (parallel) or
 * geometrically growing spacing (perspective), each sample read at 3DLevel =
 * log2(spacing / step) from the pyramid.  A gaze-directed frame casts its
 * level-m texels this way, so coarse MIP rays read level m of the max
 * pyramid.
 *
 * Two tracers draw the same samples' worth of result:
 *   blend_trace_reference: every position of the ray (the yardstick);
 *   blend_trace_batch: under parallel projection with skipping on
 *     (view.use_octree), passes whole nodes whose bound cannot change the
 *     ray (scalar_pyramid.h) and leaves a ray at once when nothing further
 *     can change it; bit-identical colours to the reference, and samples +
 *     samples_skipped equal the reference's samples (tested).  Otherwise it
 *     runs the reference.
 * The rays of a batch guess their MIP/DEMIP threshold from the previous
 * batch of the same texel row (BLEND_GUESS_FRACTION of its last ray's
 * maximum): neighbouring texels see nearly the same maximum, and a
 * threshold known from the start lets a ray pass everything dimmer, in
 * front of the maximum too.  Batches of a row are traced in a fixed order,
 * so counts stay deterministic.
 * DEMIP counts one ray per texel; its samples include both passes.
 * The renderer casts MIP and DEMIP under parallel projection in brick
 * order instead (blend_bricks.h: same images, fewer steps); this tracer
 * stays MIDA's and the yardstick's neighbour. */
#ifndef PP5_BLEND_TRACE_H
#define PP5_BLEND_TRACE_H

#include <stdbool.h>
#include "blend_ray.h"
#include "raycast.h"
#include "scalar_pyramid.h"

typedef struct {
    const scalar_pyramid_t *pyr;
    const camera_t *camera;
    blend_frame_t frame;
    float sample_step, level3d_offset;
    bool skipping;
} blend_ctx_t;

void blend_ctx_init(blend_ctx_t *c, const scalar_pyramid_t *p, const camera_t *cam,
                    const view_params_t *v, const blend_settings_t *b);

/* One ray's geometry: object-space o + t d, level-0 voxel coordinates
 * ov + t dv, the box interval [t0, t1] and the sample lattice. */
typedef struct {
    float o[3], d[3], ov[3], dv[3];
    float t0, t1, t_start;
    float base, growth, level3d;   /* parallel spacing and level; perspective growth */
    bool perspective;
    long positions;                /* parallel: positions in [t0, t1] */
} blend_geom_t;

/* The 3D level a ray of 2D level level2d starts at (parallel: throughout). */
float blend_level3d(const blend_ctx_t *c, int level2d);
/* False when the ray misses the box (its colour is black). */
bool blend_geom_begin(const blend_ctx_t *c, float px, float py, int level2d, blend_geom_t *g);

/* What the reference tracer found for one ray (tests and firmware checks). */
typedef struct {
    bool hit_box;
    blend_geom_t geom;
    float m_max;
    long k_max, k_stop;
    bool occluded;                 /* reading B's occluder test */
    float t_hit;                   /* ray 2's sample (DEMIP) */
    float rgb[3];
    uint64_t samples;
} blend_ray_info_t;

void blend_trace_reference_info(const blend_ctx_t *c, float px, float py, int level2d,
                                blend_ray_info_t *info);
void blend_trace_reference(const blend_ctx_t *c, float px, float py, int level2d, float rgb[3],
                           raycast_counts_t *counts);
/* Materials of a parallel ray's samples, in order (at most `max`); returns
 * how many the ray has (-1 under perspective), for blend_ray_from_samples. */
long blend_ray_materials(const blend_ctx_t *c, float px, float py, int level2d, float *m,
                         long max);

/* `count` rays of one 2D level; *guess_io (may be NULL) carries the
 * threshold guess from the previous batch of the same texel row in and the
 * last ray's out, so that only a row's first ray starts without one. */
#define BLEND_BATCH RAYCAST_BATCH
void blend_trace_batch(const blend_ctx_t *c, int count, const float *px, const float *py,
                       int level2d, float (*rgb)[3], float *guess_io, raycast_counts_t *counts);

/* The skipping tracer (blend_trace_fast.c, blend_trace_packet.c) for up to
 * BLEND_BATCH parallel rays of one level.  MIP and DEMIP rays start from
 * m_max = guess (0: none) and fall back to a full trace when nothing exceeds
 * it (counted in samples_retraced); the result does not depend on the
 * guess.  Returns the last ray's m_max (0 for MIDA). */
float blend_trace_fast_batch(const blend_ctx_t *c, int count, const float *px, const float *py,
                             int level2d, float guess, float (*rgb)[3], raycast_counts_t *counts);
/* The same for one ray. */
float blend_trace_fast(const blend_ctx_t *c, float px, float py, int level2d, float guess,
                       float rgb[3], raycast_counts_t *counts);
/* The fraction of a neighbour's maximum a batch's next ray guesses. */
#define BLEND_GUESS_FRACTION 0.9f

#endif
