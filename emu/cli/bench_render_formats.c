/* bench_render_formats.c: the reduced-precision mip-map formats in `pp5
 * bench render` (mip3d.h: U16, U8 against the default F32): memory (peak
 * RSS of the build, bytes per voxel over all levels), frame times, and the
 * image difference from F32. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "bench_render.h"
#include "render/quality.h"

void bench_print_memory(const char *format, const volume_t *v, const native_renderer_t *r,
                        double peak_rss_mb)
{
    double voxels = (double)v->nx * v->ny * v->nz;
    printf("   memory (%s): peak RSS %.0f MiB during the build (volume %.0f MiB as floats, 3D mip "
           "map %.1f MiB = %.2f bytes per voxel over all levels, octree %.1f MiB)\n", format,
           peak_rss_mb, voxels * sizeof(float) / (1024.0 * 1024.0),
           r->mip.bytes / (1024.0 * 1024.0), (double)r->mip.bytes / voxels,
           r->octree.bytes / (1024.0 * 1024.0));
}

pp5_status_t bench_format_references(native_renderer_t *r, const scene_t *sc, int side,
                                     image8_t ref[2])
{
    pp5_status_t st = PP5_OK;
    for (int g = 0; st == PP5_OK && g < 2; g++) {
        render_settings_t s;
        bench_render_settings(sc, side, g ? RENDER_MODE_GAZE : RENDER_MODE_FULL, &s);
        render_stats_t stats;
        st = native_renderer_frame(r, &s, &ref[g], &stats);
    }
    return st;
}

/* PSNR (quality.h's definition) and the largest channel difference. */
static double psnr(const image8_t *a, const image8_t *b, int *max_diff)
{
    size_t n = (size_t)a->width * a->height * 3;
    double se = 0.0;
    *max_diff = 0;
    for (size_t i = 0; i < n; i++) {
        int d = abs((int)a->pixels[i] - (int)b->pixels[i]);
        se += (double)d * d;
        *max_diff = d > *max_diff ? d : *max_diff;
    }
    return quality_psnr_from_mse(se / (double)n);
}

static pp5_status_t one_format(const scene_t *sc, mip3d_format_t f, int side, int reps,
                               const image8_t ref[2], double f32_ms[2])
{
    shade_params_t sh;
    shade_defaults(&sh);
    native_renderer_t r;
    bool rss = bench_peak_rss_reset();
    pp5_status_t st = native_renderer_init_format(&r, &sc->volume, &sc->tf, &sh, f, 0);
    if (st != PP5_OK)
        return st;
    bench_print_memory(mip3d_format_name(f), &sc->volume, &r, rss ? bench_peak_rss_mb() : -1.0);
    for (int g = 0; st == PP5_OK && g < 2; g++) {
        render_settings_t s;
        bench_render_settings(sc, side, g ? RENDER_MODE_GAZE : RENDER_MODE_FULL, &s);
        render_stats_t stats;
        double ms;
        image8_t img;
        st = bench_render_frames(&r, &s, reps, &ms, &stats);
        if (st == PP5_OK)
            st = native_renderer_frame(&r, &s, &img, &stats);
        if (st != PP5_OK)
            break;
        int max_diff;
        double p = psnr(&img, &ref[g], &max_diff);
        printf("   %4dx%-4d %-4s %-15s %8.1f ms/frame  (%.2fx of f32; %llu 3D samples; PSNR "
               "%.1f dB against f32, max channel difference %d)\n", side, side,
               mip3d_format_name(f), g ? "gaze-directed:" : "full resolution:", ms, ms / f32_ms[g],
               (unsigned long long)stats.samples, p, max_diff);
        image8_free(&img);
    }
    native_renderer_free(&r);
    return st;
}

pp5_status_t bench_formats(const scene_t *sc, int side, int reps, const image8_t ref[2],
                           double f32_full_ms, double f32_gaze_ms)
{
    double f32_ms[2] = {f32_full_ms, f32_gaze_ms};
    printf("   voxel formats (--voxel-format; reduced precision, bricked 4x4x4):\n");
    pp5_status_t st = one_format(sc, MIP3D_U16, side, reps, ref, f32_ms);
    if (st == PP5_OK)
        st = one_format(sc, MIP3D_U8, side, reps, ref, f32_ms);
    if (st != PP5_OK)
        printf("   format frame failed: %s\n", pp5_error_text());
    return st;
}
