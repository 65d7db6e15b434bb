/* timeline.h: Chrome trace-event recorder (opens in Perfetto / chrome://tracing).
 *
 * One track (tid) per unit: every GP, renderer, ring channel, the frame buffer
 * and the host.  Spans are "complete" events (ph "X") with ts/dur in
 * microseconds of EMULATED time (converted from integer ps only when the file
 * is written); instants are ph "i".  Track names are thread_name metadata. */
#ifndef PP5_TIMELINE_H
#define PP5_TIMELINE_H

#include <stddef.h>
#include <stdint.h>
#include "pp5_time.h"
#include "util/status.h"

typedef struct {
    uint32_t tid;
    const char *name;        /* static string */
    pp5_tick_t start, end;   /* end == start: instant */
    uint64_t arg;            /* e.g. bytes; UINT64_MAX = none */
} timeline_event_t;

typedef struct {
    char (*track_names)[32];
    size_t n_tracks, cap_tracks;
    timeline_event_t *ev;
    size_t n_ev, cap_ev;
} timeline_t;

void timeline_init(timeline_t *t);
void timeline_free(timeline_t *t);
/* Adds a track; returns its tid (1-based) or 0 when out of memory. */
uint32_t timeline_track(timeline_t *t, const char *name);
pp5_status_t timeline_span(timeline_t *t, uint32_t tid, const char *name, pp5_tick_t start,
                           pp5_tick_t end, uint64_t arg);
pp5_status_t timeline_write(const timeline_t *t, const char *path);

#endif
