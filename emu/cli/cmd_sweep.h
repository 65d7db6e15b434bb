/* cmd_sweep.h: what `pp5 sweep`'s files share: the grid (cmd_sweep.c) and
 * its points as work units (cmd_sweep_units.c). */
#ifndef PP5_CMD_SWEEP_H
#define PP5_CMD_SWEEP_H

#include <stdio.h>

#include "firmware/host/fw_session.h"
#include "render/render_job.h"
#include "workunit.h"

#define SWEEP_MAX_KEYS 4
#define SWEEP_MAX_VALUES 32
#define SWEEP_MAX_POINTS 256

typedef struct {
    char key[64];
    char values[SWEEP_MAX_VALUES][32];
    int n;
} sweep_axis_t;

typedef struct {
    sweep_axis_t axes[SWEEP_MAX_KEYS];
    int n_axes, points;
    const char *out_csv, *out_png, *phantom, *dataset, *preset;
    int w, h;
    render_mode_t mode;
    shade_case_t lighting;
    /* Running the grid as work units (cmd_sweep_units.c). */
    const char *report, *accounting;
    bool resume;
    unsigned shard_k, shard_n;
} sweep_t;

/* cmd_sweep.c */
pp5_status_t sweep_point_config(const sweep_t *sw, int pt, int *idx, pp5_params_t *p,
                                fw_options_t *o, char *label, size_t label_cap);
void sweep_csv_header(FILE *csv, const sweep_t *sw);
void sweep_csv_row(FILE *csv, const sweep_t *sw, const int *idx, pp5_status_t rst,
                   const fw_frame_result_t *r);
pp5_status_t sweep_run_point(const sweep_t *sw, const render_job_t *job, const pp5_params_t *p,
                             const fw_options_t *o, fw_frame_result_t *r);
pp5_status_t sweep_write_plot(const sweep_t *sw, double *xs, double *ph, char (*labels)[64]);

/* cmd_sweep_units.c: the grid as work units, run here, over MPI ranks or as
 * a shard; on rank 0 the CSV, the JSON report, the terminal lines and the
 * plot, in grid order.  Returns the command's exit code. */
int sweep_run_units(const sweep_t *sw, const render_job_t *job);

#endif
