/* pp_ref.h: slow bit-serial reference executor of PP instructions (the definition of their semantics).
 *
 * Each simulated PP holds its 208 memory bits one per byte, its E and F bits,
 * and its backing store as 128 uint32 blocks; every instruction is carried out
 * per PP, one bit per step, in the order the hardware's bit-serial ALU would
 * (LSB first; SHL MSB first), reading the sources of step i before writing
 * bit i of the destination.  It shares no code with pp_array.c except the
 * decoder and qee_serial_* (a per-PP serial adder of the six QEE terms).
 * A reference may simulate any subset of a renderer's 16384 PPs: PPs are
 * independent, so tests compare random samples and, sometimes, all of them. */
#ifndef PP5_PP_REF_H
#define PP5_PP_REF_H

#include <stdint.h>
#include "pp_isa.h"
#include "util/status.h"

typedef struct {
    unsigned index;                  /* PP number in the array, row-major */
    uint8_t mem[PP_MEM_BITS];        /* one bit per byte */
    uint8_t e, f;
    uint32_t bs[PP_BS_BLOCKS];
} pp_ref_pe_t;

typedef struct {
    unsigned count;
    pp_ref_pe_t *pe;
} pp_ref_t;

/* Simulates the PPs listed in `indices` (each < PP_COUNT), all cleared, E = 1. */
pp5_status_t pp_ref_init(pp_ref_t *r, const unsigned *indices, unsigned count);
void pp_ref_free(pp_ref_t *r);
/* Executes one validated instruction for a region at (x0, y0). */
void pp_ref_exec(pp_ref_t *r, const pp_insn_t *in, int x0, int y0);

#endif
