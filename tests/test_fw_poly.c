/* test_fw_poly.c: the polygon pipeline on the emulated machine against render/mesh's rasteriser: identical coverage and colours within the fixed point's rounding on exactly representable scenes, every region a triangle spans reached, Phong on a flat patch, determinism and the frame's figures.
 *
 * Tolerances (firmware/ARCHITECTURE.md "Polygons"): on scenes whose screen
 * corners lie on the 1/16-pixel grid (orthographic camera over the pixel
 * grid, coordinates multiples of 1/16) the machine's edges are exactly
 * mesh_raster's, so the covered pixels must be the same pixels; colours may
 * differ by 1 (the colour planes' 16 fraction bits and single-precision
 * set-up against render/'s doubles). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "firmware/host/poly_report.h"
#include "firmware/host/poly_scene.h"
#include "firmware/host/poly_session.h"
#include "harness.h"
#include "render/mesh/mesh.h"
#include "render/mesh/mesh_gen.h"
#include "render/mesh/mesh_raster.h"
#include "renderer.h"
#include "firmware/common/poly_phong_pp.h"
#include "firmware/gp/poly_kernels.h"

static const uint8_t BG[3] = {24, 26, 32};

typedef struct {
    int differ_cover, differ_colour, max_diff, covered;
} poly_cmp_t;

static void machine_params(pp5_params_t *p, unsigned n_gp, unsigned n_r)
{
    pp5_params_default(p);
    p->n_gp = n_gp;
    p->n_renderers = n_r;
}

/* The machine's and render/mesh's images of m; counts of differences. */
static poly_cmp_t compare_images(const image8_t *a, const image8_t *b)
{
    poly_cmp_t c = {0, 0, 0, 0};
    for (int i = 0; i < a->width * a->height; i++) {
        const uint8_t *p = a->pixels + 3 * i, *q = b->pixels + 3 * i;
        bool ca = memcmp(p, BG, 3) != 0, cb = memcmp(q, BG, 3) != 0;
        c.covered += cb;
        if (ca != cb) {
            c.differ_cover++;
            continue;
        }
        int d = 0;
        for (int k = 0; k < 3; k++)
            d = abs(p[k] - q[k]) > d ? abs(p[k] - q[k]) : d;
        c.differ_colour += d > 0;
        c.max_diff = d > c.max_diff ? d : c.max_diff;
    }
    return c;
}

static void native_image(const mesh_t *m, int w, int h, const raster_camera_t *cam,
                         const raster_style_t *st, image8_t *out)
{
    mesh_raster_t r;
    REQUIRE(mesh_raster_init(&r, w, h) == PP5_OK);
    raster_viewport_t vp = {0, 0, w, h};
    mesh_raster_clear(&r, &vp, BG);
    REQUIRE(mesh_raster_draw(&r, &vp, m, cam, st) == PP5_OK);
    *out = r.image;
    r.image.pixels = NULL;
    mesh_raster_free(&r);
}

static void machine_image(const mesh_t *m, int w, int h, const raster_camera_t *cam,
                          const raster_style_t *st, poly_shading_t sh, unsigned n_gp, unsigned n_r,
                          image8_t *out, poly_frame_result_t *res)
{
    pp5_params_t p;
    machine_params(&p, n_gp, n_r);
    poly_options_t o;
    poly_options_default(&o);
    o.shading = sh;
    memcpy(o.background, BG, 3);
    poly_session_t s;
    REQUIRE_MSG(poly_session_init_mesh(&s, &p, m, w, h, cam, st, &o) == PP5_OK, "init: %s",
                pp5_error_text());
    poly_frame_result_t r;
    REQUIRE_MSG(poly_session_frame(&s, out, res ? res : &r) == PP5_OK, "frame: %s", pp5_error_text());
    poly_session_free(&s);
}

/* n separate triangles with corners on the 1/16 grid of an N x N pixel
 * ortho view, each at its own depth slab (no two within a depth step), some
 * large enough to span several regions, both windings. */
static void dyadic_scene(mesh_t *m, int n, int N, unsigned seed)
{
    REQUIRE(mesh_alloc(m, 3 * n, n) == PP5_OK);
    for (int t = 0; t < n; t++) {
        double size = t % 5 == 0 ? N * 0.9 : 8 + (seed % 97);
        double cx = (double)((seed = seed * 1103515245u + 12345u) >> 8) / (1 << 24) * N;
        double cy = (double)((seed = seed * 1103515245u + 12345u) >> 8) / (1 << 24) * N;
        for (int c = 0; c < 3; c++) {
            double dx = ((double)((seed = seed * 1103515245u + 12345u) >> 8) / (1 << 24) - 0.5) * size;
            double dy = ((double)((seed = seed * 1103515245u + 12345u) >> 8) / (1 << 24) - 0.5) * size;
            double *p = m->pos + 9 * t + 3 * c;
            p[0] = floor((cx + dx) * 16) / 16;
            p[1] = floor((cy + dy) * 16) / 16;
            p[2] = -1.0 - 0.25 * t - 0.0625 * c;   /* tilted, inside its own slab */
            m->tri[3 * t + c] = 3 * t + c;
        }
    }
}

TEST(fw_poly_coverage_matches_mesh_raster_on_grid_scenes)
{
    const int N = 256;
    for (int sh = 0; sh < 2; sh++) {
        mesh_t m;
        dyadic_scene(&m, 40, N, 7u + (unsigned)sh);
        raster_camera_t cam;
        raster_camera_ortho(0, N, 0, N, 0.5, 20, &cam);
        raster_style_t st;
        raster_style_default(&st, sh ? RASTER_GOURAUD : RASTER_FLAT);
        image8_t a, b;
        native_image(&m, N, N, &cam, &st, &b);
        machine_image(&m, N, N, &cam, &st, sh ? POLY_GOURAUD : POLY_FLAT, 3, 2, &a, NULL);
        poly_cmp_t c = compare_images(&a, &b);
        CHECK_MSG(c.covered > N * N / 4, "the scene covers %d pixels", c.covered);
        CHECK_MSG(c.differ_cover == 0, "%s: %d pixels covered in one image only", sh ? "gouraud" : "flat",
                  c.differ_cover);
        CHECK_MSG(c.max_diff <= 1, "%s: colours differ by up to %d (%d pixels)", sh ? "gouraud" : "flat",
                  c.max_diff, c.differ_colour);
        image8_free(&a);
        image8_free(&b);
        mesh_free(&m);
    }
}


static double psnr(const image8_t *a, const image8_t *b)
{
    double se = 0;
    size_t n = (size_t)a->width * a->height * 3;
    for (size_t i = 0; i < n; i++)
        se += (double)(a->pixels[i] - b->pixels[i]) * (a->pixels[i] - b->pixels[i]);
    return se == 0 ? INFINITY : 10 * log10(255.0 * 255.0 * (double)n / se);
}

/* Off the 1/16 grid the machine snaps the corners (up to 1/32 pixel), so
 * a few pixel centres next to edges change sides, and Gouraud is linear on
 * the screen where mesh_raster is perspective-correct: bounds, not
 * equality (the measured values are in firmware/ARCHITECTURE.md). */
TEST(fw_poly_gouraud_sphere_against_mesh_raster)
{
    mesh_t m;
    REQUIRE(mesh_gen_uv_sphere(24, 16, 1.0, &m) == PP5_OK);
    for (int persp = 0; persp < 2; persp++) {
        raster_camera_t cam;
        raster_camera_fit(&m, 30, 20, 1.0, persp, &cam);
        raster_style_t st;
        raster_style_default(&st, RASTER_GOURAUD);
        image8_t a, b;
        native_image(&m, 192, 192, &cam, &st, &b);
        machine_image(&m, 192, 192, &cam, &st, POLY_GOURAUD, 2, 3, &a, NULL);
        poly_cmp_t c = compare_images(&a, &b);
        double q = psnr(&a, &b);
        CHECK_MSG(c.covered > 5000, "sphere covers %d pixels", c.covered);
        CHECK_MSG(c.differ_cover * 200 <= c.covered, "%s: %d of %d pixels covered in one image only",
                  persp ? "perspective" : "ortho", c.differ_cover, c.covered);
        CHECK_MSG(q >= (persp ? 42.0 : 45.0), "%s: PSNR %.2f dB", persp ? "perspective" : "ortho", q);
        CHECK_MSG(c.max_diff <= (persp ? 8 : 4), "%s: colours differ by %d", persp ? "perspective" : "ortho",
                  c.max_diff);
        image8_free(&a);
        image8_free(&b);
    }
    mesh_free(&m);
}

/* Phong on a plane (every normal the same, so per-pixel shading is flat
 * shading): the PPs' normalisation and lighting against mesh_raster's
 * flat colour, on the 1/16 grid (the same coverage). */
TEST(fw_poly_phong_on_a_flat_patch_is_flat_shading)
{
    mesh_t m;
    REQUIRE(mesh_gen_grid(6, 6, 192, 192, &m) == PP5_OK);
    for (int i = 0; i < m.n_vertices; i++)
        m.pos[3 * i + 2] = -2;
    raster_camera_t cam;
    raster_camera_ortho(-16, 240, -16, 240, 0.5, 20, &cam);
    raster_style_t st;
    raster_style_default(&st, RASTER_FLAT);
    for (int side = 0; side < 2; side++) {
        if (side) {   /* seen from behind: the back colour, the normal reversed */
            for (int f = 0; f < m.n_faces; f++) {
                int32_t t = m.tri[3 * f + 1];
                m.tri[3 * f + 1] = m.tri[3 * f + 2], m.tri[3 * f + 2] = t;
            }
        }
        image8_t a, b;
        native_image(&m, 256, 256, &cam, &st, &b);
        machine_image(&m, 256, 256, &cam, &st, POLY_PHONG, 2, 2, &a, NULL);
        poly_cmp_t c = compare_images(&a, &b);
        CHECK_EQ(c.covered, 192 * 192);
        CHECK_EQ(c.differ_cover, 0);
        CHECK_MSG(c.max_diff <= 1, "side %d: Phong differs from flat by %d", side, c.max_diff);
        image8_free(&a);
        image8_free(&b);
    }
    mesh_free(&m);
}

/* One triangle over 9 of a 4 x 3 region screen: every region it covers
 * gets it, from renderers that each take several regions. */
TEST(fw_poly_triangle_spanning_regions_reaches_every_one)
{
    const double xyz[9] = {8.5, 20.25, -2, 500.0625, 100, -2, 160, 380.5, -2};
    mesh_t m;
    REQUIRE(mesh_alloc(&m, 3, 1) == PP5_OK);
    memcpy(m.pos, xyz, sizeof xyz);
    m.tri[0] = 0, m.tri[1] = 1, m.tri[2] = 2;
    raster_camera_t cam;
    raster_camera_ortho(0, 512, 0, 384, 0.5, 20, &cam);
    raster_style_t st;
    raster_style_default(&st, RASTER_FLAT);
    image8_t a, b;
    poly_frame_result_t r;
    native_image(&m, 512, 384, &cam, &st, &b);
    machine_image(&m, 512, 384, &cam, &st, POLY_FLAT, 2, 5, &a, &r);
    bool touched[12] = {false};
    int n_touched = 0;
    for (int y = 0; y < 384; y++)
        for (int x = 0; x < 512; x++)
            if (memcmp(b.pixels + 3 * ((size_t)y * 512 + x), BG, 3) != 0 && !touched[(y / 128) * 4 + x / 128]) {
                touched[(y / 128) * 4 + x / 128] = true;
                n_touched++;
            }
    poly_cmp_t c = compare_images(&a, &b);
    CHECK_MSG(n_touched >= 6, "the triangle covers %d regions", n_touched);
    CHECK_EQ(c.differ_cover, 0);
    CHECK_EQ(c.max_diff, 0);
    CHECK_EQ(r.pairs_sent, (uint64_t)n_touched);
    CHECK_EQ(r.regions, 12 * 2);   /* each of 12 regions: a stream from each of 2 GPs */
    image8_free(&a);
    image8_free(&b);
    mesh_free(&m);
}

/* The test's own coverage: mesh_raster's edge functions and top-left rule
 * in 64-bit integers at pixel centres (16 x + 8, 16 y + 8). */
static bool covers(const int32_t X[3], const int32_t Y[3], int64_t px, int64_t py)
{
    int64_t area = (int64_t)(X[1] - X[0]) * (Y[2] - Y[0]) - (int64_t)(Y[1] - Y[0]) * (X[2] - X[0]);
    int64_t s = area > 0 ? 1 : -1;
    for (int k = 0; k < 3; k++) {
        int a = (k + 1) % 3, b = (k + 2) % 3;
        int64_t e = s * ((int64_t)(X[b] - X[a]) * (py - Y[a]) - (int64_t)(Y[b] - Y[a]) * (px - X[a]));
        int64_t nx = -(int64_t)(Y[b] - Y[a]) * s, ny = (int64_t)(X[b] - X[a]) * s;
        bool own = nx > 0 || (nx == 0 && ny > 0);
        if (!(e > 0 || (e == 0 && own)))
            return false;
    }
    return true;
}

/* QEE edges are exact far from the origin and below zero: a triangle with
 * corners near +-2^14 pixels at odd 1/16 positions, rendered by a renderer
 * moved to regions at large negative and positive origins that its edges
 * and corners cross; every PP's coverage against covers(). */
TEST(fw_poly_qee_edges_exact_on_large_and_negative_coordinates)
{
    poly_config_t c;
    memset(&c, 0, sizeof c);
    c.width = 2048, c.height = 1024, c.shading = POLY_FLAT;
    poly_screen_t v[3] = {{0, 0, 0, -16000 * 16 + 5, -12000 * 16 + 11},
                          {0, 0, 0, 16000 * 16 + 3, 12000 * 16 - 7},
                          {0, 0, 0, -7000 * 16 - 9, 8000 * 16 + 1}};
    float vals[4][3] = {{4e6f, 5e6f, 6e6f}};
    poly_tri_t t;
    REQUIRE(poly_setup(&c, &v[0], &v[1], &v[2], vals, 1, &t, NULL, NULL));
    t.flat_rgb = 0xffffff;
    pp5_params_t p;
    pp5_params_default(&p);
    renderer_t r;
    REQUIRE(renderer_init(&r, 0, &p.pp) == PP5_OK);
    /* the long edge 0-1 (y = 3x/4) through (-64, -64), and clipping the
     * bottom-left corner of (1000, 623), whose far corner is 178 pixels from
     * it (|e| near 2^31 there); corner 2; edge 2-0 at x = -8000; a region
     * far down and left */
    const int origins[5][2] = {{-64, -64}, {1000, 623}, {-7064, 7936}, {-8050, 5700}, {-8000, -8000}};
    uint32_t *z = malloc(sizeof *z * 128 * 128);
    REQUIRE(z != NULL);
    int inside_total = 0;
    for (int o = 0; o < 5; o++) {
        pp_stream_t st;
        pp_stream_init(&st);
        poly_region_start(&c, true, &st, NULL, NULL);
        bool some = poly_encode(&c, &t, 0, origins[o][0], origins[o][1], &st, NULL, NULL);
        REQUIRE(pp_stream_ok(&st));
        renderer_reset(&r);
        renderer_set_region(&r, origins[o][0], origins[o][1]);
        renderer_exec_result_t res;
        REQUIRE_MSG(renderer_execute(&r, st.words, st.n_words, &res) == PP5_OK, "%s", pp5_error_text());
        REQUIRE(renderer_read_field(&r, POLY_PP_Z, POLY_Z_BITS, z) == PP5_OK);
        int wrong = 0, inside = 0;
        for (int i = 0; i < 128 * 128; i++) {
            int64_t px = 16 * (int64_t)(origins[o][0] + i % 128) + 8;
            int64_t py = 16 * (int64_t)(origins[o][1] + i / 128) + 8;
            bool want = covers(t.X, t.Y, px, py);
            inside += want;
            wrong += want != (z[i] != POLY_Z_FAR);
        }
        CHECK_MSG(wrong == 0, "region at (%d, %d): %d of 16384 PPs wrong", origins[o][0], origins[o][1],
                  wrong);
        CHECK_MSG(some == (inside > 0), "region at (%d, %d): sent %d, %d pixels inside", origins[o][0],
                  origins[o][1], some, inside);
        inside_total += inside > 0 && inside < 128 * 128;
        pp_stream_free(&st);
    }
    CHECK_MSG(inside_total >= 4, "only %d regions are crossed by an edge", inside_total);
    free(z);
    renderer_free(&r);
}

/* Same scene, same machine: the same pixels and the same cycle counts,
 * whatever the host's worker threads. */
TEST(fw_poly_images_and_cycles_are_deterministic)
{
    mesh_t m;
    REQUIRE(mesh_gen_torus(24, 12, 1.0, 0.35, &m) == PP5_OK);
    raster_camera_t cam;
    raster_camera_fit(&m, 20, 35, 1.5, true, &cam);
    raster_style_t st;
    raster_style_default(&st, RASTER_GOURAUD);
    image8_t img[2];
    poly_frame_result_t r[2];
    for (int k = 0; k < 2; k++) {
        pp5_params_t p;
        machine_params(&p, 3, 4);
        p.sim_host_threads = k ? 2 : 1;
        poly_options_t o;
        poly_options_default(&o);
        o.shading = POLY_PHONG;
        poly_session_t s;
        REQUIRE(poly_session_init_mesh(&s, &p, &m, 384, 256, &cam, &st, &o) == PP5_OK);
        REQUIRE(poly_session_frame(&s, &img[k], &r[k]) == PP5_OK);
        poly_session_free(&s);
    }
    CHECK(memcmp(img[0].pixels, img[1].pixels, (size_t)384 * 256 * 3) == 0);
    CHECK(r[0].frame_time_s == r[1].frame_time_s);
    CHECK_EQ(r[0].rn_exec_cycles_total, r[1].rn_exec_cycles_total);
    CHECK_EQ(r[0].cycles_transform + r[0].cycles_encode, r[1].cycles_transform + r[1].cycles_encode);
    CHECK_EQ(r[0].tris_in, (uint64_t)m.n_faces);
    for (int k = 0; k < 2; k++)
        image8_free(&img[k]);
    mesh_free(&m);
}

/* The throughput is counted, not fitted: a cost parameter moved by delta
 * moves the bottleneck stage by (its counted operations) x delta and the
 * figure to triangles / the new stage, computed here by hand from the
 * first run's counts.  GP-bound (one GP): i860.fdiv_cycles; renderer-bound
 * (one renderer, 32 GPs, 4 regions): pp.qee_fill_cycles. */
static void bench_run(unsigned n_gp, unsigned n_r, int size, const char *set, poly_frame_result_t *r)
{
    pp5_params_t p;
    machine_params(&p, n_gp, n_r);
    if (set)
        REQUIRE(pp5_params_set_kv(&p, set) == PP5_OK);
    poly_tri_in_t *t;
    raster_camera_t cam;
    REQUIRE(poly_scene_triangles(600, 100, size, size, 5u, &t, &cam) == PP5_OK);
    raster_style_t st;
    raster_style_default(&st, RASTER_GOURAUD);
    poly_options_t o;
    poly_options_default(&o);
    poly_session_t s;
    REQUIRE_MSG(poly_session_init(&s, &p, t, 600, size, size, &cam, &st, &o) == PP5_OK, "%s",
                pp5_error_text());
    REQUIRE(poly_session_frame(&s, NULL, r) == PP5_OK);
    poly_session_free(&s);
    free(t);
}

TEST(fw_poly_throughput_moves_with_cost_parameters_as_by_hand)
{
    poly_frame_result_t a, b;
    bench_run(1, 16, 512, NULL, &a);
    bench_run(1, 16, 512, "i860.fdiv_cycles=35", &b);   /* default 25 */
    CHECK(a.stage_s[POLY_STAGE_GP] > a.stage_s[POLY_STAGE_RENDERER]);
    double gp_hand = a.stage_s[POLY_STAGE_GP] + 10.0 * (double)a.gp_fdiv_busiest / 40e6;
    CHECK_NEAR(b.stage_s[POLY_STAGE_GP], gp_hand, 1e-12);
    CHECK_NEAR(b.tris_per_s_pipelined, 600.0 / gp_hand, 1e-6);
    CHECK(b.tris_per_s_pipelined < a.tris_per_s_pipelined);

    bench_run(32, 1, 256, NULL, &a);
    bench_run(32, 1, 256, "pp.qee_fill_cycles=20", &b);   /* default 16 */
    CHECK_MSG(strcmp(a.bottleneck, poly_stage_name(POLY_STAGE_RENDERER)) == 0, "bottleneck %s",
              a.bottleneck);
    CHECK_EQ(b.rn_exec_cycles_total, a.rn_exec_cycles_total + 4 * a.rn_qee_count);
    /* Gouraud: per pair 4 QEEs (depth, 3 colours) plus its edges */
    CHECK_EQ(a.rn_qee_count, 4 * a.pairs_sent + a.edges_sent);
    double rn_hand = a.stage_s[POLY_STAGE_RENDERER] + 4.0 * (double)a.rn_qee_count / 40e6;
    CHECK_NEAR(b.stage_s[POLY_STAGE_RENDERER], rn_hand, 1e-12);
    CHECK_NEAR(b.tris_per_s_pipelined, 600.0 / rn_hand, 1e-6);
}

/* The command prints the published figures with their sources beside
 * ours, both sweeps, and rejects a bad option with a one-line error. */
TEST(fw_poly_reproduce_polygons_prints_the_table)
{
    char out[1200], err[1200];
    snprintf(out, sizeof out, "%s/repro_poly_out.txt", pp5_test_outdir());
    snprintf(err, sizeof err, "%s/repro_poly_err.txt", pp5_test_outdir());
    REQUIRE(pp5_test_run_cli("reproduce polygons --quick --triangles 300", out, err) == 0);
    char *text = pp5_test_read_file(out);
    REQUIRE(text);
    CHECK(strstr(text, "1.60 M/s") != NULL && strstr(text, "measured Apr 1991 [S] S3") != NULL);
    CHECK(strstr(text, "design target 1989 [C] S1") != NULL);
    CHECK(strstr(text, "Sweep over triangle size") != NULL && strstr(text, "Sweep over GP count") != NULL);
    CHECK(strstr(text, "turn:") != NULL && strstr(text, "Sweep over renderer count") != NULL);
    free(text);
    CHECK(pp5_test_run_cli("reproduce polygons --triangles 5", out, err) != 0);
    text = pp5_test_read_file(err);
    REQUIRE(text);
    CHECK(strstr(text, "--triangles") != NULL && strchr(text, '\n') == text + strlen(text) - 1);
    free(text);
}

/* Bad input: a clear error naming it, never a crash or a half-written
 * report. */
TEST(fw_poly_bad_input_is_a_clear_error)
{
    pp5_params_t p;
    machine_params(&p, 2, 2);
    poly_tri_in_t *t;
    raster_camera_t cam;
    REQUIRE(poly_scene_triangles(50, 100, 256, 256, 3u, &t, &cam) == PP5_OK);
    raster_style_t st;
    raster_style_default(&st, RASTER_GOURAUD);
    poly_options_t o;
    poly_options_default(&o);
    poly_session_t s;
    t[7].p[1][2] = NAN;
    CHECK(poly_session_init(&s, &p, t, 50, 256, 256, &cam, &st, &o) == PP5_E_RANGE);
    CHECK(strstr(pp5_error_text(), "triangle 7") != NULL);
    poly_session_free(&s);
    t[7].p[1][2] = -3;
    CHECK(poly_session_init(&s, &p, t, 50, 4096, 256, &cam, &st, &o) == PP5_E_RANGE);
    poly_session_free(&s);
    /* GP memory too small for the triangles: the firmware's own error */
    REQUIRE(pp5_params_set_kv(&p, "gp.local_mem_bytes=40000") == PP5_OK);
    pp5_status_t rc = poly_session_init(&s, &p, t, 50, 256, 256, &cam, &st, &o);
    poly_frame_result_t r;
    if (rc == PP5_OK)
        rc = poly_session_frame(&s, NULL, &r);
    CHECK(rc == PP5_E_FIRMWARE);
    poly_session_free(&s);
    free(t);
}

TEST(fw_poly_report_holds_the_frame)
{
    mesh_t m;
    REQUIRE(mesh_gen_cube(3, &m) == PP5_OK);
    raster_camera_t cam;
    raster_camera_fit(&m, 30, 25, 1.0, true, &cam);
    raster_style_t st;
    raster_style_default(&st, RASTER_GOURAUD);
    pp5_params_t p;
    machine_params(&p, 2, 2);
    poly_options_t o;
    poly_options_default(&o);
    poly_session_t s;
    REQUIRE(poly_session_init_mesh(&s, &p, &m, 128, 128, &cam, &st, &o) == PP5_OK);
    poly_frame_result_t r;
    image8_t img, ref;
    REQUIRE(poly_session_frame(&s, &img, &r) == PP5_OK);
    native_image(&m, 128, 128, &cam, &st, &ref);
    poly_compare_t c;
    REQUIRE(poly_compare_images(&img, &ref, BG, &c) == PP5_OK);
    char path[1200];
    snprintf(path, sizeof path, "%s/poly_report.json", pp5_test_outdir());
    REQUIRE(poly_report_write(path, &s, &r, "cube", &c) == PP5_OK);
    char *text = pp5_test_read_file(path);
    REQUIRE(text);
    CHECK(strstr(text, "\"triangles_per_s_pipelined\"") && strstr(text, "\"bottleneck\"") &&
          strstr(text, "\"rasterisation_cycles_total\"") && strstr(text, "\"image_vs_mesh_raster\""));
    CHECK_EQ(r.tris_in, (uint64_t)m.n_faces);
    CHECK(r.rn_exec_cycles_total > 0);
    CHECK_EQ(r.ring_bytes[RING_CLASS_PIXELS], 128u * 128 * 3 + p.ring_header_bytes);   /* one region, wire bytes */
    free(text);
    image8_free(&img);
    image8_free(&ref);
    poly_session_free(&s);
    mesh_free(&m);
}

/* A camera set between frames gives the image a fresh session with that
 * camera gives. */
TEST(fw_poly_camera_between_frames_equals_a_fresh_session)
{
    mesh_t m;
    REQUIRE(mesh_gen_torus(16, 8, 1.0, 0.4, &m) == PP5_OK);
    raster_camera_t c1, c2;
    raster_camera_fit(&m, 0, 10, 1.0, true, &c1);
    raster_camera_fit(&m, 70, 40, 1.0, true, &c2);
    raster_style_t st;
    raster_style_default(&st, RASTER_GOURAUD);
    pp5_params_t p;
    machine_params(&p, 2, 3);
    poly_options_t o;
    poly_options_default(&o);
    poly_session_t s;
    poly_frame_result_t r;
    image8_t a, b;
    REQUIRE(poly_session_init_mesh(&s, &p, &m, 128, 128, &c1, &st, &o) == PP5_OK);
    REQUIRE(poly_session_frame(&s, &a, &r) == PP5_OK);
    image8_free(&a);
    REQUIRE(poly_session_set_camera(&s, &c2) == PP5_OK);
    REQUIRE(poly_session_frame(&s, &a, &r) == PP5_OK);
    poly_session_free(&s);
    machine_image(&m, 128, 128, &c2, &st, POLY_GOURAUD, 2, 3, &b, NULL);
    CHECK(memcmp(a.pixels, b.pixels, (size_t)128 * 128 * 3) == 0);
    image8_free(&a);
    image8_free(&b);
    mesh_free(&m);
}

/* The PPs' Phong shading against float arithmetic: normals of lengths 0.5
 * to 1 in every direction (as interpolation leaves them), written straight
 * into PP memory, front and back, shaded by the stream; every PP's colour
 * within 1 of round(rgb (ambient + diffuse max(0, N.L / |N|))), clamped.
 * (Lengths below 1/2 are clamped by the stream: not tested.) */
TEST(fw_poly_phong_stream_matches_float_shading)
{
    pp5_params_t p;
    pp5_params_default(&p);
    renderer_t r;
    REQUIRE(renderer_init(&r, 0, &p.pp) == PP5_OK);
    const int n = 128 * 128;
    uint32_t *f[5], *out[3];
    for (int k = 0; k < 5; k++)
        REQUIRE((f[k] = calloc((size_t)n, sizeof *f[k])) != NULL);
    for (int k = 0; k < 3; k++)
        REQUIRE((out[k] = calloc((size_t)n, sizeof *out[k])) != NULL);
    double (*nv)[3] = malloc(sizeof *nv * (size_t)n);
    REQUIRE(nv != NULL);
    unsigned seed = 11u;
    for (int i = 0; i < n; i++) {
        double v[3], l2 = 0, len;
        do {
            l2 = 0;
            for (int k = 0; k < 3; k++) {
                seed = seed * 1103515245u + 12345u;
                v[k] = (double)(seed >> 8) / 8388608.0 - 1.0;
                l2 += v[k] * v[k];
            }
        } while (l2 < 1e-3 || l2 > 1);
        seed = seed * 1103515245u + 12345u;
        len = 0.5 + 0.5 * (double)(seed >> 8) / 16777216.0;
        for (int k = 0; k < 3; k++) {
            nv[i][k] = v[k] / sqrt(l2) * len;
            f[k][i] = (uint32_t)(int32_t)lrint(nv[i][k] * POLY_N_ONE) & 0xffffu;
        }
        f[3][i] = 1;               /* covered */
        f[4][i] = (unsigned)i & 1; /* back */
    }
    static const unsigned addr[5] = {POLY_PP_NX, POLY_PP_NY, POLY_PP_NZ, POLY_PP_COVER, POLY_PP_BACK};
    for (int k = 0; k < 5; k++)
        REQUIRE(renderer_write_field(&r, addr[k], k < 3 ? 16 : 1, f[k]) == PP5_OK);
    const float light[3] = {-0.4545f, 0.5555f, 0.6963f};
    const int32_t front[3] = {214, 208, 196}, back[3] = {150, 96, 84};
    pp_stream_t st;
    pp_stream_init(&st);
    poly_phong_stream(&st, light, 0.18f, 0.82f, front, back, false);
    REQUIRE(pp_stream_ok(&st));
    renderer_exec_result_t res;
    REQUIRE(renderer_execute(&r, st.words, st.n_words, &res) == PP5_OK);
    static const unsigned ch[3] = {POLY_PP_R, POLY_PP_G, POLY_PP_B};
    for (int k = 0; k < 3; k++)
        REQUIRE(renderer_read_field(&r, ch[k], 8, out[k]) == PP5_OK);
    int worst = 0;
    for (int i = 0; i < n; i++) {
        double len = sqrt(nv[i][0] * nv[i][0] + nv[i][1] * nv[i][1] + nv[i][2] * nv[i][2]);
        double d = (nv[i][0] * light[0] + nv[i][1] * light[1] + nv[i][2] * light[2]) / len;
        double in = 0.18 + 0.82 * (d > 0 ? d : 0);
        const int32_t *rgb = (i & 1) ? back : front;
        for (int k = 0; k < 3; k++) {
            double c = rgb[k] * in;
            int want = c >= 255 ? 255 : (int)(c + 0.5);
            int diff = abs((int)out[k][i] - want);
            worst = diff > worst ? diff : worst;
        }
    }
    CHECK_MSG(worst <= 1, "the PPs' Phong colour differs from float by up to %d", worst);
    pp_stream_free(&st);
    for (int k = 0; k < 5; k++)
        free(f[k]);
    for (int k = 0; k < 3; k++)
        free(out[k]);
    free(nv);
    renderer_free(&r);
}

/* The renderer's cycles by hand (emu/PP_ISA.md formulas, default PP
 * parameters: cycles_per_bit 1, alu_overhead 1, enable and flag ops 1, QEE
 * fill 16, 1 bit per clock): one Gouraud triangle inside one region, one
 * GP, one renderer.  Clear: EN_ALL 1 + SETI 24 bits (25) + SETI 24 (25) =
 * 51.  Triangle: EN_ALL 1; 3 edges x (QEE 16 + 31 + 1, F_LD 1, EN_ANDN 1)
 * = 150; depth QEE 16 + 8 + 24 = 48, CMP 25, EN_AND 1, COPY 25 = 99; 3
 * colour QEEs 16 + 16 + 8 = 40 each, 120.  In all 421. */
TEST(fw_poly_renderer_cycles_of_one_triangle_by_hand)
{
    const double xyz[9] = {20, 20, -2, 90, 30, -3, 40, 100, -4};
    mesh_t m;
    REQUIRE(mesh_alloc(&m, 3, 1) == PP5_OK);
    memcpy(m.pos, xyz, sizeof xyz);
    m.tri[0] = 0, m.tri[1] = 1, m.tri[2] = 2;
    raster_camera_t cam;
    raster_camera_ortho(0, 128, 0, 128, 0.5, 20, &cam);
    raster_style_t st;
    raster_style_default(&st, RASTER_GOURAUD);
    image8_t a;
    poly_frame_result_t r;
    machine_image(&m, 128, 128, &cam, &st, POLY_GOURAUD, 1, 1, &a, &r);
    CHECK_EQ(r.pairs_sent, 1);
    CHECK_EQ(r.edges_sent, 3);
    CHECK_EQ(r.rn_exec_cycles_total, 421);
    image8_free(&a);
    mesh_free(&m);
}
