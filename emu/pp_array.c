/* pp_array.c: fast bit-sliced execution of PP instructions over the whole 128x128 array.
 *
 * A batch of instructions runs tile by tile: every instruction on the first
 * 1024 PPs, then every instruction on the next 1024, and so on.  PPs are
 * independent, so the order changes no bit, and a tile's planes (128 bytes
 * each) stay in L1 across the batch instead of every instruction streaming
 * its whole planes (2 KB each) through L2.
 *
 * QEE results depend only on the coefficients and the region: a row-linear
 * QEE is evaluated tile by tile from its first step; another runs whole
 * before the tiles when that changes nothing (may_run_first), or else is
 * evaluated ahead into spare planes that its tile step copies under E.  A
 * backing-store transfer also runs whole before the tiles when that changes
 * nothing, where it streams its block's 64 KB; otherwise it is a tile step. */
#include "pp_array.h"

#include <stdlib.h>
#include <string.h>

#include "bit_transpose.h"
#include "pp_simd.h"

/* Kernels work on blocks of 16 words (1024 PPs) so that carries, enables and
 * flags of a block stay in registers across all bit steps of an instruction.
 * A QEE's evaluation step makes one block too (qee.h). */
#define PP_BLOCK_WORDS 16u
_Static_assert(PP_BLOCK_WORDS == QEE_LANES, "a QEE step evaluates one block");
/* Most instructions in one batch (one tiled pass). */
#define PP_ARRAY_BATCH_MAX 64u
/* The bytes of its planes' tiles that a batch may keep in the host's L1 data
 * cache (48 KB on the development host; the rest is left to E, F, the
 * QEE scratch and the stack). */
#define TILE_BYTES_BUDGET (32u * 1024u)

/* One instruction of a batch: the tile kernel that runs it, and its operands. */
typedef struct tile_step tile_step_t;
typedef void (*tile_fn)(pp_array_t *A, const tile_step_t *t, unsigned w0, unsigned w1);
struct tile_step {
    tile_fn run;
    const pp_insn_t *in;
    backing_t *bs;               /* BSLOAD, BSSTORE */
    /* QEE: its n result planes, evaluated ahead (qee_capture_t); a row-linear
     * QEE: its first step's planes, and what each step adds to them */
    const uint64_t *planes;
    int64_t step_add;
};

/* Bit i of an n-bit immediate (the kernels' copy of pp_insn_t.imm), as an
 * all-ones or all-zero word. */
static inline uint64_t word_bit(const uint32_t *imm, unsigned i)
{
    return (imm[i >> 5] >> (i & 31)) & 1u ? ~(uint64_t)0 : 0;
}

/* Words from one pixel-memory plane to the next (planes are padded, see pp_array.h). */
#define MEM_STRIDE_WORDS (sizeof ((pp_array_t *)0)->mem[0] / sizeof(uint64_t))

pp5_status_t pp_array_alloc(pp_array_t **out)
{
    /* C11 aligned_alloc wants a size that is a multiple of the alignment. */
    pp_array_t *a = aligned_alloc(64, (sizeof *a + 63) & ~(size_t)63);
    const size_t ahead_bytes = (size_t)PP_QEE_AHEAD_PLANES * PP_PLANE_WORDS * sizeof(uint64_t);
    uint64_t *ahead = a ? aligned_alloc(64, ahead_bytes) : NULL;
    if (!ahead) {
        free(a);
        return pp5_fail(PP5_E_NOMEM, "cannot allocate a %zu-byte PP array",
                        sizeof *a + ahead_bytes);
    }
    a->kernels = PP_KERNELS_PORTABLE;
    a->qee_ahead = ahead;
    pp_array_clear(a);
    pp_array_set_kernels(a, pp_kernel_level_best());
    *out = a;
    return PP5_OK;
}

void pp_array_free(pp_array_t *a)
{
    if (a)
        free(a->qee_ahead);
    free(a);
}

void pp_array_clear(pp_array_t *a)
{
    pp_kernel_level_t kernels = a->kernels;
    uint64_t *ahead = a->qee_ahead;
    memset(a, 0, sizeof *a);
    memset(a->en, 0xff, sizeof a->en);
    a->kernels = kernels;
    a->qee_ahead = ahead;
}

pp_kernel_level_t pp_array_set_kernels(pp_array_t *a, pp_kernel_level_t wanted)
{
    a->kernels = pp_kernel_level_at_most(wanted);
    return a->kernels;
}

/* Step i's source plane in the shift/copy family, for the words of a0 (the
 * field's first plane) in the next planes; `zero` (words of the zero plane)
 * past the field. */
INLINE const uint64_t *shifted_src(const uint64_t *a0, const uint64_t *zero, unsigned op,
                                   unsigned i, unsigned n, unsigned k)
{
    switch (op) {
    case PP_OP_SHL: return i >= k ? a0 + (size_t)(i - k) * MEM_STRIDE_WORDS : zero;
    case PP_OP_SHR: return i + k < n ? a0 + (size_t)(i + k) * MEM_STRIDE_WORDS : zero;
    case PP_OP_SAR: return a0 + (size_t)(i + k < n ? i + k : n - 1) * MEM_STRIDE_WORDS;
    default: return a0 + (size_t)i * MEM_STRIDE_WORDS;
    }
}

/* Plane of bit i of ext(src(m)) (the zero plane past an unsigned field). */
INLINE const uint64_t *ext_plane(const pp_array_t *A, unsigned src, unsigned m, bool sgn,
                                 unsigned i)
{
    if (i < m)
        return A->mem[src + i];
    return sgn ? A->mem[src + m - 1] : A->zero;
}

typedef struct {
    pp_array_t *A;
    unsigned d, n, shift;
} qee_ctx_t;

/* What a compare computes, by its condition (a compile-time constant in each
 * compare kernel, so an equality test does not run the subtract, nor an order
 * test the xor chain). */
enum { CMP_EQUALITY, CMP_UNSIGNED, CMP_SIGNED };

static qee_coeffs_t qee_coeffs_of(const pp_insn_t *in)
{
    return (qee_coeffs_t){(int32_t)in->imm[0], (int32_t)in->imm[1], (int32_t)in->imm[2],
                          (int32_t)in->imm[3], (int32_t)in->imm[4], (int32_t)in->imm[5]};
}

/* The entry points of one kernel copy (pp_kernels.inc defines one table per copy). */
typedef struct {
    tile_fn (*tile_kernel)(const pp_insn_t *in);   /* the kernel of one instruction */
    qee_step_fn qee_store_step;                     /* a whole-array QEE's writes under E */
    tile_fn qee_row_linear_tile;                    /* a row-linear QEE, evaluated per tile */
    void (*copy_plane)(uint64_t *dst, const uint64_t *src);   /* PP_PLANE_WORDS words */
    bool (*all_enabled)(const pp_array_t *A);                  /* E = 1 in every PP */
} array_kernels_t;

#define PP_SIMD_KERNELS "pp_kernels.inc"
#include "pp_simd_copies.inc"

/* The copy this array runs (pp_array_set_kernels keeps `kernels` to the built ones). */
static const array_kernels_t *kernels_of(const pp_array_t *A)
{
#if PP_HAVE_X86_COPIES
    if (A->kernels == PP_KERNELS_AVX512)
        return &array_kernels_avx512;
    if (A->kernels == PP_KERNELS_AVX2)
        return &array_kernels_avx2;
#endif
    return &array_kernels_base;
}

/* A QEE over the whole array now, written into d under E. */
static void exec_qee(pp_array_t *A, const array_kernels_t *k, const pp_insn_t *in, int x0, int y0)
{
    qee_coeffs_t c = qee_coeffs_of(in);
    qee_ctx_t ctx = {A, in->d, in->n, in->x};
    qee_eval_steps(&c, x0, y0, in->x + in->n, A->qee_scratch, k->qee_store_step, &ctx,
                   A->kernels);
}

/* Where a QEE evaluated ahead keeps its results: n planes, stored block by
 * block (the 16 words of block b of plane i at (b n + i) 16), so that
 * evaluating (16 words of every plane per step) writes them in one run and
 * each tile step reads its block's in one run. */
typedef struct {
    uint64_t *planes;
    unsigned shift, n;
} qee_capture_t;

static void qee_capture_step(void *vctx, unsigned step, const uint64_t *planes)
{
    const qee_capture_t *c = vctx;
    memcpy(c->planes + (size_t)step * c->n * QEE_LANES, planes + QEE_LANES * c->shift,
           (size_t)c->n * QEE_LANES * sizeof(uint64_t));
}

/* A QEE's results, unmasked, into n planes at `planes` (laid out as qee_capture_t says). */
static void eval_qee_ahead(pp_array_t *A, const pp_insn_t *in, int x0, int y0, uint64_t *planes)
{
    qee_coeffs_t c = qee_coeffs_of(in);
    qee_capture_t ctx = {planes, in->x, in->n};
    qee_eval_steps(&c, x0, y0, in->x + in->n, A->qee_scratch, qee_capture_step, &ctx, A->kernels);
}

static bool fields_overlap(unsigned lo1, unsigned n1, unsigned lo2, unsigned n2)
{
    return n1 && n2 && lo1 < lo2 + n2 && lo2 < lo1 + n1;
}

/* Whether h, a QEE or a backing-store transfer (which read E and not F), may
 * run whole before the `count` instructions the batch has gathered (which come
 * before it in the stream): it may when none of them writes E, touches a plane
 * h writes, writes a plane h reads (d is the field an instruction writes), or
 * uses h's backing-store block with a store on either side. */
static bool may_run_first(const pp_insn_t *h, const tile_step_t *steps, unsigned count)
{
    const pp_op_info_t *hop = pp_isa_info(h->op);
    const unsigned w_lo = h->d, w_n = pp_isa_field_bits(h, hop->d_width);
    const unsigned r_lo = h->a, r_n = pp_isa_field_bits(h, hop->a_width);
    for (unsigned i = 0; i < count; i++) {
        const pp_insn_t *r = steps[i].in;
        const pp_op_info_t *op = pp_isa_info(r->op);
        const unsigned d_n = pp_isa_field_bits(r, op->d_width);
        if (op->cls == PP_CLASS_ENABLE || fields_overlap(w_lo, w_n, r->d, d_n) ||
            fields_overlap(w_lo, w_n, r->a, pp_isa_field_bits(r, op->a_width)) ||
            fields_overlap(w_lo, w_n, r->b, pp_isa_field_bits(r, op->b_width)) ||
            fields_overlap(r_lo, r_n, r->d, d_n))
            return false;
        if (op->cls == PP_CLASS_BS && hop->cls == PP_CLASS_BS && r->x == h->x &&
            (r->op == PP_OP_BSSTORE || h->op == PP_OP_BSSTORE))
            return false;
    }
    return true;
}

/* A backing-store transfer over the whole array now: with every PP enabled,
 * 32 plain plane copies, which stream the block's 64 KB (contiguous in the
 * backing store) far faster than a tile at a time; else the tile kernel over
 * one tile of all words. */
static void exec_bs_now(pp_array_t *A, const array_kernels_t *k, backing_t *bs,
                        const pp_insn_t *in)
{
    if (!k->all_enabled(A)) {
        const tile_step_t one = {k->tile_kernel(in), in, bs, NULL, 0};
        one.run(A, &one, 0, PP_PLANE_WORDS);
        return;
    }
    for (unsigned j = 0; j < PP_BS_BLOCK_BITS; j++) {
        uint64_t *bp = backing_plane(bs, in->x, j);
        if (in->op == PP_OP_BSLOAD)
            k->copy_plane(A->mem[in->d + j], bp);
        else
            k->copy_plane(bp, A->mem[in->a + j]);
    }
}

/* Marks planes [lo, lo + len) in a bitmap of pixel-memory planes. */
static void mark_planes(uint64_t *map, unsigned lo, unsigned len)
{
    for (unsigned k = lo; k < lo + len;) {
        unsigned bit = k % 64, n = lo + len - k < 64 - bit ? lo + len - k : 64 - bit;
        map[k / 64] |= (n == 64 ? ~(uint64_t)0 : (((uint64_t)1 << n) - 1)) << bit;
        k += n;
    }
}

/* Plane words per tile: the most, from one block to the whole array, for
 * which the tiles of all planes the batch touches fit TILE_BYTES_BUDGET.  A
 * batch of one-plane operations then makes one kernel call per instruction,
 * not one per block. */
static unsigned tile_words_for(const tile_step_t *steps, unsigned count)
{
    uint64_t map[(PP_MEM_BITS + 63) / 64] = {0};
    unsigned planes = 2;                            /* E and F */
    for (unsigned i = 0; i < count; i++) {
        const pp_insn_t *in = steps[i].in;
        const pp_op_info_t *op = pp_isa_info(in->op);
        mark_planes(map, in->d, pp_isa_field_bits(in, op->d_width));
        mark_planes(map, in->a, pp_isa_field_bits(in, op->a_width));
        mark_planes(map, in->b, pp_isa_field_bits(in, op->b_width));
        if (op->cls == PP_CLASS_BS)
            planes += PP_BS_BLOCK_BITS;             /* the backing-store block */
        if (steps[i].planes)
            planes += in->n;                        /* a QEE's results, evaluated ahead */
    }
    for (unsigned j = 0; j < sizeof map / sizeof map[0]; j++)
        planes += (unsigned)__builtin_popcountll(map[j]);
    unsigned words = PP_PLANE_WORDS;
    while (words > PP_BLOCK_WORDS && planes * words * sizeof(uint64_t) > TILE_BYTES_BUDGET)
        words /= 2;
    return words;
}

static void run_tiles(pp_array_t *A, const tile_step_t *steps, unsigned count)
{
    const unsigned words = tile_words_for(steps, count);
    for (unsigned w = 0; w < PP_PLANE_WORDS; w += words)
        for (unsigned i = 0; i < count; i++)
            steps[i].run(A, &steps[i], w, w + words);
}

/* Adds QEE `in` to the batch of n steps, or runs it now: returns the steps
 * added (0 or 1), or -1 when its planes would not fit the words of qee_ahead
 * left after *ahead (run the batch so far; the QEE then comes first).  A
 * row-linear QEE keeps only its first step and is evaluated tile by tile;
 * another runs whole now when it may run first, else is evaluated ahead. */
static int gather_qee(pp_array_t *A, const array_kernels_t *k, const pp_insn_t *in,
                      tile_step_t *steps, unsigned n, size_t *ahead, int x0, int y0)
{
    const qee_coeffs_t c = qee_coeffs_of(in);
    const unsigned bits = in->x + in->n;
    const size_t room = (size_t)PP_QEE_AHEAD_PLANES * PP_PLANE_WORDS - *ahead;
    uint64_t *planes = A->qee_ahead + *ahead;
    if (qee_is_row_linear(&c)) {
        if ((size_t)QEE_LANES * bits > room)
            return -1;
        int64_t step_add = qee_row_linear_start(&c, x0, y0, bits, planes, A->kernels);
        *ahead += (size_t)QEE_LANES * bits;
        steps[n] = (tile_step_t){k->qee_row_linear_tile, in, NULL, planes, step_add};
        return 1;
    }
    if (may_run_first(in, steps, n)) {
        exec_qee(A, k, in, x0, y0);
        return 0;
    }
    if ((size_t)in->n * PP_PLANE_WORDS > room)
        return -1;
    eval_qee_ahead(A, in, x0, y0, planes);
    *ahead += (size_t)in->n * PP_PLANE_WORDS;
    steps[n] = (tile_step_t){k->tile_kernel(in), in, NULL, planes, 0};
    return 1;
}

void pp_array_exec_batch(pp_array_t *A, backing_t *bs, const pp_insn_t *ins, size_t count,
                         int x0, int y0)
{
    const array_kernels_t *k = kernels_of(A);
    tile_step_t steps[PP_ARRAY_BATCH_MAX];
    size_t i = 0;
    while (i < count) {
        unsigned n = 0;                   /* steps gathered */
        size_t ahead = 0;                 /* words of qee_ahead in use */
        for (; i < count && n < PP_ARRAY_BATCH_MAX; i++) {
            const pp_insn_t *in = &ins[i];
            if (in->op == PP_OP_BSWAIT)
                continue;                           /* timing only (renderer.c) */
            if ((in->op == PP_OP_BSLOAD || in->op == PP_OP_BSSTORE) &&
                may_run_first(in, steps, n)) {
                exec_bs_now(A, k, bs, in);
                continue;
            }
            if (in->op != PP_OP_QEE) {
                steps[n++] = (tile_step_t){k->tile_kernel(in), in, bs, NULL, 0};
                continue;
            }
            int added = gather_qee(A, k, in, steps, n, &ahead, x0, y0);
            if (added < 0)
                break;
            n += (unsigned)added;
        }
        run_tiles(A, steps, n);
    }
}

void pp_array_exec(pp_array_t *A, backing_t *bs, const pp_insn_t *in, int x0, int y0)
{
    pp_array_exec_batch(A, bs, in, 1, x0, y0);
}

void pp_array_read_field(const pp_array_t *a, unsigned addr, unsigned bits, uint32_t *out)
{
    bit_transpose_planes_to_words_at_level(a->kernels, &a->mem[0][0] + addr * MEM_STRIDE_WORDS,
                                           MEM_STRIDE_WORDS, bits, out);
}

void pp_array_write_field(pp_array_t *a, unsigned addr, unsigned bits, const uint32_t *in)
{
    bit_transpose_words_to_planes_at_level(a->kernels, in, bits,
                                           &a->mem[0][0] + addr * MEM_STRIDE_WORDS,
                                           MEM_STRIDE_WORDS);
}
