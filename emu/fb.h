/* fb.h: the 1280x1024 frame buffer node: receives FB_PIXELS blocks over the ring, swaps, writes PNG.
 *
 * Modelled: the screen size (parameters fb.width/height, [C] 1280x1024 facts
 * §4 S1), 24-bit RGB pixels, optional double buffering (fb.double_buffered:
 * blocks land in the back buffer, shown at FB_SWAP or at the end of a frame).
 * Depth and double buffering are [U] (facts §4: not found).
 * Not modelled: scan-out timing and refresh rate ([U]), NTSC/HMD outputs,
 * the FB's ring port bandwidth beyond the ring's own model. */
#ifndef PP5_FB_H
#define PP5_FB_H

#include <stdbool.h>
#include <stdint.h>
#include "pp5_time.h"
#include "ring_msg.h"
#include "util/png_io.h"
#include "util/status.h"

typedef void (*fb_trace_fn)(void *ctx, const ring_msg_t *msg, pp5_tick_t now);

typedef struct {
    unsigned width, height;
    bool double_buffered;
    image8_t buf[2];
    int front;                   /* index of the displayed buffer */
    uint64_t blocks_received, pixels_received, bytes_received, swaps;
    uint64_t blocks_since_swap;
    pp5_tick_t last_block_ps;
    fb_trace_fn trace;
    void *trace_ctx;
} fb_t;

pp5_status_t fb_init(fb_t *fb, unsigned width, unsigned height, bool double_buffered);
void fb_free(fb_t *fb);
/* A ring message for the FB (FB_PIXELS, FB_SWAP); bad blocks are firmware errors. */
pp5_status_t fb_deliver(fb_t *fb, const ring_msg_t *msg, pp5_tick_t now);
void fb_swap(fb_t *fb);
/* End of a frame: with double buffering, show what arrived since the last swap. */
void fb_end_frame(fb_t *fb);
/* The displayed image. */
const image8_t *fb_front(const fb_t *fb);
pp5_status_t fb_write_png(const fb_t *fb, const char *path);

#endif
