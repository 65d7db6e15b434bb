/* test_volume_real.c: the real volumes of ../shared/data (CThead, the MR
 * subject and the small fields), read exactly, skipped loudly when absent. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "harness.h"
#include "render/volume.h"
#include "volume_test_files.h"

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

/* Run from a folder outside the checkout, with $PP5_SHARED_DATA unset, pp5
 * still finds the shared data from its own place instead of falling back
 * to a phantom. */
TEST(vol_real_found_from_another_directory)
{
    if (!pp5_test_shared_data("volumes/mrbrain_brainsmall/brainsmall_128x128x84_u8.raw.gz"))
        SKIP("../shared/data/volumes/mrbrain_brainsmall absent");
    const char *bin = getenv("PP5_BIN");
    char abs_bin[4096];
    REQUIRE(realpath(bin && *bin ? bin : "./pp5", abs_bin) != NULL);
    new_dir();
    char cmd[9000];
    snprintf(cmd, sizeof cmd, "cd '%s' && env -u PP5_SHARED_DATA '%s' render --dataset mrbrain "
             "--size 16x16 --out x.png >out.txt 2>err.txt", dir, abs_bin);
    CHECK_EQ(system(cmd), 0);
    char *text = pp5_test_read_file(out_path("out.txt"));
    char *err = pp5_test_read_file(out_path("err.txt"));
    REQUIRE(text && err);
    CHECK_MSG(strstr(text, "brainsmall_128x128x84_u8.raw.gz") != NULL, "%s", text);
    CHECK_MSG(strstr(text, "absent") == NULL && strstr(err, "absent") == NULL, "%s%s", text, err);
    free(text);
    free(err);
}
