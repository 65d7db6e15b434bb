/* volume_den.c: Marc Levoy's .den density files, as shipped with VolPack
 * (brainsmall.den); optionally gzip-compressed (.den.gz).
 *
 * Layout (62-byte header, then the voxels), as documented in
 * ../shared/data/volumes/mrbrain_brainsmall/README.md and checked against
 * the header of brainsmall.den.gz byte by byte:
 *
 *   offset  field                     brainsmall.den
 *    0      int16 map_version         1
 *    2      int16 orig_min[3]         0 0 0        the original scan's box
 *    8      int16 orig_max[3]         255 255 108
 *   14      int16 orig_len[3]         256 256 109
 *   20      int16 extr_min[3]         0 0 0        the part extracted from it
 *   26      int16 extr_max[3]         255 255 108
 *   32      int16 extr_len[3]         256 256 109
 *   38      int16 map_min[3]          0 0 0        the stored map
 *   44      int16 map_max[3]          127 127 83
 *   50      int16 map_len[3]          128 128 84   (x, y, z)
 *   56      int16 map_warps           3            (not used by readers)
 *   58      int32 map_length          1376256 = product of map_len
 *   62      uint8 voxels[map_length], x fastest
 *
 * Byte order: the file's writer's; map_version must read 1, and reads 0x0100
 * when the file is the other byte order (VolPack's examples/denfile.c swaps
 * in that case; so do we).  Checks: len = max - min + 1 on every axis and
 * triple, map_length = product(map_len), and the file size = 62 + map_length
 * exactly.  The header records no physical voxel size, so the volume gets
 * spacing 1,1,1 (brainsmall is near-isotropic per its README) and the source
 * string records which box of the original scan the map covers. */
#include "volume.h"
#include "volume_io.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#define DEN_HEADER_BYTES 62
#define DEN_VERSION 1

typedef struct {
    int version;
    int orig_min[3], orig_max[3], orig_len[3];
    int extr_min[3], extr_max[3], extr_len[3];
    int map_min[3], map_max[3], map_len[3];
    int map_warps;
    int64_t map_length;
} den_header_t;

static int16_t get16(const uint8_t *p, bool big_endian)
{
    return (int16_t)(big_endian ? (p[0] << 8 | p[1]) : (p[1] << 8 | p[0]));
}

static int32_t get32(const uint8_t *p, bool big_endian)
{
    uint32_t u = big_endian ? ((uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 |
                               (uint32_t)p[2] << 8 | p[3])
                            : ((uint32_t)p[3] << 24 | (uint32_t)p[2] << 16 |
                               (uint32_t)p[1] << 8 | p[0]);
    return (int32_t)u;
}

static pp5_status_t parse_header(const char *path, const uint8_t *b, den_header_t *h)
{
    bool be;
    if (get16(b, false) == DEN_VERSION)
        be = false;
    else if (get16(b, true) == DEN_VERSION)
        be = true;
    else
        return pp5_fail(PP5_E_FORMAT, "%s: not a .den file: map_version reads %d (expected %d "
                        "in either byte order)", path, get16(b, false), DEN_VERSION);
    h->version = DEN_VERSION;
    int *triples[9] = {h->orig_min, h->orig_max, h->orig_len, h->extr_min, h->extr_max,
                       h->extr_len, h->map_min, h->map_max, h->map_len};
    const uint8_t *p = b + 2;
    for (int t = 0; t < 9; t++)
        for (int a = 0; a < 3; a++, p += 2)
            triples[t][a] = get16(p, be);
    h->map_warps = get16(p, be);
    h->map_length = get32(p + 2, be);

    static const char *box_names[3] = {"orig", "extr", "map"};
    for (int box = 0; box < 3; box++) {
        const int *mn = triples[3 * box], *mx = triples[3 * box + 1], *len = triples[3 * box + 2];
        for (int a = 0; a < 3; a++) {
            if (len[a] < 1 || mx[a] - mn[a] + 1 != len[a])
                return pp5_fail(PP5_E_FORMAT, "%s: inconsistent .den header: %s axis %d has "
                                "min %d, max %d, len %d (need len = max - min + 1 >= 1)", path,
                                box_names[box], a, mn[a], mx[a], len[a]);
        }
    }
    pp5_status_t st = volume_check_dims(path, h->map_len[0], h->map_len[1], h->map_len[2]);
    if (st != PP5_OK)
        return st;
    int64_t product = (int64_t)h->map_len[0] * h->map_len[1] * h->map_len[2];
    if (h->map_length != product)
        return pp5_fail(PP5_E_FORMAT, "%s: inconsistent .den header: map_length %lld but "
                        "map_len %dx%dx%d = %lld", path, (long long)h->map_length,
                        h->map_len[0], h->map_len[1], h->map_len[2], (long long)product);
    return PP5_OK;
}

pp5_status_t volume_load_den(const char *path, volume_t *out, volume_file_info_t *info)
{
    FILE *probe = fopen(path, "rb");
    if (!probe)
        return pp5_fail(PP5_E_IO, "%s: cannot open: %s", path, strerror(errno));
    fclose(probe);
    gzFile g = gzopen(path, "rb");   /* reads plain files transparently */
    if (!g)
        return pp5_fail(PP5_E_IO, "%s: cannot open", path);
    uint8_t head[DEN_HEADER_BYTES];
    int got = gzread(g, head, sizeof head);
    gzclose(g);
    if (got != DEN_HEADER_BYTES)
        return pp5_fail(PP5_E_FORMAT, "%s: truncated: %d bytes, a .den header needs %d", path,
                        got < 0 ? 0 : got, DEN_HEADER_BYTES);
    den_header_t h;
    pp5_status_t st = parse_header(path, head, &h);
    if (st != PP5_OK)
        return st;
    /* The voxels are plain u8 after the header: the raw loader reads them and
     * checks the exact length. */
    volume_raw_spec_t spec;
    memset(&spec, 0, sizeof spec);
    spec.nx = h.map_len[0];
    spec.ny = h.map_len[1];
    spec.nz = h.map_len[2];
    spec.type = VOXEL_U8;
    spec.header_bytes = DEN_HEADER_BYTES;
    volume_t tmp;
    st = volume_load_raw(path, &spec, &tmp);
    if (st != PP5_OK)
        return st;
    snprintf(tmp.source, sizeof tmp.source,
             "%.400s (.den map %dx%dx%d of original %dx%dx%d)", path, h.map_len[0],
             h.map_len[1], h.map_len[2], h.orig_len[0], h.orig_len[1], h.orig_len[2]);
    volume_set_info(info, "den", VOXEL_U8, false);
    *out = tmp;
    return PP5_OK;
}
