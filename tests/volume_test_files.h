/* volume_test_files.h: what the volume tests share: a scratch folder, file
 * writers (plain and gzip), byte-order packing, raw layouts, test values, a
 * hand-written .den header and hex digests. Static: each test file gets its
 * own copy. */
#ifndef PP5_VOLUME_TEST_FILES_H
#define PP5_VOLUME_TEST_FILES_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <zlib.h>

#include "harness.h"
#include "render/volume.h"

static char dir[1024];   /* set by new_dir() */

static inline const char *out_path(const char *name)
{
    static char buf[4][1400];
    static int next;
    char *p = buf[next++ % 4];
    snprintf(p, sizeof buf[0], "%s/%s", dir, name);
    return p;
}

static inline void new_dir(void)
{
    snprintf(dir, sizeof dir, "%s", pp5_test_outdir());
}

static inline void write_bytes(const char *path, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    REQUIRE(f != NULL);
    REQUIRE(fwrite(data, 1, n, f) == n);
    fclose(f);
}

static inline void write_gz(const char *path, const void *data, size_t n)
{
    gzFile g = gzopen(path, "wb");
    REQUIRE(g != NULL);
    REQUIRE(gzwrite(g, data, (unsigned)n) == (int)n);
    gzclose(g);
}

static inline void put16(uint8_t *p, unsigned v, bool be)
{
    p[be ? 0 : 1] = (uint8_t)(v >> 8);
    p[be ? 1 : 0] = (uint8_t)v;
}

static inline void put32(uint8_t *p, uint32_t v, bool be)
{
    for (int i = 0; i < 4; i++)
        p[be ? 3 - i : i] = (uint8_t)(v >> (8 * i));
}

static inline volume_raw_spec_t spec3(int nx, int ny, int nz, voxel_type_t t, bool be)
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
static inline int test_value(size_t i, bool is_signed)
{
    int v = (int)((i * 37 + 11) % 200);
    return is_signed ? v - 100 : v;
}

/* The 62-byte .den header (layout in volume_den.c), for a map of nx*ny*nz
 * taken from an original of ox*oy*oz. */
static inline void den_header(uint8_t h[62], int nx, int ny, int nz, int ox, int oy, int oz,
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

static inline void hex(const uint8_t d[32], char out[65])
{
    for (int i = 0; i < 32; i++)
        snprintf(out + 2 * i, 3, "%02x", d[i]);
}

/* A NIfTI-1 single-file header (348 bytes + 4 extension bytes), hand-made
 * per the nifti1.h field offsets: sizeof_hdr @0, dim[8] @40, datatype @70,
 * bitpix @72, pixdim[8] @76, vox_offset @108, scl_slope @112, scl_inter @116,
 * magic "n+1" @344. */
static inline void nifti_header(uint8_t h[352], const short dims[8], short datatype, short bitpix,
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

#endif
