/* test_bounds.c: no input makes pp5 allocate, loop or recurse without bound.
 *
 * The worst cases of issue 14: headers that promise 2^31 voxels (refused by
 * PP5_MAX_VOXELS before any allocation, in raw, NRRD, NIfTI and .den), NRRD
 * detached data-file lists that name the header itself, another header, or
 * two billion files, and an EyeLink file of one 100 MB line (refused after
 * reading the first PP5_MAX_LINE_BYTES; the test writes the file in 1 MB
 * pieces and times the refusal).  Each limit can be raised through its
 * environment variable, which the tests check too (each test runs in its
 * own process, so setenv does not leak into the others). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "harness.h"
#include "emu/util/input_limits.h"
#include "render/volume.h"
#include "tracker/import.h"
#include "tracker/trace_file.h"

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    REQUIRE(f != NULL);
    fputs(text, f);
    REQUIRE(fclose(f) == 0);
}

static double seconds_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

TEST(bounds_nrrd_header_of_2_31_voxels_is_refused_before_allocation)
{
    const char *dir = pp5_test_outdir();
    char path[1200];
    snprintf(path, sizeof path, "%s/tiny.raw", dir);
    write_text(path, "16 bytes of data");
    snprintf(path, sizeof path, "%s/huge.nhdr", dir);
    /* 2048 x 1024 x 1024 = 2^31 doubles = 16 GiB, with a 16-byte data file:
     * the size alone must be refused, before Teem or pp5 allocates. */
    write_text(path, "NRRD0004\ntype: double\ndimension: 3\nsizes: 2048 1024 1024\n"
                     "endian: little\nencoding: raw\ndata file: tiny.raw\n");
    volume_t v;
    CHECK_EQ(volume_load(path, NULL, &v), PP5_E_RANGE);
    const char *e = pp5_error_text();
    CHECK_MSG(strstr(e, "2147483648 voxels") && strstr(e, "PP5_MAX_VOXELS") &&
              strstr(e, "huge.nhdr"), "%s", e);
}

TEST(bounds_raw_nifti_and_den_headers_of_2_31_voxels_are_refused)
{
    const char *dir = pp5_test_outdir();
    char path[1200];
    volume_t v;
    /* raw: the layout from the name (2^31 u8 voxels); the file is empty */
    snprintf(path, sizeof path, "%s/big_2048x1024x1024_u8.raw", dir);
    write_text(path, "");
    CHECK_EQ(volume_load(path, NULL, &v), PP5_E_RANGE);
    CHECK(strstr(pp5_error_text(), "PP5_MAX_VOXELS") != NULL);
    /* NIfTI: dim = 3, 2048, 1024, 1024 in a 348-byte header + 4 bytes */
    uint8_t h[352] = {0};
    h[0] = 0x5c;
    h[1] = 0x01;                             /* sizeof_hdr = 348, little-endian */
    const int16_t dim[4] = {3, 2048, 1024, 1024};
    for (int i = 0; i < 4; i++) {
        h[40 + 2 * i] = (uint8_t)(dim[i] & 0xff);
        h[41 + 2 * i] = (uint8_t)(dim[i] >> 8);
    }
    h[70] = 2;                               /* DT_UINT8 */
    h[72] = 8;                               /* bitpix */
    memcpy(h + 108, "\x00\x00\xb0\x43", 4);  /* vox_offset = 352.0f */
    memcpy(h + 344, "n+1", 4);
    snprintf(path, sizeof path, "%s/big.nii", dir);
    FILE *f = fopen(path, "wb");
    REQUIRE(f && fwrite(h, 1, sizeof h, f) == sizeof h && fclose(f) == 0);
    CHECK_EQ(volume_load(path, NULL, &v), PP5_E_RANGE);
    CHECK_MSG(strstr(pp5_error_text(), "PP5_MAX_VOXELS") != NULL, "%s", pp5_error_text());
    /* .den: map 2048 x 1024 x 1024 (all three boxes alike), 62-byte header */
    uint8_t d[62] = {0};
    d[0] = 1;                                /* map_version 1, little-endian */
    const int side[3] = {2048, 1024, 1024};
    for (int box = 0; box < 3; box++)
        for (int a = 0; a < 3; a++) {
            int max = side[a] - 1, at = 2 + 18 * box + 2 * a;
            d[at + 6] = (uint8_t)(max & 0xff);        /* max */
            d[at + 7] = (uint8_t)(max >> 8);
            d[at + 12] = (uint8_t)(side[a] & 0xff);   /* len */
            d[at + 13] = (uint8_t)(side[a] >> 8);
        }
    snprintf(path, sizeof path, "%s/big.den", dir);
    f = fopen(path, "wb");
    REQUIRE(f && fwrite(d, 1, sizeof d, f) == sizeof d && fclose(f) == 0);
    CHECK_EQ(volume_load(path, NULL, &v), PP5_E_RANGE);
    CHECK_MSG(strstr(pp5_error_text(), "2147483648 voxels") != NULL, "%s", pp5_error_text());
}

TEST(bounds_raising_the_voxel_limit_lets_a_volume_through)
{
    const char *dir = pp5_test_outdir();
    char path[1200];
    snprintf(path, sizeof path, "%s/v_4x4x4_u8.raw", dir);
    FILE *f = fopen(path, "wb");
    uint8_t bytes[64] = {0};
    REQUIRE(f && fwrite(bytes, 1, 64, f) == 64 && fclose(f) == 0);
    volume_t v;
    setenv("PP5_MAX_VOXELS", "63", 1);
    CHECK_EQ(volume_load(path, NULL, &v), PP5_E_RANGE);
    CHECK(strstr(pp5_error_text(), "64 voxels is over the limit of 63") != NULL);
    setenv("PP5_MAX_VOXELS", "64", 1);
    REQUIRE(volume_load(path, NULL, &v) == PP5_OK);
    CHECK_EQ(v.nx * v.ny * v.nz, 64);
    volume_free(&v);
    /* A malformed value is ignored (with a warning), not taken as 0. */
    setenv("PP5_MAX_VOXELS", "lots", 1);
    CHECK_EQ(pp5_limit(PP5_LIMIT_VOXELS), pp5_limit_default(PP5_LIMIT_VOXELS));
    unsetenv("PP5_MAX_VOXELS");
}

TEST(bounds_nrrd_data_file_naming_the_header_itself_is_refused)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/self.nhdr", pp5_test_outdir());
    /* Teem would read this header's own text as the 8 voxels. */
    write_text(path, "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n"
                     "data file: self.nhdr\n");
    volume_t v;
    CHECK_EQ(volume_load(path, NULL, &v), PP5_E_FORMAT);
    CHECK_MSG(strstr(pp5_error_text(), "is the header itself") != NULL, "%s", pp5_error_text());
    /* the same through a LIST, and through a pattern that reaches it */
    write_text(path, "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n"
                     "data file: LIST\nother.raw\nself.nhdr\n");
    CHECK_EQ(volume_load(path, NULL, &v), PP5_E_FORMAT);
    CHECK(strstr(pp5_error_text(), "is the header itself") != NULL);
}

/* Teem's message about a missing file of a LIST reads past its line buffer
 * when the name is 16 to 39 characters long (the fuzzer's find): pp5 names
 * the file itself, for every way a header can name one. */
TEST(bounds_nrrd_missing_data_file_is_named)
{
    char path[1200], data[1200];
    snprintf(path, sizeof path, "%s/missing.nhdr", pp5_test_outdir());
    snprintf(data, sizeof data, "%s/present.raw", pp5_test_outdir());
    write_text(data, "1234");   /* one 2x2 slice: a LIST names one file per slice */
    const char *head = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n";
    const char *tails[] = {
        "data file: LIST\npresent.raw\nno-such-file-of-24-chars\n",
        "data file: LIST\nno-such-file-of-24-chars\n",
        "data file: no-such-file-of-24-chars\n",
        "data file: no-such-%d.raw 1 2 1\n",
    };
    const char *names[] = {"no-such-file-of-24-chars", "no-such-file-of-24-chars",
                           "no-such-file-of-24-chars", "no-such-1.raw"};
    for (int i = 0; i < 4; i++) {
        char text[512];
        snprintf(text, sizeof text, "%s%s", head, tails[i]);
        write_text(path, text);
        volume_t v;
        CHECK_EQ(volume_load(path, NULL, &v), PP5_E_IO);
        CHECK_MSG(strstr(pp5_error_text(), names[i]) && strstr(pp5_error_text(), "missing.nhdr"),
                  "%s", pp5_error_text());
    }
    /* the same header with the files present loads */
    char text[512];
    snprintf(text, sizeof text, "%sdata file: LIST\npresent.raw\npresent.raw\n", head);
    write_text(path, text);
    volume_t v;
    pp5_status_t st = volume_load(path, NULL, &v);
    CHECK_MSG(st == PP5_OK, "%s", pp5_error_text());
    if (st == PP5_OK)
        volume_free(&v);
}

TEST(bounds_nrrd_data_file_that_is_another_header_is_refused)
{
    const char *dir = pp5_test_outdir();
    char a[1200], b[1200];
    snprintf(a, sizeof a, "%s/a.nhdr", dir);
    snprintf(b, sizeof b, "%s/b.nhdr", dir);
    /* a names b, b names a: a cycle, if headers could nest (they cannot). */
    write_text(a, "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n"
                  "data file: b.nhdr\n");
    write_text(b, "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n"
                  "data file: a.nhdr\n");
    volume_t v;
    CHECK_EQ(volume_load(a, NULL, &v), PP5_E_FORMAT);
    CHECK_MSG(strstr(pp5_error_text(), "'b.nhdr' is itself a NRRD header") != NULL, "%s",
              pp5_error_text());
}

TEST(bounds_nrrd_pattern_of_two_billion_files_is_refused_without_looping)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/many.nhdr", pp5_test_outdir());
    write_text(path, "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n"
                     "data file: slice%05d.raw 1 2000000000 1 2\n");
    volume_t v;
    double t0 = seconds_now();
    CHECK_EQ(volume_load(path, NULL, &v), PP5_E_RANGE);
    CHECK_MSG(strstr(pp5_error_text(), "2000000000 data files") &&
              strstr(pp5_error_text(), "PP5_MAX_DATA_FILES"), "%s", pp5_error_text());
    CHECK(seconds_now() - t0 < 1.0);
    /* Teem would pass the pattern to sprintf: anything but one integer
     * conversion is refused. */
    write_text(path, "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n"
                     "data file: %s%n%d 1 2 1\n");
    CHECK_EQ(volume_load(path, NULL, &v), PP5_E_FORMAT);
    CHECK(strstr(pp5_error_text(), "exactly one integer conversion") != NULL);
}

TEST(bounds_nrrd_header_larger_than_the_limit_is_refused)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/long.nhdr", pp5_test_outdir());
    FILE *f = fopen(path, "wb");
    REQUIRE(f != NULL);
    fputs("NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n", f);
    for (int i = 0; i < 3000; i++)
        fputs("# a comment line that makes the header longer than 64 KiB\n", f);
    fputs("data file: d.raw\n", f);
    REQUIRE(fclose(f) == 0);
    setenv("PP5_MAX_HEADER_BYTES", "65536", 1);
    volume_t v;
    CHECK_EQ(volume_load(path, NULL, &v), PP5_E_RANGE);
    CHECK_MSG(strstr(pp5_error_text(), "PP5_MAX_HEADER_BYTES") != NULL, "%s", pp5_error_text());
    unsetenv("PP5_MAX_HEADER_BYTES");
}

/* Writes an EyeLink preamble and then one line of `mb` MB, 1 MB at a time. */
static void write_one_long_line(const char *path, int mb)
{
    FILE *f = fopen(path, "wb");
    REQUIRE(f != NULL);
    fputs("** CONVERTED FROM x.edf\nMSG\t1 DISPLAY_COORDS 0 0 1023 767\n", f);
    char *chunk = malloc(1 << 20);
    REQUIRE(chunk != NULL);
    memset(chunk, '7', 1 << 20);
    for (int i = 0; i < mb; i++)
        REQUIRE(fwrite(chunk, 1, 1 << 20, f) == 1u << 20);
    fputc('\n', f);
    free(chunk);
    REQUIRE(fclose(f) == 0);
}

TEST(bounds_eyelink_file_of_one_100_mb_line_is_refused_quickly)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/one-line.asc", pp5_test_outdir());
    write_one_long_line(path, 100);
    double t0 = seconds_now();
    trace_t t;
    import_options_t o;
    import_defaults(&o);
    CHECK_EQ(import_file(path, IMPORT_EYELINK, &o, &t), PP5_E_RANGE);
    double s = seconds_now() - t0;
    const char *e = pp5_error_text();
    CHECK_MSG(strstr(e, "one-line.asc:3: the line is longer than the limit of 65536 bytes "
                     "(PP5_MAX_LINE_BYTES") != NULL, "%s", e);
    /* The reader stops after the limit: far less than reading 100 MB. */
    CHECK_MSG(s < 0.5, "refusal took %.3f s", s);
    /* The trace reader reads through the same code. */
    CHECK_EQ(trace_read_file(path, &t), PP5_E_RANGE);
    CHECK(strstr(pp5_error_text(), "PP5_MAX_LINE_BYTES") != NULL);
}

TEST(bounds_trace_sample_limit_is_named_and_can_be_raised)
{
    trace_t t;
    trace_init(&t);
    setenv("PP5_MAX_TRACE_SAMPLES", "3", 1);
    gaze_sample_t s;
    pp5_status_t st = PP5_OK;
    int appended = 0;
    for (int i = 0; i < 5 && st == PP5_OK; i++) {
        gaze_sample_invalid(&s, (int64_t)i * 1000000);
        st = trace_append(&t, &s);
        appended += st == PP5_OK;
    }
    CHECK_EQ(appended, 3);
    CHECK_EQ(st, PP5_E_RANGE);
    CHECK(strstr(pp5_error_text(), "PP5_MAX_TRACE_SAMPLES") != NULL);
    trace_free(&t);
    unsetenv("PP5_MAX_TRACE_SAMPLES");
}
