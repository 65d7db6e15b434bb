/* test_hid.c: the HID report-descriptor walker (tracker/hid_desc.c) and the
 * page-0x12 eye-tracker report parsing (tracker/hid_eye.c) on byte arrays,
 * including truncated, mutated and hostile descriptors and reports.
 * Expected offsets and sizes come from the report layout table in
 * ../shared/docs/tracker-devices.md §1.2, not from the code under test. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "tests/fixtures/devices/eye_tracker_desc.h"
#include "tracker/hid_desc.h"
#include "tracker/hid_eye.h"

static hid_desc_t *parse_fixture(void)
{
    hid_desc_t *d = malloc(sizeof *d);
    REQUIRE(d != NULL);
    pp5_status_t st = hid_desc_parse(pp5_fixture_eye_desc, sizeof pp5_fixture_eye_desc, d);
    REQUIRE_MSG(st == PP5_OK, "parse failed: %s", pp5_error_text());
    return d;
}

static void put_le32(uint8_t *p, int32_t v)
{
    uint32_t u = (uint32_t)v;
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(u >> (8 * i));
}

TEST(hid_desc_report_sizes_match_the_documented_layout)
{
    hid_desc_t *d = parse_fixture();
    /* tracker-devices.md §1.2: 65, 22, 19, 4 (feature and input), 2 bytes. */
    CHECK_EQ(hid_desc_report_bytes(d, HID_REPORT_INPUT, 0x10), 65);
    CHECK_EQ(hid_desc_report_bytes(d, HID_REPORT_FEATURE, 0x11), 22);
    CHECK_EQ(hid_desc_report_bytes(d, HID_REPORT_FEATURE, 0x12), 19);
    CHECK_EQ(hid_desc_report_bytes(d, HID_REPORT_FEATURE, 0x13), 4);
    CHECK_EQ(hid_desc_report_bytes(d, HID_REPORT_INPUT, 0x13), 4);
    CHECK_EQ(hid_desc_report_bytes(d, HID_REPORT_FEATURE, 0x14), 2);
    CHECK_EQ(hid_desc_report_bytes(d, HID_REPORT_INPUT, 0x11), 0);
    CHECK(d->uses_report_ids);
    free(d);
}

TEST(hid_desc_field_positions_units_and_parents)
{
    hid_desc_t *d = parse_fixture();
    /* Layout: 8 timestamp bytes, then int32 gaze x,y, leye xyz, reye xyz,
     * head xyz, head direction xyz.  Bit offsets exclude the id byte. */
    const hid_field_t *gx = hid_desc_find(d, HID_REPORT_INPUT, 0x12, 0x24, 0x21);
    const hid_field_t *gy = hid_desc_find(d, HID_REPORT_INPUT, 0x12, 0x24, 0x22);
    const hid_field_t *lz = hid_desc_find(d, HID_REPORT_INPUT, 0x12, 0x25, 0x23);
    const hid_field_t *rx = hid_desc_find(d, HID_REPORT_INPUT, 0x12, 0x26, 0x21);
    const hid_field_t *rotz = hid_desc_find(d, HID_REPORT_INPUT, 0x12, 0x28, 0x2b);
    REQUIRE(gx && gy && lz && rx && rotz);
    CHECK_EQ(gx->bit_offset, 64);
    CHECK_EQ(gy->bit_offset, 96);
    CHECK_EQ(lz->bit_offset, 64 + 4 * 32);
    CHECK_EQ(rx->bit_offset, 64 + 5 * 32);
    CHECK_EQ(rotz->bit_offset, 64 + 13 * 32);
    CHECK_EQ(gx->bit_size, 32);
    CHECK_EQ(gx->logical_min, -2000000);
    CHECK_EQ(gx->logical_max, 2000000);
    CHECK_EQ(gx->app_usage, 0x01);
    CHECK_EQ(gx->report_id, 0x10);
    /* 8 timestamp pieces of 8 bits, bits 0..63 */
    const hid_field_t *ts7 = hid_desc_find_nth(d, HID_REPORT_INPUT, 0x12, 0x10, 0x20, 7);
    REQUIRE(ts7);
    CHECK_EQ(ts7->bit_offset, 56);
    CHECK_EQ(ts7->bit_size, 8);
    CHECK(hid_desc_find_nth(d, HID_REPORT_INPUT, 0x12, 0x10, 0x20, 8) == NULL);
    /* Logical Maximum 26 ff 00 is 255, not -1. */
    CHECK_EQ(ts7->logical_max, 255);

    double f = 0;
    /* unit 0x11 = cm, exponent 0xC = -4: 1e-6 m per count */
    CHECK_EQ(hid_field_si_factor(gx, &f), HID_UNIT_LENGTH);
    CHECK_NEAR(f, 1e-6, 1e-18);
    /* unit 0x1001 = s, exponent 0xA = -6 */
    CHECK_EQ(hid_field_si_factor(ts7, &f), HID_UNIT_TIME);
    CHECK_NEAR(f, 1e-6, 1e-18);
    /* unit 0x14 = degrees, exponent -4 */
    CHECK_EQ(hid_field_si_factor(rotz, &f), HID_UNIT_ROTATION);
    CHECK_NEAR(f, 1e-4 * M_PI / 180.0, 1e-15);
    const hid_field_t *hz = hid_desc_find(d, HID_REPORT_FEATURE, 0x12, 0, 0x300);
    REQUIRE(hz);
    CHECK_EQ(hid_field_si_factor(hz, &f), HID_UNIT_FREQUENCY);
    CHECK_NEAR(f, 1.0, 0);
    /* Configuration: u16, u16, u32, u16 then the calibrated size */
    const hid_field_t *calw = hid_desc_find(d, HID_REPORT_FEATURE, 0x12, 0, 0x204);
    REQUIRE(calw);
    CHECK_EQ(calw->bit_offset, 16 + 16 + 32 + 16);
    free(d);
}

/* A tracking report built byte by byte after the §1.2 table. */
static void make_tracking(uint8_t r[65], uint64_t ts_us, int32_t gx, int32_t gy)
{
    memset(r, 0, 65);
    r[0] = 0x10;
    for (int i = 0; i < 8; i++)
        r[1 + i] = (uint8_t)(ts_us >> (8 * i));
    put_le32(r + 9, gx);
    put_le32(r + 13, gy);
    for (int k = 0; k < 12; k++) /* eyes, head, direction: 1000 um * (k+1), alternating sign */
        put_le32(r + 17 + 4 * k, (k % 2 ? -1 : 1) * 1000 * (k + 1));
}

TEST(hid_eye_parses_tracking_report_in_micrometres)
{
    hid_eye_layout_t *l = malloc(sizeof *l);
    REQUIRE(l);
    REQUIRE(hid_eye_layout_init(l, pp5_fixture_eye_desc, sizeof pp5_fixture_eye_desc) == PP5_OK);
    CHECK_EQ(l->tracking_id, 0x10);
    CHECK_EQ(l->tracking_bytes, 65);
    CHECK_EQ(l->n_ts, 8);
    uint8_t r[65];
    make_tracking(r, 0x0102030405060708ull, 263520, -148230);
    hid_eye_sample_t s;
    REQUIRE(hid_eye_parse_tracking(l, r, sizeof r, &s) == PP5_OK);
    CHECK(s.has_timestamp);
    CHECK(s.timestamp_us == 0x0102030405060708ull);
    CHECK(s.gaze_valid);
    CHECK_NEAR(s.gaze_x_um, 263520, 1e-6);
    CHECK_NEAR(s.gaze_y_um, -148230, 1e-6);
    CHECK(s.eye_valid[0] && s.eye_valid[1] && s.head_valid);
    CHECK_NEAR(s.eye_um[0][0], 1000, 1e-9);
    CHECK_NEAR(s.eye_um[0][1], -2000, 1e-9);
    CHECK_NEAR(s.eye_um[1][2], -6000, 1e-9);
    CHECK_NEAR(s.head_um[2], 9000, 1e-9);

    /* Out of the logical range (+-2e6) is the HID null value: no gaze. */
    make_tracking(r, 5, 2000001, 0);
    REQUIRE(hid_eye_parse_tracking(l, r, sizeof r, &s) == PP5_OK);
    CHECK(!s.gaze_valid);
    CHECK(isnan(s.gaze_x_um));
    free(l);
}

TEST(hid_eye_truncated_or_foreign_reports_are_errors)
{
    hid_eye_layout_t *l = malloc(sizeof *l);
    REQUIRE(l);
    REQUIRE(hid_eye_layout_init(l, pp5_fixture_eye_desc, sizeof pp5_fixture_eye_desc) == PP5_OK);
    uint8_t r[65];
    make_tracking(r, 1, 1, 1);
    hid_eye_sample_t s;
    int errors = 0;
    for (size_t len = 0; len < sizeof r; len++) {
        /* copy into an exact-size heap buffer so ASan sees any overread */
        uint8_t *cut = malloc(len ? len : 1);
        memcpy(cut, r, len);
        if (hid_eye_parse_tracking(l, cut, len, &s) == PP5_E_FORMAT)
            errors++;
        free(cut);
    }
    CHECK_EQ(errors, 65);
    CHECK(strstr(pp5_error_text(), "truncated") != NULL);
    r[0] = 0x13;
    CHECK_EQ(hid_eye_parse_tracking(l, r, sizeof r, &s), PP5_E_FORMAT);
    CHECK(strstr(pp5_error_text(), "0x13") != NULL);
    free(l);
}

TEST(hid_eye_feature_reports_and_pixels)
{
    hid_eye_layout_t *l = malloc(sizeof *l);
    REQUIRE(l);
    REQUIRE(hid_eye_layout_init(l, pp5_fixture_eye_desc, sizeof pp5_fixture_eye_desc) == PP5_OK);
    uint8_t caps[22] = {0x11, 1};
    put_le32(caps + 2, 450000);
    put_le32(caps + 6, 650000);
    put_le32(caps + 10, 950000);
    put_le32(caps + 14, 600000);
    put_le32(caps + 18, 340000);
    uint8_t conf[19] = {0x12, 0xac, 0x10, 0xb1, 0xa0};
    put_le32(conf + 5, 12345678);
    conf[9] = 0xe1;
    conf[10] = 0x07;
    put_le32(conf + 11, 527040);
    put_le32(conf + 15, 296460);
    uint8_t status[4] = {0x13, 1, 0x78, 0x00}; /* ready, 120 Hz */
    hid_eye_config_t cfg = {.quality = -1};
    REQUIRE(hid_eye_parse_feature(l, caps, sizeof caps, &cfg) == PP5_OK);
    REQUIRE(hid_eye_parse_feature(l, conf, sizeof conf, &cfg) == PP5_OK);
    REQUIRE(hid_eye_parse_feature(l, status, sizeof status, &cfg) == PP5_OK);
    CHECK_EQ(cfg.quality, 1);
    CHECK_NEAR(cfg.max_screen_w_um, 600000, 1e-6);
    CHECK_NEAR(cfg.max_screen_h_um, 340000, 1e-6);
    CHECK_NEAR(cfg.optimum_distance_um, 650000, 1e-6);
    CHECK_NEAR(cfg.calibrated_w_um, 527040, 1e-6);
    CHECK_NEAR(cfg.calibrated_h_um, 296460, 1e-6);
    CHECK_NEAR(cfg.sampling_hz, 120, 0);
    /* Half the calibrated width is half the screen: 960 of 1920 px. */
    CHECK_NEAR(hid_eye_um_to_px(263520, cfg.calibrated_w_um, 1920), 960, 1e-9);
    CHECK_NEAR(hid_eye_um_to_px(296460, cfg.calibrated_h_um, 1080), 1080, 1e-9);
    CHECK(isnan(hid_eye_um_to_px(1, 0, 1920)));
    CHECK_EQ(hid_eye_parse_feature(l, conf, 18, &cfg), PP5_E_FORMAT);
    uint8_t unknown[4] = {0x42, 0, 0, 0};
    CHECK_EQ(hid_eye_parse_feature(l, unknown, 4, &cfg), PP5_E_FORMAT);
    free(l);
}

TEST(hid_desc_every_truncation_is_an_error_or_a_clean_parse)
{
    hid_desc_t *d = malloc(sizeof *d);
    REQUIRE(d);
    size_t n = sizeof pp5_fixture_eye_desc;
    int ok = 0, bad = 0, truncated_msgs = 0;
    for (size_t len = 0; len < n; len++) {
        uint8_t *cut = malloc(len ? len : 1); /* exact size: ASan catches overreads */
        memcpy(cut, pp5_fixture_eye_desc, len);
        pp5_status_t st = hid_desc_parse(cut, len, d);
        if (st == PP5_OK)
            ok++;
        else {
            bad++;
            if (strstr(pp5_error_text(), "truncated"))
                truncated_msgs++;
        }
        free(cut);
    }
    /* Every proper prefix leaves the application collection open, so none
     * may parse; some end mid-item and must say "truncated". */
    CHECK_EQ(ok, 0);
    CHECK_EQ(bad, (int)n);
    CHECK(truncated_msgs > 0);
    free(d);
}

TEST(hid_desc_structural_errors_are_reported)
{
    hid_desc_t *d = malloc(sizeof *d);
    REQUIRE(d);
    static const uint8_t end_without_begin[] = {0x75, 0x08, 0x95, 0x01, 0x81, 0x02, 0xc0};
    static const uint8_t pop_without_push[] = {0xb4};
    static const uint8_t size_zero[] = {0x09, 0x01, 0x95, 0x01, 0x81, 0x02};
    static const uint8_t size_33[] = {0x09, 0x01, 0x75, 0x21, 0x95, 0x01, 0x81, 0x02};
    static const uint8_t id_zero[] = {0x85, 0x00};
    static const uint8_t reserved_type[] = {0x0c};
    static const uint8_t huge_count[] = {0x09, 0x01, 0x75, 0x08, 0x96, 0xff, 0xff, 0x81, 0x02};
    static const uint8_t no_fields[] = {0x05, 0x12};
    struct {
        const uint8_t *b;
        size_t n;
        const char *needle;
    } cases[] = {
        {end_without_begin, sizeof end_without_begin, "End Collection"},
        {pop_without_push, sizeof pop_without_push, "Pop"},
        {size_zero, sizeof size_zero, "report size 0"},
        {size_33, sizeof size_33, "report size 33"},
        {id_zero, sizeof id_zero, "report id 0"},
        {reserved_type, sizeof reserved_type, "reserved"},
        {huge_count, sizeof huge_count, "absurd"},
        {no_fields, sizeof no_fields, "no fields"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        CHECK_EQ(hid_desc_parse(cases[i].b, cases[i].n, d), PP5_E_FORMAT);
        CHECK_MSG(strstr(pp5_error_text(), cases[i].needle) != NULL, "case %zu: '%s' lacks '%s'",
                  i, pp5_error_text(), cases[i].needle);
    }
    CHECK_EQ(hid_desc_parse(NULL, 0, d), PP5_E_FORMAT);
    free(d);
}

TEST(hid_desc_push_pop_ranges_arrays_long_items_and_odd_bits)
{
    hid_desc_t *d = malloc(sizeof *d);
    REQUIRE(d);
    static const uint8_t desc[] = {
        0x05, 0x01, 0x09, 0x02, 0xa1, 0x01, /* Generic Desktop, Mouse, Application */
        0xfe, 0x02, 0x77, 0xaa, 0xbb,       /* long item: skipped */
        0x15, 0xfc, 0x25, 0x03,             /* logical -4..3 */
        0x75, 0x03, 0x95, 0x01,             /* 3 bits */
        0xa4,                               /* Push */
        0x15, 0x00, 0x25, 0x1f, 0x75, 0x05, /* 0..31 in 5 bits */
        0x09, 0x30, 0x81, 0x02,             /* X: 5 bits at 0 */
        0xb4,                               /* Pop: back to -4..3, 3 bits */
        0x09, 0x31, 0x81, 0x02,             /* Y: 3 signed bits at 5 */
        0x05, 0x09, 0x19, 0x01, 0x29, 0x03, /* Buttons 1..3 */
        0x15, 0x00, 0x25, 0x01, 0x75, 0x01, 0x95, 0x03, 0x81, 0x02, /* 3 variables at 8 */
        0x95, 0x01, 0x75, 0x05, 0x81, 0x01, /* 5 bits constant padding at 11 */
        0x19, 0x01, 0x29, 0x08, 0x25, 0x08, 0x75, 0x04, 0x95, 0x02, 0x81, 0x00, /* array */
        0xc0,
    };
    REQUIRE_MSG(hid_desc_parse(desc, sizeof desc, d) == PP5_OK, "%s", pp5_error_text());
    CHECK(!d->uses_report_ids);
    /* 5 + 3 + 3 + 5 + 8 = 24 bits */
    CHECK_EQ(hid_desc_report_bytes(d, HID_REPORT_INPUT, 0), 3);
    const hid_field_t *x = hid_desc_find(d, HID_REPORT_INPUT, 0x01, 0x02, 0x30);
    const hid_field_t *y = hid_desc_find(d, HID_REPORT_INPUT, 0x01, 0x02, 0x31);
    const hid_field_t *b3 = hid_desc_find(d, HID_REPORT_INPUT, 0x09, 0, 3);
    REQUIRE(x && y && b3);
    CHECK_EQ(x->bit_offset, 0);
    CHECK_EQ(x->bit_size, 5);
    CHECK_EQ(y->bit_offset, 5);
    CHECK_EQ(y->bit_size, 3);
    CHECK_EQ(y->logical_min, -4);
    CHECK_EQ(b3->bit_offset, 10);
    /* byte 0 = 0b101_10110: X = 22, Y = 0b101 = -3 (signed 3 bits);
     * byte 1 bit 2 = button 3 */
    uint8_t rep[3] = {0xb6, 0x04, 0x52};
    int64_t v;
    REQUIRE(hid_field_raw(d, x, 0, rep, 3, &v) == PP5_OK);
    CHECK_EQ(v, 22);
    REQUIRE(hid_field_raw(d, y, 0, rep, 3, &v) == PP5_OK);
    CHECK_EQ(v, -3);
    REQUIRE(hid_field_raw(d, b3, 0, rep, 3, &v) == PP5_OK);
    CHECK_EQ(v, 1);
    /* the array: one field, two 4-bit elements at bit 16 */
    const hid_field_t *arr = hid_desc_find(d, HID_REPORT_INPUT, 0x09, 0, 1);
    const hid_field_t *found_arr = NULL;
    for (size_t i = 0; i < d->n_fields; i++)
        if (d->fields[i].count == 2)
            found_arr = &d->fields[i];
    REQUIRE(arr && found_arr);
    CHECK_EQ(found_arr->bit_offset, 16);
    REQUIRE(hid_field_raw(d, found_arr, 1, rep, 3, &v) == PP5_OK);
    CHECK_EQ(v, 5);
    CHECK_EQ(hid_field_raw(d, found_arr, 2, rep, 3, &v), PP5_E_RANGE);
    CHECK_EQ(hid_field_raw(d, found_arr, 1, rep, 2, &v), PP5_E_FORMAT);
    free(d);
}

TEST(hid_eye_reads_gazehid_style_constant_fields_without_units)
{
    /* GazeHid declares gaze fields Input(Cnst,Var,Abs) and relies on the
     * standard's implied micrometres (tracker-devices.md §1.2 quirks). */
    static const uint8_t desc[] = {
        0x05, 0x12, 0x09, 0x01, 0xa1, 0x01,
        0x09, 0x10, 0xa1, 0x02, 0x85, 0x10,
        0x17, 0x80, 0x7b, 0xe1, 0xff, 0x27, 0x80, 0x84, 0x1e, 0x00, 0x75, 0x20,
        0x09, 0x24, 0xa1, 0x00, 0x09, 0x21, 0x09, 0x22, 0x95, 0x02, 0x81, 0x03, 0xc0,
        0xc0, 0xc0,
    };
    hid_eye_layout_t *l = malloc(sizeof *l);
    REQUIRE(l);
    REQUIRE_MSG(hid_eye_layout_init(l, desc, sizeof desc) == PP5_OK, "%s", pp5_error_text());
    CHECK_EQ(l->tracking_bytes, 9);
    CHECK_EQ(l->n_ts, 0);
    uint8_t r[9] = {0x10};
    put_le32(r + 1, -12);
    put_le32(r + 5, 1999999);
    hid_eye_sample_t s;
    REQUIRE(hid_eye_parse_tracking(l, r, sizeof r, &s) == PP5_OK);
    CHECK(!s.has_timestamp);
    CHECK(s.gaze_valid);
    CHECK_NEAR(s.gaze_x_um, -12, 0);
    CHECK_NEAR(s.gaze_y_um, 1999999, 0);
    CHECK(!s.eye_valid[0] && !s.head_valid);

    /* a mouse descriptor is not an eye tracker */
    static const uint8_t mouse[] = {0x05, 0x01, 0x09, 0x02, 0xa1, 0x01, 0x09, 0x30,
                                    0x75, 0x08, 0x95, 0x01, 0x81, 0x02, 0xc0};
    CHECK_EQ(hid_eye_layout_init(l, mouse, sizeof mouse), PP5_E_UNSUPPORTED);
    CHECK(strstr(pp5_error_text(), "Gaze Point") != NULL);
    free(l);
}

/* Deterministic byte mutations of the fixture: the walker must return a
 * status for each (never crash or read out of bounds: run under SAN=1), and
 * whatever it accepts must describe reports it can extract from. */
TEST(hid_desc_mutated_descriptors_never_crash)
{
    hid_desc_t *d = malloc(sizeof *d);
    hid_eye_layout_t *l = malloc(sizeof *l);
    REQUIRE(d && l);
    size_t n = sizeof pp5_fixture_eye_desc;
    uint32_t rng = 12345u;
    int accepted = 0, rejected = 0, extract_ok = 1;
    for (int iter = 0; iter < 3000; iter++) {
        uint8_t *m = malloc(n);
        memcpy(m, pp5_fixture_eye_desc, n);
        int flips = 1 + iter % 4;
        for (int k = 0; k < flips; k++) {
            rng = rng * 1664525u + 1013904223u;
            size_t pos = (rng >> 8) % n;
            rng = rng * 1664525u + 1013904223u;
            m[pos] = (uint8_t)(rng >> 24);
        }
        size_t len = n - (size_t)(iter % 7); /* also cut the tail */
        if (hid_desc_parse(m, len, d) != PP5_OK) {
            rejected++;
        } else {
            accepted++;
            for (size_t i = 0; i < d->n_fields; i++) {
                const hid_field_t *f = &d->fields[i];
                size_t bytes = hid_desc_report_bytes(d, f->type, f->report_id);
                uint8_t *rep = calloc(bytes ? bytes : 1, 1);
                int64_t v;
                for (uint32_t e = 0; e < f->count && e < 4; e++)
                    if (hid_field_raw(d, f, e, rep, bytes, &v) != PP5_OK)
                        extract_ok = 0;
                free(rep);
            }
        }
        hid_eye_layout_init(l, m, len); /* must not crash either */
        free(m);
    }
    CHECK(accepted + rejected == 3000);
    CHECK(rejected > 0);
    CHECK(extract_ok);
    free(d);
    free(l);
}

TEST(hid_desc_physical_range_and_english_units)
{
    /* logical 0..255 mapped onto physical 0..1000, in inches x 10^-2 */
    static const uint8_t desc[] = {
        0x05, 0x01, 0x09, 0x30, 0x15, 0x00, 0x26, 0xff, 0x00, 0x35, 0x00, 0x46, 0xe8, 0x03,
        0x65, 0x13, 0x55, 0x0e, 0x75, 0x08, 0x95, 0x01, 0x81, 0x02,
    };
    hid_desc_t *d = malloc(sizeof *d);
    REQUIRE(d);
    REQUIRE_MSG(hid_desc_parse(desc, sizeof desc, d) == PP5_OK, "%s", pp5_error_text());
    const hid_field_t *f = hid_desc_find(d, HID_REPORT_INPUT, 0x01, 0, 0x30);
    REQUIRE(f);
    CHECK_EQ(f->physical_max, 1000);
    CHECK_EQ(f->unit_exponent, -2);
    /* HID 1.11 §6.2.2.7: physical = raw * (1000 - 0) / (255 - 0) */
    CHECK_NEAR(hid_field_physical(f, 128), 128.0 * 1000.0 / 255.0, 1e-9);
    CHECK_NEAR(hid_field_physical(f, 255), 1000.0, 1e-9);
    double factor = 0;
    /* unit 0x13: English linear, length^1 = inch = 0.0254 m */
    CHECK_EQ(hid_field_si_factor(f, &factor), HID_UNIT_LENGTH);
    CHECK_NEAR(factor, 0.0254e-2, 1e-15);
    free(d);
}
