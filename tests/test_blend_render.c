/* test_blend_render.c: MIP, DEMIP and MIDA frames through the native
 * renderer: DEMIP reduces to MIP, the occluder cases of the two readings of
 * eq. (1) worked out by hand, thread-count independence, the legend, and the
 * `pp5 render --blend` / `pp5 reproduce demip` command lines. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "harness.h"
#include "render/blend_trace.h"
#include "render/renderer_native.h"

static void renderer_for(const volume_t *v, int threads, native_renderer_t *r)
{
    classify_tf_t tf;
    REQUIRE(classify_preset("sphere-shell", &tf) == PP5_OK);
    shade_params_t sh;
    shade_defaults(&sh);
    REQUIRE(native_renderer_init(r, v, &tf, &sh, threads) == PP5_OK);
    REQUIRE(native_renderer_build_scalar(r, v, SCALAR_PYRAMID_MAX) == PP5_OK);
}

static void frame(native_renderer_t *r, const render_settings_t *s, image8_t *img,
                  render_stats_t *st)
{
    REQUIRE_MSG(native_renderer_frame(r, s, img, st) == PP5_OK, "frame: %s", pp5_error_text());
}

static bool same_image(const image8_t *a, const image8_t *b)
{
    return a->width == b->width && a->height == b->height &&
           memcmp(a->pixels, b->pixels, (size_t)a->width * a->height * 3) == 0;
}

static void settings_for(render_settings_t *s, int w, int h, render_mode_t mode)
{
    render_settings_defaults(s);
    s->width = w;
    s->height = h;
    s->mode = mode;
    s->gaze_x = 0.4 * w;
    s->gaze_y = 0.55 * h;
    s->view.rot_y_deg = 30.0f;
    s->view.rot_x_deg = -15.0f;
}

TEST(blend_demip_with_dw0_sw0_is_mip_byte_for_byte)
{
    volume_t v;
    REQUIRE(phantom_make("shepp-logan", 48, 44, 30, &v) == PP5_OK);
    native_renderer_t r;
    renderer_for(&v, 2, &r);
    for (int m = 0; m < 2; m++) {
        render_settings_t s;
        settings_for(&s, 120, 90, m ? RENDER_MODE_GAZE : RENDER_MODE_FULL);
        s.blend.mode = BLEND_MIP;
        image8_t mip, demip;
        render_stats_t st;
        frame(&r, &s, &mip, &st);
        s.blend.mode = BLEND_DEMIP;
        for (int variant = 0; variant < 4; variant++) {
            s.blend.depth_weight = 0.0f;
            s.blend.sphere_weight = 0.0f;
            s.blend.reading = variant & 1 ? DEMIP_READING_B : DEMIP_READING_A;
            s.blend.depth = variant & 2 ? DEMIP_DEPTH_ENTRY_PLUS_LENGTH : DEMIP_DEPTH_EXACT;
            frame(&r, &s, &demip, &st);
            CHECK_MSG(same_image(&mip, &demip), "mode %d variant %d differs from MIP", m,
                      variant);
            image8_free(&demip);
        }
        /* With the paper's dw the images differ: the check above can fail. */
        s.blend.depth_weight = 0.15f;
        s.blend.reading = DEMIP_READING_A;
        frame(&r, &s, &demip, &st);
        CHECK(!same_image(&mip, &demip));
        image8_free(&demip);
        size_t lit = 0;
        for (size_t i = 0; i < (size_t)mip.width * mip.height * 3; i++)
            lit += mip.pixels[i] > 0;
        CHECK(lit > (size_t)mip.width * mip.height);
        image8_free(&mip);
    }
    native_renderer_free(&r);
    volume_free(&v);
}

/* 32 x 32 x 48 voxels: a bright block (value 80) at z 30..38 and, if asked,
 * an occluder slab of value `occluder` at z 10..13, both over x, y 8..23. */
static void occluder_volume(float occluder, volume_t *v)
{
    REQUIRE(volume_alloc(v, 32, 32, 48) == PP5_OK);
    for (int z = 0; z < 48; z++)
        for (int y = 8; y < 24; y++)
            for (int x = 8; x < 24; x++) {
                float val = z >= 30 && z <= 38 ? 80.0f : (z >= 10 && z <= 13 ? occluder : 0.0f);
                v->data[((size_t)z * 32 + y) * 32 + x] = val;
            }
    volume_update_stats(v);
}

/* The centre ray of a 64x64 view along +z (window 0..100: materials are
 * value / 100), traced by the reference, and the frame's centre pixel. */
static void centre_ray(float occluder, demip_reading_t reading, blend_ray_info_t *info,
                       int *pixel)
{
    volume_t v;
    occluder_volume(occluder, &v);
    native_renderer_t r;
    renderer_for(&v, 1, &r);
    render_settings_t s;
    render_settings_defaults(&s);
    s.width = s.height = 64;
    s.mode = RENDER_MODE_FULL;
    s.blend.mode = BLEND_DEMIP;
    s.blend.window_centre = 50.0f;
    s.blend.window_width = 100.0f;
    s.blend.tolerance = 0.15f;
    s.blend.sphere_weight = 0.0f;
    s.blend.reading = reading;
    camera_t cam;
    camera_setup(&cam, &s.view, &r.mip, 64, 64);
    blend_ctx_t c;
    blend_ctx_init(&c, &r.scalar, &cam, &s.view, &s.blend);
    blend_trace_reference_info(&c, 32.0f, 32.0f, 0, info);
    image8_t img;
    render_stats_t st;
    frame(&r, &s, &img, &st);
    *pixel = img.pixels[((size_t)32 * 64 + 32) * 3];
    image8_free(&img);
    native_renderer_free(&r);
    volume_free(&v);
}

/* The sample positions along the centre ray fall on z = k (the box runs
 * z 0..47 and the ray enters at z = 0), up to rounding, so exact depth =
 * z / 47:
 *   MIP: m_max = 0.8, first at z = 30;
 *   with the occluder (material 0.72 >= 0.8 - 0.15) ray 2 stops at z = 10:
 *     eq. (1) = 0.8 * 0.85 + 0.3 * (1 - 10/47) = 0.91617;
 *   without it ray 2 stops at the block, z = 30 (or a rounding below it,
 *   on the block's rising edge, with the maximum one sample later):
 *     A: 0.68 + 0.3 * (1 - 30/47) = 0.78851;   B: MIP, 0.8 (no gap). */
TEST(blend_occluder_of_the_same_material_gives_its_depth_under_both_readings)
{
    const double with_occluder = 0.8 * 0.85 + 0.3 * (1.0 - 10.0 / 47.0);
    for (int rd = 0; rd < 2; rd++) {
        blend_ray_info_t info;
        int px;
        centre_ray(72.0f, rd ? DEMIP_READING_B : DEMIP_READING_A, &info, &px);
        CHECK_NEAR(info.m_max, 0.8, 1e-5);
        float z = info.geom.o[2] + info.t_hit * info.geom.d[2];
        CHECK_NEAR(z, 10.0, 1e-3);
        CHECK(info.k_stop < info.k_max);
        CHECK(rd == 0 || info.occluded);
        CHECK_NEAR(info.rgb[0], with_occluder, 1e-4);
        CHECK_NEAR(px, with_occluder * 255.0, 1.0);
    }
}

TEST(blend_without_occluder_reading_b_is_mip_and_a_is_not)
{
    blend_ray_info_t a, b;
    int pa, pb;
    centre_ray(0.0f, DEMIP_READING_A, &a, &pa);
    centre_ray(0.0f, DEMIP_READING_B, &b, &pb);
    CHECK(!b.occluded);
    CHECK(b.rgb[0] == b.m_max);
    CHECK_NEAR(b.rgb[0], 0.8, 1e-5);
    CHECK_NEAR(a.rgb[0], 0.68 + 0.3 * (1.0 - 30.0 / 47.0), 1e-4);
    CHECK_EQ(pb, 204);            /* round(0.8 * 255) */
    /* An occluder outside the tolerance (material 0.5 < 0.65) is ignored. */
    blend_ray_info_t c;
    int pc;
    centre_ray(50.0f, DEMIP_READING_B, &c, &pc);
    CHECK(!c.occluded);
    CHECK_EQ(pc, 204);
    /* Whole frames: reading B without the occluder equals MIP everywhere. */
    volume_t v;
    occluder_volume(0.0f, &v);
    native_renderer_t r;
    renderer_for(&v, 2, &r);
    render_settings_t s;
    settings_for(&s, 80, 80, RENDER_MODE_GAZE);
    s.blend.mode = BLEND_MIP;
    s.blend.window_centre = 50.0f;
    s.blend.window_width = 100.0f;
    image8_t mip, demip;
    render_stats_t st;
    frame(&r, &s, &mip, &st);
    s.blend.mode = BLEND_DEMIP;
    s.blend.sphere_weight = 0.0f;
    s.blend.reading = DEMIP_READING_B;     /* default tolerance 0.1: rising edges */
    frame(&r, &s, &demip, &st);
    CHECK(same_image(&mip, &demip));
    image8_free(&mip);
    image8_free(&demip);
    native_renderer_free(&r);
    volume_free(&v);
}

static void blend_threads(int threads, blend_mode_t mode, projection_t proj, image8_t *img,
                          render_stats_t *st)
{
    volume_t v;
    REQUIRE(phantom_make("shepp-logan", 44, 40, 26, &v) == PP5_OK);
    native_renderer_t r;
    renderer_for(&v, threads, &r);
    render_settings_t s;
    settings_for(&s, 131, 97, RENDER_MODE_GAZE);
    s.threads = threads;
    s.view.projection = proj;
    s.blend.mode = mode;
    s.blend.reading = DEMIP_READING_B;
    frame(&r, &s, img, st);
    native_renderer_free(&r);
    volume_free(&v);
}

TEST(blend_images_and_counts_identical_for_1_2_3_threads)
{
    const blend_mode_t modes[3] = {BLEND_MIP, BLEND_DEMIP, BLEND_MIDA};
    for (int p = 0; p < 2; p++)
        for (int m = 0; m < 3; m++) {
            projection_t proj = p ? PROJECTION_PERSPECTIVE : PROJECTION_PARALLEL;
            image8_t a, b, c;
            render_stats_t sa, sb, sc;
            blend_threads(1, modes[m], proj, &a, &sa);
            blend_threads(2, modes[m], proj, &b, &sb);
            blend_threads(3, modes[m], proj, &c, &sc);
            CHECK(same_image(&a, &b) && same_image(&a, &c));
            CHECK(sa.rays == sb.rays && sa.rays == sc.rays);
            CHECK(sa.samples == sb.samples && sa.samples == sc.samples);
            CHECK(sa.samples_skipped == sc.samples_skipped &&
                  sa.samples_retraced == sc.samples_retraced);
            image8_free(&a);
            image8_free(&b);
            image8_free(&c);
        }
}

TEST(blend_sphere_legend_only_with_sphere_weight_and_only_in_its_corner)
{
    volume_t v;
    REQUIRE(phantom_make("sphere-shell", 40, 40, 40, &v) == PP5_OK);
    native_renderer_t r;
    renderer_for(&v, 2, &r);
    render_settings_t s;
    settings_for(&s, 160, 128, RENDER_MODE_FULL);
    s.blend.mode = BLEND_DEMIP;
    image8_t with, without;
    render_stats_t st;
    frame(&r, &s, &with, &st);
    s.blend.legend = false;
    frame(&r, &s, &without, &st);
    /* Legend discs of radius side/16 = 8 in the lower left quarter. */
    long inside = 0, outside = 0;
    for (int y = 0; y < 128; y++)
        for (int x = 0; x < 160; x++) {
            size_t i = ((size_t)y * 160 + x) * 3;
            bool diff = memcmp(with.pixels + i, without.pixels + i, 3) != 0;
            if (x < 80 && y >= 64)
                inside += diff;
            else
                outside += diff;
        }
    CHECK(inside > 100);
    CHECK_EQ(outside, 0);
    /* Red front disc: its centre pixel is red-dominated. */
    int cx = 8 + 4 + 1, cy = 128 - 9 - 8 - 4 - 2;
    const uint8_t *px = with.pixels + ((size_t)cy * 160 + cx) * 3;
    CHECK(px[0] > 150 && px[2] < 60);
    image8_free(&with);
    image8_free(&without);
    native_renderer_free(&r);
    volume_free(&v);
}

TEST(blend_frame_without_value_pyramid_is_refused)
{
    volume_t v;
    REQUIRE(phantom_make("sphere-shell", 24, 24, 24, &v) == PP5_OK);
    classify_tf_t tf;
    REQUIRE(classify_preset("sphere-shell", &tf) == PP5_OK);
    shade_params_t sh;
    shade_defaults(&sh);
    native_renderer_t r;
    REQUIRE(native_renderer_init(&r, &v, &tf, &sh, 1) == PP5_OK);
    render_settings_t s;
    settings_for(&s, 32, 32, RENDER_MODE_FULL);
    s.blend.mode = BLEND_MIP;
    image8_t img = {0};
    render_stats_t st;
    CHECK(native_renderer_frame(&r, &s, &img, &st) == PP5_E_CONFIG);
    CHECK(strstr(pp5_error_text(), "value pyramid") != NULL);
    s.blend.mode = BLEND_COMPOSITE;
    s.blend.tolerance = NAN;
    CHECK(native_renderer_frame(&r, &s, &img, &st) == PP5_E_RANGE);
    native_renderer_free(&r);
    volume_free(&v);
}

TEST(blend_cli_renders_demip_full_and_gaze)
{
    const char *dir = pp5_test_outdir();
    char args[1024], out[512], png[512];
    const char *modes[2] = {"full", "gaze"};
    for (int m = 0; m < 2; m++) {
        snprintf(png, sizeof png, "%s/d_%s.png", dir, modes[m]);
        snprintf(out, sizeof out, "%s/out_%s.txt", dir, modes[m]);
        snprintf(args, sizeof args, "render --phantom sphere-shell --size 96x96 --blend demip "
                 "--sphere-weight 0.3 --mode %s --out %s --report %s/r.json", modes[m], png, dir);
        CHECK_EQ(pp5_test_run_cli(args, out, NULL), 0);
        image8_t img;
        REQUIRE(png_read(png, &img, 3) == PP5_OK);
        CHECK(img.width == 96 && img.height == 96);
        image8_free(&img);
        char *text = pp5_test_read_file(out);
        REQUIRE(text);
        CHECK(strstr(text, "blend demip: max value pyramid") != NULL);
        free(text);
    }
    char json[600];
    snprintf(json, sizeof json, "%s/r.json", dir);
    char *report = pp5_test_read_file(json);
    REQUIRE(report);
    CHECK(strstr(report, "\"blend\": \"demip\"") != NULL);
    CHECK(strstr(report, "\"sphere_weight\": 0.3") != NULL);
    free(report);
}

TEST(blend_cli_rejects_bad_values_naming_the_option)
{
    const char *dir = pp5_test_outdir();
    const char *cases[][2] = {
        {"--blend maximum", "--blend"},
        {"--blend mip --window 5,0", "--window"},
        {"--blend demip --tolerance nan", "--tolerance"},
        {"--blend demip --sphere-rotate 1,2", "--sphere-rotate"},
        {"--blend demip --sphere-map rainbow", "--sphere-map"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char args[512], err[512];
        snprintf(err, sizeof err, "%s/err%zu.txt", dir, i);
        snprintf(args, sizeof args, "render --phantom sphere-shell --size 32x32 %s --out %s/x.png",
                 cases[i][0], dir);
        CHECK_MSG(pp5_test_run_cli(args, NULL, err) == 2, "%s: exit code", cases[i][0]);
        char *text = pp5_test_read_file(err);
        REQUIRE(text);
        CHECK_MSG(strstr(text, cases[i][1]) != NULL, "%s: message '%s'", cases[i][0], text);
        free(text);
        char png[600];
        snprintf(png, sizeof png, "%s/x.png", dir);
        struct stat sb;
        CHECK(stat(png, &sb) != 0);
    }
}

TEST(blend_reproduce_demip_prints_the_table_and_writes_the_images)
{
    const char *dir = pp5_test_outdir();
    char args[512], out[512];
    snprintf(out, sizeof out, "%s/stdout.txt", dir);
    snprintf(args, sizeof args, "reproduce demip --size 48 --machine-size 16 --repeats 1 "
             "--datasets sphere-shell --out-dir %s", dir);
    CHECK_EQ(pp5_test_run_cli(args, out, NULL), 0);
    char *text = pp5_test_read_file(out);
    REQUIRE(text);
    const char *expect[] = {"Table 1", "not public", "DEMIP/MIP", "DVR/DEMIP", "MIDA/DEMIP",
                            "1.12-1.40 (1.21)", "machine full", "eps 0.40", "box",
                            /* the machine's columns: the blends' images equal render/'s,
                             * object slabs refuse them, the divisions compared */
                            "MIP         image-bands", "identical", "refused",
                            "best division per blend", "DEMIP's second ray"};
    for (size_t i = 0; i < sizeof expect / sizeof expect[0]; i++)
        CHECK_MSG(strstr(text, expect[i]) != NULL, "no '%s' in the output", expect[i]);
    /* MIP, DEMIP and MIDA identical to render/ in image-bands and resident,
     * full and gaze: 12 cells; no cell failed */
    int identical = 0;
    for (const char *q = strstr(text, "identical"); q; q = strstr(q + 1, "identical"))
        identical++;
    CHECK_EQ(identical, 12);
    CHECK(strstr(text, "failed") == NULL);
    free(text);
    const char *images[] = {"demip_sphere-shell.png", "demip_sphere-shell_eps.png",
                            "demip_sphere-shell_pyramid.png"};
    for (size_t i = 0; i < 3; i++) {
        char path[700];
        snprintf(path, sizeof path, "%s/%s", dir, images[i]);
        image8_t img;
        CHECK_MSG(png_read(path, &img, 3) == PP5_OK, "%s unreadable", path);
        image8_free(&img);
    }
    snprintf(args, sizeof args, "reproduce demip --size 5 --out-dir %s", dir);
    CHECK_EQ(pp5_test_run_cli(args, NULL, NULL), 2);
}
