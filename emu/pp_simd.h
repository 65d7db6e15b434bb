/* pp_simd.h: build switches shared by the bit-sliced kernels (pp_array.c, qee.c, bit_transpose.c).
 *
 * The kernels (pp_kernels.inc, qee_kernels.inc, bit_transpose_kernels.inc)
 * are compiled in up to three copies by pp_simd_copies.inc:
 *   *_avx512  64-byte GCC vectors under `#pragma GCC target("avx512f")`,
 *   *_avx2    32-byte vectors under `#pragma GCC target("avx2")`,
 *   *_base    16-byte vectors that any x86-64 (SSE2) or other host handles well.
 * Each PP array runs one of them, chosen at run time (pp_kernel_level.h:
 * the fastest the host supports, or the one a test forces with
 * pp_array_set_kernels).  Only bitwise operations are used, so every copy
 * computes the same bits: results never depend on the host.  pp_vec.inc
 * defines the vector helpers of one copy. */
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
/* Whether the AVX2 and AVX-512 copies are built: GCC on x86-64 (its target
 * pragmas and __builtin_cpu_supports); PP5_NO_CLONES leaves only the base copy. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(PP5_NO_CLONES)
#define PP_HAVE_X86_COPIES 1
#else
#define PP_HAVE_X86_COPIES 0
#endif
#if PP_HAVE_X86_COPIES
#include <immintrin.h>   /* the AVX-512 copy's three-input logic (pp_vec.inc) */
#endif

#endif
