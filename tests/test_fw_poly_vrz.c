/* test_fw_poly_vrz.c: gaze-directed polygon frames on the emulated machine (firmware/gp/poly_vrz.c): the variable-resolution Z-buffer's coarse levels drawn as smaller screens and resampled by the GPs.
 *
 * - With the full-resolution circle over the whole screen every pixel is at
 *   level 0, so the frame must be the full-resolution frame, byte for byte.
 * - The planned tiles must hold every texel render/'s mip map marks for the
 *   same gaze (the plan is conservative, never short), and leave some out.
 * - Against render/mesh's own variable-resolution Z-buffer on the same
 *   triangles: the same coverage within the snapping to 1/16 pixel (at most
 *   1 % of the covered pixels in one image only) and PSNR >= 30 dB (the
 *   fixed-point planes against render/'s doubles; the full-resolution
 *   machine frame of the same scene is within the same bounds).
 * - Fewer regions are drawn than at full resolution on a large screen. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "firmware/gp/poly_vrz_kernels.h"
#include "firmware/host/poly_report.h"
#include "firmware/host/poly_soup.h"
#include "firmware/host/poly_session.h"
#include "harness.h"
#include "render/gaze2d.h"
#include "render/mesh/mesh_gen.h"
#include "render/mesh/mesh_render.h"
#include "render/mip2d_row.h"

typedef struct {
    mesh_scene_t scene;
    mesh_soup_t soup;
    raster_camera_t cam;
    mesh_render_opts_t opts;
    gaze_model_t g;
    int w, h;
} vrz_scene_t;

static void scene_open(vrz_scene_t *v, int w, int h)
{
    memset(v, 0, sizeof *v);
    v->w = w, v->h = h;
    mesh_t m;
    REQUIRE(mesh_gen_torus(48, 24, 1.0, 0.4, &m) == PP5_OK);
    REQUIRE(mesh_scene_from_mesh(&m, &v->scene) == PP5_OK);
    REQUIRE(mesh_scene_flatten(&v->scene, NULL, &v->soup) == PP5_OK);
    mesh_scene_camera(&v->scene, (double)w / h, &v->cam);
    mesh_render_opts_from_scene(&v->scene, &v->cam, RASTER_GOURAUD, &v->opts);
    gaze_display_t d;
    gaze_display_defaults(&d);
    REQUIRE(gaze_model_init(&v->g, &d, w, h) == PP5_OK);
}

static void scene_close(vrz_scene_t *v)
{
    mesh_soup_free(&v->soup);
    mesh_scene_free(&v->scene);
}

/* One machine frame of the scene (vrz: gaze-directed at gx, gy). */
static void machine_frame(const vrz_scene_t *v, const gaze_model_t *g, bool vrz, double gx,
                          double gy, image8_t *img, poly_frame_result_t *r)
{
    pp5_params_t p;
    pp5_params_default(&p);
    p.n_gp = 4, p.n_renderers = 3;
    poly_tri_in_t *tris;
    REQUIRE(poly_triangles_from_soup(&v->soup, &tris) == PP5_OK);
    raster_style_t style;
    poly_options_t po;
    poly_style_from_render_opts(&v->opts, &v->soup, &style, &po);
    po.gaze = vrz, po.gaze_model = *g, po.gaze_x = gx, po.gaze_y = gy;
    poly_session_t s;
    REQUIRE_MSG(poly_session_init(&s, &p, tris, (size_t)v->soup.n_tris, v->w, v->h, &v->cam, &style,
                                  &po) == PP5_OK, "%s", pp5_error_text());
    free(tris);
    REQUIRE_MSG(poly_session_frame(&s, img, r) == PP5_OK, "%s", pp5_error_text());
    poly_session_free(&s);
}

TEST(fw_poly_vrz_with_the_sweet_spot_over_the_screen_is_the_full_resolution_frame)
{
    vrz_scene_t v;
    scene_open(&v, 300, 200);
    gaze_model_t g = v.g;
    g.r_zero_px = 1e7, g.r_max_px = 2e7;    /* every pixel inside the full-resolution circle */
    image8_t a = {0}, b = {0};
    poly_frame_result_t ra, rb;
    machine_frame(&v, &v.g, false, 0, 0, &a, &ra);
    machine_frame(&v, &g, true, 10, 190, &b, &rb);
    REQUIRE(a.width == b.width && a.height == b.height);
    CHECK_MSG(memcmp(a.pixels, b.pixels, (size_t)a.width * a.height * 3) == 0,
              "the gaze-directed frame with every pixel at level 0 differs from the full frame");
    CHECK_MSG(rb.regions_drawn == ra.regions_drawn, "regions %llu, full resolution %llu",
              (unsigned long long)rb.regions_drawn, (unsigned long long)ra.regions_drawn);
    CHECK(rb.texels_in == 300u * 200u);     /* each GP its own rows of level 0, once */
    image8_free(&a);
    image8_free(&b);
    scene_close(&v);
}

/* A GP state as poly_gp.c configures it (the session's own configuration),
 * its tiles planned. */
static void plan_state(poly_state_t *s, const gaze_model_t *g, int w, int h, double gx, double gy)
{
    memset(s, 0, sizeof *s);
    vrz_scene_t v;
    scene_open(&v, w, h);
    pp5_params_t p;
    pp5_params_default(&p);
    p.n_gp = 8, p.n_renderers = 1;   /* bands small enough for a GP's memory */
    raster_style_t style;
    poly_options_t po;
    poly_style_from_render_opts(&v.opts, &v.soup, &style, &po);
    po.gaze = true, po.gaze_model = *g, po.gaze_x = gx, po.gaze_y = gy;
    poly_tri_in_t none;
    memset(&none, 0, sizeof none);
    poly_session_t ses;
    REQUIRE_MSG(poly_session_init(&ses, &p, &none, 0, w, h, &v.cam, &style, &po) == PP5_OK, "%s",
                pp5_error_text());
    s->cfg = ses.cfg;
    poly_session_free(&ses);
    scene_close(&v);
    s->levels = s->cfg.levels2d;
    poly_levels_setup(s);
    s->slot_of = calloc((size_t)s->n_tiles, sizeof *s->slot_of);
    s->reg = calloc((size_t)s->n_tiles, sizeof *s->reg);
    REQUIRE(s->slot_of && s->reg);
    for (int l = 0; l < s->levels; l++)
        for (int ty = 0; ty < s->tiles_y[l]; ty++)
            for (int tx = 0; tx < s->tiles_x[l]; tx++)
                poly_plan_tile(s, l, tx, ty, NULL);
}

TEST(fw_poly_vrz_plan_holds_every_texel_render_marks)
{
    const int W = 1100, H = 700;
    gaze_display_t d;
    gaze_display_defaults(&d);
    gaze_model_t g;
    REQUIRE(gaze_model_init(&g, &d, W, H) == PP5_OK);
    REQUIRE_MSG(g.max_level >= 2, "the default model has %d levels", g.max_level + 1);
    const double gaze[3][2] = {{550.3, 350.7}, {0, 0}, {1099, 20.5}};
    float *row = malloc(sizeof *row * W);
    REQUIRE(row != NULL);
    gaze_level_tables_t tables;
    REQUIRE(gaze_level_tables_init(&tables, &g, W, H) == PP5_OK);
    for (int q = 0; q < 3; q++) {
        mip2d_t m;
        REQUIRE(mip2d_init(&m, W, H, g.max_level + 1) == PP5_OK);
        /* the texels of both 2DLevels: exact and by the paper's tables */
        for (int y = 0; y < H; y++) {
            gaze_level_row_reference(&g, y, W, gaze[q][0], gaze[q][1], 1.0, row);
            for (int x = 0; x < W; x++)
                mip2d_mark_pixel(&m, x, y, row[x]);
            gaze_level_row_tabled(&tables, y, W, gaze[q][0], gaze[q][1], 1.0, row);
            for (int x = 0; x < W; x++)
                mip2d_mark_pixel(&m, x, y, row[x]);
        }
        poly_state_t s;
        plan_state(&s, &g, W, H, gaze[q][0], gaze[q][1]);
        long missing = 0, marked_tiles = 0;
        for (int l = 0; l < m.levels; l++)
            for (int j = 0; j < m.h[l]; j++)
                for (int i = 0; i < m.w[l]; i++) {
                    if (!m.need[l][(size_t)j * m.w[l] + i])
                        continue;
                    bool inside = i < s.tw[l] && j < s.th[l];
                    int32_t slot = inside ? s.slot_of[s.tile_base[l] + (j / 128) * s.tiles_x[l] + i / 128] : -1;
                    missing += slot < 0;
                }
        for (int k = 0; k < s.n_tiles; k++)
            marked_tiles += s.slot_of[k] >= 0;
        CHECK_MSG(missing == 0, "gaze %g,%g: %ld marked texels outside the planned tiles",
                  gaze[q][0], gaze[q][1], missing);
        CHECK_MSG(marked_tiles < s.n_tiles, "gaze %g,%g: all %d tiles planned (no saving)", gaze[q][0],
                  gaze[q][1], s.n_tiles);
        free(s.slot_of);
        free(s.reg);
        mip2d_free(&m);
    }
    free(row);
    gaze_level_tables_free(&tables);
}

TEST(fw_poly_vrz_matches_render_mesh_vrz)
{
    vrz_scene_t v;
    scene_open(&v, 512, 384);
    const double gx = 140.5, gy = 120.0;
    image8_t a = {0}, b = {0}, fa = {0}, fb = {0};
    poly_frame_result_t r, rf;
    machine_frame(&v, &v.g, true, gx, gy, &a, &r);
    machine_frame(&v, &v.g, false, 0, 0, &fa, &rf);
    mesh_render_stats_t st;
    REQUIRE(mesh_render_vrz(&v.soup, &v.cam, &v.opts, &v.g, gx, gy, &b, &st) == PP5_OK);
    REQUIRE(mesh_render_full(&v.soup, &v.cam, &v.opts, v.w, v.h, &fb, &st) == PP5_OK);
    poly_compare_t c, cf;
    REQUIRE(poly_compare_images(&a, &b, v.opts.background, &c) == PP5_OK);
    REQUIRE(poly_compare_images(&fa, &fb, v.opts.background, &cf) == PP5_OK);
    CHECK_MSG(c.covered_native > 20000, "the torus covers %ld pixels", c.covered_native);
    CHECK_MSG(c.covered_one_only * 100 <= c.covered_native, "%ld of %ld covered pixels in one image only",
              c.covered_one_only, c.covered_native);
    CHECK_MSG(c.psnr_db >= 30.0, "PSNR %.2f dB against render/mesh's VRZ", c.psnr_db);
    CHECK_MSG(cf.covered_one_only * 100 <= cf.covered_native && cf.psnr_db >= 30.0,
              "the full-resolution frames: %ld of %ld, %.2f dB", cf.covered_one_only,
              cf.covered_native, cf.psnr_db);
    /* the coarse levels are drawn: more than level 0's populated tiles */
    CHECK_MSG(r.regions_drawn > 0 && r.cycles_resample > 0 && r.texels_in > 0,
              "regions %llu, resampling cycles %llu", (unsigned long long)r.regions_drawn,
              (unsigned long long)r.cycles_resample);
    image8_free(&a), image8_free(&b), image8_free(&fa), image8_free(&fb);
    scene_close(&v);
}

TEST(fw_poly_vrz_draws_fewer_regions_than_full_resolution_on_a_large_screen)
{
    vrz_scene_t v;
    scene_open(&v, 1024, 768);
    poly_frame_result_t r, rf;
    image8_t a = {0}, fa = {0};
    machine_frame(&v, &v.g, true, 100, 100, &a, &r);
    machine_frame(&v, &v.g, false, 0, 0, &fa, &rf);
    CHECK(rf.regions_drawn == 8 * 6);
    CHECK_MSG(r.regions_drawn < rf.regions_drawn, "gaze-directed %llu regions, full %llu",
              (unsigned long long)r.regions_drawn, (unsigned long long)rf.regions_drawn);
    image8_free(&a), image8_free(&fa);
    scene_close(&v);
}
