/* pp_simd.h: the 4-word vector type and helpers shared by the bit-sliced kernels (pp_array.c, qee.c).
 *
 * GCC/Clang vector extension: AVX2 when the function is compiled for it (the
 * PP_CLONES dispatchers are cloned for AVX2 and chosen at load time), else
 * pairs of SSE2 or scalar operations.  Every variant computes the same bits:
 * only bitwise operations are used, so results never depend on the host. */
#ifndef PP5_PP_SIMD_H
#define PP5_PP_SIMD_H

#include <stdint.h>

#ifndef PP_SIMD_NO_V4   /* pp_array.c defines its vectors in pp_kernels.inc */
typedef uint64_t v4_t __attribute__((vector_size(32)));
/* The same vector as a memory access: any alignment of 8, may alias uint64_t. */
typedef uint64_t v4_mem_t __attribute__((vector_size(32), aligned(8), may_alias));
#define VW 4u                     /* words per vector */

/* Macros rather than functions: no vector crosses a call (no -Wpsabi ABI notes). */
#define ld(p) ((v4_t)*(const v4_mem_t *)(const void *)(p))
#define st(p, v) (*(v4_mem_t *)(void *)(p) = (v))
#define splat(x) ((v4_t){(x), (x), (x), (x)})
/* Masked write: where e, new; elsewhere old. */
#define merge(e, new_v, old) (((new_v) & (e)) | ((old) & ~(e)))
#endif

#define INLINE static inline __attribute__((always_inline))
#if defined(__GNUC__) && !defined(__clang__)
/* Fully unroll the per-vector loops so carries and enables stay in registers. */
#define UNROLL _Pragma("GCC unroll 8")
/* GCC 12 reports the fully unrolled, fully initialised carry arrays of the
 * AVX2 clones as "may be used uninitialized" (a false positive). */
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#else
#define UNROLL
#endif
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(__SANITIZE_ADDRESS__) \
    && !defined(PP5_NO_CLONES)
#define PP_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define PP_CLONES
#endif
/* pp_array.c compiles its kernels twice (pp_kernels.inc): 32-byte vectors for
 * AVX2 hosts and 16-byte ones for any other, chosen per array at run time. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(PP5_NO_CLONES)
#define PP_HAVE_AVX2_COPY 1
#else
#define PP_HAVE_AVX2_COPY 0
#endif

#endif
