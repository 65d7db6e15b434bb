/* test_volume.c: the raw volume loader on files the tests write themselves
 * (every type and byte order, gzip, headers; good and malformed), resampling,
 * SHA-256, `pp5 volume`, the writers, and every truncation refused. The other
 * formats: test_volume_formats.c; the real data: test_volume_real.c. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "harness.h"
#include "render/volume.h"
#include "volume_test_files.h"

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
    for (int z = 0; z < 5; z++)
        for (int y = 0; y < 3; y++)
            for (int x = 0; x < 5; x++) {
                /* output sample i sits at input coordinate i*(n_in-1)/(n_out-1) */
                double fx = x * 0.5, fy = y * 0.5, fz = z * 0.25;
                double want = 2 * fx + 3 * fy + 5 * fz + 1;
                CHECK_MSG(fabs(volume_at(&out, x, y, z) - want) <= 1e-5,
                          "sample (%d, %d, %d) is %g, want %g", x, y, z, volume_at(&out, x, y, z),
                          want);
            }
    CHECK_NEAR(out.spacing[0], 0.5, 1e-12);
    CHECK_NEAR(out.spacing[2], 0.5, 1e-12);   /* 2.0 * (2-1)/(5-1) */
    CHECK_NEAR(out.min_value, 1, 1e-6);
    CHECK_NEAR(out.max_value, 2 * 2 + 3 + 5 + 1, 1e-5);
    volume_free(&out);
    CHECK_EQ(volume_resample(&in, 0, 3, 3, &out), PP5_E_RANGE);
    volume_free(&in);
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
