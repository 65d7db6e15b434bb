/* vec4.h: four floats (or ints) side by side, GCC's vector extension.
 * Each lane does exactly the scalar operation: the build is ISO C (no
 * fused multiply-add), so a lane's result is the scalar expression's,
 * bit for bit.  On x86-64 these are SSE registers. */
#ifndef PP5_VEC4_H
#define PP5_VEC4_H

#include <stdint.h>
#include <string.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

typedef float v4f __attribute__((vector_size(16)));
typedef int v4i __attribute__((vector_size(16)));

/* Four floats from p, unaligned. */
static inline v4f v4f_load(const float *p)
{
    v4f v;
    memcpy(&v, p, sizeof v);
    return v;
}

/* a where mask is set, else b (mask lanes all ones or all zeros). */
static inline v4f v4f_select(v4i mask, v4f a, v4f b)
{
    return (v4f)(((v4i)a & mask) | ((v4i)b & ~mask));
}

/* a > b ? a : b per lane, so b where a is NaN (SSE's MAXPS exactly). */
static inline v4f v4f_max(v4f a, v4f b)
{
#if defined(__SSE2__)
    return (v4f)_mm_max_ps((__m128)a, (__m128)b);
#else
    return v4f_select(a > b, a, b);
#endif
}

/* a < b ? a : b per lane, so b where a is NaN (SSE's MINPS exactly). */
static inline v4f v4f_min(v4f a, v4f b)
{
#if defined(__SSE2__)
    return (v4f)_mm_min_ps((__m128)a, (__m128)b);
#else
    return v4f_select(a < b, a, b);
#endif
}

/* Lanes 0-2, each in 0..255, as three bytes at dst (lane 3 is not
 * written). */
static inline void v4i_store_u8x3(uint8_t *dst, v4i c)
{
#if defined(__SSE2__)
    __m128i w = _mm_packs_epi32((__m128i)c, (__m128i)c);    /* exact: 0..255 fit */
    uint32_t bytes = (uint32_t)_mm_cvtsi128_si32(_mm_packus_epi16(w, w));
    memcpy(dst, &bytes, 3);       /* x86 is little-endian: lane 0 first */
#else
    dst[0] = (uint8_t)c[0];
    dst[1] = (uint8_t)c[1];
    dst[2] = (uint8_t)c[2];
#endif
}

#endif
