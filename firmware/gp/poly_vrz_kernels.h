/* poly_vrz_kernels.h: the kernels of gaze-directed polygon frames (the variable-resolution Z-buffer of the gaze paper's §7, seed 004): which level tiles are populated, a triangle's tiles on each level, its plane expressions on a level, and RenderPixel from the texels the renderers sent, counted by spans of common/poly_cost.h.
 *
 * Level l's texel (i, j) sits at image point (i 2^l + 0.5, j 2^l + 0.5)
 * (render/gaze2d.h), so it is a pixel centre of the image: a triangle's
 * edge function there is 2^l (D i + E j) + F with the level-0 coefficients
 * (poly_encode), positive iff D i + E j + floor(F / 2^l) is, so a level's
 * coverage is exact and the QEE's coefficients stay those of level 0. */
#ifndef PP5_POLY_VRZ_KERNELS_H
#define PP5_POLY_VRZ_KERNELS_H

#include "common/vr_kernels.h"
#include "poly_gp_internal.h"
#include "ring_msg.h"

/* Texels across n pixels at level l: mip2d_init's ((n - 1) >> l) + 2, and
 * at level 0 exactly n (a pixel reads texel x only). */
static inline int poly_level_texels(int n, int l)
{
    return l == 0 ? n : ((n - 1) >> l) + 2;
}

/* 2DLevel at distance r pixels from the gaze: render/gaze2d.c gaze_level,
 * through vr_gaze_level (its spans in s->vsp), with gaze_level's own value
 * past the periphery radius. */
static inline float poly_gaze_level(poly_state_t *s, double r, poly_count_t *cnt)
{
    int transcendental = 0;
    float level = vr_gaze_level(&s->gaze_model, r, &transcendental, &s->vsp, NULL);
    bool far = r > s->cfg.g_r_zero_px && r >= s->cfg.g_r_max_px;
    /* the two compares and the select */
    POLY_SPAN(&s->sp, cnt, VRZ_LEVEL_FAR, .fadd = 2, .branches = 2);
    return far ? s->cfg.g_level_far : level;
}

/* The image pixels [*lo, *hi] that read texels [a, b] of level l
 * (mip2d_mark_pixel: pixel x reads texel x >> l, and the next when x is not
 * a multiple of 2^l), clamped to n pixels. */
static inline void poly_texel_readers(int a, int b, int l, int n, int *lo, int *hi)
{
    *lo = l == 0 ? a : (a - 1) * (1 << l) + 1;     /* a - 1 may be -1: no shift */
    *hi = l == 0 ? b : (b + 1) * (1 << l) - 1;
    *lo = *lo < 0 ? 0 : *lo;
    *hi = *hi > n - 1 ? n - 1 : *hi;
}

/* Is tile (tx, ty) of level l populated: might a pixel of the image read
 * one of its texels?  A pixel of level v reads level floor(v) (the last
 * level at most) and, when v is fractional, the next (mip2d_pixel); so
 * level l is read by pixels of level in (l - 1, l + 1), or above l - 1 for
 * the last level.  2DLevel grows with the distance from the gaze, so over
 * the reading pixels' rectangle it lies between its values at the
 * rectangle's nearest and farthest points: the test is conservative (a
 * populated tile is never missed; tests/test_fw_poly_vrz.c checks it
 * against render/'s marks).  With the tables a pixel's distance is taken
 * from the gaze pixel (at most 0.71 pixel from the gaze) and rounded to
 * 1/4 pixel, so both distances are widened by a pixel. */
static inline bool poly_tile_populated(poly_state_t *s, int l, int tx, int ty, poly_count_t *cnt)
{
    int a = tx * 128, b = a + 127 < s->tw[l] - 1 ? a + 127 : s->tw[l] - 1;
    int c = ty * 128, d = c + 127 < s->th[l] - 1 ? c + 127 : s->th[l] - 1;
    int xa, xb, ya, yb;
    poly_texel_readers(a, b, l, s->cfg.width, &xa, &xb);
    poly_texel_readers(c, d, l, s->cfg.height, &ya, &yb);
    /* the texel box (2 multiplies by 128 as shifts, 2 adds, 2 clamps with
     * their loads); the readers (4 shifts, 4 adds, the level-0 selects, 4
     * clamps); the empty test */
    POLY_SPAN(&s->sp, cnt, VRZ_TILE, .int_ops = 2 + 2 + 2 + 4 + 4 + 4 + 4 + 2, .loads = 2 + 2,
              .branches = 2 + 4 + 4 + 2);
    if (xa > xb || ya > yb)
        return false;
    double gx = s->cfg.gaze_x, gy = s->cfg.gaze_y;
    double nx = fmax(fmax((double)xa - gx, gx - (double)xb), 0.0);
    double ny = fmax(fmax((double)ya - gy, gy - (double)yb), 0.0);
    double fx = fmax(fabs((double)xa - gx), fabs((double)xb - gx));
    double fy = fmax(fabs((double)ya - gy), fabs((double)yb - gy));
    double widen = s->cfg.level_tables ? 1.0 : 0.0;
    double rn = fmax(sqrt(nx * nx + ny * ny) - widen, 0.0), rf = sqrt(fx * fx + fy * fy) + widen;
    float near = poly_gaze_level(s, rn, cnt);
    float farthest = poly_gaze_level(s, rf, cnt);
    bool below = l == s->levels - 1 || near < (float)(l + 1);
    bool above = l == 0 || farthest > (float)(l - 1);
    /* 4 conversions; 8 subtracts, 6 max and 4 fabs (compares: adder);
     * two distances (2 products, an add, a sqrt each), the widening (2 adds,
     * a max); the two level tests (a conversion, an add and a compare each,
     * the level tests) */
    POLY_SPAN(&s->sp, cnt, VRZ_TILE_LEVELS, .int_ops = 4 + 2, .fadd = 8 + 6 + 4 + 2 + 3 + 2 + 2,
              .fmul = 4, .fsqrt = 2, .loads = 3, .branches = 2 + 2 + 2);
    return below && above;
}

/* A triangle's snapped box (1/16 pixel), once before its levels. */
typedef struct {
    int32_t xlo, xhi, ylo, yhi;
} poly_box_t;

static inline poly_box_t poly_tri_box(const poly_tri_t *t, poly_spans_t *sp, poly_count_t *cnt)
{
    poly_box_t b = {poly_min3(t->X[0], t->X[1], t->X[2]), poly_max3(t->X[0], t->X[1], t->X[2]),
                    poly_min3(t->Y[0], t->Y[1], t->Y[2]), poly_max3(t->Y[0], t->Y[1], t->Y[2])};
    /* 6 loads, 8 compares */
    POLY_SPAN(sp, cnt, VRZ_TRI, .loads = 6, .int_ops = 8, .branches = 8);
    return b;
}

/* The tiles [t[0], t[1]] x [t[2], t[3]] of level l whose texel centres
 * 16 2^l i + 8 the box reaches; false when none on the level. */
static inline bool poly_level_tiles(const poly_state_t *s, const poly_box_t *b, int l, int t[4],
                                    poly_spans_t *sp, poly_count_t *cnt)
{
    int sh = POLY_SUB_BITS + l, step = 1 << sh;
    int32_t i0 = poly_floor_shift(b->xlo - POLY_SUB / 2 + step - 1, sh);
    int32_t i1 = poly_floor_shift(b->xhi - POLY_SUB / 2, sh);
    int32_t j0 = poly_floor_shift(b->ylo - POLY_SUB / 2 + step - 1, sh);
    int32_t j1 = poly_floor_shift(b->yhi - POLY_SUB / 2, sh);
    i0 = i0 < 0 ? 0 : i0, j0 = j0 < 0 ? 0 : j0;
    i1 = i1 > s->tw[l] - 1 ? s->tw[l] - 1 : i1;
    j1 = j1 > s->th[l] - 1 ? s->th[l] - 1 : j1;
    t[0] = i0 >> 7, t[1] = i1 >> 7, t[2] = j0 >> 7, t[3] = j1 >> 7;
    /* the shift and step (2); 4 bounds (an add or two and a shift with its
     * sign fix: 4 each); 4 clamps (2 loads); 4 tile shifts; the empty test */
    POLY_SPAN(sp, cnt, VRZ_LEVEL_BOX, .int_ops = 2 + 16 + 4 + 4 + 2, .loads = 2, .branches = 4 + 2);
    return i0 <= i1 && j0 <= j1;
}

/* Triangle t as level l sees it (l > 0): its planes per texel step, corner
 * 0 in level coordinates (x = (X - 0.5) / 2^l + 0.5); the corners and
 * edges stay (poly_encode shifts F). */
static inline void poly_tri_on_level(const poly_tri_t *t, int l, int n_planes, poly_tri_t *o,
                                     poly_spans_t *sp, poly_count_t *cnt)
{
    float s = (float)(1 << l), inv = 1.0f / s;
    *o = *t;
    for (int k = 0; k < n_planes; k++)
        o->plane[k][1] *= s, o->plane[k][2] *= s;
    o->x0 = (t->x0 - 0.5f) * inv + 0.5f;
    o->y0 = (t->y0 - 0.5f) * inv + 0.5f;
    /* the record copied (14 words the encoder reads: corners, sign,
     * owned edges, back, colour, corner 0; loads and stores); 2^l and
     * 2^-l from a table (2 loads); 2 gradients per plane (load, multiply,
     * store); corner 0 (2 subtracts, 2 multiplies, 2 adds, 2 stores) */
    POLY_SPAN(sp, cnt, ENC_LEVEL, .loads = 14 + 2, .stores = 14 + 2, .fadd = 4, .fmul = 2);
    POLY_SPANS(sp, cnt, ENC_LEVEL_PLANE, (uint64_t)n_planes, .loads = 2, .fmul = 2, .stores = 2);
}

/* ---- RenderPixel from the level texels ---- */

static inline float poly_texel_channel(uint32_t w, int k)
{
    return (float)((w >> (8 * k)) & 0xffu) / 255.0f;
}

/* bilerp of render/gaze2d.c at pixel (x, y) from level l's texel rows
 * (same expressions, same order). */
static inline void poly_bilerp(const poly_state_t *s, int l, int x, int y, float rgb[3],
                               poly_spans_t *sp, poly_count_t *cnt)
{
    int i = x >> l, j = y >> l, w = s->tw[l];
    float sc = (float)(1 << l);
    float u = (float)(x - (i << l)) / sc, v = (float)(y - (j << l)) / sc;
    const uint32_t *row = s->texel[l] + (size_t)(j - s->jlo[l]) * (size_t)w;
    uint32_t t00 = row[i], t10 = u > 0.0f ? row[i + 1] : t00;
    uint32_t t01 = v > 0.0f ? row[i + w] : t00;
    uint32_t t11 = u > 0.0f && v > 0.0f ? row[i + w + 1] : (u > 0.0f ? t10 : t01);
    for (int k = 0; k < 3; k++) {
        float c00 = poly_texel_channel(t00, k), c10 = poly_texel_channel(t10, k);
        float c01 = poly_texel_channel(t01, k), c11 = poly_texel_channel(t11, k);
        float a = c00 + u * (c10 - c00), b = c01 + u * (c11 - c01);
        rgb[k] = a + v * (b - a);
    }
    /* i, j; u and v (shift, subtract, conversion, x 2^-l from a table);
     * the row (subtract, multiply, add; tw and jlo loads); the 4 texels
     * (selects: 2 compares, the both-test, 3 address adds; 4 loads); 12
     * channels (shift, and, conversion, x 1/255); 3 channels x 3 lerps */
    POLY_SPAN(sp, cnt, VRZ_BILERP, .int_ops = 2 + 6 + 3 + 3 + 36, .fmul = 2 + 12 + 9,
              .fadd = 2 + 18, .loads = 2 + 2 + 4, .branches = 2 + 2);
}

static inline uint8_t poly_to_u8(float v)
{
    if (!(v > 0.0f))
        return 0;
    if (v >= 1.0f)
        return 255;
    return (uint8_t)(v * 255.0f + 0.5f);
}

/* mip2d_pixel then render_to_u8: pixel (x, y) of the band into out[0..2]. */
static inline void poly_render_pixel(const poly_state_t *s, int x, int y, uint8_t *out,
                                     poly_spans_t *sp, poly_count_t *cnt)
{
    float level = s->level[(size_t)(y - s->y0) * (size_t)s->cfg.width + (size_t)x], rgb[3];
    int lo = (int)level;
    if (lo >= s->levels)
        lo = s->levels - 1;
    poly_bilerp(s, lo, x, y, rgb, sp, cnt);
    float t = level - (float)lo;
    if (t > 0.0f && lo + 1 < s->levels) {
        float hi[3];
        poly_bilerp(s, lo + 1, x, y, hi, sp, cnt);
        for (int k = 0; k < 3; k++)
            rgb[k] += t * (hi[k] - rgb[k]);
        POLY_SPAN(sp, cnt, VRZ_PIXEL_BLEND, .fadd = 3 * 2, .fmul = 3);
    }
    for (int k = 0; k < 3; k++)
        out[k] = poly_to_u8(rgb[k]);
    /* the x loop; the level (address, load, converted at once), the clamp;
     * t (conversion, subtract), the blend test (compare; lo + 1, compare);
     * 3 x to_u8 (2 compares, multiply, add, conversion) and 3 byte stores */
    POLY_SPAN(sp, cnt, VRZ_PIXEL, .int_ops = 2 + 2 + 1 + 1 + 1 + 2 + 3, .loads = 1, .load_use = 1,
              .branches = 1 + 1 + 2 + 6, .fadd = 1 + 1 + 3 * 3, .fmul = 3, .stores = 3);
}

/* ---- the frame's plan, per GP ---- */

/* The acuity model as vr_gaze_level takes it; per level: texels across and
 * down, tiles, the first tile's dense index (once per configuration; no
 * charge: set-up of the sequence). */
static inline void poly_levels_setup(poly_state_t *s)
{
    const poly_config_t *c = &s->cfg;
    vr_config_t *g = &s->gaze_model;
    g->g_inches_per_px = c->g_inches_per_px, g->g_view_distance_in = c->g_view_distance_in;
    g->g_e_full_deg = c->g_e_full_deg, g->g_e_edge_deg = c->g_e_edge_deg;
    g->g_sigma_deg = c->g_sigma_deg, g->g_rho_min = c->g_rho_min;
    g->g_r_zero_px = c->g_r_zero_px, g->g_r_max_px = c->g_r_max_px;
    g->g_max_level = c->g_max_level;
    s->n_tiles = 0;
    for (int l = 0; l < c->levels2d; l++) {
        s->tw[l] = poly_level_texels(c->width, l), s->th[l] = poly_level_texels(c->height, l);
        s->tiles_x[l] = (s->tw[l] + 127) / 128, s->tiles_y[l] = (s->th[l] + 127) / 128;
        s->tile_base[l] = s->n_tiles;
        s->n_tiles += s->tiles_x[l] * s->tiles_y[l];
    }
}

/* Tile (tx, ty) of level l: populated or not, its slot, its region. */
static inline void poly_plan_tile(poly_state_t *s, int l, int tx, int ty, poly_count_t *cnt)
{
    bool on = poly_tile_populated(s, l, tx, ty, cnt);
    s->slot_of[s->tile_base[l] + ty * s->tiles_x[l] + tx] = on ? s->n_regions : -1;
    if (on)
        s->reg[s->n_regions++] = (poly_region_t){l, tx * 128, ty * 128};
    /* the slot's address (2), the store, the test; the region's three
     * words and the count */
    POLY_SPAN(&s->sp, cnt, VRZ_SLOT, .stores = 1 + 3, .int_ops = 2 + 1, .branches = 1);
}

/* The rows [*a, *b] of region k that texel rows [jlo, jhi] hold; false
 * when none. */
static inline bool poly_region_rows(const poly_state_t *s, int k, int jlo, int jhi, int *a, int *b)
{
    const poly_region_t *r = &s->reg[k];
    int top = r->y, bottom = r->y + 127 < s->th[r->level] - 1 ? r->y + 127 : s->th[r->level] - 1;
    *a = jlo > top ? jlo : top;
    *b = jhi < bottom ? jhi : bottom;
    return *a <= *b;
}

/* Does this GP read texels of region k (one box to expect)? */
static inline bool poly_expect_region(poly_state_t *s, int k, poly_count_t *cnt)
{
    int a, b, l = s->reg[k].level;
    /* the region's level and top (2 loads), jlo and jhi (1 more), the
     * bottom clamp and the two intersections (6), the tests */
    POLY_SPAN(&s->sp, cnt, VRZ_EXPECT, .loads = 3, .int_ops = 6, .branches = 3);
    return poly_region_rows(s, k, s->jlo[l], s->jhi[l], &a, &b);
}

/* 2DLevel of band pixel (x, y), stored: from the paper's tables (offsets
 * from the gaze pixel, as the volume program's) or exactly (render/
 * mip2d_row.c's expression). */
static inline void poly_band_level(poly_state_t *s, int x, int y, poly_count_t *cnt)
{
    float *out = s->level + (size_t)(y - s->y0) * (size_t)s->cfg.width + (size_t)x;
    if (s->cfg.level_tables) {
        int gx = (int)floor(s->cfg.gaze_x + 0.5), gy = (int)floor(s->cfg.gaze_y + 0.5);
        *out = vr_level_tabled(&s->tables, x - gx, y - gy, 1.0, &s->vsp, NULL);
        /* the x loop; the gaze pixel (kept in registers per row); the
         * address and the store */
        POLY_SPAN(&s->sp, cnt, VRZ_BAND_PIXEL_TABLED, .int_ops = 2 + 1, .stores = 1, .branches = 1);
        return;
    }
    double dx = (double)x - s->cfg.gaze_x, dy = (double)y - s->cfg.gaze_y;
    *out = poly_gaze_level(s, sqrt(dx * dx + dy * dy), cnt);
    /* the x loop; dx, dy (conversion, subtract); the squares, their sum,
     * sqrt; the address and the store */
    POLY_SPAN(&s->sp, cnt, VRZ_BAND_PIXEL, .int_ops = 2 + 1 + 1, .fadd = 2 + 1, .fmul = 2,
              .fsqrt = 1, .stores = 1, .branches = 1);
}

/* Triangle i in tile (tx, ty) of level l: counted (fill = false) or stored
 * in the tile's bin when the tile is populated. */
static inline void poly_sort_tile(poly_state_t *s, int l, int tx, int ty, uint32_t i, bool fill,
                                  poly_count_t *cnt)
{
    int32_t k = s->slot_of[s->tile_base[l] + ty * s->tiles_x[l] + tx];
    /* the index (multiply, 2 adds), the loop, the slot's load and test */
    POLY_SPAN(&s->sp, cnt, VRZ_BIN_TILE, .int_ops = 4, .loads = 1, .load_use = 1, .branches = 2);
    if (k < 0)
        return;
    if (!fill) {
        s->count[k]++;
        POLY_SPAN(&s->sp, cnt, BIN_COUNT, .loads = 1, .load_use = 1, .stores = 1, .int_ops = 4,
                  .branches = 1);
    } else {
        s->list[s->start[k] + s->fill[k]++] = i;
        POLY_SPAN(&s->sp, cnt, BIN_FILL, .loads = 2, .load_use = 1, .stores = 2, .int_ops = 5,
                  .branches = 1);
    }
}

/* Image rows [*y0, *y1) of GP g of n: its band for resampling. */
static inline void poly_band_rows(const poly_state_t *s, unsigned g, unsigned n, int *y0, int *y1)
{
    *y0 = (int)((long)s->cfg.height * g / n);
    *y1 = (int)((long)s->cfg.height * (g + 1) / n);
}

/* The texel rows [*jlo, *jhi] of level l that image rows [y0, y1) read. */
static inline void poly_band_texel_rows(const poly_state_t *s, int y0, int y1, int l, int *jlo,
                                        int *jhi)
{
    *jlo = y0 >> l;
    *jhi = ((y1 - 1) >> l) + (l > 0 ? 1 : 0);
    if (*jhi > s->th[l] - 1)
        *jhi = s->th[l] - 1;
}

static inline int poly_region_columns(const poly_state_t *s, int k)
{
    const poly_region_t *r = &s->reg[k];
    int w = s->tw[r->level] - r->x;
    return w < 128 ? w : 128;
}

/* The last GP: the READ_BS_BOX words of GP h's box of region k (in
 * backing-store block `block`), false when h reads none of it. */
static inline bool poly_box_request(poly_state_t *s, unsigned h, unsigned n_gp, int k,
                                    unsigned block, uint32_t args[6], poly_count_t *cnt)
{
    const poly_region_t *reg = &s->reg[k];
    int y0, y1, jlo, jhi, a, b;
    poly_band_rows(s, h, n_gp, &y0, &y1);
    poly_band_texel_rows(s, y0, y1, reg->level, &jlo, &jhi);
    /* GP h's band (a multiply and a divide by the GP count: [I] a
     * reciprocal table), its texel rows, the region's rows, the message's
     * six words */
    POLY_SPAN(&s->sp, cnt, VRZ_BOX, .loads = 3, .int_ops = 14, .stores = 6, .branches = 3);
    if (y1 <= y0 || !poly_region_rows(s, k, jlo, jhi, &a, &b))
        return false;
    uint32_t sx = (uint32_t)poly_region_columns(s, k);
    args[0] = block;
    args[1] = 128u | 1u << 8 | 128u << 16;          /* the region: 128 x 1 x 128 PPs */
    args[2] = ring_addr_pack(ring_addr(RING_NODE_GP, h));
    args[3] = (uint32_t)k;
    args[4] = (uint32_t)(a - reg->y) << 16;
    args[5] = sx | (uint32_t)(b - a + 1) << 8 | 1u << 16;
    return true;
}

/* Where texel row j of region k goes in this GP's level rows (a word
 * index). */
static inline size_t poly_texel_row_at(poly_state_t *s, int k, int j, poly_count_t *cnt)
{
    const poly_region_t *reg = &s->reg[k];
    int l = reg->level;
    /* the row's place (subtract, multiply, 2 adds, the byte address) and
     * the loop */
    POLY_SPAN(&s->sp, cnt, VRZ_TEXEL_ROW, .loads = 2, .int_ops = 6, .branches = 1);
    return (size_t)(j - s->jlo[l]) * (size_t)s->tw[l] + (size_t)reg->x;
}

/* A section of the band leaves for the frame buffer. */
static inline void poly_section_sent(poly_spans_t *sp, poly_count_t *cnt)
{
    /* the section's size, allocation and message words */
    POLY_SPAN(sp, cnt, VRZ_SECTION, .int_ops = 8, .stores = 6, .branches = 2);
}

#endif
