/* pp_kernel_level.h: which copy of the bit-sliced PP kernels runs (pp_array.c,
 * qee.c, bit_transpose.c).
 *
 * The kernels are written once and compiled in three copies (pp_simd_copies.inc)
 * that differ only in vector width; they use bitwise operations alone, so every
 * copy computes the same bits and the choice is a matter of host speed.  The
 * wider copies exist only when GCC builds for x86-64 without PP5_NO_CLONES, and
 * run only when the host CPU (and its OS) supports them. */
#ifndef PP5_PP_KERNEL_LEVEL_H
#define PP5_PP_KERNEL_LEVEL_H

#include <stdbool.h>

typedef enum {
    PP_KERNELS_PORTABLE = 0,   /* 16-byte vectors: any host (SSE2 on x86-64) */
    PP_KERNELS_AVX2 = 1,       /* 32-byte vectors */
    PP_KERNELS_AVX512 = 2,     /* 64-byte vectors (AVX-512F) */
} pp_kernel_level_t;

#define PP_KERNEL_LEVELS 3

/* True when this build has the level's copy and this host can run it. */
bool pp_kernel_level_available(pp_kernel_level_t level);
/* The fastest available level: what a PP array uses unless told otherwise. */
pp_kernel_level_t pp_kernel_level_best(void);
/* The highest available level not above `wanted` (PORTABLE is always available). */
pp_kernel_level_t pp_kernel_level_at_most(pp_kernel_level_t wanted);
/* "portable", "AVX2" or "AVX-512". */
const char *pp_kernel_level_name(pp_kernel_level_t level);
/* A line for people: the level's name and vector width. */
const char *pp_kernel_level_describe(pp_kernel_level_t level);

#endif
