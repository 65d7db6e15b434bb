/* test_replay_live.c: `pp5 replay --live DEVICE` end to end against an
 * emulated HID eye tracker (umockdev-run with the shipped fixture files): the
 * live samples are recorded, the device's silence ends the recording, and what
 * arrived is replayed frame by frame. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "harness.h"

TEST(replay_live_hid_records_then_replays)
{
    if (system("command -v umockdev-run >/dev/null 2>&1") != 0)
        SKIP("umockdev-run is not installed (package umockdev): cannot emulate a tracker");
    const char *bin = getenv("PP5_BIN");
    if (!bin || !*bin)
        bin = "./pp5";
    const char *dir = pp5_test_outdir();
    char cmd[4096];
    /* The sanitised pp5 wants its runtime first in the library list, which
     * umockdev's LD_PRELOAD breaks: that check is off for this child only. */
    snprintf(cmd, sizeof cmd,
             "ASAN_OPTIONS=\"${ASAN_OPTIONS:+$ASAN_OPTIONS:}verify_asan_link_order=0\" "
             "timeout 60 umockdev-run -d tests/fixtures/devices/trackers.umockdev "
             "-i /dev/hidraw0=tests/fixtures/devices/eyetracker.ioctl "
             "-s /dev/hidraw0=tests/fixtures/devices/eyetracker.script -- "
             "%s replay --live hid --seconds 5 --cost constant:10 --latency-ms 0 "
             "--csv %s/live.csv --report %s/live.json >%s/out.txt 2>%s/err.txt",
             bin, dir, dir, dir, dir);
    int rc = system(cmd);
    char path[1200];
    snprintf(path, sizeof path, "%s/err.txt", dir);
    char *err = pp5_test_read_file(path);
    REQUIRE_MSG(rc == 0, "exit status %d; stderr: %s", rc, err ? err : "(none)");
    /* The fixture device goes silent after 20 reports: the recording says so. */
    CHECK_MSG(err && strstr(err, "ended early"), "stderr: %s", err ? err : "(none)");
    free(err);
    snprintf(path, sizeof path, "%s/live.csv", dir);
    FILE *f = fopen(path, "r");
    REQUIRE(f != NULL);
    char line[1024];
    int frames = 0, finite = 0;
    REQUIRE(fgets(line, sizeof line, f) != NULL); /* header */
    while (fgets(line, sizeof line, f)) {
        double v[8];
        if (sscanf(line, "%*d,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &v[0], &v[1], &v[2], &v[3], &v[4],
                   &v[5], &v[6]) == 7) {
            frames++;
            if (isfinite(v[5]) && isfinite(v[6]))
                finite++;
        }
    }
    fclose(f);
    /* 20 samples at 250 Hz = 76 ms of gaze; 10 ms frames: at least 5 frames,
     * each steered by a recorded gaze point. */
    CHECK_MSG(frames >= 5, "%d frames", frames);
    CHECK_EQ(finite, frames);
}
