/* blend_ray.h: the per-ray maths of MIP, depth-enhanced MIP and MIDA as
 * small pure functions of plain numbers, so that a firmware restatement can
 * mirror them line by line and a test can compare the two.  The tracers
 * (blend_trace.h) only decide which samples to draw; everything a ray does
 * with a sample's material is here.
 *
 * Material.  m = clamp((v - lo) / width, 0, 1) (window/level; seed 002 §3.1
 * calls the transfer function's value the "material").  It is monotone in v
 * (every float operation in it is), so the largest material is the material
 * of the largest value, and a bound on the values of a region bounds its
 * materials: that is what makes empty-space and max skipping exact.
 *
 * Ray 1 (MIP, seed 002 §3.1 step 1): m_max = max over samples of m, and k_max
 * = the first sample index reaching it.  m_max starts at 0, so a ray whose
 * samples are all 0 keeps k_max = -1: it saw nothing and stays black (eq. (1)
 * would otherwise paint the whole bounding box).  No sample can exceed 1, so
 * a ray stops once m_max = 1; a region whose bound is <= m_max cannot change
 * m_max or k_max and is skipped.
 *
 * Ray 2 (§3.1 step 2): restarts at the entry into the volume's bounding box,
 * on the same sample positions, and stops at the first sample with
 * m >= m_max - eps and m > 0 (material 0 is empty space, never "the same
 * material").  It stops at k_max at the latest, which is why DEMIP costs
 * less than two MIPs (the paper's Table 1: 1.12-1.40x).
 *
 * Eq. (1): c = m_max (1 - dw) + 2 dw (1 - depth), clamped to [0, 1] (it
 * exceeds 1 for bright, near points).  Reading A (default): everywhere a ray
 * saw something; it matches the paper's figure 5 and its "near lighter, far
 * darker" intent.  Reading B: only where ray 2 stopped at an occluder of
 * the same material in front of the maximum; elsewhere c = m_max, which is
 * the text's "when the reached point is the same (i.e. there are not
 * previous occlusions), the rendering will be the same as with MIP".  An
 * occluder is a stop before k_max with a sample below the threshold between
 * the two: with eps > 0 ray 2 also stops before k_max on the rising edge of
 * the maximum's own structure (trilinear samples climb to the plateau), and
 * "stopped before the maximum" alone would then change every such pixel of
 * an image without any occluder.
 *
 * Depth (§3.2).  Exact: the distance from the eye to ray 2's point (under
 * parallel projection the distance along the view axis), normalised so that
 * the nearest bounding-box corner is 0 and the farthest 1, clamped to [0, 1]
 * (under perspective a face can be nearer than every corner).
 * Entry-plus-length, the paper's approximation: the entry point's depth plus
 * the ray length from the entry to the point, both as view-axis distances
 * normalised by the corners' view-axis range.  The paper adds an OpenGL
 * depth (hyperbolic in z) to a step count without saying how the two are
 * scaled; we take the entry's linear view-axis depth so that both terms share
 * one unit.  Under parallel projection the two depths are then the same
 * number up to rounding (the ray runs along the view axis); under
 * perspective they differ off the axis, by the entry point's
 * (distance - view-axis distance) / range plus the length's obliquity.
 *
 * Eq. (2): c = c_DEMIP (1 - sw) + sphere(dir) sw, dir from the bounding-box
 * centre to ray 2's point (colour_sphere.h).
 *
 * MIDA (Bruckner & Gröller, "Instant Volume Visualization using Maximum
 * Intensity Difference Accumulation", Computer Graphics Forum 28(3):775-782,
 * EuroVis 2009, doi:10.1111/j.1467-8659.2009.01474.x), with f the sample's
 * material, f_max the largest so far (before this sample), and colour and
 * opacity from the window ramp (grey m, opacity m corrected for the sample
 * spacing as compositing does):
 *     delta = f - f_max if f > f_max, else 0;     beta = 1 - delta
 *     C     = beta C + (1 - beta A) a c;           A = beta A + (1 - beta A) a
 * Without a new maximum (beta = 1) this is front-to-back compositing; a new
 * maximum fades what lies in front of it, as MIP would show it.  Bruckner
 * and Gröller normalise the data range to [0, 1]; our f is the windowed
 * material (the same with the window spanning the data range).  Their gamma
 * (a blend towards DVR or MIP) is not implemented (gamma = 0: pure MIDA).
 * Early termination: A >= et is not enough (a later, brighter maximum can
 * still fade the colour), so a ray also needs f_max >= et: every later beta
 * product is then >= 1 - (1 - f_max) >= et, and the pixel can change by at
 * most about 1 - et^2 (0.1 for et = 0.95) of full scale. */
#ifndef PP5_BLEND_RAY_H
#define PP5_BLEND_RAY_H

#include <math.h>
#include <stdbool.h>
#include "blend.h"
#include "colour_sphere.h"
#include "raycast.h"

/* ---- material ---- */

typedef struct {
    float lo, inv_width;
} blend_window_t;

static inline float blend_material(const blend_window_t *w, float v)
{
    float m = (v - w->lo) * w->inv_width;
    if (!(m > 0.0f))
        return 0.0f;
    return m < 1.0f ? m : 1.0f;
}

/* ---- ray 1: MIP ---- */

typedef struct {
    float m_max;
    long k_max;               /* first sample reaching m_max; -1: nothing seen */
} mip_ray_t;

static inline void mip_ray_init(mip_ray_t *r)
{
    r->m_max = 0.0f;
    r->k_max = -1;
}

/* Sample k with material m; true when the ray is finished (m_max = 1). */
static inline bool mip_ray_sample(mip_ray_t *r, long k, float m)
{
    if (m > r->m_max) {
        r->m_max = m;
        r->k_max = k;
    }
    return r->m_max >= 1.0f;
}

/* True when samples whose materials are all <= m_bound cannot change the ray. */
static inline bool mip_ray_can_skip(const mip_ray_t *r, float m_bound)
{
    return m_bound <= r->m_max;
}

/* ---- ray 2: the first sample of the maximum's material ---- */

static inline float demip_ray2_threshold(float m_max, float eps)
{
    return m_max - eps;
}

static inline bool demip_ray2_stops(float m, float threshold)
{
    return m > 0.0f && m >= threshold;
}

/* Reading B's gap test for a sample between ray 2's stop and k_max. */
static inline bool demip_is_gap(float m, float threshold)
{
    return !demip_ray2_stops(m, threshold);
}

/* ---- eq. (1) and eq. (2) ---- */

static inline float demip_eq1(float mip, float depth, float dw)
{
    float c = mip * (1.0f - dw) + 2.0f * dw * (1.0f - depth);
    return c <= 0.0f ? 0.0f : (c >= 1.0f ? 1.0f : c);
}

static inline void demip_eq2(float demip, const float sphere_rgb[3], float sw, float rgb[3])
{
    for (int k = 0; k < 3; k++)
        rgb[k] = demip * (1.0f - sw) + sphere_rgb[k] * sw;
}

/* ---- MIDA ---- */

typedef struct {
    float colour, alpha, f_max;
} mida_ray_t;

static inline void mida_ray_init(mida_ray_t *s)
{
    s->colour = s->alpha = s->f_max = 0.0f;
}

/* One sample of material f and (spacing-corrected) opacity a; true when the
 * ray may stop (see above). */
static inline bool mida_ray_sample(mida_ray_t *s, float f, float a, float early_termination)
{
    float delta = f > s->f_max ? f - s->f_max : 0.0f;
    float beta = 1.0f - delta;
    float w = (1.0f - beta * s->alpha) * a;
    s->colour = beta * s->colour + w * f;
    s->alpha = beta * s->alpha + w;
    if (f > s->f_max)
        s->f_max = f;
    return s->alpha >= early_termination && s->f_max >= early_termination;
}

/* Opacity a sample of material m has when it stands for `spacing` object
 * units (the opacity per unit length is m): 1 - (1 - m)^spacing. */
static inline float mida_opacity(float m, float spacing)
{
    if (spacing == 1.0f || m <= 0.0f)
        return m;
    if (m >= 1.0f)
        return 1.0f;
    return 1.0f - powf(1.0f - m, spacing);
}

/* ---- what stays constant over a frame ---- */

typedef struct {
    blend_mode_t mode;
    blend_window_t window;
    float eps, dw, sw;
    demip_reading_t reading;
    demip_depth_t depth;
    bool perspective;
    float eye[3], forward[3], centre[3];
    float exact_near, exact_inv_range;     /* exact depth normalisation */
    float axis_near, axis_inv_range;       /* view-axis normalisation */
    colour_sphere_t sphere;
    float early_termination;
} blend_frame_t;

/* vol_lo/vol_hi: the volume's value range, used when the window width is 0. */
void blend_frame_init(blend_frame_t *f, const blend_settings_t *b, const camera_t *cam,
                      float vol_lo, float vol_hi, float early_termination);
/* Exact depth of object-space point p, 0 at the nearest corner, 1 at the farthest. */
float demip_depth_exact(const blend_frame_t *f, const float p[3]);
/* The paper's approximation: entry point's view-axis depth + ray length. */
float demip_depth_entry_plus_length(const blend_frame_t *f, const float entry[3], float length);

/* Final DEMIP colour of a ray o + t d (object space, d unit) that entered
 * the box at t_entry, whose ray 1 found m_max > 0 and whose ray 2 stopped
 * at t_hit, `occluded` when that was at an occluder (reading B's test). */
void demip_colour(const blend_frame_t *f, const float o[3], const float d[3], float t_entry,
                  float t_hit, float m_max, bool occluded, float rgb[3]);

/* Everything one parallel ray does, from its sample materials m[0..n-1]
 * (positions t_k = t_entry + k * spacing): the reference a firmware
 * restatement is compared against.  The tracers give the same numbers.
 * Under reading B the samples after k_stop are examined up to the first gap
 * (or k_max): that is the cost of the occluder test. */
typedef struct {
    float m_max;
    long k_max, k_stop;       /* -1: none */
    bool occluded;            /* reading B: a gap between k_stop and k_max */
    float mida_colour, mida_alpha;
    long samples;             /* drawn without skipping (both rays for DEMIP; early stops kept) */
} blend_ray_result_t;
void blend_ray_from_samples(const blend_frame_t *f, const float *m, long n, float spacing,
                            blend_ray_result_t *out);

#endif
