/* test_raycast.c: compositing, trilinear sampling and TraceRay against
 * hand-computed cases, and octree skipping leaving images unchanged. */
#include <math.h>
#include <string.h>

#include "harness.h"
#include "render/raycast.h"
#include "render/renderer_native.h"

/* A constant volume classified to opacity 0.5, white, unshaded (gradient 0
 * gives ka + kd = 1). */
static void make_constant_mip(mip3d_t *m, int n)
{
    volume_t v;
    REQUIRE(volume_alloc(&v, n, n, n) == PP5_OK);
    for (size_t i = 0; i < (size_t)n * n * n; i++)
        v.data[i] = 10.0f;
    v.spacing[0] = v.spacing[1] = v.spacing[2] = 1.0;
    classify_tf_t tf = {.count = 1, .contour = {{10.0f, 0.5f, 1.0f, {1.0f, 1.0f, 1.0f}, 0.0f}}};
    shade_params_t sh;
    shade_defaults(&sh);
    REQUIRE(mip3d_build(m, &v, &tf, &sh, 1) == PP5_OK);
    volume_free(&v);
}

TEST(raycast_composite_two_samples_by_hand)
{
    float acc[3] = {0, 0, 0}, a = 0.0f;
    /* Red at opacity 0.5, then green at 0.4 (opacity-weighted colours). */
    float c1[3] = {0.5f, 0.0f, 0.0f}, c2[3] = {0.0f, 0.4f, 0.0f};
    raycast_composite(acc, &a, c1, 0.5f);
    raycast_composite(acc, &a, c2, 0.4f);
    CHECK_NEAR(acc[0], 0.5, 1e-7);
    CHECK_NEAR(acc[1], 0.5 * 0.4, 1e-7);
    CHECK_NEAR(acc[2], 0.0, 1e-7);
    CHECK_NEAR(a, 0.5 + 0.5 * 0.4, 1e-7);
}

TEST(raycast_trilinear_by_hand)
{
    /* 2x2x2 level holding f = x + 2y + 4z in component 0 and a single 1 at
     * (1,1,1) in component 1. */
    float data[8 * 4];
    memset(data, 0, sizeof data);
    for (int z = 0; z < 2; z++)
        for (int y = 0; y < 2; y++)
            for (int x = 0; x < 2; x++) {
                float *v = data + ((z * 2 + y) * 2 + x) * 4;
                v[0] = (float)(x + 2 * y + 4 * z);
                v[1] = (x && y && z) ? 1.0f : 0.0f;
            }
    mip3d_t m;
    memset(&m, 0, sizeof m);
    m.levels = 1;
    m.stride = 4;
    m.level[0] = (mip3d_level_t){.nx = 2, .ny = 2, .nz = 2, .data = data};
    float out[4];
    mip3d_trilerp(&m, 0, 0.25f, 0.5f, 0.75f, out);
    CHECK_NEAR(out[0], 0.25 + 2 * 0.5 + 4 * 0.75, 1e-6);  /* linear: exact */
    CHECK_NEAR(out[1], 0.25 * 0.5 * 0.75, 1e-7);
    /* Outside the grid the edge voxels are repeated. */
    mip3d_trilerp(&m, 0, -3.0f, 5.0f, 0.0f, out);
    CHECK_NEAR(out[0], 0 + 2 * 1 + 0, 1e-6);
}

TEST(raycast_ray_through_constant_volume_by_hand)
{
    mip3d_t m;
    make_constant_mip(&m, 3);
    octree_t o;
    REQUIRE(octree_build(&o, &m, 1) == PP5_OK);
    view_params_t vp;
    view_defaults(&vp);
    camera_t cam;
    camera_setup(&cam, &vp, &m, 1, 1);
    shade_params_t sh;
    shade_defaults(&sh);
    raycast_ctx_t ctx;
    raycast_ctx_init(&ctx, &m, &o, &cam, &sh, &vp);
    /* The single pixel's ray runs along +z through the centre (1,1,1):
     * samples at z = 0, 1, 2 of opacity 0.5 and colour 1 each. */
    float rgb[3];
    raycast_counts_t counts = {0};
    raycast_trace(&ctx, 0.5f, 0.5f, 0, rgb, &counts);
    CHECK_EQ(counts.rays, 1);
    CHECK_EQ(counts.samples, 3);
    CHECK_NEAR(rgb[0], 0.5 + 0.25 + 0.125, 1e-5);
    CHECK_NEAR(rgb[2], 0.875, 1e-5);
    /* At 2D level 1 the spacing is 2: samples at z = 0 and 2 only (the
     * colour of such a ray is checked in
     * raycast_coarse_ray_opacity_correction_by_hand, on a volume without the
     * zero padding this odd size brings). */
    raycast_counts_t c2 = {0};
    raycast_trace(&ctx, 0.5f, 0.5f, 1, rgb, &c2);
    CHECK_EQ(c2.samples, 2);
    octree_free(&o);
    mip3d_free(&m);
}

TEST(raycast_early_termination_stops_ray)
{
    mip3d_t m;
    make_constant_mip(&m, 16);
    view_params_t vp;
    view_defaults(&vp);
    vp.use_octree = false;
    vp.early_termination = 0.9f;
    camera_t cam;
    camera_setup(&cam, &vp, &m, 1, 1);
    shade_params_t sh;
    shade_defaults(&sh);
    raycast_ctx_t ctx;
    raycast_ctx_init(&ctx, &m, NULL, &cam, &sh, &vp);
    float rgb[3];
    raycast_counts_t counts = {0};
    raycast_trace(&ctx, 0.5f, 0.5f, 0, rgb, &counts);
    /* 1 - 0.5^k >= 0.9 first at k = 4. */
    CHECK_EQ(counts.samples, 4);
    CHECK_NEAR(rgb[0], 1.0 - 1.0 / 16.0, 1e-5);
    mip3d_free(&m);
}

static void render_pair(bool perspective, render_mode_t mode)
{
    volume_t v;
    REQUIRE(phantom_make("shepp-logan", 48, 48, 24, &v) == PP5_OK);
    classify_tf_t tf;
    REQUIRE(classify_preset("shepp-logan", &tf) == PP5_OK);
    shade_params_t sh;
    shade_defaults(&sh);
    native_renderer_t r;
    REQUIRE(native_renderer_init(&r, &v, &tf, &sh, 1) == PP5_OK);
    render_settings_t s;
    render_settings_defaults(&s);
    s.width = s.height = 80;
    s.gaze_x = 30;
    s.gaze_y = 35;
    s.mode = mode;
    s.threads = 1;
    s.view.rot_x_deg = 25;
    s.view.rot_y_deg = 40;
    s.view.projection = perspective ? PROJECTION_PERSPECTIVE : PROJECTION_PARALLEL;
    image8_t a, b;
    render_stats_t sa, sb;
    REQUIRE(native_renderer_frame(&r, &s, &a, &sa) == PP5_OK);
    s.view.use_octree = false;
    REQUIRE(native_renderer_frame(&r, &s, &b, &sb) == PP5_OK);
    /* Stated tolerance: zero.  Skipped samples are exactly zero (octree.h), so
     * the images must match byte for byte. */
    size_t n = (size_t)a.width * a.height * 3, diff = 0, lit = 0;
    for (size_t i = 0; i < n; i++) {
        diff += a.pixels[i] != b.pixels[i];
        lit += a.pixels[i] != 0;
    }
    CHECK_EQ(diff, 0);
    CHECK(lit > n / 10);                 /* the phantom is actually in view */
    CHECK_EQ(sa.rays, sb.rays);
    CHECK(sa.samples < sb.samples);      /* and skipping saved work */
    CHECK(sa.samples_skipped > 0);
    CHECK_EQ(sb.samples_skipped, 0);
    image8_free(&a);
    image8_free(&b);
    native_renderer_free(&r);
    volume_free(&v);
}

TEST(raycast_octree_skipping_keeps_image_parallel_full)
{
    render_pair(false, RENDER_MODE_FULL);
}

TEST(raycast_octree_skipping_keeps_image_parallel_gaze)
{
    render_pair(false, RENDER_MODE_GAZE);
}

TEST(raycast_octree_skipping_keeps_image_perspective_gaze)
{
    render_pair(true, RENDER_MODE_GAZE);
}

TEST(raycast_coarse_ray_opacity_correction_by_hand)
{
    /* 4x4x4 volume of opacity 0.5: level 1 is 2x2x2, all 0.5 (no padding).
     * A level-1 ray along z through (1.5, 1.5) samples every 2 units, at
     * z = 0 and 2, from 3D level 1.  Each sample stands for 2 units:
     * a' = 1 - 0.5^2 = 0.75, colour 0.75.  Composite: 0.75 + 0.25 * 0.75. */
    mip3d_t m;
    make_constant_mip(&m, 4);
    REQUIRE(m.level[1].nx == 2);
    CHECK_NEAR(m.level[1].data[MIP3D_A], 0.5, 1e-7);
    view_params_t vp;
    view_defaults(&vp);
    camera_t cam;
    camera_setup(&cam, &vp, &m, 1, 1);
    shade_params_t sh;
    shade_defaults(&sh);
    octree_t o;
    REQUIRE(octree_build(&o, &m, 1) == PP5_OK);
    raycast_ctx_t ctx;
    raycast_ctx_init(&ctx, &m, &o, &cam, &sh, &vp);
    float rgb[3];
    raycast_counts_t counts = {0};
    raycast_trace(&ctx, 0.5f, 0.5f, 1, rgb, &counts);
    CHECK_EQ(counts.samples, 2);
    CHECK_NEAR(rgb[1], 0.75 + 0.25 * 0.75, 1e-5);
    octree_free(&o);
    mip3d_free(&m);
}

TEST(raycast_batch_matches_single_rays_bit_for_bit)
{
    volume_t v;
    REQUIRE(phantom_make("shepp-logan", 40, 36, 30, &v) == PP5_OK);
    classify_tf_t tf;
    REQUIRE(classify_preset("shepp-logan", &tf) == PP5_OK);
    shade_params_t sh;
    shade_defaults(&sh);
    mip3d_t m;
    REQUIRE(mip3d_build(&m, &v, &tf, &sh, 1) == PP5_OK);
    octree_t o;
    REQUIRE(octree_build(&o, &m, 1) == PP5_OK);
    for (int proj = 0; proj < 2; proj++) {
        view_params_t vp;
        view_defaults(&vp);
        vp.projection = proj ? PROJECTION_PERSPECTIVE : PROJECTION_PARALLEL;
        vp.rot_y_deg = 33.0f;
        camera_t cam;
        camera_setup(&cam, &vp, &m, 64, 64);
        raycast_ctx_t ctx;
        raycast_ctx_init(&ctx, &m, &o, &cam, &sh, &vp);
        for (int level = 0; level < 3; level++) {
            float px[RAYCAST_BATCH], py[RAYCAST_BATCH], batch[RAYCAST_BATCH][3];
            for (int i = 0; i < RAYCAST_BATCH; i++) {
                px[i] = 5.5f + 7.0f * (float)i;    /* across the phantom, some misses */
                py[i] = 20.5f + (float)(3 * i % 11);
            }
            raycast_counts_t cb = {0}, cs = {0};
            raycast_trace_batch(&ctx, RAYCAST_BATCH, px, py, level, batch, &cb);
            for (int i = 0; i < RAYCAST_BATCH; i++) {
                float one[3];
                raycast_trace(&ctx, px[i], py[i], level, one, &cs);
                CHECK_MSG(memcmp(one, batch[i], sizeof one) == 0,
                          "level %d, ray %d at (%g, %g): batch (%g, %g, %g), alone (%g, %g, %g)",
                          level, i, px[i], py[i], batch[i][0], batch[i][1], batch[i][2], one[0],
                          one[1], one[2]);
            }
            CHECK_EQ(cb.rays, cs.rays);
            CHECK_EQ(cb.samples, cs.samples);
            CHECK_EQ(cb.samples_skipped, cs.samples_skipped);
            CHECK(cs.samples > 0);
        }
    }
    octree_free(&o);
    mip3d_free(&m);
    volume_free(&v);
}
