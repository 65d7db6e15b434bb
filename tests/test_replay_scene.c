/* test_replay_scene.c: a polygon scene as the replay's frame-cost source
 * (firmware/host/replay_poly_machine.c, `pp5 replay --scene/--mesh`): frames
 * come from the emulated machine, a replayed frame is the frame a fresh
 * session draws from the same list, the level of detail follows the gaze as
 * the rule of render/mesh/mesh_lod.h says, and bad input exits as the
 * exit-code table says.
 *
 * The scene: one UV sphere (gen:sphere, radius 1, 760 faces) seen from 10
 * units by a 40-degree camera in a 64x64 image, on the paper's display
 * (1280x1024 px).  Its bounding sphere (box centre, half diagonal) has
 * radius sqrt(3); the rule's screen radius is sqrt(3) / (10 tan 20 deg) x 32
 * = 15.2 px.  Gaze at the display centre: the image centre, on the sphere:
 * eccentricity 0, budget 2 pi 15.2^2 = 1457 faces >= 760, full detail.
 * Gaze at the display's top-left corner: image point (0, 6.4) (scale 64 /
 * 1280 about the centre), 41.0 px from the sphere's centre, 25.7 px from its
 * rim; 64 px span 37 deg at 20 in, so 25.7 px = 5.4 in, atan(5.4 / 20) =
 * 15 deg, beyond the 10 deg periphery radius: 1/16 sample per pixel, budget
 * 91 faces < 760, a coarser level. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "firmware/host/poly_soup.h"
#include "firmware/host/replay_poly_machine.h"
#include "harness.h"
#include "render/mesh/mesh_lod.h"
#include "tracker/angles.h"
#include "tracker/replay.h"

static const double PI = 3.14159265358979323846;
#define SPHERE_FACES 760   /* mesh_gen.h: a 20x20 UV sphere has 760 faces */

static const replay_cost_source_t *poly_source(void)
{
    const replay_cost_source_t *cs = replay_find_cost_source("polygons");
    REQUIRE_MSG(cs != NULL, "the firmware registers the 'polygons' frame-cost source");
    return cs;
}

/* The scene file of the file comment, in this test's folder. */
static const char *write_scene(void)
{
    static char path[1024];
    snprintf(path, sizeof path, "%s/sphere.scene", pp5_test_outdir());
    FILE *f = fopen(path, "w");
    REQUIRE(f != NULL);
    fprintf(f, "mesh gen:sphere\ncamera 0 0 10 0 0 0 40\n");
    REQUIRE(fclose(f) == 0);
    return path;
}

/* The polygons source on the fixture scene, 64x64, with more options. */
static void *open_scene(const char *more)
{
    gaze_geometry_t display;
    angles_paper_geometry(&display);
    char opts[1400];
    snprintf(opts, sizeof opts, "scene=%s,size=64x64,%s", write_scene(), more);
    void *ctx = NULL;
    REQUIRE_MSG(poly_source()->open(opts, &display, &ctx) == PP5_OK, "%s", pp5_error_text());
    return ctx;
}

TEST(replay_scene_geometry_of_the_fixture_by_hand)
{
    /* The hand derivation of the file comment, step by step, so that the
     * expectations of the tests below rest on checked numbers. */
    double r_px = sqrt(3.0) / (10 * tan(20 * PI / 180)) * 32;
    CHECK_NEAR(r_px, 15.23, 0.01);
    CHECK(2 * PI * r_px * r_px >= SPHERE_FACES);
    double gx = (0 - 640) * (64.0 / 1280) + 32, gy = (0 - 512) * (64.0 / 1280) + 32;
    double rim = hypot(32 - gx, 32 - gy) - r_px;
    double inch_per_px = 2 * 20 * tan(18.5 * PI / 180) / 64;
    double e_deg = atan(rim * inch_per_px / 20) * 180 / PI;
    CHECK_MSG(e_deg > 10, "corner gaze at %.1f deg from the sphere's rim", e_deg);
    CHECK(2 * PI * r_px * r_px / 16 < SPHERE_FACES);
}

TEST(replay_scene_frames_come_from_the_machine)
{
    /* A few GP and renderer counts: every frame takes positive emulated
     * time and moves ring bytes; a changed list carries at least its
     * triangles' payload (72 bytes each: 3 corners x position and normal,
     * 3 floats each) over the ring, inside that frame's bytes. */
    const replay_cost_source_t *cs = poly_source();
    static const char *const machines[] = {"gp.count=1,renderer.count=1",
                                           "gp.count=2,renderer.count=2",
                                           "gp.count=3,set=renderer.count=4"};
    for (int m = 0; m < 3; m++) {
        void *ctx = open_scene(machines[m]);
        static const double gaze[3][2] = {{640, 512}, {0, 0}, {640, 512}};
        for (int k = 0; k < 3; k++) {
            replay_frame_cost_t c = {.want_image = false};
            REQUIRE_MSG(cs->cost(ctx, gaze[k][0], gaze[k][1], &c) == PP5_OK, "%s",
                        pp5_error_text());
            replay_poly_frame_info_t info;
            REQUIRE(replay_poly_last_frame(ctx, &info) == PP5_OK);
            CHECK_MSG(c.frame_s > 0 && isfinite(c.frame_s), "%s frame %d: %g s", machines[m], k,
                      c.frame_s);
            CHECK(c.ring_bytes > 0 && c.image == NULL);
            CHECK_EQ(info.list_changed, k > 0);   /* full, coarse, full again */
            if (info.list_changed)
                CHECK(info.upload_ring_bytes >= 72 * info.triangles &&
                      c.ring_bytes > info.upload_ring_bytes);
        }
        cs->close(ctx);
    }
}

TEST(replay_scene_frame_time_is_the_machines_cycles)
{
    /* GPs at half their clock make a slower frame: the time comes from the
     * cycles the machine model counts, not from a constant. */
    const replay_cost_source_t *cs = poly_source();
    gaze_geometry_t display;
    angles_paper_geometry(&display);
    double frame[2];
    for (int k = 0; k < 2; k++) {
        void *ctx = NULL;
        const char *opts = k ? "mesh=gen:torus,size=64x64,gp.count=2,gp.clock_hz=20e6"
                             : "mesh=gen:torus,size=64x64,gp.count=2";
        REQUIRE_MSG(cs->open(opts, &display, &ctx) == PP5_OK, "%s", pp5_error_text());
        replay_frame_cost_t c = {.want_image = false};
        REQUIRE(cs->cost(ctx, 640, 512, &c) == PP5_OK);
        frame[k] = c.frame_s;
        cs->close(ctx);
    }
    CHECK_MSG(frame[1] > frame[0], "20 MHz GPs %g s, 40 MHz %g s", frame[1], frame[0]);
}

/* The frame a fresh session draws for the list the levels rule gives at
 * image point (ix, iy) (pixel indices); *n_tris its triangles. */
static void direct_frame(const char *scene_path, double ix, double iy, bool vrz, image8_t *img,
                         int *n_tris)
{
    mesh_scene_t scene;
    REQUIRE(mesh_scene_load(scene_path, &scene) == PP5_OK);
    raster_camera_t cam;
    mesh_scene_camera(&scene, 1.0, &cam);
    mesh_render_opts_t ro;
    mesh_render_opts_from_scene(&scene, &cam, RASTER_GOURAUD, &ro);
    gaze_display_t d;
    gaze_display_defaults(&d);
    gaze_model_t g;
    REQUIRE(gaze_model_init(&g, &d, 64, 64) == PP5_OK);
    REQUIRE(mesh_scene_build_records(&scene) == PP5_OK);
    int levels[1];
    long faces;
    mesh_lod_choose(&scene, &cam, &g, ix, iy, levels, &faces);
    mesh_soup_t soup = {0};
    REQUIRE(mesh_scene_flatten(&scene, levels, &soup) == PP5_OK);
    poly_tri_in_t *tris;
    REQUIRE(poly_triangles_from_soup(&soup, &tris) == PP5_OK);
    raster_style_t style;
    poly_options_t po;
    poly_style_from_render_opts(&ro, &soup, &style, &po);
    po.gaze = vrz, po.gaze_model = g, po.gaze_x = ix, po.gaze_y = iy;
    pp5_params_t p;
    pp5_params_default(&p);
    p.n_gp = 2, p.n_renderers = 2;
    poly_session_t s;
    REQUIRE_MSG(poly_session_init(&s, &p, tris, (size_t)soup.n_tris, 64, 64, &cam, &style, &po) ==
                PP5_OK, "%s", pp5_error_text());
    poly_frame_result_t r;
    REQUIRE(poly_session_frame(&s, img, &r) == PP5_OK);
    *n_tris = soup.n_tris;
    poly_session_free(&s);
    free(tris);
    mesh_soup_free(&soup);
    mesh_scene_free(&scene);
}

TEST(replay_scene_image_equals_a_direct_session_frame)
{
    /* Near, far, near: the far frame draws a replacement list, the last one
     * the full list sent again; each is bit for bit the frame a fresh
     * session draws from that list.  The far list is coarser (file
     * comment): fewer triangles than the mesh's 760. */
    const replay_cost_source_t *cs = poly_source();
    void *ctx = open_scene("shading=gouraud,gp.count=2,renderer.count=2");
    const char *scene = write_scene();
    /* display -> image pixel indices: scale 64/1280 about the centre, less
     * half a pixel (pixel x spans x .. x + 1) */
    static const double gaze[3][2] = {{640, 512}, {0, 0}, {640, 512}};
    size_t tris[3];
    for (int k = 0; k < 3; k++) {
        replay_frame_cost_t c = {.want_image = true};
        REQUIRE(cs->cost(ctx, gaze[k][0], gaze[k][1], &c) == PP5_OK);
        REQUIRE(c.image != NULL && c.image->width == 64 && c.image->height == 64);
        replay_poly_frame_info_t info;
        REQUIRE(replay_poly_last_frame(ctx, &info) == PP5_OK);
        tris[k] = info.triangles;
        image8_t direct = {0};
        int n_direct = 0;
        direct_frame(scene, (gaze[k][0] - 640) * 0.05 + 31.5, (gaze[k][1] - 512) * 0.05 + 31.5,
                     false, &direct, &n_direct);
        CHECK_EQ(info.triangles, n_direct);
        CHECK_MSG(memcmp(direct.pixels, c.image->pixels, 64 * 64 * 3) == 0,
                  "frame %d: the replayed image differs from the direct session's", k);
        image8_free(&direct);
    }
    CHECK_EQ(tris[0], SPHERE_FACES);
    CHECK_MSG(tris[1] < SPHERE_FACES && tris[1] > 0, "far from the sphere: %zu triangles",
              tris[1]);
    CHECK_EQ(tris[2], SPHERE_FACES);
    cs->close(ctx);
}

/* vrz=on: each frame is a fresh session's gaze-directed frame (the same
 * list, the variable-resolution Z-buffer with the sweet spot at the gaze),
 * and far from the sphere it is not the full-resolution frame. */
TEST(replay_scene_vrz_frames_are_the_sessions_gaze_directed_frames)
{
    const replay_cost_source_t *cs = poly_source();
    void *ctx = open_scene("shading=gouraud,gp.count=2,renderer.count=2,vrz=on");
    const char *scene = write_scene();
    static const double gaze[2][2] = {{640, 512}, {0, 0}};
    for (int k = 0; k < 2; k++) {
        replay_frame_cost_t c = {.want_image = true};
        REQUIRE(cs->cost(ctx, gaze[k][0], gaze[k][1], &c) == PP5_OK);
        REQUIRE(c.image != NULL && c.image->width == 64 && c.image->height == 64);
        double ix = (gaze[k][0] - 640) * 0.05 + 31.5, iy = (gaze[k][1] - 512) * 0.05 + 31.5;
        image8_t vrz = {0}, full = {0};
        int n = 0;
        direct_frame(scene, ix, iy, true, &vrz, &n);
        direct_frame(scene, ix, iy, false, &full, &n);
        CHECK_MSG(memcmp(vrz.pixels, c.image->pixels, 64 * 64 * 3) == 0,
                  "frame %d: the replayed image differs from the session's gaze-directed frame", k);
        if (k == 1)
            CHECK_MSG(memcmp(full.pixels, c.image->pixels, 64 * 64 * 3) != 0,
                      "far from the sphere the gaze-directed frame is the full-resolution one");
        image8_free(&vrz);
        image8_free(&full);
    }
    cs->close(ctx);
}

TEST(replay_scene_lod_off_keeps_full_detail)
{
    const replay_cost_source_t *cs = poly_source();
    void *ctx = open_scene("lod=off,gp.count=2");
    replay_frame_cost_t c = {.want_image = false};
    REQUIRE(cs->cost(ctx, 640, 512, &c) == PP5_OK);
    REQUIRE(cs->cost(ctx, 0, 0, &c) == PP5_OK);
    replay_poly_frame_info_t info;
    REQUIRE(replay_poly_last_frame(ctx, &info) == PP5_OK);
    CHECK_EQ(info.triangles, SPHERE_FACES);
    CHECK(!info.list_changed && info.upload_ring_bytes == 0);
    cs->close(ctx);
}

TEST(replay_scene_cli_runs_a_synthetic_trace)
{
    const char *dir = pp5_test_outdir();
    const char *scene = write_scene();
    char args[3000], out[1100], err[1100], csv[1100];
    snprintf(out, sizeof out, "%s/out.txt", dir);
    snprintf(err, sizeof err, "%s/err.txt", dir);
    snprintf(csv, sizeof csv, "%s/frames.csv", dir);
    snprintf(args, sizeof args, "trace synth --mode saccades --seconds 0.6 --rate 250 --out %s/t.trace",
             dir);
    REQUIRE(pp5_test_run_cli(args, out, err) == 0);
    snprintf(args, sizeof args, "replay %s/t.trace --scene %s --cost polygons:size=64x64,"
             "gp.count=2,renderer.count=2 --max-frames 6 --csv %s", dir, scene, csv);
    REQUIRE_MSG(pp5_test_run_cli(args, out, err) == 0, "pp5 %s failed", args);
    FILE *f = fopen(csv, "r");
    REQUIRE(f != NULL);
    char line[1024];
    int frames = 0;
    REQUIRE(fgets(line, sizeof line, f) != NULL);   /* header */
    while (fgets(line, sizeof line, f)) {
        /* frame_ms is the 16th column, ring_bytes the 18th */
        char *tok = strtok(line, ",");
        double frame_ms = 0, ring = 0;
        for (int col = 1; tok; col++, tok = strtok(NULL, ",")) {
            if (col == 16)
                frame_ms = atof(tok);
            if (col == 18)
                ring = atof(tok);
        }
        CHECK(frame_ms > 0 && ring > 0);
        frames++;
    }
    fclose(f);
    CHECK(frames >= 2);
    f = fopen(out, "r");
    REQUIRE(f != NULL);
    bool told = false;
    while (fgets(line, sizeof line, f))
        told |= strstr(line, "triangle list changed before") != NULL;
    fclose(f);
    CHECK_MSG(told, "the summary says how often the triangle list changed");
}

TEST(replay_scene_bad_input_exits_as_the_table_says)
{
    const char *dir = pp5_test_outdir();
    char args[3000], path[1100], trace[1100], err[1100];
    snprintf(trace, sizeof trace, "%s/t.trace", dir);
    snprintf(err, sizeof err, "%s/err.txt", dir);
    snprintf(args, sizeof args, "trace synth --mode pursuit --seconds 0.2 --rate 250 --out %s",
             trace);
    REQUIRE(pp5_test_run_cli(args, NULL, NULL) == 0);
    struct { const char *content, *opts; int rc; } cases[] = {
        {NULL, "--scene %s/missing.scene", 4},               /* cannot be read: i/o */
        {"mesh\n", "--scene %s", 3},                         /* malformed: bad input */
        {"background 0 0 0\n", "--scene %s", 3},             /* no triangles: bad input */
        {"v 0 0 0\nv 1 0 0\n", "--mesh %s", 3},              /* a mesh without faces */
        {"mesh gen:sphere\n", "--cost polygons:scene=%s,bogus", 2},      /* usage */
        {"mesh gen:sphere\n", "--cost polygons:scene=%s,lod=maybe", 2},
        {"mesh gen:sphere\n", "--scene %s --cost machine", 2},
        {"mesh gen:sphere\n", "--scene %s --mesh gen:sphere", 2},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        if (cases[i].content) {
            snprintf(path, sizeof path, "%s/case%zu.%s", dir, i,
                     strncmp(cases[i].content, "v ", 2) == 0 ? "obj" : "scene");
            FILE *f = fopen(path, "w");
            REQUIRE(f != NULL);
            fputs(cases[i].content, f);
            REQUIRE(fclose(f) == 0);
        } else {
            snprintf(path, sizeof path, "%s", dir);
        }
        char opts[1300];
        snprintf(opts, sizeof opts, cases[i].opts, path);
        snprintf(args, sizeof args, "replay %s %s --max-frames 2", trace, opts);
        int rc = pp5_test_run_cli(args, NULL, err);
        CHECK_MSG(rc == cases[i].rc, "pp5 %s: exit %d, expected %d", args, rc, cases[i].rc);
        FILE *f = fopen(err, "r");
        REQUIRE(f != NULL);
        char line[1024] = "", extra[8];
        bool one = fgets(line, sizeof line, f) != NULL && !fgets(extra, sizeof extra, f);
        fclose(f);
        CHECK_MSG(one && strncmp(line, "pp5 replay: ", 12) == 0, "pp5 %s: one error line, got "
                  "'%s'", args, line);
    }
}
