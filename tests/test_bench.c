/* test_bench.c: the renderer benchmark's statistics (emu/cli/bench_render.c):
 * the median, the per-round ratio of two alternated settings, and the
 * alternated rounds themselves on a small phantom. */
#include <math.h>
#include <string.h>

#include "emu/cli/bench_render.h"
#include "harness.h"
#include "render/volume.h"

TEST(bench_median_of_odd_even_and_empty)
{
    CHECK_NEAR(bench_median((const double[]){7, 1, 5}, 3), 5.0, 0.0);
    /* even counts take the upper middle value */
    CHECK_NEAR(bench_median((const double[]){4, 1, 3, 2}, 4), 3.0, 0.0);
    CHECK_NEAR(bench_median((const double[]){2.5}, 1), 2.5, 0.0);
    CHECK_NEAR(bench_median(NULL, 0), 0.0, 0.0);
    double x[3] = {3, 2, 1};
    bench_median(x, 3);
    CHECK(x[0] == 3 && x[1] == 2 && x[2] == 1);   /* the input is left as it was */
}

/* A burst that slows one round of both settings leaves each round's ratio,
 * and so the median, where it was; the ratio of the two medians of frames
 * run in blocks would not see the burst on both sides. */
TEST(bench_paired_ratio_takes_each_round_by_itself)
{
    bench_frames_t a, b;
    memset(&a, 0, sizeof a);
    memset(&b, 0, sizeof b);
    a.reps = b.reps = 5;
    const double ta[5] = {10, 10, 30, 10, 10}, tb[5] = {5, 5, 15, 5, 5};
    memcpy(a.t, ta, sizeof ta);
    memcpy(b.t, tb, sizeof tb);
    double lo, hi;
    CHECK_NEAR(bench_paired_ratio(&a, &b, &lo, &hi), 2.0, 1e-12);
    CHECK_NEAR(lo, 2.0, 1e-12);
    CHECK_NEAR(hi, 2.0, 1e-12);
    /* ratios 2, 5, 3: median 3, range 2-5 */
    const double tc[3] = {10, 20, 30}, td[3] = {5, 4, 10};
    a.reps = b.reps = 3;
    memcpy(a.t, tc, sizeof tc);
    memcpy(b.t, td, sizeof td);
    CHECK_NEAR(bench_paired_ratio(&a, &b, &lo, &hi), 3.0, 1e-12);
    CHECK_NEAR(lo, 2.0, 1e-12);
    CHECK_NEAR(hi, 5.0, 1e-12);
}

TEST(bench_alternating_fills_every_setting_and_caps_the_rounds)
{
    volume_t v;
    REQUIRE(phantom_make("sphere-shell", 24, 24, 24, &v) == PP5_OK);
    classify_tf_t tf;
    REQUIRE(classify_preset("sphere-shell", &tf) == PP5_OK);
    shade_params_t sh;
    shade_defaults(&sh);
    native_renderer_t r;
    REQUIRE(native_renderer_init(&r, &v, &tf, &sh, 1) == PP5_OK);
    bench_frames_t f[2];
    memset(f, 0, sizeof f);
    for (int k = 0; k < 2; k++) {
        render_settings_defaults(&f[k].s);
        f[k].s.width = f[k].s.height = 32;
        f[k].s.gaze_x = f[k].s.gaze_y = 15.5;
        f[k].s.mode = k ? RENDER_MODE_GAZE : RENDER_MODE_FULL;
    }
    REQUIRE_MSG(bench_render_alternating(&r, f, 2, BENCH_MAX_REPS + 4) == PP5_OK, "%s",
                pp5_error_text());
    for (int k = 0; k < 2; k++) {
        CHECK_EQ(f[k].reps, BENCH_MAX_REPS);
        bool positive = true;
        for (int i = 0; i < f[k].reps; i++)
            positive = positive && f[k].t[i] > 0.0;
        CHECK(positive);
        CHECK_NEAR(f[k].ms, bench_median(f[k].t, f[k].reps), 0.0);
        CHECK(f[k].stats.rays > 0);
    }
    /* each setting's counts are its own: the gaze frame casts fewer rays */
    CHECK(f[1].stats.rays < f[0].stats.rays);
    native_renderer_free(&r);
    volume_free(&v);
}
