/* test_speed_identity.c: the fast tracer (raycast_trace / raycast_trace_batch)
 * against the straightforward reference tracer (raycast_trace_reference),
 * ray by ray, bit for bit: colours, rays, 3D samples and skipped positions.
 * The expectation is never a stored hash: both paths run here, on the same
 * rays, and must agree exactly. */
#include <math.h>
#include <string.h>

#include "harness.h"
#include "render/gaze2d.h"
#include "render/raycast.h"
#include "render/renderer_native.h"
#include "render/scene.h"

typedef struct {
    const char *name;
    shade_case_t lighting;
    float rot_x, rot_y, rot_z;
    float step, zoom, early_termination;
    int side;                     /* image side in pixels */
    int levels;                   /* 2D levels 0 .. levels-1 are traced */
} speed_case_t;

typedef struct {
    uint64_t texels, rgb_diff, lit;
    raycast_counts_t fast, ref, ref_all, off;
} speed_result_t;

static bool counts_equal(const raycast_counts_t *a, const raycast_counts_t *b)
{
    return a->rays == b->rays && a->samples == b->samples &&
           a->samples_skipped == b->samples_skipped;
}

/* Traces every texel of levels 0..levels-1 three ways: in the renderer's
 * batches of 8 neighbours, as scattered batches (every third texel, so that
 * the fast path's packets split), and one by one, each against the
 * reference; plus the reference without the octree for the skip count. */
static void trace_case(const mip3d_t *m, const octree_t *o, const shade_params_t *sh,
                       const speed_case_t *c, speed_result_t *res)
{
    memset(res, 0, sizeof *res);
    view_params_t vp;
    view_defaults(&vp);
    vp.rot_x_deg = c->rot_x;
    vp.rot_y_deg = c->rot_y;
    vp.rot_z_deg = c->rot_z;
    vp.sample_step = c->step;
    vp.zoom = c->zoom;
    vp.early_termination = c->early_termination;
    camera_t cam;
    camera_setup(&cam, &vp, m, c->side, c->side);
    raycast_ctx_t ctx, ctx_off;
    raycast_ctx_init(&ctx, m, o, &cam, sh, &vp);
    vp.use_octree = false;
    raycast_ctx_init(&ctx_off, m, o, &cam, sh, &vp);
    for (int l = 0; l < c->levels; l++) {
        int w = (c->side >> l) + 1, h = (c->side >> l) + 1;
        for (int j = 0; j < h; j++) {
            for (int pass = 0; pass < 3; pass++) {
                int stride = pass == 1 ? 3 : 1;
                for (int i0 = 0; i0 < w; i0 += (pass == 1 ? 3 * RAYCAST_BATCH : RAYCAST_BATCH)) {
                    float px[RAYCAST_BATCH], py[RAYCAST_BATCH], out[RAYCAST_BATCH][3];
                    int n = 0;
                    for (int i = i0; i < w && n < RAYCAST_BATCH; i += stride) {
                        mip2d_texel_point(l, i, j, &px[n], &py[n]);
                        n++;
                    }
                    if (pass == 2) {
                        for (int b = 0; b < n; b++)
                            raycast_trace(&ctx, px[b], py[b], l, out[b], &res->fast);
                    } else {
                        raycast_trace_batch(&ctx, n, px, py, l, out, &res->fast);
                    }
                    for (int b = 0; b < n; b++) {
                        float ref[3], off[3];
                        raycast_trace_reference(&ctx, px[b], py[b], l, ref, &res->ref);
                        res->rgb_diff += memcmp(ref, out[b], sizeof ref) != 0;
                        res->lit += ref[0] > 0.0f;
                        res->texels++;
                        if (pass == 0) {
                            float again[3];
                            raycast_trace_reference(&ctx, px[b], py[b], l, again,
                                                    &res->ref_all);
                            raycast_trace_reference(&ctx_off, px[b], py[b], l, off,
                                                    &res->off);
                            /* Skipped samples are exactly zero. */
                            res->rgb_diff += memcmp(ref, off, sizeof ref) != 0;
                        }
                    }
                }
            }
        }
    }
}

static void check_cases(const mip3d_t *m, const octree_t *o, const shade_params_t *sh,
                        const speed_case_t *cases, int count)
{
    for (int k = 0; k < count; k++) {
        speed_result_t res;
        trace_case(m, o, sh, &cases[k], &res);
        CHECK_MSG(res.rgb_diff == 0, "%s: %llu of %llu texels differ from the reference",
                  cases[k].name, (unsigned long long)res.rgb_diff,
                  (unsigned long long)res.texels);
        CHECK_MSG(counts_equal(&res.fast, &res.ref),
                  "%s: rays %llu/%llu samples %llu/%llu skipped %llu/%llu (fast/reference)",
                  cases[k].name, (unsigned long long)res.fast.rays,
                  (unsigned long long)res.ref.rays, (unsigned long long)res.fast.samples,
                  (unsigned long long)res.ref.samples,
                  (unsigned long long)res.fast.samples_skipped,
                  (unsigned long long)res.ref.samples_skipped);
        /* Over every texel: drawn plus skipped positions with the octree
         * equal the positions drawn without it. */
        CHECK_MSG(res.off.samples == res.ref_all.samples + res.ref_all.samples_skipped,
                  "%s: %llu positions without the octree, %llu + %llu with it",
                  cases[k].name, (unsigned long long)res.off.samples,
                  (unsigned long long)res.ref_all.samples,
                  (unsigned long long)res.ref_all.samples_skipped);
        CHECK_EQ(res.off.samples_skipped, 0);
        /* The comparison is not vacuous: the subject is in view and the
         * octree skipped work. */
        CHECK_MSG(res.lit > res.texels / 20, "%s: only %llu of %llu texels lit",
                  cases[k].name, (unsigned long long)res.lit, (unsigned long long)res.texels);
        CHECK(res.ref.samples_skipped > 0);
    }
}

static void check_phantom(const char *phantom, const char *preset, int n,
                          shade_case_t lighting, const speed_case_t *cases, int count)
{
    volume_t v;
    REQUIRE(phantom_make(phantom, n, n, n * 3 / 4, &v) == PP5_OK);
    v.spacing[2] = 1.5;           /* anisotropic, like CThead's slices */
    classify_tf_t tf;
    REQUIRE(classify_preset(preset, &tf) == PP5_OK);
    shade_params_t sh;
    shade_defaults(&sh);
    sh.lighting = lighting;
    sh.specular = 0.4f;
    mip3d_t m;
    REQUIRE(mip3d_build(&m, &v, &tf, &sh, 2) == PP5_OK);
    octree_t o;
    REQUIRE(octree_build(&o, &m, 2) == PP5_OK);
    check_cases(&m, &o, &sh, cases, count);
    octree_free(&o);
    mip3d_free(&m);
    volume_free(&v);
}

/* Views: oblique, exactly axial (rays parallel to two volume faces),
 * rotated about the view axis; steps with integer and fractional 3D levels;
 * zoomed in and out; early termination off. */
static const speed_case_t phantom_cases[] = {
    {"oblique", SHADE_DIFFUSE_FIXED_LIGHT, 25, 40, 0, 1.0f, 1.0f, 0.95f, 72, 4},
    {"axial", SHADE_DIFFUSE_FIXED_LIGHT, 0, 0, 0, 1.0f, 1.0f, 0.95f, 64, 3},
    {"axial-90", SHADE_DIFFUSE_FIXED_LIGHT, 90, 0, 0, 1.0f, 1.3f, 0.95f, 64, 3},
    {"roll", SHADE_DIFFUSE_FIXED_LIGHT, -35, 160, 70, 1.0f, 0.8f, 1.0f, 80, 4},
    {"step-0.7", SHADE_DIFFUSE_FIXED_LIGHT, 10, -30, 5, 0.7f, 1.0f, 0.95f, 60, 3},
    {"step-2.5", SHADE_DIFFUSE_FIXED_LIGHT, 50, 20, 0, 2.5f, 1.7f, 0.95f, 60, 3},
};

TEST(speed_fast_tracer_matches_reference_shepp_logan_diffuse)
{
    check_phantom("shepp-logan", "shepp-logan", 40, SHADE_DIFFUSE_FIXED_LIGHT, phantom_cases,
                  (int)(sizeof phantom_cases / sizeof phantom_cases[0]));
}

TEST(speed_fast_tracer_matches_reference_marschner_lobb_specular)
{
    static const speed_case_t cases[] = {
        {"specular", SHADE_SPECULAR_FIXED_LIGHT, 20, 35, 10, 1.0f, 1.0f, 0.95f, 56, 3},
        {"specular-step", SHADE_SPECULAR_FIXED_LIGHT, -60, 5, 0, 0.6f, 1.2f, 0.9f, 48, 2},
    };
    check_phantom("marschner-lobb", "marschner-lobb", 33, SHADE_SPECULAR_FIXED_LIGHT, cases, 2);
}

TEST(speed_fast_tracer_matches_reference_sphere_shell_moving)
{
    static const speed_case_t cases[] = {
        {"moving", SHADE_MOVING_OBJECT, 15, 70, 0, 1.0f, 1.0f, 0.95f, 64, 4},
        {"moving-axial", SHADE_MOVING_OBJECT, 0, 90, 0, 1.0f, 1.0f, 1.0f, 48, 3},
    };
    check_phantom("sphere-shell", "sphere-shell", 36, SHADE_MOVING_OBJECT, cases, 2);
}

/* The benchmark's subject and transfer function, at the benchmark's view
 * and two others, on a small image (the rays are full length). */
TEST(speed_fast_tracer_matches_reference_cthead)
{
    if (!pp5_test_shared_data("volumes/cthead/cthead_256x256x113_u16be.raw.gz"))
        SKIP("CThead absent from the shared data");
    scene_t sc;
    REQUIRE(scene_load("cthead", false, &sc) == PP5_OK);
    REQUIRE(classify_preset("ct-skin-ramp", &sc.tf) == PP5_OK);
    shade_params_t sh;
    shade_defaults(&sh);
    mip3d_t m;
    REQUIRE(mip3d_build(&m, &sc.volume, &sc.tf, &sh, 2) == PP5_OK);
    octree_t o;
    REQUIRE(octree_build(&o, &m, 2) == PP5_OK);
    speed_case_t cases[] = {
        {"cthead-face", SHADE_DIFFUSE_FIXED_LIGHT, sc.rot_x_deg, sc.rot_y_deg, sc.rot_z_deg,
         1.0f, 1.0f, 0.95f, 96, 5},
        {"cthead-oblique", SHADE_DIFFUSE_FIXED_LIGHT, sc.rot_x_deg + 33, sc.rot_y_deg - 20,
         sc.rot_z_deg + 10, 1.0f, 1.0f, 0.95f, 80, 3},
        {"cthead-top", SHADE_DIFFUSE_FIXED_LIGHT, 90, 0, 0, 1.0f, 2.0f, 0.95f, 64, 2},
    };
    check_cases(&m, &o, &sh, cases, 3);
    octree_free(&o);
    mip3d_free(&m);
    scene_free(&sc);
}
