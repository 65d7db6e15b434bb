/* test_replay.c: replay arithmetic on hand-made traces (tracker/replay.c): a
 * known latency gives a known error, a gaze step gives a known time outside
 * the sweet spot, prediction removes a constant-velocity lag, blinks hold the
 * spot, and the command writes its CSV and JSON. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "tracker/angles.h"
#include "tracker/replay.h"
#include "tracker/trace_file.h"

/* A 1000 Hz trace on the paper display whose gaze moves along the horizontal
 * meridian with azimuth angle_fn(t) degrees (NaN = blink). */
static void make_trace(trace_t *t, double seconds, double (*angle_fn)(double))
{
    trace_init(t);
    snprintf(t->header.source, sizeof t->header.source, "hand-made");
    t->header.sample_rate_hz = 1000;
    angles_paper_geometry(&t->header.geometry);
    int n = (int)lround(seconds * 1000);
    for (int i = 0; i < n; i++) {
        gaze_sample_t s;
        gaze_sample_invalid(&s, (int64_t)i * 1000000);
        double a = angle_fn(i / 1000.0);
        if (isnan(a)) {
            s.flags = GAZE_FLAG_BLINK;
        } else {
            angles_deg_to_px(&t->header.geometry, a, 0, &s.x_px, &s.y_px);
            s.flags = GAZE_FLAG_VALID;
        }
        PP5_ASSERT(trace_append(t, &s) == PP5_OK, "append");
    }
}

static double ramp_10dps(double t) { return -10.0 + 10.0 * t; }
static double step_at_1s(double t) { return t < 1.0 ? -5.0 : 5.0; }
static double blink_mid(double t) { return (t >= 0.5 && t < 0.7) ? NAN : 3.0; }

TEST(replay_known_latency_gives_known_error)
{
    /* Tracker 30 ms, frame 50.37 ms (chosen so no frame start falls exactly on
     * a sample's arrival), display 20 ms.  Frame k starts at 30 + 50.37 k ms;
     * the newest arrived sample is at floor(50.37 k) ms; the image is shown at
     * 30 + 50.37 (k + 1) + 20 ms; the eye moves 10°/s along the meridian, so
     * the error is 10°/s times (display time - sample time). */
    trace_t t;
    make_trace(&t, 2.0, ramp_10dps);
    replay_params_t p;
    replay_defaults(&p);
    p.tracker_latency_s = 0.030;
    p.display_latency_s = 0.020;
    replay_constant_cost_t c = {0.05037};
    replay_result_t r;
    REQUIRE_MSG(replay_run(&t, &p, replay_constant_cost, &c, NULL, NULL, &r) == PP5_OK, "%s",
                pp5_error_text());
    /* Frames while the display time is within the 1.999 s trace:
     * 30 + 50.37 (k+1) + 20 <= 1999  ->  k + 1 <= 38.69  ->  38 frames. */
    CHECK_EQ(r.count, 38);
    double sum = 0;
    for (size_t k = 0; k < r.count; k++) {
        double used_ms = floor(50.37 * k);
        double display_ms = 30 + 50.37 * (k + 1) + 20;
        double want = 10.0 * (display_ms - used_ms) / 1000.0;
        CHECK_NEAR(r.frames[k].sample_t_s * 1e3, used_ms, 1e-6);
        CHECK_NEAR(r.frames[k].display_s * 1e3, display_ms, 1e-6);
        CHECK_NEAR(r.frames[k].error_deg, want, 1e-6);
        sum += want;
    }
    CHECK_NEAR(r.frames[0].error_deg, 1.0037, 1e-6);
    CHECK_NEAR(r.summary.mean_error_deg, sum / 38, 1e-6);
    CHECK_NEAR(r.summary.frames_per_s, 1 / 0.05037, 1e-6);
    /* The error never drops below 1.0037° nor exceeds 1.0037 + 0.5037°, so a
     * 0.5° radius is never met and a 6° radius always is. */
    CHECK_NEAR(r.summary.inside_fraction, 1.0, 1e-12);
    replay_result_free(&r);
    p.fullres_radius_deg = 0.5;
    REQUIRE(replay_run(&t, &p, replay_constant_cost, &c, NULL, NULL, &r) == PP5_OK);
    CHECK_NEAR(r.summary.inside_fraction, 0.0, 1e-12);
    replay_result_free(&r);
    trace_free(&t);
}

TEST(replay_gaze_step_gives_known_time_outside)
{
    /* Gaze at -5° for 1 s, then +5° (10° apart, beyond the 6° radius).  The
     * sample at 1000 ms arrives at 1030 ms; the first frame starting after that
     * is k = 20 (30 + 50.37*20 = 1037.4 ms), shown at 1037.4 + 50.37 + 20 =
     * 1107.77 ms.  So the eye is outside for 107.77 ms of the display time,
     * which runs from the first image (100.37 ms) to the trace end (2999 ms). */
    trace_t t;
    make_trace(&t, 3.0, step_at_1s);
    replay_params_t p;
    replay_defaults(&p);
    p.tracker_latency_s = 0.030;
    p.display_latency_s = 0.020;
    replay_constant_cost_t c = {0.05037};
    replay_result_t r;
    REQUIRE(replay_run(&t, &p, replay_constant_cost, &c, NULL, NULL, &r) == PP5_OK);
    double valid_ms = 2999 - 100.37;
    CHECK_NEAR(r.summary.valid_display_s * 1e3, valid_ms, 1e-6);
    CHECK_NEAR(r.summary.inside_fraction, 1 - 107.77 / valid_ms, 1e-9);
    /* Frame k is shown at 100.37 + 50.37 k ms: frame 17 at 956.66 (before the
     * step: 0°), frames 18 and 19 at 1007.03 and 1057.40 (after it, spot still
     * at -5°: 10°), frame 20 at 1107.77 with the new sample (0°). */
    CHECK_NEAR(r.frames[17].error_deg, 0.0, 1e-9);
    CHECK_NEAR(r.frames[18].error_deg, 10.0, 1e-9);
    CHECK_NEAR(r.frames[19].error_deg, 10.0, 1e-9);
    CHECK_NEAR(r.frames[20].error_deg, 0.0, 1e-9);
    replay_result_free(&r);
    trace_free(&t);
}

TEST(replay_linear_prediction_removes_constant_velocity_lag)
{
    trace_t t;
    make_trace(&t, 2.0, ramp_10dps);
    replay_params_t p;
    replay_defaults(&p);
    replay_constant_cost_t c = {REPLAY_DEFAULT_FRAME_S};
    replay_result_t none, lin, kal;
    REQUIRE(replay_run(&t, &p, replay_constant_cost, &c, NULL, NULL, &none) == PP5_OK);
    predict_defaults(&p.predict, PREDICT_LINEAR);
    REQUIRE(replay_run(&t, &p, replay_constant_cost, &c, NULL, NULL, &lin) == PP5_OK);
    predict_defaults(&p.predict, PREDICT_KALMAN);
    REQUIRE(replay_run(&t, &p, replay_constant_cost, &c, NULL, NULL, &kal) == PP5_OK);
    /* Without prediction: 10°/s times the ~117 ms latency. */
    CHECK(none.summary.mean_error_deg > 1.1);
    /* Noise-free constant velocity: the extrapolation is exact once the
     * predictor has a velocity (from the second frame on, since the first frame
     * predicts with no previous frame time). */
    for (size_t k = 1; k < lin.count; k++)
        CHECK_NEAR(lin.frames[k].error_deg, 0.0, 1e-6);
    CHECK(kal.summary.mean_error_deg < 0.1);
    replay_result_free(&none);
    replay_result_free(&lin);
    replay_result_free(&kal);
    trace_free(&t);
}

TEST(replay_blink_holds_the_spot_and_is_not_scored)
{
    trace_t t;
    make_trace(&t, 1.5, blink_mid);
    replay_params_t p;
    replay_defaults(&p);
    replay_constant_cost_t c = {0.05037};
    replay_result_t r;
    REQUIRE(replay_run(&t, &p, replay_constant_cost, &c, NULL, NULL, &r) == PP5_OK);
    size_t unscored = 0;
    for (size_t k = 0; k < r.count; k++) {
        const replay_frame_t *f = &r.frames[k];
        bool in_blink = f->display_s >= 0.5 && f->display_s < 0.699;
        if (in_blink) {
            CHECK(isnan(f->error_deg));
            unscored++;
        } else {
            CHECK_NEAR(f->error_deg, 0.0, 1e-9);   /* gaze never moves */
        }
        /* the spot stays at +3° throughout */
        double ax, ay;
        angles_px_to_deg(&t.header.geometry, f->used_x_px, f->used_y_px, &ax, &ay);
        CHECK_NEAR(ax, 3.0, 1e-9);
    }
    CHECK(unscored >= 3);
    /* 200 ms of blink are neither inside nor outside. */
    CHECK_NEAR(r.summary.inside_fraction, 1.0, 1e-12);
    replay_result_free(&r);
    trace_free(&t);
}

typedef struct {
    int calls;
    double x[4], y[4];
} spy_t;

static pp5_status_t spy_cost(void *ctx, double gx, double gy, replay_frame_cost_t *out)
{
    spy_t *s = ctx;
    if (s->calls < 4) {
        s->x[s->calls] = gx;
        s->y[s->calls] = gy;
    }
    s->calls++;
    out->frame_s = 0.040 + 0.010 * (s->calls % 2);     /* alternating 50 / 40 ms */
    out->rays = 1000;
    out->ring_bytes = 64;
    CHECK(!out->want_image);
    return PP5_OK;
}

TEST(replay_cost_source_gets_display_pixels_and_sets_frame_times)
{
    /* Recording: 1000x1000 px on 500x500 mm at 500 mm, gaze fixed at its right
     * edge (26.565°); the paper display is narrower (18.5° half-width), so the
     * spot is clamped to the right edge of the rendered screen, x = 1280. */
    trace_t t;
    trace_init(&t);
    snprintf(t.header.source, sizeof t.header.source, "hand-made");
    t.header.sample_rate_hz = 100;
    t.header.geometry = (gaze_geometry_t){1000, 1000, 500, 500, 500, 0};
    for (int i = 0; i < 100; i++) {
        gaze_sample_t s;
        gaze_sample_invalid(&s, (int64_t)i * 10000000);
        s.flags = GAZE_FLAG_VALID;
        s.x_px = i < 50 ? 1000 : 750;    /* then atan(125/500) = 14.04°: on screen */
        s.y_px = 500;
        REQUIRE(trace_append(&t, &s) == PP5_OK);
    }
    replay_params_t p;
    replay_defaults(&p);
    p.timing_only = true;
    spy_t spy = {0};
    replay_result_t r;
    REQUIRE(replay_run(&t, &p, spy_cost, &spy, NULL, NULL, &r) == PP5_OK);
    CHECK_NEAR(spy.x[0], 1280, 1e-6);
    CHECK_NEAR(spy.y[0], 512, 1e-6);
    /* frame ends: 33 + 50, then + 40, + 50 ... */
    CHECK_NEAR(r.frames[0].end_s, 0.033 + 0.050, 1e-12);
    CHECK_NEAR(r.frames[1].end_s, 0.033 + 0.090, 1e-12);
    CHECK_EQ(r.summary.rays, 1000 * r.count);
    /* After the switch the spot maps 0.25 * 500 mm at 500 mm onto the paper:
     * 640 + 508 * 0.25 / pitch. */
    double pitch = 2 * 508 * tan(18.5 * M_PI / 180) / 1280;
    size_t last = r.count - 1;
    CHECK_NEAR(r.frames[last].spot_x_px, 640 + 508 * 0.25 / pitch, 1e-6);
    replay_result_free(&r);
    trace_free(&t);
}

static pp5_status_t zero_cost(void *ctx, double gx, double gy, replay_frame_cost_t *out)
{
    out->frame_s = 0;
    return PP5_OK;
}

TEST(replay_rejects_short_traces_and_bad_costs)
{
    trace_t t;
    make_trace(&t, 0.05, ramp_10dps);
    replay_params_t p;
    replay_defaults(&p);
    replay_constant_cost_t c = {REPLAY_DEFAULT_FRAME_S};
    replay_result_t r;
    CHECK(replay_run(&t, &p, replay_constant_cost, &c, NULL, NULL, &r) == PP5_E_RANGE);
    CHECK(strstr(pp5_error_text(), "shorter than one frame") != NULL);
    trace_free(&t);
    make_trace(&t, 1.0, ramp_10dps);
    CHECK(replay_run(&t, &p, zero_cost, NULL, NULL, NULL, &r) == PP5_E_RANGE);
    p.tracker_latency_s = -1;
    CHECK(replay_run(&t, &p, replay_constant_cost, &c, NULL, NULL, &r) == PP5_E_CONFIG);
    trace_free(&t);
}

TEST(replay_percentile_is_nearest_rank)
{
    double v[] = {5, 1, 4, 2, 3, 10, 9, 8, 7, 6};
    CHECK_NEAR(replay_percentile(v, 10, 0.95), 10, 0);
    CHECK_NEAR(replay_percentile(v, 10, 0.5), 5, 0);
    CHECK_NEAR(replay_percentile(v, 10, 0.0), 1, 0);
    CHECK(isnan(replay_percentile(v, 0, 0.5)));
}

TEST(replay_cli_writes_csv_and_json)
{
    const char *dir = pp5_test_outdir();
    char tr[512], json[600], csv[600], args[3000], out[600], err[600];
    snprintf(tr, sizeof tr, "%s/p.trace", dir);
    snprintf(json, sizeof json, "%s/r.json", dir);
    snprintf(csv, sizeof csv, "%s/frames.csv", dir);
    snprintf(out, sizeof out, "%s/out.txt", dir);
    snprintf(err, sizeof err, "%s/err.txt", dir);
    snprintf(args, sizeof args, "trace synth --mode pursuit --seconds 3 --rate 500 --out '%s'", tr);
    REQUIRE(pp5_test_run_cli(args, out, err) == 0);
    snprintf(args, sizeof args,
             "replay '%s' --frame-time-ms 100 --latency-ms 50 --predict kalman --report '%s' "
             "--csv '%s'", tr, json, csv);
    CHECK_EQ(pp5_test_run_cli(args, out, err), 0);
    char *j = pp5_test_read_file(json), *c = pp5_test_read_file(csv);
    REQUIRE(j && c);
    CHECK(strstr(j, "\"inside_fraction\"") && strstr(j, "\"predict\": \"kalman\"") &&
          strstr(j, "NOT the emulated machine"));
    /* 3 s trace, 100 ms frames, first start at 50 ms, shown at frame end:
     * frames k = 0..28 end at 150 + 100 k <= 2998 ms: 29 frames + header. */
    int lines = 0;
    for (char *q = c; *q; q++)
        lines += *q == '\n';
    CHECK_EQ(lines, 30);
    free(j);
    free(c);
    snprintf(args, sizeof args, "replay '%s' --predict sideways", tr);
    CHECK_EQ(pp5_test_run_cli(args, out, err), 2);
    snprintf(args, sizeof args, "replay /nonexistent.trace");
    CHECK(pp5_test_run_cli(args, out, err) != 0);
}

static pp5_status_t image_cost(void *ctx, double gx, double gy, replay_frame_cost_t *out)
{
    static uint8_t px[4 * 4];
    static image8_t img = {4, 4, 1, px};
    out->frame_s = 0.1;
    out->image = out->want_image ? &img : NULL;
    return PP5_OK;
}

static pp5_status_t count_image(void *ctx, const replay_frame_t *f, const image8_t *img)
{
    (*(int *)ctx)++;
    return img->width == 4 ? PP5_OK : PP5_E_RANGE;
}

TEST(replay_cost_sources_by_name_and_images_per_frame)
{
    const replay_cost_source_t *cs = replay_find_cost_source("constant");
    REQUIRE(cs);
    CHECK(strstr(cs->summary, "NOT the emulated machine") != NULL);
    void *ctx;
    gaze_geometry_t g;
    angles_paper_geometry(&g);
    REQUIRE(cs->open("50", &g, &ctx) == PP5_OK);
    replay_frame_cost_t c = {0};
    REQUIRE(cs->cost(ctx, 1, 2, &c) == PP5_OK);
    CHECK_NEAR(c.frame_s, 0.050, 1e-15);
    cs->close(ctx);
    CHECK(cs->open("-3", &g, &ctx) == PP5_E_CONFIG);
    CHECK(replay_find_cost_source("no-such-source") == NULL);

    trace_t t;
    make_trace(&t, 1.0, ramp_10dps);
    replay_params_t p;
    replay_defaults(&p);
    int images = 0;
    replay_result_t r;
    REQUIRE(replay_run(&t, &p, image_cost, NULL, count_image, &images, &r) == PP5_OK);
    CHECK_EQ(images, (int)r.count);
    replay_result_free(&r);
    images = 0;
    p.timing_only = true;        /* the source is told not to render */
    REQUIRE(replay_run(&t, &p, image_cost, NULL, count_image, &images, &r) == PP5_OK);
    CHECK_EQ(images, 0);
    replay_result_free(&r);
    trace_free(&t);
}

TEST(replay_refresh_waits_for_the_next_vertical_blank)
{
    /* 60 Hz refresh, frames of 50.37 ms from 30 ms: frame 0 ends at 80.37 ms,
     * the next refresh is at 83.333 ms (5/60 s), shown 20 ms later. */
    trace_t t;
    make_trace(&t, 1.0, ramp_10dps);
    replay_params_t p;
    replay_defaults(&p);
    p.tracker_latency_s = 0.030;
    p.display_latency_s = 0.020;
    p.refresh_hz = 60;
    replay_constant_cost_t c = {0.05037};
    replay_result_t r;
    REQUIRE(replay_run(&t, &p, replay_constant_cost, &c, NULL, NULL, &r) == PP5_OK);
    CHECK_NEAR(r.frames[0].display_s, 5.0 / 60 + 0.020, 1e-12);
    /* frame 1 ends at 130.74 ms -> refresh 133.333 ms (8/60) */
    CHECK_NEAR(r.frames[1].display_s, 8.0 / 60 + 0.020, 1e-12);
    CHECK_NEAR(r.frames[1].error_deg, 10.0 * (8.0 / 60 + 0.020 - 0.050), 1e-6);
    replay_result_free(&r);
    trace_free(&t);
}

static double two_blocks(double t) { return t < 1.0 ? -5.0 : 5.0; }

TEST(replay_frames_across_a_recording_gap_are_not_scored)
{
    /* Block A 0..0.999 s at -5°, then nothing until block B 4.000..4.999 s at
     * +5° (like EyeLink recording blocks).  Frame k starts at 30 + 50.37 k ms and
     * is shown 70.37 ms later: frames 78 and 79 are shown at 4032.6 and
     * 4083.0 ms, inside block B, but were started before its first sample
     * arrived (4030 ms), so they carry block A's gaze: not scored.  Frame 80
     * starts at 4059.6 ms with B's gaze. */
    trace_t a, t;
    make_trace(&a, 5.0, two_blocks);
    trace_init(&t);
    t.header = a.header;
    for (size_t i = 0; i < a.count; i++) {
        int64_t ms = a.samples[i].t_ns / 1000000;
        if (ms < 1000 || ms >= 4000)
            REQUIRE(trace_append(&t, &a.samples[i]) == PP5_OK);
    }
    replay_params_t p;
    replay_defaults(&p);
    p.tracker_latency_s = 0.030;
    p.display_latency_s = 0.020;
    replay_constant_cost_t c = {0.05037};
    replay_result_t r;
    REQUIRE(replay_run(&t, &p, replay_constant_cost, &c, NULL, NULL, &r) == PP5_OK);
    CHECK_EQ(r.summary.frames_after_gap, 2);
    CHECK(r.frames[78].after_gap && r.frames[79].after_gap && !r.frames[80].after_gap);
    CHECK(isnan(r.frames[78].error_deg));
    CHECK_NEAR(r.frames[80].error_deg, 0.0, 1e-9);
    CHECK(isnan(r.frames[40].error_deg) && !r.frames[40].after_gap);   /* shown in the gap */
    CHECK_NEAR(r.summary.max_error_deg, 0.0, 1e-9);
    replay_result_free(&r);
    p.gap_s = 10;                 /* no gap that long: the same frames now score 10° */
    REQUIRE(replay_run(&t, &p, replay_constant_cost, &c, NULL, NULL, &r) == PP5_OK);
    CHECK_EQ(r.summary.frames_after_gap, 0);
    CHECK_NEAR(r.frames[78].error_deg, 10.0, 1e-9);
    replay_result_free(&r);
    trace_free(&a);
    trace_free(&t);
}
