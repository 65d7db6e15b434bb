/* bench_polygons_native.c: `pp5 bench polygons_native`: the native polygon renderer's
 * triangles per second on the built-in 100,000-triangle scene
 * (gen:spheres100k), flat, Gouraud and Phong, full resolution and
 * gaze-directed (LOD + variable-resolution Z-buffer), minimum and median
 * thread CPU time over several runs (steadier than wall time on a shared
 * host), one thread.  Speed figures only: it
 * never fails on speed. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "registry.h"
#include "render/mesh/mesh_lod.h"
#include "render/mesh/mesh_render.h"
#include "render/mesh/mesh_scene.h"

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

typedef struct {
    mesh_scene_t scene;
    mesh_soup_t full, lod;
    raster_camera_t cam;
    gaze_model_t g;
    int width, height;
} bench_setup_t;

/* One row: `reps` frames, minimum and median ms, triangles/s at each. */
static void bench_row(bench_setup_t *b, raster_shading_t sh, bool gaze, int reps)
{
    static const char *const names[] = {"flat", "gouraud", "phong"};
    mesh_render_opts_t o;
    mesh_render_opts_from_scene(&b->scene, &b->cam, sh, &o);
    double ms[16];
    mesh_render_stats_t st = {0};
    for (int r = 0; r < reps; r++) {
        image8_t img;
        pp5_status_t s = gaze ? mesh_render_vrz(&b->lod, &b->cam, &o, &b->g, 0.5 * (b->width - 1),
                                                0.5 * (b->height - 1), &img, &st)
                              : mesh_render_full(&b->full, &b->cam, &o, b->width, b->height, &img,
                                                 &st);
        if (s != PP5_OK) {
            printf("   %s: %s\n", names[sh], pp5_error_text());
            return;
        }
        image8_free(&img);
        ms[r] = st.cpu_ms;
    }
    qsort(ms, (size_t)reps, sizeof *ms, cmp_double);
    double med = reps % 2 ? ms[reps / 2] : 0.5 * (ms[reps / 2 - 1] + ms[reps / 2]);
    printf("   %-8s %-14s %8llu %8llu %10llu %8.1f %8.1f %10.0f %10.0f\n", names[sh],
           gaze ? "LOD + VRZ" : "full", (unsigned long long)st.triangles_in,
           (unsigned long long)st.triangles_drawn, (unsigned long long)st.fragments, ms[0], med,
           1e3 * (double)st.triangles_in / ms[0], 1e3 * (double)st.triangles_in / med);
}

static int bench_polygons_native(const pp5_bench_opts_t *opt)
{
    bench_setup_t b;
    memset(&b, 0, sizeof b);
    b.width = opt->quick ? 160 : 640, b.height = opt->quick ? 120 : 480;
    int reps = opt->quick ? 1 : 7;
    gaze_display_t d;
    gaze_display_defaults(&d);
    if (mesh_scene_builtin("gen:spheres100k", &b.scene) != PP5_OK ||
        mesh_scene_flatten(&b.scene, NULL, &b.full) != PP5_OK ||
        gaze_model_init(&b.g, &d, b.width, b.height) != PP5_OK ||
        mesh_scene_build_records(&b.scene) != PP5_OK) {
        printf("   setup failed: %s\n", pp5_error_text());
        return 1;
    }
    mesh_scene_camera(&b.scene, (double)b.width / b.height, &b.cam);
    int *levels = calloc((size_t)b.scene.n_objects, sizeof *levels);
    long faces = 0;
    if (!levels)
        return 1;
    mesh_lod_choose(&b.scene, &b.cam, &b.g, 0.5 * (b.width - 1), 0.5 * (b.height - 1), levels,
                    &faces);
    int rc = mesh_scene_flatten(&b.scene, levels, &b.lod) == PP5_OK ? 0 : 1;
    free(levels);
    printf("   gen:spheres100k at %dx%d, gaze at the centre; thread CPU time of one frame (the "
           "triangle list made beforehand), one thread, min and median of %d runs on a shared "
           "host\n", b.width, b.height, reps);
    printf("   %-8s %-14s %8s %8s %10s %8s %8s %10s %10s\n", "shading", "frame", "tris", "drawn",
           "fragments", "min ms", "med ms", "tris/s min", "tris/s med");
    for (int sh = 0; sh < 3 && rc == 0; sh++)
        for (int gz = 0; gz < 2; gz++)
            bench_row(&b, (raster_shading_t)sh, gz == 1, reps);
    printf("   (tris/s = triangles submitted / frame time; back faces are culled, so about half "
           "reach the rasteriser)\n");
    mesh_soup_free(&b.full);
    mesh_soup_free(&b.lod);
    mesh_scene_free(&b.scene);
    return rc;
}

PP5_BENCH(polygons_native, "native polygon renderer: triangles/s on the 100,000-triangle scene",
          bench_polygons_native)
