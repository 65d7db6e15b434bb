/* bench_polygons.c: `pp5 bench polygons`: the polygon pipeline on the emulated machine over a scene of about 100,000 triangles (instanced UV spheres, render/mesh/mesh_gen.h): emulated triangles per emulated second, host time per emulated frame, and render/mesh's rasteriser on the same scene for scale.
 *
 * Host times are the minimum over the runs (the machine may be shared);
 * emulated figures are exact and identical every run.  Speed figures only:
 * never fails on speed. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "firmware/host/poly_session.h"
#include "registry.h"
#include "render/mesh/mesh_gen.h"

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

/* nx x ny spheres of 2 * 40 * 25 = 2,000 faces on a grid in the z = 0 plane. */
static pp5_status_t sphere_field(int nx, int ny, mesh_t *out)
{
    mesh_t s;
    pp5_status_t st = mesh_gen_uv_sphere(40, 26, 0.45, &s);
    if (st != PP5_OK)
        return st;
    int n = nx * ny;
    st = mesh_alloc(out, s.n_vertices * n, s.n_faces * n);
    for (int k = 0; st == PP5_OK && k < n; k++) {
        double ox = k % nx - 0.5 * (nx - 1), oy = k / nx - 0.5 * (ny - 1);
        for (int v = 0; v < s.n_vertices; v++) {
            double *p = out->pos + 3 * ((size_t)k * s.n_vertices + v);
            p[0] = s.pos[3 * v] + ox, p[1] = s.pos[3 * v + 1] + oy, p[2] = s.pos[3 * v + 2];
        }
        for (int f = 0; f < 3 * s.n_faces; f++)
            out->tri[(size_t)k * 3 * s.n_faces + f] = s.tri[f] + k * s.n_vertices;
    }
    snprintf(out->source, sizeof out->source, "%d instanced UV spheres (mesh_gen)", n);
    mesh_free(&s);
    return st;
}

static int bench_polygons(const pp5_bench_opts_t *o)
{
    int nx = o->quick ? 5 : 10, ny = o->quick ? 1 : 5, runs = o->quick ? 1 : 3;
    int W = 1280, H = 1024;
    mesh_t m;
    pp5_status_t st = sphere_field(nx, ny, &m);
    if (st != PP5_OK) {
        fprintf(stderr, "bench polygons: %s\n", pp5_error_text());
        return 1;
    }
    raster_camera_t cam;
    raster_camera_fit(&m, 10, 25, (double)W / H, true, &cam);
    raster_style_t style;
    raster_style_default(&style, RASTER_GOURAUD);
    printf("polygons: %s, %d triangles, %dx%d, perspective, Gouraud; host times: minimum of %d "
           "runs (shared machine)\n", m.source, m.n_faces, W, H, runs);
    for (int sh = POLY_GOURAUD; sh <= POLY_PHONG; sh++) {
        pp5_params_t p;
        pp5_params_default(&p);
        poly_options_t opt;
        poly_options_default(&opt);
        opt.shading = (poly_shading_t)sh;
        double best = 1e30;
        poly_frame_result_t r;
        for (int k = 0; k < runs; k++) {
            poly_session_t s;
            st = poly_session_init_mesh(&s, &p, &m, W, H, &cam, &style, &opt);
            double t0 = now_s();
            if (st == PP5_OK)
                st = poly_session_frame(&s, NULL, &r);
            double dt = now_s() - t0;
            poly_session_free(&s);
            if (st != PP5_OK) {
                fprintf(stderr, "bench polygons: %s\n", pp5_error_text());
                mesh_free(&m);
                return 1;
            }
            best = dt < best ? dt : best;
        }
        printf("  machine %-8s %u GPs %u renderers: emulated %.2f M triangles/s pipelined (%.3f ms "
               "bottleneck %s), %.2f M/s single frame (%.3f ms); host %.2f s per emulated frame\n",
               poly_shading_name((poly_shading_t)sh), p.n_gp, p.n_renderers,
               r.tris_per_s_pipelined / 1e6,
               r.tris_per_s_pipelined > 0 ? 1e3 * (double)r.tris_in / r.tris_per_s_pipelined : 0,
               r.bottleneck, r.tris_per_s_frame / 1e6,
               1e3 * r.frame_time_s, best);
    }
    mesh_raster_t ras;
    double best = 1e30;
    for (int k = 0; st == PP5_OK && k < runs; k++) {
        st = mesh_raster_init(&ras, W, H);
        raster_viewport_t vp = {0, 0, W, H};
        double t0 = now_s();
        if (st == PP5_OK)
            st = mesh_raster_draw(&ras, &vp, &m, &cam, &style);
        double dt = now_s() - t0;
        mesh_raster_free(&ras);
        best = dt < best ? dt : best;
    }
    if (st == PP5_OK)
        printf("  render/mesh rasteriser (host, one thread): %.3f s, %.2f M triangles/s\n", best,
               m.n_faces / best / 1e6);
    mesh_free(&m);
    return st == PP5_OK ? 0 : 1;
}

PP5_BENCH(polygons, "the polygon pipeline on the machine: emulated triangles/s and host time per "
          "frame on ~100k triangles", bench_polygons)
