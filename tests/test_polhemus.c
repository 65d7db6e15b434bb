/* test_polhemus.c: Polhemus Patriot/Liberty binary records (tracker/polhemus.c)
 * and Fastrak binary/ASCII records (tracker/fastrak.c) on byte arrays,
 * including truncated and corrupted input.  Records are assembled here from
 * the layout in ../shared/docs/tracker-devices.md §2.3. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "tracker/fastrak.h"
#include "tracker/polhemus.h"

static size_t put_float(uint8_t *p, float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(u >> (8 * i));
    return 4;
}

/* One O*,2,4,1 record: 8-byte header, 6 floats, CR LF (34 bytes). */
static size_t put_record(uint8_t *p, const char *tag, uint8_t station, uint8_t err,
                         const float v[6])
{
    p[0] = (uint8_t)tag[0];
    p[1] = (uint8_t)tag[1];
    p[2] = station;
    p[3] = 'P';
    p[4] = err;
    p[5] = 0;
    p[6] = 26;
    p[7] = 0;
    size_t n = 8;
    for (int i = 0; i < 6; i++)
        n += put_float(p + n, v[i]);
    p[n++] = '\r';
    p[n++] = '\n';
    return n;
}

static const float head_v[6] = {10.0f, -2.5f, 30.25f, 5.0f, -10.0f, 0.5f};
static const float hand_v[6] = {35.0f, 12.0f, 20.0f, 90.0f, 0.0f, -45.0f};

TEST(polhemus_model_table_matches_the_documented_ids)
{
    /* tracker-devices.md §2.1 */
    const polhemus_model_t *m = polhemus_model_for_pid(0xef12);
    REQUIRE(m);
    CHECK_EQ(m->ep_out, 0x02);
    CHECK_EQ(m->ep_in, 0x82);
    CHECK(strcmp(m->tag, "PA") == 0);
    m = polhemus_model_for_pid(0xff20);
    REQUIRE(m);
    CHECK_EQ(m->ep_out, 0x04);
    CHECK_EQ(m->ep_in, 0x88);
    m = polhemus_model_for_pid(0xef20);
    REQUIRE(m);
    CHECK_EQ(m->ep_in, 0x88);
    CHECK(polhemus_model_for_pid(0xff12) != NULL);
    CHECK(polhemus_model_for_pid(0xef11) == NULL);
    CHECK(polhemus_pid_needs_firmware(0xef11));
    CHECK(polhemus_pid_needs_firmware(0xff21));
    CHECK(!polhemus_pid_needs_firmware(0xef12));
}

TEST(polhemus_parses_head_and_hand_records)
{
    uint8_t buf[68];
    size_t n = put_record(buf, "PA", 1, 0, head_v);
    CHECK_EQ(n, 34);
    n += put_record(buf + n, "PA", 2, 0, hand_v);
    polhemus_record_t r[4];
    size_t got = 0;
    REQUIRE_MSG(polhemus_parse_records(buf, n, "PA", r, 4, &got) == PP5_OK, "%s",
                pp5_error_text());
    REQUIRE(got == 2);
    CHECK_EQ(r[0].station, 1);
    CHECK_EQ(r[0].command, 'P');
    CHECK(polhemus_record_ok(&r[0]));
    CHECK_NEAR(r[0].pos_cm[0], 10.0, 0);
    CHECK_NEAR(r[0].pos_cm[1], -2.5, 0);
    CHECK_NEAR(r[0].pos_cm[2], 30.25, 0);
    CHECK_NEAR(r[0].euler_deg[0], 5.0, 0);
    CHECK_NEAR(r[0].euler_deg[1], -10.0, 0);
    CHECK_NEAR(r[0].euler_deg[2], 0.5, 0);
    CHECK_EQ(r[1].station, 2);
    CHECK_NEAR(r[1].euler_deg[2], -45.0, 0);
    /* a Liberty record, and 'LU' accepted for a Liberty HS / Latus */
    put_record(buf, "LU", 3, ' ', hand_v);
    REQUIRE(polhemus_parse_records(buf, 34, "LY", r, 4, &got) == PP5_OK);
    CHECK_EQ(got, 1);
    CHECK(polhemus_record_ok(&r[0]));
    /* an error indicator is carried, not fatal */
    put_record(buf, "PA", 1, 'E', head_v);
    REQUIRE(polhemus_parse_records(buf, 34, "PA", r, 4, &got) == PP5_OK);
    CHECK(!polhemus_record_ok(&r[0]));
}

TEST(polhemus_every_truncation_is_a_clean_error)
{
    uint8_t full[68];
    size_t n = put_record(full, "PA", 1, 0, head_v);
    n += put_record(full + n, "PA", 2, 0, hand_v);
    polhemus_record_t r[4];
    size_t got;
    int errors = 0;
    for (size_t len = 0; len < n; len++) {
        if (len == 34)
            continue; /* exactly one whole record: valid */
        uint8_t *cut = malloc(len ? len : 1);
        memcpy(cut, full, len);
        if (polhemus_parse_records(cut, len, "PA", r, 4, &got) == PP5_E_FORMAT)
            errors++;
        free(cut);
    }
    CHECK_EQ(errors, (int)n - 1);
    CHECK(strstr(pp5_error_text(), "truncated") != NULL);
}

TEST(polhemus_rejects_bad_tag_size_station_nan_and_overflow)
{
    uint8_t buf[68];
    polhemus_record_t r[4];
    size_t got;
    put_record(buf, "PA", 1, 0, head_v);
    CHECK_EQ(polhemus_parse_records(buf, 34, "LY", r, 4, &got), PP5_E_FORMAT);
    CHECK(strstr(pp5_error_text(), "expected 'LY'") != NULL);
    buf[6] = 30; /* size not 24/26 */
    CHECK_EQ(polhemus_parse_records(buf, 34, "PA", r, 4, &got), PP5_E_FORMAT);
    CHECK(strstr(pp5_error_text(), "payload bytes") != NULL);
    put_record(buf, "PA", 0, 0, head_v); /* station 0 */
    CHECK_EQ(polhemus_parse_records(buf, 34, "PA", r, 4, &got), PP5_E_FORMAT);
    float bad[6] = {1, 2, NAN, 4, 5, 6};
    put_record(buf, "PA", 1, 0, bad);
    CHECK_EQ(polhemus_parse_records(buf, 34, "PA", r, 4, &got), PP5_E_FORMAT);
    CHECK(strstr(pp5_error_text(), "non-finite") != NULL);
    put_record(buf, "PA", 1, 0, head_v);
    buf[33] = 'x'; /* not CR LF */
    CHECK_EQ(polhemus_parse_records(buf, 34, "PA", r, 4, &got), PP5_E_FORMAT);
    put_record(buf, "PA", 1, 0, head_v);
    put_record(buf + 34, "PA", 2, 0, hand_v);
    CHECK_EQ(polhemus_parse_records(buf, 68, "PA", r, 1, &got), PP5_E_FORMAT);
    CHECK_EQ(polhemus_parse_records(buf, 0, "PA", r, 1, &got), PP5_E_FORMAT);
}

/* A Fastrak binary record for output list 2,4 (+ item 0 when `space`). */
static size_t put_fastrak(uint8_t *p, char station, char status, const float v[6], bool space)
{
    p[0] = '0';
    p[1] = (uint8_t)station;
    p[2] = (uint8_t)status;
    size_t n = 3;
    for (int i = 0; i < 6; i++)
        n += put_float(p + n, v[i]);
    if (space)
        p[n++] = ' ';
    return n;
}

TEST(fastrak_binary_records_and_resynchronisation)
{
    fastrak_format_t fmt = {6, true};
    uint8_t buf[128];
    size_t n = 0;
    buf[n++] = 0xff; /* garbage before the first record */
    buf[n++] = 'x';
    n += put_fastrak(buf + n, '1', ' ', head_v, true);
    n += put_fastrak(buf + n, '2', 'B', hand_v, true);
    fastrak_record_t r;
    size_t used, skipped;
    REQUIRE_MSG(fastrak_parse_binary(buf, n, &fmt, &r, &used, &skipped) == PP5_OK, "%s",
                pp5_error_text());
    CHECK_EQ(skipped, 2);
    CHECK_EQ(used, 2 + 28);
    CHECK_EQ(r.station, 1);
    CHECK_EQ(r.status, ' ');
    CHECK_NEAR(r.values[2], 30.25, 0);
    CHECK_NEAR(r.values[5], 0.5, 0);
    REQUIRE(fastrak_parse_binary(buf + used, n - used, &fmt, &r, &used, &skipped) == PP5_OK);
    CHECK_EQ(r.station, 2);
    CHECK_EQ(r.status, 'B');
    CHECK_NEAR(r.values[3], 90.0, 0);
    /* truncations: never a record, never an overread */
    int errors = 0;
    for (size_t len = 0; len < 28; len++) {
        uint8_t *cut = malloc(len ? len : 1);
        memcpy(cut, buf + 2, len);
        if (fastrak_parse_binary(cut, len, &fmt, &r, &used, &skipped) == PP5_E_FORMAT)
            errors++;
        free(cut);
    }
    CHECK_EQ(errors, 28);
    /* missing trailing space, bad status */
    put_fastrak(buf, '1', ' ', head_v, false);
    buf[27] = '#';
    CHECK_EQ(fastrak_parse_binary(buf, 28, &fmt, &r, &used, &skipped), PP5_E_FORMAT);
    put_fastrak(buf, '1', 'z', head_v, true);
    CHECK_EQ(fastrak_parse_binary(buf, 28, &fmt, &r, &used, &skipped), PP5_E_FORMAT);
    CHECK_EQ(used, 1); /* dropping the false start lets the caller resynchronise */
}

TEST(fastrak_ascii_records_fixed_width_and_spaced)
{
    fastrak_format_t fmt = {6, false};
    /* fixed width "Sxxx.xx": a negative field touches its neighbour */
    const char *rec = "01   10.00  -2.50  30.25   5.00-100.00   0.50\r\n"
                      "02A  35.00  12.00  20.00  90.00   0.00 -45.00\r\n";
    fastrak_record_t r;
    size_t used, skipped;
    size_t len = strlen(rec);
    REQUIRE_MSG(fastrak_parse_ascii(rec, len, &fmt, &r, &used, &skipped) == PP5_OK, "%s",
                pp5_error_text());
    CHECK_EQ(r.station, 1);
    CHECK_NEAR(r.values[0], 10.0, 1e-12);
    CHECK_NEAR(r.values[1], -2.5, 1e-12);
    CHECK_NEAR(r.values[4], -100.0, 1e-12);
    CHECK_NEAR(r.values[5], 0.5, 1e-12);
    CHECK_EQ(used, 47);
    REQUIRE(fastrak_parse_ascii(rec + used, len - used, &fmt, &r, &used, &skipped) == PP5_OK);
    CHECK_EQ(r.station, 2);
    CHECK_EQ(r.status, 'A');
    CHECK_NEAR(r.values[5], -45.0, 1e-12);
    /* too few values, extra text, no CR LF, truncations */
    const char *few = "01 1.0 2.0 3.0\r\n";
    CHECK_EQ(fastrak_parse_ascii(few, strlen(few), &fmt, &r, &used, &skipped), PP5_E_FORMAT);
    CHECK(strstr(pp5_error_text(), "value 4 of 6") != NULL);
    const char *extra = "01 1 2 3 4 5 6 7\r\n";
    CHECK_EQ(fastrak_parse_ascii(extra, strlen(extra), &fmt, &r, &used, &skipped), PP5_E_FORMAT);
    int errors = 0;
    for (size_t cut = 0; cut < 47; cut++) {
        char *c = malloc(cut ? cut : 1);
        memcpy(c, rec, cut);
        if (fastrak_parse_ascii(c, cut, &fmt, &r, &used, &skipped) == PP5_E_FORMAT)
            errors++;
        free(c);
    }
    CHECK_EQ(errors, 47);
}
