/* vr_slab_kernels.h: the object-slabs division's kernels (a ray's segment through this GP's slab, and the front-to-back merge of partial colours), counted by spans of common/vr_cost.h.
 *
 * A segment is the samples of a parallel ray whose level-0 slice lies in
 * the slab [zlo, zhi): the slices of successive samples are monotone along
 * the ray, so two binary searches find its first and last sample, and the
 * ray marches from the first with zero colour and opacity up to the last
 * (vr_ray_march, the same arithmetic as a whole ray).  The band owner merges
 * the segments front to back (firmware/ARCHITECTURE.md "object-slabs").
 * The GP program (vr_cast.c, vr_slabs.c) and tests/test_fw_cost.c both call
 * these. */
#ifndef PP5_VR_SLAB_KERNELS_H
#define PP5_VR_SLAB_KERNELS_H

#include "vr_cast_kernels.h"

/* The level-0 slice of sample k of a parallel ray: the same float
 * expressions as the ray's sample position (vr_ray_march). */
static inline long vr_sample_slice(const vr_ray_t *r, float base, long k)
{
    float t = r->t0 + (float)k * base;
    return (long)floorf(r->ov[2] + t * r->dv[2] + 0.5f);
}

/* First sample index of [0, kmax) whose slice is at or past `lim` in the
 * ray's z direction (up: >= lim, down: < lim).  Span: SEGMENT_PROBE per probe. */
static inline long vr_segment_search(const vr_ray_t *r, float base, long kmax, bool up, long lim,
                                     vr_spans_t *sp, vr_count_t *cnt)
{
    long lo = 0, hi = kmax;
    while (lo < hi) {
        long mid = lo + (hi - lo) / 2;
        long z = vr_sample_slice(r, base, mid);
        bool past = up ? z >= lim : z < lim;
        /* the loop test; mid; the slice (conversion, multiply-add for t,
         * multiply-add and + 0.5 for z, floor, conversion); both compares and
         * the select; the update and its branch */
        VR_SPAN(sp, cnt, SEGMENT_PROBE, .int_ops = 1 + 3 + 1 + 2 + 2 + 1, .fmul = 2, .fadd = 3,
                .branches = 1 + 2 + 1 + 1);
        if (past)
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo;
}

/* The ray of pixel (px, py) at 2D level rc's, set at its first sample in
 * slices [zlo, zhi), with *t_end past its last.  False when the ray misses
 * the volume or has no sample in the slab.  Spans: the camera ray and clip,
 * SEGMENT_START, SEGMENT_PROBE, SEGMENT_HIT. */
static inline bool vr_segment_begin(const vr_state_t *s, const vr_ray_consts_t *rc, float px,
                                    float py, long zlo, long zhi, vr_ray_t *r, float *t_end,
                                    vr_spans_t *sp, vr_count_t *cnt)
{
    const vr_config_t *c = &s->cfg;
    float o[3], d[3];
    vr_camera_ray(&s->fr, c->width, c->height, px, py, o, d, sp, cnt);
    if (!vr_clip_box(o, d, s->fr.box_hi, &r->t0, &r->t1, sp, cnt))
        return false;
    for (int k = 0; k < 3; k++) {
        r->ov[k] = o[k] * c->inv_spacing[k];
        r->dv[k] = d[k] * c->inv_spacing[k];
    }
    float base = rc->base;
    long kmax = (long)floorf((r->t1 - r->t0) / base) + 1;     /* samples with t <= t1 */
    kmax -= kmax > 0 && r->t0 + (float)(kmax - 1) * base > r->t1;   /* float rounding */
    /* voxel-space ray (3 loads, 6 multiplies); kmax (subtract, divide,
     * floor, conversion, + 1) and its rounding select (both compares, kmax -
     * 1 and its conversion, multiply-add, the subtract); up and the two
     * limits; both searches' set-up and final loop tests; t_end (test,
     * conversion, multiply-add); the result test.  A kmax one too large
     * would be harmless: the march stops at t1. */
    VR_SPAN(sp, cnt, SEGMENT_START, .loads = 3, .fmul = 6 + 1 + 1, .fadd = 1 + 2 + 1 + 1, .fdiv = 1,
            .int_ops = 3 + 3 + 2 + 4 + 2 + 2 + 1, .branches = 2 + 1 + 2 + 1 + 1);
    bool up = r->dv[2] >= 0.0f;
    long k_lo = vr_segment_search(r, base, kmax, up, up ? zlo : zhi, sp, cnt);
    long k_hi = vr_segment_search(r, base, kmax, up, up ? zhi : zlo, sp, cnt);
    *t_end = k_hi >= kmax ? INFINITY : r->t0 + (float)k_hi * base;
    if (!(k_lo < k_hi))
        return false;
    r->acc[0] = r->acc[1] = r->acc[2] = 0.0f;
    r->acc_a = 0.0f;
    r->k = k_lo;
    r->t = r->t0 + (float)k_lo * base;
    r->spacing = rc->base;
    r->level3d = rc->level3d;
    /* t at the first sample (conversion, multiply-add); spacing and 3D
     * level from the pass constants */
    VR_SPAN(sp, cnt, SEGMENT_HIT, .int_ops = 1, .fmul = 1, .fadd = 1, .loads = 2);
    return true;
}

/* The partial colour of texel `ref`'s ray through slices [zlo, zhi) into
 * *out.  False when the segment adds nothing (no sample in the slab, or all
 * of them transparent).  Spans: SEGMENT, those of vr_segment_begin and
 * vr_ray_march, SEGMENT_KEEP, SEGMENT_OUT. */
static inline bool vr_slab_segment(const vr_state_t *s, const vr_ray_consts_t *rc,
                                   const vr_texel_ref_t *ref, long zlo, long zhi, vr_partial_t *out,
                                   const vr_mem_t *mem, vr_spans_t *sp, vr_count_t *cnt,
                                   uint64_t *skipped)
{
    float px = (float)(ref->i << ref->m) + 0.5f, py = (float)(ref->j << ref->m) + 0.5f;
    /* i, j, m loaded; two shifts, conversions and + 0.5; the result test */
    VR_SPAN(sp, cnt, SEGMENT, .loads = 3, .int_ops = 2 + 2, .fadd = 2, .branches = 1);
    vr_ray_t r;
    float t_end;
    if (!vr_segment_begin(s, rc, px, py, zlo, zhi, &r, &t_end, sp, cnt))
        return false;
    vr_ray_march(s, rc, ref->m, &r, t_end, mem, sp, cnt, skipped);
    /* the four tests against zero (all counted) */
    VR_SPAN(sp, cnt, SEGMENT_KEEP, .branches = 4);
    if (!(r.acc_a > 0.0f || r.acc[0] > 0.0f || r.acc[1] > 0.0f || r.acc[2] > 0.0f))
        return false;
    *out = (vr_partial_t){ref->code, {r.acc[0], r.acc[1], r.acc[2], r.acc_a}};
    /* the code loaded; code and colour stored */
    VR_SPAN(sp, cnt, SEGMENT_OUT, .loads = 1, .stores = 5);
    return true;
}

/* One partial colour composited behind texel accumulator acc (4 floats),
 * front to back: acc += (1 - acc.a) * p, for partial r of the block `list`.
 * False (nothing done) when the partial names a texel past the band's
 * `total`.  Spans: MERGE, MERGE_ADD. */
static inline bool vr_merge_partial(float *acc, uint32_t total, const vr_partial_t *list, size_t r,
                                    const vr_mem_t *mem, vr_spans_t *sp, vr_count_t *cnt)
{
    const vr_partial_t *p = &list[r];
    vr_mem_access(mem, list, r * sizeof *p, sizeof *p, 0);
    /* the code loaded and tested against the band's texel count; the loop */
    VR_SPAN(sp, cnt, MERGE, .loads = 1, .int_ops = 1 + 1, .branches = 1 + 1);
    if (p->code >= total)
        return false;
    float *a = acc + (size_t)p->code * 4, t = 1.0f - a[3];
    for (int c = 0; c < 4; c++)
        a[c] += t * p->rgba[c];
    vr_mem_access(mem, acc, (size_t)p->code * 16, 16, 0);
    vr_mem_access(mem, acc, (size_t)p->code * 16, 16, 1);
    /* the address (shift, add); the partial (4) and accumulator (4) loaded,
     * 1 - a waiting on its load; four multiply-adds, four stores */
    VR_SPAN(sp, cnt, MERGE_ADD, .int_ops = 2, .loads = 4 + 4, .load_use = 1, .fadd = 1 + 4,
            .fmul = 4, .stores = 4);
    return true;
}

/* The number of set bits among the first `total` of a need set (one bit
 * per texel of a band, in texel-code order).  Span: NEED_COUNT per bit. */
static inline size_t vr_need_count(const uint8_t *bits, uint32_t total, vr_spans_t *sp,
                                   vr_count_t *cnt)
{
    size_t n = 0;
    for (uint32_t c = 0; c < total; c++) {
        n += (bits[c >> 3] >> (c & 7)) & 1;
        /* the byte; c >> 3, c & 7, the shift, & 1, the add; the loop */
        VR_SPAN(sp, cnt, NEED_COUNT, .loads = 1, .int_ops = 5 + 2, .branches = 1);
    }
    return n;
}

/* The texels of a need set as references (code, column, row, 2D level),
 * level by level of band geometry bg.  Spans: NEED_LEVEL per level,
 * NEED_TEST per bit, NEED_REF per texel set. */
static inline size_t vr_need_unpack(const uint8_t *bits, const vr_band_geom_t *bg, int levels2d,
                                    vr_texel_ref_t *out, vr_spans_t *sp, vr_count_t *cnt)
{
    size_t n = 0;
    for (int m = 0; m < levels2d; m++) {
        /* the level's first and next codes, width and first row; the loop */
        VR_SPAN(sp, cnt, NEED_LEVEL, .loads = 4, .int_ops = 2, .branches = 1);
        for (uint32_t c = bg->base[m]; c < bg->base[m + 1]; c++) {
            /* the byte; c >> 3, c & 7, the shift, & 1 and its test; the loop */
            VR_SPAN(sp, cnt, NEED_TEST, .loads = 1, .int_ops = 4 + 2, .branches = 1 + 1);
            if (!((bits[c >> 3] >> (c & 7)) & 1))
                continue;
            uint32_t off = c - bg->base[m];
            out[n++] = (vr_texel_ref_t){c, (uint16_t)(off % (uint32_t)bg->tw[m]),
                                        (uint16_t)(bg->jlo[m] + (int)(off / (uint32_t)bg->tw[m])),
                                        (uint8_t)m};
            /* the offset, % and / by the width, + the first row, n + 1; code,
             * column, row and level stored */
            VR_SPAN(sp, cnt, NEED_REF, .int_ops = 5, .stores = 4);
        }
    }
    return n;
}

/* Our band's needed texels (flag rows `need` of the band's 2D levels, row
 * pitch tw[m], first row jlo[m]) into a zeroed bit set of the band's codes.
 * Spans: NEED_ROW per texel row, NEED_FLAG per texel, NEED_SET per set bit. */
static inline void vr_need_pack(uint8_t *const *need, const int *jlo, const int *tw,
                                const vr_band_geom_t *bg, int levels2d, uint8_t *bits,
                                vr_spans_t *sp, vr_count_t *cnt)
{
    for (int m = 0; m < levels2d; m++)
        for (int j = bg->jlo[m]; j <= bg->jhi[m]; j++) {
            const uint8_t *nd = need[m] + (size_t)(j - jlo[m]) * tw[m];
            uint32_t row = bg->base[m] + (uint32_t)(j - bg->jlo[m]) * (uint32_t)bg->tw[m];
            /* the row's flags pointer and first code (loads of the level's
             * pointer, pitch and geometry; subtracts, multiplies, adds); the
             * loops */
            VR_SPAN(sp, cnt, NEED_ROW, .loads = 5, .int_ops = 6 + 2, .branches = 2);
            for (int i = 0; i < tw[m]; i++) {
                VR_SPAN(sp, cnt, NEED_FLAG, .loads = 1, .int_ops = 1, .branches = 1 + 1);
                if (!nd[i])
                    continue;
                uint32_t c = row + (uint32_t)i;
                bits[c >> 3] |= (uint8_t)(1u << (c & 7));
                /* the code; c >> 3, c & 7, the shift, the or: load and store */
                VR_SPAN(sp, cnt, NEED_SET, .int_ops = 1 + 4, .loads = 1, .stores = 1);
            }
        }
}

#endif
