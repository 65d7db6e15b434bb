/* test_pp.c: PP instruction set: fast bit-sliced array vs bit-serial reference on
 * random streams, every op against an integer model, decoder/encoder errors. */
#include <stdlib.h>
#include <string.h>

#include "backing.h"
#include "harness.h"
#include "pp_array.h"
#include "pp_encode.h"
#include "pp_isa.h"
#include "pp_ref.h"
#include "renderer.h"

/* xorshift64*: deterministic test PRNG (seeded per stream). */
static uint64_t rng_next(uint64_t *s)
{
    *s ^= *s >> 12;
    *s ^= *s << 25;
    *s ^= *s >> 27;
    return *s * 2685821657736338717ull;
}

static unsigned rng_below(uint64_t *s, unsigned n)
{
    return (unsigned)(rng_next(s) % n);
}

static renderer_t *new_renderer(void)
{
    static renderer_t r;          /* one 8 MB renderer reused by the tests */
    static bool ready;
    if (!ready) {
        pp_params_t p;
        pp_params_default(&p);
        if (renderer_init(&r, 0, &p) != PP5_OK)
            return NULL;
        ready = true;
    }
    renderer_reset(&r);
    return &r;
}

/* Makes the array run kernel copy `level` and returns true when the host has
 * it; otherwise says loudly that this copy goes unchecked here and returns
 * false (the array keeps its kernels). */
static bool use_kernels(renderer_t *r, pp_kernel_level_t level)
{
    if (!pp_kernel_level_available(level)) {
        printf("   note: this host or build has no %s kernels; they are not checked here\n",
               pp_kernel_level_name(level));
        return false;
    }
    return pp_array_set_kernels(r->array, level) == level;
}

/* ---- random streams ---- */

/* A field of `bits` at a random address inside the 208-bit memory. */
static unsigned rand_addr(uint64_t *s, unsigned bits)
{
    return rng_below(s, PP_MEM_BITS - bits + 1);
}

static unsigned rand_width(uint64_t *s, unsigned max)
{
    /* Mostly small widths (cheap for the reference), sometimes wide ones. */
    unsigned r = rng_below(s, 8);
    if (r == 0)
        return 1;
    if (r == 7)
        return 1 + rng_below(s, max);
    return 1 + rng_below(s, max < 24 ? max : 24);
}

static void rand_imm(uint64_t *s, uint32_t *imm, unsigned words)
{
    for (unsigned i = 0; i < words; i++)
        imm[i] = (uint32_t)rng_next(s);
}

static int32_t rand_coeff(uint64_t *s)
{
    switch (rng_below(s, 4)) {
    case 0: return (int32_t)rng_next(s);                      /* full range */
    case 1: return (int32_t)rng_below(s, 2001) - 1000;
    case 2: return 0;
    default: return (int32_t)(rng_next(s) % 2000001) - 1000000;
    }
}

static bool disjoint(unsigned lo1, unsigned n1, unsigned lo2, unsigned n2)
{
    return lo1 + n1 <= lo2 || lo2 + n2 <= lo1;
}

/* Appends one random instruction of opcode `op` to the stream. */
static void emit_random(pp_stream_t *st, uint64_t *s, unsigned op)
{
    uint32_t imm[7];
    unsigned n = rand_width(s, PP_MEM_BITS), d = rand_addr(s, n), a = rand_addr(s, n),
             b = rand_addr(s, n);
    rand_imm(s, imm, 7);
    switch (op) {
    case PP_OP_EN_ALL: pp_emit_en_all(st); break;
    case PP_OP_EN_FLAG: pp_emit_en_flag(st); break;
    case PP_OP_EN_AND: pp_emit_en_and(st); break;
    case PP_OP_EN_ANDN: pp_emit_en_andn(st); break;
    case PP_OP_EN_OR: pp_emit_en_or(st); break;
    case PP_OP_EN_NOT: pp_emit_en_not(st); break;
    case PP_OP_F_SET: pp_emit_f_set(st, rng_below(s, 2)); break;
    case PP_OP_F_NOT: pp_emit_f_not(st); break;
    case PP_OP_F_LD: pp_emit_f_ld(st, rng_below(s, PP_MEM_BITS)); break;
    case PP_OP_F_ST: pp_emit_f_st(st, rng_below(s, PP_MEM_BITS)); break;
    case PP_OP_COPY: pp_emit_copy(st, d, a, n); break;
    case PP_OP_NOT: pp_emit_not(st, d, a, n); break;
    case PP_OP_AND: pp_emit_and(st, d, a, b, n); break;
    case PP_OP_OR: pp_emit_or(st, d, a, b, n); break;
    case PP_OP_XOR: pp_emit_xor(st, d, a, b, n); break;
    case PP_OP_SETI: pp_emit_seti_wide(st, d, n, imm); break;
    case PP_OP_SEL: pp_emit_sel(st, d, a, b, n); break;
    case PP_OP_SHL: pp_emit_shl(st, d, a, n, rng_below(s, n + 3)); break;
    case PP_OP_SHR: pp_emit_shr(st, d, a, n, rng_below(s, n + 3)); break;
    case PP_OP_SAR: pp_emit_sar(st, d, a, n, rng_below(s, n + 3)); break;
    case PP_OP_ADD: pp_emit_add(st, d, a, b, n); break;
    case PP_OP_SUB: pp_emit_sub(st, d, a, b, n); break;
    case PP_OP_ADDI: pp_emit_addi_wide(st, d, a, n, imm); break;
    case PP_OP_CMP: pp_emit_cmp(st, rng_below(s, PP_COND_COUNT), a, b, n); break;
    case PP_OP_CMPI: pp_emit_cmpi_wide(st, rng_below(s, PP_COND_COUNT), a, n, imm); break;
    case PP_OP_MUL: case PP_OP_MULI: {
        unsigned nn = 1 + rng_below(s, 24), m = 1 + rng_below(s, 16);
        unsigned dd, aa, bb;
        do {
            dd = rand_addr(s, nn);
            aa = rand_addr(s, m);
            bb = rand_addr(s, m);
        } while (!disjoint(dd, nn, aa, m) || !disjoint(dd, nn, bb, m));
        bool sgn = rng_below(s, 2);
        if (op == PP_OP_MUL)
            pp_emit_mul(st, dd, nn, aa, bb, m, sgn);
        else
            pp_emit_muli(st, dd, nn, aa, m, sgn, rand_coeff(s));
        break;
    }
    case PP_OP_QEE: {
        unsigned nn = 1 + rng_below(s, 40);
        unsigned shift = rng_below(s, 4) == 0 ? rng_below(s, 64) : rng_below(s, 20);
        pp_emit_qee(st, rand_addr(s, nn), nn, shift, rand_coeff(s), rand_coeff(s), rand_coeff(s),
                    rand_coeff(s), rand_coeff(s), rand_coeff(s));
        break;
    }
    case PP_OP_BSLOAD: pp_emit_bsload(st, rand_addr(s, 32), rng_below(s, PP_BS_BLOCKS)); break;
    case PP_OP_BSSTORE: pp_emit_bsstore(st, rng_below(s, PP_BS_BLOCKS), rand_addr(s, 32)); break;
    case PP_OP_BSWAIT: pp_emit_bswait(st); break;
    default: break;
    }
}

/* Every legal opcode, from the table. */
static unsigned legal_ops(unsigned *ops)
{
    unsigned k = 0;
    for (unsigned c = 0; c < PP_OP_LIMIT; c++) {
        if (pp_isa_info(c))
            ops[k++] = c;
    }
    return k;
}

/* Random memory, E, F and backing store in the fast array; copied into the
 * reference PPs so both start identical. */
static void randomize(renderer_t *r, pp_ref_t *ref, uint64_t *s)
{
    pp_array_t *A = r->array;
    for (unsigned k = 0; k < PP_MEM_BITS; k++)
        for (unsigned w = 0; w < PP_PLANE_WORDS; w++)
            A->mem[k][w] = rng_next(s);
    for (unsigned w = 0; w < PP_PLANE_WORDS; w++) {
        A->en[w] = rng_next(s) | rng_next(s);   /* mostly enabled */
        A->flag[w] = rng_next(s);
    }
    for (unsigned k = 0; k < PP_BS_BITS; k++)
        for (unsigned w = 0; w < PP_PLANE_WORDS; w++)
            r->bs->plane[k][w] = rng_next(s);
    for (unsigned i = 0; i < ref->count; i++) {
        pp_ref_pe_t *p = &ref->pe[i];
        unsigned q = p->index;
        for (unsigned k = 0; k < PP_MEM_BITS; k++)
            p->mem[k] = (uint8_t)pp_array_bit(A->mem[k], q);
        p->e = (uint8_t)pp_array_bit(A->en, q);
        p->f = (uint8_t)pp_array_bit(A->flag, q);
        memset(p->bs, 0, sizeof p->bs);
    }
    /* Plane by plane: the 8 MB of backing-store planes do not fit in cache. */
    for (unsigned b = 0; b < PP_BS_BLOCKS; b++)
        for (unsigned k = 0; k < 32; k++) {
            const uint64_t *plane = backing_plane(r->bs, b, k);
            for (unsigned i = 0; i < ref->count; i++)
                ref->pe[i].bs[b] |= (uint32_t)pp_array_bit(plane, ref->pe[i].index) << k;
        }
}

/* Number of PPs whose state differs; reports the first difference.  Memory,
 * E and F are compared PP by PP (the 208 planes stay in cache); the backing
 * store (8 MB of planes) plane by plane, for block `bs_first` .. + bs_blocks. */
static unsigned compare_range(const renderer_t *r, const pp_ref_t *ref, const char *what,
                              unsigned mem_lo, unsigned mem_len, unsigned bs_first,
                              unsigned bs_blocks)
{
    uint8_t *diff = calloc(ref->count ? ref->count : 1, 1);
    if (!diff)
        return 1;
    for (unsigned i = 0; i < ref->count; i++) {
        const pp_ref_pe_t *p = &ref->pe[i];
        unsigned q = p->index;
        bool ok = p->e == pp_array_bit(r->array->en, q) && p->f == pp_array_bit(r->array->flag, q);
        for (unsigned k = mem_lo; ok && k < mem_lo + mem_len; k++)
            ok = p->mem[k] == pp_array_bit(r->array->mem[k], q);
        diff[i] = !ok;
    }
    for (unsigned b = bs_first; b < bs_first + bs_blocks; b++)
        for (unsigned k = 0; k < 32; k++) {
            const uint64_t *plane = r->bs->plane[b * 32 + k];
            for (unsigned i = 0; i < ref->count; i++)
                diff[i] |= ((ref->pe[i].bs[b] >> k) & 1u) != pp_array_bit(plane, ref->pe[i].index);
        }
    unsigned bad = 0;
    for (unsigned i = 0; i < ref->count; i++) {
        unsigned q = ref->pe[i].index;
        if (diff[i] && bad++ == 0)
            CHECK_MSG(false, "%s: PP %u (row %u col %u) differs from the reference", what, q,
                      q / PP_ARRAY_DIM, q % PP_ARRAY_DIM);
    }
    free(diff);
    return bad;
}

static unsigned compare(const renderer_t *r, const pp_ref_t *ref, const char *what,
                        unsigned bs_first, unsigned bs_blocks)
{
    return compare_range(r, ref, what, 0, PP_MEM_BITS, bs_first, bs_blocks);
}

/* Runs `n_insns` random instructions (every opcode appears) through both
 * executors, one instruction per renderer_execute so a mismatch names it. */
static unsigned run_random_stream(uint64_t seed, const unsigned *pps, unsigned n_pps,
                                  unsigned n_insns, pp_kernel_level_t level)
{
    uint64_t s = seed * 0x9E3779B97F4A7C15ull + 1;
    renderer_t *r = new_renderer();
    pp_ref_t ref;
    if (!r || pp_ref_init(&ref, pps, n_pps) != PP5_OK)
        return 1;
    randomize(r, &ref, &s);
    pp_array_set_kernels(r->array, level);
    /* Region origins: screen interior, screen edges, negative, the QEE limit. */
    static const int origins[][2] = {{0, 0}, {1152, 896}, {-128, -640}, {8064, -8064},
                                     {640, 384}, {-8064, 8064}};
    int ox = origins[seed % 6][0], oy = origins[seed % 6][1];
    renderer_set_region(r, ox, oy);
    unsigned ops[PP_OP_LIMIT], n_ops = legal_ops(ops);
    pp_stream_t st;
    pp_stream_init(&st);
    unsigned bad = 0;
    for (unsigned i = 0; i < n_insns && !bad; i++) {
        unsigned op = i < n_ops ? ops[(i + seed) % n_ops] : ops[rng_below(&s, n_ops)];
        pp_stream_clear(&st);
        emit_random(&st, &s, op);
        if (!pp_stream_ok(&st)) {
            CHECK_MSG(false, "encoder: %s", pp_stream_error(&st));
            bad++;
            break;
        }
        size_t pos = 0;
        pp_insn_t in;
        if (pp_isa_decode(st.words, st.n_words, &pos, PP_MEM_BITS, &in) != PP5_OK) {
            CHECK_MSG(false, "decode: %s", pp5_error_text());
            bad++;
            break;
        }
        pp_ref_exec(&ref, &in, ox, oy);
        renderer_exec_result_t res;
        if (renderer_execute(r, st.words, st.n_words, &res) != PP5_OK) {
            CHECK_MSG(false, "execute: %s", pp5_error_text());
            bad++;
            break;
        }
        char what[200];
        pp_isa_format(&in, what, sizeof what);
        char ctx[260];
        snprintf(ctx, sizeof ctx, "seed %llu insn %u %s", (unsigned long long)seed, i, what);
        /* After each instruction: E, F, the destination field and (after a
         * store) the stored block; after the last one everything (so a write
         * outside the destination is caught too). */
        if (i + 1 == n_insns) {
            bad += compare(r, &ref, ctx, 0, PP_BS_BLOCKS);
        } else {
            const pp_op_info_t *info = pp_isa_info(in.op);
            bad += compare_range(r, &ref, ctx, in.d, pp_isa_field_bits(&in, info->d_width), in.x,
                                 in.op == PP_OP_BSSTORE ? 1 : 0);
        }
    }
    pp_stream_free(&st);
    pp_ref_free(&ref);
    return bad;
}

/* What a random program is made of (after every opcode once):
 *   PROGRAM_ANY      random opcodes;
 *   PROGRAM_REORDER  a QEE for a quarter of the instructions, an Enable
 *                    instruction for an eighth, a backing-store transfer (of
 *                    blocks 0..3, so that transfers of one block meet in a
 *                    batch) for an eighth: the batches of pp_array_exec_batch
 *                    run such QEEs and transfers before earlier instructions
 *                    when that changes nothing, evaluate other QEEs into
 *                    spare planes and fill those planes;
 *   PROGRAM_SLOTS    the same kinds plus arithmetic on six 32-bit slots of
 *                    memory, so that fields often do not overlap and
 *                    transfers and QEEs often move ahead of arithmetic. */
typedef enum { PROGRAM_ANY, PROGRAM_REORDER, PROGRAM_SLOTS } program_mix_t;

static const char *const program_mix_names[] = {"", "reordering-heavy ", "slot "};

static unsigned program_op(uint64_t *s, const unsigned *ops, unsigned n_ops, program_mix_t mix)
{
    static const unsigned enables[] = {PP_OP_EN_ALL, PP_OP_EN_FLAG, PP_OP_EN_AND,
                                       PP_OP_EN_ANDN, PP_OP_EN_OR, PP_OP_EN_NOT};
    unsigned r = rng_below(s, 8);
    if (mix != PROGRAM_ANY && r < 2)
        return PP_OP_QEE;
    if (mix != PROGRAM_ANY && r == 2)
        return enables[rng_below(s, 6)];
    if (mix != PROGRAM_ANY && r == 3)
        return rng_below(s, 2) ? PP_OP_BSLOAD : PP_OP_BSSTORE;
    if (mix == PROGRAM_SLOTS) {
        static const unsigned arith[] = {PP_OP_ADD, PP_OP_SUB, PP_OP_COPY, PP_OP_CMP};
        return arith[rng_below(s, 4)];
    }
    return ops[rng_below(s, n_ops)];
}

/* One instruction of opcode `op` whose fields are slots (32 k) of width <= 32. */
static void emit_slot_insn(pp_stream_t *st, uint64_t *s, unsigned op)
{
    unsigned d = 32 * rng_below(s, 6), a = 32 * rng_below(s, 6), b = 32 * rng_below(s, 6);
    unsigned n = 1 + rng_below(s, 32);
    switch (op) {
    case PP_OP_BSLOAD: pp_emit_bsload(st, d, rng_below(s, 4)); break;
    case PP_OP_BSSTORE: pp_emit_bsstore(st, rng_below(s, 4), a); break;
    case PP_OP_QEE:
        pp_emit_qee(st, d, n, rng_below(s, 20), rand_coeff(s), rand_coeff(s), rand_coeff(s),
                    rand_coeff(s), rand_coeff(s), rand_coeff(s));
        break;
    case PP_OP_ADD: pp_emit_add(st, d, a, b, n); break;
    case PP_OP_SUB: pp_emit_sub(st, d, a, b, n); break;
    case PP_OP_COPY: pp_emit_copy(st, d, a, n); break;
    case PP_OP_CMP: pp_emit_cmp(st, rng_below(s, PP_COND_COUNT), a, b, n); break;
    default: emit_random(st, s, op); break;             /* Enable instructions */
    }
}

/* Instruction i of a random program: every opcode once, then as `mix` says. */
static void emit_program_insn(pp_stream_t *st, uint64_t *s, const unsigned *ops, unsigned n_ops,
                              unsigned i, program_mix_t mix)
{
    if (i < n_ops) {
        emit_random(st, s, ops[i]);
        return;
    }
    unsigned op = program_op(s, ops, n_ops, mix);
    if (mix == PROGRAM_SLOTS)
        emit_slot_insn(st, s, op);
    else if (mix == PROGRAM_REORDER && op == PP_OP_BSLOAD)
        pp_emit_bsload(st, rand_addr(s, 32), rng_below(s, 4));
    else if (mix == PROGRAM_REORDER && op == PP_OP_BSSTORE)
        pp_emit_bsstore(st, rng_below(s, 4), rand_addr(s, 32));
    else
        emit_random(st, s, op);
}

/* The same comparison with the whole program sent as ONE stream (exercises
 * decoding of consecutive instructions with immediates, and the fast array's
 * batches); compared at the end. */
static unsigned run_random_program(uint64_t seed, const unsigned *pps, unsigned n_pps,
                                   unsigned n_insns, pp_kernel_level_t level, program_mix_t mix)
{
    uint64_t s = seed * 0xD1B54A32D192ED03ull + 7;
    renderer_t *r = new_renderer();
    pp_ref_t ref;
    if (!r || pp_ref_init(&ref, pps, n_pps) != PP5_OK)
        return 1;
    randomize(r, &ref, &s);
    pp_array_set_kernels(r->array, level);
    int ox = (int)rng_below(&s, 2000) - 500, oy = (int)rng_below(&s, 2000) - 500;
    renderer_set_region(r, ox, oy);
    unsigned ops[PP_OP_LIMIT], n_ops = legal_ops(ops);
    pp_stream_t st;
    pp_stream_init(&st);
    for (unsigned i = 0; i < n_insns; i++)
        emit_program_insn(&st, &s, ops, n_ops, i, mix);
    unsigned bad = 0;
    renderer_exec_result_t res;
    if (!CHECK_MSG(pp_stream_ok(&st), "encoder: %s", pp_stream_error(&st)) ||
        !CHECK_MSG(renderer_execute(r, st.words, st.n_words, &res) == PP5_OK, "execute: %s",
                   pp5_error_text())) {
        bad = 1;
    } else {
        size_t pos = 0;
        pp_insn_t in;
        unsigned decoded = 0;
        while (pos < st.n_words &&
               pp_isa_decode(st.words, st.n_words, &pos, PP_MEM_BITS, &in) == PP5_OK) {
            pp_ref_exec(&ref, &in, ox, oy);
            decoded++;
        }
        CHECK_EQ(decoded, n_insns);
        CHECK_EQ(res.instructions, n_insns);
        char ctx[80];
        snprintf(ctx, sizeof ctx, "one-stream %sprogram, seed %llu", program_mix_names[mix],
                 (unsigned long long)seed);
        bad = compare(r, &ref, ctx, 0, PP_BS_BLOCKS);
    }
    pp_stream_free(&st);
    pp_ref_free(&ref);
    return bad;
}

/* 150 streams x 80 instructions on kernel copy `level`, each compared on 256
 * PPs (the four corners and 252 random ones) after every instruction; plus 30
 * programs of each mix (program_mix_t) of 120 instructions sent as one stream
 * and compared at the end.  SKIPs when the host lacks the level. */
static void random_streams_on_sampled_pps(pp_kernel_level_t level)
{
    enum { STREAMS = 150, INSNS = 80, PPS = 256 };
    if (!pp_kernel_level_available(level))
        SKIP("this host or build has no %s kernels", pp_kernel_level_name(level));
    unsigned pps[PPS], failed = 0;
    for (unsigned seed = 1; seed <= STREAMS; seed++) {
        uint64_t s = seed;
        pps[0] = 0;
        pps[1] = PP_ARRAY_DIM - 1;
        pps[2] = PP_COUNT - PP_ARRAY_DIM;
        pps[3] = PP_COUNT - 1;
        for (unsigned i = 4; i < PPS; i++)
            pps[i] = rng_below(&s, PP_COUNT);
        failed += run_random_stream(seed, pps, PPS, INSNS, level) != 0;
        if (seed % 5 == 0)
            failed += run_random_program(seed, pps, PPS, 120, level, PROGRAM_ANY) != 0;
        if (seed % 5 == 2)
            failed += run_random_program(seed, pps, PPS, 120, level, PROGRAM_REORDER) != 0;
        if (seed % 5 == 4)
            failed += run_random_program(seed, pps, PPS, 120, level, PROGRAM_SLOTS) != 0;
        if (failed)
            break;
    }
    CHECK_EQ(failed, 0);
    renderer_t *r = new_renderer();
    REQUIRE(r);
    pp_array_set_kernels(r->array, pp_kernel_level_best());
}

TEST(pp_random_streams_match_reference_portable_kernels)
{
    random_streams_on_sampled_pps(PP_KERNELS_PORTABLE);
}

TEST(pp_random_streams_match_reference_avx2_kernels)
{
    random_streams_on_sampled_pps(PP_KERNELS_AVX2);
}

TEST(pp_random_streams_match_reference_avx512_kernels)
{
    random_streams_on_sampled_pps(PP_KERNELS_AVX512);
}

TEST(pp_random_streams_match_reference_on_all_pps)
{
    /* Whole array: every one of the 16384 PPs, one stream of 40 instructions
     * and a reordering-heavy and a slot program of 60 on each kernel copy the
     * host has. */
    unsigned *pps = malloc(PP_COUNT * sizeof *pps);
    REQUIRE(pps);
    for (unsigned i = 0; i < PP_COUNT; i++)
        pps[i] = i;
    unsigned failed = 0, checked = 0;
    renderer_t *r = new_renderer();
    REQUIRE(r);
    for (int level = 0; level < PP_KERNEL_LEVELS; level++) {
        if (!use_kernels(r, (pp_kernel_level_t)level))
            continue;
        failed += run_random_stream(1001 + (uint64_t)level, pps, PP_COUNT, 40,
                                    (pp_kernel_level_t)level) != 0;
        failed += run_random_program(1001 + (uint64_t)level, pps, PP_COUNT, 60,
                                     (pp_kernel_level_t)level, PROGRAM_REORDER) != 0;
        failed += run_random_program(1001 + (uint64_t)level, pps, PP_COUNT, 60,
                                     (pp_kernel_level_t)level, PROGRAM_SLOTS) != 0;
        checked++;
    }
    pp_array_set_kernels(r->array, pp_kernel_level_best());
    free(pps);
    CHECK_EQ(failed, 0);
    CHECK(checked >= 1);
}

/* The level API: a wanted level falls back to the highest one the host has,
 * the portable copy is always there, and an array reports what it runs. */
TEST(pp_kernel_levels_fall_back_to_what_the_host_has)
{
    CHECK(pp_kernel_level_available(PP_KERNELS_PORTABLE));
    CHECK_EQ(pp_kernel_level_at_most(PP_KERNELS_PORTABLE), PP_KERNELS_PORTABLE);
    pp_kernel_level_t best = pp_kernel_level_best();
    CHECK(pp_kernel_level_available(best));
    CHECK_EQ(pp_kernel_level_at_most(PP_KERNELS_AVX512), best);
    for (int level = best + 1; level < PP_KERNEL_LEVELS; level++)
        CHECK(!pp_kernel_level_available((pp_kernel_level_t)level));
    if (pp_kernel_level_available(PP_KERNELS_AVX512))
        CHECK(pp_kernel_level_available(PP_KERNELS_AVX2));
    pp_array_t *a = NULL;
    REQUIRE(pp_array_alloc(&a) == PP5_OK);
    CHECK_EQ(a->kernels, best);
    for (int level = 0; level < PP_KERNEL_LEVELS; level++) {
        pp_kernel_level_t got = pp_array_set_kernels(a, (pp_kernel_level_t)level);
        CHECK_EQ(got, pp_kernel_level_at_most((pp_kernel_level_t)level));
        CHECK_EQ(a->kernels, got);
        pp_array_clear(a);                          /* clearing keeps the choice */
        CHECK_EQ(a->kernels, got);
    }
    pp_array_free(a);
    printf("   note: kernels on this host: %s\n", pp_kernel_level_describe(best));
}

/* ---- every operation against an integer model (independent of both executors) ---- */

static uint64_t mask_n(unsigned n)
{
    return n >= 64 ? ~(uint64_t)0 : ((uint64_t)1 << n) - 1;
}

/* v (n bits) sign-extended to int64. */
static int64_t sext(uint64_t v, unsigned n)
{
    v &= mask_n(n);
    return n < 64 && (v >> (n - 1)) & 1u ? (int64_t)(v | ~mask_n(n)) : (int64_t)v;
}

typedef struct {
    unsigned op, n, m, k, cond;
    bool sgn;
    uint32_t imm;
} model_case_t;

/* Expected d and F of one PP for the operation (F_in: flag before). */
static void model(const model_case_t *c, uint64_t a, uint64_t b, uint64_t d, unsigned f_in,
                  uint64_t *d_out, unsigned *f_out)
{
    const unsigned n = c->n;
    const uint64_t M = mask_n(n);
    a &= M;
    b &= M;
    *d_out = d;
    *f_out = f_in;
    switch (c->op) {
    case PP_OP_COPY: *d_out = a; break;
    case PP_OP_NOT: *d_out = ~a & M; break;
    case PP_OP_AND: *d_out = a & b; break;
    case PP_OP_OR: *d_out = a | b; break;
    case PP_OP_XOR: *d_out = a ^ b; break;
    case PP_OP_SETI: *d_out = c->imm & M; break;
    case PP_OP_SEL: *d_out = f_in ? a : b; break;
    case PP_OP_SHL: *d_out = c->k >= 64 ? 0 : (a << c->k) & M; break;
    case PP_OP_SHR: *d_out = c->k >= 64 ? 0 : a >> c->k; break;
    case PP_OP_SAR: *d_out = (uint64_t)(sext(a, n) >> (c->k < 63 ? c->k : 63)) & M; break;
    case PP_OP_ADD: *d_out = (a + b) & M; *f_out = (unsigned)((a + b) >> n) & 1u; break;
    case PP_OP_SUB: *d_out = (a - b) & M; *f_out = a < b; break;
    case PP_OP_ADDI: {
        uint64_t i = c->imm & M;
        *d_out = (a + i) & M;
        *f_out = (unsigned)((a + i) >> n) & 1u;
        break;
    }
    case PP_OP_CMP: case PP_OP_CMPI: {
        uint64_t bb = c->op == PP_OP_CMPI ? (c->imm & M) : b;
        int64_t sa = sext(a, n), sb = sext(bb, n);
        switch (c->cond) {
        case PP_COND_EQ: *f_out = a == bb; break;
        case PP_COND_NE: *f_out = a != bb; break;
        case PP_COND_LTU: *f_out = a < bb; break;
        case PP_COND_GEU: *f_out = a >= bb; break;
        case PP_COND_LTS: *f_out = sa < sb; break;
        default: *f_out = sa >= sb; break;
        }
        break;
    }
    case PP_OP_MUL: case PP_OP_MULI: {
        uint64_t am = a & mask_n(c->m), bm = b & mask_n(c->m);
        uint64_t ea = c->sgn ? (uint64_t)sext(am, c->m) : am;
        uint64_t eb = c->op == PP_OP_MULI ? (uint64_t)(int64_t)(int32_t)c->imm
                                          : (c->sgn ? (uint64_t)sext(bm, c->m) : bm);
        *d_out = (ea * eb) & M;      /* products mod 2^64, then mod 2^n (n <= 32) */
        break;
    }
    case PP_OP_F_SET: *f_out = c->k & 1u; break;
    case PP_OP_F_NOT: *f_out = !f_in; break;
    default: break;
    }
}

static void emit_case(pp_stream_t *s, const model_case_t *c)
{
    /* Fields: a at 0, b at 40, d at 80 (32 bits each region). */
    switch (c->op) {
    case PP_OP_COPY: pp_emit_copy(s, 80, 0, c->n); break;
    case PP_OP_NOT: pp_emit_not(s, 80, 0, c->n); break;
    case PP_OP_AND: pp_emit_and(s, 80, 0, 40, c->n); break;
    case PP_OP_OR: pp_emit_or(s, 80, 0, 40, c->n); break;
    case PP_OP_XOR: pp_emit_xor(s, 80, 0, 40, c->n); break;
    case PP_OP_SETI: pp_emit_seti(s, 80, c->n, c->imm); break;
    case PP_OP_SEL: pp_emit_sel(s, 80, 0, 40, c->n); break;
    case PP_OP_SHL: pp_emit_shl(s, 80, 0, c->n, c->k); break;
    case PP_OP_SHR: pp_emit_shr(s, 80, 0, c->n, c->k); break;
    case PP_OP_SAR: pp_emit_sar(s, 80, 0, c->n, c->k); break;
    case PP_OP_ADD: pp_emit_add(s, 80, 0, 40, c->n); break;
    case PP_OP_SUB: pp_emit_sub(s, 80, 0, 40, c->n); break;
    case PP_OP_ADDI: pp_emit_addi(s, 80, 0, c->n, c->imm); break;
    case PP_OP_CMP: pp_emit_cmp(s, c->cond, 0, 40, c->n); break;
    case PP_OP_CMPI: pp_emit_cmpi(s, c->cond, 0, c->n, c->imm); break;
    case PP_OP_MUL: pp_emit_mul(s, 80, c->n, 0, 40, c->m, c->sgn); break;
    case PP_OP_MULI: pp_emit_muli(s, 80, c->n, 0, c->m, c->sgn, (int32_t)c->imm); break;
    case PP_OP_F_SET: pp_emit_f_set(s, c->k); break;
    case PP_OP_F_NOT: pp_emit_f_not(s); break;
    default: break;
    }
}

/* Loads a, b, d and ctl (bit 0: F, bit 1: E) into the fields emit_case
 * uses, runs case c under that enable and reads d back into out. */
static bool run_case(renderer_t *r, const model_case_t *c, const uint32_t *a, const uint32_t *b,
                     const uint32_t *d, const uint32_t *ctl, uint32_t *out)
{
    renderer_write_field(r, 0, 32, a);
    renderer_write_field(r, 40, 32, b);
    renderer_write_field(r, 80, 32, d);
    renderer_write_field(r, 120, 2, ctl);
    pp_stream_t st;
    pp_stream_init(&st);
    pp_emit_en_all(&st);
    pp_emit_f_ld(&st, 121);
    pp_emit_en_flag(&st);          /* E = bit 1 of ctl */
    pp_emit_f_ld(&st, 120);        /* F = bit 0 where enabled (else F = E = 0) */
    emit_case(&st, c);
    bool ok = CHECK_MSG(pp_stream_ok(&st), "%s", pp_stream_error(&st)) &&
              CHECK_MSG(renderer_execute(r, st.words, st.n_words, NULL) == PP5_OK, "%s",
                        pp5_error_text());
    pp_stream_free(&st);
    return ok && renderer_read_field(r, 80, c->n, out) == PP5_OK;
}

TEST(pp_every_op_matches_an_integer_model)
{
    static const unsigned ops[] = {PP_OP_COPY, PP_OP_NOT, PP_OP_AND, PP_OP_OR, PP_OP_XOR,
                                   PP_OP_SETI, PP_OP_SEL, PP_OP_SHL, PP_OP_SHR, PP_OP_SAR,
                                   PP_OP_ADD, PP_OP_SUB, PP_OP_ADDI, PP_OP_CMP, PP_OP_CMPI,
                                   PP_OP_MUL, PP_OP_MULI, PP_OP_F_SET, PP_OP_F_NOT};
    static const unsigned widths[] = {1, 5, 13, 32};
    renderer_t *r = new_renderer();
    REQUIRE(r);
    uint32_t *a = malloc(PP_COUNT * 4), *b = malloc(PP_COUNT * 4), *d = malloc(PP_COUNT * 4),
             *ctl = malloc(PP_COUNT * 4), *out = malloc(PP_COUNT * 4);
    REQUIRE(a && b && d && ctl && out);
    uint64_t s = 77;
    unsigned cases = 0, bad = 0;
    unsigned levels = 0;
    for (int level = 0; level < PP_KERNEL_LEVELS; level++) {
        if (!use_kernels(r, (pp_kernel_level_t)level))
            continue;
        levels++;
        for (size_t oi = 0; oi < sizeof ops / sizeof ops[0]; oi++)
            for (size_t wi = 0; wi < 4; wi++)
                for (unsigned rep = 0; rep < 3; rep++) {
                    model_case_t c = {ops[oi], widths[wi], 1 + rng_below(&s, widths[wi]),
                                      rng_below(&s, widths[wi] + 2), rng_below(&s, PP_COND_COUNT),
                                      rng_below(&s, 2), (uint32_t)rng_next(&s)};
                    if (c.op == PP_OP_F_SET)
                        c.k &= 1u;
                    for (unsigned p = 0; p < PP_COUNT; p++) {
                        a[p] = (uint32_t)rng_next(&s);
                        /* Equal operands are a case of their own for compares. */
                        b[p] = rng_below(&s, 4) == 0 ? a[p] : (uint32_t)rng_next(&s);
                        d[p] = (uint32_t)rng_next(&s);
                        ctl[p] = (uint32_t)rng_next(&s) & 3u;   /* bit 0: F, bit 1: E */
                    }
                    if (c.op == PP_OP_CMPI && rep == 0)
                        c.imm = a[0];
                    REQUIRE(run_case(r, &c, a, b, d, ctl, out));
                    cases++;
                    for (unsigned p = 0; p < PP_COUNT; p++) {
                        unsigned e = (ctl[p] >> 1) & 1u, f_in = e ? ctl[p] & 1u : 0;
                        uint64_t want_d;
                        unsigned want_f;
                        model(&c, a[p], b[p], d[p] & mask_n(c.n), f_in, &want_d, &want_f);
                        if (!e) {
                            want_d = d[p] & mask_n(c.n);
                            want_f = f_in;
                        }
                        unsigned got_f = pp_array_bit(r->array->flag, p);
                        if ((out[p] != want_d || got_f != want_f) && bad++ < 3)
                            CHECK_MSG(false, "%s n=%u m=%u k=%u cond=%u sgn=%d imm=0x%x PP %u "
                                  "(E=%u a=0x%x b=0x%x): d 0x%x want 0x%llx, F %u want %u",
                                  pp_isa_info(c.op)->name, c.n, c.m, c.k, c.cond, c.sgn, c.imm,
                                  p, e, a[p], b[p], out[p], (unsigned long long)want_d, got_f,
                                  want_f);
                    }
                }
    }
    pp_array_set_kernels(r->array, pp_kernel_level_best());
    CHECK_EQ(bad, 0);
    CHECK_EQ(cases, levels * 19 * 4 * 3);
    free(a); free(b); free(d); free(ctl); free(out);
}

/* Operands for the multiply's host-speed shortcuts (pp_kernels.inc): by
 * block of 1024 PPs, no multiplier bit at all, small values whose carries
 * die out early, values at the top of the m-bit range (carries ripple all
 * the way), and random ones. */
static uint32_t mul_operand(uint64_t *s, unsigned p, unsigned m, bool multiplier)
{
    uint32_t top = (uint32_t)mask_n(m);
    switch ((p / 1024u) % 4u) {
    case 0: return multiplier ? 0u : (uint32_t)rng_next(s);
    case 1: return (uint32_t)rng_below(s, 8);
    case 2: return top - (uint32_t)rng_below(s, 3);
    default: return (uint32_t)rng_next(s);
    }
}

TEST(pp_multiply_of_sparse_and_small_operands_matches_an_integer_model)
{
    static const unsigned nm[][2] = {{8, 4}, {16, 8}, {32, 16}, {32, 32}, {13, 5}};
    renderer_t *r = new_renderer();
    REQUIRE(r);
    uint32_t *a = malloc(PP_COUNT * 4), *b = malloc(PP_COUNT * 4), *d = malloc(PP_COUNT * 4),
             *ctl = malloc(PP_COUNT * 4), *out = malloc(PP_COUNT * 4);
    REQUIRE(a && b && d && ctl && out);
    uint64_t s = 4242;
    unsigned cases = 0, bad = 0;
    unsigned levels = 0;
    for (int level = 0; level < PP_KERNEL_LEVELS; level++) {
        if (!use_kernels(r, (pp_kernel_level_t)level))
            continue;
        levels++;
        for (size_t k = 0; k < sizeof nm / sizeof nm[0]; k++)
            for (unsigned variant = 0; variant < 4; variant++) {
                model_case_t c = {variant < 2 ? PP_OP_MUL : PP_OP_MULI, nm[k][0], nm[k][1], 0, 0,
                                  variant & 1u, variant == 2 ? 5u : 0xfffffff3u};
                for (unsigned p = 0; p < PP_COUNT; p++) {
                    a[p] = mul_operand(&s, p, c.m, false);
                    b[p] = mul_operand(&s, p, c.m, true);
                    d[p] = (uint32_t)rng_next(&s);
                    ctl[p] = (p / 1024u) % 8u == 7u ? 0u : 2u;   /* one block not enabled */
                }
                REQUIRE(run_case(r, &c, a, b, d, ctl, out));
                cases++;
                for (unsigned p = 0; p < PP_COUNT; p++) {
                    uint64_t want = d[p] & mask_n(c.n);
                    unsigned f;
                    if (ctl[p])
                        model(&c, a[p], b[p], want, 0, &want, &f);
                    if (out[p] != want && bad++ < 3)
                        CHECK_MSG(false, "%s n=%u m=%u sgn=%d PP %u (a=0x%x b=0x%x): 0x%x, want "
                                  "0x%llx", pp_isa_info(c.op)->name, c.n, c.m, c.sgn, p, a[p],
                                  b[p], out[p], (unsigned long long)want);
                }
            }
    }
    pp_array_set_kernels(r->array, pp_kernel_level_best());
    CHECK_EQ(bad, 0);
    CHECK_EQ(cases, levels * 5 * 4);
    free(a); free(b); free(d); free(ctl); free(out);
}

TEST(pp_enable_ops_follow_their_truth_tables)
{
    renderer_t *r = new_renderer();
    REQUIRE(r);
    static const unsigned ops[] = {PP_OP_EN_ALL, PP_OP_EN_FLAG, PP_OP_EN_AND, PP_OP_EN_ANDN,
                                   PP_OP_EN_OR, PP_OP_EN_NOT};
    for (size_t i = 0; i < 6; i++) {
        /* All four (E, F) combinations: E = bit 0 of p, F = bit 1 of p. */
        for (unsigned w = 0; w < PP_PLANE_WORDS; w++) {
            r->array->en[w] = 0xAAAAAAAAAAAAAAAAull;
            r->array->flag[w] = 0xCCCCCCCCCCCCCCCCull;
        }
        uint32_t word = (uint32_t)ops[i] << 24;
        REQUIRE(renderer_execute(r, &word, 1, NULL) == PP5_OK);
        int wrong = -1;                   /* the first PP with a wrong E */
        for (unsigned p = 0; p < 64; p++) {
            unsigned e = p & 1u;
            unsigned f = (p >> 1) & 1u, want;
            switch (ops[i]) {
            case PP_OP_EN_ALL: want = 1; break;
            case PP_OP_EN_FLAG: want = f; break;
            case PP_OP_EN_AND: want = e & f; break;
            case PP_OP_EN_ANDN: want = e & !f; break;
            case PP_OP_EN_OR: want = e | f; break;
            default: want = !e; break;
            }
            if (pp_array_bit(r->array->en, p) != want && wrong < 0)
                wrong = (int)p;
        }
        CHECK_MSG(wrong < 0, "%s with E=%u F=%u (PP %d) gives the wrong E",
                  pp_isa_info(ops[i])->name, (unsigned)wrong & 1u, ((unsigned)wrong >> 1) & 1u,
                  wrong);
    }
}

TEST(pp_isa_doc_is_in_sync_with_the_table)
{
    /* emu/PP_ISA.md embeds the output of `pp5 pp-isa`; regenerate it when pp_isa.def changes. */
    char path[512];
    snprintf(path, sizeof path, "%s/isa.md", pp5_test_outdir());
    REQUIRE(pp5_test_run_cli("pp-isa", path, NULL) == 0);
    char *table = pp5_test_read_file(path);
    char *doc = pp5_test_read_file("emu/PP_ISA.md");
    REQUIRE(table && doc);
    CHECK(strlen(table) > 1000);
    CHECK_MSG(strstr(doc, table) != NULL, "emu/PP_ISA.md does not contain the current "
              "`pp5 pp-isa` table: regenerate it");
    free(table);
    free(doc);
}

TEST(pp_diffuse_shading_recipe_of_pp_isa_md)
{
    /* The recipe documented in emu/PP_ISA.md: I = max(0, N.L) >> 7 with signed
     * 8-bit normal components in pixel memory and L as constants; checked
     * against C for every PP. */
    renderer_t *r = new_renderer();
    REQUIRE(r);
    enum { NX = 0, NY = 8, NZ = 16, T = 24, DOT = 48, I = 72, W = 18 };
    const int32_t L[3] = {-45, 90, 71};
    uint32_t *nx = malloc(PP_COUNT * 4), *ny = malloc(PP_COUNT * 4), *nz = malloc(PP_COUNT * 4),
             *out = malloc(PP_COUNT * 4);
    REQUIRE(nx && ny && nz && out);
    uint64_t s = 4242;
    for (unsigned p = 0; p < PP_COUNT; p++) {
        nx[p] = (uint32_t)rng_next(&s) & 0xff;
        ny[p] = (uint32_t)rng_next(&s) & 0xff;
        nz[p] = (uint32_t)rng_next(&s) & 0xff;
    }
    renderer_write_field(r, NX, 8, nx);
    renderer_write_field(r, NY, 8, ny);
    renderer_write_field(r, NZ, 8, nz);
    pp_stream_t st;
    pp_stream_init(&st);
    pp_emit_muli(&st, DOT, W, NX, 8, true, L[0]);       /* dot = nx * Lx */
    pp_emit_muli(&st, T, W, NY, 8, true, L[1]);
    pp_emit_add(&st, DOT, DOT, T, W);                   /* += ny * Ly */
    pp_emit_muli(&st, T, W, NZ, 8, true, L[2]);
    pp_emit_add(&st, DOT, DOT, T, W);                   /* += nz * Lz */
    pp_emit_cmpi(&st, PP_CMP_LTS, DOT, W, 0);           /* F = dot < 0 */
    pp_emit_en_flag(&st);
    pp_emit_seti(&st, DOT, W, 0);                       /* clamp where negative */
    pp_emit_en_all(&st);
    pp_emit_shr(&st, I, DOT, W, 7);                     /* fixed point: / 128 */
    REQUIRE(pp_stream_ok(&st));
    renderer_exec_result_t res;
    REQUIRE(renderer_execute(r, st.words, st.n_words, &res) == PP5_OK);
    pp_stream_free(&st);
    renderer_read_field(r, I, 11, out);
    unsigned bad = 0, first = 0;
    for (unsigned p = 0; p < PP_COUNT; p++) {
        int32_t d = (int8_t)nx[p] * L[0] + (int8_t)ny[p] * L[1] + (int8_t)nz[p] * L[2];
        uint32_t want = d < 0 ? 0u : (uint32_t)d >> 7;
        if (out[p] != want && bad++ == 0)
            first = p;
    }
    CHECK_MSG(bad == 0, "%u PPs shade wrong; first PP %u: %u", bad, first, out[first]);
    CHECK_EQ(res.instructions, 10);
    CHECK(res.class_cycles[PP_CLASS_MUL] > 0);
    free(nx); free(ny); free(nz); free(out);
}
