/* hid_eye.c: HID usage-page-0x12 eye trackers: descriptor-driven report
 * parsing (pure) and the hidapi/hidraw device and gaze_source_t; see hid_eye.h. */
#include "hid_eye.h"
#include "pp5_features.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#if PP5_HAVE_HIDAPI
#include <hidapi.h>
#endif

/* Factor from a field's declared unit to `si_to_target` target units, or
 * `fallback` when the field declares no unit (GazeHid-style descriptors
 * rely on the standard's implied um / us, tracker-devices.md §1.2). */
static pp5_status_t unit_factor(const hid_field_t *f, hid_unit_kind_t want, double si_to_target,
                                double fallback, const char *what, double *out)
{
    double si = 1.0;
    hid_unit_kind_t kind = hid_field_si_factor(f, &si);
    if (kind == HID_UNIT_NONE) {
        *out = fallback;
        return PP5_OK;
    }
    if (kind != want)
        return pp5_fail(PP5_E_UNSUPPORTED, "HID eye tracker: %s has unit 0x%x, not a %s", what,
                        f->unit, want == HID_UNIT_TIME ? "time" : "length");
    *out = si * si_to_target;
    return PP5_OK;
}

static const hid_field_t *find_in(const hid_desc_t *d, hid_report_type_t t, uint16_t parent,
                                  uint16_t usage)
{
    return hid_desc_find(d, t, HID_EYE_PAGE, parent, usage);
}

pp5_status_t hid_eye_layout_init(hid_eye_layout_t *l, const uint8_t *desc, size_t len)
{
    memset(l, 0, sizeof *l);
    pp5_status_t st = hid_desc_parse(desc, len, &l->desc);
    if (st != PP5_OK)
        return st;
    const hid_desc_t *d = &l->desc;
    l->gaze_x = find_in(d, HID_REPORT_INPUT, HID_EYE_USAGE_GAZE_POINT, HID_EYE_USAGE_X);
    l->gaze_y = find_in(d, HID_REPORT_INPUT, HID_EYE_USAGE_GAZE_POINT, HID_EYE_USAGE_Y);
    if (!l->gaze_x || !l->gaze_y)
        return pp5_fail(PP5_E_UNSUPPORTED,
                        "HID descriptor has no Gaze Point X/Y input on usage page 0x12: "
                        "not an eye tracker pp5 can read");
    if (l->gaze_x->report_id != l->gaze_y->report_id)
        return pp5_fail(PP5_E_UNSUPPORTED, "HID eye tracker: gaze X and Y in different reports");
    l->tracking_id = l->gaze_x->report_id;
    l->tracking_bytes = hid_desc_report_bytes(d, HID_REPORT_INPUT, l->tracking_id);
    st = unit_factor(l->gaze_x, HID_UNIT_LENGTH, 1e6, 1.0, "Gaze Point X", &l->gaze_to_um);
    if (st != PP5_OK)
        return st;

    /* The timestamp may be one 64-bit field or, as in the reference
     * descriptors, 8 x 8-bit fields: take them in bit order, low first. */
    for (size_t i = 0; i < d->n_fields && l->n_ts < HID_EYE_MAX_TS_FIELDS; i++) {
        const hid_field_t *f = &d->fields[i];
        if (f->type == HID_REPORT_INPUT && f->usage_page == HID_EYE_PAGE &&
            f->usage == HID_EYE_USAGE_TIMESTAMP && f->report_id == l->tracking_id)
            l->ts[l->n_ts++] = f;
    }
    uint32_t ts_bits = 0;
    for (size_t i = 0; i < l->n_ts; i++)
        ts_bits += l->ts[i]->bit_size * l->ts[i]->count;
    if (ts_bits > 64)
        return pp5_fail(PP5_E_UNSUPPORTED, "HID eye tracker: timestamp of %u bits (max 64)",
                        ts_bits);
    if (l->n_ts > 0) {
        st = unit_factor(l->ts[0], HID_UNIT_TIME, 1e6, 1.0, "Sensor Timestamp", &l->ts_to_us);
        if (st != PP5_OK)
            return st;
    }

    static const uint16_t eye_usage[2] = {HID_EYE_USAGE_LEFT_EYE, HID_EYE_USAGE_RIGHT_EYE};
    static const uint16_t axis[3] = {HID_EYE_USAGE_X, HID_EYE_USAGE_Y, HID_EYE_USAGE_Z};
    for (int e = 0; e < 2; e++)
        for (int a = 0; a < 3; a++)
            l->eye[e][a] = find_in(d, HID_REPORT_INPUT, eye_usage[e], axis[a]);
    for (int a = 0; a < 3; a++)
        l->head[a] = find_in(d, HID_REPORT_INPUT, HID_EYE_USAGE_HEAD_POSITION, axis[a]);
    l->pos_to_um = 1.0;
    const hid_field_t *any_pos = l->eye[0][0] ? l->eye[0][0] : l->head[0];
    if (any_pos) {
        st = unit_factor(any_pos, HID_UNIT_LENGTH, 1e6, 1.0, "eye/head position", &l->pos_to_um);
        if (st != PP5_OK)
            return st;
    }

    l->cal_w = find_in(d, HID_REPORT_FEATURE, 0, HID_EYE_USAGE_CALIBRATED_W);
    l->cal_h = find_in(d, HID_REPORT_FEATURE, 0, HID_EYE_USAGE_CALIBRATED_H);
    l->max_w = find_in(d, HID_REPORT_FEATURE, 0, HID_EYE_USAGE_MAX_SCREEN_W);
    l->max_h = find_in(d, HID_REPORT_FEATURE, 0, HID_EYE_USAGE_MAX_SCREEN_H);
    l->quality = find_in(d, HID_REPORT_FEATURE, 0, HID_EYE_USAGE_QUALITY);
    l->opt_dist = find_in(d, HID_REPORT_FEATURE, 0, HID_EYE_USAGE_OPT_DISTANCE);
    l->rate_feature = find_in(d, HID_REPORT_FEATURE, 0, HID_EYE_USAGE_SAMPLING_HZ);
    return PP5_OK;
}

static bool in_logical_range(const hid_field_t *f, int64_t v)
{
    return v >= f->logical_min && v <= f->logical_max;
}

/* A value in target units (factor from unit_factor), or false when absent
 * from this report or null (outside the logical range). */
static bool read_scaled(const hid_eye_layout_t *l, const hid_field_t *f, double factor,
                        const uint8_t *r, size_t len, double *out)
{
    int64_t raw;
    if (!f || f->report_id != (l->desc.uses_report_ids ? r[0] : 0))
        return false;
    if (hid_field_raw(&l->desc, f, 0, r, len, &raw) != PP5_OK || !in_logical_range(f, raw))
        return false;
    *out = hid_field_physical(f, raw) * factor;
    return true;
}

pp5_status_t hid_eye_parse_tracking(const hid_eye_layout_t *l, const uint8_t *report,
                                    size_t len, hid_eye_sample_t *out)
{
    memset(out, 0, sizeof *out);
    if (len == 0)
        return pp5_fail(PP5_E_FORMAT, "empty HID report");
    if (l->desc.uses_report_ids && report[0] != l->tracking_id)
        return pp5_fail(PP5_E_FORMAT, "HID report id 0x%02x is not Tracking Data (0x%02x)",
                        report[0], l->tracking_id);
    if (len < l->tracking_bytes)
        return pp5_fail(PP5_E_FORMAT, "HID tracking report truncated: %zu of %zu bytes", len,
                        l->tracking_bytes);
    if (l->n_ts > 0) {
        uint64_t ts = 0;
        unsigned shift = 0;
        for (size_t i = 0; i < l->n_ts; i++) {
            const hid_field_t *f = l->ts[i];
            for (uint32_t k = 0; k < f->count; k++) {
                int64_t raw;
                pp5_status_t st = hid_field_raw(&l->desc, f, k, report, len, &raw);
                if (st != PP5_OK)
                    return st;
                uint64_t piece = (uint64_t)raw;
                if (f->bit_size < 64)
                    piece &= ((uint64_t)1 << f->bit_size) - 1;
                ts |= piece << shift;
                shift += f->bit_size;
            }
        }
        out->has_timestamp = true;
        out->timestamp_us = l->ts_to_us == 1.0 ? ts : (uint64_t)llround((double)ts * l->ts_to_us);
    }
    out->gaze_valid = read_scaled(l, l->gaze_x, l->gaze_to_um, report, len, &out->gaze_x_um) &&
                      read_scaled(l, l->gaze_y, l->gaze_to_um, report, len, &out->gaze_y_um);
    if (!out->gaze_valid)
        out->gaze_x_um = out->gaze_y_um = NAN;
    for (int e = 0; e < 2; e++) {
        out->eye_valid[e] = true;
        for (int a = 0; a < 3; a++)
            out->eye_valid[e] &= read_scaled(l, l->eye[e][a], l->pos_to_um, report, len,
                                             &out->eye_um[e][a]);
    }
    out->head_valid = true;
    for (int a = 0; a < 3; a++)
        out->head_valid &= read_scaled(l, l->head[a], l->pos_to_um, report, len, &out->head_um[a]);
    return PP5_OK;
}

pp5_status_t hid_eye_parse_feature(const hid_eye_layout_t *l, const uint8_t *report,
                                   size_t len, hid_eye_config_t *cfg)
{
    if (len == 0)
        return pp5_fail(PP5_E_FORMAT, "empty HID feature report");
    uint8_t id = l->desc.uses_report_ids ? report[0] : 0;
    size_t need = hid_desc_report_bytes(&l->desc, HID_REPORT_FEATURE, id);
    if (need == 0)
        return pp5_fail(PP5_E_FORMAT, "HID feature report 0x%02x is not in the descriptor", id);
    if (len < need)
        return pp5_fail(PP5_E_FORMAT, "HID feature report 0x%02x truncated: %zu of %zu bytes",
                        id, len, need);
    double v, f;
    if (l->cal_w && hid_field_si_factor(l->cal_w, &f) == HID_UNIT_LENGTH &&
        read_scaled(l, l->cal_w, f * 1e6, report, len, &v))
        cfg->calibrated_w_um = v;
    if (l->cal_h && hid_field_si_factor(l->cal_h, &f) == HID_UNIT_LENGTH &&
        read_scaled(l, l->cal_h, f * 1e6, report, len, &v))
        cfg->calibrated_h_um = v;
    if (l->max_w && hid_field_si_factor(l->max_w, &f) == HID_UNIT_LENGTH &&
        read_scaled(l, l->max_w, f * 1e6, report, len, &v))
        cfg->max_screen_w_um = v;
    if (l->max_h && hid_field_si_factor(l->max_h, &f) == HID_UNIT_LENGTH &&
        read_scaled(l, l->max_h, f * 1e6, report, len, &v))
        cfg->max_screen_h_um = v;
    if (l->opt_dist && hid_field_si_factor(l->opt_dist, &f) == HID_UNIT_LENGTH &&
        read_scaled(l, l->opt_dist, f * 1e6, report, len, &v))
        cfg->optimum_distance_um = v;
    if (read_scaled(l, l->quality, 1.0, report, len, &v))
        cfg->quality = (int)v;
    if (l->rate_feature && read_scaled(l, l->rate_feature, 1.0, report, len, &v)) {
        hid_field_si_factor(l->rate_feature, &f);
        cfg->sampling_hz = v * f;
    }
    return PP5_OK;
}

double hid_eye_um_to_px(double um, double extent_um, int extent_px)
{
    if (!(extent_um > 0.0) || extent_px <= 0)
        return NAN;
    return um / extent_um * (double)extent_px;
}

/* ------------------------------------------------------------------ */
#if PP5_HAVE_HIDAPI

struct hid_eye {
    hid_device *dev;
    char path[256];
    int timeout_ms;
    hid_eye_layout_t *layout;
    hid_eye_config_t cfg;
    hid_eye_stats_t stats;
};

static void wide_to_utf8(const wchar_t *w, char *out, size_t cap)
{
    out[0] = '\0';
    if (!w)
        return;
    size_t n = wcstombs(out, w, cap - 1);
    if (n == (size_t)-1) {
        /* not representable in the locale: keep ASCII, mark the rest */
        size_t i = 0;
        for (; w[i] && i + 1 < cap; i++)
            out[i] = (w[i] > 0 && w[i] < 128) ? (char)w[i] : '?';
        out[i] = '\0';
    } else {
        out[n < cap ? n : cap - 1] = '\0';
    }
}

static pp5_status_t hid_init_once(void)
{
    if (hid_init() != 0)
        return pp5_fail(PP5_E_DEVICE, "hidapi could not be initialised (hid_init failed)");
    return PP5_OK;
}

pp5_status_t hid_eye_list(hid_eye_info_t *out, size_t max, size_t *n)
{
    *n = 0;
    pp5_status_t st = hid_init_once();
    if (st != PP5_OK)
        return st;
    struct hid_device_info *all = hid_enumerate(0, 0);
    for (struct hid_device_info *i = all; i; i = i->next) {
        if (i->usage_page != HID_EYE_PAGE || i->usage != HID_EYE_USAGE_EYE_TRACKER || !i->path)
            continue;
        bool seen = false;
        for (size_t k = 0; k < *n; k++)
            seen |= strcmp(out[k].path, i->path) == 0;
        if (seen || *n == max)
            continue;
        hid_eye_info_t *e = &out[(*n)++];
        memset(e, 0, sizeof *e);
        snprintf(e->path, sizeof e->path, "%s", i->path);
        e->vendor_id = i->vendor_id;
        e->product_id = i->product_id;
        wide_to_utf8(i->manufacturer_string, e->manufacturer, sizeof e->manufacturer);
        wide_to_utf8(i->product_string, e->product, sizeof e->product);
        wide_to_utf8(i->serial_number, e->serial, sizeof e->serial);
    }
    hid_free_enumeration(all);
    return PP5_OK;
}

/* hidapi 0.13.1 has no hid_get_report_descriptor (it arrived in 0.14), so
 * read what the kernel exports: /sys/class/hidraw/hidrawN/device/report_descriptor
 * (tracker-devices.md §4.5 item 4; umockdev fakes /sys, so this is tested). */
static pp5_status_t read_sysfs_descriptor(const char *devpath, uint8_t *buf, size_t cap,
                                          size_t *len)
{
    const char *base = strrchr(devpath, '/');
    base = base ? base + 1 : devpath;
    if (strncmp(base, "hidraw", 6) != 0)
        return pp5_fail(PP5_E_DEVICE, "%s: not a hidraw device path", devpath);
    char sys[512];
    snprintf(sys, sizeof sys, "/sys/class/hidraw/%s/device/report_descriptor", base);
    FILE *f = fopen(sys, "rb");
    if (!f)
        return pp5_fail(PP5_E_DEVICE, "%s: cannot read %s (%s)", devpath, sys, strerror(errno));
    *len = fread(buf, 1, cap, f);
    fclose(f);
    if (*len == 0)
        return pp5_fail(PP5_E_DEVICE, "%s: empty report descriptor in %s", devpath, sys);
    return PP5_OK;
}

static pp5_status_t read_feature(hid_eye_t *d, uint8_t id)
{
    size_t need = hid_desc_report_bytes(&d->layout->desc, HID_REPORT_FEATURE, id);
    if (need == 0)
        return PP5_OK; /* the device does not declare it: nothing to read */
    uint8_t buf[4096];
    if (need > sizeof buf)
        return pp5_fail(PP5_E_FORMAT, "%s: feature report 0x%02x of %zu bytes is too long",
                        d->path, id, need);
    memset(buf, 0, need);
    buf[0] = id;
    int got = hid_get_feature_report(d->dev, buf, need);
    if (got < 0) {
        char msg[256];
        wide_to_utf8(hid_error(d->dev), msg, sizeof msg);
        return pp5_fail(PP5_E_DEVICE, "%s: reading feature report 0x%02x failed: %s", d->path,
                        id, msg[0] ? msg : "unknown hidapi error");
    }
    return hid_eye_parse_feature(d->layout, buf, (size_t)got, &d->cfg);
}

pp5_status_t hid_eye_open(const char *path, int timeout_ms, hid_eye_t **out)
{
    *out = NULL;
    hid_eye_info_t first;
    if (!path) {
        size_t n = 0;
        pp5_status_t st = hid_eye_list(&first, 1, &n);
        if (st != PP5_OK)
            return st;
        if (n == 0)
            return pp5_fail(PP5_E_DEVICE, "no HID eye tracker (usage page 0x12) found; see "
                                          "`pp5 track --help` about permissions");
        path = first.path;
    } else {
        pp5_status_t st = hid_init_once();
        if (st != PP5_OK)
            return st;
    }
    hid_eye_t *d = calloc(1, sizeof *d);
    if (!d)
        return pp5_fail(PP5_E_NOMEM, "out of memory");
    d->layout = malloc(sizeof *d->layout);
    if (!d->layout) {
        free(d);
        return pp5_fail(PP5_E_NOMEM, "out of memory");
    }
    snprintf(d->path, sizeof d->path, "%s", path);
    d->timeout_ms = timeout_ms;
    d->cfg.quality = -1;
    uint8_t desc[4096];
    size_t desc_len = 0;
    pp5_status_t st = read_sysfs_descriptor(path, desc, sizeof desc, &desc_len);
    if (st == PP5_OK) {
        st = hid_eye_layout_init(d->layout, desc, desc_len);
        if (st != PP5_OK) {
            char why[512]; /* copy first: pp5_fail writes the buffer it would read */
            snprintf(why, sizeof why, "%s", pp5_error_text());
            st = pp5_fail(st, "%s: %s", path, why);
        }
    }
    if (st == PP5_OK) {
        d->dev = hid_open_path(path);
        if (!d->dev)
            st = pp5_fail(PP5_E_DEVICE, "%s: cannot open (%s); if it exists, check permissions: "
                                        "see `pp5 track --help`",
                          path, strerror(errno));
    }
    if (st == PP5_OK)
        st = read_feature(d, HID_EYE_USAGE_CAPABILITIES);
    if (st == PP5_OK)
        st = read_feature(d, HID_EYE_USAGE_CONFIGURATION);
    if (st == PP5_OK && d->layout->rate_feature)
        st = read_feature(d, d->layout->rate_feature->report_id);
    if (st != PP5_OK) {
        hid_eye_close(d);
        return st;
    }
    *out = d;
    return PP5_OK;
}

const hid_eye_config_t *hid_eye_config(const hid_eye_t *d) { return &d->cfg; }
const hid_eye_stats_t *hid_eye_stats(const hid_eye_t *d) { return &d->stats; }
const char *hid_eye_path(const hid_eye_t *d) { return d->path; }

pp5_status_t hid_eye_read(hid_eye_t *d, hid_eye_sample_t *out)
{
    unsigned bad_in_a_row = 0;
    uint8_t buf[4096];
    /* Ask for the longest input report the descriptor declares: hidraw
     * returns one report per read anyway, and a byte-stream transport (the
     * umockdev pty used in tests) then keeps report boundaries too. */
    size_t want = 0;
    for (size_t i = 0; i < d->layout->desc.n_reports; i++) {
        const hid_report_info_t *r = &d->layout->desc.reports[i];
        size_t b = hid_desc_report_bytes(&d->layout->desc, r->type, r->report_id);
        if (r->type == HID_REPORT_INPUT && b > want)
            want = b;
    }
    if (want == 0 || want > sizeof buf)
        want = sizeof buf;
    for (;;) {
        int got = hid_read_timeout(d->dev, buf, want, d->timeout_ms);
        if (got < 0) {
            /* hidapi's hidraw backend returns -1 when poll() reports
             * POLLERR/POLLHUP/POLLNVAL or read() fails: the device is gone. */
            char msg[256];
            wide_to_utf8(hid_error(d->dev), msg, sizeof msg);
            return pp5_fail(PP5_E_DEVICE,
                            "%s: HID eye tracker disconnected or failed (%s) after %llu samples",
                            d->path, msg[0] ? msg : "read error",
                            (unsigned long long)d->stats.samples);
        }
        if (got == 0)
            return pp5_fail(PP5_E_DEVICE,
                            "%s: timeout: no report from the HID eye tracker within %d ms "
                            "(after %llu samples)",
                            d->path, d->timeout_ms, (unsigned long long)d->stats.samples);
        d->stats.reports++;
        uint8_t id = d->layout->desc.uses_report_ids ? buf[0] : 0;
        pp5_status_t st;
        if (id == d->layout->tracking_id) {
            st = hid_eye_parse_tracking(d->layout, buf, (size_t)got, out);
            if (st == PP5_OK) {
                d->stats.samples++;
                if (!out->gaze_valid)
                    d->stats.invalid_gaze++;
                return PP5_OK;
            }
        } else if (hid_desc_report_bytes(&d->layout->desc, HID_REPORT_INPUT, id) > 0 &&
                   hid_desc_report_bytes(&d->layout->desc, HID_REPORT_INPUT, id) <= (size_t)got) {
            d->stats.status_reports++; /* e.g. Status 0x13: nothing pp5 needs per sample */
            bad_in_a_row = 0;
            continue;
        }
        d->stats.malformed++;
        if (++bad_in_a_row > HID_EYE_MAX_BAD_IN_A_ROW)
            return pp5_fail(PP5_E_DEVICE,
                            "%s: %u malformed reports in a row (last: %d bytes, id 0x%02x); "
                            "the device does not send what its descriptor declares",
                            d->path, bad_in_a_row, got, buf[0]);
    }
}

void hid_eye_close(hid_eye_t *d)
{
    if (!d)
        return;
    if (d->dev)
        hid_close(d->dev);
    free(d->layout);
    free(d);
}

#else /* !PP5_HAVE_HIDAPI */

struct hid_eye {
    int unused;
};

#define NO_HIDAPI "pp5 was built without hidapi: HID eye trackers are not available " \
                  "(install libhidapi-dev and rebuild)"

pp5_status_t hid_eye_list(hid_eye_info_t *out, size_t max, size_t *n)
{
    *n = 0;
    return pp5_fail(PP5_E_UNSUPPORTED, NO_HIDAPI);
}
pp5_status_t hid_eye_open(const char *path, int timeout_ms, hid_eye_t **out)
{
    *out = NULL;
    return pp5_fail(PP5_E_UNSUPPORTED, NO_HIDAPI);
}
const hid_eye_config_t *hid_eye_config(const hid_eye_t *d) { return NULL; }
const hid_eye_stats_t *hid_eye_stats(const hid_eye_t *d) { return NULL; }
const char *hid_eye_path(const hid_eye_t *d) { return ""; }
pp5_status_t hid_eye_read(hid_eye_t *d, hid_eye_sample_t *out)
{
    return pp5_fail(PP5_E_UNSUPPORTED, NO_HIDAPI);
}
void hid_eye_close(hid_eye_t *d) {}

#endif

/* ---- gaze_source_t over a device ---- */

typedef struct {
    hid_eye_t *dev;
    int width_px, height_px;
    bool have_t0;
    uint64_t t0_us;
    int64_t last_t_ns;
    struct timespec host_t0;
} hid_eye_src_t;

static pp5_status_t src_next(gaze_source_t *src, gaze_sample_t *out, bool *got)
{
    hid_eye_src_t *s = src->impl;
    *got = false;
    for (;;) {
        hid_eye_sample_t e;
        pp5_status_t st = hid_eye_read(s->dev, &e);
        if (st != PP5_OK)
            return st;
        int64_t t_ns;
        if (e.has_timestamp) {
            if (!s->have_t0) {
                s->t0_us = e.timestamp_us;
                s->have_t0 = true;
            }
            if (e.timestamp_us < s->t0_us) {
#if PP5_HAVE_HIDAPI
                s->dev->stats.clock_backwards++;
#endif
                continue;
            }
            t_ns = (int64_t)(e.timestamp_us - s->t0_us) * 1000;
        } else {
            /* No device clock: stamp with the host's monotonic clock (live
             * recording only; nothing in emu/ sees this). */
            struct timespec now;
            clock_gettime(CLOCK_MONOTONIC, &now);
            if (!s->have_t0) {
                s->host_t0 = now;
                s->have_t0 = true;
            }
            t_ns = (int64_t)(now.tv_sec - s->host_t0.tv_sec) * 1000000000 +
                   (now.tv_nsec - s->host_t0.tv_nsec);
        }
        if (t_ns < s->last_t_ns) {
#if PP5_HAVE_HIDAPI
            s->dev->stats.clock_backwards++;
#endif
            continue;
        }
        s->last_t_ns = t_ns;
        gaze_sample_invalid(out, t_ns);
        const hid_eye_config_t *cfg = hid_eye_config(s->dev);
        if (e.gaze_valid && cfg) {
            out->x_px = hid_eye_um_to_px(e.gaze_x_um, cfg->calibrated_w_um, s->width_px);
            out->y_px = hid_eye_um_to_px(e.gaze_y_um, cfg->calibrated_h_um, s->height_px);
            if (isfinite(out->x_px) && isfinite(out->y_px))
                out->flags |= GAZE_FLAG_VALID;
            else
                out->x_px = out->y_px = NAN;
        }
        *got = true;
        return PP5_OK;
    }
}

static void src_close(gaze_source_t *src)
{
    if (!src)
        return;
    hid_eye_src_t *s = src->impl;
    if (s)
        hid_eye_close(s->dev);
    free(s);
    free(src);
}

static const gaze_source_ops_t hid_eye_source_ops = {src_next, src_close};

pp5_status_t hid_eye_source_open(hid_eye_t *d, int width_px, int height_px,
                                 gaze_source_t **out)
{
    *out = NULL;
    if (width_px <= 0 || height_px <= 0)
        return pp5_fail(PP5_E_CONFIG, "screen size %dx%d must be positive", width_px, height_px);
    const hid_eye_config_t *cfg = hid_eye_config(d);
    if (!cfg || !(cfg->calibrated_w_um > 0) || !(cfg->calibrated_h_um > 0))
        return pp5_fail(PP5_E_DEVICE,
                        "%s: the eye tracker reports no calibrated screen size (Configuration "
                        "report 0x12), so its micrometres cannot be turned into pixels",
                        hid_eye_path(d));
    gaze_source_t *src = calloc(1, sizeof *src);
    hid_eye_src_t *s = calloc(1, sizeof *s);
    if (!src || !s) {
        free(src);
        free(s);
        return pp5_fail(PP5_E_NOMEM, "out of memory");
    }
    s->dev = d;
    s->width_px = width_px;
    s->height_px = height_px;
    src->ops = &hid_eye_source_ops;
    src->impl = s;
    src->name = hid_eye_path(d);
    src->sample_rate_hz = cfg->sampling_hz;
    src->geometry.width_px = width_px;
    src->geometry.height_px = height_px;
    src->geometry.width_mm = cfg->calibrated_w_um / 1000.0;
    src->geometry.height_mm = cfg->calibrated_h_um / 1000.0;
    *out = src;
    return PP5_OK;
}
