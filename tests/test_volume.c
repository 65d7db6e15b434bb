/* test_volume.c: the volume loaders on files the tests write themselves (raw,
 * gzip, NRRD, NIfTI-1, .den, slice series; good and malformed), resampling,
 * SHA-256, `pp5 volume`, and the real data in ../shared/data when present. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "harness.h"
#include "render/volume.h"

/* ---- helpers ------------------------------------------------------------ */

static char dir[1024];

static const char *out_path(const char *name)
{
    static char buf[4][1400];
    static int next;
    char *p = buf[next++ % 4];
    snprintf(p, sizeof buf[0], "%s/%s", dir, name);
    return p;
}

static void new_dir(void)
{
    snprintf(dir, sizeof dir, "%s", pp5_test_outdir());
}

static void write_bytes(const char *path, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    REQUIRE(f != NULL);
    REQUIRE(fwrite(data, 1, n, f) == n);
    fclose(f);
}

static void write_gz(const char *path, const void *data, size_t n)
{
    gzFile g = gzopen(path, "wb");
    REQUIRE(g != NULL);
    REQUIRE(gzwrite(g, data, (unsigned)n) == (int)n);
    gzclose(g);
}

static void put16(uint8_t *p, unsigned v, bool be)
{
    p[be ? 0 : 1] = (uint8_t)(v >> 8);
    p[be ? 1 : 0] = (uint8_t)v;
}

static void put32(uint8_t *p, uint32_t v, bool be)
{
    for (int i = 0; i < 4; i++)
        p[be ? 3 - i : i] = (uint8_t)(v >> (8 * i));
}

static volume_raw_spec_t spec3(int nx, int ny, int nz, voxel_type_t t, bool be)
{
    volume_raw_spec_t s;
    memset(&s, 0, sizeof s);
    s.nx = nx;
    s.ny = ny;
    s.nz = nz;
    s.type = t;
    s.big_endian = be;
    return s;
}

/* Value of voxel i in the test volumes: small integers of both signs. */
static int test_value(size_t i, bool is_signed)
{
    int v = (int)((i * 37 + 11) % 200);
    return is_signed ? v - 100 : v;
}

/* ---- raw ---------------------------------------------------------------- */

TEST(vol_raw_every_type_and_byte_order)
{
    new_dir();
    const int nx = 3, ny = 4, nz = 5, n = nx * ny * nz;
    static const voxel_type_t types[] = {VOXEL_U8, VOXEL_I8, VOXEL_U16, VOXEL_I16, VOXEL_U32,
                                         VOXEL_I32, VOXEL_F32, VOXEL_F64};
    static const int widths[] = {1, 1, 2, 2, 4, 4, 4, 8};
    for (int t = 0; t < 8; t++) {
        for (int be = 0; be < 2; be++) {
            bool is_signed = types[t] == VOXEL_I8 || types[t] == VOXEL_I16 ||
                             types[t] == VOXEL_I32 || types[t] >= VOXEL_F32;
            uint8_t buf[60 * 8];
            for (int i = 0; i < n; i++) {
                int v = test_value((size_t)i, is_signed);
                uint8_t *p = buf + i * widths[t];
                switch (types[t]) {
                case VOXEL_U8: case VOXEL_I8: p[0] = (uint8_t)v; break;
                case VOXEL_U16: case VOXEL_I16: put16(p, (unsigned)v & 0xffff, be); break;
                case VOXEL_U32: case VOXEL_I32: put32(p, (uint32_t)v, be); break;
                case VOXEL_F32: {
                    float f = v * 0.5f;
                    uint32_t bits;
                    memcpy(&bits, &f, 4);
                    put32(p, bits, be);
                    break;
                }
                case VOXEL_F64: {
                    double d = v * 0.25;
                    uint64_t bits;
                    memcpy(&bits, &d, 8);
                    for (int b = 0; b < 8; b++)
                        p[be ? 7 - b : b] = (uint8_t)(bits >> (8 * b));
                    break;
                }
                }
            }
            char name[64];
            snprintf(name, sizeof name, "t%d_%d.raw", t, be);
            const char *path = out_path(name);
            write_bytes(path, buf, (size_t)n * widths[t]);
            volume_raw_spec_t s = spec3(nx, ny, nz, types[t], be);
            s.spacing[2] = 2.5;
            volume_t v;
            REQUIRE_MSG(volume_load_raw(path, &s, &v) == PP5_OK, "type %d be %d: %s", t, be,
                        pp5_error_text());
            int wrong = 0;
            for (int i = 0; i < n; i++) {
                double want = test_value((size_t)i, is_signed);
                if (types[t] == VOXEL_F32) want *= 0.5;
                if (types[t] == VOXEL_F64) want *= 0.25;
                wrong += v.data[i] != (float)want;
            }
            CHECK_MSG(wrong == 0, "type %d be %d: %d wrong voxels", t, be, wrong);
            CHECK_EQ(v.nx, nx);
            CHECK_EQ(v.nz, nz);
            CHECK_NEAR(v.spacing[0], 1.0, 0);
            CHECK_NEAR(v.spacing[2], 2.5, 0);
            volume_free(&v);
        }
    }
}

TEST(vol_raw_gzip_and_header_skip)
{
    new_dir();
    uint8_t buf[10 + 2 * 2 * 2 * 2];
    memset(buf, 0xEE, 10);                            /* a 10-byte header to skip */
    for (int i = 0; i < 8; i++)
        put16(buf + 10 + 2 * i, 1000u + 100u * i, true);
    const char *path = out_path("h.raw.gz");
    write_gz(path, buf, sizeof buf);
    volume_raw_spec_t s = spec3(2, 2, 2, VOXEL_U16, true);
    s.header_bytes = 10;
    volume_t v;
    REQUIRE_MSG(volume_load_raw(path, &s, &v) == PP5_OK, "%s", pp5_error_text());
    CHECK_NEAR(volume_at(&v, 0, 0, 0), 1000, 0);
    CHECK_NEAR(volume_at(&v, 1, 0, 0), 1100, 0);   /* x fastest */
    CHECK_NEAR(volume_at(&v, 0, 1, 0), 1200, 0);
    CHECK_NEAR(volume_at(&v, 1, 1, 1), 1700, 0);
    CHECK_NEAR(v.min_value, 1000, 0);
    CHECK_NEAR(v.max_value, 1700, 0);
    volume_free(&v);
}

TEST(vol_raw_rejects_wrong_sizes_plain_and_gzip)
{
    new_dir();
    uint8_t buf[64] = {0};
    volume_raw_spec_t s = spec3(4, 4, 4, VOXEL_U8, false);   /* needs 64 bytes */
    volume_t v;
    memset(&v, 0, sizeof v);
    const char *shortp = out_path("short.raw");
    write_bytes(shortp, buf, 63);
    CHECK_EQ(volume_load_raw(shortp, &s, &v), PP5_E_FORMAT);
    CHECK_MSG(strstr(pp5_error_text(), "short.raw") && strstr(pp5_error_text(), "truncated"),
              "message: %s", pp5_error_text());
    CHECK(v.data == NULL);   /* nothing committed */
    const char *longp = out_path("long.raw");
    uint8_t big[65] = {0};
    write_bytes(longp, big, 65);
    CHECK_EQ(volume_load_raw(longp, &s, &v), PP5_E_FORMAT);
    CHECK_MSG(strstr(pp5_error_text(), "too long"), "message: %s", pp5_error_text());
    const char *shortgz = out_path("short.raw.gz");
    write_gz(shortgz, buf, 40);
    CHECK_EQ(volume_load_raw(shortgz, &s, &v), PP5_E_FORMAT);
    CHECK_MSG(strstr(pp5_error_text(), "truncated"), "message: %s", pp5_error_text());
    const char *longgz = out_path("long.raw.gz");
    write_gz(longgz, big, 65);
    CHECK_EQ(volume_load_raw(longgz, &s, &v), PP5_E_FORMAT);
    CHECK_MSG(strstr(pp5_error_text(), "too long"), "message: %s", pp5_error_text());
    /* A gzip file cut in the middle of its stream. */
    const char *fullgz = out_path("full.raw.gz");
    uint8_t noise[4096];
    for (int i = 0; i < 4096; i++)
        noise[i] = (uint8_t)(i * 2654435761u >> 13);
    write_gz(fullgz, noise, sizeof noise);
    FILE *f = fopen(fullgz, "rb");
    REQUIRE(f != NULL);
    uint8_t comp[8192];
    size_t clen = fread(comp, 1, sizeof comp, f);
    fclose(f);
    const char *cutgz = out_path("cut.raw.gz");
    write_bytes(cutgz, comp, clen / 2);
    volume_raw_spec_t s16 = spec3(16, 16, 16, VOXEL_U8, false);
    CHECK_EQ(volume_load_raw(cutgz, &s16, &v), PP5_E_FORMAT);
    CHECK(v.data == NULL);
    CHECK_EQ(volume_load_raw(out_path("absent.raw"), &s, &v), PP5_E_IO);
}

TEST(vol_raw_rejects_absurd_dims_and_types)
{
    new_dir();
    const char *path = out_path("x.raw");
    uint8_t b[8] = {0};
    write_bytes(path, b, 8);
    volume_t v;
    memset(&v, 0, sizeof v);
    volume_raw_spec_t bad[] = {
        spec3(0, 2, 2, VOXEL_U8, false), spec3(2, -1, 4, VOXEL_U8, false),
        spec3(VOLUME_MAX_SIDE + 1, 1, 1, VOXEL_U8, false),
        spec3(2048, 2048, 512, VOXEL_U8, false),          /* 2^31 voxels > the 2^30 limit */
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        CHECK_MSG(volume_load_raw(path, &bad[i], &v) == PP5_E_RANGE, "case %zu: %s", i,
                  pp5_error_text());
        CHECK_MSG(strstr(pp5_error_text(), "x.raw") != NULL, "names the file: %s",
                  pp5_error_text());
    }
    volume_raw_spec_t t = spec3(2, 2, 2, VOXEL_U8, false);
    t.type = (voxel_type_t)42;
    CHECK_EQ(volume_load_raw(path, &t, &v), PP5_E_FORMAT);
    volume_raw_spec_t sp = spec3(2, 2, 2, VOXEL_U8, false);
    sp.spacing[1] = -1;
    CHECK_EQ(volume_load_raw(path, &sp, &v), PP5_E_RANGE);
    CHECK_EQ(volume_load_raw(path, NULL, &v), PP5_E_CONFIG);
    CHECK(v.data == NULL);
    CHECK_EQ(volume_alloc(&v, 0, 1, 1), PP5_E_RANGE);
    CHECK_EQ(volume_alloc(&v, 4096, 4096, 4096), PP5_E_RANGE);
}

TEST(vol_raw_rejects_nan_and_inf)
{
    new_dir();
    float f[8] = {0, 1, 2, 3, 4, NAN, 6, 7};
    const char *p = out_path("nan.raw");
    write_bytes(p, f, sizeof f);   /* host order: little-endian on x86/arm64 */
    const uint16_t probe = 1;
    bool host_be = *(const uint8_t *)&probe == 0;
    volume_raw_spec_t s = spec3(2, 2, 2, VOXEL_F32, host_be);
    volume_t v;
    memset(&v, 0, sizeof v);
    CHECK_EQ(volume_load_raw(p, &s, &v), PP5_E_FORMAT);
    CHECK_MSG(strstr(pp5_error_text(), "NaN") && strstr(pp5_error_text(), "x=1 y=0 z=1"),
              "message: %s", pp5_error_text());
    double d[8] = {0, 1, 2, 3, 4, 5, INFINITY, 7};
    const char *q = out_path("inf.raw");
    write_bytes(q, d, sizeof d);
    s.type = VOXEL_F64;
    CHECK_EQ(volume_load_raw(q, &s, &v), PP5_E_FORMAT);
    double big[8] = {0, 1, 2, 3, 4, 5, 1e300, 7};   /* finite, but no float can hold it */
    write_bytes(q, big, sizeof big);
    CHECK_EQ(volume_load_raw(q, &s, &v), PP5_E_FORMAT);
    CHECK(v.data == NULL);
}

TEST(vol_layout_from_file_name_and_dispatch)
{
    new_dir();
    volume_raw_spec_t s;
    REQUIRE(volume_raw_spec_from_name("/a/b/cthead_256x256x113_u16be.raw.gz", &s) == PP5_OK);
    CHECK_EQ(s.nx, 256);
    CHECK_EQ(s.ny, 256);
    CHECK_EQ(s.nz, 113);
    CHECK_EQ(s.type, VOXEL_U16);
    CHECK(s.big_endian);
    REQUIRE(volume_raw_spec_from_name("brainsmall_128x128x84_u8.raw.gz", &s) == PP5_OK);
    CHECK_EQ(s.type, VOXEL_U8);
    CHECK(!s.big_endian);
    CHECK(volume_raw_spec_from_name("dir_4x4x4_u8/plain.raw", &s) != PP5_OK);
    CHECK(volume_raw_spec_from_name("v_4x4x4_q7.raw", &s) != PP5_OK);
    CHECK_EQ(volume_raw_spec_from_name("v_0x4x4_u8.raw", &s), PP5_E_RANGE);

    /* volume_load picks raw from the name. */
    uint8_t b[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    const char *p = out_path("vol_2x2x2_u8.raw");
    write_bytes(p, b, 8);
    volume_t v;
    volume_file_info_t info;
    REQUIRE_MSG(volume_load_info(p, NULL, &v, &info) == PP5_OK, "%s", pp5_error_text());
    CHECK_NEAR(volume_at(&v, 1, 1, 1), 8, 0);
    CHECK(strcmp(info.format, "raw") == 0);
    CHECK_EQ(info.stored_type, VOXEL_U8);
    volume_free(&v);
    /* No way to know the layout: a clear error, not a guess. */
    const char *q = out_path("mystery.bin");
    write_bytes(q, b, 8);
    CHECK_EQ(volume_load(q, NULL, &v), PP5_E_FORMAT);
    CHECK_MSG(strstr(pp5_error_text(), "mystery.bin") != NULL, "%s", pp5_error_text());
    CHECK_EQ(volume_load(out_path("nothing_here"), NULL, &v), PP5_E_IO);
}

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

/* A NIfTI-1 single-file header (348 bytes + 4 extension bytes), hand-made
 * per the nifti1.h field offsets: sizeof_hdr @0, dim[8] @40, datatype @70,
 * bitpix @72, pixdim[8] @76, vox_offset @108, scl_slope @112, scl_inter @116,
 * magic "n+1" @344. */
static void nifti_header(uint8_t h[352], const short dims[8], short datatype, short bitpix,
                         const float pixdim[4], float slope, float inter, bool be)
{
    memset(h, 0, 352);
    put32(h, 348, be);
    for (int i = 0; i < 8; i++)
        put16(h + 40 + 2 * i, (unsigned)dims[i] & 0xffff, be);
    put16(h + 70, (unsigned)datatype, be);
    put16(h + 72, (unsigned)bitpix, be);
    for (int i = 0; i < 4; i++) {
        uint32_t bits;
        memcpy(&bits, &pixdim[i], 4);
        put32(h + 76 + 4 * i, bits, be);
    }
    float vox_offset = 352, fs[2] = {slope, inter};
    uint32_t bits;
    memcpy(&bits, &vox_offset, 4);
    put32(h + 108, bits, be);
    for (int i = 0; i < 2; i++) {
        memcpy(&bits, &fs[i], 4);
        put32(h + 112 + 4 * i, bits, be);
    }
    memcpy(h + 344, "n+1", 4);
}

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

/* The 62-byte .den header (layout in volume_den.c), for a map of nx*ny*nz
 * taken from an original of ox*oy*oz. */
static void den_header(uint8_t h[62], int nx, int ny, int nz, int ox, int oy, int oz,
                       int32_t length, bool be)
{
    const int orig[3] = {ox, oy, oz}, map[3] = {nx, ny, nz};
    int v[29];
    v[0] = 1;
    for (int a = 0; a < 3; a++) {
        v[1 + a] = 0; v[4 + a] = orig[a] - 1; v[7 + a] = orig[a];     /* orig */
        v[10 + a] = 0; v[13 + a] = orig[a] - 1; v[16 + a] = orig[a];  /* extr */
        v[19 + a] = 0; v[22 + a] = map[a] - 1; v[25 + a] = map[a];    /* map */
    }
    v[28] = 3;
    for (int i = 0; i < 29; i++)
        put16(h + 2 * i, (unsigned)v[i] & 0xffff, be);
    put32(h + 58, (uint32_t)length, be);
}

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

/* ---- resampling, hashes --------------------------------------------------- */

TEST(vol_resample_is_trilinear_with_aligned_corners)
{
    volume_t in, out;
    REQUIRE(volume_alloc(&in, 3, 2, 2) == PP5_OK);
    /* f = 2x + 3y + 5z + 1 is reproduced exactly by trilinear interpolation. */
    for (int z = 0; z < 2; z++)
        for (int y = 0; y < 2; y++)
            for (int x = 0; x < 3; x++)
                in.data[(z * 2 + y) * 3 + x] = (float)(2 * x + 3 * y + 5 * z + 1);
    in.spacing[2] = 2.0;
    REQUIRE(volume_resample(&in, 5, 3, 5, &out) == PP5_OK);
    int wrong = 0;
    for (int z = 0; z < 5; z++)
        for (int y = 0; y < 3; y++)
            for (int x = 0; x < 5; x++) {
                /* output sample i sits at input coordinate i*(n_in-1)/(n_out-1) */
                double fx = x * 0.5, fy = y * 0.5, fz = z * 0.25;
                double want = 2 * fx + 3 * fy + 5 * fz + 1;
                wrong += fabs(volume_at(&out, x, y, z) - want) > 1e-5;
            }
    CHECK_EQ(wrong, 0);
    CHECK_NEAR(out.spacing[0], 0.5, 1e-12);
    CHECK_NEAR(out.spacing[2], 0.5, 1e-12);   /* 2.0 * (2-1)/(5-1) */
    CHECK_NEAR(out.min_value, 1, 1e-6);
    CHECK_NEAR(out.max_value, 2 * 2 + 3 + 5 + 1, 1e-5);
    volume_free(&out);
    CHECK_EQ(volume_resample(&in, 0, 3, 3, &out), PP5_E_RANGE);
    volume_free(&in);
}

static void hex(const uint8_t d[32], char out[65])
{
    for (int i = 0; i < 32; i++)
        snprintf(out + 2 * i, 3, "%02x", d[i]);
}

TEST(vol_sha256_fips_vectors)
{
    /* FIPS 180-2 appendix B examples. */
    uint8_t d[32];
    char h[65];
    volume_sha256("abc", 3, d);
    hex(d, h);
    CHECK(strcmp(h, "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad") == 0);
    volume_sha256("", 0, d);
    hex(d, h);
    CHECK(strcmp(h, "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855") == 0);
    const char *m = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
    volume_sha256(m, strlen(m), d);
    hex(d, h);
    CHECK_MSG(strcmp(h, "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1") == 0,
              "got %s", h);
}

TEST(vol_hash_and_stats_follow_the_data)
{
    volume_t a;
    REQUIRE(volume_alloc(&a, 2, 2, 2) == PP5_OK);
    for (int i = 0; i < 8; i++)
        a.data[i] = (float)i - 3;
    volume_update_stats(&a);
    CHECK_NEAR(a.min_value, -3, 0);
    CHECK_NEAR(a.max_value, 4, 0);
    uint64_t h1 = a.hash;
    a.data[5] = 1.5f;
    volume_update_stats(&a);
    CHECK(a.hash != h1);
    a.data[5] = 2.0f;   /* the original value: 5 - 3 */
    volume_update_stats(&a);
    CHECK(a.hash == h1);
    volume_free(&a);
}

/* ---- the command ------------------------------------------------------------ */

TEST(vol_cli_info_and_phantom)
{
    new_dir();
    char args[3000], outp[1400], errp[1400];
    snprintf(outp, sizeof outp, "%s", out_path("out.txt"));
    snprintf(errp, sizeof errp, "%s", out_path("err.txt"));
    char nrrd[1400];
    snprintf(nrrd, sizeof nrrd, "%s", out_path("shell.nrrd"));
    snprintf(args, sizeof args, "volume phantom sphere-shell --size 16x16x8 --out %s", nrrd);
    CHECK_EQ(pp5_test_run_cli(args, outp, errp), 0);
    snprintf(args, sizeof args, "volume info %s", nrrd);
    REQUIRE(pp5_test_run_cli(args, outp, errp) == 0);
    char *text = pp5_test_read_file(outp);
    REQUIRE(text != NULL);
    CHECK_MSG(strstr(text, "16 x 16 x 8") != NULL, "%s", text ? text : "");
    CHECK_MSG(strstr(text, "range:    0 .. 200") != NULL, "%s", text ? text : "");
    CHECK_MSG(strstr(text, "stored as f32") != NULL, "%s", text ? text : "");
    free(text);

    uint8_t b[24];
    for (int i = 0; i < 24; i++)
        b[i] = (uint8_t)(i + 1);
    const char *raw = out_path("r.bin");
    write_bytes(raw, b, sizeof b);
    snprintf(args, sizeof args, "volume info %s --dims 2x3x4 --type u8", raw);
    REQUIRE(pp5_test_run_cli(args, outp, errp) == 0);
    text = pp5_test_read_file(outp);
    REQUIRE(text != NULL);
    CHECK_MSG(strstr(text, "range:    1 .. 24") != NULL, "%s", text ? text : "");
    free(text);
    snprintf(args, sizeof args, "volume info %s --dims 2x3x5 --type u8", raw);
    CHECK_EQ(pp5_test_run_cli(args, outp, errp), 3);   /* bad input */
    text = pp5_test_read_file(errp);
    REQUIRE(text != NULL);
    CHECK_MSG(strstr(text, "r.bin") && strstr(text, "truncated"), "%s", text ? text : "");
    free(text);
    snprintf(args, sizeof args, "volume info %s --dims 2x3 --type u8", raw);
    CHECK_EQ(pp5_test_run_cli(args, outp, errp), 2);
    snprintf(args, sizeof args, "volume phantom nosuch --out %s", nrrd);
    CHECK_EQ(pp5_test_run_cli(args, outp, errp), 2);
    snprintf(args, sizeof args, "volume phantom sphere-shell --out %s/x.png", dir);
    CHECK_EQ(pp5_test_run_cli(args, outp, errp), 2);
    CHECK_EQ(pp5_test_run_cli("volume --help", outp, errp), 0);
}

/* ---- real data (../shared/data), skipped loudly when absent ------------------ */

/* SHA-256 of the voxels written back in the file's own encoding, compared
 * with the sha256(raw) that PROVENANCE.md records: proves that every voxel
 * was read exactly. */
static void sha_of_u16be(const volume_t *v, char out[65])
{
    size_t n = volume_voxel_count(v);
    uint8_t *bytes = malloc(2 * n);
    REQUIRE(bytes != NULL);
    for (size_t i = 0; i < n; i++)
        put16(bytes + 2 * i, (unsigned)v->data[i], true);
    uint8_t d[32];
    volume_sha256(bytes, 2 * n, d);
    hex(d, out);
    free(bytes);
}

static void sha_of_u8(const volume_t *v, char out[65])
{
    size_t n = volume_voxel_count(v);
    uint8_t *bytes = malloc(n);
    REQUIRE(bytes != NULL);
    for (size_t i = 0; i < n; i++)
        bytes[i] = (uint8_t)v->data[i];
    uint8_t d[32];
    volume_sha256(bytes, n, d);
    hex(d, out);
    free(bytes);
}

static double mean_of(const volume_t *v)
{
    double s = 0;
    size_t n = volume_voxel_count(v);
    for (size_t i = 0; i < n; i++)
        s += v->data[i];
    return s / n;
}

TEST(vol_real_cthead_raw_gz)
{
    const char *p = pp5_test_shared_data("volumes/cthead/cthead_256x256x113_u16be.raw.gz");
    if (!p)
        SKIP("../shared/data/volumes/cthead/cthead_256x256x113_u16be.raw.gz absent");
    volume_t v;
    REQUIRE_MSG(volume_load(p, NULL, &v) == PP5_OK, "%s", pp5_error_text());
    CHECK_EQ(v.nx, 256);
    CHECK_EQ(v.ny, 256);
    CHECK_EQ(v.nz, 113);
    /* PROVENANCE.md / cthead README: values 0..3272, mean 379.5. */
    CHECK_NEAR(v.min_value, 0, 0);
    CHECK_NEAR(v.max_value, 3272, 0);
    CHECK_NEAR(mean_of(&v), 379.5, 0.05);
    char h[65];
    sha_of_u16be(&v, h);
    CHECK_MSG(strcmp(h, "163572eca68c0a6b4142ce43396922b465027e6bf97949b9fad168405e27e6c7") == 0,
              "sha256 %s", h);
    volume_free(&v);
}

TEST(vol_real_brainsmall_raw_and_den_agree)
{
    /* pp5_test_shared_data returns a shared buffer: copy each path. */
    char raw[1024], den[1024];
    const char *p = pp5_test_shared_data("volumes/mrbrain_brainsmall/brainsmall_128x128x84_u8.raw.gz");
    snprintf(raw, sizeof raw, "%s", p ? p : "");
    p = pp5_test_shared_data("volumes/mrbrain_brainsmall/brainsmall.den.gz");
    snprintf(den, sizeof den, "%s", p ? p : "");
    if (!raw[0] || !den[0])
        SKIP("../shared/data/volumes/mrbrain_brainsmall files absent");
    volume_t a, b;
    REQUIRE_MSG(volume_load(raw, NULL, &a) == PP5_OK, "%s", pp5_error_text());
    REQUIRE_MSG(volume_load(den, NULL, &b) == PP5_OK, "%s", pp5_error_text());
    CHECK_EQ(a.nx, 128);
    CHECK_EQ(a.ny, 128);
    CHECK_EQ(a.nz, 84);
    CHECK_NEAR(a.min_value, 0, 0);
    CHECK_NEAR(a.max_value, 202, 0);
    CHECK_NEAR(mean_of(&a), 14.0, 0.05);
    char h[65];
    sha_of_u8(&a, h);
    CHECK_MSG(strcmp(h, "fc152775a71953ec853c18c76c19c5865309163f78f0930ea7f6ca671e8db207") == 0,
              "sha256 %s", h);
    CHECK_EQ(b.nx, 128);
    CHECK_EQ(b.nz, 84);
    CHECK(a.hash == b.hash);   /* the .den holds the same voxels after its header */
    CHECK(strstr(b.source, "original 256x256x109") != NULL);
    volume_free(&a);
    volume_free(&b);
}

TEST(vol_real_small_fields)
{
    char iron[1024], neg[1024];
    const char *p = pp5_test_shared_data("volumes/ironprot/ironprot_68x68x68_u8.raw.gz");
    snprintf(iron, sizeof iron, "%s", p ? p : "");
    p = pp5_test_shared_data("volumes/neghip/neghip_66x66x66_u8.raw.gz");
    snprintf(neg, sizeof neg, "%s", p ? p : "");
    if (!iron[0] || !neg[0])
        SKIP("../shared/data/volumes/ironprot or neghip absent");
    volume_t v;
    REQUIRE_MSG(volume_load(iron, NULL, &v) == PP5_OK, "%s", pp5_error_text());
    CHECK_EQ(v.nx, 68);
    CHECK_NEAR(v.max_value, 255, 0);
    char h[65];
    sha_of_u8(&v, h);
    CHECK(strcmp(h, "e55377a16495bebf926293ad9b79205b6c47ce45f73186dfeb79c980de58899f") == 0);
    volume_free(&v);
    REQUIRE_MSG(volume_load(neg, NULL, &v) == PP5_OK, "%s", pp5_error_text());
    CHECK_EQ(v.nz, 66);
    sha_of_u8(&v, h);
    CHECK(strcmp(h, "a8032bb45132a1a87a0ef5989c37f7946fa42846c6016af5dddbbdb6fd3ec4cc") == 0);
    volume_free(&v);
}

/* ---- writers and exhaustive truncation ---------------------------------------- */

TEST(vol_writers_round_trip_exactly)
{
    new_dir();
    volume_t v, back;
    REQUIRE(phantom_make("shepp-logan", 20, 16, 12, &v) == PP5_OK);
    const char *n = out_path("p.nrrd");
    REQUIRE_MSG(volume_save_nrrd(&v, n) == PP5_OK, "%s", pp5_error_text());
    REQUIRE_MSG(volume_load(n, NULL, &back) == PP5_OK, "%s", pp5_error_text());
    CHECK(back.hash == v.hash);
    CHECK_NEAR(back.spacing[1], v.spacing[1], 1e-12);
    CHECK_NEAR(back.spacing[2], 20.0 / 12.0, 1e-12);
    volume_free(&back);
    const char *r = out_path("p.raw");
    REQUIRE(volume_save_raw_f32(&v, r) == PP5_OK);
    volume_raw_spec_t s = spec3(20, 16, 12, VOXEL_F32, false);
    REQUIRE_MSG(volume_load_raw(r, &s, &back) == PP5_OK, "%s", pp5_error_text());
    CHECK(back.hash == v.hash);
    volume_free(&back);
    volume_free(&v);
}

/* Every proper prefix of a valid file must be refused (never accepted as a
 * smaller volume, never a crash). */
static void check_every_prefix_fails(const char *name, const uint8_t *file, size_t n)
{
    const char *p = out_path(name);
    int accepted = 0;
    for (size_t len = 0; len < n; len++) {
        write_bytes(p, file, len);
        volume_t v;
        memset(&v, 0, sizeof v);
        if (volume_load(p, NULL, &v) == PP5_OK) {
            accepted++;
            volume_free(&v);
        }
    }
    CHECK_MSG(accepted == 0, "%s: %d truncated prefixes were accepted", name, accepted);
    write_bytes(p, file, n);
    volume_t v;
    CHECK_MSG(volume_load(p, NULL, &v) == PP5_OK, "%s whole: %s", name, pp5_error_text());
    volume_free(&v);
}

TEST(vol_every_truncation_is_refused)
{
    new_dir();
    uint8_t den[62 + 24];
    den_header(den, 4, 3, 2, 8, 6, 5, 24, true);
    for (int i = 0; i < 24; i++)
        den[62 + i] = (uint8_t)i;
    check_every_prefix_fails("t.den", den, sizeof den);

    const short dims[8] = {3, 2, 3, 2, 1, 1, 1, 1};
    const float pix[4] = {1, 1, 1, 1};
    uint8_t nii[352 + 12 * 4];
    nifti_header(nii, dims, 16 /* DT_FLOAT32 */, 32, pix, 0, 0, false);
    for (int i = 0; i < 12; i++) {
        float f = i * 1.5f;
        uint32_t bits;
        memcpy(&bits, &f, 4);
        put32(nii + 352 + 4 * i, bits, false);
    }
    check_every_prefix_fails("t.nii", nii, sizeof nii);

    const char *hdr = "NRRD0004\ntype: ushort\ndimension: 3\nsizes: 2 2 3\nspacings: 1 1 2\n"
                      "endian: little\nencoding: raw\n\n";
    uint8_t nrrd[256];
    size_t hl = strlen(hdr);
    memcpy(nrrd, hdr, hl);
    for (int i = 0; i < 12; i++)
        put16(nrrd + hl + 2 * i, (unsigned)(i * 100), false);
    check_every_prefix_fails("t.nrrd", nrrd, hl + 24);
}

TEST(vol_real_cthead_as_stanford_slices)
{
    const char *p = pp5_test_shared_data("volumes/cthead/cthead_256x256x113_u16be.raw.gz");
    if (!p)
        SKIP("../shared/data/volumes/cthead/cthead_256x256x113_u16be.raw.gz absent");
    /* The stored file is CThead.1..CThead.113 joined (cthead/README.md):
     * split it back into the archive's layout and load that. */
    new_dir();
    gzFile g = gzopen(p, "rb");
    REQUIRE(g != NULL);
    uint8_t *slice = malloc(131072);
    REQUIRE(slice != NULL);
    char stem[1400];
    snprintf(stem, sizeof stem, "%s/CThead", dir);
    for (int k = 1; k <= 113; k++) {
        REQUIRE(gzread(g, slice, 131072) == 131072);
        char name[1500];
        snprintf(name, sizeof name, "%s.%d", stem, k);
        write_bytes(name, slice, 131072);
    }
    gzclose(g);
    free(slice);
    volume_t a, b;
    char first[1500];
    snprintf(first, sizeof first, "%s.1", stem);
    REQUIRE_MSG(volume_load(first, NULL, &a) == PP5_OK, "%s", pp5_error_text());
    REQUIRE_MSG(volume_load(p, NULL, &b) == PP5_OK, "%s", pp5_error_text());
    CHECK_EQ(a.nx, 256);
    CHECK_EQ(a.nz, 113);
    CHECK(a.hash == b.hash);
    volume_free(&a);
    volume_free(&b);
}
