/* hid_eye.h: HID eye trackers on usage page 0x12 (HUTRR74) through hidapi's
 * hidraw backend: enumerate, read the Capabilities and Configuration feature
 * reports, parse Tracking Data input reports by walking the report
 * descriptor (tracker/hid_desc.h), convert micrometres on the screen to
 * pixels, and deliver samples as a gaze_source_t (tracker/gaze.h).
 *
 * Facts: usages, report ids and units from ../shared/docs/tracker-devices.md
 * §1.1-1.2 ([S]: three independent reference implementations agree).  The
 * gaze point is micrometres from the top-left of the calibrated display area
 * (§1.2 "Gaze point semantics"), so pixels = um / calibrated_um * size_px.
 *
 * Modelled: any descriptor that places Gaze Point X/Y (0x24 / 0x21, 0x22) in
 * an input report, with or without Sensor Timestamp, eye and head fields, in
 * any order and bit position; units and exponents as declared (missing units
 * are taken as the standard's micrometres/microseconds).  A gaze value
 * outside its logical range is "no gaze" (HID 1.11 §6.2.2.5: out-of-range
 * values are null).
 * Not modelled: the Control report (pp5 never changes the device mode), the
 * Head Tracker application collection (0x02) on its own, output reports. */
#ifndef PP5_HID_EYE_H
#define PP5_HID_EYE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "gaze.h"
#include "hid_desc.h"
#include "status.h"

#define HID_EYE_PAGE 0x12
enum {
    HID_EYE_USAGE_EYE_TRACKER = 0x01,
    HID_EYE_USAGE_TRACKING = 0x10,
    HID_EYE_USAGE_CAPABILITIES = 0x11,
    HID_EYE_USAGE_CONFIGURATION = 0x12,
    HID_EYE_USAGE_STATUS = 0x13,
    HID_EYE_USAGE_TIMESTAMP = 0x20,
    HID_EYE_USAGE_X = 0x21, HID_EYE_USAGE_Y = 0x22, HID_EYE_USAGE_Z = 0x23,
    HID_EYE_USAGE_GAZE_POINT = 0x24,
    HID_EYE_USAGE_LEFT_EYE = 0x25, HID_EYE_USAGE_RIGHT_EYE = 0x26,
    HID_EYE_USAGE_HEAD_POSITION = 0x27,
    HID_EYE_USAGE_QUALITY = 0x100, HID_EYE_USAGE_OPT_DISTANCE = 0x102,
    HID_EYE_USAGE_MAX_SCREEN_W = 0x104, HID_EYE_USAGE_MAX_SCREEN_H = 0x105,
    HID_EYE_USAGE_CALIBRATED_W = 0x204, HID_EYE_USAGE_CALIBRATED_H = 0x205,
    HID_EYE_USAGE_SAMPLING_HZ = 0x300,
    HID_EYE_USAGE_CONFIG_STATUS = 0x301,
};

enum { HID_EYE_MAX_TS_FIELDS = 8 };

/* Where the values live, found once from the descriptor. */
typedef struct {
    hid_desc_t desc;
    uint8_t tracking_id;          /* report id of Tracking Data */
    size_t tracking_bytes;        /* its length, id byte included */
    const hid_field_t *ts[HID_EYE_MAX_TS_FIELDS]; /* timestamp pieces, low bits first */
    size_t n_ts;
    double ts_to_us;              /* timestamp units to microseconds */
    const hid_field_t *gaze_x, *gaze_y;
    double gaze_to_um;            /* gaze units to micrometres */
    const hid_field_t *eye[2][3]; /* left/right X,Y,Z; NULL when absent */
    const hid_field_t *head[3];
    double pos_to_um;
    const hid_field_t *cal_w, *cal_h; /* Configuration: calibrated screen size */
    const hid_field_t *max_w, *max_h; /* Capabilities: maximum screen size */
    const hid_field_t *quality, *opt_dist;
    const hid_field_t *rate_feature;  /* Status feature: sampling frequency */
} hid_eye_layout_t;

typedef struct {
    uint64_t timestamp_us;        /* device clock; 0 when the report has none */
    bool has_timestamp;
    bool gaze_valid;
    double gaze_x_um, gaze_y_um;  /* from the top-left of the calibrated area */
    bool eye_valid[2];
    double eye_um[2][3];          /* left, right eye position, um */
    bool head_valid;
    double head_um[3];
} hid_eye_sample_t;

typedef struct {
    int quality;                  /* Tracker Quality, -1 when absent */
    double max_screen_w_um, max_screen_h_um;  /* 0 when absent */
    double optimum_distance_um;   /* Optimum Tracking Distance; 0 when absent */
    double calibrated_w_um, calibrated_h_um;  /* 0 when absent: then no pixels */
    double sampling_hz;           /* 0 when unknown */
} hid_eye_config_t;

/* Walks the descriptor and locates the fields.  PP5_E_FORMAT (descriptor
 * broken) or PP5_E_UNSUPPORTED (no Gaze Point X/Y input on page 0x12). */
pp5_status_t hid_eye_layout_init(hid_eye_layout_t *l, const uint8_t *desc, size_t len);

/* Parses one input report (id byte first).  PP5_E_FORMAT for a report of
 * another id or shorter than the descriptor says. */
pp5_status_t hid_eye_parse_tracking(const hid_eye_layout_t *l, const uint8_t *report,
                                    size_t len, hid_eye_sample_t *out);
/* Fills the fields a feature report (Capabilities, Configuration or Status,
 * chosen by its id byte) carries; other fields of *cfg are left alone. */
pp5_status_t hid_eye_parse_feature(const hid_eye_layout_t *l, const uint8_t *report,
                                   size_t len, hid_eye_config_t *cfg);

/* Micrometres from the top-left of a calibrated area `extent_um` wide to
 * pixels across `extent_px`; NaN when the extent is not positive. */
double hid_eye_um_to_px(double um, double extent_um, int extent_px);

/* ---- devices (hidapi, hidraw backend) ---- */

typedef struct {
    char path[256];
    uint16_t vendor_id, product_id;
    char manufacturer[128], product[128], serial[64];
} hid_eye_info_t;

/* Lists page-0x12 Eye Tracker application collections, one entry per
 * device path (hidapi 0.13 lists one entry per collection: deduplicated).
 * PP5_E_UNSUPPORTED when pp5 was built without hidapi. */
pp5_status_t hid_eye_list(hid_eye_info_t *out, size_t max, size_t *n);

typedef struct hid_eye hid_eye_t;

typedef struct {
    uint64_t reports;             /* input reports read */
    uint64_t samples;             /* tracking reports parsed */
    uint64_t malformed;           /* short, unknown id, or unparsable */
    uint64_t status_reports;
    uint64_t invalid_gaze;        /* tracking reports without a gaze point */
    uint64_t clock_backwards;     /* dropped: device time went backwards */
} hid_eye_stats_t;

/* Opens a device (path from hid_eye_list; NULL: the first one), reads its
 * descriptor (sysfs report_descriptor; hidapi 0.13 has no call for it, §4.5)
 * and its feature reports.  timeout_ms bounds every later read. */
pp5_status_t hid_eye_open(const char *path, int timeout_ms, hid_eye_t **out);
const hid_eye_config_t *hid_eye_config(const hid_eye_t *d);
const hid_eye_stats_t *hid_eye_stats(const hid_eye_t *d);
const char *hid_eye_path(const hid_eye_t *d);
/* Next tracking sample.  Status reports are absorbed; malformed reports are
 * counted and skipped, and more than `HID_EYE_MAX_BAD_IN_A_ROW` of them in a
 * row is an error.  PP5_E_DEVICE on a timeout (no report within timeout_ms)
 * or a disconnect, with a message saying which. */
enum { HID_EYE_MAX_BAD_IN_A_ROW = 50 };
pp5_status_t hid_eye_read(hid_eye_t *d, hid_eye_sample_t *out);
void hid_eye_close(hid_eye_t *d);

/* A gaze_source_t over an open device: pixels on a width_px x height_px
 * screen that the calibrated area covers; t_ns from the device timestamp
 * relative to the first sample (host clock when the device sends none).
 * Takes ownership of `d`. */
pp5_status_t hid_eye_source_open(hid_eye_t *d, int width_px, int height_px,
                                 gaze_source_t **out);

#endif
