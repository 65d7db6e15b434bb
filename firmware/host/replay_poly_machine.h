/* replay_poly_machine.h: what the "polygons" frame-cost source of `pp5
 * replay` (replay_poly_machine.c) gave the machine in its latest frame, for
 * callers that hold its context (the tests; the replay itself reads only the
 * replay_frame_cost_t and the source's summary). */
#ifndef PP5_REPLAY_POLY_MACHINE_H
#define PP5_REPLAY_POLY_MACHINE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "status.h"

typedef struct {
    size_t frames;               /* frames emulated so far */
    size_t triangles;            /* the list the latest frame drew */
    long triangles_full;         /* the scene at full detail */
    bool list_changed;           /* a new list went to the GPs before the latest frame */
    uint64_t upload_ring_bytes;  /* its wire bytes (0 without a change) */
    double frame_s;              /* the latest frame's emulated time, the upload included */
} replay_poly_frame_info_t;

/* ctx: a context the "polygons" source's open returned.  PP5_E_CONFIG
 * before the first frame. */
pp5_status_t replay_poly_last_frame(const void *ctx, replay_poly_frame_info_t *out);

#endif
