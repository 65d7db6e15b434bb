/* pp_array.c: fast bit-sliced execution of PP instructions over the whole 128x128 array. */
#include "pp_array.h"

#include <stdlib.h>
#include <string.h>

#include "pp_simd.h"

#define BLK 4u                    /* vectors per block: 16 words = 1024 PPs */
#define BW (VW * BLK)             /* words per block */

/* Bit i of an n-bit immediate, as an all-ones or all-zero word. */
static inline uint64_t imm_bit(const pp_insn_t *in, unsigned i)
{
    return (in->imm[i >> 5] >> (i & 31)) & 1u ? ~(uint64_t)0 : 0;
}

pp5_status_t pp_array_alloc(pp_array_t **out)
{
    pp_array_t *a = aligned_alloc(64, sizeof *a);
    if (!a)
        return pp5_fail(PP5_E_NOMEM, "cannot allocate a %zu-byte PP array", sizeof *a);
    pp_array_clear(a);
    *out = a;
    return PP5_OK;
}

void pp_array_free(pp_array_t *a)
{
    free(a);
}

void pp_array_clear(pp_array_t *a)
{
    memset(a, 0, sizeof *a);
    memset(a->en, 0xff, sizeof a->en);
}

/* Kernels below are written once as always-inline functions whose op/mode and
 * "block fully enabled" arguments are compile-time constants at each call, so
 * every combination is compiled branch-free; the dispatchers are cloned for
 * AVX2 where the compiler and CPU support it (same results, chosen at load). */
/* True when every PP of the block at word w is enabled: stores need no merge. */
static bool block_full(const pp_array_t *A, unsigned w)
{
    uint64_t all = ~(uint64_t)0;
    for (unsigned v = 0; v < BW; v++)
        all &= A->en[w + v];
    return all == ~(uint64_t)0;
}

/* Masked store of r to pd (whole-block enable known at compile time). */
#define STORE(pd, ev, r, full) \
    do { if (full) st((pd), (r)); else st((pd), merge((ev), (r), ld(pd))); } while (0)

/* ---- n-bit logic, moves and shifts: d[i] = f(a[src(i)], b[i]) ---- */

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

INLINE void logic_block(pp_array_t *A, const pp_insn_t *in, unsigned w, const unsigned op,
                        const bool full)
{
    const unsigned n = in->n;
    v4_t e[BLK], f[BLK];
    UNROLL
    for (unsigned v = 0; v < BLK; v++) {
        e[v] = ld(A->en + w + v * VW);
        f[v] = ld(A->flag + w + v * VW);
    }
    for (unsigned step = 0; step < n; step++) {
        /* SHL runs MSB first so that an in-place shift reads unmodified bits. */
        unsigned i = op == PP_OP_SHL ? n - 1 - step : step;
        uint64_t *pd = A->mem[in->d + i] + w;
        const uint64_t *pa = op == PP_OP_SETI ? A->zero : logic_src(A, in, i) + w;
        const uint64_t *pb = (op == PP_OP_AND || op == PP_OP_OR || op == PP_OP_XOR ||
                              op == PP_OP_SEL) ? A->mem[in->b + i] + w : A->zero;
        const v4_t konst = splat(op == PP_OP_SETI ? imm_bit(in, i) : 0);
        UNROLL
        for (unsigned v = 0; v < BLK; v++) {
            v4_t av = ld(pa + v * VW), bv = ld(pb + v * VW), r;
            switch (op) {
            case PP_OP_NOT: r = ~av; break;
            case PP_OP_AND: r = av & bv; break;
            case PP_OP_OR: r = av | bv; break;
            case PP_OP_XOR: r = av ^ bv; break;
            case PP_OP_SEL: r = (av & f[v]) | (bv & ~f[v]); break;
            case PP_OP_SETI: r = konst; break;
            default: r = av; break;   /* COPY, SHL, SHR, SAR */
            }
            STORE(pd + v * VW, e[v], r, full);
        }
    }
}

#define LOGIC_CASE(OP)                                                         \
    case OP:                                                                   \
        for (unsigned w = 0; w < PP_PLANE_WORDS; w += BW) {                     \
            if (block_full(A, w)) logic_block(A, in, w, OP, true);            \
            else logic_block(A, in, w, OP, false);                             \
        }                                                                      \
        break;

PP_CLONES static void exec_logic(pp_array_t *A, const pp_insn_t *in)
{
    switch (in->op) {
    LOGIC_CASE(PP_OP_NOT)
    LOGIC_CASE(PP_OP_AND)
    LOGIC_CASE(PP_OP_OR)
    LOGIC_CASE(PP_OP_XOR)
    LOGIC_CASE(PP_OP_SEL)
    LOGIC_CASE(PP_OP_SETI)
    LOGIC_CASE(PP_OP_SHL)
    default:
    LOGIC_CASE(PP_OP_COPY)      /* COPY, SHR, SAR: d = a[src(i)] */
    }
}

/* ---- add / subtract / add immediate: ripple carry, LSB first; F = carry or borrow ---- */

INLINE void add_block(pp_array_t *A, const pp_insn_t *in, unsigned w, const unsigned op,
                      const bool full)
{
    const bool sub = op == PP_OP_SUB, addi = op == PP_OP_ADDI;
    v4_t e[BLK], c[BLK];
    UNROLL
    for (unsigned v = 0; v < BLK; v++) {
        e[v] = ld(A->en + w + v * VW);
        c[v] = splat(sub ? ~(uint64_t)0 : 0);     /* a - b = a + ~b + 1 */
    }
    for (unsigned i = 0; i < in->n; i++) {
        const uint64_t *pa = A->mem[in->a + i] + w;
        const uint64_t *pb = addi ? A->zero : A->mem[in->b + i] + w;
        uint64_t *pd = A->mem[in->d + i] + w;
        const v4_t kb = splat(addi ? imm_bit(in, i) : 0);
        UNROLL
        for (unsigned v = 0; v < BLK; v++) {
            v4_t av = ld(pa + v * VW);
            v4_t bv = addi ? kb : ld(pb + v * VW);
            if (sub)
                bv = ~bv;
            v4_t x = av ^ bv;
            v4_t s = x ^ c[v];
            c[v] = (av & bv) | (c[v] & x);
            STORE(pd + v * VW, e[v], s, full);
        }
    }
    UNROLL
    for (unsigned v = 0; v < BLK; v++) {
        v4_t out = sub ? ~c[v] : c[v];
        st(A->flag + w + v * VW, merge(e[v], out, ld(A->flag + w + v * VW)));
    }
}

#define ADD_CASE(OP)                                                           \
    case OP:                                                                   \
        for (unsigned w = 0; w < PP_PLANE_WORDS; w += BW) {                     \
            if (block_full(A, w)) add_block(A, in, w, OP, true);              \
            else add_block(A, in, w, OP, false);                               \
        }                                                                      \
        break;

PP_CLONES static void exec_add(pp_array_t *A, const pp_insn_t *in)
{
    switch (in->op) {
    ADD_CASE(PP_OP_SUB)
    ADD_CASE(PP_OP_ADDI)
    default:
    ADD_CASE(PP_OP_ADD)
    }
}

/* ---- compare into F: equality by an xor chain, order by a serial subtract ---- */

INLINE void cmp_block(pp_array_t *A, const pp_insn_t *in, unsigned w, const bool imm)
{
    const unsigned n = in->n, cond = in->x;
    const bool is_signed = cond == PP_COND_LTS || cond == PP_COND_GES;
    v4_t e[BLK], c[BLK], diff[BLK];
    UNROLL
    for (unsigned v = 0; v < BLK; v++) {
        e[v] = ld(A->en + w + v * VW);
        c[v] = splat(~(uint64_t)0);
        diff[v] = splat(0);
    }
    for (unsigned i = 0; i < n; i++) {
        const uint64_t *pa = A->mem[in->a + i] + w;
        const uint64_t *pb = imm ? A->zero : A->mem[in->b + i] + w;
        const v4_t kb = splat(imm ? imm_bit(in, i) : 0);
        /* Signed order = unsigned order with both sign bits inverted. */
        const v4_t flip = splat(is_signed && i == n - 1 ? ~(uint64_t)0 : 0);
        UNROLL
        for (unsigned v = 0; v < BLK; v++) {
            v4_t av = ld(pa + v * VW) ^ flip;
            v4_t bv = (imm ? kb : ld(pb + v * VW)) ^ flip;
            v4_t nb = ~bv;
            diff[v] |= av ^ bv;
            c[v] = (av & nb) | (c[v] & (av ^ nb));
        }
    }
    UNROLL
    for (unsigned v = 0; v < BLK; v++) {
        v4_t r;
        switch (cond) {
        case PP_COND_EQ: r = ~diff[v]; break;
        case PP_COND_NE: r = diff[v]; break;
        case PP_COND_LTU: case PP_COND_LTS: r = ~c[v]; break;   /* borrow */
        default: r = c[v]; break;                                /* GEU, GES */
        }
        st(A->flag + w + v * VW, merge(e[v], r, ld(A->flag + w + v * VW)));
    }
}

PP_CLONES static void exec_cmp(pp_array_t *A, const pp_insn_t *in)
{
    for (unsigned w = 0; w < PP_PLANE_WORDS; w += BW) {
        if (in->op == PP_OP_CMPI)
            cmp_block(A, in, w, true);
        else
            cmp_block(A, in, w, false);
    }
}

/* ---- Enable and flag: one word operation per word, one loop per opcode ---- */

#define EACH_WORD for (unsigned w = 0; w < PP_PLANE_WORDS; w += VW)

PP_CLONES static void exec_enable(pp_array_t *A, unsigned op)
{
    uint64_t *E = A->en;
    const uint64_t *F = A->flag;
    switch (op) {
    case PP_OP_EN_ALL: EACH_WORD st(E + w, splat(~(uint64_t)0)); break;
    case PP_OP_EN_FLAG: EACH_WORD st(E + w, ld(F + w)); break;
    case PP_OP_EN_AND: EACH_WORD st(E + w, ld(E + w) & ld(F + w)); break;
    case PP_OP_EN_ANDN: EACH_WORD st(E + w, ld(E + w) & ~ld(F + w)); break;
    case PP_OP_EN_OR: EACH_WORD st(E + w, ld(E + w) | ld(F + w)); break;
    default: EACH_WORD st(E + w, ~ld(E + w)); break;     /* EN_NOT */
    }
}

/* dst = src where E, unchanged elsewhere (dst and src are whole planes). */
INLINE void masked_copy(uint64_t *dst, const uint64_t *src, const uint64_t *E)
{
    EACH_WORD st(dst + w, merge(ld(E + w), ld(src + w), ld(dst + w)));
}

PP_CLONES static void exec_flag(pp_array_t *A, const pp_insn_t *in)
{
    const uint64_t *E = A->en;
    uint64_t *F = A->flag;
    switch (in->op) {
    case PP_OP_F_SET: {
        const v4_t x = splat(in->x ? ~(uint64_t)0 : 0);
        EACH_WORD st(F + w, merge(ld(E + w), x, ld(F + w)));
        break;
    }
    case PP_OP_F_NOT: EACH_WORD st(F + w, ld(F + w) ^ ld(E + w)); break;
    case PP_OP_F_LD: masked_copy(F, A->mem[in->a], E); break;
    default: masked_copy(A->mem[in->d], F, E); break;    /* F_ST */
    }
}

/* ---- backing store: 32 masked plane copies ---- */

PP_CLONES static void exec_bs(pp_array_t *A, backing_t *bs, const pp_insn_t *in)
{
    for (unsigned k = 0; k < PP_BS_BLOCK_BITS; k++) {
        uint64_t *bp = backing_plane(bs, in->x, k);
        if (in->op == PP_OP_BSLOAD)
            masked_copy(A->mem[in->d + k], bp, A->en);
        else
            masked_copy(bp, A->mem[in->a + k], A->en);
    }
}

/* ---- shift-add multiply (d disjoint from the sources: checked by the decoder) ---- */

/* Plane of bit i of ext(src(m)) (the zero plane past an unsigned field). */
static const uint64_t *ext_plane(const pp_array_t *A, unsigned src, unsigned m, bool sgn,
                                 unsigned i)
{
    if (i < m)
        return A->mem[src + i];
    return sgn ? A->mem[src + m - 1] : A->zero;
}

/* Where mask: d[j..n) += ext(a) << j. */
INLINE void mul_add_pass(pp_array_t *A, const pp_insn_t *in, unsigned w, const v4_t *mask,
                         unsigned j)
{
    const bool sgn = in->mod & 1u;
    v4_t c[BLK];
    UNROLL
    for (unsigned v = 0; v < BLK; v++)
        c[v] = splat(0);
    for (unsigned i = j; i < in->n; i++) {
        const uint64_t *pa = ext_plane(A, in->a, in->m, sgn, i - j);
        uint64_t *pd = A->mem[in->d + i] + w;
        UNROLL
        for (unsigned v = 0; v < BLK; v++) {
            v4_t av = ld(pa + w + v * VW);
            v4_t dv = ld(pd + v * VW);
            v4_t x = av ^ dv;
            v4_t s = x ^ c[v];
            c[v] = (av & dv) | (c[v] & x);
            st(pd + v * VW, merge(mask[v], s, dv));
        }
    }
}

PP_CLONES static void exec_mul(pp_array_t *A, const pp_insn_t *in)
{
    const unsigned n = in->n;
    const bool sgn = in->mod & 1u;
    for (unsigned w = 0; w < PP_PLANE_WORDS; w += BW) {
        v4_t e[BLK], mask[BLK];
        UNROLL
        for (unsigned v = 0; v < BLK; v++)
            e[v] = ld(A->en + w + v * VW);
        for (unsigned i = 0; i < n; i++) {          /* clear d */
            uint64_t *pd = A->mem[in->d + i] + w;
            UNROLL
            for (unsigned v = 0; v < BLK; v++)
                st(pd + v * VW, merge(e[v], splat(0), ld(pd + v * VW)));
        }
        for (unsigned j = 0; j < n; j++) {
            bool any = false;
            if (in->op == PP_OP_MULI) {
                uint32_t imm = in->imm[0];
                unsigned bit = j < 32 ? (imm >> j) & 1u : imm >> 31;
                UNROLL
                for (unsigned v = 0; v < BLK; v++)
                    mask[v] = bit ? e[v] : splat(0);
                any = bit;
            } else {
                if (!sgn && j >= in->m)
                    break;                  /* unsigned: no more multiplier bits */
                const uint64_t *pb = ext_plane(A, in->b, in->m, sgn, j);
                UNROLL
                for (unsigned v = 0; v < BLK; v++)
                    mask[v] = e[v] & ld(pb + w + v * VW);
                any = true;
            }
            if (any)
                mul_add_pass(A, in, w, mask, j);
        }
    }
}

/* ---- QEE: Q planes from qee.c, 16 words (8 rows) at a time, written into d under E ---- */

typedef struct {
    pp_array_t *A;
    unsigned d, n, shift;
} qee_ctx_t;

PP_CLONES static void qee_store_step(void *vctx, unsigned step, const uint64_t *planes)
{
    const qee_ctx_t *q = vctx;
    pp_array_t *A = q->A;
    const unsigned w = QEE_LANES * step;
    for (unsigned i = 0; i < q->n; i++) {
        uint64_t *pd = A->mem[q->d + i] + w;
        const uint64_t *src = planes + QEE_LANES * (q->shift + i);
        UNROLL
        for (unsigned v = 0; v < QEE_LANES / VW; v++)
            st(pd + v * VW, merge(ld(A->en + w + v * VW), ld(src + v * VW), ld(pd + v * VW)));
    }
}

static void exec_qee(pp_array_t *A, const pp_insn_t *in, int x0, int y0)
{
    qee_coeffs_t c = {(int32_t)in->imm[0], (int32_t)in->imm[1], (int32_t)in->imm[2],
                      (int32_t)in->imm[3], (int32_t)in->imm[4], (int32_t)in->imm[5]};
    qee_ctx_t ctx = {A, in->d, in->n, in->x};
    qee_eval_steps(&c, x0, y0, in->x + in->n, A->qee_scratch, qee_store_step, &ctx);
}

void pp_array_exec(pp_array_t *A, backing_t *bs, const pp_insn_t *in, int x0, int y0)
{
    switch (in->op) {
    case PP_OP_EN_ALL: case PP_OP_EN_FLAG: case PP_OP_EN_AND: case PP_OP_EN_ANDN:
    case PP_OP_EN_OR: case PP_OP_EN_NOT:
        exec_enable(A, in->op);
        break;
    case PP_OP_F_SET: case PP_OP_F_NOT: case PP_OP_F_LD: case PP_OP_F_ST:
        exec_flag(A, in);
        break;
    case PP_OP_ADD: case PP_OP_SUB: case PP_OP_ADDI:
        exec_add(A, in);
        break;
    case PP_OP_CMP: case PP_OP_CMPI:
        exec_cmp(A, in);
        break;
    case PP_OP_MUL: case PP_OP_MULI:
        exec_mul(A, in);
        break;
    case PP_OP_QEE:
        exec_qee(A, in, x0, y0);
        break;
    case PP_OP_BSLOAD: case PP_OP_BSSTORE:
        exec_bs(A, bs, in);
        break;
    case PP_OP_BSWAIT:
        break;                       /* timing only (renderer.c) */
    default:
        exec_logic(A, in);
        break;
    }
}

void pp_array_read_field(const pp_array_t *a, unsigned addr, unsigned bits, uint32_t *out)
{
    memset(out, 0, PP_COUNT * sizeof *out);
    for (unsigned k = 0; k < bits; k++) {
        const uint64_t *pl = a->mem[addr + k];
        for (unsigned p = 0; p < PP_COUNT; p++)
            out[p] |= (uint32_t)pp_array_bit(pl, p) << k;
    }
}

void pp_array_write_field(pp_array_t *a, unsigned addr, unsigned bits, const uint32_t *in)
{
    for (unsigned k = 0; k < bits; k++) {
        uint64_t *pl = a->mem[addr + k];
        memset(pl, 0, PP_PLANE_WORDS * sizeof *pl);
        for (unsigned p = 0; p < PP_COUNT; p++)
            pl[p >> 6] |= (uint64_t)((in[p] >> k) & 1u) << (p & 63);
    }
}
