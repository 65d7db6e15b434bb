/* bit_transpose.h: fast conversion between bit planes (bit k of 16384 PPs in one
 * plane, PP p = bit p % 64 of word p / 64, as in pp_array.h and backing.h) and one
 * uint32 per PP.  Host speed only: the result is the same as the plain per-bit
 * loop (tests/test_bit_transpose.c checks it against one on random data).
 *
 * Why: the renderer's field and backing-store reads/writes (firmware uploads and
 * read-backs) did one shift-and-or per bit per PP and dominated the host time of
 * an emulated frame.  Here 32 plane words at a time form two 32x32 bit matrices
 * (the low and high halves of each uint64) that are transposed together with
 * five swap stages of shifts and masks. */
#ifndef PP5_BIT_TRANSPOSE_H
#define PP5_BIT_TRANSPOSE_H

#include <stddef.h>
#include <stdint.h>

#include "pp_kernel_level.h"

/* out[p] bit k = bit p of planes[k] for k < bits, 0 above (bits 0..32).
 * Planes are PP_PLANE_WORDS uint64 words each; `plane_stride` words apart
 * (plane k starts at first + k * plane_stride). */
void bit_transpose_planes_to_words(const uint64_t *first, size_t plane_stride, unsigned bits,
                                   uint32_t *out);
/* Bit p of plane k = in[p] bit k for k < bits (1..32); bits of in[p] at or above
 * `bits` are ignored and other planes are not touched. */
void bit_transpose_words_to_planes(const uint32_t *in, unsigned bits, uint64_t *first,
                                   size_t plane_stride);

/* The same with the kernel copy of the highest available level not above
 * `kernels` (pp_kernel_level.h); the two above use the host's fastest.  A PP
 * array passes its own level, so a test that forces one level gets it for
 * field reads and writes too; the tests check every copy the host has. */
void bit_transpose_planes_to_words_at_level(pp_kernel_level_t kernels, const uint64_t *first,
                                            size_t plane_stride, unsigned bits, uint32_t *out);
void bit_transpose_words_to_planes_at_level(pp_kernel_level_t kernels, const uint32_t *in,
                                            unsigned bits, uint64_t *first, size_t plane_stride);

#endif
