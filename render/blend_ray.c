/* blend_ray.c: the per-frame constants of the MIP/DEMIP/MIDA ray maths, the
 * two depths, DEMIP's final colour and the whole-ray reference (see
 * blend_ray.h for the formulas and their sources). */
#include "blend_ray.h"

#include <math.h>
#include <string.h>

static float dot3(const float a[3], const float b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static float distance3(const float a[3], const float b[3])
{
    float d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return sqrtf(dot3(d, d));
}

static void set_range(float lo, float hi, float *near, float *inv_range)
{
    *near = lo;
    *inv_range = hi > lo ? 1.0f / (hi - lo) : 0.0f;
}

void blend_frame_init(blend_frame_t *f, const blend_settings_t *b, const camera_t *cam,
                      float vol_lo, float vol_hi, float early_termination)
{
    memset(f, 0, sizeof *f);
    f->mode = b->mode;
    float lo = b->window_centre - 0.5f * b->window_width, width = b->window_width;
    if (!(width > 0.0f)) {
        lo = vol_lo;
        width = vol_hi - vol_lo;
    }
    f->window.lo = lo;
    f->window.inv_width = width > 0.0f ? 1.0f / width : 1.0f;
    f->eps = b->tolerance;
    f->dw = b->depth_weight;
    f->sw = b->sphere_weight;
    f->reading = b->reading;
    f->depth = b->depth;
    f->perspective = cam->projection == PROJECTION_PERSPECTIVE;
    memcpy(f->eye, cam->eye, sizeof f->eye);
    memcpy(f->forward, cam->forward, sizeof f->forward);
    memcpy(f->centre, cam->centre, sizeof f->centre);
    /* The sampled box [0, box_hi]: its eight corners set both ranges. */
    float axis_lo = INFINITY, axis_hi = -INFINITY, eye_lo = INFINITY, eye_hi = -INFINITY;
    for (int i = 0; i < 8; i++) {
        float c[3];
        for (int a = 0; a < 3; a++)
            c[a] = (i >> a) & 1 ? cam->box_hi[a] : 0.0f;
        float along = dot3(c, cam->forward), from_eye = distance3(c, cam->eye);
        axis_lo = fminf(axis_lo, along);
        axis_hi = fmaxf(axis_hi, along);
        eye_lo = fminf(eye_lo, from_eye);
        eye_hi = fmaxf(eye_hi, from_eye);
    }
    set_range(axis_lo, axis_hi, &f->axis_near, &f->axis_inv_range);
    if (f->perspective)
        set_range(eye_lo, eye_hi, &f->exact_near, &f->exact_inv_range);
    else
        set_range(axis_lo, axis_hi, &f->exact_near, &f->exact_inv_range);
    colour_sphere_init(&f->sphere, b->sphere_map, b->sphere_rot_deg);
    f->early_termination = early_termination;
}

static float clamp01(float x)
{
    return x <= 0.0f ? 0.0f : (x >= 1.0f ? 1.0f : x);
}

float demip_depth_exact(const blend_frame_t *f, const float p[3])
{
    float d = f->perspective ? distance3(p, f->eye) : dot3(p, f->forward);
    return clamp01((d - f->exact_near) * f->exact_inv_range);
}

float demip_depth_entry_plus_length(const blend_frame_t *f, const float entry[3], float length)
{
    float entry_depth = (dot3(entry, f->forward) - f->axis_near) * f->axis_inv_range;
    return clamp01(entry_depth + length * f->axis_inv_range);
}

void demip_colour(const blend_frame_t *f, const float o[3], const float d[3], float t_entry,
                  float t_hit, float m_max, bool occluded, float rgb[3])
{
    float p[3];
    for (int a = 0; a < 3; a++)
        p[a] = o[a] + t_hit * d[a];
    float depth;
    if (f->depth == DEMIP_DEPTH_EXACT) {
        depth = demip_depth_exact(f, p);
    } else {
        float e[3];
        for (int a = 0; a < 3; a++)
            e[a] = o[a] + t_entry * d[a];
        depth = demip_depth_entry_plus_length(f, e, t_hit - t_entry);
    }
    float grey = f->reading == DEMIP_READING_A || occluded ? demip_eq1(m_max, depth, f->dw)
                                                           : m_max;
    if (f->sw > 0.0f) {
        float dir[3] = {p[0] - f->centre[0], p[1] - f->centre[1], p[2] - f->centre[2]}, sph[3];
        colour_sphere_colour(&f->sphere, dir, sph);
        demip_eq2(grey, sph, f->sw, rgb);
    } else {
        rgb[0] = rgb[1] = rgb[2] = grey;
    }
}

void blend_ray_from_samples(const blend_frame_t *f, const float *m, long n, float spacing,
                            blend_ray_result_t *out)
{
    memset(out, 0, sizeof *out);
    out->k_max = out->k_stop = -1;
    long k = 0;
    if (f->mode == BLEND_MIDA) {
        mida_ray_t s;
        mida_ray_init(&s);
        while (k < n && !mida_ray_sample(&s, m[k], mida_opacity(m[k], spacing),
                                         f->early_termination))
            k++;
        out->samples = k < n ? k + 1 : n;
        out->mida_colour = s.colour;
        out->mida_alpha = s.alpha;
        return;
    }
    mip_ray_t r;
    mip_ray_init(&r);
    while (k < n && !mip_ray_sample(&r, k, m[k]))
        k++;
    out->samples = k < n ? k + 1 : n;
    out->m_max = r.m_max;
    out->k_max = r.k_max;
    if (f->mode != BLEND_DEMIP || r.k_max < 0)
        return;
    float threshold = demip_ray2_threshold(r.m_max, f->eps);
    long j = 0;
    while (!demip_ray2_stops(m[j], threshold))
        j++;                  /* ends at k_max at the latest: m[k_max] = m_max */
    out->k_stop = j;
    out->samples += j + 1;
    if (f->reading != DEMIP_READING_B)
        return;
    for (long g = j + 1; g < r.k_max; g++) {
        out->samples++;
        if (demip_is_gap(m[g], threshold)) {
            out->occluded = true;
            break;
        }
    }
}
