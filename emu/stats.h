/* stats.h: the named statistics of a machine run (STYLE L6): every figure pp5 reports, collected from the units' own counters and the programs' published statistics.
 *
 * An entry has a dotted name ("ring.by_channel.3.busy_s", "gp.2.prog.rays"),
 * a value, a unit, a one-line meaning and a kind:
 *   counter  accumulates over the run (cycles, bytes, messages, busy time);
 *   value    a current or last figure (a program's "time its cast ended");
 *   formula  derived from other entries, with the formula in its meaning
 *            (utilisation).
 * A collection is a snapshot.  Per-frame figures are differences of two
 * snapshots (stats_diff: counters subtract, values are taken from the later
 * one, formulas are dropped because they describe the whole run).  The run
 * report (report.c) is written from a collection only, nested by the dots of
 * the names (stats_write_json). */
#ifndef PP5_STATS_H
#define PP5_STATS_H

#include <stddef.h>
#include "machine.h"
#include "util/json.h"

typedef enum { STATS_COUNTER, STATS_VALUE, STATS_FORMULA } stats_kind_t;

typedef struct {
    char name[64];
    double value;
    stats_kind_t kind;
    const char *unit;
    const char *meaning;
} stats_entry_t;

typedef struct {
    stats_entry_t *e;
    size_t n, cap;
    uint32_t *slot;           /* open-addressing index by name (1 + entry), size slot_cap */
    size_t slot_cap;
} stats_t;

/* Snapshot of every statistic of the machine now. */
pp5_status_t stats_collect(stats_t *s, const machine_t *m);
void stats_free(stats_t *s);
const stats_entry_t *stats_find(const stats_t *s, const char *name);
/* Value of NAME, or 0 when the collection has no such entry. */
double stats_value(const stats_t *s, const char *name);
/* Printf-style name, for per-unit entries ("gp.%u.busy_s"). */
double stats_valuef(const stats_t *s, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* out = after - before (see above).  An entry only in `after` counts from 0. */
pp5_status_t stats_diff(stats_t *out, const stats_t *before, const stats_t *after);
/* The entries as nested JSON objects (numeric components become arrays),
 * then a flat "descriptions" object: name -> "unit; kind; meaning". */
void stats_write_json(const stats_t *s, json_writer_t *j);

/* Derived figures over the frames run so far (the load phase excluded). */
double stats_frame_time_s(const machine_t *m);        /* mean frame time over the frames run */
double stats_frames_total_s(const machine_t *m);      /* sum of all frame times */
/* Ring utilisation over the frames: busy time of all channels inside frames /
 * (channels x total frame time); per channel: that channel's busy time inside
 * frames / total frame time; per class: the class's share of the capacity. */
double stats_ring_utilization(const machine_t *m);
double stats_ring_channel_utilization(const machine_t *m, unsigned channel);
double stats_ring_class_utilization(const machine_t *m, unsigned cls);
const char *stats_class_name(unsigned cls);

#endif
