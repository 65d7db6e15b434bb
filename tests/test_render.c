/* test_render.c: thread-count determinism, the quality formulas, and the
 * `pp5 render` / `pp5 reproduce` command lines (good and bad input). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "harness.h"
#include "render/quality.h"
#include "render/renderer_native.h"

static void render_with_threads(int threads, render_mode_t mode, projection_t proj,
                                shade_case_t lighting, image8_t *img, render_stats_t *st)
{
    volume_t v;
    REQUIRE(phantom_make("shepp-logan", 44, 40, 26, &v) == PP5_OK);
    classify_tf_t tf;
    REQUIRE(classify_preset("shepp-logan", &tf) == PP5_OK);
    shade_params_t sh;
    shade_defaults(&sh);
    sh.lighting = lighting;
    sh.specular = 0.4f;
    native_renderer_t r;
    REQUIRE(native_renderer_init(&r, &v, &tf, &sh, threads) == PP5_OK);
    render_settings_t s;
    render_settings_defaults(&s);
    s.width = 131;
    s.height = 97;
    s.gaze_x = 50;
    s.gaze_y = 40;
    s.mode = mode;
    s.threads = threads;
    s.view.projection = proj;
    s.view.rot_y_deg = 30;
    s.view.rot_x_deg = -15;
    REQUIRE(native_renderer_frame(&r, &s, img, st) == PP5_OK);
    native_renderer_free(&r);
    volume_free(&v);
}

static void check_thread_counts(render_mode_t mode, projection_t proj, shade_case_t lighting)
{
    image8_t a, b, c;
    render_stats_t sa, sb, sc;
    render_with_threads(1, mode, proj, lighting, &a, &sa);
    render_with_threads(2, mode, proj, lighting, &b, &sb);
    render_with_threads(3, mode, proj, lighting, &c, &sc);
    size_t n = (size_t)a.width * a.height * 3;
    CHECK(memcmp(a.pixels, b.pixels, n) == 0);
    CHECK(memcmp(a.pixels, c.pixels, n) == 0);
    CHECK_EQ(sa.rays, sb.rays);
    CHECK_EQ(sa.rays, sc.rays);
    CHECK_EQ(sa.samples, sb.samples);
    CHECK_EQ(sa.samples, sc.samples);
    CHECK_EQ(sa.samples_skipped, sc.samples_skipped);
    size_t lit = 0;
    for (size_t i = 0; i < n; i++)
        lit += a.pixels[i] != 0;
    CHECK(lit > n / 10);
    image8_free(&a);
    image8_free(&b);
    image8_free(&c);
}

TEST(render_threads_identical_gaze_parallel)
{
    check_thread_counts(RENDER_MODE_GAZE, PROJECTION_PARALLEL, SHADE_DIFFUSE_FIXED_LIGHT);
}

TEST(render_threads_identical_full_perspective_specular)
{
    check_thread_counts(RENDER_MODE_FULL, PROJECTION_PERSPECTIVE, SHADE_SPECULAR_FIXED_LIGHT);
}

TEST(render_threads_identical_gaze_moving_object)
{
    check_thread_counts(RENDER_MODE_GAZE, PROJECTION_PARALLEL, SHADE_MOVING_OBJECT);
}

TEST(render_quality_formulas_by_hand)
{
    image8_t a, b;
    REQUIRE(image8_alloc(&a, 3, 1, 1) == PP5_OK);
    REQUIRE(image8_alloc(&b, 3, 1, 1) == PP5_OK);
    memset(a.pixels, 100, 3);
    memset(b.pixels, 100, 3);
    gaze_display_t d;
    gaze_display_defaults(&d);
    gaze_model_t g;
    REQUIRE(gaze_model_init(&g, &d, 3, 1) == PP5_OK);
    quality_t q;
    REQUIRE(quality_compare(&a, &b, &g, 0, 0, &q) == PP5_OK);
    CHECK(isinf(q.psnr_db));
    /* One pixel off by 10: MSE = 100 / 3, PSNR = 10 log10(65025 / (100 / 3)). */
    a.pixels[0] = 110;
    REQUIRE(quality_compare(&a, &b, &g, 0, 0, &q) == PP5_OK);
    CHECK_NEAR(q.mse, 100.0 / 3.0, 1e-9);
    CHECK_NEAR(q.psnr_db, 10.0 * log10(65025.0 / (100.0 / 3.0)), 1e-9);
    CHECK_NEAR(q.max_abs, 10.0, 0);
    /* The 13.38" image line over 3 pixels: 4.46" per pixel, so pixel 1 is at
     * atan(4.46 / 20) = 12.6 degrees, beyond the 10-degree periphery: weight
     * sqrt(1/16) = 1/4 for pixels 1 and 2, 1 at the gaze pixel 0:
     * AW-MSE = 1 * 100 / (1 + 2/4). */
    CHECK_NEAR(q.aw_mse, 100.0 / 1.5, 1e-9);
    image8_free(&a);
    image8_free(&b);
}

static long file_size(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0 ? (long)sb.st_size : -1;
}

TEST(render_cli_writes_image_figures_and_report)
{
    const char *dir = pp5_test_outdir();
    char args[2048], path[1024], out[1024];
    snprintf(args, sizeof args, "render --phantom sphere-shell --size 96x80 --mode gaze "
             "--gaze 30,20 --out %s/g.png --report %s/g.json --fig5 %s/f5.png "
             "--mip-levels-out %s/lv --compare --progressive 2 --threads 2",
             dir, dir, dir, dir);
    snprintf(out, sizeof out, "%s/stdout.txt", dir);
    CHECK_EQ(pp5_test_run_cli(args, out, NULL), 0);
    snprintf(path, sizeof path, "%s/g.png", dir);
    image8_t img;
    REQUIRE(png_read(path, &img, 3) == PP5_OK);
    CHECK_EQ(img.width, 96);
    CHECK_EQ(img.height, 80);
    image8_free(&img);
    snprintf(path, sizeof path, "%s/f5.png", dir);
    CHECK(file_size(path) > 1000);
    for (int l = 0; l < 3; l++) {
        snprintf(path, sizeof path, "%s/lv%d.png", dir, l);
        CHECK(file_size(path) > 0);
    }
    snprintf(path, sizeof path, "%s/g.json", dir);
    char *json = pp5_test_read_file(path);
    REQUIRE(json);
    CHECK(strstr(json, "\"rays\"") != NULL);
    CHECK(strstr(json, "\"samples_3d\"") != NULL);
    CHECK(strstr(json, "\"psnr_db\"") != NULL);
    CHECK(strstr(json, "\"frames_to_full_resolution\"") != NULL);
    free(json);
}

TEST(render_cli_rejects_bad_input)
{
    CHECK(pp5_test_run_cli("render --size 0x5", NULL, NULL) != 0);
    CHECK(pp5_test_run_cli("render --gaze nan,3", NULL, NULL) != 0);
    CHECK(pp5_test_run_cli("render --phantom no-such-thing", NULL, NULL) != 0);
    CHECK(pp5_test_run_cli("render --volume /nonexistent/v_8x8x8_u8.raw", NULL, NULL) != 0);
    CHECK(pp5_test_run_cli("render --mode sideways", NULL, NULL) != 0);
    CHECK(pp5_test_run_cli("render --tf nope", NULL, NULL) != 0);
    CHECK(pp5_test_run_cli("render --raw-dims 3x3", NULL, NULL) != 0);
    CHECK_EQ(pp5_test_run_cli("render --help", NULL, NULL), 0);
}

static bool has_dataset_prefix(const char *line)
{
    return strncmp(line, "mrbrain: ", 9) == 0 || strncmp(line, "cthead: ", 8) == 0;
}

/* With PP5_SHARED_DATA pointing at an empty folder, table1 must really
 * render the phantom: the volume it reports is the phantom by the loaded
 * volume's own name and size (not a text table1 prints on its own), the note
 * names the file missing under that folder, and no data set is reported as
 * present. */
TEST(render_reproduce_table1_falls_back_to_phantom)
{
    const char *dir = pp5_test_outdir();
    char out[1024], empty[1024], args[4200];
    snprintf(out, sizeof out, "%s/table1.txt", dir);
    snprintf(empty, sizeof empty, "%s/no-data", dir);
    REQUIRE(mkdir(empty, 0755) == 0);
    const char *old = getenv("PP5_SHARED_DATA");
    char *saved = old ? strdup(old) : NULL;
    setenv("PP5_SHARED_DATA", empty, 1);
    snprintf(args, sizeof args, "reproduce table1 --repeats 1 --threads 2");
    int rc = pp5_test_run_cli(args, out, NULL);
    if (saved) {
        setenv("PP5_SHARED_DATA", saved, 1);
        free(saved);
    } else {
        unsetenv("PP5_SHARED_DATA");
    }
    REQUIRE_MSG(rc == 0, "pp5 %s exited %d", args, rc);
    char *text = pp5_test_read_file(out);
    REQUIRE(text);

    /* The loaded volume's own description: phantom_make names a phantom
     * "phantom NAME NXxNYxNZ", and Shepp-Logan's default size is the paper's
     * MR scan, 256x256x109 (volume.h); brainsmall would be 128x128x84. */
    const char *want = "\nFALLBACK: phantom shepp-logan 256x256x109, 256x256x109,";
    CHECK_MSG(strstr(text, want) != NULL, "the volume line names the phantom: %s", want + 1);
    char missing[1200];
    snprintf(missing, sizeof missing, "%s/volumes/mrbrain_brainsmall/", empty);
    CHECK_MSG(strstr(text, missing) != NULL, "the note names the file missing under %s", empty);
    /* The later data sets only point back at the phantom's figures. */
    for (const char *l = strstr(text, "\n\n"); l; l = strstr(l + 1, "\n\n")) {
        const char *line = l + 2, *end = strchr(line, '\n');
        int len = end ? (int)(end - line) : (int)strlen(line);
        if (has_dataset_prefix(line))
            CHECK_MSG(memmem(line, (size_t)len, " absent: ", 9) != NULL,
                      "a data set is reported as present: %.*s", len, line);
    }

    free(text);
    CHECK(pp5_test_run_cli("reproduce no-such-scenario", NULL, NULL) != 0);
}
