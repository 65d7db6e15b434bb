/* umockdev_bed.h: the emulated trackers and the umockdev testbed shared by
 * the device integration tests (tests/test_track_umockdev*.c).
 *
 * umockdev_bed.c emulates a Polhemus Patriot / Liberty HS (usbdevfs ioctls)
 * and a HID page-0x12 eye tracker (hidraw ioctls and a pty), describes both
 * to umockdev, runs ./pp5 as a child under umockdev's preload library, and
 * holds the trace helpers and checks the tests have in common.  Include it
 * only when PP5_HAVE_UMOCKDEV is defined (it needs <umockdev.h>). */
#ifndef PP5_TESTS_UMOCKDEV_BED_H
#define PP5_TESTS_UMOCKDEV_BED_H

#include <pthread.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>
#include <umockdev.h>

#include "tracker/trace_file.h"

/* CHILD_DEADLINE_S bounds every child run: one still running after it is
 * killed and its test fails with "hang". */
enum { CHILD_DEADLINE_S = 20, MAX_URBS = 64 };

/* Which Polhemus the USB device is (tracker-devices.md §2.1, §2.3). */
typedef struct {
    uint16_t pid;
    uint8_t ep_out, ep_in;
    char tag[3];
    const char *product;
} emu_polhemus_t;
extern const emu_polhemus_t EMU_PATRIOT;
/* VRPN's Latus/Liberty HS code reads 'LU' records from EP 0x88. */
extern const emu_polhemus_t EMU_LIBERTY_HS;

/* What the emulated devices do once their trace (or limit) runs out. */
typedef enum { AFTER_END_SILENT, AFTER_END_DISCONNECT } after_end_t;

/* Calibrated screen of the emulated eye tracker: 527.04 x 296.46 mm, the
 * same numbers as the device in tracker-devices.md §4.3. */
#define CAL_W_UM 527040
#define CAL_H_UM 296460
#define EMU_RATE_HZ 250

/* The state of both emulated devices; the testbed's ioctl thread and the
 * test share it under `mu`. */
typedef struct {
    pthread_mutex_t mu;
    const emu_polhemus_t *kind;
    const trace_t *trace;
    size_t limit;              /* frames/reports served before after_end */
    after_end_t after_end;
    /* Polhemus faults: frames whose transfer is garbled (tag 'XX'), and
     * frames whose hand record carries the error indicator 'E' */
    size_t garble_every, hand_error_frame;
    /* Polhemus */
    bool configured, disconnected;
    char cmdlog[256];
    size_t frames_sent;
    uint8_t pending[512];
    size_t pending_len;
    bool has_pending;
    UMockdevIoctlData *flying[MAX_URBS];
    int n_flying;
    UMockdevIoctlData *reapable[MAX_URBS];
    int n_reapable;
    int discards;
    /* HID */
    bool features_read;
} emu_t;

/* The testbed: fake /sys, /dev and udev, the two ioctl handlers, and the
 * master side of the hidraw pty (write reports there; close it to unplug). */
typedef struct {
    UMockdevTestbed *tb;
    UMockdevIoctlBase *usb, *hid;
    emu_t emu;
    int hid_master;
} bed_t;

/* A `pp5` run in the background, its stdout and stderr in files. */
typedef struct {
    pid_t pid;
    bool reaped;
    int code;               /* exit code or 128 + signal, once reaped */
    char out[512], err[512];
} child_t;

/* ---- the emulated devices ---- */

/* Writes eye tracker feature report `id` (0x11..0x13) to out[32]; returns its
 * length, 0 for an id the device does not have. */
size_t umd_feature_report(uint8_t id, uint8_t *out);
/* A 65-byte Tracking Data report with report id `id` for sample s. */
void umd_tracking_report(uint8_t r[65], const gaze_sample_t *s, uint8_t id);
/* The sysfs/udev description of both emulated devices, the Polhemus being
 * `k`, in umockdev's record format (g_free the result). */
char *umd_trackers_umockdev_text(const emu_polhemus_t *k);

/* ---- the testbed ---- */

/* Sets up the testbed with a Polhemus of kind `kind` that serves `limit`
 * frames of t and then does `after`; false (with a message) on failure.
 * Call umd_bed_close in either case. */
bool umd_bed_open(bed_t *b, const emu_polhemus_t *kind, const trace_t *t, size_t limit,
                  after_end_t after);
void umd_bed_close(bed_t *b);
/* True when umockdev's preload library loads into a child (checked once). */
bool umd_preload_available(void);
/* Waits (bounded) until the child has read the eye tracker's Configuration
 * report, i.e. it has opened the device. */
bool umd_wait_features(bed_t *b, child_t *c);
/* Writes reports for samples [from, to) of t into the hidraw pty in one burst. */
bool umd_inject(bed_t *b, const trace_t *t, size_t from, size_t to, uint8_t id);

/* Opens the testbed with the Patriot, or SKIPs loudly when the preload
 * library is missing; fails the test when the testbed cannot be set up. */
#define BED_OR_FAIL(b, trace, limit, after)                                              \
    do {                                                                                 \
        if (!umd_preload_available())                                                    \
            SKIP("UMOCKDEV PRELOAD LIBRARY (libumockdev-preload.so.0) MISSING: the "      \
                 "device integration tests did not run (apt-get install umockdev)");      \
        if (!umd_bed_open(b, &EMU_PATRIOT, trace, limit, after)) {                       \
            umd_bed_close(b);                                                            \
            REQUIRE_MSG(false, "umockdev testbed could not be set up");                  \
        }                                                                                \
    } while (0)

/* ---- running ./pp5 ($PP5_BIN) as a child ---- */

/* Runs `pp5 ARGS` in dir's stdout.txt/stderr.txt under the preload library. */
bool umd_child_start(child_t *c, const char *dir, const char *args);
/* Runs `PREFIX pp5 ARGS`; with `preload`, the child gets umockdev's preload
 * library (the testbed route); without, the prefix is expected to be
 * umockdev-run, which sets it itself. */
bool umd_child_start_cmd(child_t *c, const char *dir, const char *prefix, const char *args,
                         bool preload);
/* True once the child has ended (then c->code holds how). */
bool umd_child_poll(child_t *c);
bool umd_child_running(child_t *c);
/* Waits at most `seconds`; returns the exit code, 128+signal, or -1 when the
 * child had to be killed (a hang). */
int umd_child_wait(child_t *c, double seconds);
/* Prints the child's stderr (for a failing check). */
void umd_show_stderr(const child_t *c);

/* ---- traces, files and checks ---- */

void umd_sleep_ms(int ms);
bool umd_file_contains(const char *path, const char *needle);
/* Writes an n-sample trace (gaze, and head and hand poses when `poses`) to
 * path and reads it back into *out: the devices are fed from files. */
void umd_make_trace(const char *path, size_t n, bool poses, trace_t *out);
/* CHECKs that the first n samples of got match want: times, validity, gaze. */
void umd_check_gaze_prefix(const trace_t *got, const trace_t *want, size_t n);
/* CHECKs the head and hand poses of the first n samples, and time order. */
void umd_check_pose_prefix(const trace_t *got, const trace_t *want, size_t n);

#endif /* PP5_TESTS_UMOCKDEV_BED_H */
