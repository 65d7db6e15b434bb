/* stats.h: named statistics counters of a machine run (STYLE L6), collected after a frame.
 *
 * Every figure pp5 reports is one named entry ("ring.ch3.busy_ps",
 * "gp2.busy_cycles", ...) with its unit and a one-line meaning, collected
 * from the units' own counters; derived figures (utilisation) say their
 * formula.  report.c writes them into the JSON report under "counters". */
#ifndef PP5_STATS_H
#define PP5_STATS_H

#include <stddef.h>
#include "machine.h"

typedef struct {
    char name[48];
    double value;
    const char *unit;
    const char *meaning;
} stats_entry_t;

typedef struct {
    stats_entry_t *e;
    size_t n, cap;
} stats_t;

pp5_status_t stats_collect(stats_t *s, const machine_t *m);
void stats_free(stats_t *s);
const stats_entry_t *stats_find(const stats_t *s, const char *name);

/* Shared derived figures. */
double stats_frame_time_s(const machine_t *m);        /* mean frame time over the frames run */
double stats_frames_total_s(const machine_t *m);      /* sum of all frame times */
/* Ring utilisation over the frames (load phase excluded): busy time of all
 * channels inside frames / (channels x total frame time); per channel: that
 * channel's busy time inside frames / total frame time. */
double stats_ring_utilization(const machine_t *m);
double stats_ring_channel_utilization(const machine_t *m, unsigned channel);
/* Share of the ring's capacity (channels x frame time) used by one class. */
double stats_ring_class_utilization(const machine_t *m, unsigned cls);
const char *stats_class_name(unsigned cls);

#endif
