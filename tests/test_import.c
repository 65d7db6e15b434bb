/* test_import.c: importers (tracker/import_*.c) on the real recordings in
 * ../shared/data/gaze (skipped loudly when absent), cross-checked against the
 * independent gaze-trace v1 conversions stored beside them; on hand-written
 * Tobii Pro Lab and Pupil Labs files following the documented column names
 * (gaze-facts.md §4.2, §4.3; no such recordings are in shared/); and on
 * malformed input.  The GPL data are only read, never copied. */
#include <glob.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "tracker/angles.h"
#include "tracker/import.h"
#include "tracker/trace_file.h"

static char *dup_path(const char *p)
{
    return p ? strdup(p) : NULL;
}

/* Same samples: times exact, gaze to 1e-6 px, the same status and labels. */
static void check_same(const trace_t *a, const trace_t *b, const char *what, bool labels)
{
    CHECK_MSG(a->count == b->count, "%s: %zu vs %zu samples", what, a->count, b->count);
    size_t bad_t = 0, bad_xy = 0, bad_flags = 0, bad_label = 0;
    for (size_t i = 0; i < a->count && i < b->count; i++) {
        const gaze_sample_t *x = &a->samples[i], *y = &b->samples[i];
        bad_t += x->t_ns != y->t_ns;
        bad_flags += x->flags != y->flags;
        bad_label += labels && x->label != y->label;
        if ((x->flags & GAZE_FLAG_VALID) && (y->flags & GAZE_FLAG_VALID))
            bad_xy += fabs(x->x_px - y->x_px) > 1e-6 || fabs(x->y_px - y->y_px) > 1e-6;
    }
    CHECK_MSG(bad_t == 0, "%s: %zu times differ", what, bad_t);
    CHECK_MSG(bad_xy == 0, "%s: %zu positions differ", what, bad_xy);
    CHECK_MSG(bad_flags == 0, "%s: %zu statuses differ", what, bad_flags);
    CHECK_MSG(bad_label == 0, "%s: %zu labels differ", what, bad_label);
}

static void compare_with_shared(const char *original, const char *trace, import_format_t fmt,
                                const import_options_t *o, bool labels)
{
    char *orig = dup_path(pp5_test_shared_data(original));
    char *conv = dup_path(pp5_test_shared_data(trace));
    if (!orig || !conv) {
        free(orig);
        free(conv);
        SKIP("../shared/data/%s or %s is absent: the real-data importer check did not run",
             original, trace);
    }
    import_options_t none;
    import_defaults(&none);
    trace_t a, b;
    REQUIRE_MSG(import_file(orig, fmt, o, &a) == PP5_OK, "%s: %s", original, pp5_error_text());
    REQUIRE_MSG(import_file(conv, IMPORT_SHARED, &none, &b) == PP5_OK, "%s: %s", trace,
                pp5_error_text());
    check_same(&a, &b, original, labels);
    CHECK_NEAR(a.header.sample_rate_hz, b.header.sample_rate_hz, 0.02 * b.header.sample_rate_hz);
    CHECK_EQ(a.header.geometry.width_px, b.header.geometry.width_px);
    CHECK_EQ(a.header.geometry.height_px, b.header.geometry.height_px);
    trace_free(&a);
    trace_free(&b);
    free(orig);
    free(conv);
}

TEST(import_eyelink_mono_matches_the_shared_conversion)
{
    import_options_t o;
    import_defaults(&o);
    compare_with_shared("gaze/eyelink_sr_samples/original/mono250.asc.gz",
                        "gaze/eyelink_sr_samples/trace/mono250.tsv.gz", IMPORT_EYELINK, &o, true);
}

TEST(import_eyelink_2000hz_half_millisecond_steps)
{
    import_options_t o;
    import_defaults(&o);
    compare_with_shared("gaze/eyelink_sr_samples/original/mono2000.asc.gz",
                        "gaze/eyelink_sr_samples/trace/mono2000.tsv.gz", IMPORT_AUTO, &o, true);
    trace_t t;
    const char *p = pp5_test_shared_data("gaze/eyelink_sr_samples/original/mono2000.asc.gz");
    REQUIRE(p && import_file(p, IMPORT_AUTO, &o, &t) == PP5_OK);
    CHECK_EQ(t.samples[1].t_ns - t.samples[0].t_ns, 500000);
    CHECK_NEAR(t.header.sample_rate_hz, 2000, 0);
    CHECK_NEAR(t.header.geometry.px_per_deg, 35.2, 0.1);   /* PROVENANCE: 35.2 px/deg */
    trace_free(&t);
}

TEST(import_eyelink_binocular_and_remote_match)
{
    import_options_t o;
    import_defaults(&o);
    compare_with_shared("gaze/eyelink_sr_samples/original/bino1000.asc.gz",
                        "gaze/eyelink_sr_samples/trace/bino1000.tsv.gz", IMPORT_EYELINK, &o, true);
    compare_with_shared("gaze/eyelink_sr_samples/original/binoRemote250.asc.gz",
                        "gaze/eyelink_sr_samples/trace/binoRemote250.tsv.gz", IMPORT_EYELINK, &o,
                        true);
}

TEST(import_eyelink_sptool_gaze_coords_and_mcsorley_blinks)
{
    import_options_t o;
    import_defaults(&o);
    compare_with_shared("gaze/sptool_eyelink/original/eyelink_data_example.asc.gz",
                        "gaze/sptool_eyelink/trace/eyelink_data_example.tsv.gz", IMPORT_EYELINK,
                        &o, true);
    compare_with_shared("gaze/mcsorley2006/original/example_eyelink_events.txt.gz",
                        "gaze/mcsorley2006/trace/example_eyelink_events.tsv.gz", IMPORT_EYELINK,
                        &o, true);
    /* GAZE_COORDS 0 0 1679 1049 is 1680 x 1050; DISPLAY_COORDS 0 0 640 480 is 640 x 480. */
    trace_t t;
    const char *p = pp5_test_shared_data("gaze/sptool_eyelink/original/eyelink_data_example.asc.gz");
    REQUIRE(p && import_file(p, IMPORT_AUTO, &o, &t) == PP5_OK);
    CHECK_EQ(t.header.geometry.width_px, 1680);
    CHECK_EQ(t.header.geometry.height_px, 1050);
    trace_free(&t);
    p = pp5_test_shared_data("gaze/mcsorley2006/original/example_eyelink_events.txt.gz");
    REQUIRE(p && import_file(p, IMPORT_AUTO, &o, &t) == PP5_OK);
    CHECK_EQ(t.header.geometry.width_px, 640);
    size_t blinks = 0;
    for (size_t i = 0; i < t.count; i++)
        blinks += (t.samples[i].flags & GAZE_FLAG_BLINK) != 0;
    CHECK(blinks > 0);
    trace_free(&t);
}

TEST(import_tobii_tx300_matches_the_shared_conversion)
{
    import_options_t o;
    import_defaults(&o);
    o.source_width_px = 1920;
    o.source_height_px = 1080;
    o.source_width_mm = 509.174;
    o.source_height_mm = 286.411;
    o.source_distance_mm = 650;
    /* participant2/3 has real off-screen gaze (PROVENANCE). */
    compare_with_shared("gaze/i2mc_tx300/original/participant1/1.tsv",
                        "gaze/i2mc_tx300/trace/participant1_1.tsv.gz", IMPORT_AUTO, &o, false);
    compare_with_shared("gaze/i2mc_tx300/original/participant2/3.tsv",
                        "gaze/i2mc_tx300/trace/participant2_3.tsv.gz", IMPORT_TOBII, &o, false);
}

TEST(import_every_shared_trace_reads_with_its_stated_sample_count)
{
    const char *root = pp5_test_shared_data("gaze");
    if (!root)
        SKIP("../shared/data/gaze is absent: no real traces checked");
    char pattern[1024];
    glob_t g;
    int files = 0;
    for (int depth = 0; depth < 2; depth++) {
        snprintf(pattern, sizeof pattern, depth ? "%s/*/trace/*/*.tsv.gz" : "%s/*/trace/*.tsv.gz",
                 root);
        if (glob(pattern, 0, NULL, &g) != 0)
            continue;
        for (size_t i = 0; i < g.gl_pathc; i++) {
            import_options_t o;
            import_defaults(&o);
            trace_t t;
            pp5_status_t st = import_file(g.gl_pathv[i], IMPORT_AUTO, &o, &t);
            CHECK_MSG(st == PP5_OK, "%s: %s", g.gl_pathv[i], pp5_error_text());
            if (st != PP5_OK)
                continue;
            /* The header's own "samples:" key is the converter's count. */
            char *text;
            size_t len;
            REQUIRE(trace_slurp(g.gl_pathv[i], (size_t)1 << 28, &text, &len) == PP5_OK);
            const char *k = strstr(text, "\n# samples: ");
            CHECK_MSG(k && (size_t)atol(k + 12) == t.count, "%s: %zu samples", g.gl_pathv[i],
                      t.count);
            free(text);
            trace_free(&t);
            files++;
        }
        globfree(&g);
    }
    CHECK_MSG(files >= 30, "only %d shared traces found", files);
}

/* ---- hand-written files in the documented layouts ---- */

TEST(import_tobii_pro_lab_export_by_column_name)
{
    /* Columns as a Pro Lab export names them (gaze-facts §4.2), in an order of
     * the user's choosing, with a gyroscope row, an event row, an EyesNotFound
     * row and a decimal comma. */
    const char *tsv =
        "Recording timestamp [ms]\tSensor\tEvent\tGaze point X\tGaze point Y\tValidity left\t"
        "Validity right\tEye movement type\n"
        "1000\tEye Tracker\t\t960\t540\tValid\tValid\tFixation\n"
        "1008.3\tEye Tracker\t\t961,5\t541\tValid\tInvalid\tFixation\n"
        "1010\tGyroscope\t\t\t\t\t\t\n"
        "1012\t\tImageStimulusStart\t\t\t\t\t\n"
        "1016.7\tEye Tracker\t\t\t\tInvalid\tInvalid\tEyesNotFound\n"
        "1025\tEye Tracker\t\t-100\t2000\tValid\tValid\tUnclassified\n";
    import_options_t o;
    import_defaults(&o);
    trace_t t;
    CHECK(import_tobii(tsv, strlen(tsv), "prolab", &o, &t) == PP5_E_CONFIG);   /* no --source-px */
    CHECK(strstr(pp5_error_text(), "--source-px") != NULL);
    o.source_width_px = 1920;
    o.source_height_px = 1080;
    o.source_width_mm = 531;
    o.source_height_mm = 299;
    o.source_distance_mm = 650;
    CHECK(import_detect(tsv, strlen(tsv)) == IMPORT_TOBII);
    REQUIRE_MSG(import_tobii(tsv, strlen(tsv), "prolab", &o, &t) == PP5_OK, "%s", pp5_error_text());
    CHECK_EQ(t.count, 4);
    CHECK_EQ(t.samples[1].t_ns, 8300000);
    CHECK_NEAR(t.samples[1].x_px, 961.5, 1e-9);
    CHECK(t.samples[2].flags == 0);
    CHECK_EQ(t.samples[3].t_ns, 25000000);
    CHECK_NEAR(t.samples[3].y_px, 2000, 0);           /* off-screen kept */
    /* median step of 8.3, 8.4, 8.3 ms -> 120.5 Hz */
    CHECK_NEAR(t.header.sample_rate_hz, 1000 / 8.3, 0.01);
    trace_free(&t);
    /* Without a unit, a 20 000 step is microseconds (50 Hz glasses rows). */
    const char *us = "Recording timestamp\tGaze point X\tGaze point Y\n0\t1\t2\n20000\t3\t4\n"
                     "40000\t5\t6\n";
    REQUIRE(import_tobii(us, strlen(us), "us", &o, &t) == PP5_OK);
    CHECK_EQ(t.samples[2].t_ns, 40000000);
    CHECK_NEAR(t.header.sample_rate_hz, 50, 1e-9);
    trace_free(&t);
}

TEST(import_pupil_gaze_positions_csv)
{
    /* gaze_positions.csv columns (gaze-facts §4.3); base_data quoted with a comma. */
    const char *csv =
        "gaze_timestamp,world_index,confidence,norm_pos_x,norm_pos_y,base_data\n"
        "5000.000,0,0.99,0.5,0.5,\"5000.0-0 5000.0-1\"\n"
        "5000.005,0,0.95,0.25,0.75,\"a,b\"\n"
        "5000.010,1,0.10,0.9,0.9,x\n"
        "5000.010,1,0.80,1.0,0.0,x\n"
        "5000.015,1,0.70,0.1,1.2,x\n";
    import_options_t o;
    import_defaults(&o);
    o.source_width_px = 1280;
    o.source_height_px = 720;
    o.source_width_mm = 600;
    o.source_height_mm = 340;
    o.source_distance_mm = 700;
    CHECK(import_detect(csv, strlen(csv)) == IMPORT_PUPIL);
    trace_t t;
    REQUIRE_MSG(import_pupil(csv, strlen(csv), "pupil", &o, &t) == PP5_OK, "%s", pp5_error_text());
    CHECK_EQ(t.count, 5);
    CHECK_NEAR(t.samples[0].x_px, 640, 1e-9);
    CHECK_NEAR(t.samples[0].y_px, 360, 1e-9);
    CHECK_NEAR(t.samples[1].x_px, 320, 1e-9);          /* 0.25 * 1280 */
    CHECK_NEAR(t.samples[1].y_px, 180, 1e-9);          /* (1 - 0.75) * 720: y flipped */
    CHECK(t.samples[2].flags == 0);                    /* confidence 0.1 < 0.6 */
    CHECK_EQ(t.samples[3].t_ns, t.samples[2].t_ns);    /* equal times kept */
    CHECK_NEAR(t.samples[3].y_px, 720, 1e-9);
    CHECK_NEAR(t.samples[4].y_px, -0.2 * 720, 1e-9);   /* off the surface, kept */
    CHECK_EQ(t.samples[1].t_ns, 5000000);
    CHECK_NEAR(t.header.sample_rate_hz, 200, 0.01);
    trace_free(&t);
    /* Surface export: x_norm, y_norm, on_surf. */
    const char *surf = "world_timestamp,world_index,gaze_timestamp,x_norm,y_norm,x_scaled,"
                       "y_scaled,on_surf,confidence\n"
                       "1,0,10.0,0.5,0.25,0,0,True,0.9\n"
                       "1,0,10.01,0.5,0.25,0,0,False,0.9\n";
    REQUIRE(import_pupil(surf, strlen(surf), "surf", &o, &t) == PP5_OK);
    CHECK_NEAR(t.samples[0].y_px, 540, 1e-9);
    CHECK(t.samples[1].flags == 0);
    trace_free(&t);
}

TEST(import_malformed_inputs_give_clear_errors)
{
    import_options_t o;
    import_defaults(&o);
    o.source_width_px = 1000;
    o.source_height_px = 1000;
    o.source_px_per_deg = 30;
    static const struct { import_format_t f; const char *text, *want; } cases[] = {
        {IMPORT_EYELINK, "MSG 1 DISPLAY_COORDS 0 0 1023 767\n100\t1\t2\t3\n", "outside a START"},
        {IMPORT_EYELINK, "START 1 RIGHT SAMPLES EVENTS\nSAMPLES GAZE RIGHT RATE 500\n"
                         "100\t1\t2\t3\n98\t1\t2\t3\nEND 200 SAMPLES EVENTS RES 30 30\n",
         "out-of-order time"},
        {IMPORT_EYELINK, "START 1 LEFT RIGHT SAMPLES EVENTS\nSAMPLES GAZE LEFT RIGHT RATE 500\n"
                         "100\t1\t2\t3\t4\n", "needs 7"},
        {IMPORT_EYELINK, "START 1 RIGHT SAMPLES EVENTS\n100\t1\t2\t3\n", "RATE"},
        {IMPORT_EYELINK, "START 1 RIGHT SAMPLES EVENTS\nSAMPLES GAZE RIGHT RATE 500\n"
                         "100\tabc\t2\t3\n", "neither a number"},
        {IMPORT_EYELINK, "START 1 RIGHT SAMPLES EVENTS\nSAMPLES HREF RIGHT RATE 500\n"
                         "100\t1\t2\t3\n", "not GAZE"},
        {IMPORT_EYELINK, "** nothing\n", "no sample lines"},
        {IMPORT_TOBII, "Recording timestamp\tGaze point X\n1\t2\n", "Gaze point Y"},
        {IMPORT_TOBII, "Recording timestamp\tGaze point X\tGaze point Y\n1\t2\t3\n0\t2\t3\n",
         "out-of-order"},
        {IMPORT_TOBII, "Recording timestamp\tGaze point X\tGaze point Y\n1\t2\t3\n2\t2\n",
         "truncated"},
        {IMPORT_TOBII, "Recording timestamp\tGaze point X\tGaze point Y\nnan\t2\t3\n",
         "not a number"},
        {IMPORT_PUPIL, "gaze_timestamp,confidence,norm_pos_x,norm_pos_y\nnan,1,0.5,0.5\n",
         "NaN is not allowed"},
        {IMPORT_PUPIL, "gaze_timestamp,confidence,norm_pos_x,norm_pos_y\n2,1,0.5,0.5\n"
                       "1,1,0.5,0.5\n", "out-of-order"},
        {IMPORT_PUPIL, "gaze_timestamp,confidence,norm_pos_y\n2,1,0.5\n", "norm_pos_x"},
        {IMPORT_PUPIL, "gaze_timestamp,confidence,norm_pos_x,norm_pos_y\n2,7,0.5,0.5\n",
         "confidence"},
        {IMPORT_SHARED, "# gaze-trace v1\n# source: x\n# sample_rate_hz: 500\n# screen_px: 10 10\n"
                        "# screen_mm: 1 1\nt_ms\tx_px\ty_px\n", "'distance_mm' is missing"},
        {IMPORT_SHARED, "# gaze-trace v1\n# source: x\n# sample_rate_hz: 500\n# screen_px: 10 10\n"
                        "# screen_mm: 1 1\n# distance_mm: 5\nt_ms\tx_px\ty_px\n2\t1\t1\n1\t1\t1\n",
         "backwards"},
        {IMPORT_SHARED, "# gaze-trace v1\n# source: x\n# sample_rate_hz: 500\n# screen_px: 10 10\n"
                        "# screen_mm: 1 1\n# distance_mm: 5\nt_ms\tx_px\ty_px\nnan\t1\t1\n",
         "NaN is not allowed"},
        {IMPORT_SHARED, "# gaze-trace v2\n", "not a gaze-trace v1"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        trace_t t;
        pp5_status_t st;
        const char *txt = cases[i].text;
        switch (cases[i].f) {
        case IMPORT_EYELINK: st = import_eyelink(txt, strlen(txt), "m", &o, &t); break;
        case IMPORT_TOBII:   st = import_tobii(txt, strlen(txt), "m", &o, &t); break;
        case IMPORT_PUPIL:   st = import_pupil(txt, strlen(txt), "m", &o, &t); break;
        default:             st = import_shared(txt, strlen(txt), "m", &o, &t); break;
        }
        CHECK_MSG(st != PP5_OK, "case %zu imported but should fail (%s)", i, cases[i].want);
        CHECK_MSG(strstr(pp5_error_text(), cases[i].want) != NULL,
                  "case %zu: error '%s' does not mention '%s'", i, pp5_error_text(), cases[i].want);
    }
}

TEST(import_eyelink_tolerates_blinks_gaps_and_extra_columns)
{
    /* Binocular with velocity and CR flags, a blink with '.', a gap between
     * blocks, an empty EBLINK (end before start, as EyeLink I writes). */
    const char *asc =
        "** CONVERTED FROM test.edf\n"
        "MSG\t1 GAZE_COORDS 0.00 0.00 1023.00 767.00\n"
        "START\t100 \tLEFT\tRIGHT\tSAMPLES\tEVENTS\n"
        "SAMPLES\tGAZE\tLEFT\tRIGHT\tVEL\tRATE\t1000.00\tTRACKING\tCR\tFILTER\t2\n"
        "100\t 100.0\t 200.0\t 1000.0\t 110.0\t 210.0\t 1000.0\t0\t0\t0\t0\t.....\n"
        "101\t   .\t   .\t    0.0\t 120.0\t 220.0\t 1000.0\t0\t0\t0\t0\t.C...\n"
        "102\t   .\t   .\t    0.0\t   .\t   .\t    0.0\t0\t0\t0\t0\t.C.C.\n"
        "EBLINK L 102 102 1\n"
        "EBLINK R 103 101 0\n"
        "END\t103 \tSAMPLES\tEVENTS\tRES\t 35.0\t 36.0\n"
        "START\t5000 \tLEFT\tRIGHT\tSAMPLES\tEVENTS\n"
        "SAMPLES\tGAZE\tLEFT\tRIGHT\tVEL\tRATE\t1000.00\tTRACKING\tCR\tFILTER\t2\n"
        "5000\t 3000.0\t -50.0\t 1000.0\t 3010.0\t -60.0\t 1000.0\t0\t0\t0\t0\t.....\n"
        "END\t5001 \tSAMPLES\tEVENTS\tRES\t 35.0\t 36.0\n";
    import_options_t o;
    import_defaults(&o);
    trace_t t;
    CHECK(import_detect(asc, strlen(asc)) == IMPORT_EYELINK);
    REQUIRE_MSG(import_eyelink(asc, strlen(asc), "hand.asc", &o, &t) == PP5_OK, "%s",
                pp5_error_text());
    CHECK_EQ(t.count, 4);
    CHECK_NEAR(t.samples[0].x_px, 105, 1e-12);         /* mean of the eyes */
    CHECK_NEAR(t.samples[1].x_px, 120, 1e-12);         /* only the right eye has data */
    CHECK(t.samples[2].flags == GAZE_FLAG_BLINK);
    CHECK_EQ(t.samples[3].t_ns, 4900000000LL);          /* the gap is kept */
    CHECK_NEAR(t.samples[3].x_px, 3005, 1e-12);        /* off screen, kept */
    CHECK_EQ(t.header.geometry.width_px, 1024);
    CHECK_NEAR(t.header.geometry.px_per_deg, 35.0, 1e-12);
    trace_free(&t);
    o.eye = 'L';
    REQUIRE(import_eyelink(asc, strlen(asc), "hand.asc", &o, &t) == PP5_OK);
    CHECK(t.samples[1].flags == 0);                    /* left eye missing there */
    trace_free(&t);
}

TEST(import_cli_converts_and_carries_to_the_paper_display)
{
    const char *dir = pp5_test_outdir();
    char in[512], outp[600], args[1400], err[600];
    snprintf(in, sizeof in, "%s/g.csv", dir);
    snprintf(outp, sizeof outp, "%s/g.trace", dir);
    snprintf(err, sizeof err, "%s/err.txt", dir);
    FILE *f = fopen(in, "w");
    REQUIRE(f);
    /* Centre and the right edge of a 1000x1000 px, 500x500 mm screen at 500 mm. */
    fputs("gaze_timestamp,confidence,norm_pos_x,norm_pos_y\n1.0,1,0.5,0.5\n1.01,1,1.0,0.5\n", f);
    fclose(f);
    snprintf(args, sizeof args, "trace import '%s' --source-px 1000x1000 --source-mm 500x500 "
             "--source-distance-mm 500 --to paper --out '%s'", in, outp);
    REQUIRE_MSG(pp5_test_run_cli(args, NULL, err) == 0, "import failed");
    trace_t t;
    REQUIRE(trace_read_file(outp, &t) == PP5_OK);
    CHECK_EQ(t.header.geometry.width_px, 1280);
    CHECK_NEAR(t.samples[0].x_px, 640, 0.001);
    double pitch = 2 * 508 * tan(18.5 * M_PI / 180) / 1280;
    CHECK_NEAR(t.samples[1].x_px, 640 + 508 * 0.5 / pitch, 0.001);
    trace_free(&t);
    snprintf(args, sizeof args, "trace import '%s' --out '%s'", in, outp);
    CHECK(pp5_test_run_cli(args, NULL, err) != 0);     /* Pupil needs --source-px */
    char *e = pp5_test_read_file(err);
    CHECK(e && strstr(e, "--source-px"));
    free(e);
}

#include "tracker/synth.h"

/* Flips, deletes and truncates bytes of valid inputs: every parser must return
 * (OK or an error with a message), never crash or read out of bounds (the
 * ASan build runs this too). */
TEST(import_mutated_inputs_never_crash)
{
    static const char *const seeds[] = {
        "** CONVERTED\nMSG\t1 DISPLAY_COORDS 0 0 1023 767\nSTART\t10 \tLEFT\tRIGHT\tSAMPLES\tEVENTS\n"
        "SAMPLES\tGAZE\tLEFT\tRIGHT\tRATE\t500.00\n10\t1.0\t2.0\t3.0\t4.0\t5.0\t6.0\t.....\n"
        "12\t   .\t   .\t0.0\t4.0\t5.0\t6.0\t.C...\nEFIX L 10 12 4 1 2 3\n"
        "END\t13 \tSAMPLES\tEVENTS\tRES\t 35.0\t 36.0\n",
        "Recording timestamp [ms]\tSensor\tGaze point X\tGaze point Y\n1\tEye Tracker\t5\t6\n"
        "2\tEye Tracker\t7,5\t8\n3\tGyroscope\t\t\n",
        "Time\tLGazePos2dx\tLGazePos2dy\tLValidity\tRGazePos2dx\tRGazePos2dy\tRValidity\n"
        "100\t0.5\t0.5\t0\t0.4\t0.4\t1\n3433\t-1\t-1\t4\t0.4\t0.4\t0\n",
        "gaze_timestamp,confidence,norm_pos_x,norm_pos_y,base_data\n1.0,0.9,0.5,0.5,\"a b\"\n"
        "1.01,0.9,0.5,0.5,\"x,y\"\n",
        "# gaze-trace v1\n# source: s\n# sample_rate_hz: 500\n# screen_px: 10 10\n"
        "# screen_mm: 1 1\n# distance_mm: 5\nt_ms\tx_px\ty_px\tlabel\n0\t1\t1\t1\n2\tnan\tnan\t5\n",
        "# pp5-trace v1\n# source: s\n# sample_rate_hz: 500\n# screen_px: 10 10\n"
        "# screen_mm: 1 1\n# distance_mm: 5\nt_ms\tx_px\ty_px\tstatus\tlabel\n0\t1\t1\tok\t1\n"
        "2\tnan\tnan\tblink\t5\n# end: 2 samples\n",
    };
    synth_rng_t rng;
    synth_rng_seed(&rng, 42);
    import_options_t o;
    import_defaults(&o);
    o.source_width_px = 100;
    o.source_height_px = 100;
    o.source_px_per_deg = 10;
    int ok = 0, errors = 0;
    for (size_t s = 0; s < sizeof seeds / sizeof seeds[0]; s++) {
        size_t len = strlen(seeds[s]);
        char *buf = malloc(len + 1);
        REQUIRE(buf);
        for (int round = 0; round < 1000; round++) {
            memcpy(buf, seeds[s], len + 1);
            size_t n = len;
            int edits = 1 + (int)(synth_rng_next(&rng) % 4);
            for (int e = 0; e < edits && n > 0; e++) {
                size_t at = synth_rng_next(&rng) % n;
                switch (synth_rng_next(&rng) % 4) {
                case 0: buf[at] = (char)(synth_rng_next(&rng) & 0xff); break;
                case 1: memmove(buf + at, buf + at + 1, n - at); n--; break;
                case 2: n = at; break;                                  /* truncate */
                default: buf[at] = "\t\n.,-9e"[synth_rng_next(&rng) % 7]; break;
                }
            }
            trace_t t;
            pp5_status_t st;
            switch (s) {
            case 0: st = import_eyelink(buf, n, "fuzz", &o, &t); break;
            case 1: case 2: st = import_tobii(buf, n, "fuzz", &o, &t); break;
            case 3: st = import_pupil(buf, n, "fuzz", &o, &t); break;
            case 4: st = import_shared(buf, n, "fuzz", &o, &t); break;
            default: st = trace_parse(buf, n, "fuzz", &t); break;
            }
            if (st == PP5_OK) {
                ok++;
                /* Whatever was accepted is in time order. */
                for (size_t i = 1; i < t.count; i++)
                    if (t.samples[i].t_ns < t.samples[i - 1].t_ns)
                        CHECK_MSG(false, "seed %zu: accepted out-of-order time", s);
                trace_free(&t);
            } else {
                errors++;
                CHECK(pp5_error_text()[0] != '\0');
            }
        }
        free(buf);
    }
    CHECK(ok > 0 && errors > 0);
}
