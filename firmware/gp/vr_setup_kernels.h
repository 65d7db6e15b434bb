/* vr_setup_kernels.h: the once-per-sequence kernels of the mip-map build: a level-0 voxel (gradient, classification, shading), the 2x2x2 box filter, quantisation to the backing-store formats, the opacity-correction tables; counted by spans of common/vr_cost.h.
 *
 * Called by vr_setup.c and by tests/test_fw_cost.c (see vr_cast_kernels.h
 * for the counting).  The slab's reads are declared to the data cache; the
 * strips and levels the build writes and the filter reads are not (taken as
 * hits).  render/mip3d.c is the reference: every float operation is in its
 * order, so the GPs' mip map equals render/'s. */
#ifndef PP5_VR_SETUP_KERNELS_H
#define PP5_VR_SETUP_KERNELS_H

#include <math.h>
#include <stddef.h>
#include <string.h>

#include "vr_cast_kernels.h"
#include "vr_gp_internal.h"

/* Voxel (x, y, z) of the slab (the host's slices [data_z0, data_z1) in
 * local memory): index (subtract, 2 multiplies, 2 adds) and load, counted by
 * the caller's span. */
static inline float vr_slab_at(const vr_state_t *s, int x, int y, int z, const vr_mem_t *mem)
{
    const vr_config_t *c = &s->cfg;
    size_t i = ((size_t)(z - c->data_z0) * c->ny + y) * c->nx + x;
    vr_mem_access(mem, s->slab, i * 4, 4, 0);
    return s->slab[i];
}

/* Level-0 components of one voxel (render/mip3d.c mip3d_base_slice with
 * shade_gradient inlined) into o[0 .. stride).  Spans: VOXEL,
 * GRADIENT_AXIS per axis with two neighbours, vr_classify's, and ZERO per
 * component of a transparent voxel or SURFACE (+ SURFACE_NORMAL, vr_diffuse's)
 * for an opaque one. */
static inline void vr_base_voxel(const vr_state_t *s, int x, int y, int z, float *o,
                                 const vr_mem_t *mem, vr_spans_t *sp, vr_count_t *cnt)
{
    const vr_config_t *c = &s->cfg;
    int p[3] = {x, y, z}, n[3] = {c->nx, c->ny, c->nz};
    float g[3];
    /* the caller's x loop (increment, compare); per axis the neighbours
     * (compare and subtract; n - 1, compare, add), span, its zero test */
    VR_SPAN(sp, cnt, VOXEL, .int_ops = 2 + 3 * 6, .branches = 1 + 3 * 3);
    for (int a = 0; a < 3; a++) {
        int lo[3] = {x, y, z}, hi[3] = {x, y, z};
        lo[a] = p[a] > 0 ? p[a] - 1 : p[a];
        hi[a] = p[a] < n[a] - 1 ? p[a] + 1 : p[a];
        int span = hi[a] - lo[a];
        if (span == 0) {
            g[a] = 0.0f;
            continue;
        }
        float d = vr_slab_at(s, hi[0], hi[1], hi[2], mem) - vr_slab_at(s, lo[0], lo[1], lo[2], mem);
        g[a] = d / (float)span * c->inv_spacing[a];
        /* two slab indices and loads (the second used at once), the
         * difference, span's conversion, the divide and the spacing */
        VR_SPAN(sp, cnt, GRADIENT_AXIS, .int_ops = 2 * 5 + 1, .loads = 2, .load_use = 1, .fadd = 1, .fdiv = 1,
                .fmul = 1);
    }
    float rgb[3], nn[3] = {0.0f, 0.0f, 0.0f};
    float gm = sqrtf(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    float a = vr_classify(c, vr_slab_at(s, x, y, z, mem), gm, rgb, sp, cnt);
    /* |g| (3 multiplies, 2 adds, sqrt); the voxel's own value (index, load);
     * the opacity test */
    VR_COUNT(cnt, VOXEL, .fmul = 3, .fadd = 2 + 1, .fsqrt = 1, .int_ops = 5, .loads = 1, .branches = 1);
    if (a <= 0.0f) {
        for (int k = 0; k < s->stride; k++) {
            o[k] = 0.0f;
            VR_SPAN(sp, cnt, ZERO, .stores = 1);
        }
        return;
    }
    if (gm > 0.0f)
        for (int k = 0; k < 3; k++)
            nn[k] = g[k] / gm;
    float shade = 1.0f;
    if (c->lighting != VR_LIGHT_MOVING)
        shade = vr_diffuse(c, nn, c->light_dir, sp, cnt);
    for (int k = 0; k < 3; k++)
        o[k] = a * rgb[k] * shade;
    o[3] = a;
    /* gm > 0 and 3 divides (both sides of the select); the lighting test;
     * 3 x 2 multiplies; 4 stores; the stride test */
    VR_SPAN(sp, cnt, SURFACE, .fadd = 1, .fdiv = 3, .fmul = 6, .stores = 4, .branches = 1 + 1 + 1);
    if (s->stride == 8) {
        for (int k = 0; k < 3; k++)
            o[4 + k] = a * nn[k];
        o[7] = 0.0f;
        VR_SPAN(sp, cnt, SURFACE_NORMAL, .fmul = 3, .stores = 4);
    }
}

/* One output voxel (x, y, z) of the 2x2x2 box filter (mip3d_filter_slice):
 * the children in the finer level, whose rows are stored from slice z_off
 * and row y_off on, `rows` rows per slice, dims (snx, sny, snz).  Spans:
 * FILTER_LOOP per child coordinate tried, FILTER_CHILD per child,
 * FILTER_ADD per child component, FILTER_COMPONENT per output component. */
static inline void vr_filter_voxel(const float *src, int snx, int sny, int snz, int z_off, int y_off,
                                   int rows, int x, int y, int z, int stride, float *o,
                                   vr_spans_t *sp, vr_count_t *cnt)
{
    float acc[8] = {0};
    for (int dz = 0; dz < 2; dz++) {
        int cz = 2 * z + dz;
        /* the coordinate (add; 2z kept), its bound (compare); the two-step
         * loops are unrolled */
        VR_SPAN(sp, cnt, FILTER_LOOP, .int_ops = 1 + 1, .branches = 1);
        if (cz >= snz)
            continue;
        for (int dy = 0; dy < 2; dy++) {
            int cy = 2 * y + dy;
            VR_SPAN(sp, cnt, FILTER_LOOP, .int_ops = 1 + 1, .branches = 1);
            if (cy >= sny)
                continue;
            for (int dx = 0; dx < 2; dx++) {
                int cx = 2 * x + dx;
                VR_SPAN(sp, cnt, FILTER_LOOP, .int_ops = 1 + 1, .branches = 1);
                if (cx >= snx)
                    continue;
                const float *cc = src + (((size_t)(cz - z_off) * rows + (cy - y_off)) * snx + cx) * stride;
                /* the child's address: 2 subtracts, 3 multiplies, 2 adds */
                VR_SPAN(sp, cnt, FILTER_CHILD, .int_ops = 7);
                for (int k = 0; k < stride; k++) {
                    acc[k] += cc[k];
                    VR_SPAN(sp, cnt, FILTER_ADD, .loads = 1, .fadd = 1);
                }
            }
        }
    }
    for (int k = 0; k < stride; k++) {
        o[k] = acc[k] * 0.125f;
        VR_SPAN(sp, cnt, FILTER_COMPONENT, .fmul = 1, .stores = 1);
    }
}

/* Quantises one voxel's components into blocks A and (stride 8) N
 * (vr_shade_fixed.h).  Spans QUANTISE, QUANTISE_NORMAL. */
static inline void vr_quantise(const float *o, int stride, uint32_t *qa, uint32_t *qn,
                               vr_spans_t *sp, vr_count_t *cnt)
{
    *qa = vr_q8(o[0]) | vr_q8(o[1]) << 8 | vr_q8(o[2]) << 16 | vr_q8(o[3]) << 24;
    /* 4 loads; 4 x vr_q8 (2 compares, multiply, add, conversion: every
     * path counted); 3 shifts, 3 ors; the store; the stride test */
    VR_SPAN(sp, cnt, QUANTISE, .loads = 4, .fadd = 4 * 3, .fmul = 4, .int_ops = 4 + 6, .branches = 4 * 2 + 1,
            .stores = 1);
    if (stride == 8 && qn) {
        float n[3] = {o[4], o[5], o[6]};
        float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (len > 0.0f)
            for (int k = 0; k < 3; k++)
                n[k] /= len;
        *qn = vr_pack_normal(n);
        /* 3 loads, the length (3 multiplies, 2 adds, sqrt); len > 0 and 3
         * divides; per component vr_q_normal (multiply, lrintf, 2 compares)
         * and the packing (mask, shift, or); the store */
        VR_SPAN(sp, cnt, QUANTISE_NORMAL, .loads = 3, .fmul = 3 + 3, .fadd = 2 + 1, .fsqrt = 1, .fdiv = 3,
                .int_ops = 3 * (1 + 2 + 3), .branches = 1 + 3 * 2, .stores = 1);
    }
}

/* ---- the value pyramid of a blend (render/scalar_pyramid.c) ---- */

/* Level-0 value of voxel (x, y, z) of the slab: the volume's own value.
 * Span VALUE_VOXEL. */
static inline void vr_value_voxel(const vr_state_t *s, int x, int y, int z, float *o,
                                  const vr_mem_t *mem, vr_spans_t *sp, vr_count_t *cnt)
{
    o[0] = vr_slab_at(s, x, y, z, mem);
    /* the caller's x loop (increment, compare); the slab index (subtract, 2
     * multiplies, 2 adds) and load; the store */
    VR_SPAN(sp, cnt, VALUE_VOXEL, .int_ops = 2 + 5, .branches = 1, .loads = 1, .stores = 1);
}

/* One output voxel of the max reduction (filter_slice's max) over the
 * children vr_filter_voxel reads; the box kind is vr_filter_voxel itself
 * with stride 1 (the same sum in the same order, times 1/8).  Spans
 * FILTER_LOOP, FILTER_CHILD, REDUCE_MAX per child, REDUCE_OUT. */
static inline void vr_max_voxel(const float *src, int snx, int sny, int snz, int z_off, int y_off,
                                int rows, int x, int y, int z, float *o, vr_spans_t *sp,
                                vr_count_t *cnt)
{
    float acc = -INFINITY;
    for (int dz = 0; dz < 2; dz++) {
        int cz = 2 * z + dz;
        VR_SPAN(sp, cnt, FILTER_LOOP, .int_ops = 1 + 1, .branches = 1);
        if (cz >= snz)
            continue;
        for (int dy = 0; dy < 2; dy++) {
            int cy = 2 * y + dy;
            VR_SPAN(sp, cnt, FILTER_LOOP, .int_ops = 1 + 1, .branches = 1);
            if (cy >= sny)
                continue;
            for (int dx = 0; dx < 2; dx++) {
                int cx = 2 * x + dx;
                VR_SPAN(sp, cnt, FILTER_LOOP, .int_ops = 1 + 1, .branches = 1);
                if (cx >= snx)
                    continue;
                float c = src[((size_t)(cz - z_off) * rows + (cy - y_off)) * snx + cx];
                acc = c > acc ? c : acc;
                /* the child's address as FILTER_CHILD's; its load, the
                 * compare of the select */
                VR_SPAN(sp, cnt, FILTER_CHILD, .int_ops = 7);
                VR_SPAN(sp, cnt, REDUCE_MAX, .loads = 1, .fadd = 1, .branches = 1);
            }
        }
    }
    *o = acc;
    VR_SPAN(sp, cnt, REDUCE_OUT, .stores = 1);
}

/* A blend voxel's backing-store word: the float's own bits (so a fetched
 * value is the float render/ samples); true when the voxel is not cold
 * (the octree grids' bit).  Span VALUE_WORD. */
static inline bool vr_value_word(const vr_state_t *s, const float *o, uint32_t *word,
                                 vr_spans_t *sp, vr_count_t *cnt)
{
    memcpy(word, o, sizeof *word);
    /* the load and the store of the word; the cold test (compare) */
    VR_SPAN(sp, cnt, VALUE_WORD, .loads = 1, .stores = 1, .fadd = 1, .branches = 1);
    return o[0] > s->cfg.cold_below;
}

/* The opacity-correction tables (raycast_ctx_init): per 2D level and
 * table entry 1 - (1 - i / N)^spacing.  Spans ALPHA_ENTRY (+ LIBM). */
static inline void vr_alpha_lut_fill(vr_state_t *s, vr_spans_t *sp, vr_count_t *cnt)
{
    const vr_config_t *c = &s->cfg;
    for (int l = 0; l < VR_LUT_LEVELS; l++) {
        double spacing = (double)c->sample_step * (double)(1 << l);
        for (int i = 0; i <= VR_LUT_SIZE; i++) {
            s->alpha_lut[l][i] = (float)(1.0 - pow(1.0 - (double)i / VR_LUT_SIZE, spacing));
            vr_libm(sp, cnt);
            /* i's conversion, / N (x 2^-10), 1 - twice, the conversion back,
             * the store; the loop (increment, compare) */
            VR_SPAN(sp, cnt, ALPHA_ENTRY, .int_ops = 1 + 1 + 2, .fmul = 1, .fadd = 2, .stores = 1,
                    .branches = 1);
        }
    }
}

#endif
