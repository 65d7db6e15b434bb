/* host.h: the host-interface node: loads firmware images and data into GPs over the ring.
 *
 * The host is a node on the ring ([I] facts §1, §6: "the data is loaded in
 * each GP in the beginning by the host", S5); its traffic is counted in the
 * HOST class.  Not modelled: the host workstation itself and its own
 * interface bandwidth ([U] facts §6): it injects at ring speed. */
#ifndef PP5_HOST_H
#define PP5_HOST_H

#include <stddef.h>
#include <stdint.h>
#include "pp5_time.h"
#include "ring_msg.h"
#include "util/status.h"

typedef pp5_status_t (*host_send_fn)(void *ctx, const ring_msg_t *msg, pp5_tick_t t);

typedef struct {
    uint64_t loads, bytes_loaded, msgs_received, frame_starts;
    host_send_fn send;
    void *send_ctx;
} host_t;

void host_init(host_t *h, host_send_fn send, void *send_ctx);
/* Send HOST_LOAD to GP `gp`: image_bytes of program image then `data`. */
pp5_status_t host_load_gp(host_t *h, unsigned gp, size_t image_bytes, const void *data, size_t data_bytes,
                          pp5_tick_t t);
/* Send FRAME_START(frame) to GPs 0..n_gp-1 at time t (in GP order). */
pp5_status_t host_start_frame(host_t *h, unsigned n_gp, uint32_t frame, pp5_tick_t t);
pp5_status_t host_deliver(host_t *h, const ring_msg_t *msg, pp5_tick_t now);

#endif
