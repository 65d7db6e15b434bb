/* poly_phong_pp.c: the deferred Phong shading stream of a region (poly_phong_pp.h). */
#include "common/poly_phong_pp.h"

#include <math.h>

/* E = covered (and, with `back` 0 or 1, the pixels of that side only). */
static void enable_covered(pp_stream_t *s, int back)
{
    pp_emit_en_all(s);
    pp_emit_f_ld(s, POLY_PP_COVER);
    pp_emit_en_flag(s);
    if (back < 0)
        return;
    pp_emit_f_ld(s, POLY_PP_BACK);
    if (back)
        pp_emit_en_and(s);
    else
        pp_emit_en_andn(s);
}

/* D = N.L: each term by |L_k| (a positive constant costs a pass per 1 bit
 * only, PP_ISA.md) and added or subtracted. */
static void dot_light(pp_stream_t *s, const float light[3])
{
    static const unsigned n[3] = {POLY_PP_NX, POLY_PP_NY, POLY_PP_NZ};
    pp_emit_seti(s, POLY_PP_D, 32, 0);
    for (int k = 0; k < 3; k++) {
        int32_t l = (int32_t)lrintf(light[k] * (float)POLY_N_ONE);
        pp_emit_muli(s, POLY_PP_P, 32, n[k], 16, true, l < 0 ? -l : l);
        if (l < 0)
            pp_emit_sub(s, POLY_PP_D, POLY_PP_D, POLY_PP_P, 32);
        else
            pp_emit_add(s, POLY_PP_D, POLY_PP_D, POLY_PP_P, 32);
    }
}

/* S = |N|^2 with 2^14 = 1, at least 0.25 + 2^-14 (so 1/|N| < 2). */
static void length_squared(pp_stream_t *s)
{
    static const unsigned n[3] = {POLY_PP_NX, POLY_PP_NY, POLY_PP_NZ};
    for (int k = 0; k < 3; k++) {
        pp_emit_mul(s, POLY_PP_P, 32, n[k], n[k], 16, true);
        if (k == 0)
            pp_emit_copy(s, POLY_PP_S, POLY_PP_P + 14, 16);
        else
            pp_emit_add(s, POLY_PP_S, POLY_PP_S, POLY_PP_P + 14, 16);
    }
    pp_emit_cmpi(s, PP_CMP_LTU, POLY_PP_S, 16, 4097);
    pp_emit_en_and(s);
    pp_emit_seti(s, POLY_PP_S, 16, 4097);
    enable_covered(s, -1);
}

/* RS = 1/sqrt(S), 2^14 = 1. */
static void inverse_length(pp_stream_t *s)
{
    pp_emit_shr(s, POLY_PP_W, POLY_PP_S, 16, 1);
    pp_emit_seti(s, POLY_PP_RS, 16, 24576);
    pp_emit_sub(s, POLY_PP_RS, POLY_PP_RS, POLY_PP_W, 16);
    for (int step = 0; step < 3; step++) {
        pp_emit_mul(s, POLY_PP_P, 32, POLY_PP_RS, POLY_PP_RS, 16, false);   /* r^2, 2^28 = 1 */
        pp_emit_copy(s, POLY_PP_W, POLY_PP_P + 14, 16);
        pp_emit_mul(s, POLY_PP_P, 32, POLY_PP_S, POLY_PP_W, 16, false);     /* u = S r^2 */
        pp_emit_seti(s, POLY_PP_W, 16, 24576);
        pp_emit_sub(s, POLY_PP_W, POLY_PP_W, POLY_PP_P + 15, 16);           /* 3/2 - u/2 */
        pp_emit_mul(s, POLY_PP_P, 32, POLY_PP_RS, POLY_PP_W, 16, false);
        pp_emit_copy(s, POLY_PP_RS, POLY_PP_P + 14, 16);
    }
}

/* The channels of one side from c = P + 14 (2^14 = 1). */
static void channels(pp_stream_t *s, int back, const int32_t rgb[3], float ambient, float diffuse)
{
    static const unsigned out[3] = {POLY_PP_R, POLY_PP_G, POLY_PP_B};
    for (int k = 0; k < 3; k++) {
        enable_covered(s, back);
        int32_t kd = (int32_t)lrintf((float)rgb[k] * diffuse * 256.0f);
        uint32_t ka = (uint32_t)lrint(((double)rgb[k] * ambient + 0.5) * 4194304.0);
        pp_emit_muli(s, POLY_PP_D, 32, POLY_PP_P + 14, 16, false, kd);
        pp_emit_addi(s, POLY_PP_D, POLY_PP_D, 32, ka);
        pp_emit_copy(s, out[k], POLY_PP_D + 22, 8);
        pp_emit_cmpi(s, PP_CMP_GEU, POLY_PP_D, 32, 256u << 22);
        pp_emit_en_and(s);
        pp_emit_seti(s, out[k], 8, 255);
    }
}

/* Colours per pixel (each triangle wrote its side's colour into R, G, B):
 * I = c Kd + Ka (2^28 = 1; Kd = round(diffuse 2^14), Ka = round(ambient
 * 2^28)), kept in S as 16 bits (2^14 = 1, so ambient + diffuse < 4); then
 * each channel min(255, floor(I ch + 0.5)), mesh_render's rgb I rounded. */
static void channels_per_pixel(pp_stream_t *s, float ambient, float diffuse)
{
    static const unsigned out[3] = {POLY_PP_R, POLY_PP_G, POLY_PP_B};
    int32_t kd = (int32_t)lrintf(diffuse * 16384.0f);
    uint32_t ka = (uint32_t)lrint((double)ambient * 268435456.0);
    enable_covered(s, -1);
    pp_emit_muli(s, POLY_PP_D, 32, POLY_PP_P + 14, 16, false, kd);
    pp_emit_addi(s, POLY_PP_D, POLY_PP_D, 32, ka);
    pp_emit_copy(s, POLY_PP_S, POLY_PP_D + 14, 16);
    for (int k = 0; k < 3; k++) {
        pp_emit_seti(s, POLY_PP_W, 16, 0);
        pp_emit_copy(s, POLY_PP_W, out[k], 8);
        pp_emit_mul(s, POLY_PP_D, 32, POLY_PP_S, POLY_PP_W, 16, false);
        pp_emit_addi(s, POLY_PP_D, POLY_PP_D, 32, 8192);
        pp_emit_copy(s, out[k], POLY_PP_D + 14, 8);
        pp_emit_cmpi(s, PP_CMP_GEU, POLY_PP_D, 32, 256u << 14);
        pp_emit_en_and(s);
        pp_emit_seti(s, out[k], 8, 255);
        enable_covered(s, -1);
    }
}

void poly_phong_stream(pp_stream_t *s, const float light[3], float ambient, float diffuse,
                       const int32_t front_rgb[3], const int32_t back_rgb[3], bool per_pixel)
{
    enable_covered(s, -1);
    dot_light(s, light);
    length_squared(s);
    inverse_length(s);
    /* c = max(0, D) / |N| */
    pp_emit_cmpi(s, PP_CMP_LTS, POLY_PP_D, 32, 0);
    pp_emit_en_and(s);
    pp_emit_seti(s, POLY_PP_D, 32, 0);
    enable_covered(s, -1);
    pp_emit_mul(s, POLY_PP_P, 32, POLY_PP_D + 14, POLY_PP_RS, 16, false);
    if (per_pixel) {
        channels_per_pixel(s, ambient, diffuse);
    } else {
        channels(s, 0, front_rgb, ambient, diffuse);
        channels(s, 1, back_rgb, ambient, diffuse);
    }
    pp_emit_en_all(s);
}
