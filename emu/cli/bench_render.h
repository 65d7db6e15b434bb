/* bench_render.h: what the renderer benchmarks share (bench_render.c,
 * bench_render_scaling.c, bench_peers.c, bench_memory.c). */
#ifndef PP5_BENCH_RENDER_H
#define PP5_BENCH_RENDER_H

#include "render/renderer_native.h"

/* The comparisons with VTK and VolPack (render/peers/run_peers.sh). */
int render_peers_run(const char *dataset_path, int size, double ours_full_ms,
                     double ours_gaze_ms, double ours_mip_ms, float window_lo, float window_hi);

/* Median frame time of `reps` frames (reps <= 9); `last` gets the last
 * frame's counts. */
pp5_status_t bench_render_frames(native_renderer_t *r, const render_settings_t *s, int reps,
                                 double *ms, render_stats_t *last);

/* The fastest of `reps` frames: wall time and the process's CPU time (all
 * threads), the figures least disturbed by other jobs on a shared host. */
pp5_status_t bench_render_frames_min(native_renderer_t *r, const render_settings_t *s, int reps,
                                     double *wall_ms, double *cpu_ms, render_stats_t *last);

/* The process's peak resident set (Linux VmHWM) in MB, and a reset of that
 * peak to the present RSS (/proc/self/clear_refs), so that one build's peak
 * can be read on its own.  -1 / false where the host does not offer them. */
double bench_peak_rss_mb(void);
bool bench_peak_rss_reset(void);

/* Least-squares slope of log(y) against log(x): the exponent e of y ~ x^e. */
double bench_fit_exponent(const double *x, const double *y, int n);

#endif
