/* vr_blend_kernels.h: MIP, depth-enhanced MIP and MIDA rays on the fetched value pyramid (render/blend_ray.h's per-ray maths and render/blend_trace.c's sample lattice, restated operation for operation), counted by spans of common/vr_cost.h.
 *
 * The GP program (vr_cast.c) and tests/test_fw_cost.c both call these (see
 * vr_cast_kernels.h for the counting).  A fetched unit of a blend holds one
 * float per voxel: the value pyramid's value, bit for bit (setup stores the
 * float's bits in the backing-store word), so every sample here is the float
 * render/'s scalar_pyramid_sample computes, and every float expression below
 * is render/'s own in the same order: the images agree bit for bit
 * (tests/test_fw_blend.c; firmware/ARCHITECTURE.md "Blends").
 *
 * Skipping.  A blend ray passes only cells whose voxels are all cold (value
 * <= cfg.cold_below, which makes every sample there material 0: nothing
 * there can raise ray 1's maximum, stop ray 2, change MIDA's colour, and
 * every such sample is a gap for reading B).  The octree grids of a blend
 * mark the voxels that are not cold (vr_setup.c), so the compositing
 * octree's walk (vr_oct_empty_node, vr_ray_skip) serves unchanged.  The host
 * turns skipping off (cold_below = -inf, use_octree = 0) where a sample
 * could read two 3D levels (perspective, a sample step that is not a power
 * of two): the grids are per level.  Paper: seed 002 §3 (ray 1, ray 2,
 * eq. (1), eq. (2)); MIDA: Bruckner & Gröller 2009. */
#ifndef PP5_VR_BLEND_KERNELS_H
#define PP5_VR_BLEND_KERNELS_H

#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "vr_cast_kernels.h"

/* What a blend ray reports beyond its colour (the published statistics). */
typedef struct {
    uint64_t ray2_samples;        /* DEMIP: samples of ray 2 and of reading B's gap test */
    uint64_t saturated;           /* MIP/DEMIP rays stopped at m_max = 1 */
    uint64_t occluded;            /* DEMIP reading B: rays that met an occluder */
    uint64_t terminated;          /* MIDA rays stopped early (opacity and maximum) */
} vr_blend_tally_t;

/* A corner of a value lookup in unit `id` at word `word`: the float the
 * word holds.  Its unit lookup is VALUE_TRILERP's.  An absent unit is never
 * read by a drawn sample (its voxels are read only from cold cells, which
 * are skipped: vr_units.c), so its 0 is never used. */
static inline float vr_value_corner(const vr_state_t *s, int id, size_t word, const vr_mem_t *mem,
                                    vr_spans_t *sp, vr_count_t *cnt)
{
    const uint32_t *b = s->cache[id];
    /* the pointer (shift, load: the test needs it at once), the test */
    VR_COUNT(cnt, VALUE_TRILERP, .int_ops = 1, .loads = 1, .load_use = 1, .branches = 1);
    if (!b)
        return 0.0f;
    vr_mem_access(mem, b, word * 4, 4, 0);
    float v;
    memcpy(&v, &b[word], sizeof v);
    /* the word's address (shift) and its load into an FP register (the
     * lerps come after the eighth corner: no stall) */
    VR_SPAN(sp, cnt, VALUE_CORNER, .int_ops = 1, .loads = 1);
    return v;
}

/* scalar_trilerp (render/scalar_pyramid.h) at level-0 position p in 3D
 * level n, from the units in the cache: vr_trilerp's addressing, one
 * component.  Span VALUE_TRILERP (+ VALUE_CORNER per corner in a held unit). */
static inline float vr_value_trilerp(const vr_state_t *s, int n, const float p[3],
                                     const vr_mem_t *mem, vr_spans_t *sp, vr_count_t *cnt)
{
    const vr_level_geom_t *L = &s->geom[n];
    const vr_unit_geom_t *u = &s->unit[n];
    float x = vr_level_coord(p[0], n), y = vr_level_coord(p[1], n), z = vr_level_coord(p[2], n);
    float fx = floorf(x), fy = floorf(y), fz = floorf(z);
    float wx = x - fx, wy = y - fy, wz = z - fz;
    int x0 = (int)fx, y0 = (int)fy, z0 = (int)fz;
    int cx[2] = {vr_clampi(x0, L->nx), vr_clampi(x0 + 1, L->nx)};
    int cy[2] = {vr_clampi(y0, L->ny), vr_clampi(y0 + 1, L->ny)};
    int cz[2] = {vr_clampi(z0, L->nz), vr_clampi(z0 + 1, L->nz)};
    /* as vr_trilerp: 3 level coordinates, floors, weights, conversions, 3
     * increments, the dims (3 loads) and 6 clamps */
    VR_SPAN(sp, cnt, VALUE_TRILERP, .fadd = 3 * 2 + 3, .fmul = 3, .loads = 1 + 3,
            .int_ops = 3 + 3 + 3 + 6 * 2, .branches = 6 * 2);
    int ux[2], lx[2], uy[2], ly[2], uz[2], lz[2];
    for (int k = 0; k < 2; k++) {
        ux[k] = cx[k] / u->ux;
        lx[k] = cx[k] - ux[k] * u->ux;
        uy[k] = cy[k] / u->uy;
        ly[k] = cy[k] - uy[k] * u->uy;
        uz[k] = cz[k] / u->uz;
        lz[k] = cz[k] - uz[k] * u->uz;
    }
    int base = s->unit_base[n];
    float c[8];
    for (int dz = 0; dz < 2; dz++)
        for (int dy = 0; dy < 2; dy++) {
            int row = base + (uz[dz] * u->ugy + uy[dy]) * u->ugx;
            size_t woff = ((size_t)lz[dz] * u->uy + ly[dy]) * u->ux;
            for (int dx = 0; dx < 2; dx++)
                c[(dz * 2 + dy) * 2 + dx] = vr_value_corner(s, row + ux[dx], woff + (size_t)lx[dx],
                                                            mem, sp, cnt);
        }
    /* the corners' units and offsets as vr_trilerp's */
    VR_COUNT(cnt, VALUE_TRILERP, .int_ops = 6 * 3 + 4 * 4 + 4 * 3 + 8 * 2, .loads = 3 + 3);
    float a = c[0] + wx * (c[1] - c[0]);
    float b = c[2] + wx * (c[3] - c[2]);
    float cc = c[4] + wx * (c[5] - c[4]);
    float d = c[6] + wx * (c[7] - c[6]);
    float e = a + wy * (b - a);
    float f = cc + wy * (d - cc);
    VR_COUNT(cnt, VALUE_TRILERP, .fadd = 7 * 2, .fmul = 7);   /* 7 lerps */
    return e + wz * (f - e);
}

/* scalar_pyramid_sample: the value at p between 3D levels, then its
 * material (blend_material).  Spans VALUE_POINT, MATERIAL (+ VALUE_TRILERP,
 * VALUE_LEVEL_BLEND). */
static inline float vr_value_material(const vr_state_t *s, float level3d, const float p[3],
                                      const vr_mem_t *mem, vr_spans_t *sp, vr_count_t *cnt)
{
    int lo;
    float t = vr_level_split(s, level3d, &lo);
    /* the clamp (2 compares), the conversions, t; the blend test (compare,
     * lo + 1 against the levels) */
    VR_SPAN(sp, cnt, VALUE_POINT, .fadd = 2 + 1 + 1, .branches = 2 + 2, .int_ops = 2 + 2);
    float v = vr_value_trilerp(s, lo, p, mem, sp, cnt);
    if (t > 0.0f && lo + 1 < s->cfg.levels) {
        float w = vr_value_trilerp(s, lo + 1, p, mem, sp, cnt);
        v += t * (w - v);
        VR_SPAN(sp, cnt, VALUE_LEVEL_BLEND, .fadd = 2, .fmul = 1);
    }
    float m = (v - s->cfg.window_lo) * s->cfg.window_inv_width;
    /* subtract and multiply (the window in registers); the clamp's two
     * compares */
    VR_SPAN(sp, cnt, MATERIAL, .fadd = 1 + 2, .fmul = 1, .branches = 2);
    if (!(m > 0.0f))
        return 0.0f;
    return m < 1.0f ? m : 1.0f;
}

/* A blend ray: the lattice (vr_ray_t: voxel-space ray, t0, t1, t, sample
 * index k, spacing, 3D level) and the object-space ray DEMIP's depth and
 * sphere need. */
typedef struct {
    vr_ray_t r;
    float o[3], d[3];
    float t_start;                /* the lattice's first position (ray 2 restarts there) */
} vr_blend_ray_t;

/* blend_geom_begin (render/blend_trace.c).  False when the ray misses the
 * volume: its texel is then black (RAY_MISS).  Spans: vr_camera_ray's,
 * vr_clip_box's, BLEND_START (+ RAY_NEAR). */
static inline bool vr_blend_begin(const vr_state_t *s, const vr_ray_consts_t *rc, float px,
                                  float py, vr_ray_slot_t slot, vr_blend_ray_t *b,
                                  const vr_mem_t *mem, vr_spans_t *sp, vr_count_t *cnt)
{
    const vr_config_t *c = &s->cfg;
    vr_ray_t *r = &b->r;
    vr_camera_ray(&s->fr, c->width, c->height, px, py, b->o, b->d, sp, cnt);
    if (!vr_clip_box(b->o, b->d, s->fr.box_hi, &r->t0, &r->t1, sp, cnt)) {
        float *rgb = s->texel[slot.m] + slot.idx * 3;
        rgb[0] = rgb[1] = rgb[2] = 0.0f;
        vr_mem_access(mem, s->texel[slot.m], slot.idx * 12, 12, 1);
        VR_SPAN(sp, cnt, RAY_MISS, .branches = 1, .stores = 3);
        return false;
    }
    for (int k = 0; k < 3; k++) {
        r->ov[k] = b->o[k] * c->inv_spacing[k];
        r->dv[k] = b->d[k] * c->inv_spacing[k];
    }
    r->k = 0;
    r->t = r->t0;
    r->spacing = rc->base;
    r->level3d = rc->level3d;
    /* voxel-space origin and direction (3 loads, 6 multiplies); the
     * projection test */
    VR_SPAN(sp, cnt, BLEND_START, .loads = 3, .fmul = 6, .branches = 1);
    if (rc->perspective) {
        if (r->t < 1e-3f)
            r->t = 1e-3f;
        VR_SPAN(sp, cnt, RAY_NEAR, .fadd = 1, .branches = 1);
    }
    b->t_start = r->t;
    return true;
}

/* walk_material's position: the sample at the ray's t (and under
 * perspective its spacing and 3D level).  Spans BLEND_SAMPLE (+
 * SAMPLE_PERSPECTIVE, LIBM). */
static inline void vr_blend_position(const vr_ray_consts_t *rc, vr_ray_t *r, float p[3],
                                     vr_spans_t *sp, vr_count_t *cnt)
{
    /* the caller's loop test (compare), the projection test, the skipping
     * test; the position (3 multiply-adds) */
    VR_SPAN(sp, cnt, BLEND_SAMPLE, .fadd = 1 + 3, .fmul = 3, .branches = 1 + 1 + 1);
    if (rc->perspective) {
        r->spacing = r->t * (rc->growth - 1.0f);
        float level3d = log2f(r->spacing) - rc->offset;
        r->level3d = level3d < 0.0f ? 0.0f : (level3d > rc->top ? rc->top : level3d);
        vr_libm(sp, cnt);
        VR_SPAN(sp, cnt, SAMPLE_PERSPECTIVE, .fmul = 1, .fadd = 1 + 2, .branches = 2);
    }
    p[0] = r->ov[0] + r->t * r->dv[0];
    p[1] = r->ov[1] + r->t * r->dv[1];
    p[2] = r->ov[2] + r->t * r->dv[2];
}

/* walk_next: the next position of the lattice.  Span STEP (parallel) or
 * BLEND_STEP_PERSPECTIVE. */
static inline void vr_blend_next(const vr_ray_consts_t *rc, vr_ray_t *r, vr_spans_t *sp,
                                 vr_count_t *cnt)
{
    r->k++;
    if (rc->perspective) {
        r->t *= rc->growth;
        VR_SPAN(sp, cnt, BLEND_STEP_PERSPECTIVE, .fmul = 1, .int_ops = 1, .branches = 1);
    } else {
        r->t = r->t0 + (float)r->k * rc->base;
        VR_SPAN(sp, cnt, STEP, .int_ops = 1 + 1, .fmul = 1, .fadd = 1, .branches = 1);
    }
}

/* The skipping test at position p: 0 when the cell may hold material
 * (sample it), 1 when the ray jumped past a cold node, -1 when that jump
 * left the volume.  Spans as the compositing march's octree test. */
static inline int vr_blend_skip(const vr_state_t *s, const vr_ray_consts_t *rc, vr_ray_t *r,
                                const float p[3], const vr_mem_t *mem, vr_spans_t *sp,
                                vr_count_t *cnt, uint64_t *skipped)
{
    float lo[3], hi[3];
    int n = (int)r->level3d;
    bool exact = r->level3d == (float)n;
    /* n (conversion), exact (conversion, compare); the result's test */
    VR_SPAN(sp, cnt, OCT_LEAF, .int_ops = 2 + 1, .fadd = 1, .branches = 1);
    if (!exact || vr_oct_empty_node(s, n, true, p, lo, hi, mem, sp, cnt) < 0)
        return 0;
    return vr_ray_skip(rc, n, lo, hi, r, sp, cnt, skipped) ? 1 : -1;
}

/* Ray 1 (mip_ray_sample) from the ray's current position to its end or to
 * m_max = 1.  Spans BLEND_SAMPLE and MIP_SAMPLE per position sampled (+ the
 * lookup's, the skips'). */
static inline void vr_mip_march(const vr_state_t *s, const vr_ray_consts_t *rc, vr_ray_t *r,
                                float *m_max, long *k_max, const vr_mem_t *mem, vr_spans_t *sp,
                                vr_count_t *cnt, uint64_t *skipped)
{
    bool skipping = s->cfg.use_octree != 0;
    while (r->t <= r->t1) {
        float p[3];
        vr_blend_position(rc, r, p, sp, cnt);
        if (skipping) {
            int k = vr_blend_skip(s, rc, r, p, mem, sp, cnt, skipped);
            if (k < 0)
                break;
            if (k > 0)
                continue;
        }
        float m = vr_value_material(s, r->level3d, p, mem, sp, cnt);
        if (m > *m_max) {
            *m_max = m;
            *k_max = r->k;
        }
        /* the maximum's compare (the two moves in delay slots), m_max >= 1 */
        VR_SPAN(sp, cnt, MIP_SAMPLE, .fadd = 1 + 1, .branches = 1 + 1);
        if (*m_max >= 1.0f)
            break;
        vr_blend_next(rc, r, sp, cnt);
    }
}

/* Ray 2 (demip_ray2_stops) from the lattice's first position: the first
 * sample with m > 0 and m >= threshold, at k_max at the latest.  Leaves the
 * ray at its stop.  Spans BLEND_SAMPLE and RAY2_TEST per position sampled. */
static inline void vr_ray2_march(const vr_state_t *s, const vr_ray_consts_t *rc,
                                 vr_blend_ray_t *b, float threshold, const vr_mem_t *mem,
                                 vr_spans_t *sp, vr_count_t *cnt, uint64_t *skipped,
                                 vr_blend_tally_t *tally)
{
    vr_ray_t *r = &b->r;
    bool skipping = s->cfg.use_octree != 0;
    r->k = 0;
    r->t = b->t_start;
    while (r->t <= r->t1) {
        float p[3];
        vr_blend_position(rc, r, p, sp, cnt);
        if (skipping) {
            int k = vr_blend_skip(s, rc, r, p, mem, sp, cnt, skipped);
            if (k < 0)
                break;
            if (k > 0)
                continue;
        }
        float m = vr_value_material(s, r->level3d, p, mem, sp, cnt);
        tally->ray2_samples++;
        /* m > 0 (the branch), m >= threshold (compare) */
        VR_SPAN(sp, cnt, RAY2_TEST, .fadd = 1, .branches = 1 + 1);
        if (m > 0.0f && m >= threshold)
            return;
        vr_blend_next(rc, r, sp, cnt);
    }
}

/* Reading B's occluder test: a sample below the threshold (a gap) between
 * ray 2's stop and k_max.  A cold cell is a gap at once.  Spans GAP_TEST
 * per position (+ BLEND_SAMPLE and the lookup's). */
static inline bool vr_gap_scan(const vr_state_t *s, const vr_ray_consts_t *rc, vr_ray_t *r,
                               long k_max, float threshold, const vr_mem_t *mem, vr_spans_t *sp,
                               vr_count_t *cnt, uint64_t *skipped, vr_blend_tally_t *tally)
{
    bool skipping = s->cfg.use_octree != 0;
    for (vr_blend_next(rc, r, sp, cnt);; vr_blend_next(rc, r, sp, cnt)) {
        /* k < k_max (compare) */
        VR_SPAN(sp, cnt, GAP_TEST, .int_ops = 1, .branches = 1);
        if (r->k >= k_max)
            return false;
        float p[3];
        vr_blend_position(rc, r, p, sp, cnt);
        if (skipping) {
            float lo[3], hi[3];
            int n = (int)r->level3d;
            bool exact = r->level3d == (float)n;
            VR_SPAN(sp, cnt, OCT_LEAF, .int_ops = 2 + 1, .fadd = 1, .branches = 1);
            if (exact && vr_oct_empty_node(s, n, true, p, lo, hi, mem, sp, cnt) >= 0) {
                (*skipped)++;
                return true;
            }
        }
        float m = vr_value_material(s, r->level3d, p, mem, sp, cnt);
        tally->ray2_samples++;
        /* demip_is_gap: !(m > 0 && m >= threshold) */
        VR_SPAN(sp, cnt, RAY2_TEST, .fadd = 1, .branches = 1 + 1);
        if (!(m > 0.0f && m >= threshold))
            return true;
    }
}

static inline float vr_clamp01(float x)
{
    return x <= 0.0f ? 0.0f : (x >= 1.0f ? 1.0f : x);
}

/* demip_colour (render/blend_ray.c): the depth of ray 2's point t_hit,
 * eq. (1) where the reading applies it, eq. (2) with the colour sphere.
 * Spans DEMIP_POINT, DEPTH_AXIS or DEPTH_EYE or DEPTH_ENTRY, DEMIP_GREY
 * (+ EQ1), SPHERE or NO_SPHERE. */
static inline void vr_demip_colour(const vr_state_t *s, const vr_blend_ray_t *b, float t_hit,
                                   float m_max, bool occluded, float rgb[3], vr_spans_t *sp,
                                   vr_count_t *cnt)
{
    const vr_config_t *c = &s->cfg;
    const vr_frame_t *f = &s->fr;
    float p[3];
    for (int a = 0; a < 3; a++)
        p[a] = b->o[a] + t_hit * b->d[a];
    /* 3 multiply-adds; the depth's kind test */
    VR_SPAN(sp, cnt, DEMIP_POINT, .fadd = 3, .fmul = 3, .branches = 1);
    float depth;
    if (c->depth == VR_DEPTH_EXACT) {
        float dd;
        if (f->projection) {
            float q[3] = {p[0] - f->eye[0], p[1] - f->eye[1], p[2] - f->eye[2]};
            dd = sqrtf(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
            /* the projection test; 3 eye loads and subtracts, the squared
             * length, sqrt; the normalisation (2 loads, subtract, multiply)
             * and its clamp (2 compares) */
            VR_SPAN(sp, cnt, DEPTH_EYE, .branches = 1 + 2, .loads = 3 + 2, .fadd = 3 + 2 + 1 + 2,
                    .fmul = 3 + 1, .fsqrt = 1);
        } else {
            dd = p[0] * f->forward[0] + p[1] * f->forward[1] + p[2] * f->forward[2];
            /* the projection test; the dot product with forward (3 loads);
             * the normalisation and its clamp */
            VR_SPAN(sp, cnt, DEPTH_AXIS, .branches = 1 + 2, .loads = 3 + 2, .fadd = 2 + 1 + 2,
                    .fmul = 3 + 1);
        }
        depth = vr_clamp01((dd - f->exact_near) * f->exact_inv_range);
    } else {
        float e[3];
        for (int a = 0; a < 3; a++)
            e[a] = b->o[a] + b->r.t0 * b->d[a];
        float entry = (e[0] * f->forward[0] + e[1] * f->forward[1] + e[2] * f->forward[2] -
                       f->axis_near) * f->axis_inv_range;
        depth = vr_clamp01(entry + (t_hit - b->r.t0) * f->axis_inv_range);
        /* the entry (3 multiply-adds), its view-axis depth (3 loads, dot,
         * 2 loads, subtract, multiply), the length (subtract, multiply,
         * add), the clamp */
        VR_SPAN(sp, cnt, DEPTH_ENTRY, .fadd = 3 + 2 + 1 + 2 + 2, .fmul = 3 + 3 + 1 + 1,
                .loads = 3 + 2, .branches = 2);
    }
    bool eq1 = c->reading == VR_READING_A || occluded;
    /* the reading and occluder tests (both counted) */
    VR_SPAN(sp, cnt, DEMIP_GREY, .branches = 2);
    float grey = m_max;
    if (eq1) {
        float dw = c->dw;
        float g = m_max * (1.0f - dw) + 2.0f * dw * (1.0f - depth);
        grey = g <= 0.0f ? 0.0f : (g >= 1.0f ? 1.0f : g);
        /* dw loaded; 1 - dw, 2 dw, 1 - depth, 3 multiplies, the sum; the
         * clamp's two compares */
        VR_SPAN(sp, cnt, EQ1, .loads = 1, .fadd = 3 + 2, .fmul = 3, .branches = 2);
    }
    if (!(c->sw > 0.0f)) {
        rgb[0] = rgb[1] = rgb[2] = grey;
        VR_SPAN(sp, cnt, NO_SPHERE, .loads = 1, .fadd = 1, .branches = 1);
        return;
    }
    /* colour_sphere_colour at dir = p - centre, then eq. (2) */
    float dir[3] = {p[0] - f->centre[0], p[1] - f->centre[1], p[2] - f->centre[2]}, sph[3];
    float len = sqrtf(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    float cs = len > 0.0f ? (dir[0] * c->sphere_pole[0] + dir[1] * c->sphere_pole[1] +
                             dir[2] * c->sphere_pole[2]) / len
                          : 0.0f;
    cs = cs < -1.0f ? -1.0f : (cs > 1.0f ? 1.0f : cs);
    float ff = 0.5f * (1.0f + cs);
    for (int k = 0; k < 3; k++)
        sph[k] = c->sphere_back[k] + ff * (c->sphere_front[k] - c->sphere_back[k]);
    float sw = c->sw;
    for (int k = 0; k < 3; k++)
        rgb[k] = grey * (1.0f - sw) + sph[k] * sw;
    /* sw loaded, sw > 0; dir (3 centre loads, 3 subtracts), |dir| (3
     * multiplies, 2 adds, sqrt), len > 0, the dot with the pole (3 loads, 3
     * multiplies, 2 adds) and the divide (both sides of the select), the
     * clamp (2 compares), 1 + c and 0.5 x; per channel the front and back
     * loads, their difference, multiply-add; 1 - sw and per channel two
     * multiplies and an add */
    VR_SPAN(sp, cnt, SPHERE, .loads = 1 + 3 + 3 + 6, .fadd = 1 + 3 + 2 + 2 + 2 + 1 + 3 * 2 + 1 + 3,
            .fmul = 3 + 3 + 1 + 3 + 6, .fsqrt = 1, .fdiv = 1, .branches = 1 + 1 + 2);
}

/* mida_opacity: the opacity of a sample of material m standing for
 * `spacing` object units.  Spans MIDA_OPACITY, then MIDA_RAMP (+
 * MIDA_POW, LIBM) when neither short cut applies. */
static inline float vr_mida_opacity(float m, float spacing, vr_spans_t *sp, vr_count_t *cnt)
{
    /* spacing == 1 and m <= 0: equality and zero tests (branches) */
    VR_SPAN(sp, cnt, MIDA_OPACITY, .branches = 2);
    if (spacing == 1.0f || m <= 0.0f)
        return m;
    VR_SPAN(sp, cnt, MIDA_RAMP, .fadd = 1, .branches = 1);   /* m >= 1 */
    if (m >= 1.0f)
        return 1.0f;
    vr_libm(sp, cnt);
    VR_SPAN(sp, cnt, MIDA_POW, .fadd = 2);                   /* 1 - m, 1 - powf */
    return 1.0f - powf(1.0f - m, spacing);
}

/* MIDA (mida_ray_sample) from the ray's current position to its end or
 * early termination.  Spans BLEND_SAMPLE, MIDA_SAMPLE per position sampled
 * (+ the lookup's, the opacity's, the skips'). */
static inline void vr_mida_march(const vr_state_t *s, const vr_ray_consts_t *rc, vr_ray_t *r,
                                 float *colour, const vr_mem_t *mem, vr_spans_t *sp,
                                 vr_count_t *cnt, uint64_t *skipped, vr_blend_tally_t *tally)
{
    bool skipping = s->cfg.use_octree != 0;
    float C = 0.0f, A = 0.0f, f_max = 0.0f, et = s->cfg.early_termination;
    while (r->t <= r->t1) {
        float p[3];
        vr_blend_position(rc, r, p, sp, cnt);
        if (skipping) {
            int k = vr_blend_skip(s, rc, r, p, mem, sp, cnt, skipped);
            if (k < 0)
                break;
            if (k > 0)
                continue;
        }
        float f = vr_value_material(s, r->level3d, p, mem, sp, cnt);
        float a = vr_mida_opacity(f, r->spacing, sp, cnt);
        float delta = f > f_max ? f - f_max : 0.0f;
        float beta = 1.0f - delta;
        float w = (1.0f - beta * A) * a;
        C = beta * C + w * f;
        A = beta * A + w;
        if (f > f_max)
            f_max = f;
        /* f > f_max (compare; the second use is the same flag) and f -
         * f_max; 1 - delta; beta A, 1 -, x a; beta C + w f; beta A + w; the
         * two termination compares */
        VR_SPAN(sp, cnt, MIDA_SAMPLE, .fadd = 1 + 1 + 1 + 1 + 1 + 1 + 2, .fmul = 1 + 1 + 2,
                .branches = 1 + 2);
        if (A >= et && f_max >= et) {
            tally->terminated++;
            break;
        }
        vr_blend_next(rc, r, sp, cnt);
    }
    *colour = C;
}

/* One blend ray of texel slot (render/blend_trace.c's reference tracer,
 * skipping only cold cells): its grey or DEMIP colour into the texel.
 * *skipped counts the sample positions passed (a statistic).  Spans: every
 * row of the blends' ray block of vr_cost.h (+ RAY_END). */
static inline void vr_blend_trace(const vr_state_t *s, const vr_ray_consts_t *rc, float px,
                                  float py, vr_ray_slot_t slot, const vr_mem_t *mem,
                                  vr_spans_t *sp, vr_count_t *cnt, uint64_t *skipped,
                                  vr_blend_tally_t *tally)
{
    vr_blend_ray_t b;
    if (!vr_blend_begin(s, rc, px, py, slot, &b, mem, sp, cnt))
        return;
    float rgb[3], grey = 0.0f;
    int mode = s->cfg.blend;
    if (mode == VR_BLEND_MIDA) {
        vr_mida_march(s, rc, &b.r, &grey, mem, sp, cnt, skipped, tally);
        rgb[0] = rgb[1] = rgb[2] = grey;
    } else {
        float m_max = 0.0f;
        long k_max = -1;
        vr_mip_march(s, rc, &b.r, &m_max, &k_max, mem, sp, cnt, skipped);
        tally->saturated += m_max >= 1.0f;
        rgb[0] = rgb[1] = rgb[2] = m_max;
        /* the mode test (equality) and k_max >= 0 (compare) */
        VR_SPAN(sp, cnt, MIP_END, .int_ops = 1, .branches = 2);
        if (mode == VR_BLEND_DEMIP && k_max >= 0) {
            float threshold = m_max - s->cfg.eps;
            /* the threshold (eps loaded, subtract); the reading test */
            VR_SPAN(sp, cnt, RAY2_START, .loads = 1, .fadd = 1, .branches = 1);
            vr_ray2_march(s, rc, &b, threshold, mem, sp, cnt, skipped, tally);
            float t_hit = b.r.t;
            bool occluded = false;
            if (s->cfg.reading == VR_READING_B)
                occluded = vr_gap_scan(s, rc, &b.r, k_max, threshold, mem, sp, cnt, skipped,
                                       tally);
            tally->occluded += occluded;
            vr_demip_colour(s, &b, t_hit, m_max, occluded, rgb, sp, cnt);
        }
    }
    float *dst = s->texel[slot.m] + slot.idx * 3;
    dst[0] = rgb[0];
    dst[1] = rgb[1];
    dst[2] = rgb[2];
    vr_mem_access(mem, s->texel[slot.m], slot.idx * 12, 12, 1);
    VR_SPAN(sp, cnt, RAY_END, .stores = 3);
}

#endif
