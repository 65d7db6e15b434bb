/* test_fw_machine.c: the gaze-directed renderer on the emulated machine against render/ (image, rays, samples), conservation, memory limit, scaling, determinism. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "firmware/host/fw_reference.h"
#include "firmware/host/fw_session.h"
#include "harness.h"
#include "render/quality.h"

/* A small phantom, its preset and a view; 64x64 images keep a frame fast. */
typedef struct {
    volume_t v;
    classify_tf_t tf;
    shade_params_t shade;
    render_settings_t rs;
    pp5_params_t p;
} fixture_t;

/* The fixture's volume: bricks of 40 voxels a row, each brick holding every
 * row of its slices. */
static const int fixture_dims[3] = {40, 40, 36};

static void fixture_sized(fixture_t *f, shade_case_t lighting, render_mode_t mode, const int dims[3])
{
    memset(f, 0, sizeof *f);
    REQUIRE(phantom_make("shepp-logan", dims[0], dims[1], dims[2], &f->v) == PP5_OK);
    REQUIRE(classify_preset("shepp-logan", &f->tf) == PP5_OK);
    shade_defaults(&f->shade);
    f->shade.lighting = lighting;
    if (lighting != SHADE_DIFFUSE_FIXED_LIGHT)
        f->shade.specular = 0.5f;
    render_settings_defaults(&f->rs);
    f->rs.width = 64;
    f->rs.height = 64;
    f->rs.mode = mode;
    f->rs.threads = 1;
    f->rs.view.rot_x_deg = 20.0f;
    f->rs.view.rot_y_deg = 30.0f;
    /* 2DLevel as the machine computes it by default (the paper's tables),
     * so that render/ is compared like for like. */
    f->rs.level_tables = true;
    pp5_params_default(&f->p);
    f->p.n_gp = 4;
    f->p.n_renderers = 4;
}

static void fixture(fixture_t *f, shade_case_t lighting, render_mode_t mode)
{
    fixture_sized(f, lighting, mode, fixture_dims);
}

/* The fixture as a render job (the settings as they are now). */
#define JOB(f)                                                                                 \
    (&(render_job_t){.volume = &(f).v, .volume_name = "phantom", .tf = (f).tf,                \
                     .shade = (f).shade, .settings = (f).rs, .frames = 1})

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

static int max_diff(const image8_t *a, const image8_t *b)
{
    int m = 0;
    size_t n = (size_t)a->width * a->height * 3;
    for (size_t i = 0; i < n; i++) {
        int d = abs((int)a->pixels[i] - (int)b->pixels[i]);
        m = d > m ? d : m;
    }
    return m;
}

/* Runs the machine and both native references for a few gazes. */
static void check_against_native_sized(shade_case_t lighting, render_mode_t mode,
                                       const fw_options_t *opts, projection_t proj,
                                       const int dims[3])
{
    fixture_t f;
    fixture_sized(&f, lighting, mode, dims);
    f.rs.view.projection = proj;
    f.rs.level_tables = opts->level_tables;
    fw_options_t o = *opts;
    fw_session_t s;
    pp5_status_t st = fw_session_init(&s, JOB(f), &f.p, &o);
    REQUIRE_MSG(st == PP5_OK, "session: %s", pp5_error_text());
    native_renderer_t exact, quant, flt;
    REQUIRE(native_renderer_init(&exact, &f.v, &f.tf, &f.shade, 1) == PP5_OK);
    REQUIRE(fw_reference_init(&quant, JOB(f), true) == PP5_OK);
    REQUIRE(fw_reference_init(&flt, JOB(f), false) == PP5_OK);
    const double gazes[3][2] = {{31.5, 31.5}, {10.0, 50.0}, {55.0, 8.0}};
    for (int k = 0; k < (mode == RENDER_MODE_GAZE ? 3 : 1); k++) {
        image8_t img = {0}, re = {0}, rq = {0}, rf = {0};
        fw_frame_result_t r;
        st = fw_session_frame(&s, gazes[k][0], gazes[k][1], &img, &r);
        REQUIRE_MSG(st == PP5_OK, "frame: %s", pp5_error_text());
        render_settings_t ns = f.rs;
        ns.gaze_x = gazes[k][0];
        ns.gaze_y = gazes[k][1];
        render_stats_t se, sq, sf;
        REQUIRE(native_renderer_frame(&exact, &ns, &re, &se) == PP5_OK);
        REQUIRE(native_renderer_frame(&quant, &ns, &rq, &sq) == PP5_OK);
        REQUIRE(native_renderer_frame(&flt, &ns, &rf, &sf) == PP5_OK);
        /* Like for like (the machine's formats in the native renderer):
         * same rays and samples, images equal to within float rounding. */
        CHECK_EQ(r.rays, sq.rays);
        CHECK_EQ(r.samples, sq.samples);
        CHECK_MSG(max_diff(&img, &rq) <= 1, "max diff vs quantised native %d", max_diff(&img, &rq));
        /* Against render/ itself: same rays; samples within 0.5 % (8-bit
         * opacity moves early termination), and >= 45 dB against the native
         * image with the same per-voxel shading (diffuse: render/ itself). */
        CHECK_EQ(r.rays, se.rays);
        CHECK_MSG(fabs((double)r.samples - (double)se.samples) <= 0.005 * (double)se.samples,
                  "samples %llu vs native %llu", (unsigned long long)r.samples,
                  (unsigned long long)se.samples);
        const image8_t *ref = lighting == SHADE_DIFFUSE_FIXED_LIGHT ? &re : &rf;
        double q = psnr(&img, ref);
        CHECK_MSG(q >= 45.0, "PSNR %.2f dB against native (gaze %g,%g)", q, gazes[k][0], gazes[k][1]);
        CHECK(r.frame_time_s > 0);
        image8_free(&img);
        image8_free(&re);
        image8_free(&rq);
        image8_free(&rf);
    }
    native_renderer_free(&exact);
    native_renderer_free(&quant);
    native_renderer_free(&flt);
    fw_session_free(&s);
    volume_free(&f.v);
}

static void check_against_native_opts(shade_case_t lighting, render_mode_t mode,
                                      const fw_options_t *opts, projection_t proj)
{
    check_against_native_sized(lighting, mode, opts, proj, fixture_dims);
}

static void check_against_native_view(shade_case_t lighting, render_mode_t mode, int split,
                                      projection_t proj)
{
    fw_options_t o;
    fw_options_default(&o);
    o.split = split;
    check_against_native_opts(lighting, mode, &o, proj);
}

static void check_against_native(shade_case_t lighting, render_mode_t mode, int split)
{
    check_against_native_view(lighting, mode, split, PROJECTION_PARALLEL);
}

/* 2DLevel computed exactly (atan, exp, log2) instead of by the tables. */
TEST(fw_image_matches_native_exact_2dlevel_gaze)
{
    fw_options_t o;
    fw_options_default(&o);
    o.level_tables = false;
    check_against_native_opts(SHADE_DIFFUSE_FIXED_LIGHT, RENDER_MODE_GAZE, &o, PROJECTION_PARALLEL);
}

/* The resident division gives the same image, rays and samples. */
TEST(fw_image_matches_native_resident_specular_gaze)
{
    fw_options_t o;
    fw_options_default(&o);
    o.division = FW_DIVISION_RESIDENT;
    check_against_native_opts(SHADE_SPECULAR_FIXED_LIGHT, RENDER_MODE_GAZE, &o, PROJECTION_PARALLEL);
}

TEST(fw_image_matches_native_resident_perspective_gp_split)
{
    fw_options_t o;
    fw_options_default(&o);
    o.division = FW_DIVISION_RESIDENT;
    o.split = VR_SPLIT_GP;
    check_against_native_opts(SHADE_SPECULAR_FIXED_LIGHT, RENDER_MODE_GAZE, &o,
                              PROJECTION_PERSPECTIVE);
}

TEST(fw_image_matches_native_perspective_gaze)
{
    check_against_native_view(SHADE_DIFFUSE_FIXED_LIGHT, RENDER_MODE_GAZE, VR_SPLIT_PP,
                              PROJECTION_PERSPECTIVE);
}

TEST(fw_image_matches_native_moving_object_gaze)
{
    check_against_native(SHADE_MOVING_OBJECT, RENDER_MODE_GAZE, VR_SPLIT_PP);
}

TEST(fw_image_matches_native_diffuse_gaze) { check_against_native(SHADE_DIFFUSE_FIXED_LIGHT, RENDER_MODE_GAZE, VR_SPLIT_PP); }
TEST(fw_image_matches_native_diffuse_full) { check_against_native(SHADE_DIFFUSE_FIXED_LIGHT, RENDER_MODE_FULL, VR_SPLIT_PP); }
TEST(fw_image_matches_native_specular_pp_gaze) { check_against_native(SHADE_SPECULAR_FIXED_LIGHT, RENDER_MODE_GAZE, VR_SPLIT_PP); }
TEST(fw_image_matches_native_specular_gp_split_full) { check_against_native(SHADE_SPECULAR_FIXED_LIGHT, RENDER_MODE_FULL, VR_SPLIT_GP); }

/* 48 voxels a row: 16384 voxels in 8 slices would make a level-0 brick 42
 * rows high, fewer than the volume has and not a whole number of the 8-row
 * strips the GPs build the levels in (the geometry rounds it to 40).  The
 * machine must build the same mip map as the native renderer. */
TEST(fw_image_matches_native_bricks_narrower_than_64)
{
    static const int dims[3] = {48, 48, 40};
    fw_options_t o;
    fw_options_default(&o);
    check_against_native_sized(SHADE_SPECULAR_FIXED_LIGHT, RENDER_MODE_GAZE, &o,
                               PROJECTION_PARALLEL, dims);
    check_against_native_sized(SHADE_DIFFUSE_FIXED_LIGHT, RENDER_MODE_FULL, &o,
                               PROJECTION_PARALLEL, dims);
}

/* Both splits compute the same integer shading: identical images, and the
 * PP split really runs shading streams on the renderers. */
TEST(fw_split_pp_and_gp_give_identical_images)
{
    image8_t img[2] = {{0}, {0}};
    fw_frame_result_t r[2];
    for (int k = 0; k < 2; k++) {
        fixture_t f;
        fixture(&f, SHADE_SPECULAR_FIXED_LIGHT, RENDER_MODE_GAZE);
        fw_options_t o;
        fw_options_default(&o);
        o.split = k == 0 ? VR_SPLIT_PP : VR_SPLIT_GP;
        fw_session_t s;
        REQUIRE(fw_session_init(&s, JOB(f), &f.p, &o) == PP5_OK);
        REQUIRE(fw_session_frame(&s, 20.0, 30.0, &img[k], &r[k]) == PP5_OK);
        fw_session_free(&s);
        volume_free(&f.v);
    }
    CHECK(memcmp(img[0].pixels, img[1].pixels, (size_t)64 * 64 * 3) == 0);
    CHECK(r[0].rn_exec_cycles_max > 0);
    CHECK_EQ(r[1].rn_exec_cycles_max, 0);
    CHECK(r[0].pp_stream_words > 0);
    image8_free(&img[0]);
    image8_free(&img[1]);
}

/* Bytes sent equal bytes delivered, per class, once the machine is idle. */
TEST(fw_ring_conservation_per_class)
{
    fixture_t f;
    fixture(&f, SHADE_SPECULAR_FIXED_LIGHT, RENDER_MODE_GAZE);
    fw_options_t o;
    fw_options_default(&o);
    fw_session_t s;
    REQUIRE(fw_session_init(&s, JOB(f), &f.p, &o) == PP5_OK);
    fw_frame_result_t r;
    REQUIRE(fw_session_frame(&s, 31.5, 31.5, NULL, &r) == PP5_OK);
    REQUIRE(fw_session_frame(&s, 5.0, 5.0, NULL, &r) == PP5_OK);
    for (unsigned k = 0; k < RING_CLASS_COUNT; k++)
        CHECK_EQ(s.m.ring.bytes_sent[k], s.m.ring.bytes_delivered[k]);
    /* The frame's data-class bytes are the fetched bricks plus their headers:
     * at least the payload the GPs report receiving. */
    CHECK(r.ring_bytes[RING_CLASS_DATA] >= r.bytes_fetched);
    CHECK(r.ring_bytes[RING_CLASS_PIXELS] >= (uint64_t)64 * 64 * 3);
    fw_session_free(&s);
    volume_free(&f.v);
}

/* A GP whose memory cannot hold its partition stops the run with a clear
 * firmware error, never a wrong image. */
TEST(fw_gp_memory_limit_is_a_firmware_error)
{
    fixture_t f;
    fixture(&f, SHADE_DIFFUSE_FIXED_LIGHT, RENDER_MODE_FULL);
    f.p.gp_local_mem_bytes = 200000;
    fw_options_t o;
    fw_options_default(&o);
    fw_session_t s;
    pp5_status_t st = fw_session_init(&s, JOB(f), &f.p, &o);
    if (st == PP5_OK) {
        fw_frame_result_t r;
        st = fw_session_frame(&s, 31.5, 31.5, NULL, &r);
    }
    CHECK_EQ(st, PP5_E_FIRMWARE);
    CHECK(strstr(pp5_error_text(), "memory") != NULL);
    fw_session_free(&s);
    volume_free(&f.v);
}

static double frame_time(int n_gp, double ring_hz, uint64_t *max_cast_cycles,
                         uint64_t *sum_cast_cycles)
{
    fixture_t f;
    fixture(&f, SHADE_DIFFUSE_FIXED_LIGHT, RENDER_MODE_FULL);
    f.p.n_gp = (uint32_t)n_gp;
    f.p.ring_clock_hz = ring_hz;
    fw_options_t o;
    fw_options_default(&o);
    fw_session_t s;
    REQUIRE(fw_session_init(&s, JOB(f), &f.p, &o) == PP5_OK);
    fw_frame_result_t r;
    image8_t img = {0};
    REQUIRE(fw_session_frame(&s, 31.5, 31.5, &img, &r) == PP5_OK);
    /* every frame: the machine's image equals the native full-resolution one
     * to within the 8-bit formats (the bands tile the image) */
    native_renderer_t nr;
    REQUIRE(native_renderer_init(&nr, &f.v, &f.tf, &f.shade, 1) == PP5_OK);
    image8_t ref = {0};
    render_stats_t rst;
    REQUIRE(native_renderer_frame(&nr, &f.rs, &ref, &rst) == PP5_OK);
    CHECK_EQ(r.rays, rst.rays);
    CHECK_MSG(psnr(&img, &ref) >= 45.0, "%d GPs: PSNR %.2f", n_gp, psnr(&img, &ref));
    image8_free(&img);
    image8_free(&ref);
    native_renderer_free(&nr);
    *max_cast_cycles = *sum_cast_cycles = 0;
    for (unsigned g = 0; g < s.m.n_gp; g++) {
        if (s.last_gp[g].cycles_cast > *max_cast_cycles)
            *max_cast_cycles = s.last_gp[g].cycles_cast;
        *sum_cast_cycles += s.last_gp[g].cycles_cast;
    }
    fw_session_free(&s);
    volume_free(&f.v);
    return r.frame_time_s;
}

/* Every ray is cast once, by exactly one GP, with operations that depend
 * only on the ray; only its data-cache misses depend on which rays share a
 * GP.  So the GPs' summed casting cycles are the same for any ring and within
 * the misses' small share for any GP count (a ray dropped or cast twice
 * would move the sum by a band's share, 3 % or more here), the busiest GP
 * holds at least the mean, and the frame cannot end before the busiest GP
 * has cast. */
TEST(fw_scaling_sanity)
{
    static const int counts[] = {4, 8, 16, 32};
    uint64_t max_c[4], sum_c[4];
    double t[4];
    for (int i = 0; i < 4; i++)
        t[i] = frame_time(counts[i], 20e6, &max_c[i], &sum_c[i]);
    uint64_t max_slow, sum_slow;
    double t_slow = frame_time(4, 10e6, &max_slow, &sum_slow);
    CHECK_MSG(t_slow >= t[0], "%g s at 10 MHz vs %g s at 20 MHz", t_slow, t[0]);
    CHECK_EQ(sum_slow, sum_c[0]);
    CHECK_EQ(max_slow, max_c[0]);
    pp5_params_t defaults;
    pp5_params_default(&defaults);
    double clock = defaults.gp_clock_hz;   /* frame_time leaves the GP clock alone */
    for (int i = 0; i < 4; i++) {
        double mean = (double)sum_c[i] / counts[i];
        CHECK_MSG(fabs((double)sum_c[i] - (double)sum_c[0]) <= 0.005 * (double)sum_c[0],
                  "%d GPs: summed casting %llu cycles vs %llu with 4", counts[i],
                  (unsigned long long)sum_c[i], (unsigned long long)sum_c[0]);
        CHECK_MSG((double)max_c[i] >= mean, "%d GPs: max %llu below the mean %.0f", counts[i],
                  (unsigned long long)max_c[i], mean);
        /* Balanced bands: the busiest GP within 1.6x the mean even at 2 rows a GP. */
        CHECK_MSG((double)max_c[i] <= 1.6 * mean, "%d GPs: max %llu vs mean %.0f", counts[i],
                  (unsigned long long)max_c[i], mean);
        CHECK_MSG(t[i] >= (double)max_c[i] / clock, "%d GPs: frame %g s before its casting %g s",
                  counts[i], t[i], (double)max_c[i] / clock);
    }
    /* Up to 16 GPs the casting dominates this frame: more GPs, a faster frame. */
    CHECK_MSG(t[1] < t[0] && t[2] < t[1], "4/8/16 GPs: %g %g %g s", t[0], t[1], t[2]);
}

TEST(fw_runs_are_deterministic)
{
    image8_t img[2] = {{0}, {0}};
    fw_frame_result_t r[2];
    uint64_t cycles[2] = {0, 0};
    for (int k = 0; k < 2; k++) {
        fixture_t f;
        fixture(&f, SHADE_SPECULAR_FIXED_LIGHT, RENDER_MODE_GAZE);
        fw_options_t o;
        fw_options_default(&o);
        fw_session_t s;
        REQUIRE(fw_session_init(&s, JOB(f), &f.p, &o) == PP5_OK);
        REQUIRE(fw_session_frame(&s, 12.0, 40.0, &img[k], &r[k]) == PP5_OK);
        for (unsigned g = 0; g < s.m.n_gp; g++)
            cycles[k] += s.m.gp[g].busy_cycles;
        fw_session_free(&s);
        volume_free(&f.v);
    }
    CHECK(memcmp(img[0].pixels, img[1].pixels, (size_t)64 * 64 * 3) == 0);
    CHECK(r[0].frame_time_s == r[1].frame_time_s);
    CHECK_EQ(cycles[0], cycles[1]);
    CHECK_EQ(r[0].samples, r[1].samples);
    image8_free(&img[0]);
    image8_free(&img[1]);
}

/* A mip map bigger than the renderers' backing store is a clear error. */
TEST(fw_backing_store_limit_is_reported)
{
    fixture_t f;
    fixture(&f, SHADE_SPECULAR_FIXED_LIGHT, RENDER_MODE_FULL);
    f.p.n_renderers = 1;
    volume_free(&f.v);
    REQUIRE(phantom_make("shepp-logan", 128, 128, 100, &f.v) == PP5_OK);
    fw_options_t o;
    fw_options_default(&o);
    fw_session_t s;
    pp5_status_t st = fw_session_init(&s, JOB(f), &f.p, &o);
    CHECK_EQ(st, PP5_E_FIRMWARE);
    CHECK(strstr(pp5_error_text(), "backing-store") != NULL);
    fw_session_free(&s);
    volume_free(&f.v);
}

/* Progressive refinement (paper §7): the machine keeps its 2D mip map between
 * frames like render/ does: per frame the same new rays, the same samples as
 * the like-for-like reference, and full resolution reached on the same frame. */
TEST(fw_progressive_refinement_matches_native)
{
    fixture_t f;
    fixture(&f, SHADE_DIFFUSE_FIXED_LIGHT, RENDER_MODE_GAZE);
    f.rs.progressive = true;
    f.rs.progressive_growth = 2.0;
    fw_options_t o;
    fw_options_default(&o);
    fw_session_t s;
    REQUIRE(fw_session_init(&s, JOB(f), &f.p, &o) == PP5_OK);
    native_renderer_t quant;
    REQUIRE(fw_reference_init(&quant, JOB(f), true) == PP5_OK);
    render_settings_t ns = f.rs;
    ns.gaze_x = 20.0;
    ns.gaze_y = 25.0;
    bool machine_full = false, native_full = false;
    uint64_t total_rays = 0;
    for (int k = 0; k < 6; k++) {
        image8_t img = {0}, rq = {0};
        fw_frame_result_t r;
        render_stats_t sq;
        REQUIRE(fw_session_frame(&s, ns.gaze_x, ns.gaze_y, &img, &r) == PP5_OK);
        REQUIRE(native_renderer_frame(&quant, &ns, &rq, &sq) == PP5_OK);
        CHECK_EQ(r.rays, sq.rays);
        CHECK_EQ(r.samples, sq.samples);
        CHECK_MSG(max_diff(&img, &rq) <= 1, "frame %d: max diff %d", k, max_diff(&img, &rq));
        CHECK_EQ(r.full_resolution_everywhere, sq.full_resolution_everywhere);
        machine_full = r.full_resolution_everywhere;
        native_full = sq.full_resolution_everywhere;
        total_rays += r.rays;
        image8_free(&img);
        image8_free(&rq);
    }
    CHECK(machine_full && native_full);
    /* every pixel's level-0 ray was cast exactly once over the sequence */
    CHECK(total_rays >= (uint64_t)64 * 64);
    native_renderer_free(&quant);
    fw_session_free(&s);
    volume_free(&f.v);
}

/* The gaze replay's callback: one frame per gaze point, setup reused. */
TEST(fw_replay_callback_runs_frames)
{
    fixture_t f;
    fixture(&f, SHADE_DIFFUSE_FIXED_LIGHT, RENDER_MODE_GAZE);
    fw_options_t o;
    fw_options_default(&o);
    fw_session_t s;
    REQUIRE(fw_session_init(&s, JOB(f), &f.p, &o) == PP5_OK);
    double setup = s.setup_s;
    native_renderer_t nr;
    REQUIRE(native_renderer_init(&nr, &f.v, &f.tf, &f.shade, 1) == PP5_OK);
    for (int k = 0; k < 3; k++) {
        fw_replay_cost_t c;
        memset(&c, 0, sizeof c);
        double gx = 10.0 + 20.0 * k, gy = 30.0;
        REQUIRE(fw_replay_frame_cost(&s, gx, gy, &c) == PP5_OK);
        render_settings_t ns = f.rs;
        ns.gaze_x = gx;
        ns.gaze_y = gy;
        image8_t img = {0};
        render_stats_t st;
        REQUIRE(native_renderer_frame(&nr, &ns, &img, &st) == PP5_OK);
        CHECK_EQ(c.rays, st.rays);
        CHECK(c.frame_time_s > 0);
        CHECK(c.ring_bytes > 0);
        image8_free(&img);
    }
    CHECK(s.setup_s == setup);   /* no second setup */
    CHECK_EQ(s.frames, 3);
    native_renderer_free(&nr);
    fw_session_free(&s);
    volume_free(&f.v);
}

/* Bands cast in passes (column ranges x depth segments, rays parked and
 * resumed between segments; forced here by capping bricks per pass, as a
 * small GP memory would) give the same image, rays and samples as one pass:
 * identical to the like-for-like reference. */
TEST(fw_passes_do_not_change_the_image)
{
    const projection_t projs[2] = {PROJECTION_PARALLEL, PROJECTION_PERSPECTIVE};
    for (int pi = 0; pi < 2; pi++) {
        fixture_t f;
        fixture(&f, SHADE_DIFFUSE_FIXED_LIGHT, RENDER_MODE_GAZE);
        f.p.n_gp = 2;
        f.rs.view.projection = projs[pi];
        volume_free(&f.v);
        REQUIRE(phantom_make("shepp-logan", 96, 96, 48, &f.v) == PP5_OK);
        native_renderer_t quant;
        REQUIRE(fw_reference_init(&quant, JOB(f), true) == PP5_OK);
        image8_t rq = {0};
        render_stats_t sq;
        render_settings_t ns = f.rs;
        ns.gaze_x = 28.0;
        ns.gaze_y = 36.0;
        REQUIRE(native_renderer_frame(&quant, &ns, &rq, &sq) == PP5_OK);
        /* cap 0 (one pass), then caps from 44 bricks down: some need several
         * passes, the smallest ones cannot be met (a clear firmware error). */
        int multi = 0;
        for (int cap = 0; cap >= 0; cap = cap == 0 ? 44 : (cap > 20 ? cap - 4 : -1)) {
            fw_options_t o;
            fw_options_default(&o);
            o.max_pass_bricks = cap;
            fw_session_t s;
            pp5_status_t st = fw_session_init(&s, JOB(f), &f.p, &o);
            fw_frame_result_t r;
            image8_t img = {0};
            if (st == PP5_OK)
                st = fw_session_frame(&s, ns.gaze_x, ns.gaze_y, &img, &r);
            if (st == PP5_OK) {
                CHECK_EQ(r.rays, sq.rays);
                CHECK_EQ(r.samples, sq.samples);
                CHECK_MSG(max_diff(&img, &rq) <= 1, "projection %d cap %d: max diff %d", pi, cap,
                          max_diff(&img, &rq));
                multi += r.passes_max > 1;
            } else {
                CHECK_MSG(cap > 0 && st == PP5_E_FIRMWARE && strstr(pp5_error_text(), "do not fit"),
                          "projection %d cap %d: %s", pi, cap, pp5_error_text());
            }
            image8_free(&img);
            fw_session_free(&s);
        }
        CHECK_MSG(multi > 0, "projection %d: no multi-pass frame", pi);
        image8_free(&rq);
        native_renderer_free(&quant);
        volume_free(&f.v);
    }
}
