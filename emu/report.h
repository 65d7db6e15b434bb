/* report.h: the JSON run report (--report FILE.json): who ran what, every machine parameter, and every named statistic.
 *
 * Written from the statistics registry only (stats.h), so a figure in a
 * report is always the same figure pp5 prints or tests.  Keys:
 * pp5_version, workload, command_line, inputs[] (name + FNV-1a 64 hash),
 * frame_stops[], gp_programs[], machine (every parameter), statistics (the
 * named statistics nested by the dots of their names: statistics.sim.
 * frame_time_s, statistics.frame[i].frame_time_s, statistics.gp[g].busy_s,
 * statistics.gp[g].prog.* (what the GP program published),
 * statistics.renderer[r].pp.cycles_by_class, statistics.ring.by_class.data.
 * bytes_sent, statistics.ring.by_channel[c].utilization, ...) and
 * descriptions (each statistic's unit, kind and meaning). */
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
