/* test_mesh_scene.c: scene files (statements, instancing, relative paths,
 * one-line errors naming file and line), the built-in scene, flattening
 * (counts, unit normals, mirrored transforms), levels of detail by
 * eccentricity, and `pp5 render --mesh/--scene`. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "render/mesh/mesh_gen.h"
#include "render/mesh/mesh_lod.h"
#include "render/mesh/mesh_scene.h"

/* Writes text into dir/name (dir: this test's pp5_test_outdir(), asked
 * once, as asking clears the folder). */
static const char *write_text(const char *dir, const char *name, const char *text)
{
    static char path[4][1200];
    static int k;
    char *p = path[k++ % 4];
    snprintf(p, 1200, "%s/%s", dir, name);
    FILE *f = fopen(p, "w");
    REQUIRE(f);
    fputs(text, f);
    fclose(f);
    return p;
}

TEST(mesh_scene_file_places_instances_and_reads_every_statement)
{
    mesh_t cube;
    REQUIRE(mesh_gen_cube(2, &cube) == PP5_OK);
    char off[1200];
    const char *dir = pp5_test_outdir();
    snprintf(off, sizeof off, "%s/scene_cube.off", dir);
    REQUIRE(mesh_save(off, &cube) == PP5_OK);
    const char *path = write_text(dir, "two.scene",
                                  "# two spheres and a cube\n"
                                  "mesh gen:sphere\n"
                                  "  scale 2\n  translate 10 0 0   # after the scale\n"
                                  "  colour 1 0 0\n"
                                  "mesh gen:sphere\n  rotate 90 0 0 1\n  translate 0 5 0\n"
                                  "mesh scene_cube.off\n  scale 1 2 -1\n"
                                  "camera 0 0 30 0 0 0 50\n"
                                  "light 0 1 0 0.1 0.9 0.5 16\n"
                                  "background 0 0 0.5\n");
    mesh_scene_t s;
    REQUIRE(mesh_scene_load(path, &s) == PP5_OK);
    CHECK_EQ(s.n_objects, 3);
    CHECK_EQ(s.n_meshes, 2);   /* gen:sphere once, instanced */
    /* object 0: p -> 2 p + (10, 0, 0); its pole (0, 0, 1) lands on (10, 0, 2) */
    const double *x = s.objects[0].xform;
    CHECK_NEAR(x[0], 2, 1e-12);
    CHECK_NEAR(x[3], 10, 1e-12);
    CHECK_NEAR(x[2] * 0 + x[10] * 1 + x[11], 2, 1e-12);
    CHECK(s.objects[0].rgb[0] == 1 && s.objects[0].rgb[1] == 0);
    /* object 1: 90 degrees about z takes (1, 0, 0) to (0, 1, 0), then +5 y */
    x = s.objects[1].xform;
    CHECK_NEAR(x[4] * 1 + x[7], 6, 1e-12);
    CHECK_NEAR(x[0], 0, 1e-12);
    CHECK(s.have_camera && s.fovy_deg == 50 && s.eye[2] == 30);
    CHECK(s.ambient == 0.1 && s.diffuse == 0.9 && s.specular == 0.5 && s.shininess == 16);
    CHECK(s.background[2] == 0.5);
    /* flattening: every face once; unit normals; the mirrored cube (scale
     * z by -1) keeps its normals pointing out of its faces' winding */
    mesh_soup_t soup;
    REQUIRE(mesh_scene_flatten(&s, NULL, &soup) == PP5_OK);
    CHECK_EQ(soup.n_tris, 2 * s.meshes[0].mesh.n_faces + cube.n_faces);
    int bad_len = 0, bad_dir = 0;
    for (int t = 0; t < soup.n_tris; t++) {
        const double *p = soup.pos + 9 * t, *n = soup.nrm + 9 * t;
        double e1[3] = {p[3] - p[0], p[4] - p[1], p[5] - p[2]}, e2[3] = {p[6] - p[0], p[7] - p[1],
                                                                        p[8] - p[2]};
        double g[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                       e1[0] * e2[1] - e1[1] * e2[0]};
        for (int c = 0; c < 3; c++) {
            const double *nc = n + 3 * c;
            bad_len += fabs(sqrt(nc[0] * nc[0] + nc[1] * nc[1] + nc[2] * nc[2]) - 1) > 1e-9;
            bad_dir += g[0] * nc[0] + g[1] * nc[1] + g[2] * nc[2] <= 0;
        }
    }
    CHECK_EQ(bad_len, 0);
    CHECK_EQ(bad_dir, 0);
    mesh_soup_free(&soup);
    mesh_scene_free(&s);
    mesh_free(&cube);
}

/* Loading `text` fails with a one-line message holding `want`. */
static void fails_with(const char *dir, const char *text, const char *want)
{
    const char *path = write_text(dir, "bad.scene", text);
    mesh_scene_t s;
    pp5_status_t st = mesh_scene_load(path, &s);
    CHECK_MSG(st != PP5_OK, "accepted: %s", text);
    const char *msg = pp5_error_text();
    CHECK_MSG(strstr(msg, want) != NULL, "'%s' lacks '%s'", msg, want);
    CHECK(strchr(msg, '\n') == NULL);
}

TEST(mesh_scene_file_errors_name_the_file_and_line)
{
    const char *d = pp5_test_outdir();
    fails_with(d, "mesh gen:sphere\nspin 3\n", "bad.scene:2: unknown statement 'spin'");
    fails_with(d, "translate 1 2 3\n", "bad.scene:1: a transform before any 'mesh' line");
    fails_with(d, "mesh gen:sphere\n\nscale 1 nan 1\n", "bad.scene:3: scale: 'nan'");
    fails_with(d, "mesh gen:sphere\nscale 0\n", "bad.scene:2: scale: a factor of zero");
    fails_with(d, "mesh gen:sphere\ntranslate 1 2\n", "bad.scene:2: translate takes X Y Z");
    fails_with(d, "mesh gen:sphere\ncolour 2 0 0\n", "bad.scene:2: colours are");
    fails_with(d, "mesh gen:sphere\nrotate 10 0 0 0\n", "bad.scene:2: rotate: the axis is zero");
    fails_with(d, "mesh gen:sphere\ncamera 1 1 1 1 1 1\n", "bad.scene:2: camera: the eye");
    fails_with(d, "mesh gen:sphere\nlight 0 0 0\n", "bad.scene:2: light: the direction is zero");
    fails_with(d, "# nothing\n", "bad.scene: no 'mesh' line");
    fails_with(d, "\n\nmesh no_such_file.obj\n", "bad.scene:3: ");
    fails_with(d, "\n\nmesh no_such_file.obj\n", "no_such_file.obj");
    fails_with(d, "mesh gen:teapot\n", "bad.scene:1: gen:teapot: unknown generated mesh");
    mesh_scene_t s;
    CHECK(mesh_scene_load("gen:nothing", &s) == PP5_E_CONFIG);
}

TEST(mesh_scene_builtin_has_100k_triangles_from_two_meshes)
{
    mesh_scene_t s;
    REQUIRE(mesh_scene_builtin("gen:spheres100k", &s) == PP5_OK);
    CHECK_EQ(s.n_objects, 100);
    CHECK_EQ(s.n_meshes, 2);
    CHECK_EQ(s.meshes[0].mesh.n_faces, 1000);
    CHECK_EQ(s.meshes[1].mesh.n_faces, 1000);
    mesh_soup_t soup;
    REQUIRE(mesh_scene_flatten(&s, NULL, &soup) == PP5_OK);
    CHECK_EQ(soup.n_tris, 100000);
    mesh_soup_free(&soup);
    mesh_scene_free(&s);
}

TEST(mesh_lod_gives_fewer_faces_away_from_the_gaze)
{
    mesh_scene_t s;
    REQUIRE(mesh_scene_builtin("gen:spheres100k", &s) == PP5_OK);
    REQUIRE(mesh_scene_build_records(&s) == PP5_OK);
    raster_camera_t cam;
    mesh_scene_camera(&s, 640.0 / 480, &cam);
    gaze_display_t d;
    gaze_display_defaults(&d);
    gaze_model_t g;
    REQUIRE(gaze_model_init(&g, &d, 640, 480) == PP5_OK);
    int levels[100];
    long faces_centre, faces_corner;
    mesh_lod_choose(&s, &cam, &g, 319.5, 239.5, levels, &faces_centre);
    /* objects k = 44, 45, 54, 55 sit around the centre: full detail there */
    CHECK(levels[44] == 0 && levels[55] == 0);
    /* the corner objects (0 and 99) lie in the periphery: coarser */
    CHECK(levels[0] > 0 && levels[99] > 0);
    CHECK(faces_centre < 100000 && faces_centre > 1000);
    /* the same scene with the gaze in a corner: object 0 refined, 55 coarsened */
    mesh_lod_choose(&s, &cam, &g, 10, 470, levels, &faces_corner);
    int l0 = levels[0];
    mesh_lod_choose(&s, &cam, &g, 319.5, 239.5, levels, &faces_centre);
    CHECK(l0 < levels[0]);
    /* a sweet spot covering the screen: every object at full detail only where
     * its screen size allows more than its faces (none here is that small) */
    d.full_res_diameter_deg = 150, d.periphery_diameter_deg = 158;
    REQUIRE(gaze_model_init(&g, &d, 640, 480) == PP5_OK);
    long faces_all;
    mesh_lod_choose(&s, &cam, &g, 319.5, 239.5, levels, &faces_all);
    CHECK(faces_all > faces_centre);
    mesh_scene_free(&s);
}

TEST(mesh_cli_render_scene_writes_image_and_report_and_refuses_cleanly)
{
    char out[1200], err[1200], png[1200], rep[1200], args[4000];
    const char *dir = pp5_test_outdir();
    snprintf(out, sizeof out, "%s/rs_out.txt", dir);
    snprintf(err, sizeof err, "%s/rs_err.txt", dir);
    snprintf(png, sizeof png, "%s/rs.png", dir);
    snprintf(rep, sizeof rep, "%s/rs.json", dir);
    snprintf(args, sizeof args, "render --scene gen:spheres100k --size 96x72 --mode gaze "
             "--compare --shading phong --out %s --report %s", png, rep);
    CHECK_EQ(pp5_test_run_cli(args, out, err), 0);
    image8_t img;
    REQUIRE(png_read(png, &img, 3) == PP5_OK);
    CHECK(img.width == 96 && img.height == 72);
    image8_free(&img);
    char *text = pp5_test_read_file(rep);
    REQUIRE(text);
    CHECK(strstr(text, "\"pixels_shaded\"") && strstr(text, "\"aw_psnr_db\""));
    CHECK(strstr(text, "\"triangles\": 100000"));
    free(text);
    text = pp5_test_read_file(out);
    REQUIRE(text);
    CHECK(strstr(text, "LOD + VRZ") != NULL);
    free(text);
    snprintf(args, sizeof args, "render --mesh gen:torus --size 64x48 --mode full --out %s", png);
    CHECK_EQ(pp5_test_run_cli(args, out, err), 0);
    /* both inputs, a broken scene, a bad shading: one line, non-zero */
    const char *bad_scene = write_text(dir, "cli_bad.scene", "mesh gen:sphere\nwobble\n");
    const char *cases[][2] = {
        {"render --mesh gen:torus --scene %s", "give one of them"},
        {"render --scene %s", "cli_bad.scene:2:"},
        {"render --mesh gen:torus --shading toon", "--shading"},
    };
    for (int i = 0; i < 3; i++) {
        snprintf(args, sizeof args, cases[i][0], bad_scene);
        CHECK(pp5_test_run_cli(args, out, err) != 0);
        text = pp5_test_read_file(err);
        REQUIRE(text);
        CHECK_MSG(strstr(text, cases[i][1]) != NULL, "%s: %s", args, text);
        CHECK(strchr(text, '\n') == text + strlen(text) - 1);
        free(text);
    }
}

TEST(mesh_scene_example_file_loads)
{
    mesh_scene_t s;
    REQUIRE(mesh_scene_load("render/mesh/example.scene", &s) == PP5_OK);
    CHECK_EQ(s.n_objects, 4);
    CHECK_EQ(s.n_meshes, 3);   /* the sphere is instanced */
    CHECK(s.have_camera && s.specular == 0.4);
    mesh_scene_free(&s);
}

TEST(mesh_lod_budget_matches_the_hand_value)
{
    /* gen:sphere: box [-1, 1]^3, bounding radius sqrt 3.  Camera 40 units
     * away on +z, 40 degree field of view, 640 x 480: f = 1 / tan 20 deg =
     * 2.74748, so the radius projects to sqrt 3 x 2.74748 / 40 x 240 =
     * 28.553 px.  At x = 8 the centre is at screen x = 451.9, 423 px (less
     * the radius) from a gaze at (0, 240): 8.9 inches at 20, 24 degrees, far
     * in the periphery (rho = 1/16).  Budget: 2 pi 28.553^2 / 16 = 320.2
     * faces -> the finest recorded level with at most 321 faces. */
    const char *dir = pp5_test_outdir();
    const char *path = write_text(dir, "lod.scene", "mesh gen:sphere\ntranslate 8 0 0\n"
                                                    "camera 0 0 40 0 0 0 40\n");
    mesh_scene_t s;
    REQUIRE(mesh_scene_load(path, &s) == PP5_OK);
    REQUIRE(mesh_scene_build_records(&s) == PP5_OK);
    raster_camera_t cam;
    mesh_scene_camera(&s, 640.0 / 480, &cam);
    gaze_display_t d;
    gaze_display_defaults(&d);
    gaze_model_t g;
    REQUIRE(gaze_model_init(&g, &d, 640, 480) == PP5_OK);
    const mesh_record_t *rec = &s.meshes[0].rec;
    int level;
    long faces;
    mesh_lod_choose(&s, &cam, &g, 0, 240, &level, &faces);
    CHECK(level > 0);
    CHECK(rec->level_faces[level] <= 321);
    CHECK(rec->level_faces[level - 1] > 321);
    CHECK_EQ(faces, rec->level_faces[level]);
    /* gazed at: rho = 1, a budget of 5,123 faces, over the sphere's 760 */
    mesh_lod_choose(&s, &cam, &g, 451.9, 240, &level, &faces);
    CHECK_EQ(level, 0);
    CHECK_EQ(faces, 760);
    mesh_scene_free(&s);
}

TEST(mesh_render_on_the_machine_covers_what_the_native_frame_covers)
{
    /* `render --machine --mesh`: the polygon pipeline's frame, its report,
     * and the same coverage as the native frame of the same triangles up to
     * edge pixels (the machine snaps corners to 1/16 pixel: at most 1 % of
     * the covered pixels may be drawn by one image only). */
    const char *dir = pp5_test_outdir();
    char png[1200], rep[1200], out[1200], err[1200], args[4000];
    snprintf(png, sizeof png, "%s/m.png", dir);
    snprintf(rep, sizeof rep, "%s/m.json", dir);
    snprintf(out, sizeof out, "%s/out.txt", dir);
    snprintf(err, sizeof err, "%s/err.txt", dir);
    snprintf(args, sizeof args, "render --machine --mesh gen:torus --size 96x64 --mode full "
             "--shading gouraud --out %s --report %s", png, rep);
    REQUIRE(pp5_test_run_cli(args, out, err) == 0);
    image8_t img;
    REQUIRE(png_read(png, &img, 3) == PP5_OK);
    CHECK(img.width == 96 && img.height == 64);
    image8_free(&img);
    char *text = pp5_test_read_file(rep);
    REQUIRE(text);
    long covered = -1, one_only = -1;
    const char *a = strstr(text, "\"pixels_covered_native\":");
    const char *b = strstr(text, "\"pixels_covered_by_one_only\":");
    REQUIRE(a && b);
    covered = strtol(strchr(a, ':') + 1, NULL, 10);
    one_only = strtol(strchr(b, ':') + 1, NULL, 10);
    CHECK_MSG(covered > 500, "the torus covers %ld pixels", covered);
    CHECK_MSG(one_only >= 0 && one_only * 100 <= covered, "%ld of %ld pixels drawn by one image",
              one_only, covered);
    CHECK(strstr(text, "\"triangles\": 2304") != NULL);   /* gen:torus, 48 x 24 x 2 */
    free(text);
    text = pp5_test_read_file(out);
    REQUIRE(text);
    CHECK(strstr(text, "bottleneck") != NULL);
    free(text);
}
