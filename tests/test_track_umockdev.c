/* test_track_umockdev.c: device integration tests, listing and recording.
 * The REAL hidapi (hidraw backend) and libusb code inside ./pp5 talks to
 * emulated devices: this test process builds a umockdev testbed (fake /sys,
 * /dev and udev) with an emulated HID page-0x12 eye tracker and an emulated
 * Polhemus Patriot, answers their ioctls from handler callbacks (libumockdev
 * API, run on the testbed's own thread), feeds the devices from trace files,
 * and runs `pp5 track ...` as a child with LD_PRELOAD=libumockdev-preload.so.0
 * (the way umockdev-run does; ../shared/docs/tracker-devices.md §4.4).  The
 * devices and the testbed are in umockdev_bed.c; the faults (timeouts,
 * disconnects, bad records, signals) in test_track_umockdev_faults.c; the
 * umockdev-run route and the live soak in test_track_umockdev_run.c.
 *
 * What the child exercises for real: libusb_init / get_device_list (udev
 * enumeration) / get_device_descriptor / open / claim_interface /
 * bulk_transfer (SUBMITURB, REAPURBNDELAY, and DISCARDURB on timeouts) /
 * release / close; hid_enumerate (udev + sysfs report_descriptor) /
 * hid_open_path / hid_get_feature_report (HIDIOCGFEATURE) / hid_read_timeout
 * (poll + read on the hidraw node, a pty here).
 *
 * Every child run is bounded: a child still running after CHILD_DEADLINE_S
 * is killed and the test fails with "hang".  Without umockdev the tests SKIP
 * loudly (the one test below stands for the three files). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"

#ifndef PP5_HAVE_UMOCKDEV

TEST(track_umockdev_devices)
{
    SKIP("UMOCKDEV NOT INSTALLED: the device integration tests did not run "
         "(apt-get install umockdev libumockdev-dev, then rebuild)");
}

#else

#include "emu/util/status.h"
#include "umockdev_bed.h"

TEST(track_umockdev_list_finds_both_emulated_devices)
{
    bed_t b;
    BED_OR_FAIL(&b, NULL, 0, AFTER_END_SILENT);
    child_t c;
    REQUIRE(umd_child_start(&c, pp5_test_outdir(), "track list"));
    int rc = umd_child_wait(&c, CHILD_DEADLINE_S);
    umd_bed_close(&b);
    CHECK_MSG(rc == 0, "pp5 track list exited %d", rc);
    char *out = pp5_test_read_file(c.out);
    REQUIRE(out);
    CHECK_MSG(strstr(out, "hid:/dev/hidraw0  1209:0001") != NULL, "no eye tracker in: %s", out);
    CHECK_MSG(strstr(out, "polhemus:1:2  0f44:ef12  Polhemus Patriot") != NULL,
              "no Patriot in: %s", out);
    free(out);
}

TEST(track_umockdev_polhemus_record_matches_the_trace)
{
    const char *dir = pp5_test_outdir();
    char in[600], outp[600], args[1400];
    snprintf(in, sizeof in, "%s/poses-in.trace", dir);
    trace_t want;
    umd_make_trace(in, 30, true, &want);
    bed_t b;
    BED_OR_FAIL(&b, &want, 30, AFTER_END_SILENT);
    child_t c;
    snprintf(outp, sizeof outp, "%s/polhemus-out.trace", dir);
    snprintf(args, sizeof args,
             "track record --device polhemus --out %s --max-samples 30 --rate 500 --timeout-ms 2000",
             outp);
    REQUIRE(umd_child_start(&c, dir, args));
    int rc = umd_child_wait(&c, CHILD_DEADLINE_S);
    char cmdlog[256];
    pthread_mutex_lock(&b.emu.mu);
    snprintf(cmdlog, sizeof cmdlog, "%s", b.emu.cmdlog);
    int discards = b.emu.discards;
    pthread_mutex_unlock(&b.emu.mu);
    umd_bed_close(&b);
    if (rc != 0)
        umd_show_stderr(&c);
    CHECK_MSG(rc == 0, "pp5 track record exited %d (-1: hang, killed)", rc);
    /* the init sequence of tracker-devices.md §2.4, in order */
    CHECK_MSG(strcmp(cmdlog, "U1\r|F1\r|O*,2,4,1\r|") == 0, "commands seen: '%s'", cmdlog);
    /* the drain after the first 'P' ended with a real libusb timeout */
    CHECK(discards >= 1);
    trace_t got;
    REQUIRE_MSG(trace_read_file(outp, &got) == PP5_OK, "%s", pp5_error_text());
    CHECK(got.complete);
    CHECK_EQ(got.count, 30);
    umd_check_pose_prefix(&got, &want, 30);
    trace_free(&got);
    trace_free(&want);
}

/* The HS models use EP 0x04 / 0x88 and the Latus/HS 'LU' record tag. */
TEST(track_umockdev_liberty_hs_endpoints_and_lu_records)
{
    const char *dir = pp5_test_outdir();
    char in[600], outp[600], args[1400];
    snprintf(in, sizeof in, "%s/poses-in-hs.trace", dir);
    trace_t want;
    umd_make_trace(in, 12, true, &want);
    bed_t b;
    if (!umd_preload_available())
        SKIP("UMOCKDEV PRELOAD LIBRARY (libumockdev-preload.so.0) MISSING: the device "
             "integration tests did not run (apt-get install umockdev)");
    if (!umd_bed_open(&b, &EMU_LIBERTY_HS, &want, 12, AFTER_END_SILENT)) {
        umd_bed_close(&b);
        REQUIRE_MSG(false, "umockdev testbed could not be set up");
    }
    child_t c;
    snprintf(outp, sizeof outp, "%s/hs-out.trace", dir);
    snprintf(args, sizeof args, "track record --device polhemus:1:2 --out %s --max-samples 12 "
             "--rate 500 --timeout-ms 2000", outp);
    REQUIRE(umd_child_start(&c, dir, args));
    int rc = umd_child_wait(&c, CHILD_DEADLINE_S);
    umd_bed_close(&b);
    if (rc != 0)
        umd_show_stderr(&c);
    CHECK_MSG(rc == 0, "pp5 exited %d (-1: hang, killed)", rc);
    CHECK(umd_file_contains(c.err, "Liberty HS"));
    trace_t got;
    REQUIRE_MSG(trace_read_file(outp, &got) == PP5_OK, "%s", pp5_error_text());
    CHECK_EQ(got.count, 12);
    umd_check_pose_prefix(&got, &want, 12);
    trace_free(&got);
    trace_free(&want);
}

TEST(track_umockdev_hid_record_matches_the_trace)
{
    const char *dir = pp5_test_outdir();
    char in[600], outp[600], args[1400];
    snprintf(in, sizeof in, "%s/gaze-in.trace", dir);
    trace_t want;
    umd_make_trace(in, 40, false, &want);
    bed_t b;
    BED_OR_FAIL(&b, &want, 40, AFTER_END_SILENT);
    child_t c;
    snprintf(outp, sizeof outp, "%s/hid-out.trace", dir);
    snprintf(args, sizeof args,
             "track record --device hid --out %s --max-samples 40 --timeout-ms 3000", outp);
    REQUIRE(umd_child_start(&c, dir, args));
    bool opened = umd_wait_features(&b, &c);
    CHECK_MSG(opened, "pp5 never read the Configuration feature report");
    /* three reports of a foreign id among the samples: counted, not fatal */
    if (opened) {
        CHECK(umd_inject(&b, &want, 0, 20, 0x10));
        CHECK(umd_inject(&b, &want, 0, 3, 0x42));
        CHECK(umd_inject(&b, &want, 20, 40, 0x10));
    }
    int rc = umd_child_wait(&c, CHILD_DEADLINE_S);
    umd_bed_close(&b);
    if (rc != 0)
        umd_show_stderr(&c);
    CHECK_MSG(rc == 0, "pp5 track record exited %d (-1: hang, killed)", rc);
    CHECK_MSG(umd_file_contains(c.err, "malformed 3"), "malformed reports not counted");
    trace_t got;
    REQUIRE_MSG(trace_read_file(outp, &got) == PP5_OK, "%s", pp5_error_text());
    CHECK(got.complete);
    CHECK_EQ(got.count, 40);
    /* header from the device's feature reports */
    CHECK_NEAR(got.header.sample_rate_hz, EMU_RATE_HZ, 0);
    CHECK_NEAR(got.header.geometry.width_mm, CAL_W_UM / 1000.0, 1e-9);
    CHECK_NEAR(got.header.geometry.distance_mm, 650.0, 1e-9);
    umd_check_gaze_prefix(&got, &want, 40);
    trace_free(&got);
    trace_free(&want);
}

#endif /* PP5_HAVE_UMOCKDEV */
