/* bench_render.h: what the renderer benchmarks share (bench_render.c,
 * bench_render_scaling.c, bench_render_formats.c, bench_peers.c and
 * bench_render_common.c). */
#ifndef PP5_BENCH_RENDER_H
#define PP5_BENCH_RENDER_H

#include "render/renderer_native.h"
#include "render/scene.h"

/* The comparisons with VTK and VolPack (render/peers/run_peers.sh). */
int render_peers_run(const char *dataset_path, int size, double ours_full_ms,
                     double ours_gaze_ms, double ours_mip_ms, float window_lo, float window_hi);

/* CThead with the peers' transfer function "ct-skin-ramp" (the
 * Shepp-Logan phantom, noted, when the shared data is absent). */
pp5_status_t bench_render_scene(scene_t *sc);
/* The benchmark's frame: side x side, gaze at the centre, the scene's view. */
void bench_render_settings(const scene_t *sc, int side, render_mode_t mode, render_settings_t *s);

#define BENCH_MAX_REPS 9

/* Median frame time of `reps` frames (reps <= BENCH_MAX_REPS); `last` gets
 * the last frame's counts. */
pp5_status_t bench_render_frames(native_renderer_t *r, const render_settings_t *s, int reps,
                                 double *ms, render_stats_t *last);

/* Median of n values (n <= BENCH_MAX_REPS; 0 when n is 0). */
double bench_median(const double *x, int n);

/* One setting of an alternated measurement: its frame times by round, their
 * median and the last frame's counts. */
typedef struct {
    render_settings_t s;
    double t[BENCH_MAX_REPS], ms;
    int reps;
    render_stats_t stats;
} bench_frames_t;

/* `reps` rounds (at most BENCH_MAX_REPS), each one frame of every setting
 * in turn; fills t, ms, reps and stats of each. */
pp5_status_t bench_render_alternating(native_renderer_t *r, bench_frames_t *set, int n, int reps);

/* Median over the rounds of a's frame time over b's in the same round, with
 * the smallest and largest of those per-round ratios. */
double bench_paired_ratio(const bench_frames_t *a, const bench_frames_t *b, double *lo,
                          double *hi);

/* The fastest of `reps` frames: wall time and the process's CPU time (all
 * threads), the figures least disturbed by other jobs on a shared host. */
pp5_status_t bench_render_frames_min(native_renderer_t *r, const render_settings_t *s, int reps,
                                     double *wall_ms, double *cpu_ms, render_stats_t *last);

/* The process's peak resident set (Linux VmHWM) in MB, and a reset of that
 * peak to the present RSS (/proc/self/clear_refs), so that one build's peak
 * can be read on its own.  -1 / false where the host does not offer them. */
double bench_peak_rss_mb(void);
bool bench_peak_rss_reset(void);

/* One line: the build's peak RSS beside what it holds (volume, mip map,
 * octree), and the mip map's bytes per level-0 voxel over all levels. */
void bench_print_memory(const char *format, const volume_t *v, const native_renderer_t *r,
                        double peak_rss_mb);

/* bench_render_formats.c: the F32 images the reduced formats are compared
 * with (full and gaze-directed at `side`), then U16 and U8: build, peak
 * RSS, frame times, PSNR against F32. */
pp5_status_t bench_format_references(native_renderer_t *r, const scene_t *sc, int side,
                                     image8_t ref[2]);
pp5_status_t bench_formats(const scene_t *sc, int side, int reps, const image8_t ref[2],
                           double f32_full_ms, double f32_gaze_ms);

/* Least-squares slope of log(y) against log(x): the exponent e of y ~ x^e. */
double bench_fit_exponent(const double *x, const double *y, int n);

#endif
