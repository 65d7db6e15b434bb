/* bench_render_scaling.c: `pp5 bench render_scaling` (also run by `pp5 bench
 * render`, a prefix): the gaze paper's scaling claim, measured.
 *
 * Seed 004 §5 "Rendering efficiency": "Rendering cost per unit area on the
 * image plane is therefore linearly related to the density of rays and
 * samples and independent of the data resolution."  Two axes:
 * - data resolution: CThead resampled to N^3 (N = 64 .. 512, the object's
 *   shape kept), gaze-directed frames at 512x512 and 1024x1024 with the
 *   same ray density (the image) and the same sample density along a ray
 *   in object space (sample step N/256 voxels, so every N takes as many
 *   samples per unit of the object as the 256^3 volume at one per voxel);
 * - image size: the volume as loaded, gaze-directed frames from 256x256 to
 *   2048x2048 (the display geometry is the paper's, so the periphery's
 *   share of the image stays the same and the ray count grows with area).
 * Each axis gets a fitted exponent (least squares in log-log); the claim
 * is 0 for the data resolution and 1 for the image area.  The peak RSS of
 * each volume's build is printed beside it; the plot goes to
 * build/bench/render_scaling.png. */
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "bench_render.h"
#include "plot.h"
#include "registry.h"
#include "render/scene.h"

#define MAX_POINTS 8
#define PLOT_PATH "build/bench/render_scaling.png"

typedef struct {
    int n_vol, n_img;
    int vol[MAX_POINTS], img[MAX_POINTS];
    double vol_ms[2][MAX_POINTS], vol_cpu[2][MAX_POINTS], vol_rss[MAX_POINTS];
    double img_ms[MAX_POINTS], img_cpu[MAX_POINTS];
    uint64_t vol_samples[2][MAX_POINTS], img_rays[MAX_POINTS];
} scaling_t;

static void gaze_settings(const scene_t *sc, int side, float step, render_settings_t *s)
{
    bench_render_settings(sc, side, RENDER_MODE_GAZE, s);
    s->view.sample_step = step;
    s->view.opacity_unit = step;  /* as opaque per unit of the object as at 256^3 */
}

/* One resolution N: resample, build (its peak RSS on its own), two frames. */
static pp5_status_t volume_point(const scene_t *sc, int n, int reps, scaling_t *out, int k,
                                 const int sides[2])
{
    volume_t v;
    bool reset = bench_peak_rss_reset();
    pp5_status_t st = volume_resample(&sc->volume, n, n, n, &v);
    if (st != PP5_OK)
        return st;
    shade_params_t sh;
    shade_defaults(&sh);
    native_renderer_t r;
    st = native_renderer_init(&r, &v, &sc->tf, &sh, 0);
    if (st != PP5_OK) {
        volume_free(&v);
        return st;
    }
    out->vol_rss[k] = reset ? bench_peak_rss_mb() : -1.0;
    for (int i = 0; st == PP5_OK && i < 2; i++) {
        render_settings_t s;
        gaze_settings(sc, sides[i], (float)n / 256.0f, &s);
        render_stats_t stats;
        st = bench_render_frames_min(&r, &s, reps, &out->vol_ms[i][k], &out->vol_cpu[i][k],
                                     &stats);
        out->vol_samples[i][k] = stats.samples;
    }
    native_renderer_free(&r);
    volume_free(&v);
    out->vol[k] = n;
    return st;
}

static pp5_status_t image_points(const scene_t *sc, int reps, scaling_t *out)
{
    shade_params_t sh;
    shade_defaults(&sh);
    native_renderer_t r;
    pp5_status_t st = native_renderer_init(&r, &sc->volume, &sc->tf, &sh, 0);
    if (st != PP5_OK)
        return st;
    for (int k = 0; st == PP5_OK && k < out->n_img; k++) {
        render_settings_t s;
        gaze_settings(sc, out->img[k], 1.0f, &s);
        render_stats_t stats;
        st = bench_render_frames_min(&r, &s, reps, &out->img_ms[k], &out->img_cpu[k], &stats);
        out->img_rays[k] = stats.rays;
    }
    native_renderer_free(&r);
    return st;
}

/* The chart, through the plot module in one place: frame time against the
 * axis value (log2 of the side), both axes' series. */
static pp5_status_t scaling_plot(const scaling_t *sc, const int sides[2], const char *path)
{
    plot_t p;
    plot_init(&p, "Gaze-directed frame time (seed 004 s5 scaling)", "log2(side): volume N or image",
              "CPU ms per frame (all threads, fastest run)");
    plot_set_log_y(&p, true);
    double x[MAX_POINTS], y[MAX_POINTS];
    char names[2][48];
    for (int i = 0; i < 2; i++)
        snprintf(names[i], sizeof names[i], "volume N^3, %dx%d image", sides[i], sides[i]);
    pp5_status_t st = PP5_OK;
    for (int i = 0; st == PP5_OK && i < 2; i++) {
        for (int k = 0; k < sc->n_vol; k++) {
            x[k] = log2((double)sc->vol[k]);
            y[k] = sc->vol_cpu[i][k];
        }
        st = plot_add_series(&p, names[i], x, y, sc->n_vol);
    }
    for (int k = 0; k < sc->n_img; k++) {
        x[k] = log2((double)sc->img[k]);
        y[k] = sc->img_cpu[k];
    }
    if (st == PP5_OK)
        st = plot_add_series(&p, "image side, native volume", x, y, sc->n_img);
    for (int i = 0; i < 3; i++)
        plot_set_style(&p, i, PLOT_LINE_POINTS);
    if (st == PP5_OK && (mkdir("build", 0777) == 0 || errno == EEXIST) &&
        (mkdir("build/bench", 0777) == 0 || errno == EEXIST))
        st = plot_write(&p, path, 900, 520);
    plot_free(&p);
    return st;
}

static void print_tables(const scaling_t *sc, const int sides[2])
{
    printf("   scaling, data resolution (CThead resampled to N^3, shape kept; gaze-directed; sample\n"
           "   step N/256 voxels and opacity per N/256 voxels, so every N takes as many samples\n"
           "   per unit of the object, as opaque, as 256^3 at one per voxel; fastest of the runs,\n"
           "   wall and CPU (all threads) ms):\n");
    printf("     %-6s", "N^3");
    for (int i = 0; i < 2; i++)
        printf(" %4dx%-4d wall   cpu   samples  cpu ns/smp", sides[i], sides[i]);
    printf("  build peak RSS\n");
    double n[MAX_POINTS], per[2][MAX_POINTS];
    for (int k = 0; k < sc->n_vol; k++) {
        n[k] = sc->vol[k];
        printf("     %4d^3", sc->vol[k]);
        for (int i = 0; i < 2; i++) {
            per[i][k] = sc->vol_cpu[i][k] * 1e6 / (double)(sc->vol_samples[i][k] + 1);
            printf(" %14.1f %6.1f %9llu %11.0f", sc->vol_ms[i][k], sc->vol_cpu[i][k],
                   (unsigned long long)sc->vol_samples[i][k], per[i][k]);
        }
        printf(" %11.0f MiB\n", sc->vol_rss[k]);
    }
    for (int i = 0; i < 2; i++)
        printf("   fitted exponent at %dx%d, frame time ~ N^e: wall e = %.2f, cpu e = %.2f; cpu per "
               "drawn sample e = %.2f (paper: 0, independent of the data resolution)\n", sides[i],
               sides[i], bench_fit_exponent(n, sc->vol_ms[i], sc->n_vol),
               bench_fit_exponent(n, sc->vol_cpu[i], sc->n_vol),
               bench_fit_exponent(n, per[i], sc->n_vol));
    printf("   scaling, image size (volume as loaded, gaze-directed; fastest of the runs):\n");
    printf("     %-11s %10s %10s %10s %16s\n", "image", "wall ms", "cpu ms", "rays",
           "cpu ms / Mpixel");
    double area[MAX_POINTS];
    for (int k = 0; k < sc->n_img; k++) {
        area[k] = (double)sc->img[k] * sc->img[k];
        printf("     %4dx%-6d %10.1f %10.1f %10llu %16.1f\n", sc->img[k], sc->img[k],
               sc->img_ms[k], sc->img_cpu[k], (unsigned long long)sc->img_rays[k],
               sc->img_cpu[k] / (area[k] / 1e6));
    }
    printf("   fitted exponent, frame time ~ (pixels)^e: wall e = %.2f, cpu e = %.2f (paper: 1, "
           "linear in the image area)\n", bench_fit_exponent(area, sc->img_ms, sc->n_img),
           bench_fit_exponent(area, sc->img_cpu, sc->n_img));
}

static int bench_render_scaling(const pp5_bench_opts_t *o)
{
    scene_t sc;
    pp5_status_t st = bench_render_scene(&sc);
    if (st != PP5_OK)
        return 1;
    scaling_t r = {0};
    const int vols[] = {64, 128, 256, 512}, vols_quick[] = {32, 64, 128};
    const int imgs[] = {256, 512, 1024, 2048}, imgs_quick[] = {128, 256, 512};
    const int sides[2] = {o->quick ? 128 : 512, o->quick ? 256 : 1024};
    r.n_vol = o->quick ? 3 : 4;
    r.n_img = o->quick ? 3 : 4;
    for (int k = 0; k < r.n_vol; k++)
        r.vol[k] = o->quick ? vols_quick[k] : vols[k];
    for (int k = 0; k < r.n_img; k++)
        r.img[k] = o->quick ? imgs_quick[k] : imgs[k];
    int reps = o->quick ? 1 : 5;
    for (int k = 0; st == PP5_OK && k < r.n_vol; k++)
        st = volume_point(&sc, r.vol[k], reps, &r, k, sides);
    if (st == PP5_OK)
        st = image_points(&sc, reps, &r);
    scene_free(&sc);
    if (st != PP5_OK) {
        printf("   scaling frame failed: %s\n", pp5_error_text());
        return 1;
    }
    print_tables(&r, sides);
    st = scaling_plot(&r, sides, PLOT_PATH);
    if (st == PP5_OK)
        printf("   plot: %s\n", PLOT_PATH);
    else
        printf("   plot not written: %s\n", pp5_error_text());
    return 0;
}

PP5_BENCH(render_scaling, "the paper's s5 scaling: frame time against data resolution and image size",
          bench_render_scaling)
