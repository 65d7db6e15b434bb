/* mip2d_row.c: row-at-a-time 2DLevel, texel marking and RenderPixel (see
 * mip2d_row.h); each fast path does the reference's arithmetic, only less
 * often, so results are bit-identical. */
#include "mip2d_row.h"

#include <math.h>
#include <string.h>

#include "renderer_native.h"
#include "vec4.h"

/* Distance used by the renderer: exactly the reference's expression. */
static inline double level_radius(int x, double dy2, double gaze_x, double scale)
{
    double dx = (double)x - gaze_x;
    return sqrt(dx * dx + dy2) / scale;
}

void gaze_level_row_reference(const gaze_model_t *g, int y, int width, double gaze_x,
                              double gaze_y, double scale, float *levels)
{
    for (int x = 0; x < width; x++) {
        double dx = (double)x - gaze_x, dy = (double)y - gaze_y;
        levels[x] = gaze_level(g, sqrt(dx * dx + dy * dy) / scale);
    }
}

/* Why this is exact: every step of level_radius (subtraction, square, sum,
 * sqrt, division by a positive scale) is a correctly rounded, monotone
 * operation, so r never decreases as x moves away from the gaze column.  The
 * pixels at the periphery level (r >= r_max_px, where gaze_level returns
 * level_edge without computing anything) are therefore a prefix and a
 * suffix of the row, found by binary search; only the pixels between are
 * evaluated, with the reference's own expression. */
void gaze_level_row(const gaze_model_t *g, int y, int width, double gaze_x, double gaze_y,
                    double scale, float *levels)
{
    double dy = (double)y - gaze_y;
    double dy2 = dy * dy;
    /* First x whose dx is >= 0 (the right half, where r grows with x). */
    int split;
    if (!(gaze_x > 0.0))
        split = 0;
    else if (gaze_x > (double)width)
        split = width;
    else
        split = (int)ceil(gaze_x);
    /* Left half [0, split): r falls with x; find the first x with r < r_max. */
    int lo = 0, hi = split;
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (level_radius(mid, dy2, gaze_x, scale) >= g->r_max_px)
            lo = mid + 1;
        else
            hi = mid;
    }
    int x_begin = lo;
    /* Right half [split, width): r grows with x; first x with r >= r_max. */
    lo = split;
    hi = width;
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (level_radius(mid, dy2, gaze_x, scale) >= g->r_max_px)
            hi = mid;
        else
            lo = mid + 1;
    }
    int x_end = lo;
    /* r_max_px > r_zero_px, so these pixels take gaze_level's second branch. */
    for (int x = 0; x < x_begin; x++)
        levels[x] = g->level_edge;
    /* A gaze on a pixel centre or edge (2 gaze_x an integer, e.g. the image
     * centre): pixel x and its mirror 2 gaze_x - x have dx of exactly
     * opposite sign (all values are small multiples of 1/2), hence the same
     * dx * dx and level; the left half copies the right one. */
    double twice = 2.0 * gaze_x;
    int mirror = fabs(twice) < 1e9 && twice == floor(twice) ? (int)twice : -1;
    int copy_begin = split, copy_end = split;   /* [copy_begin, copy_end) mirrored */
    if (mirror >= 0 && x_begin < split) {
        /* x < split mirrors to mirror - x >= split; usable when < x_end. */
        copy_begin = mirror - x_end + 1 > x_begin ? mirror - x_end + 1 : x_begin;
        if (copy_begin > split)
            copy_begin = split;
        copy_end = split;
    }
    for (int x = x_begin; x < copy_begin; x++)
        levels[x] = gaze_level(g, level_radius(x, dy2, gaze_x, scale));
    for (int x = split > x_begin ? split : x_begin; x < x_end; x++)
        levels[x] = gaze_level(g, level_radius(x, dy2, gaze_x, scale));
    for (int x = copy_begin; x < copy_end; x++)
        levels[x] = levels[mirror - x];
    for (int x = x_end; x < width; x++)
        levels[x] = g->level_edge;
}

/* need[] of texel row j of level l: columns i0..i1 set. */
static void mark_span(mip2d_t *m, int l, int x0, int x1, int y)
{
    /* mark_level (gaze2d.c) sets, per pixel x, texel x >> l and, when x has a
     * fractional part at level l, texel (x >> l) + 1; in both texel rows
     * y >> l and (if y has a fractional part) the next one.  Over x0..x1
     * (inclusive) that union is x0 >> l .. x1 >> l, plus one more when x1
     * itself has a fractional part (the block x1 falls in starts before x1
     * and has no other member later than x1). */
    int mask = (1 << l) - 1;
    int i0 = x0 >> l, i1 = (x1 >> l) + ((x1 & mask) != 0);
    int j = y >> l;
    int w = m->w[l];
    size_t n = (size_t)(i1 - i0 + 1);
    memset(m->need[l] + (size_t)j * w + i0, 1, n);
    if (y & mask)
        memset(m->need[l] + (size_t)(j + 1) * w + i0, 1, n);
}

/* What mip2d_mark_pixel does with a level depends only on its floor level
 * (clamped to the top one) and whether the next level is blended in: pixels
 * with the same pair mark the same texel rows, so a run of them is one span
 * per level, whatever the levels' exact values (the Gaussian falloff has a
 * different level at nearly every pixel but few distinct pairs). */
static inline int mark_key(const mip2d_t *m, float level)
{
    int l = (int)level;
    if (l >= m->levels)
        l = m->levels - 1;
    bool blend = level > (float)l && l + 1 < m->levels;
    return 2 * l + blend;
}

bool mip2d_mark_row_runs(mip2d_t *m, int y, const float *levels, int width)
{
    bool full = true;
    for (int x = 0; x < width && full; x++)
        full = levels[x] == 0.0f;
    int x0 = 0;
    while (x0 < width) {
        int key = mark_key(m, levels[x0]);
        int x1 = x0;
        while (x1 + 1 < width && (levels[x1 + 1] == levels[x1] ||
                                  mark_key(m, levels[x1 + 1]) == key))
            x1++;
        int l = key >> 1;
        mark_span(m, l, x0, x1, y);
        if (key & 1)
            mark_span(m, l + 1, x0, x1, y);
        x0 = x1 + 1;
    }
    return full;
}

/* render_to_u8 without branches: clamping to [0, 1] first leaves the
 * in-range expression v * 255 + 0.5 unchanged, maps v >= 1 to 255.5 -> 255
 * and v <= 0 or NaN to 0.5 -> 0, exactly the reference's three cases. */
static inline uint8_t to_u8_clamped(float v)
{
    float c = v > 0.0f ? v : 0.0f;
    c = c < 1.0f ? c : 1.0f;
    return (uint8_t)(c * 255.0f + 0.5f);
}

void mip2d_render_row_reference(const mip2d_t *m, int y, const float *levels, int width,
                                uint8_t *rgb)
{
    for (int x = 0; x < width; x++) {
        float c[3];
        mip2d_pixel(m, x, y, levels[x], c);
        rgb[3 * x + 0] = render_to_u8(c[0]);
        rgb[3 * x + 1] = render_to_u8(c[1]);
        rgb[3 * x + 2] = render_to_u8(c[2]);
    }
}

/* to_u8_clamped on four lanes: the same clamps (v4f_max and v4f_min are
 * its two comparisons, a NaN giving 0 as there), the same multiply and
 * add, the same truncation. */
static inline v4i to_u8_clamped4(v4f v)
{
    const v4f zero = {0.0f, 0.0f, 0.0f, 0.0f}, one = {1.0f, 1.0f, 1.0f, 1.0f};
    v4f c = v4f_min(v4f_max(v, zero), one);
    return __builtin_convertvector(c * 255.0f + 0.5f, v4i);
}

/* bilerp() of gaze2d.c for pixel x of a row whose texel row pointer, row
 * stride and vertical weight are known, the three channels in lanes 0-2
 * (lane 3 reads the next float, which mip2d_init allocates, and is never
 * used): per lane the same expressions in the same order.  bilerp's corner
 * choice reduces to offsets: with u > 0 the right-hand corners are the next
 * texels (c11 is c01 + 1 whether or not v > 0), with u = 0 they are the
 * left-hand ones themselves. */
static inline v4f bilerp_in_row(const float *row0, size_t stride3, int l, int x, float v,
                                const float *u_of_phase)
{
    int phase = x & ((1 << l) - 1);
    float u = u_of_phase[phase];                /* (x - (i << l)) / 2^l */
    const float *c00 = row0 + (size_t)(x >> l) * 3;
    const float *c01 = v > 0.0f ? c00 + stride3 : c00;
    size_t right = phase != 0 ? 3 : 0;
    v4f a = v4f_load(c00), b = v4f_load(c01);
    v4f top = a + u * (v4f_load(c00 + right) - a);
    v4f bottom = b + u * (v4f_load(c01 + right) - b);
    return top + v * (bottom - top);
}

/* Level 0 at weight u = v = 0: bilerp returns c00 + 0 * 0 terms, i.e. the
 * texel itself for any finite colour (a -0 texel becomes +0, the same
 * byte); four floats at a time (they span pixels: a row's channels are
 * contiguous). */
static void render_level0_run(const float *src, int x0, int x1, uint8_t *rgb)
{
    size_t f = 3 * (size_t)x0, end = 3 * (size_t)x1;
    for (; f + 4 <= end; f += 4) {
        v4i c = to_u8_clamped4(v4f_load(src + f));
        rgb[f + 0] = (uint8_t)c[0];
        rgb[f + 1] = (uint8_t)c[1];
        rgb[f + 2] = (uint8_t)c[2];
        rgb[f + 3] = (uint8_t)c[3];
    }
    for (; f < end; f++)
        rgb[f] = to_u8_clamped(src[f]);
}

/* One level, block by block: the 2^l pixels of a texel column share their
 * corners, so they are loaded once; per pixel the reference's expressions
 * with its u (phase 0 keeps u = 0 and right-hand corners equal to the
 * left-hand ones). */
static void render_level_run(const float *row0, size_t stride3, int l, float v,
                             const float *u_of_phase, int x0, int x1, uint8_t *rgb)
{
    int mask = (1 << l) - 1;
    size_t down = v > 0.0f ? stride3 : 0;
    for (int x = x0; x < x1;) {
        int i = x >> l;
        int block_end = (i + 1) << l;
        if (block_end > x1)
            block_end = x1;
        const float *c00 = row0 + (size_t)i * 3, *c01 = c00 + down;
        v4f a = v4f_load(c00), b = v4f_load(c01);
        /* Right-hand corners only exist (and are read) for phase > 0. */
        bool has_right = (block_end - 1) & mask;
        v4f ra = has_right ? v4f_load(c00 + 3) : a, rb = has_right ? v4f_load(c01 + 3) : b;
        for (; x < block_end; x++) {
            int phase = x & mask;
            float u = u_of_phase[phase];
            v4f e = phase ? ra : a, f = phase ? rb : b;
            v4f p = a + u * (e - a), q = b + u * (f - b);
            v4i_store_u8x3(rgb + 3 * (size_t)x, to_u8_clamped4(p + v * (q - p)));
        }
    }
}

void mip2d_render_row(const mip2d_t *m, int y, const float *levels, int width, uint8_t *rgb)
{
    /* Per level: the texel row, stride and vertical weight of this image row
     * (bilerp's j and v), computed once per row instead of per pixel. */
    const float *row0[MIP2D_MAX_LEVELS];
    size_t stride3[MIP2D_MAX_LEVELS];
    float vw[MIP2D_MAX_LEVELS];
    /* bilerp's horizontal weight for each pixel phase x mod 2^l, with its
     * expression; at most 255 divisions a row instead of one a pixel. */
    float u_table[MIP2D_MAX_LEVELS][1 << (MIP2D_MAX_LEVELS - 1)];
    for (int l = 0; l < m->levels; l++)
        for (int f = 0; f < (1 << l); f++)
            u_table[l][f] = (float)f / (float)(1 << l);
    for (int l = 0; l < m->levels; l++) {
        int j = y >> l;
        float s = (float)(1 << l);
        vw[l] = (float)(y - (j << l)) / s;
        stride3[l] = (size_t)m->w[l] * 3;
        row0[l] = m->rgb[l] + (size_t)j * stride3[l];
    }
    int x0 = 0;
    while (x0 < width) {
        float level = levels[x0];
        int x1 = x0 + 1;
        while (x1 < width && levels[x1] == level)
            x1++;
        int lo = (int)level;
        if (lo >= m->levels)
            lo = m->levels - 1;
        float t = level - (float)lo;
        bool blend = t > 0.0f && lo + 1 < m->levels;
        if (lo == 0 && !blend) {
            render_level0_run(row0[0], x0, x1, rgb);
        } else if (!blend) {
            render_level_run(row0[lo], stride3[lo], lo, vw[lo], u_table[lo], x0, x1, rgb);
        } else {
            for (int x = x0; x < x1; x++) {
                v4f c = bilerp_in_row(row0[lo], stride3[lo], lo, x, vw[lo], u_table[lo]);
                v4f hi = bilerp_in_row(row0[lo + 1], stride3[lo + 1], lo + 1, x, vw[lo + 1],
                                       u_table[lo + 1]);
                v4i_store_u8x3(rgb + 3 * (size_t)x, to_u8_clamped4(c + t * (hi - c)));
            }
        }
        x0 = x1;
    }
}
