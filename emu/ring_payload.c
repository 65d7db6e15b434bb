/* ring_payload.c: payload buffers with headroom (ring_payload.h). */
#include "ring_payload.h"

#include <stdint.h>
#include <stdlib.h>

_Static_assert(RING_PAYLOAD_HEADROOM % _Alignof(max_align_t) == 0,
               "the headroom must keep malloc's alignment");

void *ring_payload_alloc(size_t bytes)
{
    if (bytes > SIZE_MAX - RING_PAYLOAD_HEADROOM)
        return NULL;
    char *base = malloc(RING_PAYLOAD_HEADROOM + bytes);
    return base ? base + RING_PAYLOAD_HEADROOM : NULL;
}

void *ring_payload_host_base(void *payload)
{
    return payload ? (char *)payload - RING_PAYLOAD_HEADROOM : NULL;
}

void ring_payload_free(void *payload)
{
    free(ring_payload_host_base(payload));
}
