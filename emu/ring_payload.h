/* ring_payload.h: the host buffers that carry ring payloads, with room in front for a receiver's header.
 *
 * Host speed only: nothing emulated depends on these buffers.  Every
 * payload buffer the ring holds, and every one a unit hands it or takes
 * from it, comes from ring_payload_alloc and goes back through
 * ring_payload_free.  In front of each lie RING_PAYLOAD_HEADROOM spare
 * bytes, as aligned as malloc's memory, where a receiver that keeps the
 * buffer may put its own header: a GP keeps a delivered unit as a block of
 * its local memory that way instead of copying it (fw_take_payload). */
#ifndef PP5_RING_PAYLOAD_H
#define PP5_RING_PAYLOAD_H

#include <stddef.h>

#define RING_PAYLOAD_HEADROOM 64

/* NULL when the host is out of memory. */
void *ring_payload_alloc(size_t bytes);
/* NULL is ignored. */
void ring_payload_free(void *payload);
/* The host allocation a payload buffer lies in (what free() would take). */
void *ring_payload_host_base(void *payload);

#endif
