/* test_mesh_raster.c: the triangle rasteriser: shared edges drawn exactly
 * once (top-left rule), the depth test in either draw order, flat and
 * Gouraud intensities worked out by hand, near-plane clipping, repeatable
 * pixels, contact sheets and `pp5 mesh render`. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "render/mesh/mesh.h"
#include "render/mesh/mesh_gen.h"
#include "render/mesh/mesh_raster.h"
#include "render/mesh/mesh_sheet.h"

static const uint8_t WHITE[3] = {255, 255, 255};

/* A mesh of n triangles given as 9 n coordinates (no shared vertices). */
static void tri_mesh(mesh_t *m, const double *xyz, int n)
{
    REQUIRE(mesh_alloc(m, 3 * n, n) == PP5_OK);
    memcpy(m->pos, xyz, sizeof *xyz * 9 * (size_t)n);
    for (int i = 0; i < 3 * n; i++)
        m->tri[i] = i;
}

/* Pixels of an N x N image (ortho camera: world [0,N]^2, y up) that differ from white. */
static int draw_count(const double *xyz, int n, int N)
{
    mesh_t m;
    tri_mesh(&m, xyz, n);
    mesh_raster_t r;
    REQUIRE(mesh_raster_init(&r, N, N) == PP5_OK);
    raster_viewport_t vp = {0, 0, N, N};
    raster_camera_t cam;
    raster_style_t st;
    raster_camera_ortho(0, N, 0, N, 0.5, 10, &cam);
    raster_style_default(&st, RASTER_FLAT);
    mesh_raster_clear(&r, &vp, WHITE);
    REQUIRE(mesh_raster_draw(&r, &vp, &m, &cam, &st) == PP5_OK);
    int drawn = 0;
    for (int i = 0; i < N * N; i++)
        drawn += memcmp(r.image.pixels + 3 * i, WHITE, 3) != 0;
    mesh_raster_free(&r);
    mesh_free(&m);
    return drawn;
}

TEST(mesh_raster_shared_edges_are_drawn_exactly_once)
{
    /* an 8 x 8 square split along its diagonal, which passes through 8 pixel
     * centres: 64 pixels whichever way, 64 in all when drawn apart */
    const double a[9] = {0, 0, -1, 8, 0, -1, 8, 8, -1}, b[9] = {0, 0, -1, 8, 8, -1, 0, 8, -1};
    double both[18];
    memcpy(both, a, sizeof a);
    memcpy(both + 9, b, sizeof b);
    int na = draw_count(a, 1, 16), nb = draw_count(b, 1, 16);
    CHECK_EQ(na + nb, 64);
    CHECK_EQ(draw_count(both, 2, 16), 64);
    CHECK(na > 0 && nb > 0);
    /* a triangle cut in two along a vertical line through pixel centres
     * covers the same pixels as the whole */
    const double whole[9] = {0, 0, -1, 9, 0, -1, 4.5, 8, -1};
    const double left[9] = {0, 0, -1, 4.5, 0, -1, 4.5, 8, -1};
    const double right[9] = {4.5, 0, -1, 9, 0, -1, 4.5, 8, -1};
    CHECK_EQ(draw_count(left, 1, 16) + draw_count(right, 1, 16), draw_count(whole, 1, 16));
    /* the same with the faces turned over (drawn as back faces) */
    const double flipped[9] = {0, 0, -1, 8, 8, -1, 8, 0, -1};
    CHECK_EQ(draw_count(flipped, 1, 16), na);
}

/* Two squares, near (z = -1, red) and far (z = -2, blue), overlapping in
 * x in [4, 8]; returns the image. */
static void two_squares(bool near_first, mesh_raster_t *r)
{
    const double near_sq[18] = {0, 0, -1, 8, 0, -1, 8, 8, -1, 0, 0, -1, 8, 8, -1, 0, 8, -1};
    const double far_sq[18] = {4, 0, -2, 12, 0, -2, 12, 8, -2, 4, 0, -2, 12, 8, -2, 4, 8, -2};
    mesh_t mn, mf;
    tri_mesh(&mn, near_sq, 2);
    tri_mesh(&mf, far_sq, 2);
    REQUIRE(mesh_raster_init(r, 16, 16) == PP5_OK);
    raster_viewport_t vp = {0, 0, 16, 16};
    raster_camera_t cam;
    raster_camera_ortho(0, 16, 0, 16, 0.5, 10, &cam);
    raster_style_t red, blue;
    raster_style_default(&red, RASTER_FLAT);
    raster_style_default(&blue, RASTER_FLAT);
    red.front_rgb[0] = 255, red.front_rgb[1] = red.front_rgb[2] = 0;
    blue.front_rgb[2] = 255, blue.front_rgb[0] = blue.front_rgb[1] = 0;
    mesh_raster_clear(r, &vp, WHITE);
    for (int k = 0; k < 2; k++) {
        bool near_now = (k == 0) == near_first;
        REQUIRE(mesh_raster_draw(r, &vp, near_now ? &mn : &mf, &cam, near_now ? &red : &blue) ==
                PP5_OK);
    }
    mesh_free(&mn);
    mesh_free(&mf);
}

TEST(mesh_raster_nearer_surface_wins_in_either_draw_order)
{
    mesh_raster_t a, b;
    two_squares(true, &a);
    two_squares(false, &b);
    CHECK(memcmp(a.image.pixels, b.image.pixels, 16 * 16 * 3) == 0);
    /* the overlap (x 4..8, image rows 8..15) is red; x 8..12 blue */
    const uint8_t *overlap = a.image.pixels + 3 * (12 * 16 + 6);
    const uint8_t *far_only = a.image.pixels + 3 * (12 * 16 + 10);
    CHECK(overlap[0] > 0 && overlap[2] == 0);
    CHECK(far_only[2] > 0 && far_only[0] == 0);
    mesh_raster_free(&a);
    mesh_raster_free(&b);
}

/* m drawn into a fresh 8 x 8 image (ortho: world [0,8]^2), ambient 0.2,
 * diffuse 0.8, the given light and colours. */
static void draw8(const mesh_t *m, raster_shading_t shading, const double light[3],
                  const uint8_t front[3], const uint8_t back[3], mesh_raster_t *r)
{
    REQUIRE(mesh_raster_init(r, 8, 8) == PP5_OK);
    raster_viewport_t vp = {0, 0, 8, 8};
    raster_camera_t cam;
    raster_style_t st;
    raster_camera_ortho(0, 8, 0, 8, 0.5, 10, &cam);
    raster_style_default(&st, shading);
    memcpy(st.light_dir, light, sizeof st.light_dir);
    st.ambient = 0.2, st.diffuse = 0.8;
    memcpy(st.front_rgb, front, 3);
    memcpy(st.back_rgb, back, 3);
    mesh_raster_clear(r, &vp, WHITE);
    REQUIRE(mesh_raster_draw(r, &vp, m, &cam, &st) == PP5_OK);
}

/* One pixel of a square facing +z (toward the camera), lit from `light`. */
static void lit_square(const double light[3], bool turned, raster_shading_t shading,
                       uint8_t out[3])
{
    double sq[18] = {0, 0, -1, 8, 0, -1, 8, 8, -1, 0, 0, -1, 8, 8, -1, 0, 8, -1};
    if (turned)   /* reverse both triangles: the camera sees their backs */
        for (int t = 0; t < 2; t++)
            for (int k = 0; k < 3; k++) {
                double tmp = sq[9 * t + 3 + k];
                sq[9 * t + 3 + k] = sq[9 * t + 6 + k], sq[9 * t + 6 + k] = tmp;
            }
    mesh_t m;
    tri_mesh(&m, sq, 2);
    mesh_raster_t r;
    static const uint8_t front[3] = {200, 100, 50}, back[3] = {100, 60, 20};
    draw8(&m, shading, light, front, back, &r);
    memcpy(out, r.image.pixels + 3 * (3 * 8 + 5), 3);
    mesh_raster_free(&r);
    mesh_free(&m);
}

TEST(mesh_raster_flat_and_gouraud_intensities_match_the_hand_values)
{
    uint8_t px[3];
    const double head_on[3] = {0, 0, 1}, at60[3] = {sqrt(3.0) / 2, 0, 0.5};
    /* head on: 0.2 + 0.8 x 1 = 1 -> the colour itself */
    lit_square(head_on, false, RASTER_FLAT, px);
    CHECK(px[0] == 200 && px[1] == 100 && px[2] == 50);
    /* 60 degrees: 0.2 + 0.8 x 0.5 = 0.6 -> 120, 60, 30 */
    lit_square(at60, false, RASTER_FLAT, px);
    CHECK(px[0] == 120 && px[1] == 60 && px[2] == 30);
    /* seen from behind: the back colour, lit with the normal reversed (so
     * the same 0.6 from the same light), and dark (0.2) lit from behind */
    lit_square(at60, true, RASTER_FLAT, px);
    CHECK(px[0] == 60 && px[1] == 36 && px[2] == 12);
    const double from_behind[3] = {sqrt(3.0) / 2, 0, -0.5};
    lit_square(from_behind, true, RASTER_FLAT, px);
    CHECK(px[0] == 20 && px[1] == 12 && px[2] == 4);
    /* a flat square has one normal everywhere: Gouraud equals flat */
    lit_square(at60, false, RASTER_GOURAUD, px);
    CHECK(px[0] == 120 && px[1] == 60 && px[2] == 30);
}

TEST(mesh_raster_gouraud_varies_across_a_crease_and_flat_does_not)
{
    /* a roof: two faces meeting along the ridge x = 4, each at 45 degrees;
     * triangulated symmetrically, so the ridge's vertex normals point at the
     * camera (intensity 0.2 + 0.8 = 1) and the eaves' along their face
     * (0.2 + 0.8 cos 45) */
    mesh_t roof;
    REQUIRE(mesh_alloc(&roof, 6, 4) == PP5_OK);
    const double p[18] = {0, 0, -5, 4, 0, -1, 4, 8, -1, 0, 8, -5, 8, 0, -5, 8, 8, -5};
    const int32_t t[12] = {0, 1, 2, 0, 2, 3, 1, 4, 2, 4, 5, 2};
    memcpy(roof.pos, p, sizeof p);
    memcpy(roof.tri, t, sizeof t);
    double I[2][8];
    static const double head_on[3] = {0, 0, 1};
    static const uint8_t grey[3] = {250, 250, 250};
    for (int s = 0; s < 2; s++) {
        mesh_raster_t r;
        draw8(&roof, s ? RASTER_GOURAUD : RASTER_FLAT, head_on, grey, grey, &r);
        for (int x = 0; x < 8; x++)
            I[s][x] = r.image.pixels[3 * (4 * 8 + x)] / 250.0;
        mesh_raster_free(&r);
    }
    double eave = 0.2 + 0.8 * sqrt(0.5);
    for (int x = 0; x < 8; x++)
        CHECK_NEAR(I[0][x], eave, 0.6 / 250);   /* flat: one value (to the 8-bit step) */
    /* Gouraud, linear across each face (orthographic): eave + (1 - eave) x / 4
     * at the pixel centre x = 0.5 .. 3.5, mirrored on the right */
    for (int x = 0; x < 4; x++) {
        double want = eave + (1 - eave) * (x + 0.5) / 4;
        CHECK_NEAR(I[1][x], want, 0.6 / 250);
        CHECK_NEAR(I[1][7 - x], want, 0.6 / 250);
    }
    mesh_free(&roof);
}

TEST(mesh_raster_clips_at_the_near_plane)
{
    mesh_raster_t r;
    REQUIRE(mesh_raster_init(&r, 32, 32) == PP5_OK);
    raster_viewport_t vp = {0, 0, 32, 32};
    raster_camera_t cam;
    raster_style_t st;
    raster_camera_perspective(90, 1, 1, 100, &cam);
    raster_style_default(&st, RASTER_FLAT);
    /* wholly behind the eye: nothing */
    const double behind[9] = {-1, -1, 2, 1, -1, 2, 0, 1, 2};
    mesh_t m;
    tri_mesh(&m, behind, 1);
    mesh_raster_clear(&r, &vp, WHITE);
    REQUIRE(mesh_raster_draw(&r, &vp, &m, &cam, &st) == PP5_OK);
    int drawn = 0;
    for (int i = 0; i < 32 * 32; i++)
        drawn += r.depth[i] < INFINITY;
    CHECK_EQ(drawn, 0);
    mesh_free(&m);
    /* from behind the eye (z = 4) to far in front (z = -8): the part beyond
     * the near plane, which holds the point straight ahead at z = -2 */
    const double through[9] = {-8, -4, -8, 8, -4, -8, 0, 4, 4};
    tri_mesh(&m, through, 1);
    REQUIRE(mesh_raster_draw(&r, &vp, &m, &cam, &st) == PP5_OK);
    for (int i = 0; i < 32 * 32; i++) {
        drawn += r.depth[i] < INFINITY;
        CHECK(r.depth[i] == INFINITY || (r.depth[i] >= -1 && r.depth[i] <= 1));
    }
    CHECK(drawn > 100);
    CHECK(r.depth[16 * 32 + 16] < INFINITY);
    mesh_free(&m);
    mesh_raster_free(&r);
}

TEST(mesh_raster_same_mesh_same_pixels_and_sheets_lay_out)
{
    mesh_t t;
    REQUIRE(mesh_gen_torus(48, 24, 1.0, 0.35, &t) == PP5_OK);
    uint8_t *first = NULL;
    for (int k = 0; k < 2; k++) {
        mesh_sheet_t sh;
        REQUIRE(mesh_sheet_init(&sh, 2, 3, 64, 48, "torus") == PP5_OK);
        CHECK_EQ(sh.raster.image.width, 100 + 3 * 64);
        CHECK_EQ(sh.raster.image.height, 30 + 2 * (48 + 26));
        raster_camera_t cam;
        raster_style_t st;
        raster_camera_fit(&t, 30, 40, 64.0 / 48, true, &cam);
        raster_style_default(&st, RASTER_GOURAUD);
        REQUIRE(mesh_sheet_draw(&sh, 1, 2, &t, &cam, &st, "a", "b") == PP5_OK);
        CHECK(mesh_sheet_draw(&sh, 2, 0, &t, &cam, &st, NULL, NULL) == PP5_E_RANGE);
        size_t n = (size_t)sh.raster.image.width * sh.raster.image.height * 3;
        if (k == 0) {
            first = malloc(n);
            REQUIRE(first);
            memcpy(first, sh.raster.image.pixels, n);
        } else {
            CHECK(memcmp(first, sh.raster.image.pixels, n) == 0);
        }
        mesh_sheet_free(&sh);
    }
    free(first);
    mesh_free(&t);
}

TEST(mesh_cli_render_writes_a_png_and_fails_cleanly)
{
    char out[1200], err[1200], png[1200], args[2600];
    snprintf(out, sizeof out, "%s/render_out.txt", pp5_test_outdir());
    snprintf(err, sizeof err, "%s/render_err.txt", pp5_test_outdir());
    snprintf(png, sizeof png, "%s/torus.png", pp5_test_outdir());
    snprintf(args, sizeof args, "mesh render gen:torus --out %s --size 64x48 --gouraud", png);
    CHECK_EQ(pp5_test_run_cli(args, out, err), 0);
    image8_t img;
    REQUIRE(png_read(png, &img, 3) == PP5_OK);
    CHECK(img.width == 64 && img.height == 48);
    int drawn = 0;
    for (int i = 0; i < 64 * 48; i++)
        drawn += memcmp(img.pixels + 3 * i, WHITE, 3) != 0;
    CHECK(drawn > 300);
    image8_free(&img);
    snprintf(args, sizeof args, "mesh render gen:torus --out %s --size 0x48", png);
    CHECK(pp5_test_run_cli(args, out, err) != 0);
    char *text = pp5_test_read_file(err);
    REQUIRE(text);
    CHECK(strstr(text, "--size") != NULL);
    CHECK(strchr(text, '\n') == text + strlen(text) - 1);
    free(text);
    CHECK(pp5_test_run_cli("mesh render gen:torus", out, err) != 0);
}

TEST(mesh_raster_phong_matches_the_hand_values)
{
    /* the roof of the test above, Phong, lit head on: the normal is
     * interpolated between the eave's (-1, 0, 1)/sqrt 2 and the ridge's
     * (0, 0, 1) (orthographic: linearly, t = x / 4), then normalised:
     * n = ((1-t)(-1/sqrt 2), 0, (1-t)/sqrt 2 + t), I = 0.2 + 0.8 n_z / |n|.
     * At the first pixel centre t = 1/8: n = (-0.61872, 0, 0.74372),
     * |n| = 0.96744, I = 0.2 + 0.8 x 0.76875 = 0.81500 -> 250 x I = 203.75,
     * where Gouraud gives 0.79508 (198.77): the two differ by 5 levels. */
    mesh_t roof;
    REQUIRE(mesh_alloc(&roof, 6, 4) == PP5_OK);
    const double p[18] = {0, 0, -5, 4, 0, -1, 4, 8, -1, 0, 8, -5, 8, 0, -5, 8, 8, -5};
    const int32_t t[12] = {0, 1, 2, 0, 2, 3, 1, 4, 2, 4, 5, 2};
    memcpy(roof.pos, p, sizeof p);
    memcpy(roof.tri, t, sizeof t);
    static const double head_on[3] = {0, 0, 1};
    static const uint8_t grey[3] = {250, 250, 250};
    mesh_raster_t r;
    draw8(&roof, RASTER_PHONG, head_on, grey, grey, &r);
    CHECK_EQ(r.image.pixels[3 * (4 * 8 + 0)], 204);
    CHECK_EQ(r.image.pixels[3 * (4 * 8 + 7)], 204);
    for (int x = 0; x < 4; x++) {
        double tt = (x + 0.5) / 4, nx = -(1 - tt) * sqrt(0.5), nz = (1 - tt) * sqrt(0.5) + tt;
        double want = 250 * (0.2 + 0.8 * nz / sqrt(nx * nx + nz * nz));
        CHECK_NEAR(r.image.pixels[3 * (4 * 8 + x)], want, 0.5 + 1e-9);
        CHECK_NEAR(r.image.pixels[3 * (4 * 8 + 7 - x)], want, 0.5 + 1e-9);
    }
    mesh_raster_free(&r);
    mesh_free(&roof);
}

TEST(mesh_raster_phong_highlight_matches_the_hand_value)
{
    /* a square facing the camera, light at 60 degrees: n.l = 0.5, the
     * reflection r = 2 (n.l) n - l = (-sqrt 3 / 2, 0, 0.5), r.v = 0.5;
     * specular 0.5, exponent 2: 0.5 x 0.25 = 0.125 of white (31.875) on
     * top of (0.2 + 0.8 x 0.5) = 0.6 of the colour (200, 100, 50):
     * 151.875, 91.875, 61.875 -> 152, 92, 62 */
    double sq[18] = {0, 0, -1, 8, 0, -1, 8, 8, -1, 0, 0, -1, 8, 8, -1, 0, 8, -1};
    mesh_t m;
    tri_mesh(&m, sq, 2);
    mesh_raster_t r;
    REQUIRE(mesh_raster_init(&r, 8, 8) == PP5_OK);
    raster_viewport_t vp = {0, 0, 8, 8};
    raster_camera_t cam;
    raster_style_t st;
    raster_camera_ortho(0, 8, 0, 8, 0.5, 10, &cam);
    raster_style_default(&st, RASTER_PHONG);
    CHECK(st.specular == 0);   /* no highlight unless asked */
    st.light_dir[0] = sqrt(3.0) / 2, st.light_dir[1] = 0, st.light_dir[2] = 0.5;
    st.ambient = 0.2, st.diffuse = 0.8, st.specular = 0.5, st.shininess = 2;
    st.front_rgb[0] = 200, st.front_rgb[1] = 100, st.front_rgb[2] = 50;
    mesh_raster_clear(&r, &vp, WHITE);
    REQUIRE(mesh_raster_draw(&r, &vp, &m, &cam, &st) == PP5_OK);
    const uint8_t *px = r.image.pixels + 3 * (3 * 8 + 5);
    CHECK(px[0] == 152 && px[1] == 92 && px[2] == 62);
    mesh_raster_free(&r);
    mesh_free(&m);
}
