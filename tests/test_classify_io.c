/* test_classify_io.c: the users' own transfer functions: pp5's text format
 * and ParaView presets on good and malformed files, the table form's
 * classification worked out by hand, write-then-read round trips, the
 * histogram and the automatic default on volumes whose percentiles are known
 * by construction, and `pp5 render` on a float volume of values 0-5 with no
 * --tf (the case that gave a blank image with every preset). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "png_io.h"
#include "render/classify_auto.h"
#include "render/classify_io.h"
#include "render/volume_histogram.h"

/* This test's output folder (pp5_test_outdir empties it on every call). */
static char dir[1024];

static void fresh_dir(void)
{
    snprintf(dir, sizeof dir, "%s", pp5_test_outdir());
}

static const char *write_text(const char *name, const char *text)
{
    static char path[4][1200];
    static int next;
    char *p = path[next++ % 4];
    snprintf(p, sizeof path[0], "%s/%s", dir, name);
    FILE *f = fopen(p, "w");
    REQUIRE(f != NULL);
    fputs(text, f);
    fclose(f);
    return p;
}

TEST(tf_text_contours_and_table_classify_as_worked_out)
{
    classify_tf_t tf;
    REQUIRE_MSG(classify_tf_parse_text("# a comment\n\npp5-tf 1\nname bone  # trailing\n"
                                       "contour 100 0.5 2 1 0.5 0.25\nmin-opacity 0.05\n",
                                       "t.tf", &tf) == PP5_OK, "%s", pp5_error_text());
    CHECK(strcmp(tf.name, "bone") == 0);
    CHECK_EQ(tf.count, 1);
    CHECK_NEAR(tf.contour[0].value, 100, 0);
    CHECK_NEAR(tf.contour[0].width_vox, 2, 0);
    CHECK_NEAR(tf.contour[0].rgb[2], 0.25, 0);
    CHECK_NEAR(tf.min_opacity, 0.05, 1e-7);
    /* A voxel of value 99 with |g| = 1: 0.5 * (1 - 1 / (2 * 1)) = 0.25. */
    float rgb[3];
    CHECK_NEAR(classify_voxel(&tf, 99.0f, 1.0f, rgb), 0.25, 1e-6);

    REQUIRE(classify_tf_parse_text("pp5-tf 1\nopacity 0 0\nopacity 10 1\n"
                                   "color 0 1 0 0\ncolor 10 0 0 1\n", "t.tf", &tf) == PP5_OK);
    CHECK(classify_tf_is_table(&tf));
    /* At 2.5, a quarter of the way: opacity 0.25, colour (0.75, 0, 0.25);
     * the gradient plays no part. */
    CHECK_NEAR(classify_voxel(&tf, 2.5f, 0.0f, rgb), 0.25, 1e-6);
    CHECK_NEAR(rgb[0], 0.75, 1e-6);
    CHECK_NEAR(rgb[2], 0.25, 1e-6);
    CHECK_NEAR(classify_voxel(&tf, 2.5f, 7.0f, rgb), 0.25, 1e-6);
    /* Held beyond the ends. */
    CHECK_NEAR(classify_voxel(&tf, -5.0f, 0.0f, rgb), 0.0, 0);
    CHECK_NEAR(rgb[0], 1.0, 0);
    CHECK_NEAR(classify_voxel(&tf, 50.0f, 0.0f, rgb), 1.0, 0);
    CHECK_NEAR(rgb[2], 1.0, 0);
    /* Opacity points alone: white. */
    REQUIRE(classify_tf_parse_text("pp5-tf 1\nopacity 0 0\nopacity 4 0.8\n", "t.tf", &tf) ==
            PP5_OK);
    CHECK_NEAR(classify_voxel(&tf, 1.0f, 0.0f, rgb), 0.2, 1e-6);
    CHECK(rgb[0] == 1.0f && rgb[1] == 1.0f && rgb[2] == 1.0f);
}

TEST(tf_text_malformed_files_name_the_line)
{
    static const struct {
        const char *text;
        int line;
    } bad[] = {
        {"contour 1 1 1 1 1 1\n", 1},                        /* no pp5-tf line first */
        {"pp5-tf 2\n", 1},                                   /* unknown version */
        {"pp5-tf 1\nsurface 1 2\n", 2},                      /* unknown keyword */
        {"pp5-tf 1\ncontour 1 nan 2 1 1 1\n", 2},            /* not finite */
        {"pp5-tf 1\ncontour 1 1.5 2 1 1 1\n", 2},            /* opacity above 1 */
        {"pp5-tf 1\ncontour 1 1 0 1 1 1\n", 2},              /* zero thickness */
        {"pp5-tf 1\ncontour 1 1 2 1 1\n", 2},                /* a number missing */
        {"pp5-tf 1\nopacity 5 0\nopacity 5 1\n", 3},         /* not increasing */
        {"pp5-tf 1\n\ncolor 0 1 1 1\n", 4},                  /* colour without opacity (at end) */
        {"pp5-tf 1\ncontour 1 1 2 1 1 1\nopacity 0 1\n", 4}, /* both forms */
        {"pp5-tf 1\nname x\n", 3},                           /* nothing visible */
        {"pp5-tf 1\ncontour 1 1 2 1 1 1\ncontour 2 1 2 1 1 1\ncontour 3 1 2 1 1 1\n"
         "contour 4 1 2 1 1 1\ncontour 5 1 2 1 1 1\n", 6},   /* five contours */
        {"", 1},                                             /* empty */
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        classify_tf_t tf;
        pp5_status_t st = classify_tf_parse_text(bad[i].text, "bad.tf", &tf);
        char want[32];
        snprintf(want, sizeof want, "bad.tf:%d:", bad[i].line);
        CHECK_MSG(st == PP5_E_FORMAT && strstr(pp5_error_text(), want),
                  "case %zu: status %d, message '%s' (want %s)", i, st, pp5_error_text(), want);
    }
    /* Files: a missing one, and binary data, are refused by name. */
    fresh_dir();
    classify_tf_t tf;
    char note[128];
    CHECK_EQ(classify_tf_read("/nonexistent/x.tf", &tf, note, sizeof note), PP5_E_IO);
    CHECK(strstr(pp5_error_text(), "/nonexistent/x.tf") != NULL);
    const char *bin = write_text("bin.tf", "pp5-tf 1\n");
    FILE *f = fopen(bin, "ab");
    REQUIRE(f != NULL);
    fputc(0, f);
    fclose(f);
    CHECK_EQ(classify_tf_read(bin, &tf, note, sizeof note), PP5_E_FORMAT);
}

TEST(tf_paraview_presets_good_and_malformed)
{
    fresh_dir();
    const char *good = write_text("bone.json",
        "[\n {\n  \"ColorSpace\": \"RGB\",\n  \"Name\": \"bone ramp\",\n"
        "  \"RGBPoints\": [0, 0, 0, 0, 100, 1, 1, 1],\n"
        "  \"Points\": [0, 0, 0.5, 0, 100, 1, 0.5, 0]\n }\n]\n");
    classify_tf_t tf;
    char note[256];
    REQUIRE_MSG(classify_tf_read(good, &tf, note, sizeof note) == PP5_OK, "%s", pp5_error_text());
    CHECK(strcmp(tf.name, "bone ramp") == 0);
    CHECK_EQ(tf.n_alpha, 2);
    CHECK_EQ(tf.n_rgb, 2);
    CHECK_MSG(note[0] == '\0', "note '%s'", note);
    float rgb[3];
    CHECK_NEAR(classify_voxel(&tf, 25.0f, 0.0f, rgb), 0.25, 1e-6);
    CHECK_NEAR(rgb[1], 0.25, 1e-6);
    /* Two presets, a diverging colour space and shaped opacity: read, with
     * notes saying what pp5 does differently. */
    const char *two = write_text("two.json",
        "[{\"ColorSpace\": \"Diverging\", \"RGBPoints\": [0,0,0,1, 1,1,0,0],"
        " \"Points\": [0,0,0.3,0.2, 1,1,0.5,0]}, {\"RGBPoints\": [0,0,0,0]}]");
    REQUIRE(classify_tf_read(two, &tf, note, sizeof note) == PP5_OK);
    CHECK_MSG(strstr(note, "2 presets") && strstr(note, "Diverging") && strstr(note, "linear"),
              "note '%s'", note);
    static const struct {
        const char *name, *text, *says;
    } bad[] = {
        {"syntax.json", "[{\"RGBPoints\": [0, 0, 0, 0,]}]", "line and column"},
        {"noalpha.json", "[{\"RGBPoints\": [0, 0, 0, 0, 1, 1, 1, 1]}]", "Save opacities"},
        {"ragged.json", "[{\"RGBPoints\": [0, 0, 0], \"Points\": [0, 0, 0.5, 0]}]",
         "4 numbers per point"},
        {"string.json", "[{\"Points\": [0, \"x\", 0.5, 0]}]", "not a finite number"},
        {"alpha.json", "[{\"Points\": [0, 2, 0.5, 0]}]", "opacity outside 0..1"},
        {"order.json", "[{\"Points\": [1, 0, 0.5, 0, 0, 1, 0.5, 0]}]", "not increasing"},
        {"scalar.json", "[42]", "expected a ParaView preset"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char name[64];
        snprintf(name, sizeof name, "bad_%s", bad[i].name);
        const char *path = write_text(name, bad[i].text);
        pp5_status_t st = classify_tf_read(path, &tf, note, sizeof note);
        const char *want = strcmp(bad[i].name, "syntax.json") == 0 ? ".json:1:" : bad[i].says;
        CHECK_MSG(st != PP5_OK && strstr(pp5_error_text(), want) &&
                      strstr(pp5_error_text(), name),
                  "%s: status %d, '%s'", bad[i].name, st, pp5_error_text());
    }
}

static void check_round_trip(const classify_tf_t *tf)
{
    char *text = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&text, &len);
    REQUIRE(m != NULL);
    classify_tf_write_text(m, tf, "a header\nof two lines");
    fclose(m);
    classify_tf_t back;
    REQUIRE_MSG(classify_tf_parse_text(text, "round-trip", &back) == PP5_OK, "%s\n%s",
                pp5_error_text(), text);
    CHECK_MSG(memcmp(tf, &back, sizeof back) == 0, "%s did not read back exactly:\n%s", tf->name,
              text);
    free(text);
}

TEST(tf_written_text_reads_back_exactly)
{
    static const char *const presets[] = {"ct-skin", "ct-skin-ramp", "ct-bone", "mr",
                                          "shepp-logan", "marschner-lobb", "sphere-shell"};
    for (size_t i = 0; i < sizeof presets / sizeof presets[0]; i++) {
        classify_tf_t tf;
        REQUIRE(classify_preset(presets[i], &tf) == PP5_OK);
        check_round_trip(&tf);
    }
    classify_tf_t t;
    memset(&t, 0, sizeof t);
    snprintf(t.name, sizeof t.name, "table");
    for (int i = 0; i < 40; i++) {
        t.alpha[i] = (classify_alpha_point_t){(float)i / 7.0f, (float)(i % 10) / 9.0f};
        t.rgb[i].value = (float)i * 0.3f - 2.0f;
        t.rgb[i].rgb[0] = (float)i / 39.0f;
    }
    t.n_alpha = t.n_rgb = 40;
    t.min_opacity = 1.0f / 3.0f;
    check_round_trip(&t);
}

/* 1000 voxels: 500 at 0, 400 at 2, 100 at 4 (values 0..4, bins 1/1024 wide). */
static void make_three_valued(volume_t *v)
{
    REQUIRE(volume_alloc(v, 10, 10, 10) == PP5_OK);
    for (int i = 0; i < 1000; i++)
        v->data[i] = i < 500 ? 0.0f : i < 900 ? 2.0f : 4.0f;
    volume_update_stats(v);
}

TEST(tf_histogram_and_auto_contours_worked_out)
{
    volume_t v;
    make_three_valued(&v);
    volume_histogram_t *h = malloc(sizeof *h);
    REQUIRE(h != NULL);
    volume_histogram_compute(&v, h);
    const double w = 4.0 / 4096;
    /* The background: the 500 zeros in bin 0; the 5-bin average keeps falling
     * through bin 3 (500/3, 500/4, 500/5, 0) and stops at bin 4 (0 again). */
    CHECK_EQ(h->n_background, 500);
    CHECK_EQ(h->n_foreground, 500);
    CHECK_NEAR(h->background_max, 4 * w, 1e-12);
    CHECK_NEAR(h->background_peak, 0.5 * w, 1e-12);
    /* Foreground median: 250 of the 400 in bin 2048 (value 2); 99th: 95 of the
     * 100 in the last bin, 4095. */
    double median = (2048 + 250.0 / 400) * w, p99 = (4095 + 95.0 / 100) * w;
    CHECK_NEAR(h->fg_p50, median, 1e-9);
    CHECK_NEAR(h->fg_p99, p99, 1e-9);
    CHECK_NEAR(h->fg_p1, (2048 + 5.0 / 400) * w, 1e-9);
    classify_tf_t tf;
    classify_auto_info_t info;
    REQUIRE(classify_tf_auto(h, &tf, &info) == PP5_OK);
    CHECK_EQ(tf.count, 2);
    CHECK_NEAR(tf.contour[0].value, 0.5 * (0.5 * w + median), 1e-6);
    CHECK_NEAR(tf.contour[1].value, 0.5 * (median + p99), 1e-6);
    CHECK_NEAR(tf.contour[0].opacity, 0.3, 1e-7);
    /* A constant volume has no foreground: a clear error, no function. */
    for (int i = 0; i < 1000; i++)
        v.data[i] = 3.0f;
    volume_update_stats(&v);
    volume_histogram_compute(&v, h);
    CHECK_EQ(classify_tf_auto(h, &tf, &info), PP5_E_RANGE);
    CHECK(strstr(pp5_error_text(), "--tf") != NULL);
    free(h);
    volume_free(&v);
}

/* A float32 head of values 0-5 (shell 5, inside 1.2, a 3.5 lesion), written
 * with its layout in the name, as a new user's file would be. */
static const char *write_float_head(void)
{
    static char path[1200];
    enum { N = 40 };
    snprintf(path, sizeof path, "%s/head_%dx%dx%d_f32le.raw", dir, N, N, N);
    float *d = malloc(sizeof(float) * N * N * N);
    REQUIRE(d != NULL);
    for (int z = 0; z < N; z++)
        for (int y = 0; y < N; y++)
            for (int x = 0; x < N; x++) {
                double dx = x - 19.5, dy = y - 19.5, dz = z - 19.5;
                double r = sqrt(dx * dx + dy * dy + dz * dz);
                double les = sqrt((dx - 5) * (dx - 5) + dy * dy + dz * dz);
                d[(z * N + y) * N + x] = r > 16 ? 0.0f : r > 13 ? 5.0f : les < 4 ? 3.5f : 1.2f;
            }
    FILE *f = fopen(path, "wb");
    REQUIRE(f != NULL);
    REQUIRE(fwrite(d, sizeof(float), N * N * N, f) == N * N * N);
    fclose(f);
    free(d);
    return path;
}

static int lit_pixels(const char *png)
{
    image8_t img;
    if (png_read(png, &img, 3) != PP5_OK)
        return -1;
    int lit = 0;
    for (int i = 0; i < img.width * img.height; i++)
        lit += img.pixels[3 * i] + img.pixels[3 * i + 1] + img.pixels[3 * i + 2] > 30;
    image8_free(&img);
    return lit;
}

TEST(tf_auto_default_gives_an_image_of_a_float_volume_and_saves_what_it_chose)
{
    fresh_dir();
    const char *vol = write_float_head();
    char args[4096], out[1200], png[1200], png2[1200], tfo[1200];
    snprintf(out, sizeof out, "%s/out.txt", dir);
    snprintf(png, sizeof png, "%s/auto.png", dir);
    snprintf(png2, sizeof png2, "%s/again.png", dir);
    snprintf(tfo, sizeof tfo, "%s/chosen.tf", dir);
    /* A preset made for other values shows nothing: the problem. */
    snprintf(args, sizeof args, "render --volume %s --size 96x96 --tf shepp-logan --out %s", vol,
             png);
    REQUIRE(pp5_test_run_cli(args, NULL, NULL) == 0);
    CHECK_EQ(lit_pixels(png), 0);
    /* No --tf: the histogram's choice, printed and saved. */
    snprintf(args, sizeof args, "render --volume %s --size 96x96 --out %s --tf-out %s", vol, png,
             tfo);
    REQUIRE(pp5_test_run_cli(args, out, NULL) == 0);
    char *text = pp5_test_read_file(out);
    CHECK(text && strstr(text, "transfer function: automatic") && strstr(text, "contour "));
    free(text);
    int lit = lit_pixels(png);
    CHECK_MSG(lit > 96 * 96 / 10, "%d of %d pixels lit", lit, 96 * 96);
    /* The saved function read back gives the same picture. */
    snprintf(args, sizeof args, "render --volume %s --size 96x96 --tf %s --out %s", vol, tfo, png2);
    REQUIRE(pp5_test_run_cli(args, NULL, NULL) == 0);
    image8_t ia, ib;
    REQUIRE(png_read(png, &ia, 3) == PP5_OK && png_read(png2, &ib, 3) == PP5_OK);
    CHECK(memcmp(ia.pixels, ib.pixels, (size_t)96 * 96 * 3) == 0);
    image8_free(&ia);
    image8_free(&ib);
    /* `pp5 volume info` shows the histogram and the same choice. */
    snprintf(args, sizeof args, "volume info %s", vol);
    REQUIRE(pp5_test_run_cli(args, out, NULL) == 0);
    text = pp5_test_read_file(out);
    CHECK(text && strstr(text, "background:") && strstr(text, "foreground:") &&
          strstr(text, "pp5-tf 1"));
    free(text);
}
