/* renderer.c: one renderer: validates and executes PP instruction streams on its
 * array and charges renderer-clock cycles (timing rules in renderer.h). */
#include "renderer.h"

#include <stdlib.h>
#include <string.h>

#include "backing.h"
#include "pp_array.h"
#include "qee.h"

pp5_status_t renderer_init(renderer_t *r, int index, const pp_params_t *pp)
{
    memset(r, 0, sizeof *r);
    pp5_status_t st = pp_params_check(pp);
    if (st != PP5_OK)
        return st;
    r->index = index;
    r->pp = *pp;
    if ((st = pp_array_alloc(&r->array)) != PP5_OK)
        return st;
    r->bs_words = calloc(PP_BS_BLOCKS, sizeof *r->bs_words);
    if (!r->bs_words)
        st = pp5_fail(PP5_E_NOMEM, "renderer %d: out of memory", index);
    else
        st = backing_alloc(&r->bs);
    if (st != PP5_OK) {
        pp_array_free(r->array);
        free(r->bs_words);
        r->array = NULL;
        r->bs_words = NULL;
    }
    return st;
}

/* The held words of `block` are no longer the backing store's. */
static void bs_words_drop(const renderer_t *r, unsigned block)
{
    free(r->bs_words[block]);
    r->bs_words[block] = NULL;
}

void renderer_free(renderer_t *r)
{
    for (unsigned b = 0; r->bs_words && b < PP_BS_BLOCKS; b++)
        bs_words_drop(r, b);
    free(r->bs_words);
    pp_array_free(r->array);
    backing_free(r->bs);
    free(r->decoded);
    r->array = NULL;
    r->bs = NULL;
    r->bs_words = NULL;
    r->decoded = NULL;
    r->decoded_cap = 0;
}

void renderer_reset(renderer_t *r)
{
    pp_array_clear(r->array);
    backing_clear(r->bs);
    for (unsigned b = 0; b < PP_BS_BLOCKS; b++)
        bs_words_drop(r, b);
    r->x0 = r->y0 = 0;
    memset(&r->stats, 0, sizeof r->stats);
}

void renderer_set_region(renderer_t *r, int x0, int y0)
{
    r->x0 = x0;
    r->y0 = y0;
}

/* Room for one more decoded instruction after `count`. */
static pp5_status_t decoded_room(renderer_t *r, size_t count)
{
    if (count < r->decoded_cap)
        return PP5_OK;
    size_t cap = r->decoded_cap ? 2 * r->decoded_cap : 64;
    pp_insn_t *grown = realloc(r->decoded, cap * sizeof *grown);
    if (!grown)
        return pp5_fail(PP5_E_NOMEM, "renderer %d: no memory for a %zu-instruction stream",
                        r->index, count + 1);
    r->decoded = grown;
    r->decoded_cap = cap;
    return PP5_OK;
}

/* Pass 1: the whole stream must decode and validate before anything runs;
 * its instructions are kept in r->decoded (*count of them). */
static pp5_status_t validate_stream(renderer_t *r, const uint32_t *words, size_t n_words,
                                    size_t *count)
{
    size_t pos = 0;
    *count = 0;
    while (pos < n_words) {
        size_t at = pos;
        pp5_status_t st = decoded_room(r, *count);
        if (st != PP5_OK)
            return st;
        pp_insn_t *in = &r->decoded[*count];
        if ((st = pp_isa_decode(words, n_words, &pos, r->pp.mem_bits, in)) != PP5_OK)
            return st;
        if (in->op == PP_OP_QEE && !qee_origin_ok(r->x0, r->y0))
            return pp5_fail(PP5_E_FIRMWARE, "PP stream word %zu: QEE with region origin (%d, %d) "
                            "outside +-%d (the QEE's exact range)", at, r->x0, r->y0,
                            PP_REGION_COORD_MAX);
        (*count)++;
    }
    return PP5_OK;
}

static uint64_t max64(uint64_t a, uint64_t b)
{
    return a > b ? a : b;
}

/* When may `in` start, given transfers in flight (the interlock in renderer.h)? */
static uint64_t ready_time(const renderer_t *r, const bs_channel_t *ch, const pp_insn_t *in,
                           uint64_t now)
{
    const pp_op_info_t *op = pp_isa_info(in->op);
    uint64_t t = now;
    if (ch->count == 0)
        return t;
    t = max64(t, bs_channel_field_ready(ch, now, in->d, pp_isa_field_bits(in, op->d_width)));
    t = max64(t, bs_channel_field_ready(ch, now, in->a, pp_isa_field_bits(in, op->a_width)));
    t = max64(t, bs_channel_field_ready(ch, now, in->b, pp_isa_field_bits(in, op->b_width)));
    if (in->op == PP_OP_BSLOAD || in->op == PP_OP_BSSTORE) {
        t = max64(t, bs_channel_block_ready(ch, now, in->x));
        t = max64(t, bs_channel_slot_ready(ch, t, r->pp.bs_queue_depth));
    }
    if (in->op == PP_OP_BSWAIT)
        t = max64(t, ch->free_at);
    return t;
}

pp5_status_t renderer_execute(renderer_t *r, const uint32_t *words, size_t n_words,
                              renderer_exec_result_t *res)
{
    renderer_exec_result_t out;
    memset(&out, 0, sizeof out);
    if (!r->array || !r->bs)
        return pp5_fail(PP5_E_RANGE, "renderer %d was not initialised", r->index);
    size_t count;
    pp5_status_t st = validate_stream(r, words, n_words, &count);
    if (st != PP5_OK) {
        if (res)
            *res = out;
        return st;
    }
    bs_channel_t ch;
    bs_channel_reset(&ch);
    uint64_t now = 0;
    /* The cycles of an instruction never depend on PP data: the stream is
     * timed first, then executed in batches (pp_array_exec_batch). */
    for (size_t i = 0; i < count; i++) {
        const pp_insn_t *in = &r->decoded[i];
        const pp_op_info_t *op = pp_isa_info(in->op);
        uint64_t start = ready_time(r, &ch, in, now);
        out.stall_cycles += start - now;
        uint64_t cyc = pp_isa_cycles(in, &r->pp);
        now = start + cyc;
        if (in->op == PP_OP_BSLOAD || in->op == PP_OP_BSSTORE) {
            unsigned lo = in->op == PP_OP_BSLOAD ? in->d : in->a;
            bs_channel_issue(&ch, now, in->x, lo, PP_BS_BLOCK_BITS, r->pp.bs_block_cycles);
            r->stats.bs_blocks++;
        }
        bs_channel_retire(&ch, now);
        if (in->op == PP_OP_BSSTORE)
            bs_words_drop(r, in->x);
        out.instructions++;
        out.class_cycles[op->cls] += cyc;
        out.class_instructions[op->cls]++;
        r->stats.op_instructions[in->op]++;
        r->stats.op_cycles[in->op] += cyc;
    }
    pp_array_exec_batch(r->array, r->bs, r->decoded, count, r->x0, r->y0);
    out.compute_cycles = now;
    out.bs_cycles = ch.busy_cycles;
    out.total_cycles = max64(now, ch.free_at);

    renderer_stats_t *s = &r->stats;
    s->streams++;
    s->instructions += out.instructions;
    s->compute_cycles += out.compute_cycles;
    s->bs_cycles += out.bs_cycles;
    s->stall_cycles += out.stall_cycles;
    s->total_cycles += out.total_cycles;
    for (int c = 0; c < PP_CLASS_COUNT; c++) {
        s->class_cycles[c] += out.class_cycles[c];
        s->class_instructions[c] += out.class_instructions[c];
    }
    if (res)
        *res = out;
    return PP5_OK;
}

static pp5_status_t check_field_args(const renderer_t *r, unsigned addr, unsigned bits,
                                     const char *what)
{
    if (bits < 1 || bits > 32 || addr + bits > r->pp.mem_bits)
        return pp5_fail(PP5_E_FIRMWARE, "renderer %d: %s of field [%u, %u): need 1..32 bits "
                        "inside the %u-bit pixel memory", r->index, what, addr, addr + bits,
                        r->pp.mem_bits);
    return PP5_OK;
}

pp5_status_t renderer_read_field(const renderer_t *r, unsigned addr, unsigned bits, uint32_t *out)
{
    pp5_status_t st = check_field_args(r, addr, bits, "read");
    if (st == PP5_OK)
        pp_array_read_field(r->array, addr, bits, out);
    return st;
}

pp5_status_t renderer_write_field(renderer_t *r, unsigned addr, unsigned bits, const uint32_t *in)
{
    pp5_status_t st = check_field_args(r, addr, bits, "write");
    if (st == PP5_OK)
        pp_array_write_field(r->array, addr, bits, in);
    return st;
}

pp5_status_t renderer_bs_read(const renderer_t *r, unsigned block, uint32_t *out)
{
    if (block >= PP_BS_BLOCKS)
        return pp5_fail(PP5_E_FIRMWARE, "renderer %d: backing-store block %u (blocks are 0..%u)",
                        r->index, block, PP_BS_BLOCKS - 1);
    uint32_t *held = r->bs_words[block];
    if (held) {
        memcpy(out, held, sizeof *held * PP_COUNT);
        return PP5_OK;
    }
    backing_read_block(r->bs, block, out);
    /* keep a copy for the next read; without memory, just do not keep it */
    if ((held = malloc(sizeof *held * PP_COUNT)) != NULL) {
        memcpy(held, out, sizeof *held * PP_COUNT);
        r->bs_words[block] = held;
    }
    return PP5_OK;
}

pp5_status_t renderer_bs_write(renderer_t *r, unsigned block, const uint32_t *in)
{
    if (block >= PP_BS_BLOCKS)
        return pp5_fail(PP5_E_FIRMWARE, "renderer %d: backing-store block %u (blocks are 0..%u)",
                        r->index, block, PP_BS_BLOCKS - 1);
    bs_words_drop(r, block);
    backing_write_block(r->bs, block, in);
    return PP5_OK;
}
