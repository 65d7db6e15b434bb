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

#include "firmware/host/poly_session.h"
#include "harness.h"
#include "render/mesh/mesh.h"
#include "render/mesh/mesh_gen.h"
#include "render/mesh/mesh_raster.h"

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
    return se == 0 ? INFINITY : 10 * log10(255.0 * 255.0 * n / se);
}

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
        printf("DEBUG persp %d covered %d differ_cover %d differ_colour %d max %d psnr %.2f\n", persp, c.covered, c.differ_cover, c.differ_colour, c.max_diff, psnr(&a, &b));
        image8_free(&a);
        image8_free(&b);
    }
    mesh_free(&m);
}

TEST(fw_poly_phong_on_a_flat_patch_is_flat_shading)
{
    mesh_t m;
    REQUIRE(mesh_gen_grid(6, 6, 200, 200, &m) == PP5_OK);
    raster_camera_t cam;
    raster_camera_ortho(-10, 246, -10, 246, 0.5, 20, &cam);
    for (int i = 0; i < m.n_vertices; i++)
        m.pos[3 * i + 2] = -2;
    raster_style_t st;
    raster_style_default(&st, RASTER_FLAT);
    image8_t a, b;
    native_image(&m, 256, 256, &cam, &st, &b);
    machine_image(&m, 256, 256, &cam, &st, POLY_PHONG, 2, 2, &a, NULL);
    poly_cmp_t c = compare_images(&a, &b);
    printf("DEBUG phong covered %d differ_cover %d differ_colour %d max %d psnr %.2f\n", c.covered, c.differ_cover, c.differ_colour, c.max_diff, psnr(&a, &b));
    png_write("/tmp/polym_ph.png", &a);
    image8_free(&a);
    image8_free(&b);
    mesh_free(&m);
}
