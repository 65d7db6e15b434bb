/* backing.h: the renderer's backing store (4096 bits of VRAM per PP, moved in
 * 32-bit blocks) and the timing of its single asynchronous transfer channel.
 *
 * Storage is bit-sliced like the PP array (pp_array.h): bit k of block b of all
 * 16384 PPs is one plane, so a block transfer is 32 plane copies.
 *
 * Timing model ([U]: facts §3.1 S4 says only "accessed in 32-bit blocks ...
 * significantly slower ... asynchronous and can overlap other operations";
 * open question 4): one channel, transfers in issue order, each busy for
 * pp.bs_block_cycles; at most pp.bs_queue_depth in flight.  The channel answers
 * "when may an instruction touching field [lo, lo+len) / block b start?".
 * Not modelled: VRAM refresh, page modes, the serial port of the VRAM. */
#ifndef PP5_BACKING_H
#define PP5_BACKING_H

#include <stdint.h>
#include "pp_params.h"
#include "util/status.h"

typedef struct backing {
    uint64_t plane[PP_BS_BITS][PP_PLANE_WORDS];
} backing_t;

pp5_status_t backing_alloc(backing_t **out);
void backing_free(backing_t *b);
void backing_clear(backing_t *b);
/* Plane of bit `bit` (0..31) of block `block`. */
static inline uint64_t *backing_plane(backing_t *b, unsigned block, unsigned bit)
{
    return b->plane[block * PP_BS_BLOCK_BITS + bit];
}
/* One uint32 per PP, row-major (block < PP_BS_BLOCKS, checked by the caller). */
void backing_read_block(const backing_t *b, unsigned block, uint32_t *out);
void backing_write_block(backing_t *b, unsigned block, const uint32_t *in);

#define BS_CHANNEL_MAX 64
typedef struct {
    uint64_t done_at;      /* renderer cycle at which the transfer is complete */
    unsigned block;
    unsigned lo, len;      /* pixel-memory field it reads or writes */
} bs_transfer_t;

typedef struct {
    bs_transfer_t q[BS_CHANNEL_MAX];  /* in flight, oldest first (done_at ascending) */
    unsigned count;
    uint64_t free_at;                 /* when the channel finishes its last transfer */
    uint64_t busy_cycles;             /* sum of transfer times issued */
} bs_channel_t;

void bs_channel_reset(bs_channel_t *ch);
/* Earliest time >= now at which nothing in flight touches [lo, lo+len). */
uint64_t bs_channel_field_ready(const bs_channel_t *ch, uint64_t now, unsigned lo, unsigned len);
/* Earliest time >= now at which no transfer of `block` is in flight. */
uint64_t bs_channel_block_ready(const bs_channel_t *ch, uint64_t now, unsigned block);
/* Earliest time >= now at which fewer than `depth` transfers are in flight. */
uint64_t bs_channel_slot_ready(const bs_channel_t *ch, uint64_t now, unsigned depth);
/* Queues a transfer issued at `now`; returns its completion time.  The caller
 * has waited for a slot (bs_channel_slot_ready), so the queue has room. */
uint64_t bs_channel_issue(bs_channel_t *ch, uint64_t now, unsigned block, unsigned lo,
                          unsigned len, uint64_t busy_cycles);
/* Forgets transfers complete by `now`. */
void bs_channel_retire(bs_channel_t *ch, uint64_t now);

#endif
