/* host.c: host-interface node: HOST_LOAD messages to GPs. */
#include "host.h"

#include <stdlib.h>
#include <string.h>

void host_init(host_t *h, host_send_fn send, void *send_ctx)
{
    memset(h, 0, sizeof *h);
    h->send = send;
    h->send_ctx = send_ctx;
}

pp5_status_t host_load_gp(host_t *h, unsigned gp, size_t image_bytes, const void *data, size_t data_bytes,
                          pp5_tick_t t)
{
    size_t total = image_bytes + data_bytes;
    if (total < image_bytes || image_bytes > UINT32_MAX) {
        return pp5_fail(PP5_E_RANGE, "host: load of %zu + %zu bytes is too large", image_bytes, data_bytes);
    }
    /* The image stands in for i860 code (fw_program_t.image_bytes): zeros. */
    uint8_t *buf = calloc(1, total ? total : 1);
    if (!buf) {
        return pp5_fail(PP5_E_NOMEM, "host: out of memory building a %zu-byte load", total);
    }
    if (data_bytes) {
        memcpy(buf + image_bytes, data, data_bytes);
    }
    const uint32_t args[RING_MSG_ARGS] = {(uint32_t)image_bytes};
    ring_msg_t m = ring_msg_make(ring_addr(RING_NODE_HOST, 0), ring_addr(RING_NODE_GP, gp),
                                 RING_MSG_HOST_LOAD, RING_CLASS_HOST, args, buf, total);
    pp5_status_t st = h->send(h->send_ctx, &m, t);
    free(buf);
    if (st == PP5_OK) {
        h->loads++;
        h->bytes_loaded += total;
    }
    return st;
}

pp5_status_t host_start_frame(host_t *h, unsigned n_gp, uint32_t frame, pp5_tick_t t)
{
    for (unsigned g = 0; g < n_gp; g++) {
        const uint32_t args[RING_MSG_ARGS] = {frame};
        ring_msg_t m = ring_msg_make(ring_addr(RING_NODE_HOST, 0), ring_addr(RING_NODE_GP, g),
                                     RING_MSG_FRAME_START, RING_CLASS_HOST, args, NULL, 0);
        pp5_status_t st = h->send(h->send_ctx, &m, t);
        if (st != PP5_OK) {
            return st;
        }
        h->frame_starts++;
    }
    return PP5_OK;
}

pp5_status_t host_deliver(host_t *h, const ring_msg_t *msg, pp5_tick_t now)
{
    h->msgs_received++;   /* results for the host are counted, not interpreted */
    return PP5_OK;
}
