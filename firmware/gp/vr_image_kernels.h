/* vr_image_kernels.h: the per-pixel kernels of a frame: 2DLevel of a pixel, the texels its rays must fill (mip2d_mark_pixel), and RenderPixel back from the 2D mip map, counted by spans of common/vr_cost.h.
 *
 * Called by vr_plan.c and vr_resample.c and by tests/test_fw_cost.c (see
 * vr_cast_kernels.h for the counting).  RenderPixel declares its reads of
 * the 2DLevel row and the texel rows and its writes into the section to the
 * data cache; the 2DLevel tables and the marks' flag rows are left as hits.
 * Paper: seed 004 §4 (2DLevel, RenderPixel). */
#ifndef PP5_VR_IMAGE_KERNELS_H
#define PP5_VR_IMAGE_KERNELS_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>

#include "vr_cast_kernels.h"
#include "vr_gp_internal.h"

/* 2DLevel of pixel (x, y) (render/gaze2d.c), kept when finer than the
 * level it had (*row_level: render/'s level_best).  Spans: LEVEL_PIXEL, and
 * LEVEL (exact) or LEVEL_TABLE (tables) with theirs. */
static inline void vr_pixel_level(const vr_state_t *s, int x, int y, bool gaze, bool tables, int gx,
                                  int gy, float *row_level, vr_spans_t *sp, vr_count_t *cnt)
{
    const vr_config_t *c = &s->cfg;
    float level = 0.0f;
    /* the x loop (increment, compare); the two mode tests; the kept level
     * (load, compared at once), the compare and the store (both sides of
     * the min) */
    VR_SPAN(sp, cnt, LEVEL_PIXEL, .int_ops = 2, .branches = 1 + 2 + 1, .loads = 1, .load_use = 1, .fadd = 1,
            .stores = 1);
    if (tables) {
        level = vr_level_tabled(&s->level_tables, x - gx, y - gy, s->fr.gaze_scale, sp, cnt);
    } else if (gaze) {
        double dx = (double)x - s->fr.gaze_x, dy = (double)y - s->fr.gaze_y;
        int tr = 0;
        level = vr_gaze_level(c, sqrt(dx * dx + dy * dy) / s->fr.gaze_scale, &tr, sp, cnt);
        /* dx, dy (conversion, subtract); sqrt of the squares; / scale */
        VR_SPAN(sp, cnt, LEVEL, .int_ops = 2, .fadd = 2 + 1, .fmul = 2, .fsqrt = 1, .fdiv = 1);
    }
    if (level < *row_level)
        *row_level = level;
}

/* Marks the texels of level l that pixel (x, y) reads (mip2d_mark_pixel for
 * one level).  Spans MARK_LEVEL, MARK_ROW per texel row tried, MARK_STORE
 * per own row, MARK_RIGHT for a pixel between two texel columns. */
static inline void vr_mark_level(vr_state_t *s, int x, int y, int l, vr_spans_t *sp, vr_count_t *cnt)
{
    int i = x >> l, j = y >> l;
    bool fx = (x & ((1 << l) - 1)) != 0, fy = (y & ((1 << l) - 1)) != 0;
    int rows = fy ? 1 : 0;
    /* i, j (2 shifts); the mask (2), two ands, two != 0; the rows select;
     * the level's jlo, jhi, need and tw loads; the row loop's last test */
    VR_SPAN(sp, cnt, MARK_LEVEL, .int_ops = 2 + 2 + 2 + 2 + 1 + 1, .loads = 4, .branches = 1);
    for (int dj = 0; dj <= rows; dj++) {
        int jj = j + dj;
        /* the loop test and increment; jj; the two bounds (both counted) */
        VR_SPAN(sp, cnt, MARK_ROW, .int_ops = 2 + 1 + 2, .branches = 1 + 2);
        if (jj < s->jlo[l] || jj > s->jhi[l])
            continue;
        uint8_t *nd = s->need[l] + (size_t)(jj - s->jlo[l]) * s->tw[l];
        nd[i] = 1;
        /* the row (subtract, multiply, add), the flag's address, the store;
         * the fx test */
        VR_SPAN(sp, cnt, MARK_STORE, .int_ops = 3 + 1, .stores = 1, .branches = 1);
        if (fx) {
            nd[i + 1] = 1;
            VR_SPAN(sp, cnt, MARK_RIGHT, .stores = 1);
        }
    }
}

/* mip2d_mark_pixel: the texels of the pixel's level and, when it lies
 * between two levels, of the next.  Span MARK. */
static inline void vr_mark_pixel(vr_state_t *s, int x, int y, float level, vr_spans_t *sp,
                                 vr_count_t *cnt)
{
    int lo = (int)level;
    if (lo >= s->levels2d)
        lo = s->levels2d - 1;
    /* the x loop; the level (loaded by the caller, converted at once), the
     * clamp (compare); the second-level test (conversion, compare; lo + 1,
     * compare) */
    VR_SPAN(sp, cnt, MARK, .int_ops = 2 + 1 + 1 + 1 + 2, .branches = 1 + 1 + 2, .loads = 1, .load_use = 1,
            .fadd = 1);
    vr_mark_level(s, x, y, lo, sp, cnt);
    if (level > (float)lo && lo + 1 < s->levels2d)
        vr_mark_level(s, x, y, lo + 1, sp, cnt);
}

/* Bilinear lookup of 2D level l at pixel (x, y) (render/gaze2d.c).  Span
 * BILERP; the four corner texels are declared to the data cache. */
static inline void vr_bilerp(const vr_state_t *s, int l, int x, int y, float rgb[3],
                             const vr_mem_t *mem, vr_spans_t *sp, vr_count_t *cnt)
{
    int i = x >> l, j = y >> l;
    float sc = (float)(1 << l);
    float u = (float)(x - (i << l)) / sc, v = (float)(y - (j << l)) / sc;
    int w = s->tw[l];
    const float *texel = s->texel[l];
    size_t o00 = ((size_t)(j - s->jlo[l]) * w + i) * 3;
    size_t o10 = u > 0.0f ? o00 + 3 : o00;
    size_t o01 = v > 0.0f ? o00 + (size_t)w * 3 : o00;
    size_t o11 = (u > 0.0f && v > 0.0f) ? o00 + ((size_t)w + 1) * 3 : (u > 0.0f ? o10 : o01);
    const float *c00 = texel + o00, *c10 = texel + o10, *c01 = texel + o01, *c11 = texel + o11;
    vr_mem_access(mem, texel, o00 * 4, 12, 0);
    vr_mem_access(mem, texel, o10 * 4, 12, 0);
    vr_mem_access(mem, texel, o01 * 4, 12, 0);
    vr_mem_access(mem, texel, o11 * 4, 12, 0);
    for (int k = 0; k < 3; k++) {
        float a = c00[k] + u * (c10[k] - c00[k]);
        float b = c01[k] + u * (c11[k] - c01[k]);
        rgb[k] = a + v * (b - a);
    }
    /* i, j; u and v (shift, subtract, conversion, x 2^-l from a table: one
     * load); tw, texel and jlo loads; the corner (subtract, multiply, add, x
     * 3, byte address: shift and add); the three selects (u > 0, v > 0
     * compares, the both-test; 1 + 2 + 3 address ops); 3 channels x 4 texel
     * loads (scheduled) and 3 lerps */
    VR_SPAN(sp, cnt, BILERP, .int_ops = 2 + 2 * 3 + 6 + 6, .fmul = 2 + 9, .fadd = 2 + 18,
            .loads = 1 + 3 + 12, .branches = 2 + 2);
}

static inline uint8_t vr_to_u8(float v)
{
    if (!(v > 0.0f))
        return 0;
    if (v >= 1.0f)
        return 255;
    return (uint8_t)(v * 255.0f + 0.5f);
}

/* RenderPixel of pixel (x, y) of the band into out[0..2] (render/gaze2d.c):
 * the pixel's 2D level, one or two bilinear lookups, three bytes.  Spans
 * PIXEL, BILERP, PIXEL_BLEND. */
static inline void vr_render_pixel(const vr_state_t *s, int x, int y, uint8_t *section,
                                   size_t out_off, const vr_mem_t *mem, vr_spans_t *sp,
                                   vr_count_t *cnt)
{
    size_t li = (size_t)(y - s->ly0) * s->cfg.width + (size_t)x;
    float level = s->level[li], rgb[3];
    vr_mem_access(mem, s->level, li * 4, 4, 0);
    int lo = (int)level;
    if (lo >= s->levels2d)
        lo = s->levels2d - 1;
    /* the x loop; the level (load, converted at once), the clamp; t
     * (conversion, subtract) and the blend test (compare; lo + 1, compare);
     * the output offset (3); 3 x to_u8 (2 compares, multiply, add,
     * conversion) and 3 byte stores */
    VR_SPAN(sp, cnt, PIXEL, .int_ops = 2 + 1 + 1 + 1 + 2 + 3 + 3, .branches = 1 + 1 + 2 + 3 * 2,
            .loads = 1, .load_use = 1, .fadd = 1 + 1 + 3 * 3, .fmul = 3, .stores = 3);
    vr_bilerp(s, lo, x, y, rgb, mem, sp, cnt);
    float t = level - (float)lo;
    if (t > 0.0f && lo + 1 < s->levels2d) {
        float hi[3];
        vr_bilerp(s, lo + 1, x, y, hi, mem, sp, cnt);
        for (int k = 0; k < 3; k++)
            rgb[k] += t * (hi[k] - rgb[k]);
        VR_SPAN(sp, cnt, PIXEL_BLEND, .fadd = 3 * 2, .fmul = 3);
    }
    uint8_t *o = section + out_off;
    o[0] = vr_to_u8(rgb[0]);
    o[1] = vr_to_u8(rgb[1]);
    o[2] = vr_to_u8(rgb[2]);
    vr_mem_access(mem, section, out_off, 3, 1);
}

#endif
