/* test_bit_transpose.c: the word-parallel plane <-> word transposes (backing-store
 * blocks, pixel-memory fields) against a plain per-bit loop on random data. */
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "backing.h"
#include "bit_transpose.h"
#include "pp_array.h"

static uint64_t next_random(uint64_t *s)
{
    /* xorshift64*: fixed seeds, so failures reproduce. */
    *s ^= *s >> 12;
    *s ^= *s << 25;
    *s ^= *s >> 27;
    return *s * 0x2545f4914f6cdd1dull;
}

/* The definition, one bit at a time: out[p] bit k = bit p of plane k. */
static uint32_t ref_word(const uint64_t *first, size_t stride, unsigned bits, unsigned p)
{
    uint32_t v = 0;
    for (unsigned k = 0; k < bits; k++)
        v |= (uint32_t)((first[k * stride + p / 64] >> (p % 64)) & 1u) << k;
    return v;
}

static unsigned count_word_mismatches(const uint64_t *first, size_t stride, unsigned bits,
                                      const uint32_t *got)
{
    unsigned bad = 0;
    for (unsigned p = 0; p < PP_COUNT; p++)
        bad += got[p] != ref_word(first, stride, bits, p);
    return bad;
}

/* Planes lo..lo+bits-1 must hold bit k of in[p]; every other plane of `planes`
 * (n_planes of them) must equal `before`. */
static unsigned count_plane_mismatches(const uint64_t *planes, const uint64_t *before,
                                       size_t stride, unsigned n_planes, unsigned lo,
                                       unsigned bits, const uint32_t *in)
{
    unsigned bad = 0;
    for (unsigned k = 0; k < n_planes; k++) {
        for (unsigned p = 0; p < PP_COUNT; p++) {
            unsigned got = (unsigned)(planes[k * stride + p / 64] >> (p % 64)) & 1u;
            unsigned want = k >= lo && k < lo + bits
                                ? (in[p] >> (k - lo)) & 1u
                                : (unsigned)(before[k * stride + p / 64] >> (p % 64)) & 1u;
            bad += got != want;
        }
    }
    return bad;
}

TEST(bit_transpose_backing_all_blocks)
{
    backing_t *b = NULL;
    REQUIRE(backing_alloc(&b) == PP5_OK);
    uint32_t *words = malloc(PP_COUNT * sizeof *words);
    uint64_t *before = malloc(sizeof b->plane);
    REQUIRE(words && before);
    uint64_t s = 0x9e3779b97f4a7c15ull;
    for (unsigned k = 0; k < PP_BS_BITS; k++)
        for (unsigned w = 0; w < PP_PLANE_WORDS; w++)
            b->plane[k][w] = next_random(&s);
    for (unsigned blk = 0; blk < PP_BS_BLOCKS; blk++) {
        backing_read_block(b, blk, words);
        unsigned bad = count_word_mismatches(backing_plane(b, blk, 0), PP_PLANE_WORDS, 32, words);
        CHECK_MSG(bad == 0, "read of block %u: %u PPs' words wrong", blk, bad);
    }
    for (unsigned blk = 0; blk < PP_BS_BLOCKS; blk++) {
        for (unsigned p = 0; p < PP_COUNT; p++)
            words[p] = (uint32_t)next_random(&s);
        /* Neighbouring blocks (one each side) must be left alone. */
        unsigned first = blk ? blk - 1 : 0;
        unsigned last = blk + 1 < PP_BS_BLOCKS ? blk + 1 : blk;
        unsigned n_planes = (last - first + 1) * 32;
        memcpy(before, backing_plane(b, first, 0), n_planes * PP_PLANE_WORDS * sizeof *before);
        backing_write_block(b, blk, words);
        unsigned bad = count_plane_mismatches(backing_plane(b, first, 0), before, PP_PLANE_WORDS,
                                              n_planes, (blk - first) * 32, 32, words);
        CHECK_MSG(bad == 0, "write of block %u: %u plane bits wrong (blocks %u..%u)", blk, bad,
                  first, last);
    }
    free(before);
    free(words);
    backing_free(b);
}

TEST(bit_transpose_fields_all_widths_offsets)
{
    pp_array_t *a = NULL;
    REQUIRE(pp_array_alloc(&a) == PP5_OK);
    const size_t stride = sizeof a->mem[0] / sizeof a->mem[0][0];
    uint32_t *words = malloc(PP_COUNT * sizeof *words);
    uint64_t *before = malloc(sizeof a->mem);
    REQUIRE(words && before);
    uint64_t s = 0x0123456789abcdefull;
    for (unsigned k = 0; k < PP_MEM_BITS; k++)
        for (unsigned w = 0; w < PP_PLANE_WORDS; w++)
            a->mem[k][w] = next_random(&s);
    /* Even, odd and end-of-memory offsets for every width 1..32. */
    unsigned cases = 0;
    for (unsigned bits = 1; bits <= 32; bits++) {
        const unsigned addrs[4] = {0, 1 + 2 * (bits % 7), 97 + 2 * bits, PP_MEM_BITS - bits};
        for (unsigned i = 0; i < 4; i++) {
            unsigned addr = addrs[i];
            REQUIRE(addr + bits <= PP_MEM_BITS);
            pp_array_read_field(a, addr, bits, words);
            unsigned bad = count_word_mismatches(a->mem[addr], stride, bits, words);
            CHECK_MSG(bad == 0, "read of %u bits at %u: %u PPs' words wrong", bits, addr, bad);
            /* Random words with garbage above `bits`, which the write must ignore. */
            for (unsigned p = 0; p < PP_COUNT; p++)
                words[p] = (uint32_t)next_random(&s);
            memcpy(before, a->mem, sizeof a->mem);
            pp_array_write_field(a, addr, bits, words);
            bad = count_plane_mismatches(a->mem[0], before, stride, PP_MEM_BITS, addr, bits,
                                         words);
            CHECK_MSG(bad == 0, "write of %u bits at %u: %u plane bits wrong", bits, addr, bad);
            cases++;
        }
    }
    CHECK_EQ(cases, 128);
    free(before);
    free(words);
    pp_array_free(a);
}

/* The first PP p whose word is not p & mask, or -1. */
static int first_wrong_word(const uint32_t *words, uint32_t mask)
{
    for (unsigned p = 0; p < PP_COUNT; p++)
        if (words[p] != (p & mask))
            return (int)p;
    return -1;
}

/* A hand-made case: PP p holds p in a 14-bit field, so plane k is the pattern of
 * bit k of the PP index (plane 0 = 0xaaaa..., plane 6 = words alternating 0 / ~0). */
TEST(bit_transpose_index_pattern)
{
    static uint64_t planes[14][PP_PLANE_WORDS];
    for (unsigned k = 0; k < 14; k++)
        for (unsigned w = 0; w < PP_PLANE_WORDS; w++) {
            uint64_t v = 0;
            for (unsigned j = 0; j < 64; j++)
                v |= (uint64_t)(((w * 64 + j) >> k) & 1u) << j;
            planes[k][w] = v;
        }
    CHECK_EQ(planes[0][0], 0xaaaaaaaaaaaaaaaaull);
    uint32_t *words = malloc(PP_COUNT * sizeof *words);
    REQUIRE(words);
    bit_transpose_planes_to_words(planes[0], PP_PLANE_WORDS, 14, words);
    int bad = first_wrong_word(words, 0x3fffu);
    CHECK_MSG(bad < 0, "14 bits: PP %d reads %u", bad, bad < 0 ? 0 : words[bad]);
    /* Width 5 keeps only the low 5 bits of the index. */
    bit_transpose_planes_to_words(planes[0], PP_PLANE_WORDS, 5, words);
    bad = first_wrong_word(words, 31u);
    CHECK_MSG(bad < 0, "5 bits: PP %d reads %u", bad, bad < 0 ? 0 : words[bad]);
    free(words);
}

/* Every kernel copy the host has (the portable one is what hosts without AVX2
 * run) on random planes, every width, odd plane strides included; a copy the
 * host lacks is named. */
TEST(bit_transpose_every_kernel_copy)
{
    const size_t stride = PP_PLANE_WORDS + 3;          /* odd: unaligned plane starts */
    uint64_t *planes = malloc(33 * stride * sizeof *planes);
    uint64_t *before = malloc(33 * stride * sizeof *before);
    uint32_t *words = malloc(PP_COUNT * sizeof *words);
    REQUIRE(planes && before && words);
    uint64_t s = 0xfeedfacecafebeefull;
    for (size_t i = 0; i < 33 * stride; i++)
        planes[i] = next_random(&s);
    unsigned levels = 0;
    for (int l = 0; l < PP_KERNEL_LEVELS; l++) {
        const pp_kernel_level_t level = (pp_kernel_level_t)l;
        const char *name = pp_kernel_level_name(level);
        if (!pp_kernel_level_available(level)) {
            printf("   note: this host or build has no %s kernels; they are not checked here\n",
                   name);
            continue;
        }
        levels++;
        for (unsigned bits = 1; bits <= 32; bits++) {
            unsigned lo = bits & 1u;                         /* odd first plane for odd widths */
            bit_transpose_planes_to_words_at_level(level, planes + lo * stride, stride, bits, words);
            unsigned bad = count_word_mismatches(planes + lo * stride, stride, bits, words);
            CHECK_MSG(bad == 0, "%s read of %u bits: %u PPs' words wrong", name, bits, bad);
            for (unsigned p = 0; p < PP_COUNT; p++)
                words[p] = (uint32_t)next_random(&s);
            memcpy(before, planes, 33 * stride * sizeof *planes);
            bit_transpose_words_to_planes_at_level(level, words, bits, planes + lo * stride, stride);
            bad = count_plane_mismatches(planes, before, stride, 33, lo, bits, words);
            CHECK_MSG(bad == 0, "%s write of %u bits: %u plane bits wrong", name, bits, bad);
        }
    }
    CHECK(levels >= 1);
    free(words);
    free(before);
    free(planes);
}
