/* test_trace.c: the pp5 trace format (tracker/trace_file.c): round trips, the
 * strict errors, tolerance of real data, the flush-as-you-go writer under
 * kill -9, and the screen-geometry arithmetic (tracker/angles.c). */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "harness.h"
#include "tracker/angles.h"
#include "tracker/trace_file.h"

#define HEADER "# pp5-trace v1\n# source: test\n# sample_rate_hz: 500\n# screen_px: 1024 768\n" \
               "# screen_mm: 380 300\n# distance_mm: 670\n"
#define COLS "t_ms\tx_px\ty_px\tstatus\tlabel\n"

static pp5_status_t parse_str(const char *text, trace_t *t)
{
    return trace_parse(text, strlen(text), "mem", t);
}

static void header_for_test(trace_header_t *h)
{
    memset(h, 0, sizeof *h);
    snprintf(h->source, sizeof h->source, "unit test");
    h->sample_rate_hz = 2000;
    h->geometry = (gaze_geometry_t){1024, 768, 380, 300, 670, 0};
}

TEST(trace_round_trip_keeps_every_field)
{
    trace_t t;
    trace_init(&t);
    header_for_test(&t.header);
    t.has_head = t.has_hand = true;
    for (int i = 0; i < 50; i++) {
        gaze_sample_t s;
        gaze_sample_invalid(&s, (int64_t)i * 500000);          /* 0.5 ms steps */
        s.label = i % 7;
        if (i % 10 == 3) {
            s.flags = GAZE_FLAG_BLINK;
        } else if (i % 10 != 7) {
            s.flags = GAZE_FLAG_VALID;
            s.x_px = -300.125 + i * 37.5;                       /* some off-screen */
            s.y_px = 2000.5 - i * 11.25;
        }
        if (i % 2 == 0) {
            s.flags |= GAZE_FLAG_HEAD;
            s.head = (gaze_pose_t){{1.5, -2.25, 500}, 10, -20.5, 3};
        }
        if (i % 3 == 0) {
            s.flags |= GAZE_FLAG_HAND;
            s.hand = (gaze_pose_t){{-100, 7, 8}, 179.5, 0, -45};
        }
        REQUIRE(trace_append(&t, &s) == PP5_OK);
    }
    char path[512];
    snprintf(path, sizeof path, "%s/rt.trace", pp5_test_outdir());
    REQUIRE(trace_write_file(path, &t) == PP5_OK);
    trace_t b;
    REQUIRE_MSG(trace_read_file(path, &b) == PP5_OK, "%s", pp5_error_text());
    CHECK(b.complete);
    CHECK(b.has_head && b.has_hand);
    CHECK_EQ(b.count, t.count);
    CHECK(strcmp(b.header.source, "unit test") == 0);
    CHECK_NEAR(b.header.sample_rate_hz, 2000, 0);
    CHECK_EQ(b.header.geometry.width_px, 1024);
    CHECK_NEAR(b.header.geometry.distance_mm, 670, 0);
    for (size_t i = 0; i < t.count && i < b.count; i++) {
        const gaze_sample_t *x = &t.samples[i], *y = &b.samples[i];
        CHECK_EQ(x->t_ns, y->t_ns);
        CHECK_EQ(x->flags, y->flags);
        CHECK_EQ(x->label, y->label);
        if (x->flags & GAZE_FLAG_VALID) {
            CHECK_NEAR(x->x_px, y->x_px, 0.0005);
            CHECK_NEAR(x->y_px, y->y_px, 0.0005);
        } else {
            CHECK(isnan(y->x_px) && isnan(y->y_px));
        }
        if (x->flags & GAZE_FLAG_HEAD)
            CHECK_NEAR(x->head.elevation_deg, y->head.elevation_deg, 0.0005);
        if (x->flags & GAZE_FLAG_HAND)
            CHECK_NEAR(x->hand.pos_mm[0], y->hand.pos_mm[0], 0.0005);
    }
    trace_free(&t);
    trace_free(&b);
}

TEST(trace_times_parse_to_exact_nanoseconds)
{
    trace_t t;
    REQUIRE(parse_str(HEADER COLS "0\t1\t2\tok\t0\n0.5\t1\t2\tok\t0\n1234.000001\t1\t2\tok\t0\n"
                      "1234.0000016\t1\t2\tok\t0\n", &t) == PP5_OK);
    CHECK_EQ(t.samples[0].t_ns, 0);
    CHECK_EQ(t.samples[1].t_ns, 500000);
    CHECK_EQ(t.samples[2].t_ns, 1234000001LL);
    CHECK_EQ(t.samples[3].t_ns, 1234000002LL);   /* the 7th decimal rounds */
    CHECK(!t.complete);
    trace_free(&t);
}

TEST(trace_strict_errors_name_the_problem)
{
    static const struct { const char *text, *want; } cases[] = {
        {"# pp5-trace v2\n", "not a pp5 trace"},
        {"", "empty"},
        {"# pp5-trace v1\n# sample_rate_hz: 500\n# screen_px: 1024 768\n# screen_mm: 380 300\n"
         "# distance_mm: 670\n" COLS, "'source' is missing"},
        {"# pp5-trace v1\n# source: x\n# screen_px: 1024 768\n# screen_mm: 380 300\n"
         "# distance_mm: 670\n" COLS, "'sample_rate_hz' is missing"},
        {"# pp5-trace v1\n# source: x\n# sample_rate_hz: 500\n# screen_mm: 380 300\n"
         "# distance_mm: 670\n" COLS, "'screen_px' is missing"},
        {"# pp5-trace v1\n# source: x\n# sample_rate_hz: 500\n# screen_px: 1024 768\n"
         "# distance_mm: 670\n" COLS, "'screen_mm' is missing"},
        {"# pp5-trace v1\n# source: x\n# sample_rate_hz: 500\n# screen_px: 1024 768\n"
         "# screen_mm: unknown\n# distance_mm: unknown\n" COLS, "px_per_deg"},
        {HEADER COLS "5\t1\t2\tok\t0\n4\t1\t2\tok\t0\n", "time goes backwards"},
        {HEADER COLS "nan\t1\t2\tok\t0\n", "NaN is not allowed"},
        {HEADER COLS "1\tnan\t2\tok\t0\n", "NaN gaze in a sample whose status is ok"},
        {HEADER COLS "1\tinf\t2\tok\t0\n", "not a number"},
        {HEADER COLS "1\t1\t2\tmaybe\t0\n", "status 'maybe'"},
        {HEADER COLS "1\t1\t2\tok\t9\n", "label '9'"},
        {HEADER COLS "1\t1\t2\tok\n", "4 fields"},
        {HEADER COLS "1\t1\t2\tok\t0", "truncated"},
        {HEADER, "no column line"},
        {HEADER "t_ms\tx_px\ty_px\tstatus\tlabel\tpupil\n", "unknown column 'pupil'"},
        {HEADER "t_ms\ty_px\tx_px\tstatus\tlabel\n", "expected 'x_px'"},
        {HEADER COLS "1\t1\t2\tok\t0\n# end: 2 samples\n", "end line says 2"},
        {HEADER COLS "1\t1\t2\tok\t0\n# end: 1 samples\n2\t1\t2\tok\t0\n", "after the end"},
        {HEADER "t_ms\tx_px\ty_px\tstatus\tlabel\thead_x_mm\thead_y_mm\thead_z_mm\thead_az_deg"
         "\thead_el_deg\thead_roll_deg\n1\t1\t2\tok\t0\t1\tnan\t3\t4\t5\t6\n", "partly NaN"},
        {"# pp5-trace v1\n# source: x\n# sample_rate_hz: 500\n# screen_px: 0 768\n" COLS,
         "screen_px"},
        {"# pp5-trace v1\n# source: x\n# sample_rate_hz: -5\n" COLS, "sample_rate_hz"},
        {HEADER COLS "1\t1e300\t2\tok\t0\n", "absurdly far"},
        {"# pp5-trace v1\nnot a header\n", "'source' is missing"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        trace_t t;
        trace_init(&t);
        pp5_status_t st = trace_parse(cases[i].text, strlen(cases[i].text), "mem", &t);
        CHECK_MSG(st != PP5_OK, "case %zu parsed but should fail (%s)", i, cases[i].want);
        CHECK_MSG(strstr(pp5_error_text(), cases[i].want) != NULL,
                  "case %zu: error '%s' does not mention '%s'", i, pp5_error_text(), cases[i].want);
        CHECK(t.samples == NULL && t.count == 0);   /* nothing committed */
    }
}

TEST(trace_tolerates_gaps_offscreen_blinks_crlf_and_comments)
{
    const char *text =
        "# pp5-trace v1\r\n# source: real\r\n# sample_rate_hz: 500\r\n# screen_px: 1024 768\r\n"
        "# screen_mm: unknown\r\n# distance_mm: unknown\r\n# px_per_deg: 35.2\r\n"
        "# some_future_key: ignored\r\n" COLS
        "0\t-250.5\t900\tok\t1\n"            /* off screen */
        "2\tnan\tnan\tblink\t5\n"
        "4\tnan\tnan\tlost\t0\n"
        "\n"                                /* blank */
        "# a note in the data\n"
        "4\t512\t384\tok\t1\n"              /* same time again: allowed */
        "2404\t5000\t-3000\tok\t0\n";       /* a 2.4 s gap */
    trace_t t;
    REQUIRE_MSG(parse_str(text, &t) == PP5_OK, "%s", pp5_error_text());
    CHECK_EQ(t.count, 5);
    CHECK(!t.complete);
    CHECK_NEAR(t.header.geometry.px_per_deg, 35.2, 1e-12);
    CHECK(t.samples[0].flags == GAZE_FLAG_VALID && t.samples[0].x_px == -250.5);
    CHECK(t.samples[1].flags == GAZE_FLAG_BLINK && t.samples[1].label == 5);
    CHECK(t.samples[2].flags == 0);
    CHECK_EQ(t.samples[4].t_ns, 2404000000LL);
    trace_free(&t);
}

TEST(trace_writer_survives_kill_9_up_to_the_last_flush)
{
    char path[512];
    snprintf(path, sizeof path, "%s/killed.trace", pp5_test_outdir());
    pid_t pid = fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        trace_header_t h;
        header_for_test(&h);
        trace_writer_t w;
        if (trace_writer_open(&w, path, &h, true, false) != PP5_OK)
            _exit(3);
        for (int i = 0; i < 150; i++) {
            gaze_sample_t s;
            gaze_sample_invalid(&s, (int64_t)i * 1000000);
            s.flags = GAZE_FLAG_VALID | GAZE_FLAG_HEAD;
            s.x_px = i;
            s.y_px = 2 * i;
            s.head.pos_mm[2] = 600;
            if (trace_writer_append(&w, &s) != PP5_OK)
                _exit(4);
            if (i == 99 && trace_writer_flush(&w) != PP5_OK)
                _exit(5);
        }
        raise(SIGKILL);      /* 50 samples still in the buffer */
        _exit(6);
    }
    int status;
    REQUIRE(waitpid(pid, &status, 0) == pid);
    CHECK(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
    trace_t t;
    REQUIRE_MSG(trace_read_file(path, &t) == PP5_OK, "%s", pp5_error_text());
    CHECK_EQ(t.count, 100);
    CHECK(!t.complete);
    CHECK(t.has_head);
    CHECK_NEAR(t.samples[99].y_px, 198, 0);
    trace_free(&t);
}

TEST(trace_writer_refuses_bad_samples)
{
    char path[512];
    snprintf(path, sizeof path, "%s/bad.trace", pp5_test_outdir());
    trace_header_t h;
    header_for_test(&h);
    trace_writer_t w;
    REQUIRE(trace_writer_open(&w, path, &h, false, false) == PP5_OK);
    gaze_sample_t s;
    gaze_sample_invalid(&s, 5000000);
    s.flags = GAZE_FLAG_VALID;
    s.x_px = NAN;
    s.y_px = 1;
    CHECK(trace_writer_append(&w, &s) == PP5_E_RANGE);   /* valid but NaN */
    s.x_px = 1;
    CHECK(trace_writer_append(&w, &s) == PP5_OK);
    s.t_ns = 4000000;
    CHECK(trace_writer_append(&w, &s) == PP5_E_FORMAT); /* time backwards */
    CHECK(trace_writer_close(&w) == PP5_OK);
    trace_t t;
    REQUIRE(trace_read_file(path, &t) == PP5_OK);
    CHECK_EQ(t.count, 1);
    CHECK(t.complete);
    trace_free(&t);
    h.sample_rate_hz = 0;
    CHECK(trace_writer_open(&w, path, &h, false, false) != PP5_OK);
    /* abandon: what was appended is kept, without the end line */
    h.sample_rate_hz = 100;
    REQUIRE(trace_writer_open(&w, path, &h, false, false) == PP5_OK);
    s.t_ns = 1000;
    REQUIRE(trace_writer_append(&w, &s) == PP5_OK);
    CHECK(trace_writer_abandon(&w) == PP5_OK);
    REQUIRE(trace_read_file(path, &t) == PP5_OK);
    CHECK_EQ(t.count, 1);
    CHECK(!t.complete);
    trace_free(&t);
}

TEST(trace_source_plays_every_sample_then_ends)
{
    trace_t t;
    REQUIRE(parse_str(HEADER COLS "0\t1\t2\tok\t0\n1\t3\t4\tok\t0\n2\tnan\tnan\tlost\t0\n", &t) ==
            PP5_OK);
    gaze_source_t *src;
    REQUIRE(trace_source_open(&t, "mem", &src) == PP5_OK);
    CHECK(t.samples == NULL);                 /* ownership moved */
    CHECK_NEAR(src->sample_rate_hz, 500, 0);
    gaze_sample_t s;
    bool got;
    int n = 0;
    while (gaze_source_next(src, &s, &got) == PP5_OK && got)
        n++;
    CHECK_EQ(n, 3);
    CHECK(!got);
    gaze_source_close(src);
    /* trace_collect drains a source back into a trace. */
    REQUIRE(parse_str(HEADER COLS "0\t1\t2\tok\t0\n1\t3\t4\tok\t0\n2\tnan\tnan\tlost\t0\n", &t) ==
            PP5_OK);
    REQUIRE(trace_source_open(&t, "again", &src) == PP5_OK);
    trace_t back;
    REQUIRE(trace_collect(src, 2, &back) == PP5_OK);
    CHECK_EQ(back.count, 2);
    CHECK(!back.complete);
    CHECK(strcmp(back.header.source, "again") == 0);
    CHECK_EQ(back.header.geometry.width_px, 1024);
    CHECK_NEAR(back.samples[1].x_px, 3, 0);
    trace_free(&back);
    REQUIRE(trace_collect(src, 0, &back) == PP5_OK);    /* the rest */
    CHECK_EQ(back.count, 1);
    CHECK(back.complete);
    trace_free(&back);
    gaze_source_close(src);
}

TEST(trace_reads_gzip_and_rejects_truncated_gzip)
{
    char path[512], gz[600], cmd[2200];
    snprintf(path, sizeof path, "%s/z.trace", pp5_test_outdir());
    FILE *f = fopen(path, "w");
    REQUIRE(f);
    fputs(HEADER COLS, f);
    for (int i = 0; i < 2000; i++)
        fprintf(f, "%d\t%d.25\t7\tok\t1\n", i * 2, i);
    fclose(f);
    snprintf(gz, sizeof gz, "%s.gz", path);
    snprintf(cmd, sizeof cmd, "gzip -kf '%s' && head -c 3000 '%s' > '%s.cut.gz'", path, gz, path);
    REQUIRE(system(cmd) == 0);
    trace_t t;
    REQUIRE_MSG(trace_read_file(gz, &t) == PP5_OK, "%s", pp5_error_text());
    CHECK_EQ(t.count, 2000);
    trace_free(&t);
    snprintf(gz, sizeof gz, "%s.cut.gz", path);
    CHECK(trace_read_file(gz, &t) == PP5_E_FORMAT);
    CHECK(trace_read_file("/nonexistent/x.trace", &t) == PP5_E_IO);
}

TEST(trace_cli_info_and_bad_file_exit_codes)
{
    char path[512], args[1200], out[600], err[600];
    const char *dir = pp5_test_outdir();
    snprintf(path, sizeof path, "%s/cli.trace", dir);
    snprintf(out, sizeof out, "%s/out.txt", dir);
    snprintf(err, sizeof err, "%s/err.txt", dir);
    FILE *f = fopen(path, "w");
    REQUIRE(f);
    fputs(HEADER COLS "0\t1\t2\tok\t1\n2\tnan\tnan\tblink\t5\n# end: 2 samples\n", f);
    fclose(f);
    snprintf(args, sizeof args, "trace info '%s'", path);
    CHECK_EQ(pp5_test_run_cli(args, out, err), 0);
    char *text = pp5_test_read_file(out);
    CHECK(text && strstr(text, "blink: 50.0 %"));
    free(text);
    f = fopen(path, "w");
    REQUIRE(f);
    fputs(HEADER COLS "5\t1\t2\tok\t1\n2\t1\t2\tok\t1\n", f);
    fclose(f);
    CHECK(pp5_test_run_cli(args, out, err) != 0);
    text = pp5_test_read_file(err);
    CHECK(text && strstr(text, "backwards"));
    free(text);
}

/* ---- screen geometry (tracker/angles.c) ---- */

TEST(trace_angles_paper_display_matches_the_facts_file)
{
    gaze_geometry_t g;
    angles_paper_geometry(&g);
    /* gaze-facts.md §0: 340 mm wide, 0.266 mm/px, 33.4 px/deg at the centre, 30.0° high. */
    CHECK_NEAR(g.width_mm, 340, 0.5);
    CHECK_NEAR(g.width_mm / g.width_px, 0.266, 0.0005);
    CHECK_NEAR(angles_px_per_deg_centre(&g), 33.4, 0.05);
    double ax, ay;
    angles_px_to_deg(&g, 1280, 1024, &ax, &ay);
    CHECK_NEAR(2 * ax, 37.0, 1e-9);
    CHECK_NEAR(2 * ay, 30.0, 0.05);
    /* The 12° spot is ~402 px across (facts §0). */
    double x1, y1, x2, y2;
    angles_deg_to_px(&g, -6, 0, &x1, &y1);
    angles_deg_to_px(&g, 6, 0, &x2, &y2);
    CHECK_NEAR(x2 - x1, 402, 1.0);
}

TEST(trace_angles_remap_and_separation_by_hand)
{
    /* Recording: 1000x1000 px on 500x500 mm at 500 mm.  The right edge is
     * atan(250/500) = 26.565°; on the paper display (0.26558 mm/px at 508 mm)
     * that direction is 640 + 508*0.5/0.26558 px. */
    gaze_geometry_t rec = {1000, 1000, 500, 500, 500, 0}, paper;
    angles_paper_geometry(&paper);
    double x, y;
    angles_remap(&rec, &paper, 1000, 500, &x, &y);
    double pitch = 2 * 508 * tan(18.5 * M_PI / 180) / 1280;
    CHECK_NEAR(x, 640 + 508 * 0.5 / pitch, 1e-6);
    CHECK_NEAR(y, 512, 1e-9);
    /* Two points 250 mm apart straddling the centre: 2*atan(125/500). */
    CHECK_NEAR(angles_between_px(&rec, 250, 500, 750, 500), 2 * atan(0.25) * 180 / M_PI, 1e-9);
    /* Diagonal: the angle between (0,0,500) and (250,250,500) directions. */
    CHECK_NEAR(angles_between_px(&rec, 500, 500, 1000, 1000),
               acos(500 / sqrt(250.0 * 250 * 2 + 500 * 500)) * 180 / M_PI, 1e-9);
    /* px_per_deg stand-in: one degree off centre spans px_per_deg pixels. */
    gaze_geometry_t el = {1024, 768, 0, 0, 0, 35.2}, r;
    REQUIRE(angles_resolve(&el, &r) == PP5_OK);
    angles_deg_to_px(&r, 1, 0, &x, &y);
    CHECK_NEAR(x - 512, 35.2, 1e-9);
    gaze_geometry_t none = {1024, 768, 0, 0, 0, 0};
    CHECK(angles_resolve(&none, &r) == PP5_E_CONFIG);
}
