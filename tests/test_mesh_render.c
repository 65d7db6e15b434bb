/* test_mesh_render.c: the native polygon renderer (mesh_render.h): Gouraud
 * against hand values from known vertex colours, perspective correctness
 * on a gradient worked out by hand, Z order, agreement with mesh_raster, and
 * the variable-resolution Z-buffer equal to the full-resolution render where
 * the sweet spot covers the screen (and in the sweet spot otherwise). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "render/mesh/mesh_gen.h"
#include "render/mesh/mesh_raster.h"
#include "render/mesh/mesh_render.h"
#include "render/mesh/mesh_scene.h"
#include "render/mip2d_row.h"

/* A soup of n triangles from 9 n coordinates and 9 n colours (normals +z). */
static void soup_of(mesh_soup_t *s, const double *xyz, const double *rgb, int n)
{
    memset(s, 0, sizeof *s);
    s->n_tris = n;
    s->pos = malloc(sizeof *s->pos * 9 * (size_t)n);
    s->nrm = malloc(sizeof *s->nrm * 9 * (size_t)n);
    s->rgb = malloc(sizeof *s->rgb * 9 * (size_t)n);
    s->object = calloc((size_t)n, sizeof *s->object);
    REQUIRE(s->pos && s->nrm && s->rgb && s->object);
    memcpy(s->pos, xyz, sizeof *xyz * 9 * (size_t)n);
    memcpy(s->rgb, rgb, sizeof *rgb * 9 * (size_t)n);
    for (int i = 0; i < 3 * n; i++)
        s->nrm[3 * i] = 0, s->nrm[3 * i + 1] = 0, s->nrm[3 * i + 2] = 1;
}

/* Unlit: ambient 1, diffuse 0, so a sample's colour is its interpolated colour. */
static void unlit(mesh_render_opts_t *o, raster_shading_t s)
{
    memset(o, 0, sizeof *o);
    o->shading = s;
    o->light_dir[2] = 1;
    o->ambient = 1;
    o->background[0] = o->background[1] = o->background[2] = 255;
}

TEST(mesh_render_gouraud_matches_the_hand_values)
{
    /* red, green, blue corners at world (0,0), (8,0), (0,8); orthographic
     * onto 8 x 8 pixels.  Pixel (1, 6) has its centre at world (1.5, 1.5):
     * barycentrics 0.625, 0.1875, 0.1875 -> 159.375, 47.8125, 47.8125 ->
     * (159, 48, 48).  Pixel (1, 2) centre (1.5, 5.5): 0.125, 0.1875, 0.6875
     * -> 31.875, 47.8125, 175.3125 -> (32, 48, 175). */
    const double xyz[9] = {0, 0, -1, 8, 0, -1, 0, 8, -1};
    const double rgb[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    mesh_soup_t s;
    soup_of(&s, xyz, rgb, 1);
    raster_camera_t cam;
    raster_camera_ortho(0, 8, 0, 8, 0.5, 10, &cam);
    mesh_render_opts_t o;
    unlit(&o, RASTER_GOURAUD);
    image8_t img;
    mesh_render_stats_t st;
    REQUIRE(mesh_render_full(&s, &cam, &o, 8, 8, &img, &st) == PP5_OK);
    const uint8_t *a = img.pixels + 3 * (6 * 8 + 1), *b = img.pixels + 3 * (2 * 8 + 1);
    CHECK(a[0] == 159 && a[1] == 48 && a[2] == 48);
    CHECK(b[0] == 32 && b[1] == 48 && b[2] == 175);
    /* 36 centres lie strictly inside (x + y < 8 at centres: 8+7+...+1), the
     * 8 on the hypotenuse x + y = 8 belong to it only if the rule says so;
     * either way each pixel is shaded once */
    CHECK(st.pixels_shaded == st.fragments);
    CHECK(st.pixels_shaded == 28 || st.pixels_shaded == 36);
    CHECK_EQ(st.triangles_in, 1);
    CHECK_EQ(st.triangles_drawn, 1);
    image8_free(&img);
    mesh_soup_free(&s);
}

TEST(mesh_render_interpolation_is_perspective_correct_on_a_gradient)
{
    /* Perspective, 90 degrees, 64 x 64.  A quad from camera-space x = -1 at
     * depth 1 to x = 3 at depth 3 (both ends at the image's left and right
     * edges, y spanning the image), red running 0 -> 1 across it.  Along it
     * x = -1 + 4 s, depth 1 + 2 s, so the screen's X = (-1 + 4 s)/(1 + 2 s)
     * and s = (1 + X)/(4 - 2 X).  Pixel 31 (X = -1/64): s = 0.24419 -> 62
     * (a screen-space lerp would give 126); pixel 48 (X = 0.515625):
     * s = 0.51053 -> 130. */
    const double xyz[18] = {-1, -1, -1, 3, -3, -3, 3, 3, -3, -1, -1, -1, 3, 3, -3, -1, 1, -1};
    const double rgb[18] = {0, 0, 0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0};
    mesh_soup_t s;
    soup_of(&s, xyz, rgb, 2);
    raster_camera_t cam;
    raster_camera_perspective(90, 1, 0.5, 10, &cam);
    mesh_render_opts_t o;
    unlit(&o, RASTER_GOURAUD);
    image8_t img;
    mesh_render_stats_t st;
    REQUIRE(mesh_render_full(&s, &cam, &o, 64, 64, &img, &st) == PP5_OK);
    CHECK_EQ(img.pixels[3 * (32 * 64 + 31)], 62);
    CHECK_EQ(img.pixels[3 * (32 * 64 + 48)], 130);
    for (int x = 0; x < 64; x++) {
        double X = (x + 0.5) / 32 - 1, want = 255 * (1 + X) / (4 - 2 * X);
        CHECK_NEAR(img.pixels[3 * (20 * 64 + x)], want, 0.5 + 1e-6);
    }
    image8_free(&img);
    mesh_soup_free(&s);
}

TEST(mesh_render_nearer_triangle_wins_in_either_order)
{
    const double near_far[18] = {0, 0, -1, 8, 0, -1, 0, 8, -1, 0, 0, -2, 8, 0, -2, 0, 8, -2};
    const double rgb[18] = {1, 0, 0, 1, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    double xyz2[18], rgb2[18];
    memcpy(xyz2, near_far + 9, 9 * sizeof *xyz2), memcpy(xyz2 + 9, near_far, 9 * sizeof *xyz2);
    memcpy(rgb2, rgb + 9, 9 * sizeof *rgb2), memcpy(rgb2 + 9, rgb, 9 * sizeof *rgb2);
    raster_camera_t cam;
    raster_camera_ortho(0, 8, 0, 8, 0.5, 10, &cam);
    mesh_render_opts_t o;
    unlit(&o, RASTER_FLAT);
    for (int k = 0; k < 2; k++) {
        mesh_soup_t s;
        soup_of(&s, k ? xyz2 : near_far, k ? rgb2 : rgb, 2);
        image8_t img;
        mesh_render_stats_t st;
        REQUIRE(mesh_render_full(&s, &cam, &o, 8, 8, &img, &st) == PP5_OK);
        const uint8_t *p = img.pixels + 3 * (6 * 8 + 1);
        CHECK(p[0] == 255 && p[2] == 0);
        CHECK_EQ(st.fragments, 2 * st.pixels_shaded);
        image8_free(&img);
        mesh_soup_free(&s);
    }
}

TEST(mesh_render_agrees_with_mesh_raster_on_one_mesh)
{
    /* the same torus, camera and light through both rasterisers: the same
     * pixels covered, colours within one 8-bit step (the renderer keeps its
     * attributes in floats and shades after the Z pass) */
    mesh_t m;
    REQUIRE(mesh_gen_torus(48, 24, 1.0, 0.35, &m) == PP5_OK);
    raster_camera_t cam;
    raster_camera_fit(&m, 30, 40, 1.0, true, &cam);
    for (int sh = 0; sh < 3; sh++) {
        raster_style_t style;
        raster_style_default(&style, (raster_shading_t)sh);
        style.specular = sh == RASTER_PHONG ? 0.3 : 0;
        mesh_raster_t r;
        REQUIRE(mesh_raster_init(&r, 96, 96) == PP5_OK);
        raster_viewport_t vp = {0, 0, 96, 96};
        static const uint8_t white[3] = {255, 255, 255};
        mesh_raster_clear(&r, &vp, white);
        REQUIRE(mesh_raster_draw(&r, &vp, &m, &cam, &style) == PP5_OK);
        mesh_t copy;
        REQUIRE(mesh_copy(&m, &copy) == PP5_OK);
        mesh_scene_t s;
        REQUIRE(mesh_scene_from_mesh(&copy, &s) == PP5_OK);
        memcpy(s.light_dir, style.light_dir, sizeof s.light_dir);
        s.specular = style.specular, s.shininess = style.shininess;
        mesh_soup_t soup;
        REQUIRE(mesh_scene_flatten(&s, NULL, &soup) == PP5_OK);
        mesh_render_opts_t o;
        /* the scene light is in world space; the style's in camera space */
        mesh_render_opts_from_scene(&s, &cam, (raster_shading_t)sh, &o);
        static const uint8_t marker[3] = {1, 2, 3};   /* a background no surface is lit to */
        memcpy(o.background, marker, 3);
        memcpy(o.light_dir, style.light_dir, sizeof o.light_dir);
        double l = sqrt(o.light_dir[0] * o.light_dir[0] + o.light_dir[1] * o.light_dir[1] +
                        o.light_dir[2] * o.light_dir[2]);
        for (int k = 0; k < 3; k++)
            o.light_dir[k] /= l;
        image8_t img;
        mesh_render_stats_t st;
        REQUIRE(mesh_render_full(&soup, &cam, &o, 96, 96, &img, &st) == PP5_OK);
        int cover_diff = 0, max_diff = 0;
        for (int i = 0; i < 96 * 96; i++) {
            bool a = r.depth[i] < INFINITY, b = memcmp(img.pixels + 3 * i, marker, 3) != 0;
            cover_diff += a != b;
            for (int k = 0; a && k < 3; k++) {
                int d = abs(img.pixels[3 * i + k] - r.image.pixels[3 * i + k]);
                max_diff = d > max_diff ? d : max_diff;
            }
        }
        CHECK_MSG(cover_diff == 0, "shading %d: %d pixels covered by one only", sh, cover_diff);
        CHECK_MSG(max_diff <= 1, "shading %d: largest difference %d", sh, max_diff);
        CHECK(st.pixels_shaded > 1000);
        image8_free(&img);
        mesh_soup_free(&soup);
        mesh_scene_free(&s);
        mesh_raster_free(&r);
    }
    mesh_free(&m);
}

/* The built-in scene at 128 x 96 with the given sweet-spot diameter. */
static void vrz_against_full(raster_shading_t sh, double sweet_deg, double gaze_x, double gaze_y,
                             int *differ_in_sweet_spot, int *differ, mesh_render_stats_t *full_st,
                             mesh_render_stats_t *vrz_st, int *level0_pixels)
{
    mesh_scene_t s;
    REQUIRE(mesh_scene_builtin("gen:spheres100k", &s) == PP5_OK);
    mesh_soup_t soup;
    REQUIRE(mesh_scene_flatten(&s, NULL, &soup) == PP5_OK);
    raster_camera_t cam;
    mesh_scene_camera(&s, 128.0 / 96, &cam);
    mesh_render_opts_t o;
    mesh_render_opts_from_scene(&s, &cam, sh, &o);
    gaze_display_t d;
    gaze_display_defaults(&d);
    d.full_res_diameter_deg = sweet_deg;
    d.periphery_diameter_deg = sweet_deg + 8;
    gaze_model_t g;
    REQUIRE(gaze_model_init(&g, &d, 128, 96) == PP5_OK);
    image8_t a, b;
    REQUIRE(mesh_render_full(&soup, &cam, &o, 128, 96, &a, full_st) == PP5_OK);
    REQUIRE(mesh_render_vrz(&soup, &cam, &o, &g, gaze_x, gaze_y, &b, vrz_st) == PP5_OK);
    *differ_in_sweet_spot = *differ = *level0_pixels = 0;
    float levels[128];
    for (int y = 0; y < 96; y++) {
        gaze_level_row(&g, y, 128, gaze_x, gaze_y, 1.0, levels);
        for (int x = 0; x < 128; x++) {
            bool same = memcmp(a.pixels + 3 * (y * 128 + x), b.pixels + 3 * (y * 128 + x), 3) == 0;
            *differ += !same;
            *differ_in_sweet_spot += levels[x] == 0.0f && !same;
            *level0_pixels += levels[x] == 0.0f;
        }
    }
    image8_free(&a);
    image8_free(&b);
    mesh_soup_free(&soup);
    mesh_scene_free(&s);
}

TEST(mesh_render_vrz_with_the_sweet_spot_covering_the_screen_equals_full_resolution)
{
    for (int sh = 0; sh < 3; sh++) {
        int in_spot, differ, level0;
        mesh_render_stats_t f, v;
        vrz_against_full((raster_shading_t)sh, 150, 64, 48, &in_spot, &differ, &f, &v, &level0);
        CHECK_EQ(level0, 128 * 96);
        CHECK_EQ(differ, 0);
        CHECK_EQ(v.fragments, f.fragments);
        CHECK_EQ(v.pixels_shaded, f.pixels_shaded);
        CHECK_EQ(v.samples, 128 * 96);
    }
}

TEST(mesh_render_vrz_equals_full_resolution_in_the_sweet_spot_and_costs_less)
{
    /* a sweet spot of a few degrees: its pixels read level 0 only */
    int in_spot, differ, level0;
    mesh_render_stats_t f, v;
    vrz_against_full(RASTER_PHONG, 6, 40, 30, &in_spot, &differ, &f, &v, &level0);
    CHECK(level0 > 50 && level0 < 128 * 96 / 2);
    CHECK_EQ(in_spot, 0);
    CHECK(differ > 0);
    CHECK(v.fragments < f.fragments / 2);
    CHECK(v.pixels_shaded < f.pixels_shaded / 2);
    CHECK(v.samples < 128 * 96 / 2);
    CHECK_EQ(v.triangles_drawn, f.triangles_drawn);
}

TEST(mesh_render_a_fan_is_drawn_without_overlaps_or_gaps_on_every_grid)
{
    /* a 10-gon fan in one plane (orthographic, 64 x 48, vertices off the
     * pixel grid and one on a pixel centre): every covered sample is covered
     * once (fragments = samples shaded), at full resolution and in the
     * variable-resolution Z-buffer's coarser grids, and the full-resolution
     * count equals the pixel centres strictly inside plus some of those on
     * the boundary */
    enum { N = 10 };
    double xyz[9 * N], rgb[9 * N], cx = 31.3, cy = 23.7, poly[N][2];
    for (int i = 0; i < N; i++) {
        double a = 2 * 3.14159265358979323846 * i / N;
        poly[i][0] = cx + 20 * cos(a), poly[i][1] = cy + 20 * sin(a);
    }
    poly[3][0] = 25.5, poly[3][1] = 42.5;
    for (int i = 0; i < N; i++) {
        const double *p[3] = {(const double[2]){cx, cy}, poly[i], poly[(i + 1) % N]};
        for (int c = 0; c < 3; c++) {
            /* world y up: image row r has its centre at world y = 48 - (r + 0.5) */
            xyz[9 * i + 3 * c] = p[c][0], xyz[9 * i + 3 * c + 1] = p[c][1];
            xyz[9 * i + 3 * c + 2] = -1;
            rgb[9 * i + 3 * c] = rgb[9 * i + 3 * c + 1] = 0.5, rgb[9 * i + 3 * c + 2] = 0;
        }
    }
    mesh_soup_t s;
    soup_of(&s, xyz, rgb, N);
    raster_camera_t cam;
    raster_camera_ortho(0, 64, 0, 48, 0.5, 10, &cam);
    mesh_render_opts_t o;
    unlit(&o, RASTER_GOURAUD);
    image8_t img;
    mesh_render_stats_t st;
    REQUIRE(mesh_render_full(&s, &cam, &o, 64, 48, &img, &st) == PP5_OK);
    CHECK_EQ(st.fragments, st.pixels_shaded);
    int inside = 0, boundary = 0;
    for (int r = 0; r < 48; r++)
        for (int x = 0; x < 64; x++) {
            double px = x + 0.5, py = 48 - (r + 0.5);
            bool in = true, on = false;
            for (int i = 0; i < N && in; i++) {
                const double *a = poly[i], *b = poly[(i + 1) % N];
                double e = (b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0]);
                in = e >= 0;
                on |= e == 0;
            }
            inside += in && !on;
            boundary += in && on;
        }
    CHECK(boundary >= 1);   /* the vertex on a pixel centre */
    CHECK((int)st.pixels_shaded >= inside && (int)st.pixels_shaded <= inside + boundary);
    image8_free(&img);
    gaze_display_t d;
    gaze_display_defaults(&d);
    d.full_res_diameter_deg = 2, d.periphery_diameter_deg = 4;
    gaze_model_t g;
    REQUIRE(gaze_model_init(&g, &d, 64, 48) == PP5_OK);
    REQUIRE(mesh_render_vrz(&s, &cam, &o, &g, 10, 10, &img, &st) == PP5_OK);
    CHECK_EQ(st.fragments, st.pixels_shaded);
    CHECK(st.samples < 64 * 48 / 2);
    image8_free(&img);
    mesh_soup_free(&s);
}
