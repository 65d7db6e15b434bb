/* vr_kernels.h: the GP's numerical kernels: classification, gradients, diffuse shading, 2DLevel, 2D mip map, camera rays.
 *
 * Each kernel repeats the float arithmetic of the native renderer (render/
 * classify.c, shade.c, gaze2d.c, raycast.c) operation for operation and in the
 * same order, so the machine's image agrees with render/'s bit for bit where
 * the data agree.  Firmware cannot include render/ (the Makefile's include
 * path), hence the restatement.  tests/test_fw_machine.c checks them end to
 * end: the machine's rays and samples equal render/'s run on the machine's
 * formats, and the images agree to 1/255.
 *
 * The cost-counted ones take the span counters and the optional operation
 * count of common/vr_cost.h (sp, cnt; NULL when not wanted): each states its
 * operations beside its code, and tests/test_fw_cost.c checks them against
 * the rows. */
#ifndef PP5_VR_KERNELS_H
#define PP5_VR_KERNELS_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include "vr_config.h"
#include "vr_cost.h"

/* classify_voxel (render/classify.c).  Spans: CLASSIFY once, CONTOUR per
 * contour (+ CONTOUR_RAMP where the gradient is non-zero, CONTOUR_FLAT where
 * it is zero, CONTOUR_HIT where the contour gives opacity). */
static inline float vr_classify(const vr_config_t *c, float value, float grad_mag, float rgb[3],
                                vr_spans_t *sp, vr_count_t *cnt)
{
    float transparency = 1.0f, wsum = 0.0f;
    float col[3] = {0.0f, 0.0f, 0.0f};
    /* the loop's entry test; after it: wsum > 0, 3 divides (both sides of the
     * select), 1 - transparency */
    VR_SPAN(sp, cnt, CLASSIFY, .int_ops = 1, .branches = 1 + 1, .fadd = 1 + 1, .fdiv = 3);
    for (int i = 0; i < c->tf_count; i++) {
        const vr_contour_t *k = &c->tf[i];
        float d = fabsf(k->value - value);
        float a = 0.0f;
        /* i++ and the loop test; the contour's value (the subtract needs it
         * at once), fabs; the gradient test, the opacity test below */
        VR_SPAN(sp, cnt, CONTOUR, .int_ops = 2 + 1, .branches = 1 + 1 + 1, .loads = 1, .load_use = 1,
                .fadd = 1 + 1 + 1);
        if (grad_mag > 0.0f) {
            float f = 1.0f - d / (k->width_vox * grad_mag);
            if (f > 0.0f)
                a = k->opacity * f;
            /* width (used at once), multiply, divide, subtract; f > 0 and the
             * opacity load (used at once) and multiply of the select */
            VR_SPAN(sp, cnt, CONTOUR_RAMP, .loads = 2, .load_use = 2, .fmul = 2, .fdiv = 1, .fadd = 2,
                    .branches = 1);
        } else if (d == 0.0f) {
            a = k->opacity;
            VR_SPAN(sp, cnt, CONTOUR_FLAT, .fadd = 1, .branches = 1, .loads = 1);
        } else {
            VR_SPAN(sp, cnt, CONTOUR_FLAT, .fadd = 1, .branches = 1, .loads = 1);
        }
        if (a > 0.0f) {
            transparency *= 1.0f - a;
            wsum += a;
            for (int ch = 0; ch < 3; ch++)
                col[ch] += a * k->rgb[ch];
            /* 1 - a, x, +; 3 colour loads (scheduled before their multiplies),
             * 3 multiply-adds */
            VR_SPAN(sp, cnt, CONTOUR_HIT, .fadd = 2 + 3, .fmul = 1 + 3, .loads = 3);
        }
    }
    for (int ch = 0; ch < 3; ch++)
        rgb[ch] = wsum > 0.0f ? col[ch] / wsum : 0.0f;
    return 1.0f - transparency;
}

/* shade_diffuse (render/shade.c) */
/* Spans: DIFFUSE, then DIFFUSE_LIT or (zero normal) DIFFUSE_UNLIT.  The
 * light and the coefficients are the sequence's: in registers. */
static inline float vr_diffuse(const vr_config_t *c, const float n[3], const float l[3],
                               vr_spans_t *sp, vr_count_t *cnt)
{
    float len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    VR_SPAN(sp, cnt, DIFFUSE, .fmul = 3, .fadd = 2 + 1, .branches = 1);
    if (len2 == 0.0f) {
        VR_SPAN(sp, cnt, DIFFUSE_UNLIT, .fadd = 1);
        return c->ambient + c->diffuse;
    }
    float d = n[0] * l[0] + n[1] * l[1] + n[2] * l[2];
    d = c->two_sided ? fabsf(d) : fmaxf(d, 0.0f);
    /* the dot product; the two-sided test with fabs or max (both counted);
     * ambient + diffuse d */
    VR_SPAN(sp, cnt, DIFFUSE_LIT, .fmul = 3 + 1, .fadd = 2 + 1 + 1, .int_ops = 1, .branches = 1 + 1);
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

/* One libm-style transcendental (atan, exp, exp2, log2, pow).  Its row is
 * an estimate [I] (range reduction and a polynomial of about 20
 * multiply-adds, facts §8 has no libm figures); the spans count the calls. */
static inline void vr_libm(vr_spans_t *sp, vr_count_t *cnt)
{
    VR_SPAN(sp, cnt, LIBM, .fadd = 20, .fmul = 20, .fdiv = 2, .loads = 4, .int_ops = 3, .branches = 3);
}

/* gaze_level (render/gaze2d.c) from the host's model constants.  Spans:
 * GAZE_LEVEL per call (the two radius tests and the conversion of the
 * result, both sides of the selects); inside the annulus (*transcendental =
 * 1) LEVEL_ANNULUS with atan and log2 (LIBM each) and, between the full and
 * the edge eccentricity, LEVEL_FALLOFF with an exp (LIBM).  Double precision
 * is counted as single (gp_cost.h: not modelled). */
#define VR_DEG (M_PI / 180.0)
static inline float vr_gaze_level(const vr_config_t *c, double r_px, int *transcendental,
                                  vr_spans_t *sp, vr_count_t *cnt)
{
    VR_SPAN(sp, cnt, GAZE_LEVEL, .fadd = 2, .branches = 2, .int_ops = 1);
    if (r_px <= c->g_r_zero_px)
        return 0.0f;
    if (r_px >= c->g_r_max_px)
        return (float)c->g_max_level;
    *transcendental = 1;
    double e = atan(r_px * c->g_inches_per_px / c->g_view_distance_in) / VR_DEG;
    vr_libm(sp, cnt);
    /* the argument (multiply, divide), / degree (divide); e against the
     * full and the edge eccentricity; 0.5 log2(1 / rho) (divide, multiply);
     * the two clamps */
    VR_SPAN(sp, cnt, LEVEL_ANNULUS, .fmul = 1 + 1, .fdiv = 1 + 1 + 1, .fadd = 2 + 2, .branches = 2 + 2);
    double rho;
    if (e <= c->g_e_full_deg) {
        rho = 1.0;
    } else if (e >= c->g_e_edge_deg) {
        rho = c->g_rho_min;
    } else {
        double x = (e - c->g_e_full_deg) / c->g_sigma_deg;
        rho = c->g_rho_min + (1.0 - c->g_rho_min) * exp(-0.5 * x * x);
        vr_libm(sp, cnt);
        /* (e - full) / sigma; -0.5 x x; min + (1 - min) exp (1 - min hoisted) */
        VR_SPAN(sp, cnt, LEVEL_FALLOFF, .fadd = 1 + 1, .fdiv = 1, .fmul = 2 + 1);
    }
    double level = 0.5 * log2(1.0 / rho);
    vr_libm(sp, cnt);
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

/* Fills both tables.  Spans: TABLE_DIST per entry of the distance table,
 * TABLE_LEVEL per entry of the level table (plus vr_gaze_level's). */
static inline void vr_level_tables_fill(const vr_config_t *c, vr_level_tables_t *t, vr_spans_t *sp,
                                        vr_count_t *cnt)
{
    for (int dy = 0; dy < t->h; dy++)
        for (int dx = 0; dx < t->w; dx++) {
            t->dist[(size_t)dy * t->w + dx] =
                (uint16_t)floor(sqrt((double)dx * dx + (double)dy * dy) * VR_TABLE_STEPS + 0.5);
            /* 2 conversions, 2 multiplies and an add, sqrt, x steps, + 0.5,
             * floor and conversion; the index (multiply, add) and the store;
             * the inner loop (increment, test) */
            VR_SPAN(sp, cnt, TABLE_DIST, .int_ops = 2 + 2 + 2 + 2, .fmul = 2 + 1, .fadd = 1 + 1, .fsqrt = 1,
                    .stores = 1, .branches = 1);
        }
    int trans = 0;
    for (int k = 0; k < t->n; k++) {
        trans = 0;
        t->level[k] = vr_gaze_level(c, (double)k / VR_TABLE_STEPS, &trans, sp, cnt);
        /* k / steps (conversion, multiply by 1/4), the store, the loop */
        VR_SPAN(sp, cnt, TABLE_LEVEL, .int_ops = 1 + 2, .fmul = 1, .stores = 1, .branches = 1);
    }
    t->level_far = vr_gaze_level(c, INFINITY, &trans, NULL, NULL);
}

/* Allocates and fills both tables for offsets within a w x h image (the
 * fill charged to the GP now: once per sequence). */
static inline fw_status_t vr_level_tables_build(gp_t *gp, const vr_config_t *c, int w, int h,
                                                vr_level_tables_t *t)
{
    t->w = w;
    t->h = h;
    t->n = vr_level_tables_entries(c, t->w, t->h);
    t->dist = fw_alloc(gp, (size_t)t->w * (size_t)t->h * sizeof *t->dist);
    t->level = fw_alloc(gp, (size_t)t->n * sizeof *t->level);
    if (!t->dist || !t->level)
        return FW_ERROR;
    vr_spans_t sp;
    memset(&sp, 0, sizeof sp);
    vr_level_tables_fill(c, t, &sp, NULL);
    fw_ops_t ops = {0};
    vr_spans_charge(&ops, &sp);
    fw_charge(gp, &ops);
    return FW_OK;
}

/* 2DLevel of a pixel from the tables.  Spans: LEVEL_TABLE per pixel,
 * LEVEL_TABLE_FAR for an offset outside the distance table. */
static inline float vr_level_tabled(const vr_level_tables_t *t, int dx, int dy, double scale,
                                    vr_spans_t *sp, vr_count_t *cnt)
{
    dx = dx < 0 ? -dx : dx;
    dy = dy < 0 ? -dy : dy;
    /* the caller's two offsets (subtract); two absolute values (compare,
     * negate); the offset inside the table (2 compares); the far test; d's
     * conversion; the scale test; k < n (compare), and the level (index
     * shift, load: the caller compares it at once) */
    VR_SPAN(sp, cnt, LEVEL_TABLE, .int_ops = 2 + 4 + 2 + 1 + 1 + 1, .branches = 2 + 2 + 1 + 1 + 1,
            .loads = 1, .load_use = 1, .fadd = 1 + 1);
    double d;
    if (dx < t->w && dy < t->h) {
        d = (double)t->dist[(size_t)dy * (size_t)t->w + (size_t)dx];
        /* index (multiply, add), the 16-bit load (the conversion needs it
         * at once), the conversion */
        VR_SPAN(sp, cnt, LEVEL_TABLE_NEAR, .int_ops = 2 + 1, .loads = 1, .load_use = 1);
    } else {
        d = floor(sqrt((double)dx * dx + (double)dy * dy) * VR_TABLE_STEPS + 0.5);
        /* the same arithmetic as a table entry */
        VR_SPAN(sp, cnt, LEVEL_TABLE_FAR, .int_ops = 2 + 1, .fmul = 2 + 1, .fadd = 1 + 1, .fsqrt = 1);
    }
    if (d >= 4294967295.0)
        return t->level_far;
    unsigned k = (unsigned)d;
    if (scale != 1.0) {
        k = (unsigned)((double)k / scale + 0.5);
        VR_SPAN(sp, cnt, LEVEL_TABLE_SCALED, .int_ops = 2, .fdiv = 1, .fadd = 1);
    }
    return k < (unsigned)t->n ? t->level[k] : t->level_far;
}

/* camera_ray (render/raycast.c).  Span RAY (parallel) or RAY_PERSPECTIVE.
 * Expressions of the frame's constants alone (0.5 width, radius + 1) are
 * computed once per pass, not per ray; the basis vectors are loaded per ray. */
static inline void vr_camera_ray(const vr_frame_t *f, int width, int height, float px, float py,
                                 float origin[3], float dir[3], vr_spans_t *sp, vr_count_t *cnt)
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
        /* dx, dy (subtract, multiply; the pixel size loaded); P: 9 basis
         * loads, 6 multiply-adds; the projection test; origin: 3 forward
         * loads, 3 multiply-subtracts (dir is the same registers) */
        VR_SPAN(sp, cnt, RAY, .fadd = 2 + 6 + 3, .fmul = 2 + 6 + 3, .loads = 1 + 9 + 3, .branches = 1);
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
    /* dx, dy and P as above; the projection test; P - eye (3 eye loads), the
     * squared length, sqrt, 3 divides */
    VR_SPAN(sp, cnt, RAY_PERSPECTIVE, .fadd = 2 + 6 + 3 + 3, .fmul = 2 + 6 + 3, .loads = 1 + 9 + 3,
            .branches = 1, .fsqrt = 1, .fdiv = 3);
}

/* clip_box (render/raycast.c).  Spans: CLIP_AXIS per axis the ray crosses,
 * CLIP_FLAT per axis it runs parallel to, CLIP_END once both bounds are
 * known. */
static inline bool vr_clip_box(const float o[3], const float d[3], const float hi[3], float *t0,
                               float *t1, vr_spans_t *sp, vr_count_t *cnt)
{
    float a = -INFINITY, b = INFINITY;
    for (int k = 0; k < 3; k++) {
        if (d[k] == 0.0f) {
            /* d == 0, the two bound tests (both counted), the bound's load */
            VR_SPAN(sp, cnt, CLIP_FLAT, .fadd = 1 + 2, .branches = 1 + 2, .loads = 1);
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
        /* d == 0; two subtracts and divides (the bound loaded); the swap and
         * the two bound updates (compare, branch; moves in delay slots) */
        VR_SPAN(sp, cnt, CLIP_AXIS, .fadd = 1 + 2 + 3, .fdiv = 2, .loads = 1, .branches = 1 + 3);
    }
    if (a < 0.0f)
        a = 0.0f;
    *t0 = a;
    *t1 = b;
    VR_SPAN(sp, cnt, CLIP_END, .fadd = 2, .branches = 2);
    return a <= b;
}

/* 2^-n for 0 <= n < 127, built from its bits (exact). */
static inline float vr_pow2_neg(int n)
{
    union {
        uint32_t u;
        float f;
    } v = {(uint32_t)(127 - n) << 23};
    return v.f;
}

/* mip3d_level_coord (render/mip3d.h), which divides by 2^n.  Multiplying
 * by 2^-n gives the same float: both round the same real number, since
 * 2^-n is exact (host speed only: a multiply instead of a divide). */
static inline float vr_level_coord(float p, int n)
{
    return (p + 0.5f) * vr_pow2_neg(n) - 0.5f;
}

#endif
