/* test_track_umockdev_run.c: device integration tests by the umockdev-run
 * route: pp5 under `umockdev-run` with fixture files (sysfs description,
 * hidraw ioctl tree, read script) instead of handler callbacks, checked
 * against the shipped copies in tests/fixtures/devices; and the live HID
 * recording soak (`make soak`).  The files are generated from the emulated
 * devices of umockdev_bed.c.  Without umockdev nothing here is built;
 * test_track_umockdev.c's track_umockdev_devices SKIPs loudly for all the
 * device tests. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "harness.h"

#ifdef PP5_HAVE_UMOCKDEV

#include "emu/util/status.h"
#include "soak.h"
#include "tests/fixtures/devices/eye_tracker_desc.h"
#include "umockdev_bed.h"

/* ---- the umockdev-run route: fixture files instead of handlers ----
 * umockdev-run replays hidraw ioctls from an ioctl tree (answered in the
 * order recorded) and input reports from a read script; the files are
 * generated here from a trace, like tests/fixtures/devices/eyetracker.*.
 * The script ends after 20 reports, so pp5 must stop with a timeout. */

static void write_script_bytes(FILE *f, const uint8_t *b, size_t n)
{
    /* umockdev script escaping: bytes below 32 as '^' + (b + 64), '^' as "^`" */
    for (size_t i = 0; i < n; i++) {
        if (b[i] < 32)
            fprintf(f, "^%c", b[i] + 64);
        else if (b[i] == '^')
            fputs("^`", f);
        else
            fputc(b[i], f);
    }
}

static bool write_fixture_files(const char *dir, const trace_t *t, size_t n_reports)
{
    char path[700];
    snprintf(path, sizeof path, "%s/trackers.umockdev", dir);
    FILE *f = fopen(path, "w");
    if (!f)
        return false;
    char *text = umd_trackers_umockdev_text(&EMU_PATRIOT);
    fputs(text, f);
    g_free(text);
    fclose(f);

    snprintf(path, sizeof path, "%s/eyetracker.ioctl", dir);
    f = fopen(path, "w");
    if (!f)
        return false;
    uint32_t dlen = sizeof pp5_fixture_eye_desc;
    fprintf(f, "@DEV /dev/hidraw0\nHIDIOCGRDESCSIZE 0 %02x%02x%02x%02x\n", dlen & 0xff,
            (dlen >> 8) & 0xff, (dlen >> 16) & 0xff, dlen >> 24);
    static const uint8_t ids[3] = {0x11, 0x12, 0x13}; /* the order pp5 asks in */
    for (int k = 0; k < 3; k++) {
        uint8_t rep[32];
        size_t n = umd_feature_report(ids[k], rep);
        fprintf(f, "HIDIOCGFEATURE %zu ", n);
        for (size_t i = 0; i < n; i++)
            fprintf(f, "%02x", rep[i]);
        fputc('\n', f);
    }
    fclose(f);

    snprintf(path, sizeof path, "%s/eyetracker.script", dir);
    f = fopen(path, "w");
    if (!f)
        return false;
    for (size_t i = 0; i < n_reports && i < t->count; i++) {
        uint8_t r[65];
        umd_tracking_report(r, &t->samples[i], 0x10);
        fputs("r 4 ", f);
        write_script_bytes(f, r, sizeof r);
        fputc('\n', f);
    }
    fclose(f);
    return true;
}

TEST(track_umockdev_run_replays_fixture_files)
{
    if (system("command -v umockdev-run >/dev/null 2>&1") != 0)
        SKIP("UMOCKDEV-RUN NOT INSTALLED: this device integration test did not run "
             "(apt-get install umockdev)");
    const char *dir = pp5_test_outdir();
    char in[600], outp[600], prefix[2400], args[800];
    snprintf(in, sizeof in, "%s/gaze-in-run.trace", dir);
    trace_t want;
    umd_make_trace(in, 20, false, &want);
    REQUIRE(write_fixture_files(dir, &want, 20));
    /* the shipped copies (for trying by hand) must be what this generates */
    static const char *const names[4][2] = {{"trackers.umockdev", "trackers.umockdev"},
                                            {"eyetracker.ioctl", "eyetracker.ioctl"},
                                            {"eyetracker.script", "eyetracker.script"},
                                            {"gaze-in-run.trace", "eyetracker-20.trace"}};
    for (int k = 0; k < 4; k++) {
        char gen[700], shipped[700];
        snprintf(gen, sizeof gen, "%s/%s", dir, names[k][0]);
        snprintf(shipped, sizeof shipped, "tests/fixtures/devices/%s", names[k][1]);
        char *a = pp5_test_read_file(gen), *b = pp5_test_read_file(shipped);
        CHECK_MSG(a && b && strcmp(a, b) == 0,
                  "%s differs from what the test generates (copy %s over it)", shipped, gen);
        free(a);
        free(b);
    }
    snprintf(prefix, sizeof prefix,
             "umockdev-run -d %s/trackers.umockdev -i /dev/hidraw0=%s/eyetracker.ioctl "
             "-s /dev/hidraw0=%s/eyetracker.script --",
             dir, dir, dir);
    snprintf(outp, sizeof outp, "%s/run-out.trace", dir);
    snprintf(args, sizeof args, "track record --device hid --out %s --timeout-ms 1000", outp);
    child_t c;
    REQUIRE(umd_child_start_cmd(&c, dir, prefix, args, false));
    int rc = umd_child_wait(&c, CHILD_DEADLINE_S);
    CHECK_MSG(rc == PP5_EXIT_DEVICE, "umockdev-run pp5 exited %d, expected %d (device error; "
              "-1: hang, killed)", rc, PP5_EXIT_DEVICE);
    CHECK_MSG(umd_file_contains(c.err, "timeout"), "stderr lacks 'timeout'");
    if (rc != PP5_EXIT_DEVICE || !umd_file_contains(c.err, "timeout"))
        umd_show_stderr(&c);
    trace_t got;
    REQUIRE_MSG(trace_read_file(outp, &got) == PP5_OK, "%s", pp5_error_text());
    CHECK(!got.complete);
    CHECK_EQ(got.count, 20);
    CHECK_NEAR(got.header.sample_rate_hz, EMU_RATE_HZ, 0);
    umd_check_gaze_prefix(&got, &want, 20);
    trace_free(&got);
    trace_free(&want);
}

/* Soak (`make soak`; hidden unless PP5_SOAK=1): PP5_SOAK_LIVE_S seconds
 * (default 600) of live HID recording, the path `pp5 track record --device
 * hid` takes, from the emulated eye tracker under umockdev-run, whose script
 * sends one 65-byte report every 4 ms in real time.  Memory is sampled every
 * two seconds; the peak RSS over the first and the last tenth must agree
 * within 5 % + 2 MB, and every report must reach the file. */
TEST(soak_live_hid_recording_from_an_emulated_device)
{
    if (system("command -v umockdev-run >/dev/null 2>&1") != 0)
        SKIP("UMOCKDEV-RUN NOT INSTALLED: the live soak did not run (apt-get install umockdev)");
    const char *v = getenv("PP5_SOAK_LIVE_S");
    double seconds = v && atof(v) > 0 ? atof(v) : 600;
    size_t n = (size_t)(seconds * EMU_RATE_HZ);
    const char *dir = pp5_test_outdir();
    char in[600], outp[600], prefix[2400], args[800];
    snprintf(in, sizeof in, "%s/gaze-in-soak.trace", dir);
    trace_t want;
    umd_make_trace(in, n, false, &want);
    REQUIRE(write_fixture_files(dir, &want, n));
    snprintf(prefix, sizeof prefix,
             "umockdev-run -d %s/trackers.umockdev -i /dev/hidraw0=%s/eyetracker.ioctl "
             "-s /dev/hidraw0=%s/eyetracker.script --",
             dir, dir, dir);
    snprintf(outp, sizeof outp, "%s/soak-out.trace", dir);
    snprintf(args, sizeof args, "track record --device hid --out %s --timeout-ms 2000", outp);
    child_t c;
    REQUIRE(umd_child_start_cmd(&c, dir, prefix, args, false));
    soak_series_t ser = {0};
    struct timespec t0, now;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    pid_t pp5 = -1;
    double wall = 0;
    while (umd_child_running(&c) && wall < seconds + 300) {
        if (pp5 < 0)
            pp5 = soak_find_child(c.pid);      /* umockdev-run's child is pp5 */
        long rss, hwm;
        if (pp5 > 0 && soak_read_memory(pp5, &rss, &hwm))
            soak_series_add(&ser, wall, rss, hwm);
        umd_sleep_ms(2000);
        clock_gettime(CLOCK_MONOTONIC, &now);
        wall = (double)(now.tv_sec - t0.tv_sec) + 1e-9 * (double)(now.tv_nsec - t0.tv_nsec);
    }
    int rc = umd_child_wait(&c, 5);
    /* The script runs out, and the recorder stops on its timeout (a device error). */
    CHECK_MSG(rc == PP5_EXIT_DEVICE, "pp5 exited %d, expected %d", rc, PP5_EXIT_DEVICE);
    if (rc != PP5_EXIT_DEVICE)
        umd_show_stderr(&c);
    trace_t got;
    REQUIRE_MSG(trace_read_file(outp, &got) == PP5_OK, "%s", pp5_error_text());
    CHECK_EQ(got.count, n);
    umd_check_gaze_prefix(&got, &want, n < got.count ? n : got.count);
    REQUIRE(ser.n >= 10);
    char csv[700];
    snprintf(csv, sizeof csv, "%s/rss.csv", dir);
    CHECK(soak_series_write_csv(&ser, csv));
    long first = soak_peak_rss(&ser, 0, 0.1 * wall), last = soak_peak_rss(&ser, 0.9 * wall, wall + 1);
    printf("    soak live: %zu reports (%.0f s at %d Hz) recorded in %.0f s wall; peak RSS %ld kB "
           "over the first tenth, %ld kB over the last tenth; VmHWM at the end %ld kB (%s)\n",
           got.count, seconds, (int)EMU_RATE_HZ, wall, first, last, ser.s[ser.n - 1].hwm_kb, csv);
    CHECK_MSG((double)last <= 1.05 * (double)first + 2048, "RSS rose from %ld kB to %ld kB",
              first, last);
    soak_series_free(&ser);
    trace_free(&got);
    trace_free(&want);
}

#endif /* PP5_HAVE_UMOCKDEV */
