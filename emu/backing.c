/* backing.c: backing-store storage (bit-sliced blocks) and its transfer channel timing. */
#include "backing.h"

#include "bit_transpose.h"

#include <stdlib.h>
#include <string.h>

pp5_status_t backing_alloc(backing_t **out)
{
    /* C11 aligned_alloc wants a size that is a multiple of the alignment. */
    backing_t *b = aligned_alloc(64, (sizeof *b + 63) & ~(size_t)63);
    if (!b)
        return pp5_fail(PP5_E_NOMEM, "cannot allocate a %zu-byte backing store", sizeof *b);
    backing_clear(b);
    *out = b;
    return PP5_OK;
}

void backing_free(backing_t *b)
{
    free(b);
}

void backing_clear(backing_t *b)
{
    memset(b, 0, sizeof *b);
}

/* First word of plane 0 of `block`: the block's 32 planes follow PP_PLANE_WORDS apart. */
static uint64_t *block_planes(const backing_t *b, unsigned block)
{
    return (uint64_t *)&b->plane[block * PP_BS_BLOCK_BITS][0];
}

void backing_read_block(const backing_t *b, unsigned block, uint32_t *out)
{
    bit_transpose_planes_to_words(block_planes(b, block), PP_PLANE_WORDS, PP_BS_BLOCK_BITS, out);
}

void backing_write_block(backing_t *b, unsigned block, const uint32_t *in)
{
    bit_transpose_words_to_planes(in, PP_BS_BLOCK_BITS, block_planes(b, block), PP_PLANE_WORDS);
}

void bs_channel_reset(bs_channel_t *ch)
{
    memset(ch, 0, sizeof *ch);
}

static uint64_t max64(uint64_t a, uint64_t b)
{
    return a > b ? a : b;
}

uint64_t bs_channel_field_ready(const bs_channel_t *ch, uint64_t now, unsigned lo, unsigned len)
{
    uint64_t t = now;
    for (unsigned i = 0; i < ch->count; i++) {
        const bs_transfer_t *x = &ch->q[i];
        if (len && lo < x->lo + x->len && x->lo < lo + len)
            t = max64(t, x->done_at);
    }
    return t;
}

uint64_t bs_channel_block_ready(const bs_channel_t *ch, uint64_t now, unsigned block)
{
    uint64_t t = now;
    for (unsigned i = 0; i < ch->count; i++) {
        if (ch->q[i].block == block)
            t = max64(t, ch->q[i].done_at);
    }
    return t;
}

uint64_t bs_channel_slot_ready(const bs_channel_t *ch, uint64_t now, unsigned depth)
{
    /* Transfers complete in order: with `count` in flight, the slot frees when
     * transfer count - depth (0-based) completes. */
    unsigned in_flight = 0;
    for (unsigned i = 0; i < ch->count; i++)
        in_flight += ch->q[i].done_at > now;
    if (in_flight < depth)
        return now;
    unsigned first = ch->count - in_flight;   /* oldest still in flight */
    return max64(now, ch->q[first + in_flight - depth].done_at);
}

void bs_channel_retire(bs_channel_t *ch, uint64_t now)
{
    unsigned keep = 0;
    for (unsigned i = 0; i < ch->count; i++) {
        if (ch->q[i].done_at > now)
            ch->q[keep++] = ch->q[i];
    }
    ch->count = keep;
}

uint64_t bs_channel_issue(bs_channel_t *ch, uint64_t now, unsigned block, unsigned lo,
                          unsigned len, uint64_t busy_cycles)
{
    bs_channel_retire(ch, now);
    uint64_t start = max64(now, ch->free_at);
    uint64_t done = start + busy_cycles;
    ch->free_at = done;
    ch->busy_cycles += busy_cycles;
    if (ch->count < BS_CHANNEL_MAX)
        ch->q[ch->count++] = (bs_transfer_t){done, block, lo, len};
    return done;
}
