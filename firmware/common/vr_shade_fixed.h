/* vr_shade_fixed.h: the fixed-point formats of the mip map in PP backing store and the per-voxel viewpoint-dependent shading, as integer C.
 *
 * One definition used three ways: the GP split shades fetched voxels with it,
 * the host checks the PP stream (firmware/pp/vr_shade_pp.c) against it bit
 * for bit, and the host's like-for-like native reference quantises with it.
 *
 * Formats (every value fits one 32-bit backing-store block, facts §3.1):
 *   block A  r8 | g8 << 8 | b8 << 16 | a8 << 24: opacity-weighted colour and
 *            opacity, q = round(clamp(v, 0, 1) * 255).  In the specular case
 *            RGB is already diffuse-shaded (viewpoint-independent, mip3d.h).
 *   block N  unit normal, three signed 10-bit fields nx | ny << 10 | nz << 20,
 *            n = round(N * 511) (the GP renormalises the filtered a*N).
 *   block O  the shaded output, same layout as A.
 * Per frame the half vector H becomes three signed immediates
 * h = round(H * 2^21 / 511), so N.H has scale 2^21 exactly (up to rounding)
 * and x = |N.H| >> 6 is Q15.  (N.H)^e by square-and-multiply with
 * y = (y * y) >> 15 (truncating); specular in units of 1/255:
 * s = (((y * ks8) >> 15) * a8 + 128) >> 8 with ks8 = round(ks * 256); each
 * channel saturates at 255.  Errors against float shading are documented in
 * firmware/ARCHITECTURE.md ("Where the machine's image differs"). */
#ifndef PP5_VR_SHADE_FIXED_H
#define PP5_VR_SHADE_FIXED_H

#include <math.h>
#include <stdint.h>
#include "vr_cost.h"

#define VR_N_SCALE 511.0f
#define VR_H_SCALE (2097152.0 / 511.0)

typedef struct {
    int32_t h[3];          /* half vector immediates */
    int32_t ks8;           /* round(ks * 256) */
    int32_t exponent;      /* integer specular exponent 1..255 */
    int32_t two_sided;
    /* Moving object (paper §5): diffuse per frame too.  l = light immediates
     * (same scale as h); shade sh = ka15 + (((|N.L| + 32) >> 6) * kd15 + 2^14 >> 15)
     * in Q15, ka15 + kd15 for a zero normal (render/'s "no surface"); each
     * channel becomes min(255, (c * sh + 2^14) >> 15) before the specular. */
    int32_t diffuse_on;
    int32_t l[3];
    int32_t ka15, kd15;
} vr_shade_consts_t;

static inline uint32_t vr_q8(float v)
{
    if (!(v > 0.0f))
        return 0;
    if (v >= 1.0f)
        return 255;
    return (uint32_t)(v * 255.0f + 0.5f);
}

static inline int32_t vr_q_normal(float v)
{
    float s = v * VR_N_SCALE;
    int32_t q = (int32_t)lrintf(s);
    return q > 511 ? 511 : (q < -511 ? -511 : q);
}

static inline uint32_t vr_pack_normal(const float n[3])
{
    uint32_t w = 0;
    for (int k = 0; k < 3; k++)
        w |= ((uint32_t)vr_q_normal(n[k]) & 0x3ffu) << (10 * k);
    return w;
}

static inline int32_t vr_sext10(uint32_t v)
{
    v &= 0x3ffu;
    return (v & 0x200u) ? (int32_t)v - 1024 : (int32_t)v;
}

static inline void vr_shade_consts(vr_shade_consts_t *c, const float half[3], float ks, int exponent,
                                   int two_sided)
{
    for (int k = 0; k < 3; k++)
        c->h[k] = (int32_t)lrint((double)half[k] * VR_H_SCALE);
    c->ks8 = (int32_t)lrintf(ks * 256.0f);
    c->exponent = exponent;
    c->two_sided = two_sided;
    c->diffuse_on = 0;
    c->l[0] = c->l[1] = c->l[2] = 0;
    c->ka15 = c->kd15 = 0;
}

/* Adds the per-frame diffuse term (moving object): light l (unit, object space). */
static inline void vr_shade_consts_diffuse(vr_shade_consts_t *c, const float l[3], float ka, float kd)
{
    c->diffuse_on = 1;
    for (int k = 0; k < 3; k++)
        c->l[k] = (int32_t)lrint((double)l[k] * VR_H_SCALE);
    c->ka15 = (int32_t)lrintf(ka * 32768.0f);
    c->kd15 = (int32_t)lrintf(kd * 32768.0f);
}

/* (x / 2^15)^e in Q15 by square-and-multiply from the exponent's top bit.
 * Spans: SHADE_TOP per bit above the top one found, SHADE_SQUARE per
 * squaring, SHADE_MULTIPLY per set bit below the top. */
static inline uint32_t vr_pow_q15_counted(uint32_t x, int e, vr_spans_t *sp, vr_count_t *cnt)
{
    int top = 0;
    while ((e >> (top + 1)) != 0) {
        top++;
        VR_SPAN(sp, cnt, SHADE_TOP, .int_ops = 2 + 1, .branches = 1);   /* top + 1, shift, ++; test */
    }
    uint32_t y = x;
    for (int b = top - 1; b >= 0; b--) {
        y = (uint32_t)(((uint64_t)y * y) >> 15) & 0xffffu;
        /* the square (multiply, shift, mask); the bit test (shift, and);
         * the loop (decrement, test) */
        VR_SPAN(sp, cnt, SHADE_SQUARE, .int_ops = 3 + 2 + 1, .branches = 1 + 1);
        if ((e >> b) & 1) {
            y = (uint32_t)(((uint64_t)y * x) >> 15) & 0xffffu;
            VR_SPAN(sp, cnt, SHADE_MULTIPLY, .int_ops = 3);
        }
    }
    return y;
}

static inline uint32_t vr_pow_q15(uint32_t x, int e)
{
    return vr_pow_q15_counted(x, e, NULL, NULL);
}

/* N.h in the normal's fixed point: three sign-extended 10-bit fields times
 * the immediates (per field: shift but the first, mask, sign test and
 * subtract, multiply, add but the first). */
static inline int32_t vr_dot10(uint32_t n_blk, const int32_t h[3])
{
    int32_t d = 0;
    for (int k = 0; k < 3; k++)
        d += vr_sext10(n_blk >> (10 * k)) * h[k];
    return d;
}
#define VR_DOT10_INT_OPS (2 + 3 * (1 + 2 + 1) + 2)   /* 2 shifts, 3 x (mask, test+subtract, multiply), 2 adds */

/* Shaded block O from blocks A and N.  Spans: SHADE_VOXEL, SHADE_DIFFUSE
 * (moving object), and vr_pow_q15's. */
static inline uint32_t vr_shade_voxel_counted(const vr_shade_consts_t *c, uint32_t a_blk,
                                              uint32_t n_blk, vr_spans_t *sp, vr_count_t *cnt)
{
    if (c->diffuse_on) {
        int32_t dl = vr_dot10(n_blk, c->l);
        if (dl < 0)
            dl = c->two_sided ? -dl : 0;
        /* rounded shifts: truncation would darken every voxel by about 1/255 */
        uint32_t xl = ((uint32_t)(dl + 32) >> 6) & 0xffffu;
        uint32_t sh = (((uint32_t)((((uint64_t)xl * (uint32_t)c->kd15 + 16384u) >> 15) & 0x1ffffu)) +
                       (uint32_t)c->ka15) & 0x3ffffu;
        if ((n_blk & 0x3fffffffu) == 0)
            sh = (uint32_t)(c->ka15 + c->kd15) & 0x3ffffu;
        uint32_t shaded = a_blk & 0xff000000u;
        for (int k = 0; k < 3; k++) {
            uint32_t ch = (a_blk >> (8 * k)) & 0xffu;
            uint32_t v = (uint32_t)((((uint64_t)ch * sh + 16384u) >> 15) & 0xffffu);
            if (v > 255u)
                v = 255u;
            shaded |= v << (8 * k);
        }
        a_blk = shaded;
        /* N.L (3 sign tests); |N.L| or max (compare, two-sided test,
         * negate); xl (add, shift, mask); sh (multiply, add, shift, mask,
         * add, mask); the zero-normal select (mask, test, add); the alpha
         * mask; per channel byte (shift but the first, mask), multiply, add,
         * shift, mask, saturate (compare), shift but the first, or (9; 7 for
         * the first channel) */
        VR_SPAN(sp, cnt, SHADE_DIFFUSE, .int_ops = VR_DOT10_INT_OPS + 2 + 3 + 6 + 2 + 1 + (3 * 9 - 2),
                .branches = 3 + 2 + 1 + 3);
    }
    int32_t d = vr_dot10(n_blk, c->h);
    if (d < 0)
        d = c->two_sided ? -d : 0;
    uint32_t x = ((uint32_t)d >> 6) & 0xffffu;
    uint32_t y = vr_pow_q15_counted(x, c->exponent, sp, cnt);
    uint32_t s = (uint32_t)((((uint64_t)y * (uint32_t)c->ks8) >> 15) & 0xffffu);
    uint32_t a8 = a_blk >> 24;
    uint32_t spec = ((s * a8 + 128u) & 0xffffffu) >> 8;
    uint32_t out = a_blk & 0xff000000u;
    for (int k = 0; k < 3; k++) {
        uint32_t v = ((a_blk >> (8 * k)) & 0xffu) + spec;
        if (v > 255u)
            v = 255u;
        out |= v << (8 * k);
    }
    /* the diffuse test; N.H (3 sign tests); |N.H| or max (compare,
     * two-sided test, negate); x (shift, mask); the power's last top test
     * (shift, compare) and y = x; s (multiply, shift, mask); a8; spec
     * (multiply, add, mask, shift); the alpha mask; per channel byte (shift
     * but the first, mask), add, saturate (compare), shift but the first,
     * or (6; 4 for the first channel) */
    VR_SPAN(sp, cnt, SHADE_VOXEL, .int_ops = VR_DOT10_INT_OPS + 2 + 2 + 2 + 3 + 1 + 4 + 1 + (3 * 6 - 2),
            .branches = 1 + 3 + 2 + 1 + 3);
    return out;
}

static inline uint32_t vr_shade_voxel(const vr_shade_consts_t *c, uint32_t a_blk, uint32_t n_blk)
{
    return vr_shade_voxel_counted(c, a_blk, n_blk, NULL, NULL);
}

#endif
