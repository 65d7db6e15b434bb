/* raycast_internal.h: per-sample arithmetic shared by the reference tracer
 * (raycast.c) and the fast parallel tracer (raycast_parallel.c), in one place
 * so both do exactly the same floating-point operations in the same order. */
#ifndef PP5_RAYCAST_INTERNAL_H
#define PP5_RAYCAST_INTERNAL_H

#include <math.h>
#include <stdbool.h>

#include "raycast.h"

/* Opacity of a sample standing for `spacing` object units when a has been
 * classified per unit: 1 - (1 - a)^spacing. */
static inline float raycast_correct_alpha(const raycast_ctx_t *r, int level2d, bool perspective,
                                          float spacing, float a)
{
    if (a >= 1.0f)
        return 1.0f;
    if (perspective || level2d >= RAYCAST_LUT_LEVELS)
        return 1.0f - powf(1.0f - a, spacing);
    float x = a * (float)RAYCAST_LUT_SIZE;
    int i = (int)x;
    if (i >= RAYCAST_LUT_SIZE)
        i = RAYCAST_LUT_SIZE - 1;
    float f = x - (float)i;
    const float *t = r->alpha_lut[level2d];
    return t[i] + f * (t[i + 1] - t[i]);
}

/* Parametric interval [t0, t1] of the ray inside the box [0, hi]. */
static inline bool raycast_clip_box(const float o[3], const float d[3], const float hi[3],
                                    float *t0, float *t1)
{
    float a = -INFINITY, b = INFINITY;
    for (int k = 0; k < 3; k++) {
        if (d[k] == 0.0f) {
            if (o[k] < 0.0f || o[k] > hi[k])
                return false;
            continue;
        }
        float ta = (0.0f - o[k]) / d[k], tb = (hi[k] - o[k]) / d[k];
        if (ta > tb) {
            float s = ta;
            ta = tb;
            tb = s;
        }
        if (ta > a)
            a = ta;
        if (tb < b)
            b = tb;
    }
    if (a < 0.0f)
        a = 0.0f;
    *t0 = a;
    *t1 = b;
    return a <= b;
}

/* The ray through image point (px, py) clipped to the volume ([t0, t1];
 * false: it misses), in level-0 voxel coordinates ov + t dv, with 1/dv (0
 * where dv is 0) and the shading half vector for its direction. */
static inline bool raycast_ray_setup(const raycast_ctx_t *r, float px, float py, float *t0,
                                     float *t1, float ov[3], float dv[3], float inv_dv[3],
                                     float half[3])
{
    const camera_t *cam = r->camera;
    float o[3], d[3];
    camera_ray(cam, px, py, o, d);
    if (!raycast_clip_box(o, d, cam->box_hi, t0, t1))
        return false;
    for (int a = 0; a < 3; a++) {
        ov[a] = o[a] * cam->inv_spacing[a];
        dv[a] = d[a] * cam->inv_spacing[a];
        inv_dv[a] = dv[a] != 0.0f ? 1.0f / dv[a] : 0.0f;
    }
    float view[3] = {-d[0], -d[1], -d[2]};
    shade_half_vector(r->light_obj, view, half);
    return true;
}

/* Where the ray ov + t dv leaves the box [lo, hi] of an empty node, going
 * forward (faces at +-INFINITY never: INFINITY when none is crossed). */
static inline float raycast_node_exit(const float ov[3], const float dv[3], const float inv_dv[3],
                                      const float lo[3], const float hi[3])
{
    float t_exit = INFINITY;
    for (int a = 0; a < 3; a++) {
        float te = INFINITY;
        if (dv[a] > 0.0f && isfinite(hi[a]))
            te = (hi[a] - ov[a]) * inv_dv[a];
        else if (dv[a] < 0.0f && isfinite(lo[a]))
            te = (lo[a] - ov[a]) * inv_dv[a];
        if (te < t_exit)
            t_exit = te;
    }
    return t_exit;
}

/* Viewpoint-dependent shading of one sample's components: writes the
 * opacity-weighted colour and returns the opacity. */
static inline float raycast_shade_sample(const raycast_ctx_t *r, const float *s,
                                         const float half[3], float c[3])
{
    float a = s[MIP3D_A];
    c[0] = s[MIP3D_R];
    c[1] = s[MIP3D_G];
    c[2] = s[MIP3D_B];
    if (r->mip->stride == 4 || a <= 0.0f)
        return a;
    float n[3] = {s[MIP3D_NX], s[MIP3D_NY], s[MIP3D_NZ]};
    float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (len > 0.0f)
        for (int k = 0; k < 3; k++)
            n[k] /= len;
    if (r->mip->lighting == SHADE_MOVING_OBJECT) {
        float d = shade_diffuse(r->shade, n, r->light_obj);
        for (int k = 0; k < 3; k++)
            c[k] *= d;
    }
    if (len > 0.0f) {
        float sp = a * shade_specular(r->shade, n, half);
        for (int k = 0; k < 3; k++)
            c[k] += sp;
    }
    return a;
}

/* Shading, opacity correction and front-to-back compositing of one drawn
 * sample `comp`; true when the ray has reached early termination. */
static inline bool raycast_accumulate(const raycast_ctx_t *r, const float *comp,
                                      const float half[3], int level2d, bool perspective,
                                      float spacing, float acc[3], float *acc_a)
{
    float c[3];
    float a = raycast_shade_sample(r, comp, half, c);
    if (a > 0.0f) {
        if (spacing != 1.0f) {
            /* Opacity per unit length is fixed; a sample standing for
             * `spacing` units has opacity 1 - (1 - a)^spacing. */
            float ac = raycast_correct_alpha(r, level2d, perspective, spacing, a);
            float scale = ac / a;
            c[0] *= scale;
            c[1] *= scale;
            c[2] *= scale;
            a = ac;
        }
        raycast_composite(acc, acc_a, c, a);
        if (*acc_a >= r->early_termination)
            return true;
    }
    return false;
}

/* Number of parallel sample positions t0 + k * base, k = 0, 1, ..., with
 * t <= t1 (the tracer's exact float expression; 0 when t1 < t0). */
long raycast_parallel_positions(float t0, float t1, float base);

/* Fast tracer for parallel projection with the octree (raycast_parallel.c):
 * draws exactly the samples of the reference tracer; count <= RAYCAST_CHUNK. */
void raycast_parallel_batch(const raycast_ctx_t *r, int count, const float *px, const float *py,
                            int level2d, float (*rgb)[3], raycast_counts_t *counts);

/* Fast tracer for perspective projection with the octree
 * (raycast_perspective.c): the reference's positions and samples;
 * count <= RAYCAST_CHUNK.  raycast_perspective_tables fills the context's
 * level bounds (raycast_ctx_init calls it for perspective cameras). */
void raycast_perspective_batch(const raycast_ctx_t *r, int count, const float *px,
                               const float *py, int level2d, float (*rgb)[3],
                               raycast_counts_t *counts);
void raycast_perspective_tables(raycast_ctx_t *r);

#endif
