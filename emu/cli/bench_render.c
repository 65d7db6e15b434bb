/* bench_render.c: `pp5 bench render`: native renderer speed on CThead
 * (phantom fallback), full resolution against gaze-directed frames, and
 * with --peers the VTK / VolPack comparisons (render/peers/). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_render.h"
#include "registry.h"
#include "render/scene.h"

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median frame time over `reps` frames (first frame not discarded: the
 * renderer keeps no per-view caches outside progressive mode). */
pp5_status_t bench_render_frames(native_renderer_t *r, const render_settings_t *s, int reps,
                                 double *ms, render_stats_t *last)
{
    double t[9];
    if (reps > 9)
        reps = 9;
    for (int i = 0; i < reps; i++) {
        image8_t img;
        pp5_status_t st = native_renderer_frame(r, s, &img, last);
        if (st != PP5_OK)
            return st;
        image8_free(&img);
        t[i] = last->ms_total;
    }
    qsort(t, (size_t)reps, sizeof t[0], cmp_double);
    *ms = t[reps / 2];
    return PP5_OK;
}

/* MIP, DEMIP and MIDA (render/blend.h) at the first size, full resolution
 * and gaze-directed, with the same view; new summary lines below the
 * compositing ones (which stay as they were: scripts read them). */
static pp5_status_t bench_blends(native_renderer_t *r, const scene_t *sc, int size, int reps,
                                 double full_composite_ms, double *mip_full_ms)
{
    pp5_status_t st = native_renderer_build_scalar(r, &sc->volume, SCALAR_PYRAMID_MAX);
    if (st != PP5_OK)
        return st;
    render_settings_t s;
    bench_render_settings(sc, size, RENDER_MODE_FULL, &s);
    blend_settings_fill(&s.blend, sc->window_centre, sc->window_width,
                        (const float[3]){sc->rot_x_deg, sc->rot_y_deg, sc->rot_z_deg});
    printf("   blends: window C=%g W=%g (%s), value pyramid (max) built in %.0f ms; DEMIP with "
           "the defaults (tolerance %.2f, dw %.2f, sphere weight %.2f)\n", s.blend.window_centre,
           s.blend.window_width, s.blend.window_width > 0.0f ? "the dataset's" : "value range",
           r->ms_build_scalar, s.blend.tolerance, s.blend.depth_weight, s.blend.sphere_weight);
    const blend_mode_t modes[3] = {BLEND_MIP, BLEND_DEMIP, BLEND_MIDA};
    double ms[3] = {0, 0, 0}, gaze_ms = 0.0;
    render_stats_t stats[3], gs;
    s.mode = RENDER_MODE_FULL;
    for (int i = 0; st == PP5_OK && i < 3; i++) {
        s.blend.mode = modes[i];
        st = bench_render_frames(r, &s, reps, &ms[i], &stats[i]);
    }
    s.mode = RENDER_MODE_GAZE;
    s.blend.mode = BLEND_MIP;
    if (st == PP5_OK)
        st = bench_render_frames(r, &s, reps, &gaze_ms, &gs);
    if (st != PP5_OK)
        return st;
    const char *names[3] = {"MIP", "DEMIP", "MIDA"};
    for (int i = 0; i < 3; i++)
        printf("   %4dx%-4d %-5s full resolution: %8.1f ms/frame  (%llu rays, %llu 3D samples)\n",
               size, size, names[i], ms[i], (unsigned long long)stats[i].rays,
               (unsigned long long)stats[i].samples);
    printf("   %4dx%-4d compositing full resolution: %8.1f ms/frame  (above)\n", size, size,
           full_composite_ms);
    printf("   %4dx%-4d MIP gaze-directed:   %8.1f ms/frame  (%llu rays, %llu 3D samples)\n",
           size, size, gaze_ms, (unsigned long long)gs.rays, (unsigned long long)gs.samples);
    printf("   %4dx%-4d DEMIP/MIP cost: %.2fx (goal <= 1.25x); MIP speed-up gaze vs full: %.2fx "
           "(goal >= 4x)\n", size, size, ms[1] / ms[0], ms[0] / gaze_ms);
    *mip_full_ms = ms[0];
    return PP5_OK;
}

/* Full resolution and gaze-directed frames at one image side (parallel or
 * perspective). */
typedef struct {
    double full_ms, gaze_ms;
    render_stats_t fs, gs;
} size_result_t;

static pp5_status_t bench_size(native_renderer_t *r, const scene_t *sc, int side,
                               projection_t projection, int reps, size_result_t *out)
{
    render_settings_t s;
    bench_render_settings(sc, side, RENDER_MODE_FULL, &s);
    s.view.projection = projection;
    pp5_status_t st = bench_render_frames(r, &s, reps, &out->full_ms, &out->fs);
    s.mode = RENDER_MODE_GAZE;
    if (st == PP5_OK)
        st = bench_render_frames(r, &s, reps, &out->gaze_ms, &out->gs);
    if (st != PP5_OK)
        printf("   frame failed: %s\n", pp5_error_text());
    return st;
}

static void print_size(int side, const size_result_t *z)
{
    printf("   %4dx%-4d full resolution: %8.1f ms/frame  (%llu rays, %llu 3D samples)\n", side,
           side, z->full_ms, (unsigned long long)z->fs.rays, (unsigned long long)z->fs.samples);
    printf("   %4dx%-4d gaze-directed:   %8.1f ms/frame  (%llu rays, %llu 3D samples)\n", side,
           side, z->gaze_ms, (unsigned long long)z->gs.rays, (unsigned long long)z->gs.samples);
    printf("   %4dx%-4d speed-up gaze vs full: %.2fx%s\n", side, side, z->full_ms / z->gaze_ms,
           (side == 1024 ? " (goal >= 5x, the paper's factor)" : ""));
}

/* The figures beside the summary lines: the 5x goal at every size, samples
 * per second per thread, perspective. */
static pp5_status_t bench_more(native_renderer_t *r, const scene_t *sc, const int sides[3],
                               const size_result_t z[3], int reps)
{
    printf("   gaze vs full (goal >= 5x at %d, %d and %d):", sides[0], sides[1], sides[2]);
    bool met = true;
    for (int k = 0; k < 3; k++) {
        double x = z[k].full_ms / z[k].gaze_ms;
        met = met && x >= 5.0;
        printf(" %.2fx%s", x, k < 2 ? "," : "");
    }
    printf(": %s\n", met ? "met" : "missed");
    printf("   %4dx%-4d full resolution: %.1f M 3D samples/s per thread (%d threads; goal >= 50 M "
           "per core), %.0f ns per ray-thread\n", sides[0], sides[0],
           (double)z[0].fs.samples / (z[0].full_ms * 1e3 * r->threads), r->threads,
           z[0].full_ms * 1e6 * r->threads / (double)z[0].fs.rays);
    size_result_t p;
    pp5_status_t st = bench_size(r, sc, sides[0], PROJECTION_PERSPECTIVE, reps, &p);
    if (st == PP5_OK)
        printf("   %4dx%-4d perspective (eye at 3 bounding radii): full %.1f ms/frame (%llu "
               "samples), gaze-directed %.1f ms/frame (%llu samples), %.2fx\n", sides[0],
               sides[0], p.full_ms, (unsigned long long)p.fs.samples, p.gaze_ms,
               (unsigned long long)p.gs.samples, p.full_ms / p.gaze_ms);
    return st;
}

static int bench_render(const pp5_bench_opts_t *o)
{
    scene_t sc;
    pp5_status_t st = bench_render_scene(&sc);
    if (st != PP5_OK)
        return 1;
    shade_params_t sh;
    shade_defaults(&sh);
    native_renderer_t r;
    bool rss = bench_peak_rss_reset();
    st = native_renderer_init(&r, &sc.volume, &sc.tf, &sh, 0);
    if (st != PP5_OK) {
        printf("   renderer init failed: %s\n", pp5_error_text());
        scene_free(&sc);
        return 1;
    }
    printf("   volume %s (%dx%dx%d), tf %s, diffuse shading, parallel, octree on, %d threads\n",
           sc.volume.source, sc.volume.nx, sc.volume.ny, sc.volume.nz, sc.tf.name, r.threads);
    printf("   3D mip map + octree build: %.0f ms (once per volume/transfer function)\n",
           r.ms_build_mip + r.ms_build_octree);
    bench_print_memory("f32", &sc.volume, &r, rss ? bench_peak_rss_mb() : -1.0);
    int sides[3] = {512, 1024, 2048};
    if (o->quick)
        for (int k = 0; k < 3; k++)
            sides[k] /= 4;
    int reps = o->quick ? 1 : 5;
    size_result_t z[3];
    for (int k = 0; st == PP5_OK && k < 3; k++) {
        st = bench_size(&r, &sc, sides[k], PROJECTION_PARALLEL, k == 2 ? (reps + 1) / 2 : reps,
                        &z[k]);
        if (st == PP5_OK)
            print_size(sides[k], &z[k]);
    }
    if (st == PP5_OK)
        st = bench_more(&r, &sc, sides, z, reps);
    double mip_full_ms = 0.0;
    if (st == PP5_OK) {
        st = bench_blends(&r, &sc, sides[0], reps, z[0].full_ms, &mip_full_ms);
        if (st != PP5_OK)
            printf("   blend frame failed: %s\n", pp5_error_text());
    }
    image8_t ref[2] = {{0}, {0}};
    if (st == PP5_OK)
        st = bench_format_references(&r, &sc, sides[0], ref);
    native_renderer_free(&r);
    if (st == PP5_OK)
        st = bench_formats(&sc, sides[0], reps, ref, z[0].full_ms, z[0].gaze_ms);
    image8_free(&ref[0]);
    image8_free(&ref[1]);
    if (o->peers && st == PP5_OK) {
        char path[1200];
        snprintf(path, sizeof path, "%s/volumes/cthead/cthead_256x256x113_u16be.raw.gz",
                 scene_data_root());
        render_peers_run(sc.fell_back ? NULL : path, sides[0], z[0].full_ms, z[0].gaze_ms,
                         mip_full_ms, sc.window_centre - 0.5f * sc.window_width,
                         sc.window_centre + 0.5f * sc.window_width);
    }
    scene_free(&sc);
    return st == PP5_OK ? 0 : 1;
}

PP5_BENCH(render, "native gaze-directed renderer: full vs gaze frame times (CThead)",
          bench_render)
