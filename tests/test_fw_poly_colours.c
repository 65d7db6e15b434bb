/* test_fw_poly_colours.c: a scene's objects keep their own colours on the emulated machine (poly_tri_in_t.rgb; Phong shades them per pixel in the PPs), for flat, Gouraud and Phong, against the native polygon renderer on the same triangles.
 *
 * The scene: a red sphere on the left, a smaller blue one on the right (an
 * instance of the same mesh), no
 * specular term (the pipeline lights ambient + diffuse).  At each object's
 * centre pixel the machine's colour must be the native one within 6 per
 * channel (the fixed-point planes and screen-linear Gouraud), the two
 * objects' colours must differ as the scene says (red against blue), and
 * the whole image must be within 30 dB. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "firmware/host/poly_report.h"
#include "firmware/host/poly_soup.h"
#include "harness.h"
#include "render/mesh/mesh_render.h"
#include "render/mesh/mesh_scene.h"

static const char SCENE[] =
    "mesh gen:sphere\n"
    "translate -1.3 0 0\n"
    "colour 0.9 0.15 0.1\n"
    "mesh gen:sphere\n"
    "scale 0.8\n"
    "translate 1.3 0 0\n"
    "colour 0.1 0.2 0.85\n"
    "camera 0 0 6 0 0 0 40\n"
    "light 0.3 0.5 1 0.2 0.8\n";

static void pixel(const image8_t *im, int x, int y, int rgb[3])
{
    const uint8_t *p = im->pixels + 3 * ((size_t)y * (size_t)im->width + (size_t)x);
    rgb[0] = p[0], rgb[1] = p[1], rgb[2] = p[2];
}

TEST(fw_poly_scene_objects_keep_their_colours_on_the_machine)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/two.scene", pp5_test_outdir());
    FILE *f = fopen(path, "w");
    REQUIRE(f != NULL);
    fputs(SCENE, f);
    REQUIRE(fclose(f) == 0);
    mesh_scene_t scene;
    REQUIRE_MSG(mesh_scene_load(path, &scene) == PP5_OK, "%s", pp5_error_text());
    mesh_soup_t soup;
    REQUIRE(mesh_scene_flatten(&scene, NULL, &soup) == PP5_OK);
    const int W = 320, H = 160;
    raster_camera_t cam;
    mesh_scene_camera(&scene, (double)W / H, &cam);
    const raster_shading_t shadings[3] = {RASTER_FLAT, RASTER_GOURAUD, RASTER_PHONG};
    for (int k = 0; k < 3; k++) {
        mesh_render_opts_t o;
        mesh_render_opts_from_scene(&scene, &cam, shadings[k], &o);
        image8_t native = {0}, img = {0};
        mesh_render_stats_t st;
        REQUIRE(mesh_render_full(&soup, &cam, &o, W, H, &native, &st) == PP5_OK);
        poly_tri_in_t *tris;
        REQUIRE(poly_triangles_from_soup(&soup, &tris) == PP5_OK);
        raster_style_t style;
        poly_options_t po;
        poly_style_from_render_opts(&o, &soup, &style, &po);
        pp5_params_t p;
        pp5_params_default(&p);
        p.n_gp = 3, p.n_renderers = 2;
        poly_session_t s;
        REQUIRE_MSG(poly_session_init(&s, &p, tris, (size_t)soup.n_tris, W, H, &cam, &style, &po) ==
                    PP5_OK, "%s", pp5_error_text());
        free(tris);
        poly_frame_result_t r;
        REQUIRE(poly_session_frame(&s, &img, &r) == PP5_OK);
        poly_session_free(&s);
        /* the objects' centres: world x = -1.3 and 1.3 at depth 6, fovy 40 */
        int cx[2] = {W / 2 - (int)(1.3 / (6 * 0.36397) * H / 2 + 0.5),
                     W / 2 + (int)(1.3 / (6 * 0.36397) * H / 2 + 0.5)};
        int m[2][3], n[2][3];
        for (int obj = 0; obj < 2; obj++) {
            pixel(&img, cx[obj], H / 2, m[obj]);
            pixel(&native, cx[obj], H / 2, n[obj]);
            for (int c = 0; c < 3; c++)
                CHECK_MSG(abs(m[obj][c] - n[obj][c]) <= 6, "shading %d object %d channel %d: "
                          "machine %d, native %d", k, obj, c, m[obj][c], n[obj][c]);
        }
        CHECK_MSG(m[0][0] > m[0][2] + 40 && m[1][2] > m[1][0] + 40,
                  "shading %d: the left sphere (%d,%d,%d) should be red, the right (%d,%d,%d) blue", k,
                  m[0][0], m[0][1], m[0][2], m[1][0], m[1][1], m[1][2]);
        poly_compare_t cmp;
        REQUIRE(poly_compare_images(&img, &native, o.background, &cmp) == PP5_OK);
        CHECK_MSG(cmp.psnr_db >= 30.0, "shading %d: PSNR %.2f dB", k, cmp.psnr_db);
        image8_free(&img);
        image8_free(&native);
    }
    mesh_soup_free(&soup);
    mesh_scene_free(&scene);
}
