/* test_replay_machine.c: the emulated machine as the replay's frame-cost
 * source (firmware/host/replay_machine.c): frames cost what the firmware
 * session says, the sweet spot follows the gaze, and bad options are refused. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "tracker/angles.h"
#include "tracker/replay.h"

static const replay_cost_source_t *machine_source(void)
{
    const replay_cost_source_t *cs = replay_find_cost_source("machine");
    REQUIRE_MSG(cs != NULL, "the firmware registers the 'machine' frame-cost source");
    return cs;
}

TEST(replay_machine_frames_come_from_the_emulator)
{
    const replay_cost_source_t *cs = machine_source();
    gaze_geometry_t display;
    angles_paper_geometry(&display);
    void *ctx = NULL;
    REQUIRE_MSG(cs->open("size=48x48", &display, &ctx) == PP5_OK, "%s", pp5_error_text());
    replay_frame_cost_t centre = {.want_image = true}, corner = {.want_image = false};
    REQUIRE(cs->cost(ctx, 0.5 * display.width_px, 0.5 * display.height_px, &centre) == PP5_OK);
    /* The image belongs to the source and lasts until its next call. */
    CHECK(centre.image != NULL && centre.image->width == 48 && centre.image->height == 48);
    REQUIRE(cs->cost(ctx, 0, 0, &corner) == PP5_OK);
    CHECK(centre.frame_s > 0 && isfinite(centre.frame_s));
    CHECK(corner.frame_s > 0 && isfinite(corner.frame_s));
    CHECK(centre.rays > 0 && centre.ring_bytes > 0);
    /* A 48-pixel image spans 37 degrees: a sweet spot in the middle covers far
     * more of it at full resolution than one in the corner, so it casts more
     * rays (the count comes from the emulated GPs, not from this test). */
    CHECK_MSG(centre.rays > corner.rays, "centre %llu rays, corner %llu",
              (unsigned long long)centre.rays, (unsigned long long)corner.rays);
    CHECK(corner.image == NULL);
    cs->close(ctx);
}

TEST(replay_machine_rejects_bad_options)
{
    const replay_cost_source_t *cs = machine_source();
    gaze_geometry_t display;
    angles_paper_geometry(&display);
    void *ctx = NULL;
    CHECK(cs->open("size=0x10", &display, &ctx) == PP5_E_CONFIG);
    CHECK(cs->open("volume=teapot", &display, &ctx) == PP5_E_CONFIG);
    CHECK(strstr(pp5_error_text(), "volume=teapot") != NULL);
    CHECK(cs->open("nonsense", &display, &ctx) == PP5_E_CONFIG);
    CHECK(cs->open("preset=no-such-preset", &display, &ctx) != PP5_OK);
}

TEST(replay_machine_takes_machine_settings)
{
    /* set=PARAM=VALUE reaches the machine: the GPs at half their clock make
     * a slower frame than the default; a setting the table refuses is an
     * error naming it. */
    const replay_cost_source_t *cs = machine_source();
    gaze_geometry_t display;
    angles_paper_geometry(&display);
    double frame[2];
    for (int k = 0; k < 2; k++) {
        void *ctx = NULL;
        REQUIRE_MSG(cs->open(k ? "size=48x48,set=gp.clock_hz=20e6" : "size=48x48", &display,
                             &ctx) == PP5_OK, "%s", pp5_error_text());
        replay_frame_cost_t c = {.want_image = false};
        REQUIRE(cs->cost(ctx, 0.5 * display.width_px, 0.5 * display.height_px, &c) == PP5_OK);
        frame[k] = c.frame_s;
        cs->close(ctx);
    }
    CHECK_MSG(frame[1] > frame[0], "20 MHz GPs %g s, 40 MHz %g s", frame[1], frame[0]);
    void *ctx = NULL;
    CHECK(cs->open("size=48x48,set=gp.count=99", &display, &ctx) == PP5_E_CONFIG);
    CHECK(strstr(pp5_error_text(), "gp.count") != NULL);
    CHECK(cs->open("size=48x48,set=no.such.param=1", &display, &ctx) != PP5_OK);
    CHECK(cs->open("size=48x48,set=gp.count", &display, &ctx) == PP5_E_CONFIG);
}
