/* pp_array.c: fast bit-sliced execution of PP instructions over the whole 128x128 array. */
#include "pp_array.h"

#include <stdlib.h>
#include <string.h>

#include "bit_transpose.h"
#include "pp_simd.h"

/* Kernels work on blocks of 16 words (1024 PPs) so that carries, enables and
 * flags of a block stay in registers across all bit steps of an instruction. */
#define PP_BLOCK_WORDS 16u

/* Bit i of an n-bit immediate, as an all-ones or all-zero word. */
static inline uint64_t imm_bit(const pp_insn_t *in, unsigned i)
{
    return (in->imm[i >> 5] >> (i & 31)) & 1u ? ~(uint64_t)0 : 0;
}

pp5_status_t pp_array_alloc(pp_array_t **out)
{
    /* C11 aligned_alloc wants a size that is a multiple of the alignment. */
    pp_array_t *a = aligned_alloc(64, (sizeof *a + 63) & ~(size_t)63);
    if (!a)
        return pp5_fail(PP5_E_NOMEM, "cannot allocate a %zu-byte PP array", sizeof *a);
    a->kernels = PP_KERNELS_PORTABLE;
    pp_array_clear(a);
    pp_array_set_kernels(a, pp_kernel_level_best());
    *out = a;
    return PP5_OK;
}

void pp_array_free(pp_array_t *a)
{
    free(a);
}

void pp_array_clear(pp_array_t *a)
{
    pp_kernel_level_t kernels = a->kernels;
    memset(a, 0, sizeof *a);
    memset(a->en, 0xff, sizeof a->en);
    a->kernels = kernels;
}

pp_kernel_level_t pp_array_set_kernels(pp_array_t *a, pp_kernel_level_t wanted)
{
    a->kernels = pp_kernel_level_at_most(wanted);
    return a->kernels;
}

/* True when every PP of the block at word w is enabled: stores need no merge. */
static bool block_full(const pp_array_t *A, unsigned w)
{
    uint64_t all = ~(uint64_t)0;
    for (unsigned v = 0; v < PP_BLOCK_WORDS; v++)
        all &= A->en[w + v];
    return all == ~(uint64_t)0;
}

/* Source plane of step i for the shift/copy family (the zero plane past the field). */
static const uint64_t *logic_src(const pp_array_t *A, const pp_insn_t *in, unsigned i)
{
    const unsigned n = in->n, k = in->x;
    switch (in->op) {
    case PP_OP_SHL: return i >= k ? A->mem[in->a + i - k] : A->zero;
    case PP_OP_SHR: return i + k < n ? A->mem[in->a + i + k] : A->zero;
    case PP_OP_SAR: return A->mem[in->a + (i + k < n ? i + k : n - 1)];
    default: return A->mem[in->a + i];
    }
}

/* Plane of bit i of ext(src(m)) (the zero plane past an unsigned field). */
static const uint64_t *ext_plane(const pp_array_t *A, unsigned src, unsigned m, bool sgn,
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

/* The entry points of one kernel copy (pp_kernels.inc defines one table per copy). */
typedef struct {
    void (*exec_enable)(pp_array_t *A, unsigned op);
    void (*exec_flag)(pp_array_t *A, const pp_insn_t *in);
    void (*exec_add)(pp_array_t *A, const pp_insn_t *in);
    void (*exec_cmp)(pp_array_t *A, const pp_insn_t *in);
    void (*exec_mul)(pp_array_t *A, const pp_insn_t *in);
    void (*exec_logic)(pp_array_t *A, const pp_insn_t *in);
    void (*exec_bs)(pp_array_t *A, backing_t *bs, const pp_insn_t *in);
    qee_step_fn qee_store_step;
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

static void exec_qee(pp_array_t *A, const array_kernels_t *k, const pp_insn_t *in, int x0, int y0)
{
    qee_coeffs_t c = {(int32_t)in->imm[0], (int32_t)in->imm[1], (int32_t)in->imm[2],
                      (int32_t)in->imm[3], (int32_t)in->imm[4], (int32_t)in->imm[5]};
    qee_ctx_t ctx = {A, in->d, in->n, in->x};
    qee_eval_steps(&c, x0, y0, in->x + in->n, A->qee_scratch, k->qee_store_step, &ctx,
                   A->kernels);
}

void pp_array_exec(pp_array_t *A, backing_t *bs, const pp_insn_t *in, int x0, int y0)
{
    const array_kernels_t *k = kernels_of(A);
    switch (in->op) {
    case PP_OP_EN_ALL: case PP_OP_EN_FLAG: case PP_OP_EN_AND: case PP_OP_EN_ANDN:
    case PP_OP_EN_OR: case PP_OP_EN_NOT:
        k->exec_enable(A, in->op);
        break;
    case PP_OP_F_SET: case PP_OP_F_NOT: case PP_OP_F_LD: case PP_OP_F_ST:
        k->exec_flag(A, in);
        break;
    case PP_OP_ADD: case PP_OP_SUB: case PP_OP_ADDI:
        k->exec_add(A, in);
        break;
    case PP_OP_CMP: case PP_OP_CMPI:
        k->exec_cmp(A, in);
        break;
    case PP_OP_MUL: case PP_OP_MULI:
        k->exec_mul(A, in);
        break;
    case PP_OP_QEE:
        exec_qee(A, k, in, x0, y0);
        break;
    case PP_OP_BSLOAD: case PP_OP_BSSTORE:
        k->exec_bs(A, bs, in);
        break;
    case PP_OP_BSWAIT:
        break;                       /* timing only (renderer.c) */
    default:
        k->exec_logic(A, in);
        break;
    }
}

/* Words from one pixel-memory plane to the next (planes are padded, see pp_array.h). */
#define MEM_STRIDE_WORDS (sizeof ((pp_array_t *)0)->mem[0] / sizeof(uint64_t))

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
