/* bit_transpose.c: bit planes <-> one uint32 per PP by word-parallel 32x32 bit-matrix transposes. */
#include "bit_transpose.h"

#include <string.h>

#include "pp_params.h"
#include "pp_simd.h"

/* Plane words handled per pass: one 64-byte cache line of each plane, so the
 * 32 planes (2 KB apart in backing_t, which maps them onto two L1 sets) are each
 * touched once per line rather than once per word. */
#define TILE_WORDS 8u

/* The kernels transpose, in every 64-bit lane, the two 32x32 bit matrices held
 * in rows x[0..31] (matrix h is bits 32h..32h+31 of every row): bit j of row i
 * moves to bit i of row j.  Stage s swaps the off-diagonal s x s sub-blocks of
 * every 2s x 2s block; the masks are the low s bits of every 2s-bit group,
 * repeated in both halves, and shifts by s < 32 under those masks never carry
 * bits between the halves.  Rows are plane words going in (row k = bit k of
 * 64 PPs), so coming out row j holds PP j (low half) and PP 32 + j (high). */
#define PP_SIMD_KERNELS "bit_transpose_kernels.inc"
#include "pp_simd_copies.inc"

void bit_transpose_planes_to_words_at_level(pp_kernel_level_t kernels, const uint64_t *first,
                                            size_t plane_stride, unsigned bits, uint32_t *out)
{
    switch (pp_kernel_level_at_most(kernels)) {
#if PP_HAVE_X86_COPIES
    case PP_KERNELS_AVX512: planes_to_words_avx512(first, plane_stride, bits, out); break;
    case PP_KERNELS_AVX2: planes_to_words_avx2(first, plane_stride, bits, out); break;
#endif
    default: planes_to_words_base(first, plane_stride, bits, out); break;
    }
}

void bit_transpose_words_to_planes_at_level(pp_kernel_level_t kernels, const uint32_t *in,
                                            unsigned bits, uint64_t *first, size_t plane_stride)
{
    switch (pp_kernel_level_at_most(kernels)) {
#if PP_HAVE_X86_COPIES
    case PP_KERNELS_AVX512: words_to_planes_avx512(in, bits, first, plane_stride); break;
    case PP_KERNELS_AVX2: words_to_planes_avx2(in, bits, first, plane_stride); break;
#endif
    default: words_to_planes_base(in, bits, first, plane_stride); break;
    }
}

void bit_transpose_planes_to_words(const uint64_t *first, size_t plane_stride, unsigned bits,
                                   uint32_t *out)
{
    bit_transpose_planes_to_words_at_level(pp_kernel_level_best(), first, plane_stride, bits, out);
}

void bit_transpose_words_to_planes(const uint32_t *in, unsigned bits, uint64_t *first,
                                   size_t plane_stride)
{
    bit_transpose_words_to_planes_at_level(pp_kernel_level_best(), in, bits, first, plane_stride);
}
