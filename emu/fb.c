/* fb.c: frame buffer node: pixel blocks in, buffer swap, PNG out. */
#include "fb.h"

#include <string.h>

pp5_status_t fb_init(fb_t *fb, unsigned width, unsigned height, bool double_buffered)
{
    memset(fb, 0, sizeof *fb);
    fb->width = width;
    fb->height = height;
    fb->double_buffered = double_buffered;
    int n = double_buffered ? 2 : 1;
    for (int i = 0; i < n; i++) {
        pp5_status_t st = image8_alloc(&fb->buf[i], (int)width, (int)height, 3);
        if (st != PP5_OK) {
            fb_free(fb);
            return st;
        }
    }
    return PP5_OK;
}

void fb_free(fb_t *fb)
{
    image8_free(&fb->buf[0]);
    image8_free(&fb->buf[1]);
    memset(fb, 0, sizeof *fb);
}

static image8_t *fb_back(fb_t *fb)
{
    return &fb->buf[fb->double_buffered ? 1 - fb->front : fb->front];
}

void fb_swap(fb_t *fb)
{
    if (fb->double_buffered) {
        fb->front = 1 - fb->front;
        /* The new back buffer starts as a copy, so partial updates keep the rest. */
        memcpy(fb->buf[1 - fb->front].pixels, fb->buf[fb->front].pixels, (size_t)fb->width * fb->height * 3);
    }
    fb->swaps++;
    fb->blocks_since_swap = 0;
}

void fb_end_frame(fb_t *fb)
{
    if (fb->blocks_since_swap > 0) {
        fb_swap(fb);
    }
}

const image8_t *fb_front(const fb_t *fb)
{
    return &fb->buf[fb->front];
}

pp5_status_t fb_deliver(fb_t *fb, const ring_msg_t *msg, pp5_tick_t now)
{
    if (fb->trace) {
        fb->trace(fb->trace_ctx, msg, now);
    }
    if (msg->kind == RING_MSG_FB_SWAP) {
        fb_swap(fb);
        return PP5_OK;
    }
    if (msg->kind != RING_MSG_FB_PIXELS) {
        return pp5_fail(PP5_E_FIRMWARE, "frame buffer: message kind %u from node %u.%u is not FB_PIXELS or FB_SWAP",
                        msg->kind, msg->src.type, msg->src.index);
    }
    uint64_t x = msg->args[0], y = msg->args[1], w = msg->args[2], h = msg->args[3];
    if (w == 0 || h == 0 || x + w > fb->width || y + h > fb->height) {
        return pp5_fail(PP5_E_FIRMWARE, "frame buffer: block %llux%llu at (%llu,%llu) outside the %ux%u screen",
                        (unsigned long long)w, (unsigned long long)h, (unsigned long long)x,
                        (unsigned long long)y, fb->width, fb->height);
    }
    if (msg->payload_bytes != w * h * 3) {
        return pp5_fail(PP5_E_FIRMWARE, "frame buffer: %llux%llu block carries %zu bytes, expected %llu",
                        (unsigned long long)w, (unsigned long long)h, msg->payload_bytes,
                        (unsigned long long)(w * h * 3));
    }
    image8_t *img = fb_back(fb);
    const uint8_t *src = msg->payload;
    for (uint64_t row = 0; row < h; row++) {
        memcpy(img->pixels + ((y + row) * fb->width + x) * 3, src + row * w * 3, (size_t)(w * 3));
    }
    fb->blocks_received++;
    fb->blocks_since_swap++;
    fb->pixels_received += w * h;
    fb->bytes_received += msg->payload_bytes;
    fb->last_block_ps = now;
    return PP5_OK;
}

pp5_status_t fb_write_png(const fb_t *fb, const char *path)
{
    return png_write(path, fb_front(fb));
}
