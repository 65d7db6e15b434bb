/* pp_simd.h: build switches shared by the bit-sliced kernels (pp_array.c, qee.c, bit_transpose.c).
 *
 * The kernels (pp_kernels.inc, qee_kernels.inc, bit_transpose_kernels.inc)
 * are compiled twice by pp_simd_copies.inc: with 32-byte GCC vectors under
 * `#pragma GCC target("avx2")` (names *_avx2) and with 16-byte vectors that
 * any x86-64 (SSE2) or other host handles well (names *_base); each PP array
 * picks one at run time (pp_array_set_avx2).  Only bitwise operations are
 * used, so both copies compute the same bits: results never depend on the
 * host.  pp_vec.inc defines the vector helpers of one copy. */
#ifndef PP5_PP_SIMD_H
#define PP5_PP_SIMD_H

#include <stdint.h>

#define INLINE static inline __attribute__((always_inline))
#if defined(__GNUC__) && !defined(__clang__)
/* Fully unroll the per-vector loops so carries and enables stay in registers. */
#define UNROLL _Pragma("GCC unroll 8")
/* GCC 12 reports the fully unrolled, fully initialised carry arrays of the
 * kernels as "may be used uninitialized" (a false positive). */
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#else
#define UNROLL
#endif
/* Whether the AVX2 copies are built (GCC on x86-64; PP5_NO_CLONES disables). */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(PP5_NO_CLONES)
#define PP_HAVE_AVX2_COPY 1
#else
#define PP_HAVE_AVX2_COPY 0
#endif

#endif
