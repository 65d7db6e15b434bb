/* test_speed_formats.c: the AVX2 lanes of the fast parallel tracer and the
 * reduced-precision mip-map formats.
 *
 * - Whole texel rows through raycast_trace_rays (lanes refilled from rows
 *   of any length) with the AVX2 walk, the same with the portable walk, and
 *   each ray through the reference tracer must agree bit for bit, counts
 *   included; on a host without AVX2 both runs take the portable walk.
 * - The U16 and U8 formats: their fast tracers against their own reference
 *   tracer, bit for bit, and skipping exact on their own opacities; their
 *   images against the F32 images within a tolerance derived below; and
 *   their size. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "render/gaze2d.h"
#include "render/raycast_parallel.h"
#include "render/renderer_native.h"
#include "render/scene.h"

typedef struct {
    float rot_x, rot_y, rot_z, step, zoom;
    int side, levels;
    projection_t projection;
} lanes_view_t;

typedef struct {
    uint64_t texels, diff, lit;
    raycast_counts_t simd, portable, ref;
} lanes_result_t;

static bool same_counts(const raycast_counts_t *a, const raycast_counts_t *b)
{
    return a->rays == b->rays && a->samples == b->samples &&
           a->samples_skipped == b->samples_skipped;
}

/* Every texel row of levels 0..levels-1, whole, three ways. */
static void trace_rows(const mip3d_t *m, const octree_t *o, const shade_params_t *sh,
                       const lanes_view_t *c, lanes_result_t *res)
{
    memset(res, 0, sizeof *res);
    view_params_t vp;
    view_defaults(&vp);
    vp.rot_x_deg = c->rot_x;
    vp.rot_y_deg = c->rot_y;
    vp.rot_z_deg = c->rot_z;
    vp.sample_step = c->step;
    vp.zoom = c->zoom;
    vp.projection = c->projection;
    camera_t cam;
    camera_setup(&cam, &vp, m, c->side, c->side);
    raycast_ctx_t simd, portable;
    raycast_ctx_init(&simd, m, o, &cam, sh, &vp);
    portable = simd;
    portable.simd_walk = false;
    int w_max = c->side + 1;
    float *px = malloc((size_t)w_max * sizeof(float)), *py = malloc((size_t)w_max * sizeof(float));
    float(*a)[3] = malloc((size_t)w_max * sizeof *a), (*b)[3] = malloc((size_t)w_max * sizeof *b);
    REQUIRE(px && py && a && b);
    for (int l = 0; l < c->levels; l++) {
        int w = (c->side >> l) + 1;
        for (int j = 0; j < w; j++) {
            for (int i = 0; i < w; i++)
                mip2d_texel_point(l, i, j, &px[i], &py[i]);
            raycast_trace_rays(&simd, w, px, py, l, a, &res->simd);
            raycast_trace_rays(&portable, w, px, py, l, b, &res->portable);
            for (int i = 0; i < w; i++) {
                float ref[3];
                raycast_trace_reference(&simd, px[i], py[i], l, ref, &res->ref);
                res->diff += memcmp(ref, a[i], sizeof ref) != 0;
                res->diff += memcmp(ref, b[i], sizeof ref) != 0;
                res->lit += ref[0] > 0.0f;
                res->texels++;
            }
        }
    }
    free(px);
    free(py);
    free(a);
    free(b);
}

static void check_rows(const char *what, const mip3d_t *m, const octree_t *o,
                       const shade_params_t *sh, const lanes_view_t *views, int count)
{
    for (int k = 0; k < count; k++) {
        lanes_result_t res;
        trace_rows(m, o, sh, &views[k], &res);
        CHECK_MSG(res.diff == 0, "%s view %d: %llu of %llu texels differ from the reference", what,
                  k, (unsigned long long)res.diff, (unsigned long long)res.texels);
        CHECK_MSG(same_counts(&res.simd, &res.ref) && same_counts(&res.portable, &res.ref),
                  "%s view %d: samples %llu/%llu/%llu skipped %llu/%llu/%llu "
                  "(lanes/portable/reference)", what, k, (unsigned long long)res.simd.samples,
                  (unsigned long long)res.portable.samples, (unsigned long long)res.ref.samples,
                  (unsigned long long)res.simd.samples_skipped,
                  (unsigned long long)res.portable.samples_skipped,
                  (unsigned long long)res.ref.samples_skipped);
        /* Not vacuous: the subject is in view and samples were drawn. */
        CHECK_MSG(res.lit > res.texels / 20 && res.ref.samples > 0, "%s view %d: %llu of %llu lit",
                  what, k, (unsigned long long)res.lit, (unsigned long long)res.texels);
    }
}

/* Oblique, axial, rolled, a fractional 3D level (step 0.7) and a coarse
 * step; image sides give rows longer than one 64-ray chunk. */
static const lanes_view_t views[] = {
    {25, 40, 0, 1.0f, 1.0f, 150, 3, PROJECTION_PARALLEL},
    {0, 0, 0, 1.0f, 1.2f, 96, 2, PROJECTION_PARALLEL},
    {-35, 160, 70, 1.0f, 0.8f, 80, 3, PROJECTION_PARALLEL},
    {10, -30, 5, 0.7f, 1.0f, 70, 2, PROJECTION_PARALLEL},
    {50, 20, 0, 2.5f, 1.7f, 70, 2, PROJECTION_PARALLEL},
};
#define VIEW_COUNT ((int)(sizeof views / sizeof views[0]))

/* Perspective (raycast_perspective.c): near and far eyes, an oblique view. */
static const lanes_view_t perspective_views[] = {
    {25, 40, 0, 1.0f, 1.0f, 90, 3, PROJECTION_PERSPECTIVE},
    {-15, 200, 30, 0.8f, 1.4f, 70, 2, PROJECTION_PERSPECTIVE},
};

static void build(const char *phantom, const char *preset, int n, shade_case_t lighting,
                  mip3d_format_t format, volume_t *v, mip3d_t *m, octree_t *o, shade_params_t *sh)
{
    REQUIRE(phantom_make(phantom, n, n, n * 3 / 4, v) == PP5_OK);
    v->spacing[2] = 1.5;
    classify_tf_t tf;
    REQUIRE(classify_preset(preset, &tf) == PP5_OK);
    shade_defaults(sh);
    sh->lighting = lighting;
    sh->specular = 0.4f;
    REQUIRE(mip3d_build_format(m, v, &tf, sh, format, 2) == PP5_OK);
    REQUIRE(octree_build(o, m, 2) == PP5_OK);
}

static void check_format(mip3d_format_t format, shade_case_t lighting, const char *phantom)
{
    volume_t v;
    mip3d_t m;
    octree_t o;
    shade_params_t sh;
    build(phantom, phantom, 40, lighting, format, &v, &m, &o, &sh);
    char what[64];
    snprintf(what, sizeof what, "%s %s", phantom, mip3d_format_name(format));
    check_rows(what, &m, &o, &sh, views, lighting == SHADE_DIFFUSE_FIXED_LIGHT ? VIEW_COUNT : 2);
    octree_free(&o);
    mip3d_free(&m);
    volume_free(&v);
}

TEST(speed_lanes_rows_match_portable_walk_and_reference)
{
    if (!raycast_walk_avx2_supported())
        printf("   note: no AVX2 on this host; both runs take the portable walk\n");
    check_format(MIP3D_F32, SHADE_DIFFUSE_FIXED_LIGHT, "shepp-logan");
    check_format(MIP3D_F32, SHADE_SPECULAR_FIXED_LIGHT, "marschner-lobb");
}

TEST(speed_perspective_fast_tracer_matches_reference)
{
    volume_t v;
    mip3d_t m;
    octree_t o;
    shade_params_t sh;
    build("shepp-logan", "shepp-logan", 40, SHADE_DIFFUSE_FIXED_LIGHT, MIP3D_F32, &v, &m, &o, &sh);
    check_rows("perspective", &m, &o, &sh, perspective_views, 2);
    octree_free(&o);
    mip3d_free(&m);
    volume_free(&v);
    build("marschner-lobb", "marschner-lobb", 33, SHADE_SPECULAR_FIXED_LIGHT, MIP3D_U8, &v, &m, &o,
          &sh);
    check_rows("perspective specular u8", &m, &o, &sh, perspective_views, 1);
    octree_free(&o);
    mip3d_free(&m);
    volume_free(&v);
}

TEST(speed_packed_formats_fast_tracer_matches_their_reference)
{
    check_format(MIP3D_U8, SHADE_DIFFUSE_FIXED_LIGHT, "shepp-logan");
    check_format(MIP3D_U16, SHADE_DIFFUSE_FIXED_LIGHT, "shepp-logan");
    check_format(MIP3D_U8, SHADE_SPECULAR_FIXED_LIGHT, "marschner-lobb");
}

/* Skipping on the packed opacities is exact: the reference with the octree
 * and without it give the same bits (a sample in an empty cell is zero). */
TEST(speed_packed_formats_skipping_is_exact)
{
    volume_t v;
    mip3d_t m;
    octree_t o;
    shade_params_t sh;
    build("shepp-logan", "shepp-logan", 40, SHADE_DIFFUSE_FIXED_LIGHT, MIP3D_U8, &v, &m, &o, &sh);
    view_params_t vp;
    view_defaults(&vp);
    vp.rot_x_deg = 20;
    vp.rot_y_deg = 35;
    camera_t cam;
    camera_setup(&cam, &vp, &m, 64, 64);
    raycast_ctx_t on, off;
    raycast_ctx_init(&on, &m, &o, &cam, &sh, &vp);
    vp.use_octree = false;
    raycast_ctx_init(&off, &m, &o, &cam, &sh, &vp);
    raycast_counts_t con = {0}, coff = {0};
    int diff = 0;
    for (int l = 0; l < 3; l++)
        for (int j = 0; j <= 64 >> l; j++)
            for (int i = 0; i <= 64 >> l; i++) {
                float px, py, a[3], b[3];
                mip2d_texel_point(l, i, j, &px, &py);
                raycast_trace_reference(&on, px, py, l, a, &con);
                raycast_trace_reference(&off, px, py, l, b, &coff);
                diff += memcmp(a, b, sizeof a) != 0;
            }
    CHECK_EQ(diff, 0);
    CHECK(con.samples_skipped > 0);
    CHECK_EQ(con.samples + con.samples_skipped, coff.samples);
    octree_free(&o);
    mip3d_free(&m);
    volume_free(&v);
}

typedef struct {
    double mean, psnr;
    int max;
} image_diff_t;

static image_diff_t image_compare(const image8_t *a, const image8_t *b)
{
    image_diff_t d = {0.0, INFINITY, 0};
    size_t n = (size_t)a->width * (size_t)a->height * 3;
    double se = 0.0;
    for (size_t i = 0; i < n; i++) {
        int e = abs((int)a->pixels[i] - (int)b->pixels[i]);
        d.mean += e;
        se += (double)e * e;
        d.max = e > d.max ? e : d.max;
    }
    d.mean /= (double)n;
    if (se > 0.0)
        d.psnr = 10.0 * log10(255.0 * 255.0 / (se / (double)n));
    return d;
}

/* Frames in every format, full and gaze-directed, against F32.  Why these
 * bounds: a stored component is off by at most half a step (1/510 of its
 * range for U8, 1/131070 for U16) at level 0 and by at most half a step
 * more per level of integer box filtering; the 8-bit output step is 1/255.
 * A composited colour is a weighted sum whose weights add up to at most 1,
 * so U8 moves a typical pixel by under one output level (mean < 1) and U16
 * by a 256th of that (mean < 0.05); a ray whose opacity crosses the early
 * termination threshold (0.95) one sample sooner or later can differ by at
 * most the remaining 5% of its colour, 12.75 levels, plus the per-sample
 * error: max <= 16.  PSNR: U8 >= 40 dB (an RMS error of 2.6 levels), U16
 * >= 60 dB. */
static void check_tolerance(const volume_t *v, const classify_tf_t *tf, const float rot[3],
                            const char *what)
{
    shade_params_t sh;
    shade_defaults(&sh);
    const mip3d_format_t formats[3] = {MIP3D_F32, MIP3D_U16, MIP3D_U8};
    image8_t img[3][2];
    for (int f = 0; f < 3; f++) {
        native_renderer_t r;
        REQUIRE(native_renderer_init_format(&r, v, tf, &sh, formats[f], 2) == PP5_OK);
        CHECK(r.mip.format == formats[f]);
        for (int g = 0; g < 2; g++) {
            render_settings_t s;
            render_settings_defaults(&s);
            s.width = s.height = 96;
            s.gaze_x = s.gaze_y = 47.5;
            s.mode = g ? RENDER_MODE_GAZE : RENDER_MODE_FULL;
            s.view.rot_x_deg = rot[0];
            s.view.rot_y_deg = rot[1];
            s.view.rot_z_deg = rot[2];
            s.threads = 2;
            render_stats_t st;
            REQUIRE(native_renderer_frame(&r, &s, &img[f][g], &st) == PP5_OK);
            CHECK(st.samples > 0);
        }
        native_renderer_free(&r);
    }
    for (int f = 1; f < 3; f++)
        for (int g = 0; g < 2; g++) {
            image_diff_t d = image_compare(&img[0][g], &img[f][g]);
            bool u8 = formats[f] == MIP3D_U8;
            CHECK_MSG(d.mean < (u8 ? 1.0 : 0.05) && d.max <= 16 && d.psnr >= (u8 ? 40.0 : 60.0),
                      "%s %s %s: mean %.3f max %d PSNR %.1f dB", what,
                      mip3d_format_name(formats[f]), g ? "gaze" : "full", d.mean, d.max, d.psnr);
        }
    for (int f = 0; f < 3; f++)
        for (int g = 0; g < 2; g++)
            image8_free(&img[f][g]);
}

TEST(speed_packed_formats_within_tolerance_of_f32)
{
    volume_t v;
    REQUIRE(phantom_make("shepp-logan", 64, 64, 48, &v) == PP5_OK);
    classify_tf_t tf;
    REQUIRE(classify_preset("shepp-logan", &tf) == PP5_OK);
    check_tolerance(&v, &tf, (const float[3]){20.0f, 30.0f, 0.0f}, "shepp-logan");
    volume_free(&v);
    if (!pp5_test_shared_data("volumes/mrbrain_brainsmall/brainsmall_128x128x84_u8.raw.gz"))
        SKIP("the MR subject is absent from the shared data (phantom checked)");
    scene_t sc;
    REQUIRE(scene_load("mrbrain", false, &sc) == PP5_OK);
    check_tolerance(&sc.volume, &sc.tf, (const float[3]){sc.rot_x_deg, sc.rot_y_deg, sc.rot_z_deg},
                    "mrbrain");
    scene_free(&sc);
}

/* U8 diffuse: 4 bytes per voxel at level 0 and at most 8/7 of that over
 * all levels, plus the bricks' padding (none here: every level of a 64^3
 * volume but the last three is a multiple of 4) and a few tiny top levels
 * padded to one brick each. */
TEST(speed_packed_u8_size_is_4_to_5_bytes_per_voxel)
{
    volume_t v;
    REQUIRE(phantom_make("sphere-shell", 64, 64, 64, &v) == PP5_OK);
    classify_tf_t tf;
    REQUIRE(classify_preset("sphere-shell", &tf) == PP5_OK);
    shade_params_t sh;
    shade_defaults(&sh);
    mip3d_t m;
    REQUIRE(mip3d_build_format(&m, &v, &tf, &sh, MIP3D_U8, 2) == PP5_OK);
    double per_voxel = (double)m.bytes / (64.0 * 64.0 * 64.0);
    CHECK_MSG(per_voxel >= 4.0 && per_voxel <= 5.0, "%.3f bytes per voxel", per_voxel);
    mip3d_t f;
    REQUIRE(mip3d_build(&f, &v, &tf, &sh, 2) == PP5_OK);
    CHECK_MSG(f.bytes > 3 * m.bytes, "F32 %zu bytes, U8 %zu", f.bytes, m.bytes);
    mip3d_free(&f);
    mip3d_free(&m);
    volume_free(&v);
}

/* The octree answers queries from its block map alone (the per-cell tables
 * are freed after the build): every cell of every grid against a top-down
 * descent through an OR pyramid rebuilt here from the mip map's opacities
 * (octree.h: cell i occupied when a voxel in [i-2, i+3]^3, or [i, i+1]^3 for
 * the exact grid, has opacity > 0). */
static int descend(const uint8_t *const *pyr, const int (*dims)[3], int heights, int x, int y,
                   int z)
{
    for (int h = heights - 1; h >= 0; h--) {
        int cx = x >> h, cy = y >> h, cz = z >> h;
        if (!pyr[h][((size_t)cz * dims[h][1] + cy) * dims[h][0] + cx])
            return h;
    }
    return -1;
}

static int check_grid(const mip3d_t *m, const octree_grid_t *g, int n, int lo, int hi)
{
    const mip3d_level_t *L = &m->level[n];
    int dims[OCTREE_MAX_HEIGHT][3] = {{L->nx, L->ny, L->nz}};
    uint8_t *pyr[OCTREE_MAX_HEIGHT] = {0};
    int heights = 1;
    pyr[0] = calloc((size_t)L->nx * L->ny * L->nz, 1);
    for (int z = 0; z < L->nz; z++)
        for (int y = 0; y < L->ny; y++)
            for (int x = 0; x < L->nx; x++) {
                bool occ = false;
                for (int dz = -lo; dz <= hi && !occ; dz++)
                    for (int dy = -lo; dy <= hi && !occ; dy++)
                        for (int dx = -lo; dx <= hi && !occ; dx++) {
                            int vx = x + dx, vy = y + dy, vz = z + dz;
                            occ = vx >= 0 && vy >= 0 && vz >= 0 && vx < L->nx && vy < L->ny &&
                                  vz < L->nz && mip3d_voxel_occupied(m, n, vx, vy, vz);
                        }
                pyr[0][((size_t)z * L->ny + y) * L->nx + x] = occ;
            }
    while (dims[heights - 1][0] > 1 || dims[heights - 1][1] > 1 || dims[heights - 1][2] > 1) {
        int *p = dims[heights - 1], *c = dims[heights];
        for (int a = 0; a < 3; a++)
            c[a] = (p[a] + 1) / 2;
        pyr[heights] = calloc((size_t)c[0] * c[1] * c[2], 1);
        for (int z = 0; z < p[2]; z++)
            for (int y = 0; y < p[1]; y++)
                for (int x = 0; x < p[0]; x++)
                    pyr[heights][((size_t)(z / 2) * c[1] + y / 2) * c[0] + x / 2] |=
                        pyr[heights - 1][((size_t)z * p[1] + y) * p[0] + x];
        heights++;
    }
    int wrong = 0;
    for (int z = 0; z < L->nz; z++)
        for (int y = 0; y < L->ny; y++)
            for (int x = 0; x < L->nx; x++)
                wrong += octree_cell_height(g, x, y, z) !=
                         descend((const uint8_t *const *)pyr, (const int (*)[3])dims, heights, x,
                                 y, z);
    for (int h = 0; h < heights; h++)
        free(pyr[h]);
    return wrong;
}

TEST(speed_octree_block_map_answers_as_a_top_down_descent)
{
    const mip3d_format_t formats[2] = {MIP3D_F32, MIP3D_U8};
    for (int f = 0; f < 2; f++) {
        volume_t v;
        mip3d_t m;
        octree_t o;
        shade_params_t sh;
        build("shepp-logan", "shepp-logan", 30, SHADE_DIFFUSE_FIXED_LIGHT, formats[f], &v, &m, &o,
              &sh);
        int wrong = 0, empty = 0;
        for (int n = 0; n < m.levels; n++) {
            wrong += check_grid(&m, &o.grid[n], n, 2, 3) + check_grid(&m, &o.exact[n], n, 0, 1);
            empty += o.exact[n].any_occupied ? 0 : 1;
        }
        CHECK_MSG(wrong == 0, "%s: %d cells answer differently", mip3d_format_name(formats[f]),
                  wrong);
        CHECK(empty < m.levels);
        CHECK(o.grid[0].empty_height == NULL && o.grid[0].occupied[0] == NULL);
        octree_free(&o);
        mip3d_free(&m);
        volume_free(&v);
    }
}
