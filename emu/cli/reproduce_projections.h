/* reproduce_projections.h: what the files of `pp5 reproduce projections` share: the workloads, one row of the table, and the study's runs. */
#ifndef PP5_REPRODUCE_PROJECTIONS_H
#define PP5_REPRODUCE_PROJECTIONS_H

#include <pthread.h>
#include <stdbool.h>
#include "firmware/host/fw_session.h"
#include "progress.h"

typedef struct {
    char tag;                         /* 'A' (Table I) or 'B' (the 10 frames/s claim) */
    char label[200];
    volume_t volume;
    classify_tf_t tf;
    float rot[3];
} proj_workload_t;

/* One machine configuration's frames: cold (nothing cached), steady (the
 * view held, the gaze moving), progressive refinement to full resolution. */
typedef struct {
    fw_frame_result_t cold, steady;
    double steady_s, steady_ring_bytes, steady_gp_mean, steady_gp_max;
    double prog_s;
    int prog_frames;                  /* -1: not reached or not available */
} proj_row_t;

typedef struct {
    bool have;
    fw_division_t division;
    proj_row_t row;
} proj_best_t;

typedef struct {
    const char *name, *value;
} proj_set_t;

/* A (Table I: the MR subject at 256x256x109) and B (128x128x109); with
 * quick, only a small phantom as B (for the tests). */
pp5_status_t proj_load_workloads(proj_workload_t *w, int *n, bool quick);
void proj_workload_free(proj_workload_t *w);
/* The paper's machine (16 GPs, 16 renderers) under a preset, with sets. */
pp5_status_t proj_machine(const char *preset, const proj_set_t *sets, int n_sets, pp5_params_t *p);
/* lighting 0 diffuse, 1 specular; image size x size. */
pp5_status_t proj_run(const proj_workload_t *w, int lighting, fw_division_t division,
                      const pp5_params_t *p, int size, proj_row_t *out);

/* The progress line of runs that finish on several host threads. */
typedef struct {
    progress_t pr;
    pthread_mutex_t lock;
} proj_runs_t;
void proj_runs_begin(proj_runs_t *r, const char *label, int total);
void proj_runs_step(proj_runs_t *r, const char *what);   /* from any thread */
void proj_runs_end(proj_runs_t *r);

/* The sensitivity block: every ranged [U]/[I] parameter to its plausible low
 * and high, the steady frame of the division on workload w (specular); the
 * runs on `threads` host threads. */
int proj_sensitivity(const proj_workload_t *w, fw_division_t division, int size, bool quick,
                     int threads);

#endif
