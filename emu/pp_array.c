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
    a->use_avx2 = false;
    pp_array_clear(a);
    pp_array_set_avx2(a, true);
    *out = a;
    return PP5_OK;
}

void pp_array_free(pp_array_t *a)
{
    free(a);
}

void pp_array_clear(pp_array_t *a)
{
    bool avx2 = a->use_avx2;
    memset(a, 0, sizeof *a);
    memset(a->en, 0xff, sizeof a->en);
    a->use_avx2 = avx2;
}

bool pp_array_set_avx2(pp_array_t *a, bool allow)
{
#if PP_HAVE_AVX2_COPY
    a->use_avx2 = allow && __builtin_cpu_supports("avx2");
#else
    (void)allow;
    a->use_avx2 = false;
#endif
    return a->use_avx2;
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

#define PP_SIMD_KERNELS "pp_kernels.inc"
#include "pp_simd_copies.inc"

/* Calls the AVX2 copy of a kernel when this array may use it, else the base copy. */
#if PP_HAVE_AVX2_COPY
#define KCALL(A, fn, ...) ((A)->use_avx2 ? fn##_avx2(__VA_ARGS__) : fn##_base(__VA_ARGS__))
#else
#define KCALL(A, fn, ...) fn##_base(__VA_ARGS__)
#endif

static void exec_qee(pp_array_t *A, const pp_insn_t *in, int x0, int y0)
{
    qee_coeffs_t c = {(int32_t)in->imm[0], (int32_t)in->imm[1], (int32_t)in->imm[2],
                      (int32_t)in->imm[3], (int32_t)in->imm[4], (int32_t)in->imm[5]};
    qee_ctx_t ctx = {A, in->d, in->n, in->x};
    qee_eval_steps(&c, x0, y0, in->x + in->n, A->qee_scratch, 
#if PP_HAVE_AVX2_COPY
                   A->use_avx2 ? qee_store_step_avx2 :
#endif
                   qee_store_step_base, &ctx, A->use_avx2);
}

void pp_array_exec(pp_array_t *A, backing_t *bs, const pp_insn_t *in, int x0, int y0)
{
    switch (in->op) {
    case PP_OP_EN_ALL: case PP_OP_EN_FLAG: case PP_OP_EN_AND: case PP_OP_EN_ANDN:
    case PP_OP_EN_OR: case PP_OP_EN_NOT:
        KCALL(A, exec_enable, A, in->op);
        break;
    case PP_OP_F_SET: case PP_OP_F_NOT: case PP_OP_F_LD: case PP_OP_F_ST:
        KCALL(A, exec_flag, A, in);
        break;
    case PP_OP_ADD: case PP_OP_SUB: case PP_OP_ADDI:
        KCALL(A, exec_add, A, in);
        break;
    case PP_OP_CMP: case PP_OP_CMPI:
        KCALL(A, exec_cmp, A, in);
        break;
    case PP_OP_MUL: case PP_OP_MULI:
        KCALL(A, exec_mul, A, in);
        break;
    case PP_OP_QEE:
        exec_qee(A, in, x0, y0);
        break;
    case PP_OP_BSLOAD: case PP_OP_BSSTORE:
        KCALL(A, exec_bs, A, bs, in);
        break;
    case PP_OP_BSWAIT:
        break;                       /* timing only (renderer.c) */
    default:
        KCALL(A, exec_logic, A, in);
        break;
    }
}

/* Words from one pixel-memory plane to the next (planes are padded, see pp_array.h). */
#define MEM_STRIDE_WORDS (sizeof ((pp_array_t *)0)->mem[0] / sizeof(uint64_t))

void pp_array_read_field(const pp_array_t *a, unsigned addr, unsigned bits, uint32_t *out)
{
    bit_transpose_planes_to_words(&a->mem[0][0] + addr * MEM_STRIDE_WORDS, MEM_STRIDE_WORDS,
                                  bits, out);
}

void pp_array_write_field(pp_array_t *a, unsigned addr, unsigned bits, const uint32_t *in)
{
    bit_transpose_words_to_planes(in, bits, &a->mem[0][0] + addr * MEM_STRIDE_WORDS,
                                  MEM_STRIDE_WORDS);
}
