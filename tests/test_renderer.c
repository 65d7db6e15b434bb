/* test_renderer.c: renderer cycle accounting (hand-calculated from the cost
 * formulas), backing-store overlap and interlock, stream validation, field access. */
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "pp_encode.h"
#include "renderer.h"

/* A renderer with chosen (non-default) costs, so the checks prove the formulas
 * read the parameters. */
static renderer_t *timing_renderer(void)
{
    static renderer_t r;
    static bool ready;
    if (!ready) {
        pp_params_t p;
        pp_params_default(&p);
        p.cycles_per_bit = 1;
        p.alu_overhead_cycles = 2;
        p.enable_op_cycles = 1;
        p.flag_op_cycles = 3;
        p.qee_fill_cycles = 10;
        p.qee_bits_per_cycle = 1;
        p.bs_issue_cycles = 1;
        p.bs_block_cycles = 64;
        p.bs_queue_depth = 4;
        p.bs_wait_cycles = 2;
        if (renderer_init(&r, 1, &p) != PP5_OK)
            return NULL;
        ready = true;
    }
    renderer_reset(&r);
    return &r;
}

static pp5_status_t run(renderer_t *r, pp_stream_t *s, renderer_exec_result_t *res)
{
    if (!pp_stream_ok(s))
        return PP5_E_FIRMWARE;
    return renderer_execute(r, s->words, s->n_words, res);
}

TEST(renderer_cycles_follow_the_cost_table)
{
    renderer_t *r = timing_renderer();
    REQUIRE(r);
    pp_stream_t s;
    pp_stream_init(&s);
    pp_emit_add(&s, 0, 8, 16, 8);                 /* 8 + 2 = 10 */
    pp_emit_cmp(&s, PP_CMP_LTS, 0, 16, 16);       /* 16 + 2 = 18 */
    pp_emit_en_flag(&s);                          /* 1 */
    pp_emit_f_not(&s);                            /* 3 */
    pp_emit_qee(&s, 40, 20, 4, 1, 2, 3, 4, 5, 6); /* fill 10 + (4 + 20) bits = 34 */
    pp_emit_mul(&s, 100, 8, 120, 130, 4, false);  /* clear 10; j=0..3: 10+9+8+7 -> 44 */
    pp_emit_mul(&s, 100, 8, 120, 130, 4, true);   /* clear 10; j=0..7: 10+9+...+3 = 52 -> 62 */
    pp_emit_muli(&s, 100, 8, 120, 4, false, 5);   /* clear 10; bits 0, 2: 10 + 8 -> 28 */
    pp_emit_muli(&s, 100, 8, 120, 4, true, -1);   /* clear 10; bits 0..7 -> 52 -> 62 */
    renderer_exec_result_t res;
    REQUIRE(run(r, &s, &res) == PP5_OK);
    pp_stream_free(&s);
    CHECK_EQ(res.instructions, 9);
    CHECK_EQ(res.compute_cycles, 10 + 18 + 1 + 3 + 34 + 44 + 62 + 28 + 62);
    CHECK_EQ(res.total_cycles, res.compute_cycles);
    CHECK_EQ(res.bs_cycles, 0);
    CHECK_EQ(res.stall_cycles, 0);
    CHECK_EQ(res.class_cycles[PP_CLASS_ADD], 10);
    CHECK_EQ(res.class_cycles[PP_CLASS_CMP], 18);
    CHECK_EQ(res.class_cycles[PP_CLASS_ENABLE], 1);
    CHECK_EQ(res.class_cycles[PP_CLASS_FLAG], 3);
    CHECK_EQ(res.class_cycles[PP_CLASS_QEE], 34);
    CHECK_EQ(res.class_cycles[PP_CLASS_MUL], 44 + 62 + 28 + 62);
    CHECK_EQ(res.class_instructions[PP_CLASS_MUL], 4);
    CHECK_EQ(r->stats.op_cycles[PP_OP_MULI], 28 + 62);
}

TEST(renderer_backing_store_overlaps_compute)
{
    renderer_t *r = timing_renderer();
    REQUIRE(r);
    renderer_exec_result_t res;
    pp_stream_t s;
    pp_stream_init(&s);
    /* Store, then an unrelated add: the transfer [1, 65) runs under the add [1, 11). */
    pp_emit_bsstore(&s, 0, 0);
    pp_emit_add(&s, 100, 120, 140, 8);
    REQUIRE(run(r, &s, &res) == PP5_OK);
    CHECK_EQ(res.compute_cycles, 11);
    CHECK_EQ(res.bs_cycles, 64);
    CHECK_EQ(res.stall_cycles, 0);
    CHECK_EQ(res.total_cycles, 65);

    /* Load, then an add that reads the loaded field: it waits for cycle 65. */
    pp_stream_clear(&s);
    pp_emit_bsload(&s, 0, 1);
    pp_emit_add(&s, 100, 0, 140, 8);
    REQUIRE(run(r, &s, &res) == PP5_OK);
    CHECK_EQ(res.stall_cycles, 64);
    CHECK_EQ(res.compute_cycles, 65 + 10);
    CHECK_EQ(res.total_cycles, 75);

    /* Five stores from disjoint fields to distinct blocks, queue depth 4, then
     * BSWAIT.  Issues end at 1, 2, 3, 4; transfers [1,65) [65,129) [129,193)
     * [193,257); the fifth waits for a free slot (65), issues 65..66, transfers
     * [257,321); BSWAIT waits to 321 and takes 2: 323. */
    pp_stream_clear(&s);
    for (unsigned i = 0; i < 5; i++)
        pp_emit_bsstore(&s, 10 + i, 32 * i);
    pp_emit_bswait(&s);
    REQUIRE(run(r, &s, &res) == PP5_OK);
    CHECK_EQ(res.bs_cycles, 5 * 64);
    CHECK_EQ(res.stall_cycles, (65 - 4) + (321 - 66));
    CHECK_EQ(res.compute_cycles, 323);
    CHECK_EQ(res.total_cycles, 323);
    CHECK_EQ(res.class_cycles[PP_CLASS_BS], 5 + 2);
    pp_stream_free(&s);
}

TEST(renderer_backing_store_round_trip_under_enable)
{
    renderer_t *r = timing_renderer();
    REQUIRE(r);
    uint32_t *v = malloc(PP_COUNT * sizeof *v), *w = malloc(PP_COUNT * sizeof *w);
    REQUIRE(v && w);
    for (unsigned p = 0; p < PP_COUNT; p++)
        v[p] = p * 2654435761u;
    REQUIRE(renderer_write_field(r, 64, 32, v) == PP5_OK);
    REQUIRE(renderer_write_field(r, 0, 1, v) == PP5_OK);    /* bit 0 of v: the enable pattern */
    pp_stream_t s;
    pp_stream_init(&s);
    pp_emit_bsstore(&s, 77, 64);                  /* all PPs */
    pp_emit_f_ld(&s, 0);
    pp_emit_en_flag(&s);
    pp_emit_bsload(&s, 128, 77);                  /* only where bit 0 of v is 1 */
    pp_emit_en_all(&s);
    REQUIRE(run(r, &s, NULL) == PP5_OK);
    pp_stream_free(&s);
    REQUIRE(renderer_bs_read(r, 77, w) == PP5_OK);
    unsigned p = 0;
    while (p < PP_COUNT && w[p] == v[p])
        p++;
    CHECK_MSG(p == PP_COUNT, "BSSTORE (all PPs): block 77 of PP %u holds 0x%x, want 0x%x", p,
              p < PP_COUNT ? w[p] : 0, p < PP_COUNT ? v[p] : 0);
    REQUIRE(renderer_read_field(r, 128, 32, w) == PP5_OK);
    for (p = 0; p < PP_COUNT && w[p] == ((v[p] & 1u) ? v[p] : 0u); p++)
        ;
    CHECK_MSG(p == PP_COUNT, "BSLOAD (enabled PPs only): field 128 of PP %u holds 0x%x", p,
              p < PP_COUNT ? w[p] : 0);
    CHECK_EQ(renderer_bs_read(r, 128, w), PP5_E_FIRMWARE);
    CHECK_EQ(renderer_bs_write(r, 200, w), PP5_E_FIRMWARE);
    CHECK_EQ(renderer_read_field(r, 200, 9, w), PP5_E_FIRMWARE);
    CHECK_EQ(renderer_read_field(r, 0, 33, w), PP5_E_FIRMWARE);
    CHECK_EQ(renderer_write_field(r, 0, 0, v), PP5_E_FIRMWARE);
    free(v);
    free(w);
}

/* The first mismatching PP of block `block` against want, or PP_COUNT. */
static unsigned bs_mismatch(renderer_t *r, unsigned block, const uint32_t *want, uint32_t *buf)
{
    if (renderer_bs_read(r, block, buf) != PP5_OK)
        return 0;
    unsigned p = 0;
    while (p < PP_COUNT && buf[p] == want[p])
        p++;
    return p;
}

/* renderer_bs_read keeps the words it returned (renderer.h); every way of
 * writing the block must drop them: a stream's BSSTORE, renderer_bs_write
 * and renderer_reset, each after a read that filled the copy. */
TEST(renderer_backing_store_reads_never_return_stale_words)
{
    renderer_t *r = timing_renderer();
    REQUIRE(r);
    uint32_t *a = malloc(PP_COUNT * sizeof *a), *b = malloc(PP_COUNT * sizeof *b);
    uint32_t *zero = calloc(PP_COUNT, sizeof *zero), *buf = malloc(PP_COUNT * sizeof *buf);
    REQUIRE(a && b && zero && buf);
    for (unsigned p = 0; p < PP_COUNT; p++)
        a[p] = p * 2654435761u + 1u, b[p] = ~a[p] ^ (p << 7);
    REQUIRE(renderer_bs_write(r, 5, a) == PP5_OK);
    CHECK_EQ(bs_mismatch(r, 5, a, buf), PP_COUNT);
    CHECK_EQ(bs_mismatch(r, 5, a, buf), PP_COUNT);   /* the second read is served from the copy */
    /* a stream stores other words into the block */
    REQUIRE(renderer_write_field(r, 64, 32, b) == PP5_OK);
    pp_stream_t s;
    pp_stream_init(&s);
    pp_emit_bsstore(&s, 5, 64);
    REQUIRE(run(r, &s, NULL) == PP5_OK);
    pp_stream_free(&s);
    CHECK_EQ(bs_mismatch(r, 5, b, buf), PP_COUNT);
    REQUIRE(renderer_bs_write(r, 5, a) == PP5_OK);
    CHECK_EQ(bs_mismatch(r, 5, a, buf), PP_COUNT);
    renderer_reset(r);
    CHECK_EQ(bs_mismatch(r, 5, zero, buf), PP_COUNT);
    free(a), free(b), free(zero), free(buf);
}

/* Executes raw words; returns the status and leaves the message in pp5_error_text. */
static pp5_status_t exec_words(renderer_t *r, const uint32_t *w, size_t n)
{
    return renderer_execute(r, w, n, NULL);
}

TEST(renderer_rejects_illegal_streams_with_a_named_message)
{
    renderer_t *r = timing_renderer();
    REQUIRE(r);
    pp_stream_t s;
    pp_stream_init(&s);
    /* A field past the 208-bit pixel memory. */
    pp_emit_add(&s, 200, 0, 16, 16);
    CHECK_EQ(run(r, &s, NULL), PP5_E_FIRMWARE);
    CHECK(strstr(pp5_error_text(), "ADD") && strstr(pp5_error_text(), "field d") &&
          strstr(pp5_error_text(), "208"));
    pp_stream_clear(&s);
    pp_emit_qee(&s, 190, 20, 0, 0, 0, 0, 0, 0, 1);
    CHECK_EQ(run(r, &s, NULL), PP5_E_FIRMWARE);
    CHECK(strstr(pp5_error_text(), "QEE") != NULL);
    pp_stream_clear(&s);
    pp_emit_bsload(&s, 180, 0);                   /* 32-bit block at 180: past 208 */
    CHECK_EQ(run(r, &s, NULL), PP5_E_FIRMWARE);
    CHECK(strstr(pp5_error_text(), "BSLOAD") != NULL);
    /* Multiply into its own source. */
    pp_stream_clear(&s);
    pp_emit_mul(&s, 0, 16, 8, 40, 8, false);
    CHECK_EQ(run(r, &s, NULL), PP5_E_FIRMWARE);
    CHECK(strstr(pp5_error_text(), "overlaps") != NULL);
    pp_stream_free(&s);

    /* Illegal opcodes, zero words, truncation, bad sub-fields. */
    uint32_t zero = 0;
    CHECK_EQ(exec_words(r, &zero, 1), PP5_E_FIRMWARE);
    CHECK(strstr(pp5_error_text(), "illegal opcode") != NULL);
    uint32_t bad_op = 0x3Fu << 24;
    CHECK_EQ(exec_words(r, &bad_op, 1), PP5_E_FIRMWARE);
    uint32_t truncated[3] = {(uint32_t)PP_OP_QEE << 24 | 8u << 16, 0, 1};
    CHECK_EQ(exec_words(r, truncated, 3), PP5_E_FIRMWARE);
    CHECK(strstr(pp5_error_text(), "needs") != NULL);
    uint32_t n_zero[2] = {(uint32_t)PP_OP_ADD << 24, 0};
    CHECK_EQ(exec_words(r, n_zero, 2), PP5_E_FIRMWARE);
    uint32_t stray[1] = {(uint32_t)PP_OP_EN_ALL << 24 | 5u << 8};
    CHECK_EQ(exec_words(r, stray, 1), PP5_E_FIRMWARE);
    uint32_t bad_cond[2] = {(uint32_t)PP_OP_CMP << 24 | 8u << 16 | 6u, 0};
    CHECK_EQ(exec_words(r, bad_cond, 2), PP5_E_FIRMWARE);
    uint32_t bad_block[2] = {(uint32_t)PP_OP_BSSTORE << 24 | 128u, 0};
    CHECK_EQ(exec_words(r, bad_block, 2), PP5_E_FIRMWARE);
}

TEST(renderer_rejected_stream_changes_nothing)
{
    renderer_t *r = timing_renderer();
    REQUIRE(r);
    pp_stream_t s;
    pp_stream_init(&s);
    pp_emit_seti(&s, 0, 16, 0xBEEF);              /* valid ... */
    pp_emit_copy(&s, 200, 0, 16);                 /* ... then past the memory */
    uint64_t before = r->stats.instructions;
    CHECK_EQ(run(r, &s, NULL), PP5_E_FIRMWARE);
    pp_stream_free(&s);
    uint32_t *v = malloc(PP_COUNT * sizeof *v);
    REQUIRE(v);
    renderer_read_field(r, 0, 16, v);
    CHECK_EQ(v[0], 0);
    CHECK_EQ(v[PP_COUNT - 1], 0);
    CHECK_EQ(r->stats.instructions, before);
    free(v);
}

TEST(renderer_init_rejects_bad_parameters)
{
    pp_params_t p;
    pp_params_default(&p);
    p.mem_bits = 100;
    renderer_t r;
    CHECK_EQ(renderer_init(&r, 0, &p), PP5_E_CONFIG);
    CHECK(strstr(pp5_error_text(), "pp.mem_bits") != NULL);
    pp_params_default(&p);
    p.qee_bits_per_cycle = 0;
    CHECK_EQ(renderer_init(&r, 0, &p), PP5_E_CONFIG);
    CHECK(strstr(pp5_error_text(), "pp.qee_bits_per_cycle") != NULL);
}

TEST(renderer_encoder_rejects_values_that_do_not_fit)
{
    pp_stream_t s;
    pp_stream_init(&s);
    pp_emit_add(&s, 300, 0, 0, 8);
    CHECK(!pp_stream_ok(&s));
    CHECK(strstr(pp_stream_error(&s), "ADD") != NULL);
    size_t n = s.n_words;
    pp_emit_en_all(&s);                           /* sticky: nothing more is emitted */
    CHECK_EQ(s.n_words, n);
    pp_stream_clear(&s);
    CHECK(pp_stream_ok(&s));
    pp_emit_seti(&s, 0, 65, 1);                   /* > 64 bits needs the _wide form */
    CHECK(!pp_stream_ok(&s));
    pp_stream_free(&s);
}

TEST(renderer_survives_random_garbage_streams)
{
    /* Valid little programs with random bits flipped, and pure noise: every
     * stream either runs or is rejected with PP5_E_FIRMWARE; never a crash or
     * another status (the sanitizer build checks memory safety too). */
    renderer_t *r = timing_renderer();
    REQUIRE(r);
    uint64_t s = 0x1234567;
    unsigned ok = 0, rejected = 0, other = 0;
    pp_stream_t st;
    pp_stream_init(&st);
    for (int t = 0; t < 3000; t++) {
        s ^= s << 13; s ^= s >> 7; s ^= s << 17;
        unsigned v = (unsigned)(s >> 8);
        pp_stream_clear(&st);
        pp_emit_add(&st, v % 64, (v >> 6) % 64, (v >> 12) % 64, 1 + (v >> 18) % 40);
        pp_emit_qee(&st, v % 100, 1 + (v >> 7) % 64, (v >> 13) % 64, (int32_t)s, 2, -3, 4, 5,
                    (int32_t)(s >> 32));
        pp_emit_cmpi(&st, (v >> 3) % 6, v % 150, 1 + (v >> 9) % 40, s);
        pp_emit_muli(&st, 150, 1 + v % 50, (v >> 6) % 100, 1 + (v >> 12) % 40, v & 1, (int32_t)s);
        pp_emit_bsload(&st, (v >> 4) % 180, (v >> 11) % 128);
        REQUIRE(pp_stream_ok(&st));
        size_t n = st.n_words;
        if (t % 3 == 1) {                         /* flip one bit */
            st.words[(s >> 40) % n] ^= 1u << ((s >> 20) % 32);
        } else if (t % 3 == 2) {                  /* noise, often a legal opcode */
            for (size_t i = 0; i < n; i++) {
                s ^= s << 13; s ^= s >> 7; s ^= s << 17;
                st.words[i] = (uint32_t)s;
                if ((s >> 40) % 2)
                    st.words[i] = (st.words[i] & 0x00ffffffu) | (uint32_t)((s >> 32) % 0x3B) << 24;
            }
        }
        renderer_set_region(r, (int)(s % 3000) - 1000, (int)((s >> 20) % 3000) - 1000);
        pp5_status_t res = renderer_execute(r, st.words, n, NULL);
        ok += res == PP5_OK;
        rejected += res == PP5_E_FIRMWARE;
        other += res != PP5_OK && res != PP5_E_FIRMWARE;
    }
    pp_stream_free(&st);
    CHECK_EQ(other, 0);
    CHECK(ok > 100);
    CHECK(rejected > 100);
}
