/* test_volume_formats.c: the NRRD, NIfTI-1, .den and slice-series loaders on
 * files the tests write by hand, good and malformed. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "harness.h"
#include "render/volume.h"
#include "volume_test_files.h"

/* ---- NRRD ---------------------------------------------------------------- */

/* Writes a NRRD header (hand-written per the NRRD0004 format) and data. */
static void write_nrrd(const char *path, const char *header, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    REQUIRE(f != NULL);
    fputs(header, f);
    if (n)
        REQUIRE(fwrite(data, 1, n, f) == n);
    fclose(f);
}

TEST(vol_nrrd_attached_detached_and_ascii)
{
    new_dir();
    uint8_t data[3 * 2 * 2 * 2];
    for (int i = 0; i < 12; i++)
        put16(data + 2 * i, (unsigned)(i * 300 - 1000) & 0xffff, true);   /* signed shorts */
    const char *p = out_path("a.nrrd");
    write_nrrd(p, "NRRD0004\ntype: short\ndimension: 3\nsizes: 3 2 2\nspacings: 1.5 2 3\n"
                  "endian: big\nencoding: raw\n\n", data, sizeof data);
    volume_t v;
    volume_file_info_t info;
    REQUIRE_MSG(volume_load_info(p, NULL, &v, &info) == PP5_OK, "%s", pp5_error_text());
    CHECK_EQ(v.nx, 3);
    CHECK_EQ(v.ny, 2);
    CHECK_EQ(v.nz, 2);
    CHECK_NEAR(volume_at(&v, 0, 0, 0), -1000, 0);
    CHECK_NEAR(volume_at(&v, 2, 0, 0), -400, 0);
    CHECK_NEAR(volume_at(&v, 0, 1, 0), -100, 0);
    CHECK_NEAR(volume_at(&v, 2, 1, 1), 2300, 0);
    CHECK_NEAR(v.spacing[0], 1.5, 1e-12);
    CHECK_NEAR(v.spacing[2], 3.0, 1e-12);
    CHECK(strcmp(info.format, "nrrd") == 0);
    CHECK_EQ(info.stored_type, VOXEL_I16);
    volume_free(&v);

    /* Detached header with space directions (spacing = vector length). */
    const char *raw = out_path("d.raw");
    write_bytes(raw, data, sizeof data);
    const char *h = out_path("d.nhdr");
    write_nrrd(h, "NRRD0004\ntype: int16\ndimension: 3\nsizes: 3 2 2\nspace: 3D-right-handed\n"
                  "space directions: (0,0.5,0) (2,0,0) (0,0,4)\nendian: big\nencoding: raw\n"
                  "data file: d.raw\n\n", NULL, 0);
    REQUIRE_MSG(volume_load(h, NULL, &v) == PP5_OK, "%s", pp5_error_text());
    CHECK_NEAR(volume_at(&v, 2, 1, 1), 2300, 0);
    CHECK_NEAR(v.spacing[0], 0.5, 1e-12);
    CHECK_NEAR(v.spacing[1], 2.0, 1e-12);
    CHECK_NEAR(v.spacing[2], 4.0, 1e-12);
    volume_free(&v);

    const char *t = out_path("t.nrrd");
    write_nrrd(t, "NRRD0004\ntype: float\ndimension: 3\nsizes: 2 1 2\nencoding: ascii\n\n"
                  "0.5 -2\n7.25 1e3\n", NULL, 0);
    REQUIRE_MSG(volume_load(t, NULL, &v) == PP5_OK, "%s", pp5_error_text());
    CHECK_NEAR(volume_at(&v, 1, 0, 0), -2, 0);
    CHECK_NEAR(volume_at(&v, 0, 0, 1), 7.25, 0);
    CHECK_NEAR(v.max_value, 1000, 0);
    volume_free(&v);
}

TEST(vol_nrrd_rejects_malformed)
{
    new_dir();
    uint8_t data[64] = {0};
    volume_t v;
    memset(&v, 0, sizeof v);
    struct { const char *name, *header; size_t n; pp5_status_t want; } cases[] = {
        {"trunc.nrrd", "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 4\nencoding: raw\n\n", 40,
         PP5_E_FORMAT},
        {"long.nrrd", "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n", 9,
         PP5_E_FORMAT},
        {"twod.nrrd", "NRRD0004\ntype: uchar\ndimension: 2\nsizes: 4 4\nencoding: raw\n\n", 16,
         PP5_E_FORMAT},
        {"huge.nrrd", "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 100000 100000 100000\n"
                      "encoding: raw\n\n", 8, PP5_E_RANGE},
        {"big.nrrd", "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4096 4096 4096\n"
                     "encoding: raw\n\n", 8, PP5_E_RANGE},
        {"zero.nrrd", "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 0 4 4\nencoding: raw\n\n", 8,
         PP5_E_FORMAT},
        {"type.nrrd", "NRRD0004\ntype: quaternion\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n",
         8, PP5_E_FORMAT},
        {"llong.nrrd", "NRRD0004\ntype: int64\ndimension: 3\nsizes: 2 2 2\nendian: little\n"
                       "encoding: raw\n\n", 64, PP5_E_FORMAT},
        {"magic.nrrd", "NRRX0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n", 8,
         PP5_E_FORMAT},
        {"enc.nrrd", "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: morse\n\n", 8,
         PP5_E_FORMAT},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const char *p = out_path(cases[i].name);
        write_nrrd(p, cases[i].header, data, cases[i].n);
        pp5_status_t st = volume_load(p, NULL, &v);
        CHECK_MSG(st == cases[i].want, "%s: status %d, want %d (%s)", cases[i].name, st,
                  cases[i].want, pp5_error_text());
        CHECK_MSG(strstr(pp5_error_text(), cases[i].name) != NULL, "message names the file: %s",
                  pp5_error_text());
    }
    float nan_data[8] = {0, 0, 0, NAN, 0, 0, 0, 0};
    const char *p = out_path("nan.nrrd");
    write_nrrd(p, "NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 2\nendian: little\n"
                  "encoding: raw\n\n", nan_data, sizeof nan_data);
    CHECK_EQ(volume_load(p, NULL, &v), PP5_E_FORMAT);
    CHECK(v.data == NULL);
}

/* ---- NIfTI-1 ------------------------------------------------------------- */

TEST(vol_nifti_hand_written_plain_gzip_and_big_endian)
{
    new_dir();
    const short dims[8] = {3, 4, 3, 2, 1, 1, 1, 1};
    const float pix[4] = {1, 0.9f, 1.1f, 2.5f};
    for (int be = 0; be < 2; be++) {
        uint8_t file[352 + 24 * 2];
        nifti_header(file, dims, 4 /* DT_INT16 */, 16, pix, 2.0f, -5.0f, be);
        for (int i = 0; i < 24; i++)
            put16(file + 352 + 2 * i, (unsigned)(i * 10 - 50) & 0xffff, be);
        const char *p = out_path(be ? "b.nii" : "l.nii");
        write_bytes(p, file, sizeof file);
        volume_t v;
        volume_file_info_t info;
        REQUIRE_MSG(volume_load_info(p, NULL, &v, &info) == PP5_OK, "be %d: %s", be,
                    pp5_error_text());
        CHECK_EQ(v.nx, 4);
        CHECK_EQ(v.ny, 3);
        CHECK_EQ(v.nz, 2);
        /* stored -50 + 10 i, scaled by 2 and shifted by -5 */
        CHECK_NEAR(volume_at(&v, 0, 0, 0), -105, 0);
        CHECK_NEAR(volume_at(&v, 3, 2, 1), (23 * 10 - 50) * 2 - 5, 0);
        CHECK_NEAR(volume_at(&v, 1, 2, 0), (9 * 10 - 50) * 2 - 5, 0);
        CHECK_NEAR(v.spacing[0], 0.9, 1e-6);
        CHECK_NEAR(v.spacing[2], 2.5, 1e-6);
        CHECK(strcmp(info.format, "nifti") == 0);
        CHECK_EQ(info.stored_type, VOXEL_I16);
        CHECK_EQ(info.big_endian, be);
        volume_free(&v);
        if (!be) {
            const char *g = out_path("l.nii.gz");
            write_gz(g, file, sizeof file);
            REQUIRE_MSG(volume_load(g, NULL, &v) == PP5_OK, "%s", pp5_error_text());
            CHECK_NEAR(volume_at(&v, 3, 2, 1), (23 * 10 - 50) * 2 - 5, 0);
            volume_free(&v);
        }
    }
}

TEST(vol_nifti_rejects_malformed)
{
    new_dir();
    const float pix[4] = {1, 1, 1, 1};
    uint8_t file[352 + 64];
    volume_t v;
    memset(&v, 0, sizeof v);
    const short good[8] = {3, 4, 4, 4, 1, 1, 1, 1};
    nifti_header(file, good, 2 /* DT_UINT8 */, 8, pix, 0, 0, false);
    memset(file + 352, 7, 64);
    write_bytes(out_path("ok.nii"), file, sizeof file);
    REQUIRE_MSG(volume_load(out_path("ok.nii"), NULL, &v) == PP5_OK, "%s", pp5_error_text());
    CHECK_NEAR(v.max_value, 7, 0);
    volume_free(&v);

    write_bytes(out_path("trunc.nii"), file, sizeof file - 10);
    CHECK_EQ(volume_load(out_path("trunc.nii"), NULL, &v), PP5_E_FORMAT);
    uint8_t longer[sizeof file + 5] = {0};
    memcpy(longer, file, sizeof file);
    write_bytes(out_path("long.nii"), longer, sizeof longer);
    CHECK_EQ(volume_load(out_path("long.nii"), NULL, &v), PP5_E_FORMAT);
    uint8_t junk[400];
    memset(junk, 'x', sizeof junk);
    write_bytes(out_path("junk.nii"), junk, sizeof junk);
    CHECK_EQ(volume_load(out_path("junk.nii"), NULL, &v), PP5_E_FORMAT);
    const short series[8] = {4, 4, 4, 2, 2, 1, 1, 1};
    nifti_header(file, series, 2, 8, pix, 0, 0, false);
    write_bytes(out_path("series.nii"), file, sizeof file);
    CHECK_EQ(volume_load(out_path("series.nii"), NULL, &v), PP5_E_FORMAT);
    const short huge[8] = {3, 30000, 30000, 30000, 1, 1, 1, 1};
    nifti_header(file, huge, 2, 8, pix, 0, 0, false);
    write_bytes(out_path("huge.nii"), file, sizeof file);
    pp5_status_t st = volume_load(out_path("huge.nii"), NULL, &v);
    CHECK_MSG(st == PP5_E_RANGE || st == PP5_E_FORMAT, "huge: %d %s", st, pp5_error_text());
    nifti_header(file, good, 32 /* DT_COMPLEX64 */, 64, pix, 0, 0, false);
    write_bytes(out_path("complex.nii"), file, sizeof file);
    CHECK_EQ(volume_load(out_path("complex.nii"), NULL, &v), PP5_E_FORMAT);
    CHECK(v.data == NULL);
}

/* ---- .den ----------------------------------------------------------------- */


TEST(vol_den_both_byte_orders_and_gzip)
{
    new_dir();
    for (int be = 0; be < 2; be++) {
        uint8_t file[62 + 24];
        den_header(file, 4, 3, 2, 8, 6, 5, 24, be);
        for (int i = 0; i < 24; i++)
            file[62 + i] = (uint8_t)(i * 10);
        const char *p = out_path(be ? "b.den" : "l.den");
        write_bytes(p, file, sizeof file);
        volume_t v;
        volume_file_info_t info;
        REQUIRE_MSG(volume_load_info(p, NULL, &v, &info) == PP5_OK, "%s", pp5_error_text());
        CHECK_EQ(v.nx, 4);
        CHECK_EQ(v.ny, 3);
        CHECK_EQ(v.nz, 2);
        CHECK_NEAR(volume_at(&v, 3, 2, 1), 230, 0);
        CHECK_NEAR(volume_at(&v, 1, 1, 0), 50, 0);
        CHECK(strcmp(info.format, "den") == 0);
        CHECK(strstr(v.source, "original 8x6x5") != NULL);
        volume_free(&v);
        if (be) {
            const char *g = out_path("b.den.gz");
            write_gz(g, file, sizeof file);
            REQUIRE_MSG(volume_load(g, NULL, &v) == PP5_OK, "%s", pp5_error_text());
            CHECK_NEAR(volume_at(&v, 3, 2, 1), 230, 0);
            volume_free(&v);
        }
    }
}

TEST(vol_den_rejects_malformed)
{
    new_dir();
    uint8_t file[62 + 24] = {0};
    volume_t v;
    memset(&v, 0, sizeof v);
    den_header(file, 4, 3, 2, 8, 6, 5, 25, false);            /* map_length disagrees */
    write_bytes(out_path("len.den"), file, sizeof file);
    CHECK_EQ(volume_load(out_path("len.den"), NULL, &v), PP5_E_FORMAT);
    CHECK_MSG(strstr(pp5_error_text(), "map_length"), "%s", pp5_error_text());
    den_header(file, 4, 3, 2, 8, 6, 5, 24, false);
    write_bytes(out_path("trunc.den"), file, sizeof file - 1);
    CHECK_EQ(volume_load(out_path("trunc.den"), NULL, &v), PP5_E_FORMAT);
    write_bytes(out_path("head.den"), file, 30);
    CHECK_EQ(volume_load(out_path("head.den"), NULL, &v), PP5_E_FORMAT);
    uint8_t bad_version[sizeof file];
    memcpy(bad_version, file, sizeof file);
    put16(bad_version, 7, false);
    write_bytes(out_path("ver.den"), bad_version, sizeof bad_version);
    CHECK_EQ(volume_load(out_path("ver.den"), NULL, &v), PP5_E_FORMAT);
    uint8_t incons[sizeof file];
    memcpy(incons, file, sizeof file);
    put16(incons + 44, 9, false);                             /* map_max[0] != map_len-1 */
    write_bytes(out_path("box.den"), incons, sizeof incons);
    CHECK_EQ(volume_load(out_path("box.den"), NULL, &v), PP5_E_FORMAT);
    den_header(file, 5000, 3, 2, 8, 6, 5, 30000, false);
    write_bytes(out_path("huge.den"), file, sizeof file);
    CHECK_EQ(volume_load(out_path("huge.den"), NULL, &v), PP5_E_RANGE);
    CHECK(v.data == NULL);
}

/* ---- slice series --------------------------------------------------------- */

static void write_slice(const char *stem, int k, int side, int base, size_t bytes_override)
{
    char name[1500];
    snprintf(name, sizeof name, "%s.%d", stem, k);
    uint8_t buf[2 * 16 * 16];
    for (int i = 0; i < side * side; i++)
        put16(buf + 2 * i, (unsigned)(base + i), true);
    write_bytes(name, buf, bytes_override ? bytes_override : (size_t)(2 * side * side));
}

TEST(vol_slices_stanford_layout)
{
    new_dir();
    char stem[1400];
    snprintf(stem, sizeof stem, "%s", out_path("CThead"));
    for (int k = 1; k <= 3; k++)
        write_slice(stem, k, 4, 1000 * k, 0);
    char first[1500];
    snprintf(first, sizeof first, "%s.1", stem);
    volume_t v;
    volume_file_info_t info;
    for (int form = 0; form < 2; form++) {
        REQUIRE_MSG(volume_load_info(form ? stem : first, NULL, &v, &info) == PP5_OK, "%s",
                    pp5_error_text());
        CHECK_EQ(v.nx, 4);
        CHECK_EQ(v.ny, 4);
        CHECK_EQ(v.nz, 3);
        CHECK_NEAR(volume_at(&v, 0, 0, 0), 1000, 0);
        CHECK_NEAR(volume_at(&v, 1, 2, 1), 2000 + 9, 0);   /* slice 2, pixel 2*4+1 */
        CHECK_NEAR(volume_at(&v, 3, 3, 2), 3000 + 15, 0);
        CHECK(strcmp(info.format, "slices") == 0);
        CHECK(info.big_endian);
        volume_free(&v);
    }
}

TEST(vol_slices_reject_gaps_and_odd_sizes)
{
    new_dir();
    char stem[1400], first[1500];
    snprintf(stem, sizeof stem, "%s", out_path("Gap"));
    snprintf(first, sizeof first, "%s.1", stem);
    write_slice(stem, 1, 4, 0, 0);
    write_slice(stem, 2, 4, 0, 0);
    write_slice(stem, 4, 4, 0, 0);
    volume_t v;
    memset(&v, 0, sizeof v);
    CHECK_EQ(volume_load(first, NULL, &v), PP5_E_FORMAT);
    CHECK_MSG(strstr(pp5_error_text(), "missing slice") && strstr(pp5_error_text(), "Gap.3"),
              "%s", pp5_error_text());

    snprintf(stem, sizeof stem, "%s", out_path("Odd"));
    snprintf(first, sizeof first, "%s.1", stem);
    write_slice(stem, 1, 4, 0, 0);
    write_slice(stem, 2, 4, 0, 30);     /* truncated second slice */
    CHECK_EQ(volume_load(first, NULL, &v), PP5_E_FORMAT);
    CHECK_MSG(strstr(pp5_error_text(), "Odd.2") && strstr(pp5_error_text(), "truncated"), "%s",
              pp5_error_text());

    snprintf(stem, sizeof stem, "%s", out_path("Rect"));
    snprintf(first, sizeof first, "%s.1", stem);
    write_slice(stem, 1, 4, 0, 24);     /* 12 pixels: not a square slice */
    CHECK_EQ(volume_load(first, NULL, &v), PP5_E_FORMAT);
    /* ... but fine when the caller says 4x3 u16 big-endian. */
    volume_raw_spec_t s = spec3(4, 3, 1, VOXEL_U16, true);
    REQUIRE_MSG(volume_load(first, &s, &v) == PP5_OK, "%s", pp5_error_text());
    CHECK_EQ(v.ny, 3);
    CHECK_NEAR(volume_at(&v, 3, 2, 0), 11, 0);
    volume_free(&v);
}
