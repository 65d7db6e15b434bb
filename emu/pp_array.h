/* pp_array.h: the fast functional 128x128 PP array: bit-sliced pixel memory, E, F.
 *
 * Layout: bit k of all 16384 PPs is one plane of 256 uint64 words; PP p (row
 * p / 128, column p % 128, row-major) is bit p % 64 of word p / 64.  One bit-
 * serial step of an instruction across the whole array is then a few word
 * operations per word.  Loops run over tiles of words (outermost: a batch of
 * instructions runs on one tile, then on the next), then instructions, then
 * blocks of 16 words and bit steps (innermost) so carries stay in registers;
 * PPs are independent, so this order gives exactly the per-PP bit-serial
 * result that pp_ref.c computes step by step (the tests check it on random
 * streams).
 * Instructions must have been validated by pp_isa_decode. */
#ifndef PP5_PP_ARRAY_H
#define PP5_PP_ARRAY_H

#include <stdbool.h>
#include <stdint.h>
#include "backing.h"
#include "pp_isa.h"
#include "pp_kernel_level.h"
#include "pp_params.h"
#include "qee.h"
#include "util/status.h"

#define PP_QEE_MAX_BITS (PP_QEE_MAX_SHIFT + 1 + PP_MEM_BITS)
/* Planes for the results of QEEs that a batch evaluates ahead (pp_array_exec_batch):
 * any one QEE fits. */
#define PP_QEE_AHEAD_PLANES PP_MEM_BITS

typedef struct pp_array {
    /* Planes are padded by one cache line so that the same word of successive
     * planes falls in different L1 sets (a 2 KB stride would use only two). */
    uint64_t mem[PP_MEM_BITS][PP_PLANE_WORDS + 8];
    uint64_t en[PP_PLANE_WORDS];
    uint64_t flag[PP_PLANE_WORDS];
    uint64_t zero[PP_PLANE_WORDS];     /* always zero: the source of constant-0 bits */
    uint64_t qee_scratch[QEE_SCRATCH_WORDS(PP_QEE_MAX_BITS)];
    pp_kernel_level_t kernels;         /* copy that runs: host speed only, results are identical */
    /* PP_QEE_AHEAD_PLANES planes of PP_PLANE_WORDS words (a separate block,
     * kept by pp_array_clear): only ever read after a batch wrote them. */
    uint64_t *qee_ahead;
} pp_array_t;

pp5_status_t pp_array_alloc(pp_array_t **out);
void pp_array_free(pp_array_t *a);
/* Memory and F zero, E = 1 everywhere. */
void pp_array_clear(pp_array_t *a);
/* Runs the kernel copy of the highest level available at or below `wanted`
 * (pp_kernel_level.h; a new array runs the host's fastest) and returns the
 * level it now runs.  Tests check every level the host has this way. */
pp_kernel_level_t pp_array_set_kernels(pp_array_t *a, pp_kernel_level_t wanted);

/* Executes one validated instruction; (x0, y0) is the region origin for the QEE
 * (checked by the caller with qee_origin_ok). */
void pp_array_exec(pp_array_t *a, backing_t *bs, const pp_insn_t *in, int x0, int y0);
/* Executes `count` validated instructions in order: the same bits as
 * pp_array_exec on each in turn, but faster, as it runs them in batches,
 * 1024 PPs at a time, so that those PPs' planes stay in the host's L1 cache
 * (pp_array.c). */
void pp_array_exec_batch(pp_array_t *a, backing_t *bs, const pp_insn_t *ins, size_t count,
                         int x0, int y0);

/* Field access, one uint32 per PP row-major; bits <= 32, addr + bits <= 208. */
void pp_array_read_field(const pp_array_t *a, unsigned addr, unsigned bits, uint32_t *out);
void pp_array_write_field(pp_array_t *a, unsigned addr, unsigned bits, const uint32_t *in);
static inline unsigned pp_array_bit(const uint64_t *plane, unsigned pp)
{
    return (unsigned)(plane[pp >> 6] >> (pp & 63)) & 1u;
}

#endif
