/* vr_kernels.h: the GP's numerical kernels: classification, gradients, diffuse shading, 2DLevel, 2D mip map, camera rays.
 *
 * Each kernel repeats the float arithmetic of the native renderer (render/
 * classify.c, shade.c, gaze2d.c, raycast.c) operation for operation and in the
 * same order, so the machine's image agrees with render/'s bit for bit where
 * the data agree.  Firmware cannot include render/ (the Makefile's include
 * path), hence the restatement.  tests/test_fw_machine.c checks them end to
 * end: the machine's rays and samples equal render/'s run on the machine's
 * formats, and the images agree to 1/255. */
#ifndef PP5_VR_KERNELS_H
#define PP5_VR_KERNELS_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include "vr_config.h"

/* classify_voxel (render/classify.c) */
static inline float vr_classify(const vr_config_t *c, float value, float grad_mag, float rgb[3])
{
    float transparency = 1.0f, wsum = 0.0f;
    float col[3] = {0.0f, 0.0f, 0.0f};
    for (int i = 0; i < c->tf_count; i++) {
        const vr_contour_t *k = &c->tf[i];
        float d = fabsf(k->value - value);
        float a = 0.0f;
        if (grad_mag > 0.0f) {
            float f = 1.0f - d / (k->width_vox * grad_mag);
            if (f > 0.0f)
                a = k->opacity * f;
        } else if (d == 0.0f) {
            a = k->opacity;
        }
        if (a > 0.0f) {
            transparency *= 1.0f - a;
            wsum += a;
            for (int ch = 0; ch < 3; ch++)
                col[ch] += a * k->rgb[ch];
        }
    }
    for (int ch = 0; ch < 3; ch++)
        rgb[ch] = wsum > 0.0f ? col[ch] / wsum : 0.0f;
    return 1.0f - transparency;
}

/* shade_diffuse (render/shade.c) */
static inline float vr_diffuse(const vr_config_t *c, const float n[3], const float l[3])
{
    float len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    if (len2 == 0.0f)
        return c->ambient + c->diffuse;
    float d = n[0] * l[0] + n[1] * l[1] + n[2] * l[2];
    d = c->two_sided ? fabsf(d) : fmaxf(d, 0.0f);
    return c->ambient + c->diffuse * d;
}

/* shade_half_vector (render/shade.c) */
static inline void vr_half_vector(const float l[3], const float e[3], float h[3])
{
    float s[3] = {l[0] + e[0], l[1] + e[1], l[2] + e[2]};
    float n = sqrtf(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    for (int i = 0; i < 3; i++)
        h[i] = n > 0.0f ? s[i] / n : 0.0f;
}

/* gaze_level (render/gaze2d.c) from the host's model constants. */
#define VR_DEG (M_PI / 180.0)
static inline float vr_gaze_level(const vr_config_t *c, double r_px, int *transcendental)
{
    if (r_px <= c->g_r_zero_px)
        return 0.0f;
    if (r_px >= c->g_r_max_px)
        return (float)c->g_max_level;
    *transcendental = 1;
    double e = atan(r_px * c->g_inches_per_px / c->g_view_distance_in) / VR_DEG;
    double rho;
    if (e <= c->g_e_full_deg) {
        rho = 1.0;
    } else if (e >= c->g_e_edge_deg) {
        rho = c->g_rho_min;
    } else {
        double x = (e - c->g_e_full_deg) / c->g_sigma_deg;
        rho = c->g_rho_min + (1.0 - c->g_rho_min) * exp(-0.5 * x * x);
    }
    double level = 0.5 * log2(1.0 / rho);
    if (level < 0.0)
        level = 0.0;
    if (level > c->g_max_level)
        level = c->g_max_level;
    return (float)level;
}

/* 2DLevel by the paper's two lookup tables (seed 004 §4; render/gaze2d.h
 * gaze_level_tables_t, restated): distances in 1/VR_TABLE_STEPS pixel for
 * integer offsets from the gaze pixel, then levels by distance.  The GP
 * allocates the arrays (vr_level_tables_sizes) and fills them once per
 * sequence (vr_level_tables_fill). */
#define VR_TABLE_STEPS 4
typedef struct {
    int w, h, n;
    uint16_t *dist;                 /* w * h */
    float *level;                   /* n */
    float level_far;
} vr_level_tables_t;

/* Entries of the 1D table for an image of w x h offsets. */
static inline int vr_level_tables_entries(const vr_config_t *c, int w, int h)
{
    double diag = sqrt((double)w * w + (double)h * h);
    double far = c->g_r_max_px < diag ? c->g_r_max_px : diag;
    return (int)ceil(far * VR_TABLE_STEPS) + 2;
}

/* Fills both tables; returns the transcendental evaluations (for the cost). */
static inline uint64_t vr_level_tables_fill(const vr_config_t *c, vr_level_tables_t *t)
{
    for (int dy = 0; dy < t->h; dy++)
        for (int dx = 0; dx < t->w; dx++)
            t->dist[(size_t)dy * t->w + dx] =
                (uint16_t)floor(sqrt((double)dx * dx + (double)dy * dy) * VR_TABLE_STEPS + 0.5);
    int trans = 0;
    uint64_t n_trans = 0;
    for (int k = 0; k < t->n; k++) {
        trans = 0;
        t->level[k] = vr_gaze_level(c, (double)k / VR_TABLE_STEPS, &trans);
        n_trans += (uint64_t)trans;
    }
    t->level_far = vr_gaze_level(c, INFINITY, &trans);
    return n_trans;
}

static inline float vr_level_tabled(const vr_level_tables_t *t, int dx, int dy, double scale)
{
    dx = dx < 0 ? -dx : dx;
    dy = dy < 0 ? -dy : dy;
    double d = dx < t->w && dy < t->h ? (double)t->dist[(size_t)dy * (size_t)t->w + (size_t)dx]
                                      : floor(sqrt((double)dx * dx + (double)dy * dy) *
                                              VR_TABLE_STEPS + 0.5);
    if (d >= 4294967295.0)
        return t->level_far;
    unsigned k = (unsigned)d;
    if (scale != 1.0)
        k = (unsigned)((double)k / scale + 0.5);
    return k < (unsigned)t->n ? t->level[k] : t->level_far;
}

/* camera_ray (render/raycast.c) */
static inline void vr_camera_ray(const vr_frame_t *f, int width, int height, float px, float py,
                                 float origin[3], float dir[3])
{
    float dx = (px - 0.5f * (float)width) * f->pixel_size;
    float dy = (py - 0.5f * (float)height) * f->pixel_size;
    float P[3];
    for (int a = 0; a < 3; a++)
        P[a] = f->centre[a] + dx * f->right[a] + dy * f->down[a];
    if (f->projection == 0) {
        for (int a = 0; a < 3; a++) {
            origin[a] = P[a] - (f->radius + 1.0f) * f->forward[a];
            dir[a] = f->forward[a];
        }
        return;
    }
    float d[3], n = 0.0f;
    for (int a = 0; a < 3; a++) {
        d[a] = P[a] - f->eye[a];
        n += d[a] * d[a];
    }
    n = sqrtf(n);
    for (int a = 0; a < 3; a++) {
        origin[a] = f->eye[a];
        dir[a] = d[a] / n;
    }
}

/* clip_box (render/raycast.c) */
static inline bool vr_clip_box(const float o[3], const float d[3], const float hi[3], float *t0,
                               float *t1)
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

/* mip3d_level_coord (render/mip3d.h) */
static inline float vr_level_coord(float p, int n)
{
    return (p + 0.5f) / (float)(1 << n) - 0.5f;
}

#endif
