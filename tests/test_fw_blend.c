/* test_fw_blend.c: MIP, DEMIP and MIDA on the emulated machine against render/ (ray by ray, image by image), the restated per-ray maths against render/blend_ray.h, and what the machine refuses. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "firmware/gp/vr_blend_kernels.h"
#include "firmware/host/fw_session.h"
#include "harness.h"
#include "render/blend_trace.h"

/* A small phantom, a blend and a view; 48x48 images keep a frame fast. */
typedef struct {
    volume_t v;
    classify_tf_t tf;
    shade_params_t shade;
    render_settings_t rs;
    pp5_params_t p;
    fw_options_t o;
} blend_fixture_t;

static void blend_fixture(blend_fixture_t *f, blend_mode_t mode, render_mode_t rmode)
{
    memset(f, 0, sizeof *f);
    REQUIRE(phantom_make("shepp-logan", 40, 40, 36, &f->v) == PP5_OK);
    REQUIRE(classify_preset("shepp-logan", &f->tf) == PP5_OK);
    shade_defaults(&f->shade);
    render_settings_defaults(&f->rs);
    f->rs.width = f->rs.height = 48;
    f->rs.mode = rmode;
    f->rs.threads = 1;
    f->rs.view.rot_x_deg = 20.0f;
    f->rs.view.rot_y_deg = 30.0f;
    f->rs.level_tables = true;       /* 2DLevel the machine's way: like for like */
    f->rs.blend.mode = mode;
    /* The phantom is 0..200: a window from 40 to 190 leaves the brain and
     * the air cold (skipped) and saturates the skull's voxel centres, so
     * that ray 1 stops early on some rays and reading B meets the front
     * skull as an occluder of the back on others. */
    f->rs.blend.window_centre = 115.0f;
    f->rs.blend.window_width = 150.0f;
    f->rs.blend.tolerance = 0.1f;
    pp5_params_default(&f->p);
    f->p.n_gp = 4;
    f->p.n_renderers = 4;
    fw_options_default(&f->o);
}

#define BLEND_JOB(f)                                                                           \
    (&(render_job_t){.volume = &(f).v, .volume_name = "phantom", .tf = (f).tf,                \
                     .shade = (f).shade, .settings = (f).rs, .frames = 1})

/* render/'s context for the fixture's view (the reference tracer). */
typedef struct {
    native_renderer_t nr;
    camera_t cam;
    blend_ctx_t ctx;
} native_ref_t;

static void native_ref_open(native_ref_t *n, const blend_fixture_t *f)
{
    REQUIRE(native_renderer_init(&n->nr, &f->v, &f->tf, &f->shade, 1) == PP5_OK);
    REQUIRE(native_renderer_build_scalar(&n->nr, &f->v, f->rs.blend.pyramid) == PP5_OK);
    camera_setup(&n->cam, &f->rs.view, &n->nr.mip, f->rs.width, f->rs.height);
    blend_ctx_init(&n->ctx, &n->nr.scalar, &n->cam, &f->rs.view, &f->rs.blend);
}

/* Every texel ray of GP g's band, traced by the GP's kernel on the units a
 * resident frame left in its cache, against render/'s reference tracer:
 * the same three floats, bit for bit.  Returns the rays compared.  The
 * fixture is full resolution: a gaze-directed frame fetches only the units
 * of the texels it needs, while this traces them all (the gaze-directed
 * levels are compared image against image below). */
static int rays_against_reference(blend_fixture_t *f, int g, vr_blend_tally_t *tally)
{
    f->o.division = FW_DIVISION_RESIDENT;
    fw_session_t s;
    REQUIRE_MSG(fw_session_init(&s, BLEND_JOB(*f), &f->p, &f->o) == PP5_OK, "session: %s",
                pp5_error_text());
    fw_frame_result_t r;
    REQUIRE_MSG(fw_session_frame(&s, 20.0, 26.0, NULL, &r) == PP5_OK, "frame: %s", pp5_error_text());
    gp_t *gp = &s.m.gp[g];
    vr_state_t *st = fw_state(gp);
    REQUIRE(st != NULL);
    native_ref_t n;
    native_ref_open(&n, f);
    int rays = 0, same = 0;
    uint64_t skipped = 0;
    for (int m = 0; m < st->levels2d; m++) {
        vr_ray_consts_t rc;
        vr_ray_consts(st, m, &rc);
        size_t rows = (size_t)(st->jhi[m] - st->jlo[m] + 2);
        st->texel[m] = fw_alloc(gp, rows * (size_t)st->tw[m] * 3 * sizeof(float));
        REQUIRE(st->texel[m] != NULL);
        for (int j = st->jlo[m]; j <= st->jhi[m]; j++)
            for (int i = 0; i < st->tw[m]; i++) {
                vr_ray_slot_t slot = {m, (size_t)(j - st->jlo[m]) * st->tw[m] + (size_t)i};
                float px = (float)(i << m) + 0.5f, py = (float)(j << m) + 0.5f;
                vr_blend_trace(st, &rc, px, py, slot, NULL, NULL, NULL, &skipped, tally);
                const float *got = st->texel[m] + slot.idx * 3;
                blend_ray_info_t info;
                blend_trace_reference_info(&n.ctx, px, py, m, &info);
                bool ok = memcmp(got, info.rgb, sizeof info.rgb) == 0;
                if (!ok && rays - same < 3)
                    CHECK_MSG(ok, "GP %d texel (%d, %d) level %d: machine %.9g %.9g %.9g, render/ "
                              "%.9g %.9g %.9g (m_max %.9g k_max %ld k_stop %ld)", g, i, j, m,
                              got[0], got[1], got[2], info.rgb[0], info.rgb[1], info.rgb[2],
                              info.m_max, info.k_max, info.k_stop);
                same += ok;
                rays++;
            }
        fw_free(gp, st->texel[m]);
        st->texel[m] = NULL;
    }
    CHECK_EQ(same, rays);
    /* parallel views skip the cold cells (their samples are material 0) */
    CHECK(f->rs.view.projection == PROJECTION_PERSPECTIVE || skipped > 0);
    native_renderer_free(&n.nr);
    fw_session_free(&s);
    return rays;
}

TEST(fw_blend_rays_equal_render_reference_mip)
{
    blend_fixture_t f;
    blend_fixture(&f, BLEND_MIP, RENDER_MODE_FULL);
    /* 40 to 100: the thin skull's samples (its voxels are partial volumes
     * at 40^3) saturate, and ray 1 stops there */
    f.rs.blend.window_centre = 70.0f;
    f.rs.blend.window_width = 60.0f;
    vr_blend_tally_t t = {0};
    CHECK(rays_against_reference(&f, 1, &t) > 100);
    CHECK(t.saturated > 0);          /* ray 1 stopped at material 1 somewhere */
    volume_free(&f.v);
}

TEST(fw_blend_rays_equal_render_reference_demip_b_sphere_box_pyramid)
{
    blend_fixture_t f;
    blend_fixture(&f, BLEND_DEMIP, RENDER_MODE_FULL);
    f.rs.blend.reading = DEMIP_READING_B;
    f.rs.blend.sphere_weight = 0.3f;
    f.rs.blend.depth_weight = 0.2f;
    f.rs.blend.pyramid = SCALAR_PYRAMID_BOX;
    /* Slices 1.7 apart: the camera's 1 / spacing and the mip map's differ
     * in the last bit there, and the rays must use render/'s. */
    f.v.spacing[2] = 1.7;
    vr_blend_tally_t t = {0};
    CHECK(rays_against_reference(&f, 2, &t) > 100);
    CHECK(t.ray2_samples > 0);
    CHECK(t.occluded > 0);           /* the occluder test decided some rays */
    volume_free(&f.v);
}

TEST(fw_blend_rays_equal_render_reference_mida_perspective_entry_depth)
{
    blend_fixture_t f;
    blend_fixture(&f, BLEND_MIDA, RENDER_MODE_FULL);
    f.rs.view.projection = PROJECTION_PERSPECTIVE;
    f.rs.blend.window_centre = 70.0f;  /* the skull opaque: MIDA stops early */
    f.rs.blend.window_width = 60.0f;
    vr_blend_tally_t t = {0};
    CHECK(rays_against_reference(&f, 1, &t) > 100);
    CHECK(t.terminated > 0);
    volume_free(&f.v);
    blend_fixture(&f, BLEND_DEMIP, RENDER_MODE_FULL);
    f.rs.view.projection = PROJECTION_PERSPECTIVE;
    f.rs.blend.depth = DEMIP_DEPTH_ENTRY_PLUS_LENGTH;
    CHECK(rays_against_reference(&f, 3, &t) > 100);
    volume_free(&f.v);
}

/* The machine's frame image against render/'s on the same job: byte for
 * byte (the GPs' rays are render/'s floats, the 2D resampling the
 * compositing path's, checked by its own tests). */
static void image_against_native(blend_fixture_t *f, fw_division_t division, fw_frame_result_t *r)
{
    f->o.division = division;
    const render_job_t *job = BLEND_JOB(*f);
    fw_session_t s;
    REQUIRE_MSG(fw_session_init(&s, job, &f->p, &f->o) == PP5_OK, "session: %s", pp5_error_text());
    image8_t img = {0}, ref = {0};
    REQUIRE_MSG(fw_session_frame(&s, 20.0, 26.0, &img, r) == PP5_OK, "frame: %s",
                pp5_error_text());
    native_renderer_t nr;
    REQUIRE(native_renderer_init(&nr, &f->v, &f->tf, &f->shade, 1) == PP5_OK);
    REQUIRE(native_renderer_build_scalar(&nr, &f->v, f->rs.blend.pyramid) == PP5_OK);
    render_settings_t rs = f->rs;
    rs.gaze_x = 20.0;
    rs.gaze_y = 26.0;
    render_stats_t ns;
    REQUIRE(native_renderer_frame(&nr, &rs, &ref, &ns) == PP5_OK);
    REQUIRE(img.width == ref.width && img.height == ref.height && img.channels == ref.channels);
    size_t n = (size_t)img.width * img.height * img.channels, diff = 0, first = n;
    for (size_t i = 0; i < n; i++)
        if (img.pixels[i] != ref.pixels[i]) {
            diff++;
            first = first < n ? first : i;
        }
    CHECK_MSG(diff == 0, "%s, %s: %zu of %zu bytes differ from render/'s (first at pixel %zu: "
              "machine %u, render/ %u)", blend_mode_name(f->rs.blend.mode),
              fw_division_name(division), diff, n, first / (size_t)img.channels,
              first < n ? img.pixels[first] : 0, first < n ? ref.pixels[first] : 0);
    size_t lit = 0;
    for (size_t i = 0; i < n; i++)
        lit += ref.pixels[i] > 0;
    CHECK(lit > n / 10);             /* the phantom is in the picture */
    CHECK(r->rays > 0 && r->samples > 0 && r->frame_time_s > 0.0);
    CHECK(r->ring_bytes_total > 0);
    image8_free(&img);
    image8_free(&ref);
    native_renderer_free(&nr);
    fw_session_free(&s);
}

TEST(fw_blend_images_equal_native_in_both_divisions)
{
    const blend_mode_t modes[3] = {BLEND_MIP, BLEND_DEMIP, BLEND_MIDA};
    for (int k = 0; k < 3; k++)
        for (int d = 0; d < 2; d++) {
            blend_fixture_t f;
            blend_fixture(&f, modes[k], k == 1 ? RENDER_MODE_FULL : RENDER_MODE_GAZE);
            if (modes[k] == BLEND_DEMIP)
                f.rs.blend.sphere_weight = 0.3f;   /* the legend drawn on both */
            fw_frame_result_t r;
            image_against_native(&f, d == 0 ? FW_DIVISION_IMAGE_BANDS : FW_DIVISION_RESIDENT, &r);
            if (modes[k] == BLEND_DEMIP)
                CHECK(r.ray2_samples > 0 && r.ray2_samples < r.samples);
            volume_free(&f.v);
        }
}

/* Resident on the paper's machine (16 GPs, 8 MB each) with a small image:
 * each GP's band crosses the whole volume, so its cache fills local memory
 * and every later frame's units must find room by eviction.  Room is
 * counted from a unit's request, so the units of one pass in flight cannot
 * add up to more than the cache holds. */
TEST(fw_blend_resident_cache_full_frames_keep_within_memory)
{
    blend_fixture_t f;
    blend_fixture(&f, BLEND_DEMIP, RENDER_MODE_GAZE);
    volume_free(&f.v);
    REQUIRE(phantom_make("shepp-logan", 256, 256, 109, &f.v) == PP5_OK);
    f.rs.width = f.rs.height = 40;
    f.rs.blend.window_centre = 100.0f;   /* the phantom's whole range: less is skipped */
    f.rs.blend.window_width = 200.0f;
    f.p.n_gp = 16;
    f.p.n_renderers = 16;
    f.o.division = FW_DIVISION_RESIDENT;
    fw_session_t s;
    REQUIRE_MSG(fw_session_init(&s, BLEND_JOB(f), &f.p, &f.o) == PP5_OK, "session: %s",
                pp5_error_text());
    native_renderer_t nr;
    REQUIRE(native_renderer_init(&nr, &f.v, &f.tf, &f.shade, 1) == PP5_OK);
    REQUIRE(native_renderer_build_scalar(&nr, &f.v, f.rs.blend.pyramid) == PP5_OK);
    for (int k = 0; k < 3; k++) {
        image8_t img = {0}, ref = {0};
        fw_frame_result_t r;
        double gx = 9.5 + 10.0 * k, gy = 19.5;
        pp5_status_t st = fw_session_frame(&s, gx, gy, &img, &r);
        CHECK_MSG(st == PP5_OK, "frame %d: %s", k, pp5_error_text());
        if (st != PP5_OK)
            break;
        render_settings_t rs = f.rs;
        rs.gaze_x = gx;
        rs.gaze_y = gy;
        render_stats_t ns;
        REQUIRE(native_renderer_frame(&nr, &rs, &ref, &ns) == PP5_OK);
        size_t n = (size_t)img.width * img.height * img.channels, diff = 0;
        for (size_t i = 0; i < n; i++)
            diff += img.pixels[i] != ref.pixels[i];
        CHECK_MSG(diff == 0, "frame %d: %zu of %zu bytes differ from render/'s", k, diff, n);
        image8_free(&img);
        image8_free(&ref);
    }
    native_renderer_free(&nr);
    fw_session_free(&s);
    volume_free(&f.v);
}

TEST(fw_blend_object_slabs_refused_with_reason)
{
    blend_fixture_t f;
    blend_fixture(&f, BLEND_MIP, RENDER_MODE_GAZE);
    f.o.division = FW_DIVISION_OBJECT_SLABS;
    fw_session_t s;
    pp5_status_t st = fw_session_init(&s, BLEND_JOB(f), &f.p, &f.o);
    CHECK(st == PP5_E_UNSUPPORTED);
    CHECK(strstr(pp5_error_text(), "object slabs") != NULL);
    if (st == PP5_OK)
        fw_session_free(&s);
    volume_free(&f.v);
}

/* The command: a machine DEMIP frame with the sphere, its report's blend
 * statistics and its agreement with render/; object slabs refused with the
 * reason and no image written. */
TEST(fw_blend_cli_renders_on_the_machine_and_refuses_object_slabs)
{
    const char *dir = pp5_test_outdir();
    char args[1400], out[600], err[600], json[600], png[600];
    snprintf(out, sizeof out, "%s/stdout.txt", dir);
    snprintf(err, sizeof err, "%s/stderr.txt", dir);
    snprintf(json, sizeof json, "%s/r.json", dir);
    snprintf(png, sizeof png, "%s/d.png", dir);
    snprintf(args, sizeof args, "render --machine --phantom sphere-shell --size 32x32 --blend demip "
             "--demip-reading B --sphere-weight 0.3 --division resident --report %s --out %s",
             json, png);
    CHECK_EQ(pp5_test_run_cli(args, out, NULL), 0);
    char *text = pp5_test_read_file(out);
    REQUIRE(text);
    CHECK(strstr(text, "bottleneck") != NULL);
    CHECK(strstr(text, "DEMIP ray-2 samples") != NULL);
    CHECK_MSG(strstr(text, "PSNR inf dB, max diff 0") != NULL, "not identical to render/: %s", text);
    free(text);
    char *report = pp5_test_read_file(json);
    REQUIRE(report);
    CHECK(strstr(report, "\"demip_ray2_samples\"") != NULL);
    CHECK(strstr(report, "\"blend\": \"demip\"") != NULL);
    free(report);
    remove(png);
    snprintf(args, sizeof args, "render --machine --phantom sphere-shell --size 32x32 --blend mip "
             "--division object-slabs --out %s", png);
    CHECK(pp5_test_run_cli(args, NULL, err) != 0);
    text = pp5_test_read_file(err);
    REQUIRE(text);
    CHECK_MSG(strstr(text, "not cast in object slabs") != NULL, "message: %s", text);
    free(text);
    struct stat sb;
    CHECK(stat(png, &sb) != 0);
}

/* The host's band estimate for a blend (fw_estimate.c): rays through cold
 * cells cost nothing, a saturated cell stops ray 1, the rest is sampled to
 * the end.  Its bands balance a blend's first frame better than bands of
 * equal rays. */
TEST(fw_blend_band_estimate_balances_better_than_rays)
{
    double imbalance[2];
    for (int k = 0; k < 2; k++) {
        blend_fixture_t f;
        blend_fixture(&f, BLEND_DEMIP, RENDER_MODE_FULL);
        f.o.division = FW_DIVISION_RESIDENT;
        f.o.plan = k == 0 ? FW_PLAN_SAMPLES : FW_PLAN_RAYS;
        fw_session_t s;
        REQUIRE(fw_session_init(&s, BLEND_JOB(f), &f.p, &f.o) == PP5_OK);
        fw_frame_result_t r;
        REQUIRE(fw_session_frame(&s, 24.0, 24.0, NULL, &r) == PP5_OK);
        imbalance[k] = r.gp_imbalance;
        fw_session_free(&s);
        volume_free(&f.v);
    }
    CHECK_MSG(imbalance[0] < imbalance[1], "samples plan %.3f, rays plan %.3f", imbalance[0],
              imbalance[1]);
}
