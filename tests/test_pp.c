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
        for (unsigned b = 0; b < PP_BS_BLOCKS; b++) {
            uint32_t v = 0;
            for (unsigned k = 0; k < 32; k++)
                v |= (uint32_t)pp_array_bit(backing_plane(r->bs, b, k), q) << k;
            p->bs[b] = v;
        }
    }
}

/* Number of PPs whose state differs; reports the first difference. */
static unsigned compare(const renderer_t *r, const pp_ref_t *ref, const char *what, bool with_bs)
{
    unsigned bad = 0;
    for (unsigned i = 0; i < ref->count; i++) {
        const pp_ref_pe_t *p = &ref->pe[i];
        unsigned q = p->index;
        bool ok = p->e == pp_array_bit(r->array->en, q) && p->f == pp_array_bit(r->array->flag, q);
        for (unsigned k = 0; ok && k < PP_MEM_BITS; k++)
            ok = p->mem[k] == pp_array_bit(r->array->mem[k], q);
        for (unsigned b = 0; ok && with_bs && b < PP_BS_BLOCKS; b++)
            for (unsigned k = 0; ok && k < 32; k++)
                ok = ((p->bs[b] >> k) & 1u) == pp_array_bit(r->bs->plane[b * 32 + k], q);
        if (!ok && bad++ == 0)
            CHECK_MSG(false, "%s: PP %u (row %u col %u) differs from the reference", what, q,
                      q / PP_ARRAY_DIM, q % PP_ARRAY_DIM);
    }
    return bad;
}

/* Runs `n_insns` random instructions (every opcode appears) through both
 * executors, one instruction per renderer_execute so a mismatch names it. */
static unsigned run_random_stream(uint64_t seed, const unsigned *pps, unsigned n_pps,
                                  unsigned n_insns)
{
    uint64_t s = seed * 0x9E3779B97F4A7C15ull + 1;
    renderer_t *r = new_renderer();
    pp_ref_t ref;
    if (!r || pp_ref_init(&ref, pps, n_pps) != PP5_OK)
        return 1;
    randomize(r, &ref, &s);
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
        /* The backing store (4096 bits per PP) is compared after stores and at the end. */
        bad += compare(r, &ref, ctx, in.op == PP_OP_BSSTORE || i + 1 == n_insns);
    }
    pp_stream_free(&st);
    pp_ref_free(&ref);
    return bad;
}

TEST(pp_random_streams_match_reference_on_sampled_pps)
{
    /* 150 streams x 80 instructions; each compares 256 PPs (the four corners
     * and 252 random ones) after every instruction. */
    enum { STREAMS = 150, INSNS = 80, PPS = 256 };
    unsigned pps[PPS], failed = 0;
    for (unsigned seed = 1; seed <= STREAMS; seed++) {
        uint64_t s = seed;
        pps[0] = 0;
        pps[1] = PP_ARRAY_DIM - 1;
        pps[2] = PP_COUNT - PP_ARRAY_DIM;
        pps[3] = PP_COUNT - 1;
        for (unsigned i = 4; i < PPS; i++)
            pps[i] = rng_below(&s, PP_COUNT);
        failed += run_random_stream(seed, pps, PPS, INSNS) != 0;
        if (failed)
            break;
    }
    CHECK_EQ(failed, 0);
}

TEST(pp_random_streams_match_reference_on_all_pps)
{
    /* Whole array: every one of the 16384 PPs, 2 streams x 40 instructions. */
    unsigned *pps = malloc(PP_COUNT * sizeof *pps);
    REQUIRE(pps);
    for (unsigned i = 0; i < PP_COUNT; i++)
        pps[i] = i;
    unsigned failed = 0;
    for (uint64_t seed = 1001; seed <= 1002; seed++)
        failed += run_random_stream(seed, pps, PP_COUNT, 40) != 0;
    free(pps);
    CHECK_EQ(failed, 0);
}
