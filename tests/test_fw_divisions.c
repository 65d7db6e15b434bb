/* test_fw_divisions.c: the machine renderer's work divisions: the resident cache (never stale, nothing refetched for a repeated frame), object slabs against render/, band planning by samples, and the division axis of the commands. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "firmware/host/fw_reference.h"
#include "firmware/host/fw_session.h"
#include "harness.h"

typedef struct {
    volume_t v;
    render_job_t job;
    pp5_params_t p;
} div_fixture_t;

static void div_fixture_sized(div_fixture_t *f, shade_case_t lighting, int side, int n_gp,
                              int vx, int vz)
{
    memset(f, 0, sizeof *f);
    REQUIRE(phantom_make("shepp-logan", vx, vx, vz, &f->v) == PP5_OK);
    f->job.volume = &f->v;
    f->job.volume_name = "phantom";
    f->job.frames = 1;
    REQUIRE(classify_preset("shepp-logan", &f->job.tf) == PP5_OK);
    shade_defaults(&f->job.shade);
    f->job.shade.lighting = lighting;
    if (lighting != SHADE_DIFFUSE_FIXED_LIGHT)
        f->job.shade.specular = 0.5f;
    render_settings_defaults(&f->job.settings);
    f->job.settings.width = f->job.settings.height = side;
    f->job.settings.mode = RENDER_MODE_GAZE;
    f->job.settings.threads = 1;
    f->job.settings.level_tables = true;
    f->job.settings.view.rot_x_deg = 20.0f;
    f->job.settings.view.rot_y_deg = 30.0f;
    pp5_params_default(&f->p);
    f->p.n_gp = (unsigned)n_gp;
    f->p.n_renderers = 4;
}

static void div_fixture(div_fixture_t *f, shade_case_t lighting, int side, int n_gp)
{
    div_fixture_sized(f, lighting, side, n_gp, 40, 36);
}

static int max_diff(const image8_t *a, const image8_t *b)
{
    int m = 0;
    for (size_t i = 0; i < (size_t)a->width * a->height * 3; i++) {
        int d = abs((int)a->pixels[i] - (int)b->pixels[i]);
        m = d > m ? d : m;
    }
    return m;
}

static double psnr(const image8_t *a, const image8_t *b)
{
    double se = 0;
    size_t n = (size_t)a->width * a->height * 3;
    for (size_t i = 0; i < n; i++) {
        double d = (double)a->pixels[i] - (double)b->pixels[i];
        se += d * d;
    }
    return se == 0 ? INFINITY : 10.0 * log10(255.0 * 255.0 / (se / (double)n));
}

/* One frame of a fresh session (nothing cached) of job with options o. */
static void fresh_frame(const div_fixture_t *f, const render_job_t *job, const fw_options_t *o,
                        double gx, double gy, image8_t *img, fw_frame_result_t *r)
{
    fw_session_t s;
    REQUIRE_MSG(fw_session_init(&s, job, &f->p, o) == PP5_OK, "session: %s", pp5_error_text());
    REQUIRE_MSG(fw_session_frame(&s, gx, gy, img, r) == PP5_OK, "frame: %s", pp5_error_text());
    fw_session_free(&s);
}

/* View-dependent shading under resident (a moving object: the PPs apply
 * diffuse and specular every frame): after the view changes, and after the
 * light changes, every frame equals the same frame rendered by a fresh
 * session (which has no cache) byte for byte. */
TEST(fw_division_resident_cache_never_serves_a_stale_unit)
{
    div_fixture_t f;
    div_fixture(&f, SHADE_MOVING_OBJECT, 48, 3);
    fw_options_t o;
    fw_options_default(&o);
    o.division = FW_DIVISION_RESIDENT;
    fw_session_t s;
    REQUIRE(fw_session_init(&s, &f.job, &f.p, &o) == PP5_OK);
    render_job_t job = f.job;
    const float light2[3] = {-0.3f, 0.8f, -0.52f};
    for (int step = 0; step < 3; step++) {
        if (step == 1) {
            job.settings.view.rot_y_deg = 55.0f;        /* a new view */
            REQUIRE(fw_session_set_view(&s, &job.settings.view) == PP5_OK);
        } else if (step == 2) {
            memcpy(job.shade.light_dir, light2, sizeof light2);   /* a new light */
            REQUIRE(fw_session_set_light(&s, light2) == PP5_OK);
        }
        image8_t kept = {0}, fresh = {0};
        fw_frame_result_t rk, rf;
        REQUIRE(fw_session_frame(&s, 20.0, 25.0, &kept, &rk) == PP5_OK);
        fresh_frame(&f, &job, &o, 20.0, 25.0, &fresh, &rf);
        CHECK_MSG(max_diff(&kept, &fresh) == 0, "step %d: cached vs fresh max diff %d", step,
                  max_diff(&kept, &fresh));
        CHECK_EQ(rk.samples, rf.samples);
        /* A change of view or light under specular lighting refetches. */
        if (step > 0)
            CHECK_MSG(rk.ring_bytes[RING_CLASS_DATA] > 0, "step %d fetched nothing", step);
        image8_free(&kept);
        image8_free(&fresh);
    }
    fw_session_free(&s);
    volume_free(&f.v);
}

/* The paper's §6 case (diffuse, view fixed, only the gaze moves): a repeated
 * frame under resident moves no mip-map bytes; image-bands refetches all. */
TEST(fw_division_resident_repeated_diffuse_frame_moves_no_mip_map_bytes)
{
    div_fixture_t f;
    div_fixture(&f, SHADE_DIFFUSE_FIXED_LIGHT, 48, 3);
    for (int d = 0; d < 2; d++) {
        fw_options_t o;
        fw_options_default(&o);
        o.division = d ? FW_DIVISION_RESIDENT : FW_DIVISION_IMAGE_BANDS;
        fw_session_t s;
        REQUIRE(fw_session_init(&s, &f.job, &f.p, &o) == PP5_OK);
        fw_frame_result_t r1, r2;
        REQUIRE(fw_session_frame(&s, 24.0, 24.0, NULL, &r1) == PP5_OK);
        REQUIRE(fw_session_frame(&s, 24.0, 24.0, NULL, &r2) == PP5_OK);
        CHECK(r1.ring_bytes[RING_CLASS_DATA] > 0);
        if (d)
            CHECK_MSG(r2.ring_bytes[RING_CLASS_DATA] == 0, "resident refetched %llu bytes",
                      (unsigned long long)r2.ring_bytes[RING_CLASS_DATA]);
        else
            CHECK_EQ(r2.ring_bytes[RING_CLASS_DATA], r1.ring_bytes[RING_CLASS_DATA]);
        /* Resident fetches units, not whole bricks: less than image-bands. */
        fw_session_free(&s);
    }
    volume_free(&f.v);
}

/* Object slabs composite each ray from segments whose early termination
 * cannot see the opacity in front of them: the same rays, more samples, and
 * an image within 35 dB of render/ on the machine's formats. */
static void check_object_slabs_against_native(int size, int n_gp)
{
    div_fixture_t f;
    div_fixture(&f, SHADE_DIFFUSE_FIXED_LIGHT, size, n_gp);
    fw_options_t o;
    fw_options_default(&o);
    o.division = FW_DIVISION_OBJECT_SLABS;
    native_renderer_t quant;
    REQUIRE(fw_reference_init(&quant, &f.job, true) == PP5_OK);
    /* the centre, and a point towards a corner (12, 50 of a 64-pixel side) */
    const double gazes[2][2] = {{0.5 * (size - 1), 0.5 * (size - 1)},
                                {size * 12.0 / 64.0, size * 50.0 / 64.0}};
    for (int k = 0; k < 2; k++) {
        image8_t img = {0}, ref = {0};
        fw_frame_result_t r;
        fresh_frame(&f, &f.job, &o, gazes[k][0], gazes[k][1], &img, &r);
        render_settings_t ns = f.job.settings;
        ns.gaze_x = gazes[k][0];
        ns.gaze_y = gazes[k][1];
        render_stats_t st;
        REQUIRE(native_renderer_frame(&quant, &ns, &ref, &st) == PP5_OK);
        CHECK_EQ(r.rays, st.rays);
        CHECK(r.samples >= st.samples);
        double q = psnr(&img, &ref);
        CHECK_MSG(q >= 35.0, "gaze %g,%g: PSNR %.2f dB", gazes[k][0], gazes[k][1], q);
        image8_free(&img);
        image8_free(&ref);
    }
    native_renderer_free(&quant);
    volume_free(&f.v);
}

TEST(fw_division_object_slabs_image_within_tolerance_of_native)
{
    check_object_slabs_against_native(64, 4);
}

/* 40 rows over 16 GPs: bands of 4 rows leave the last GPs without a band,
 * but they still hold slabs whose segments every band needs. */
TEST(fw_division_object_slabs_with_gps_that_own_no_band)
{
    check_object_slabs_against_native(40, 16);
}

/* A fixed light is in the mip map: changing it between frames is refused. */
TEST(fw_division_fixed_light_cannot_change_between_frames)
{
    div_fixture_t f;
    div_fixture(&f, SHADE_SPECULAR_FIXED_LIGHT, 32, 2);
    fw_options_t o;
    fw_options_default(&o);
    fw_session_t s;
    REQUIRE(fw_session_init(&s, &f.job, &f.p, &o) == PP5_OK);
    const float l[3] = {0.0f, 1.0f, 0.0f};
    CHECK(fw_session_set_light(&s, l) == PP5_E_UNSUPPORTED);
    CHECK(strstr(pp5_error_text(), "fixed light") != NULL);
    fw_session_free(&s);
    volume_free(&f.v);
}

/* A perspective view is refused under object slabs with a clear message. */
TEST(fw_division_object_slabs_refuse_perspective)
{
    div_fixture_t f;
    div_fixture(&f, SHADE_DIFFUSE_FIXED_LIGHT, 32, 2);
    f.job.settings.view.projection = PROJECTION_PERSPECTIVE;
    fw_options_t o;
    fw_options_default(&o);
    o.division = FW_DIVISION_OBJECT_SLABS;
    fw_session_t s;
    CHECK(fw_session_init(&s, &f.job, &f.p, &o) == PP5_E_UNSUPPORTED);
    CHECK(strstr(pp5_error_text(), "object-slabs") != NULL);
    fw_session_free(&s);
    volume_free(&f.v);
}

/* Bands planned from the estimated samples are more even than bands of
 * equal rays on frames with the gaze off-centre (busiest GP / mean GP). */
TEST(fw_division_sample_planning_lowers_gp_imbalance)
{
    div_fixture_t f;
    div_fixture_sized(&f, SHADE_DIFFUSE_FIXED_LIGHT, 160, 8, 96, 80);
    const double gazes[1][2] = {{50.0, 60.0}};
    for (int k = 0; k < 1; k++) {
        double imb[2];
        for (int plan = 0; plan < 2; plan++) {
            fw_options_t o;
            fw_options_default(&o);
            o.plan = plan ? FW_PLAN_SAMPLES : FW_PLAN_RAYS;
            fw_frame_result_t r;
            fresh_frame(&f, &f.job, &o, gazes[k][0], gazes[k][1], NULL, &r);
            imb[plan] = r.gp_imbalance;
        }
        CHECK_MSG(imb[1] < imb[0], "gaze %g,%g: max/mean GP busy: samples %.3f, rays %.3f",
                  gazes[k][0], gazes[k][1], imb[1], imb[0]);
    }
    volume_free(&f.v);
}

/* The samples plan keeps its coarse marches while the view stays: a
 * session's bands, as the gaze moves and after the view changes, are the
 * bands a fresh session plans for the same view and gaze. */
TEST(fw_division_sample_plan_follows_the_view)
{
    div_fixture_t f;
    div_fixture_sized(&f, SHADE_DIFFUSE_FIXED_LIGHT, 160, 8, 96, 80);
    fw_options_t o;
    fw_options_default(&o);
    o.plan = FW_PLAN_SAMPLES;
    fw_session_t s;
    REQUIRE(fw_session_init(&s, &f.job, &f.p, &o) == PP5_OK);
    render_job_t job = f.job;
    const double gazes[3][2] = {{50.0, 60.0}, {120.0, 20.0}, {50.0, 60.0}};
    double first_view[128];
    REQUIRE(s.n_units <= 128);
    for (int step = 0; step < 3; step++) {
        if (step == 2) {
            job.settings.view.rot_x_deg += 60.0f;
            job.settings.view.rot_y_deg += 35.0f;
            REQUIRE(fw_session_set_view(&s, &job.settings.view) == PP5_OK);
        }
        fw_frame_result_t r;
        REQUIRE(fw_session_frame(&s, gazes[step][0], gazes[step][1], NULL, &r) == PP5_OK);
        fw_session_t fresh;
        REQUIRE(fw_session_init(&fresh, &job, &f.p, &o) == PP5_OK);
        REQUIRE(fw_session_frame(&fresh, gazes[step][0], gazes[step][1], NULL, &r) == PP5_OK);
        int n = (int)f.p.n_gp + 1, same = 1;
        for (int g = 0; g < n; g++)
            same &= s.last_bands[g] == fresh.last_bands[g];
        CHECK_MSG(same, "step %d: the session's bands differ from a fresh session's", step);
        for (int u = 0; u < s.n_units; u++)
            CHECK_MSG(s.unit_weight[u] == fresh.unit_weight[u], "step %d unit %d: weight %.17g, "
                      "fresh %.17g", step, u, s.unit_weight[u], fresh.unit_weight[u]);
        if (step == 0)
            memcpy(first_view, s.unit_weight, (size_t)s.n_units * sizeof *first_view);
        if (step == 2) {
            int moved = 0;
            for (int u = 0; u < s.n_units; u++)
                moved |= s.unit_weight[u] != first_view[u];
            CHECK_MSG(moved, "the new view estimated the same work as the old one at this gaze");
        }
        fw_session_free(&fresh);
    }
    fw_session_free(&s);
    volume_free(&f.v);
}

/* `pp5 sweep` takes the division as an axis: one CSV row per division. */
TEST(fw_division_sweep_axis_writes_one_row_per_division)
{
    const char *dir = pp5_test_outdir();
    char args[1200], csv[600];
    snprintf(csv, sizeof csv, "%s/d.csv", dir);
    snprintf(args, sizeof args, "sweep --set division=image-bands,resident,object-slabs --size 48x48 "
             "--set gp.count=4 --out %s --plot %s/d.png", csv, dir);
    REQUIRE(pp5_test_run_cli(args, NULL, NULL) == 0);
    char *text = pp5_test_read_file(csv);
    REQUIRE(text != NULL);
    int lines = 0;
    for (const char *p = text; *p; p++)
        lines += *p == '\n';
    CHECK_EQ(lines, 4);
    CHECK(strstr(text, "\nimage-bands,") && strstr(text, "\nresident,") &&
          strstr(text, "\nobject-slabs,"));
    CHECK(strstr(text, "error") == NULL);
    free(text);
    snprintf(args, sizeof args, "sweep --set division=nope --out %s", csv);
    CHECK_EQ(pp5_test_run_cli(args, NULL, NULL), 2);
}
