/* test_pixel_identity.c: the renderer's row-wise fast paths (mip2d_row.h:
 * 2DLevel, texel marking, RenderPixel) against the straightforward per-pixel
 * reference code, byte for byte, over sizes, gazes (on and off the image),
 * sweet-spot scales and display settings; and whole frames against the
 * references applied to the renderer's own mip map. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "render/gaze2d.h"
#include "render/mip2d_row.h"
#include "render/renderer_native.h"

static uint32_t lcg_next(uint32_t *state)
{
    *state = *state * 1664525u + 1013904223u;
    return *state >> 8;
}

/* Display variants: the paper's defaults, a coarser periphery (4 levels),
 * an explicit sigma, and an image spanning the whole monitor. */
static void display_variant(int k, gaze_display_t *d)
{
    gaze_display_defaults(d);
    if (k == 1)
        d->periphery_rays_per_px = 1.0 / 64.0;
    if (k == 2) {
        d->sigma_deg = 1.3;
        d->full_res_diameter_deg = 7.0;
    }
    if (k == 3) {
        d->image_subtense_deg = 0.0;
        d->periphery_rays_per_px = 1.0 / 8.0;   /* non-integer edge level 1.5 */
    }
}

static const int sizes[][2] = {{1, 1}, {7, 5}, {64, 48}, {129, 257}, {512, 512}};
static const double gazes[][2] = {
    {-1.0, -1.0}, {0.5, 0.5}, {0.0, 0.0}, {31.5, 23.5}, {100.25, 40.75},
    {255.5, 255.5}, {300.0, 17.0}, {-400.0, 90.0}, {1e4, -3e3}, {511.0, 600.5}};
static const double scales[] = {1.0, 2.0, 3.7};

TEST(pixel_level_rows_match_reference)
{
    int compared = 0, mismatched = 0, annulus = 0;
    for (int k = 0; k < 4; k++) {
        gaze_display_t d;
        display_variant(k, &d);
        for (size_t si = 0; si < sizeof sizes / sizeof sizes[0]; si++) {
            int w = sizes[si][0], h = sizes[si][1];
            gaze_model_t g;
            REQUIRE(gaze_model_init(&g, &d, w, h) == PP5_OK);
            float *fast = malloc((size_t)w * sizeof(float));
            float *ref = malloc((size_t)w * sizeof(float));
            REQUIRE(fast && ref);
            for (size_t gi = 0; gi < sizeof gazes / sizeof gazes[0]; gi++)
                for (size_t ci = 0; ci < sizeof scales / sizeof scales[0]; ci++)
                    for (int y = 0; y < h; y += (h > 64 ? 3 : 1)) {
                        gaze_level_row(&g, y, w, gazes[gi][0], gazes[gi][1], scales[ci], fast);
                        gaze_level_row_reference(&g, y, w, gazes[gi][0], gazes[gi][1],
                                                 scales[ci], ref);
                        compared++;
                        if (memcmp(fast, ref, (size_t)w * sizeof(float)) != 0)
                            mismatched++;
                        for (int x = 0; x < w; x++)
                            annulus += ref[x] > 0.0f && ref[x] < g.level_edge;
                    }
            free(fast);
            free(ref);
        }
    }
    CHECK_EQ(mismatched, 0);
    CHECK(compared > 1000);
    /* The sweep must reach the Gaussian falloff, not only the flat spans. */
    CHECK(annulus > 10000);
}

/* Levels of one row: runs of values including integers, blends, values above
 * the top level and the renderer's own levels for a gaze. */
static void synthetic_levels(uint32_t *seed, const gaze_model_t *g, int y, int w, float *out)
{
    static const float palette[] = {0.0f, 0.0f, 0.25f, 1.0f, 0.5f, 1.5f, 2.0f, 2.0f,
                                    1.999f, 2.7f, 3.0f, 6.5f};
    if (lcg_next(seed) % 3 == 0) {
        gaze_level_row_reference(g, y, w, w * 0.4, y + 3.5, 1.0, out);
        return;
    }
    int x = 0;
    while (x < w) {
        float v = palette[lcg_next(seed) % (sizeof palette / sizeof palette[0])];
        int run = 1 + (int)(lcg_next(seed) % 9);
        for (int i = 0; i < run && x < w; i++)
            out[x++] = v;
    }
}

TEST(pixel_mark_runs_match_reference)
{
    uint32_t seed = 12345;
    int mismatched = 0, cases = 0;
    for (int levels = 1; levels <= 4; levels++)
        for (size_t si = 0; si < sizeof sizes / sizeof sizes[0]; si++) {
            int w = sizes[si][0], h = sizes[si][1];
            gaze_display_t d;
            gaze_display_defaults(&d);
            gaze_model_t g;
            REQUIRE(gaze_model_init(&g, &d, w, h) == PP5_OK);
            mip2d_t a, b;
            REQUIRE(mip2d_init(&a, w, h, levels) == PP5_OK);
            REQUIRE(mip2d_init(&b, w, h, levels) == PP5_OK);
            float *lv = malloc((size_t)w * sizeof(float));
            REQUIRE(lv);
            for (int y = 0; y < h; y++) {
                synthetic_levels(&seed, &g, y, w, lv);
                bool full_a = mip2d_mark_row(&a, y, lv, w);
                bool full_b = mip2d_mark_row_runs(&b, y, lv, w);
                if (full_a != full_b)
                    mismatched++;
            }
            for (int l = 0; l < levels; l++)
                if (memcmp(a.need[l], b.need[l], (size_t)a.w[l] * a.h[l]) != 0)
                    mismatched++;
            cases++;
            free(lv);
            mip2d_free(&a);
            mip2d_free(&b);
        }
    CHECK_EQ(mismatched, 0);
    CHECK_EQ(cases, 20);
}

TEST(pixel_render_rows_match_reference)
{
    uint32_t seed = 777;
    long mismatched_rows = 0, rows = 0;
    for (int levels = 1; levels <= 4; levels++)
        for (size_t si = 0; si < sizeof sizes / sizeof sizes[0]; si++) {
            int w = sizes[si][0], h = sizes[si][1];
            gaze_display_t d;
            gaze_display_defaults(&d);
            gaze_model_t g;
            REQUIRE(gaze_model_init(&g, &d, w, h) == PP5_OK);
            mip2d_t m;
            REQUIRE(mip2d_init(&m, w, h, levels) == PP5_OK);
            /* Every texel gets a finite colour, some outside [0, 1] and some
             * -0, so the clamps and rounding of render_to_u8 are exercised. */
            for (int l = 0; l < levels; l++)
                for (size_t i = 0; i < (size_t)m.w[l] * m.h[l] * 3; i++) {
                    uint32_t r = lcg_next(&seed);
                    m.rgb[l][i] = r % 17 == 0 ? -0.0f : (float)(r % 14001) / 10000.0f - 0.2f;
                }
            float *lv = malloc((size_t)w * sizeof(float));
            uint8_t *fast = malloc((size_t)w * 3);
            uint8_t *ref = malloc((size_t)w * 3);
            REQUIRE(lv && fast && ref);
            for (int y = 0; y < h; y++) {
                synthetic_levels(&seed, &g, y, w, lv);
                mip2d_render_row(&m, y, lv, w, fast);
                mip2d_render_row_reference(&m, y, lv, w, ref);
                rows++;
                if (memcmp(fast, ref, (size_t)w * 3) != 0)
                    mismatched_rows++;
            }
            free(lv);
            free(fast);
            free(ref);
            mip2d_free(&m);
        }
    CHECK_EQ(mismatched_rows, 0);
    CHECK(rows > 3000);
}

/* Renders frames (new views of one size in one renderer, so buffers are
 * reused, then a progressive sequence) and checks each against the
 * reference steps applied to the renderer's state: the levels map, the need
 * flags (re-marked from those levels), every needed texel cast, and the
 * image reconstructed per pixel; plus a fresh renderer for the same view
 * giving the same bytes and counts. */
static void check_frame(native_renderer_t *r, const volume_t *v, const classify_tf_t *tf,
                        const shade_params_t *sh, const render_settings_t *s,
                        const float *prev_best, int *bad)
{
    image8_t img;
    render_stats_t st;
    REQUIRE(native_renderer_frame(r, s, &img, &st) == PP5_OK);
    int w = s->width, h = s->height;
    const float *best = native_renderer_levels(r);
    float *lv = malloc((size_t)w * sizeof(float));
    uint8_t *row = malloc((size_t)w * 3);
    REQUIRE(lv && row);
    mip2d_t *m = &r->mip2d;
    mip2d_t fresh;
    REQUIRE(mip2d_init(&fresh, w, h, m->levels) == PP5_OK);
    for (int y = 0; y < h; y++) {
        if (s->mode == RENDER_MODE_GAZE) {
            double scale = s->progressive ? pow(s->progressive_growth, st.frame_index) : 1.0;
            gaze_level_row_reference(&r->gaze, y, w, s->gaze_x, s->gaze_y, scale, lv);
        } else {
            for (int x = 0; x < w; x++)
                lv[x] = 0.0f;
        }
        for (int x = 0; x < w; x++) {
            float expect = lv[x];
            if (prev_best && prev_best[(size_t)y * w + x] < expect)
                expect = prev_best[(size_t)y * w + x];
            if (memcmp(&expect, &best[(size_t)y * w + x], sizeof expect) != 0)
                (*bad)++;
        }
        mip2d_mark_row(&fresh, y, best + (size_t)y * w, w);
        mip2d_render_row_reference(m, y, best + (size_t)y * w, w, row);
        if (memcmp(row, img.pixels + (size_t)y * w * 3, (size_t)w * 3) != 0)
            (*bad)++;
    }
    for (int l = 0; l < m->levels; l++) {
        size_t n = (size_t)m->w[l] * m->h[l];
        if (memcmp(fresh.need[l], m->need[l], n) != 0)
            (*bad)++;
        for (size_t i = 0; i < n; i++)
            if (fresh.need[l][i] && !m->cast[l][i])
                (*bad)++;
    }
    if (!s->progressive) {
        native_renderer_t r2;
        REQUIRE(native_renderer_init(&r2, v, tf, sh, 1) == PP5_OK);
        image8_t img2;
        render_stats_t st2;
        REQUIRE(native_renderer_frame(&r2, s, &img2, &st2) == PP5_OK);
        if (memcmp(img.pixels, img2.pixels, (size_t)w * h * 3) != 0 || st.rays != st2.rays ||
            st.samples != st2.samples || st.samples_skipped != st2.samples_skipped)
            (*bad)++;
        image8_free(&img2);
        native_renderer_free(&r2);
    }
    mip2d_free(&fresh);
    free(lv);
    free(row);
    image8_free(&img);
}

TEST(pixel_frames_match_reference_steps)
{
    volume_t v;
    REQUIRE(phantom_make("shepp-logan", 40, 36, 24, &v) == PP5_OK);
    classify_tf_t tf;
    REQUIRE(classify_preset("shepp-logan", &tf) == PP5_OK);
    shade_params_t sh;
    shade_defaults(&sh);
    native_renderer_t r;
    REQUIRE(native_renderer_init(&r, &v, &tf, &sh, 2) == PP5_OK);
    render_settings_t s;
    render_settings_defaults(&s);
    s.width = 150;
    s.height = 110;
    s.view.rot_y_deg = 25;
    int bad = 0, frames = 0;
    /* New views of one size: centre, fractional, off-image gazes, full mode,
     * a coarser periphery; then back to the first settings. */
    const double g[][2] = {{74.5, 54.5}, {20.3, 90.8}, {-60, 30}, {400, -200}};
    for (int i = 0; i < 4; i++) {
        s.gaze_x = g[i][0];
        s.gaze_y = g[i][1];
        check_frame(&r, &v, &tf, &sh, &s, NULL, &bad);
        frames++;
    }
    s.mode = RENDER_MODE_FULL;
    check_frame(&r, &v, &tf, &sh, &s, NULL, &bad);
    s.mode = RENDER_MODE_GAZE;
    s.display.periphery_rays_per_px = 1.0 / 64.0;
    check_frame(&r, &v, &tf, &sh, &s, NULL, &bad);
    s.display.periphery_rays_per_px = 1.0 / 16.0;
    s.gaze_x = 74.5;
    s.gaze_y = 54.5;
    check_frame(&r, &v, &tf, &sh, &s, NULL, &bad);
    frames += 3;
    /* Progressive refinement: levels are the minimum over frames. */
    s.progressive = true;
    s.view.rot_y_deg = 35;   /* a new view: the first progressive frame starts afresh */
    s.gaze_x = 30.25;
    s.gaze_y = 70.5;
    float *prev = malloc((size_t)s.width * s.height * sizeof(float));
    REQUIRE(prev);
    for (int f = 0; f < 4; f++) {
        if (f > 0)
            memcpy(prev, native_renderer_levels(&r), (size_t)s.width * s.height * sizeof(float));
        check_frame(&r, &v, &tf, &sh, &s, f > 0 ? prev : NULL, &bad);
        frames++;
    }
    free(prev);
    CHECK_EQ(bad, 0);
    CHECK_EQ(frames, 11);
    native_renderer_free(&r);
    volume_free(&v);
}
