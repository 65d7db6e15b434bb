/* renderer.h: one Pixel-Planes 5 renderer: a 128x128 array of bit-serial PPs,
 * its QEE, its backing store, and the cycle accounting of the streams it runs.
 *
 * Time.  renderer_execute charges renderer-clock cycles from the pp_isa.def cost
 * column.  Compute instructions run one after another (compute_cycles).  A
 * BSLOAD/BSSTORE costs pp.bs_issue_cycles of compute, then its transfer occupies
 * the single backing-store channel for pp.bs_block_cycles, starting when the
 * channel is free (transfers run in issue order).  Overlap rule: compute goes on
 * while a transfer is in flight, except that an instruction that touches the
 * memory field or the block of an unfinished transfer waits for it (interlock,
 * counted in stall_cycles), an issue waits while pp.bs_queue_depth transfers are
 * in flight, and BSWAIT waits for all.  A stream ends when compute has finished
 * AND every transfer is done: total_cycles = that end time, which is what a
 * renderer is busy for (>= compute_cycles, >= bs_cycles).  Functionally every
 * transfer takes effect at issue; the interlock makes that indistinguishable.
 *
 * Modelled: functional PP memory, E, F, QEE, backing store, per-opcode cycles.
 * Not modelled: the instruction FIFO and controller ([U] facts §3.4), refresh
 * or contention inside the VRAM, the shipped clock ([U] facts §3.1). */
#ifndef PP5_RENDERER_H
#define PP5_RENDERER_H

#include <stddef.h>
#include <stdint.h>
#include "pp_isa.h"
#include "pp_params.h"
#include "util/json.h"
#include "util/status.h"

struct pp_array;
struct backing;

/* Result of one renderer_execute call (renderer-clock cycles). */
typedef struct {
    uint64_t compute_cycles;   /* SIMD instruction cycles, stalls included */
    uint64_t bs_cycles;        /* backing-store channel busy cycles (overlap compute) */
    uint64_t stall_cycles;     /* part of compute_cycles spent waiting for transfers */
    uint64_t total_cycles;     /* busy time of the renderer for this stream (see above) */
    uint64_t instructions;
    uint64_t class_cycles[PP_CLASS_COUNT];       /* compute cycles by class */
    uint64_t class_instructions[PP_CLASS_COUNT];
} renderer_exec_result_t;

/* Cumulative counters since renderer_init (for the report). */
typedef struct {
    uint64_t streams, instructions, compute_cycles, bs_cycles, stall_cycles, total_cycles;
    uint64_t bs_blocks;
    uint64_t class_cycles[PP_CLASS_COUNT];
    uint64_t class_instructions[PP_CLASS_COUNT];
    uint64_t op_instructions[PP_OP_LIMIT];
    uint64_t op_cycles[PP_OP_LIMIT];
} renderer_stats_t;

typedef struct {
    int index;
    pp_params_t pp;
    int x0, y0;                  /* screen origin of the region (QEE x, y of PP (0,0)) */
    struct pp_array *array;      /* 208 bit planes + E + F (heap, ~420 KB) */
    struct backing *bs;          /* 128 blocks x 16384 PPs (heap, 8 MB) */
    /* Host speed only: the words of each block as renderer_bs_read last
     * returned them (NULL: not held), dropped whenever the block is written.
     * A frame reads the same unchanged bricks again and again, and turning
     * 32 bit planes into words was a quarter of the host time of a frame.
     * So the backing store is written only through renderer_bs_write and
     * streams (BSSTORE), never by poking bs->plane.  Costs 64 KB of host
     * memory per block read (at most 8 MB per renderer, as much again as
     * the backing store). */
    uint32_t **bs_words;
    /* The last stream, decoded by its validation (host speed only: the
     * executor reads it instead of decoding every instruction again);
     * grows to the longest stream seen. */
    pp_insn_t *decoded;
    size_t decoded_cap;
    renderer_stats_t stats;
} renderer_t;

pp5_status_t renderer_init(renderer_t *r, int index, const pp_params_t *pp);
void renderer_free(renderer_t *r);
/* Clears pixel memory, flag and backing store; E = 1; region (0,0); stats zero. */
void renderer_reset(renderer_t *r);

/* Screen origin for the QEE's x, y.  The QEE accepts origins with
 * |x0|, |y0| <= PP_REGION_COORD_MAX (so its arithmetic is exact); a QEE executed
 * with another origin is a firmware error. */
#define PP_REGION_COORD_MAX 8064
void renderer_set_region(renderer_t *r, int x0, int y0);

/* Executes an encoded PP instruction stream (words from emu/api/pp_encode.h).
 * The whole stream is decoded and checked first: an illegal stream is rejected
 * with PP5_E_FIRMWARE (message names the word, instruction and field) and
 * changes nothing. */
pp5_status_t renderer_execute(renderer_t *r, const uint32_t *words, size_t n_words,
                              renderer_exec_result_t *res);

/* Functional access for the ring port (its cost is charged by renderer_node.c): an n-bit field
 * (1 <= bits <= 32, addr + bits <= 208) of all 16384 PPs, row-major (128 per
 * row), unsigned, bit 0 = the bit at addr.  Not masked by E. */
pp5_status_t renderer_read_field(const renderer_t *r, unsigned addr, unsigned bits, uint32_t *out);
pp5_status_t renderer_write_field(renderer_t *r, unsigned addr, unsigned bits, const uint32_t *in);
/* Backing store: 32-bit block `block` (0..127) of every PP, row-major. */
pp5_status_t renderer_bs_read(const renderer_t *r, unsigned block, uint32_t *out);
pp5_status_t renderer_bs_write(renderer_t *r, unsigned block, const uint32_t *in);


#endif
