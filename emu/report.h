/* report.h: the JSON run report (--report FILE.json): frame time, unit busy times, ring traffic, parameters.
 *
 * Keys other tools read (stable): frame_time_s (mean over frames),
 * frames_total_s, frames[] (each with its own frame_time_s), gp[].busy_s,
 * renderers[].busy_s, renderers[].cycles, ring.bytes (total, by_class,
 * by_channel), ring.utilization (aggregate, by_channel), machine (every
 * parameter), pp5_version, command_line, inputs[] (name + FNV-1a 64 hash).
 * "counters" holds every named statistic of stats.c. */
#ifndef PP5_REPORT_H
#define PP5_REPORT_H

#include <stddef.h>
#include "machine.h"

typedef struct {
    const char *name;        /* e.g. a path or "config" */
    uint64_t fnv1a64;
    uint64_t bytes;
} report_input_t;

#define REPORT_MAX_INPUTS 8

typedef struct {
    int argc;
    char **argv;
    const char *workload;    /* e.g. "test-pattern" */
    report_input_t inputs[REPORT_MAX_INPUTS];
    int n_inputs;
} report_meta_t;

/* Hash a file into meta->inputs (PP5_E_IO if unreadable). */
pp5_status_t report_add_input_file(report_meta_t *meta, const char *path);
uint64_t report_fnv1a64(const void *data, size_t n, uint64_t h);
pp5_status_t report_write(const machine_t *m, const report_meta_t *meta, const char *path);

#endif
