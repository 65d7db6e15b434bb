/* test_replay_sweep.c: `pp5 replay --sweep-latency` (emu/cli/cmd_replay_sweep.c)
 * on a trace whose answer is known, and its machine configurations. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "tracker/angles.h"
#include "tracker/trace_file.h"

/* 10 s at 1000 Hz on the paper's display: gaze jumps between -5 and +5 deg
 * on the horizontal meridian every 500 ms (a 10 deg step, beyond the 6 deg
 * radius). */
static void write_steps(const char *path)
{
    trace_t t;
    trace_init(&t);
    snprintf(t.header.source, sizeof t.header.source, "hand-made steps");
    t.header.sample_rate_hz = 1000;
    angles_paper_geometry(&t.header.geometry);
    for (int i = 0; i < 10000; i++) {
        gaze_sample_t s;
        gaze_sample_invalid(&s, (int64_t)i * 1000000);
        angles_deg_to_px(&t.header.geometry, (i / 500) % 2 ? 5.0 : -5.0, 0, &s.x_px, &s.y_px);
        s.flags = GAZE_FLAG_VALID;
        REQUIRE(trace_append(&t, &s) == PP5_OK);
    }
    t.complete = true;
    REQUIRE(trace_write_file(path, &t) == PP5_OK);
    trace_free(&t);
}

/* The inside share the sweep prints for `ms`, or NaN. */
static double inside_at(const char *text, int ms)
{
    for (const char *line = text; line && *line;) {
        int got;
        double v;
        if (sscanf(line, " %d ms %lf %%", &got, &v) == 2 && got == ms)
            return v / 100.0;
        line = strchr(line, '\n');
        line = line ? line + 1 : NULL;
    }
    return NAN;
}

TEST(replay_sweep_inside_share_follows_the_latency)
{
    /* After each step the spot stays on the old side until an image made from
     * a newer sample appears: the latency L, plus the wait for the next frame
     * start, uniform over one frame F (16.7 ms; F = L below that): on average
     * L + F/2 outside per 500 ms.  Inside = 1 - (L + F/2) / 500 ms. */
    const char *dir = pp5_test_outdir();
    char trace[600], out[700], args[1600];
    snprintf(trace, sizeof trace, "%s/steps.trace", dir);
    snprintf(out, sizeof out, "%s/sweep.txt", dir);
    write_steps(trace);
    snprintf(args, sizeof args, "replay '%s' --sweep-latency --machine none", trace);
    REQUIRE(pp5_test_run_cli(args, out, NULL) == 0);
    char *text = pp5_test_read_file(out);
    REQUIRE(text);
    const int ms[] = {10, 50, 100, 150, 200};
    for (size_t i = 0; i < sizeof ms / sizeof ms[0]; i++) {
        double f = ms[i] < 16.667 ? ms[i] : 16.667;
        double want = 1.0 - (ms[i] + f / 2) / 500.0, got = inside_at(text, ms[i]);
        CHECK_MSG(fabs(got - want) < 0.012, "%d ms: inside %.3f, expected %.3f", ms[i], got, want);
    }
    CHECK(strstr(text, "  100 ms") && strstr(text, "the paper's system (100-150 ms)"));
    CHECK(strstr(text, "tolerable (50-70 ms, Albert et al. 2017)") != NULL);
    CHECK(strstr(text, "machine configurations") == NULL);
    free(text);
}

TEST(replay_sweep_names_the_machine_that_meets_the_budget)
{
    /* One GP cannot hold the volume (its local memory): that configuration is
     * reported, not fatal.  Whether 32 GPs meet 70 ms with no tracker or
     * display latency is the emulator's answer; the sweep must give one. */
    const char *dir = pp5_test_outdir();
    char trace[600], out[700], args[1800];
    snprintf(trace, sizeof trace, "%s/steps.trace", dir);
    snprintf(out, sizeof out, "%s/machines.txt", dir);
    write_steps(trace);
    snprintf(args, sizeof args, "replay '%s' --sweep-latency --sweep-ms 50:70:10 --latency-ms 0 "
             "--machine 'gp.count=1' --machine 'gp.count=32 ring.channels=16' "
             "--machine-frames 1", trace);
    REQUIRE(pp5_test_run_cli(args, out, NULL) == 0);
    char *text = pp5_test_read_file(out);
    REQUIRE(text);
    CHECK(strstr(text, "gp.count=32 ring.channels=16") != NULL);
    CHECK(strstr(text, "gp.count=1") && strstr(text, "cannot run it"));
    CHECK(strstr(text, "first to meet 70 ms") || strstr(text, "none meets 70 ms"));
    free(text);
    snprintf(args, sizeof args, "replay '%s' --sweep-latency --machine 'gp.count'", trace);
    CHECK_EQ(pp5_test_run_cli(args, NULL, NULL), 2);
    snprintf(args, sizeof args, "replay '%s' --sweep-latency --sweep-ms 200:10:5", trace);
    CHECK_EQ(pp5_test_run_cli(args, NULL, NULL), 2);
}

TEST(replay_cli_predict_landing_reports_the_landing_error)
{
    const char *dir = pp5_test_outdir();
    char args[1600], out[700];
    snprintf(out, sizeof out, "%s/landing.txt", dir);
    snprintf(args, sizeof args, "trace synth --mode saccades --seconds 5 --rate 500 --out "
             "'%s/s.trace'", dir);
    REQUIRE(pp5_test_run_cli(args, NULL, NULL) == 0);
    snprintf(args, sizeof args, "replay '%s/s.trace' --predict landing --frame-time-ms 20", dir);
    REQUIRE(pp5_test_run_cli(args, out, NULL) == 0);
    char *text = pp5_test_read_file(out);
    REQUIRE(text);
    CHECK(strstr(text, "prediction: landing") != NULL);
    CHECK(strstr(text, "landing prediction per true amplitude (truth: the trace's own") != NULL);
    CHECK(strstr(text, "5-10 deg") != NULL);
    free(text);
    snprintf(args, sizeof args, "replay '%s/s.trace' --predict landing:landing", dir);
    CHECK_EQ(pp5_test_run_cli(args, NULL, NULL), 2);
    snprintf(args, sizeof args, "replay '%s/s.trace' --predict none:kalman", dir);
    CHECK_EQ(pp5_test_run_cli(args, NULL, NULL), 2);
}
