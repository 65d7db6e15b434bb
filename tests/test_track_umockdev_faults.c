/* test_track_umockdev_faults.c: device integration tests, the faults: a
 * Polhemus or eye tracker that times out or is unplugged mid-recording,
 * garbled transfers and station errors, malformed HID reports, and pp5
 * stopped by SIGTERM or killed by SIGKILL.  The emulated devices and the
 * testbed are in umockdev_bed.c (see test_track_umockdev.c for the route).
 * Without umockdev nothing here is built; test_track_umockdev.c's
 * track_umockdev_devices SKIPs loudly for all the device tests. */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "harness.h"

#ifdef PP5_HAVE_UMOCKDEV

#include "emu/util/status.h"
#include "umockdev_bed.h"

static void polhemus_failure(after_end_t after, const char *needle)
{
    const char *dir = pp5_test_outdir();
    char in[600], outp[600], args[1400];
    snprintf(in, sizeof in, "%s/poses-in-%d.trace", dir, (int)after);
    trace_t want;
    umd_make_trace(in, 30, true, &want);
    bed_t b;
    BED_OR_FAIL(&b, &want, 10, after);
    child_t c;
    snprintf(outp, sizeof outp, "%s/polhemus-fail-%d.trace", dir, (int)after);
    snprintf(args, sizeof args,
             "track record --device polhemus --out %s --rate 500 --timeout-ms 1000 --flush-every 100",
             outp);
    REQUIRE(umd_child_start(&c, dir, args));
    int rc = umd_child_wait(&c, CHILD_DEADLINE_S);
    umd_bed_close(&b);
    CHECK_MSG(rc == PP5_EXIT_DEVICE, "pp5 exited %d, expected %d (device error; -1: hang, killed)",
              rc, PP5_EXIT_DEVICE);
    CHECK_MSG(umd_file_contains(c.err, needle), "stderr lacks '%s'", needle);
    if (!umd_file_contains(c.err, needle))
        umd_show_stderr(&c);
    /* the 10 samples that arrived were kept although no flush was due */
    trace_t got;
    REQUIRE_MSG(trace_read_file(outp, &got) == PP5_OK, "%s", pp5_error_text());
    CHECK(!got.complete);
    CHECK_EQ(got.count, 10);
    umd_check_pose_prefix(&got, &want, 10);
    trace_free(&got);
    trace_free(&want);
}

TEST(track_umockdev_polhemus_timeout_is_reported)
{
    polhemus_failure(AFTER_END_SILENT, "timeout");
}

TEST(track_umockdev_polhemus_disconnect_is_reported)
{
    polhemus_failure(AFTER_END_DISCONNECT, "disconnected");
}

/* Garbled transfers are counted and skipped (pp5 polls again, so each costs
 * one trace frame); a station's error indicator drops that station's pose
 * from the sample and is reported. */
TEST(track_umockdev_polhemus_bad_records_are_counted)
{
    const char *dir = pp5_test_outdir();
    char in[600], outp[600], args[1400];
    snprintf(in, sizeof in, "%s/poses-in-bad.trace", dir);
    trace_t want;
    umd_make_trace(in, 40, true, &want);
    bed_t b;
    BED_OR_FAIL(&b, &want, 40, AFTER_END_SILENT);
    b.emu.garble_every = 10;    /* frames 9, 19, 29, 39 */
    b.emu.hand_error_frame = 5;
    child_t c;
    snprintf(outp, sizeof outp, "%s/polhemus-bad.trace", dir);
    snprintf(args, sizeof args, "track record --device polhemus --out %s --max-samples 30 "
             "--rate 500 --timeout-ms 2000", outp);
    REQUIRE(umd_child_start(&c, dir, args));
    int rc = umd_child_wait(&c, CHILD_DEADLINE_S);
    umd_bed_close(&b);
    if (rc != 0)
        umd_show_stderr(&c);
    CHECK_MSG(rc == 0, "pp5 exited %d (-1: hang, killed)", rc);
    CHECK_MSG(umd_file_contains(c.err, "malformed transfers 3"), "garbled transfers not counted");
    CHECK_MSG(umd_file_contains(c.err, "station errors 1"), "station error not counted");
    CHECK_MSG(umd_file_contains(c.err, "station 2 reported error 'E'"), "station error not reported");
    trace_t got;
    REQUIRE_MSG(trace_read_file(outp, &got) == PP5_OK, "%s", pp5_error_text());
    REQUIRE(got.count == 30);
    /* sample k came from frame k + (garbled frames before it): frames 9,
     * 19, 29 were skipped; frame 5's hand record carried the error */
    int bad = 0;
    for (size_t k = 0; k < 30; k++) {
        size_t frame = k + (k >= 9) + (k >= 18) + (k >= 27);
        const gaze_sample_t *g = &got.samples[k], *w = &want.samples[frame];
        bool hand_expected = frame != 5;
        if (!(g->flags & GAZE_FLAG_HEAD) || ((g->flags & GAZE_FLAG_HAND) != 0) != hand_expected ||
            fabs(g->head.pos_mm[0] - w->head.pos_mm[0]) > 1e-3)
            bad++;
    }
    CHECK_MSG(bad == 0, "%d samples do not match the frames the device sent", bad);
    trace_free(&got);
    trace_free(&want);
}

static void hid_failure(bool disconnect, int n_good, int n_bad, const char *needle)
{
    const char *dir = pp5_test_outdir();
    char in[600], outp[600], args[1400];
    snprintf(in, sizeof in, "%s/gaze-in-fail.trace", dir);
    trace_t want;
    umd_make_trace(in, 80, false, &want);
    bed_t b;
    BED_OR_FAIL(&b, &want, (size_t)n_good, AFTER_END_SILENT);
    child_t c;
    snprintf(outp, sizeof outp, "%s/hid-fail.trace", dir);
    /* --flush-every 1 --verbose only for the disconnect test, which waits
     * for the flush lines; the others check that an error still flushes */
    snprintf(args, sizeof args, "track record --device hid --out %s --timeout-ms 1000 %s", outp,
             disconnect ? "--flush-every 1 --verbose" : "--flush-every 1000");
    REQUIRE(umd_child_start(&c, dir, args));
    bool opened = umd_wait_features(&b, &c);
    CHECK_MSG(opened, "pp5 never read the Configuration feature report");
    if (opened) {
        CHECK(umd_inject(&b, &want, 0, (size_t)n_good, 0x10));
        CHECK(umd_inject(&b, &want, 0, (size_t)n_bad, 0x42));
    }
    if (disconnect) {
        /* wait (bounded) until the child has the samples, then the device
         * goes away: the pty's other side closes, and the child's poll()
         * sees POLLHUP as with an unplugged hidraw node */
        char line[64];
        snprintf(line, sizeof line, "flushed %d samples", n_good);
        for (int i = 0; i < CHILD_DEADLINE_S * 100 && !umd_file_contains(c.err, line) &&
                        umd_child_running(&c); i++)
            umd_sleep_ms(10);
        CHECK_MSG(umd_file_contains(c.err, line), "child never reported '%s'", line);
        close(b.hid_master);
    }
    int rc = umd_child_wait(&c, CHILD_DEADLINE_S);
    umd_bed_close(&b);
    CHECK_MSG(rc == PP5_EXIT_DEVICE, "pp5 exited %d, expected %d (device error; -1: hang, killed)",
              rc, PP5_EXIT_DEVICE);
    CHECK_MSG(umd_file_contains(c.err, needle), "stderr lacks '%s'", needle);
    if (!umd_file_contains(c.err, needle))
        umd_show_stderr(&c);
    trace_t got;
    REQUIRE_MSG(trace_read_file(outp, &got) == PP5_OK, "%s", pp5_error_text());
    CHECK(!got.complete);
    CHECK_EQ(got.count, (size_t)n_good);
    umd_check_gaze_prefix(&got, &want, (size_t)n_good);
    trace_free(&got);
    trace_free(&want);
}

/* SIGTERM (or Ctrl-C) while pp5 waits for the device: a clean stop, the
 * file complete with its end line, exit 0. */
TEST(track_umockdev_hid_sigterm_ends_the_file_cleanly)
{
    const char *dir = pp5_test_outdir();
    char in[600], outp[600], args[1400];
    snprintf(in, sizeof in, "%s/gaze-in-term.trace", dir);
    trace_t want;
    umd_make_trace(in, 12, false, &want);
    bed_t b;
    BED_OR_FAIL(&b, &want, 12, AFTER_END_SILENT);
    child_t c;
    snprintf(outp, sizeof outp, "%s/hid-term.trace", dir);
    snprintf(args, sizeof args, "track record --device hid --out %s --timeout-ms 10000 "
             "--flush-every 1 --verbose", outp);
    REQUIRE(umd_child_start(&c, dir, args));
    bool opened = umd_wait_features(&b, &c);
    CHECK_MSG(opened, "pp5 never read the Configuration feature report");
    if (opened)
        CHECK(umd_inject(&b, &want, 0, 12, 0x10));
    for (int i = 0; i < CHILD_DEADLINE_S * 100 && !umd_file_contains(c.err, "flushed 12 samples") &&
                    umd_child_running(&c); i++)
        umd_sleep_ms(10);
    if (!umd_child_poll(&c))
        kill(c.pid, SIGTERM);
    int rc = umd_child_wait(&c, CHILD_DEADLINE_S);
    umd_bed_close(&b);
    if (rc != 0)
        umd_show_stderr(&c);
    CHECK_MSG(rc == 0, "pp5 exited %d after SIGTERM, expected 0 (-1: hang, killed)", rc);
    trace_t got;
    REQUIRE_MSG(trace_read_file(outp, &got) == PP5_OK, "%s", pp5_error_text());
    CHECK(got.complete);
    CHECK_EQ(got.count, 12);
    umd_check_gaze_prefix(&got, &want, 12);
    trace_free(&got);
    trace_free(&want);
}

TEST(track_umockdev_hid_timeout_is_reported)
{
    hid_failure(false, 10, 0, "timeout");
}

TEST(track_umockdev_hid_disconnect_is_reported)
{
    hid_failure(true, 10, 0, "disconnected");
}

TEST(track_umockdev_hid_persistent_malformed_reports_stop_the_recording)
{
    hid_failure(false, 5, 60, "malformed reports in a row");
}

/* After a kill -9 the testbed's ioctl thread finds the client gone in the
 * middle of a request and GLib logs a warning and a critical about it; they
 * are expected there, so they are counted and summarised instead. */
static int umockdev_msgs_after_kill;

static void quiet_log(const gchar *domain, GLogLevelFlags level, const gchar *msg, gpointer data)
{
    (void)domain, (void)level, (void)msg, (void)data;
    umockdev_msgs_after_kill++;
}

/* kill -9 in the middle of a recording: the file must parse and hold at
 * least every sample the recorder said it had flushed. */
TEST(track_umockdev_kill9_keeps_flushed_samples)
{
    const char *dir = pp5_test_outdir();
    char in[600], outp[600], args[1400];
    snprintf(in, sizeof in, "%s/gaze-in-kill.trace", dir);
    trace_t want;
    umd_make_trace(in, 300, false, &want);
    bed_t b;
    BED_OR_FAIL(&b, &want, 300, AFTER_END_SILENT);
    child_t c;
    snprintf(outp, sizeof outp, "%s/hid-kill9.trace", dir);
    snprintf(args, sizeof args, "track record --device hid --out %s --timeout-ms 5000 "
             "--flush-every 7 --verbose", outp);
    REQUIRE(umd_child_start(&c, dir, args));
    bool opened = umd_wait_features(&b, &c);
    REQUIRE_MSG(opened, "pp5 never read the Configuration feature report");
    /* feed until the recorder reports a few flushes, then kill it; stay at
     * most 10 reports ahead of what it has flushed, so the kill lands in
     * the middle of a stream, with samples received but not yet flushed */
    size_t sent = 0;
    long flushed = 0;
    for (int spins = 0; sent < want.count && umd_child_running(&c) && flushed < 35 &&
                        spins < CHILD_DEADLINE_S * 500; spins++) {
        if ((long)sent < flushed + 10) {
            REQUIRE(umd_inject(&b, &want, sent, sent + 1, 0x10));
            sent++;
        } else {
            umd_sleep_ms(2);
        }
        char *e = pp5_test_read_file(c.err);
        const char *last = NULL;
        for (const char *p = e; p && (p = strstr(p, "flushed ")); p++)
            last = p;
        if (last)
            flushed = strtol(last + 8, NULL, 10);
        free(e);
    }
    umockdev_msgs_after_kill = 0;
    GLogFunc previous = g_log_set_default_handler(quiet_log, NULL);
    if (!umd_child_poll(&c))
        kill(c.pid, SIGKILL);
    int rc = umd_child_wait(&c, CHILD_DEADLINE_S);
    umd_bed_close(&b);
    g_log_set_default_handler(previous, NULL);
    if (umockdev_msgs_after_kill)
        printf("    (%d umockdev log messages about the killed client suppressed)\n",
               umockdev_msgs_after_kill);
    CHECK_MSG(rc == 128 + SIGKILL, "child ended with %d, not by the kill", rc);
    CHECK_MSG(flushed >= 35, "recorder reported only %ld flushed samples", flushed);
    /* re-read stderr after the kill: the last flush line is the bound */
    char *e = pp5_test_read_file(c.err);
    for (const char *p = e; p && (p = strstr(p, "flushed ")); p++)
        flushed = strtol(p + 8, NULL, 10);
    free(e);
    trace_t got;
    REQUIRE_MSG(trace_read_file(outp, &got) == PP5_OK, "killed recording does not parse: %s",
                pp5_error_text());
    CHECK(!got.complete);
    CHECK_MSG((long)got.count >= flushed, "file has %zu samples, recorder had flushed %ld",
              got.count, flushed);
    CHECK(got.count <= sent);
    umd_check_gaze_prefix(&got, &want, got.count);
    trace_free(&got);
    trace_free(&want);
}

#endif /* PP5_HAVE_UMOCKDEV */
