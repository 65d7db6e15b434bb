/* test_blend_trace.c: the skipping MIP/DEMIP/MIDA tracer against the
 * reference tracer (every sample position), ray by ray and bit for bit, and
 * both against the whole-ray reference of blend_ray.h fed with the ray's
 * sample materials.  Expectations are never stored: both paths run here. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "render/blend_trace.h"
#include "render/renderer_native.h"
#include "render/scene.h"

typedef struct {
    const char *name;
    blend_mode_t mode;
    demip_reading_t reading;
    demip_depth_t depth;
    float sw, eps;
    float rot_x, rot_y, rot_z;
    int levels, side, stride;     /* 2D levels traced, image side, texel stride */
} trace_case_t;

typedef struct {
    uint64_t rays, diff, lit;
    raycast_counts_t fast, ref;
} trace_result_t;

/* A value pyramid and the 3D mip map header camera_setup reads (its
 * dimensions and spacing): the tracers need nothing else. */
typedef struct {
    scalar_pyramid_t scalar;
    mip3d_t mip;
} pyramid_t;

static void pyramid_build(const volume_t *v, pyramid_t *p)
{
    memset(p, 0, sizeof *p);
    REQUIRE(scalar_pyramid_build(&p->scalar, v, SCALAR_PYRAMID_MAX, 2) == PP5_OK);
    p->mip.levels = 1;
    p->mip.level[0].nx = v->nx;
    p->mip.level[0].ny = v->ny;
    p->mip.level[0].nz = v->nz;
    mip3d_voxel_spacing(v, p->mip.spacing, p->mip.inv_spacing);
}

static void trace_case(const pyramid_t *r, const trace_case_t *tc, const float *window,
                       trace_result_t *res)
{
    memset(res, 0, sizeof *res);
    view_params_t vp;
    view_defaults(&vp);
    vp.rot_x_deg = tc->rot_x;
    vp.rot_y_deg = tc->rot_y;
    vp.rot_z_deg = tc->rot_z;
    blend_settings_t b;
    blend_settings_defaults(&b);
    b.mode = tc->mode;
    b.reading = tc->reading;
    b.depth = tc->depth;
    b.sphere_weight = tc->sw;
    b.tolerance = tc->eps;
    if (window) {
        b.window_centre = window[0];
        b.window_width = window[1];
    }
    camera_t cam;
    camera_setup(&cam, &vp, &r->mip, tc->side, tc->side);
    blend_ctx_t c;
    blend_ctx_init(&c, &r->scalar, &cam, &vp, &b);
    for (int l = 0; l < tc->levels; l++) {
        int n = (tc->side >> l) + 1;
        for (int j = 0; j < n; j += tc->stride) {
            /* A row in the renderer's batches of 8 (packets), the guess
             * carried along as the renderer does; every fifth batch gets a
             * far too high guess (the fallback path). */
            float guess = 0.0f;
            for (int i0 = 0, batch = 0; i0 < n; i0 += BLEND_BATCH, batch++) {
                float px[BLEND_BATCH], py[BLEND_BATCH], fast[BLEND_BATCH][3];
                int cnt = n - i0 < BLEND_BATCH ? n - i0 : BLEND_BATCH;
                for (int i = 0; i < cnt; i++)
                    mip2d_texel_point(l, i0 + i, j, &px[i], &py[i]);
                float g = batch % 5 == 3 ? 0.999f : guess;
                blend_trace_batch(&c, cnt, px, py, l, fast, &g, &res->fast);
                guess = g;
                for (int i = 0; i < cnt; i++) {
                    float ref[3];
                    blend_trace_reference(&c, px[i], py[i], l, ref, &res->ref);
                    res->rays++;
                    res->diff += memcmp(fast[i], ref, sizeof ref) != 0;
                    res->lit += ref[0] + ref[1] + ref[2] > 0.0f;
                }
            }
        }
    }
}

static void check_cases(const pyramid_t *r, const trace_case_t *cases, int n,
                        const float *window)
{
    for (int i = 0; i < n; i++) {
        trace_result_t res;
        trace_case(r, &cases[i], window, &res);
        CHECK_MSG(res.diff == 0, "%s: %llu of %llu rays differ from the reference",
                  cases[i].name, (unsigned long long)res.diff, (unsigned long long)res.rays);
        const raycast_counts_t *f = &res.fast;
        CHECK_MSG(f->samples - f->samples_retraced + f->samples_skipped == res.ref.samples,
                  "%s: drawn %llu - retraced %llu + skipped %llu != reference %llu",
                  cases[i].name, (unsigned long long)f->samples,
                  (unsigned long long)f->samples_retraced,
                  (unsigned long long)f->samples_skipped, (unsigned long long)res.ref.samples);
        CHECK_MSG(f->samples < res.ref.samples, "%s: skipping drew no fewer samples",
                  cases[i].name);
        CHECK_MSG(cases[i].mode == BLEND_MIDA || f->samples_retraced > 0,
                  "%s: the fallback after a too-high guess never ran", cases[i].name);
        CHECK_MSG(res.lit > res.rays / 20, "%s: only %llu of %llu rays lit", cases[i].name,
                  (unsigned long long)res.lit, (unsigned long long)res.rays);
    }
}

static const trace_case_t phantom_cases[] = {
    {"mip front", BLEND_MIP, DEMIP_READING_A, DEMIP_DEPTH_EXACT, 0, 0.1f, 0, 0, 0, 3, 64, 5},
    {"mip oblique", BLEND_MIP, DEMIP_READING_A, DEMIP_DEPTH_EXACT, 0, 0.1f, 23, 37, 11, 3, 64, 5},
    {"demip A exact sphere", BLEND_DEMIP, DEMIP_READING_A, DEMIP_DEPTH_EXACT, 0.3f, 0.1f, -31,
     142, 5, 3, 64, 5},
    {"demip B entry eps0", BLEND_DEMIP, DEMIP_READING_B, DEMIP_DEPTH_ENTRY_PLUS_LENGTH, 0, 0.0f,
     71, -12, 40, 3, 64, 5},
    {"demip A eps0.4", BLEND_DEMIP, DEMIP_READING_A, DEMIP_DEPTH_EXACT, 0, 0.4f, 90, 0, 0, 3, 64,
     5},
    {"mida front", BLEND_MIDA, DEMIP_READING_A, DEMIP_DEPTH_EXACT, 0, 0.1f, 0, 0, 0, 3, 64, 5},
    {"mida oblique", BLEND_MIDA, DEMIP_READING_A, DEMIP_DEPTH_EXACT, 0, 0.1f, 17, 203, -8, 3, 64,
     5},
};

static void phantom_pyramid(const char *name, int nx, int ny, int nz, pyramid_t *r, volume_t *v)
{
    REQUIRE(phantom_make(name, nx, ny, nz, v) == PP5_OK);
    pyramid_build(v, r);
}

TEST(blend_fast_tracer_matches_reference_shepp_logan)
{
    volume_t v;
    pyramid_t r;
    phantom_pyramid("shepp-logan", 61, 54, 37, &r, &v);
    check_cases(&r, phantom_cases, (int)(sizeof phantom_cases / sizeof phantom_cases[0]), NULL);
    /* A window that cuts the skull shell's top: saturated rays stop early. */
    const float window[2] = {120.0f, 120.0f};
    check_cases(&r, phantom_cases, 3, window);
    scalar_pyramid_free(&r.scalar);
    volume_free(&v);
}

TEST(blend_fast_tracer_matches_reference_sphere_shell)
{
    volume_t v;
    pyramid_t r;
    phantom_pyramid("sphere-shell", 40, 33, 47, &r, &v);
    check_cases(&r, phantom_cases, (int)(sizeof phantom_cases / sizeof phantom_cases[0]), NULL);
    scalar_pyramid_free(&r.scalar);
    volume_free(&v);
}

TEST(blend_fast_tracer_matches_reference_cthead)
{
    scene_t sc;
    if (!pp5_test_shared_data("volumes/cthead/cthead_256x256x113_u16be.raw.gz"))
        SKIP("volumes/cthead/cthead_256x256x113_u16be.raw.gz absent (see shared/data/README)");
    REQUIRE(scene_load("cthead", false, &sc) == PP5_OK);
    /* Half size: the real data's structure at an eighth of the build cost. */
    volume_t half;
    REQUIRE(volume_resample(&sc.volume, 128, 128, 57, &half) == PP5_OK);
    memcpy(half.spacing, sc.volume.spacing, sizeof half.spacing);
    pyramid_t r;
    pyramid_build(&half, &r);
    const trace_case_t cases[] = {
        {"cthead mip face", BLEND_MIP, DEMIP_READING_A, DEMIP_DEPTH_EXACT, 0, 0.1f, 90, 0, 180,
         3, 192, 9},
        {"cthead demip oblique", BLEND_DEMIP, DEMIP_READING_B, DEMIP_DEPTH_EXACT, 0.3f, 0.1f, 70,
         30, 160, 3, 256, 5},
        {"cthead mida face", BLEND_MIDA, DEMIP_READING_A, DEMIP_DEPTH_EXACT, 0, 0.1f, 90, 0, 180,
         2, 128, 9},
    };
    const float window[2] = {sc.window_centre, sc.window_width};
    check_cases(&r, cases, 3, window);
    scalar_pyramid_free(&r.scalar);
    volume_free(&half);
    scene_free(&sc);
}

/* The tracer's result is what blend_ray_from_samples makes of the ray's
 * sample materials: the statement a firmware restatement mirrors. */
TEST(blend_tracer_equals_whole_ray_reference)
{
    volume_t v;
    pyramid_t r;
    phantom_pyramid("shepp-logan", 61, 54, 37, &r, &v);
    const blend_mode_t modes[3] = {BLEND_MIP, BLEND_DEMIP, BLEND_MIDA};
    long rays = 0, equal = 0, lit = 0;
    float m[4096];
    for (int mi = 0; mi < 3; mi++) {
        view_params_t vp;
        view_defaults(&vp);
        vp.rot_y_deg = 30.0f;
        vp.rot_x_deg = -20.0f;
        blend_settings_t b;
        blend_settings_defaults(&b);
        b.mode = modes[mi];
        b.reading = DEMIP_READING_B;
        camera_t cam;
        camera_setup(&cam, &vp, &r.mip, 64, 64);
        blend_ctx_t c;
        blend_ctx_init(&c, &r.scalar, &cam, &vp, &b);
        for (int l = 0; l < 2; l++)
            for (int j = 0; j < 64 >> l; j += 3)
                for (int i = 0; i < 64 >> l; i += 3) {
                    float px, py;
                    mip2d_texel_point(l, i, j, &px, &py);
                    blend_ray_info_t info;
                    blend_trace_reference_info(&c, px, py, l, &info);
                    long n = blend_ray_materials(&c, px, py, l, m, 4096);
                    REQUIRE(n >= 0 && n <= 4096);
                    blend_ray_result_t res;
                    blend_ray_from_samples(&c.frame, m, n, info.geom.base, &res);
                    bool same = res.samples == (long)info.samples;
                    if (b.mode == BLEND_MIDA) {
                        same = same && res.mida_colour == info.rgb[0];
                    } else {
                        same = same && res.m_max == info.m_max && res.k_max == info.k_max &&
                               res.k_stop == info.k_stop && res.occluded == info.occluded;
                    }
                    rays++;
                    equal += same;
                    lit += info.rgb[0] > 0.0f;
                }
    }
    CHECK_EQ(equal, rays);
    CHECK(lit > rays / 4);
    scalar_pyramid_free(&r.scalar);
    volume_free(&v);
}
