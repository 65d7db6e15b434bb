/* volume_raw.c: headerless raw volumes (optionally gzip-compressed), any voxel
 * type and byte order, converted to float; and the raw float32 writer.
 *
 * Files are read through zlib's gzopen, which also reads uncompressed files
 * transparently.  The size must match exactly: a file shorter or longer than
 * header + nx*ny*nz*type bytes is an error, because either means the stated
 * dimensions or type are wrong (a silently wrong volume is worse than none). */
#include "volume.h"
#include "volume_io.h"
#include "outfile.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <zlib.h>

#define RAW_CHUNK_BYTES (1u << 20)

static uint64_t load_be(const uint8_t *p, size_t n)
{
    uint64_t v = 0;
    for (size_t i = 0; i < n; i++)
        v = (v << 8) | p[i];
    return v;
}

static uint64_t load_le(const uint8_t *p, size_t n)
{
    uint64_t v = 0;
    for (size_t i = n; i-- > 0;)
        v = (v << 8) | p[i];
    return v;
}

bool voxels_to_float(const uint8_t *bytes, size_t n, voxel_type_t type, bool big_endian,
                     float *dst, size_t *bad_index)
{
    size_t w = voxel_type_bytes(type);
    for (size_t i = 0; i < n; i++) {
        const uint8_t *p = bytes + i * w;
        uint64_t u = big_endian ? load_be(p, w) : load_le(p, w);
        float f;
        switch (type) {
        case VOXEL_U8: f = (float)(uint8_t)u; break;
        case VOXEL_I8: f = (float)(int8_t)(uint8_t)u; break;
        case VOXEL_U16: f = (float)(uint16_t)u; break;
        case VOXEL_I16: f = (float)(int16_t)(uint16_t)u; break;
        case VOXEL_U32: f = (float)(uint32_t)u; break;
        case VOXEL_I32: f = (float)(int32_t)(uint32_t)u; break;
        case VOXEL_F32: {
            uint32_t bits = (uint32_t)u;
            memcpy(&f, &bits, sizeof f);
            break;
        }
        case VOXEL_F64: {
            double d;
            memcpy(&d, &u, sizeof d);
            /* A finite double beyond float range would become inf: refuse it too. */
            f = (isfinite(d) && fabs(d) <= 3.4028234663852886e38) ? (float)d : NAN;
            break;
        }
        default: f = NAN; break;
        }
        if (!isfinite(f)) {
            *bad_index = i;
            return false;
        }
        dst[i] = f;
    }
    return true;
}

static pp5_status_t check_raw_spec(const char *path, const volume_raw_spec_t *raw)
{
    if (!raw)
        return pp5_fail(PP5_E_CONFIG, "%s: raw volume needs dimensions and a voxel type", path);
    pp5_status_t st = volume_check_dims(path, raw->nx, raw->ny, raw->nz);
    if (st != PP5_OK)
        return st;
    if ((int)raw->type < (int)VOXEL_U8 || (int)raw->type > (int)VOXEL_F64)
        return pp5_fail(PP5_E_FORMAT, "%s: unknown voxel type code %d", path, (int)raw->type);
    for (int a = 0; a < 3; a++) {
        if (!isfinite(raw->spacing[a]) || raw->spacing[a] < 0)
            return pp5_fail(PP5_E_RANGE, "%s: spacing %g on axis %d must be finite and >= 0", path,
                            raw->spacing[a], a);
    }
    if (raw->header_bytes > (1ull << 40))
        return pp5_fail(PP5_E_RANGE, "%s: header size %llu is absurd", path,
                        (unsigned long long)raw->header_bytes);
    return PP5_OK;
}

/* True when the file starts with the gzip magic bytes. */
static bool is_gzip(FILE *f)
{
    uint8_t m[2];
    bool gz = fread(m, 1, 2, f) == 2 && m[0] == 0x1f && m[1] == 0x8b;
    rewind(f);
    return gz;
}

/* Reads exactly `n` bytes or reports why not. */
static pp5_status_t gz_read_exact(gzFile gz, const char *path, uint8_t *buf, size_t n,
                                  uint64_t offset, uint64_t expected_total)
{
    size_t got = 0;
    while (got < n) {
        unsigned want = (unsigned)((n - got) > RAW_CHUNK_BYTES ? RAW_CHUNK_BYTES : (n - got));
        int r = gzread(gz, buf + got, want);
        if (r < 0) {
            int errnum;
            const char *msg = gzerror(gz, &errnum);
            return pp5_fail(PP5_E_FORMAT, "%s: decompression failed after %llu bytes: %s", path,
                            (unsigned long long)(offset + got), msg ? msg : "unknown error");
        }
        if (r == 0)
            return pp5_fail(PP5_E_FORMAT,
                            "%s: truncated: data ends after %llu bytes, expected %llu", path,
                            (unsigned long long)(offset + got),
                            (unsigned long long)expected_total);
        got += (size_t)r;
    }
    return PP5_OK;
}

pp5_status_t volume_load_raw(const char *path, const volume_raw_spec_t *raw, volume_t *out)
{
    pp5_status_t st = check_raw_spec(path, raw);
    if (st != PP5_OK)
        return st;
    size_t type_bytes = voxel_type_bytes(raw->type);
    uint64_t voxels = (uint64_t)raw->nx * (uint64_t)raw->ny * (uint64_t)raw->nz;
    uint64_t expected = raw->header_bytes + voxels * type_bytes;

    FILE *f = fopen(path, "rb");
    if (!f)
        return pp5_fail(PP5_E_IO, "%s: cannot open: %s", path, strerror(errno));
    struct stat kind;
    if (fstat(fileno(f), &kind) == 0 && S_ISDIR(kind.st_mode)) {
        fclose(f);
        return pp5_fail(PP5_E_IO, "%s: is a directory, not a volume file", path);
    }
    bool gz = is_gzip(f);
    if (!gz) {
        /* Uncompressed: the size is known up front, so check it before reading. */
        struct stat sb;
        if (fstat(fileno(f), &sb) == 0 && S_ISREG(sb.st_mode) &&
            (uint64_t)sb.st_size != expected) {
            fclose(f);
            return pp5_fail(PP5_E_FORMAT,
                            "%s: file has %llu bytes but %dx%dx%d %s voxels%s need %llu (%s)",
                            path, (unsigned long long)sb.st_size, raw->nx, raw->ny, raw->nz,
                            voxel_type_name(raw->type), raw->header_bytes ? " + header" : "",
                            (unsigned long long)expected,
                            (uint64_t)sb.st_size < expected ? "truncated" : "too long");
        }
    }
    fclose(f);
    gzFile g = gzopen(path, "rb");
    if (!g)
        return pp5_fail(PP5_E_IO, "%s: cannot open for reading", path);
    gzbuffer(g, 256 * 1024);

    volume_t tmp;
    st = volume_alloc(&tmp, raw->nx, raw->ny, raw->nz);
    uint8_t *chunk = NULL;
    if (st == PP5_OK) {
        chunk = malloc(RAW_CHUNK_BYTES);
        if (!chunk)
            st = pp5_fail(PP5_E_NOMEM, "%s: cannot allocate a read buffer", path);
    }
    /* Skip the header. */
    uint64_t skipped = 0;
    while (st == PP5_OK && skipped < raw->header_bytes) {
        uint64_t left = raw->header_bytes - skipped;
        size_t n = left > RAW_CHUNK_BYTES ? RAW_CHUNK_BYTES : (size_t)left;
        st = gz_read_exact(g, path, chunk, n, skipped, expected);
        skipped += n;
    }
    /* Voxels, a whole number of voxels per chunk. */
    size_t per_chunk = RAW_CHUNK_BYTES / type_bytes;
    for (uint64_t done = 0; st == PP5_OK && done < voxels;) {
        size_t n = (voxels - done) > per_chunk ? per_chunk : (size_t)(voxels - done);
        st = gz_read_exact(g, path, chunk, n * type_bytes,
                           raw->header_bytes + done * type_bytes, expected);
        if (st != PP5_OK)
            break;
        size_t bad;
        if (!voxels_to_float(chunk, n, raw->type, raw->big_endian, tmp.data + done, &bad)) {
            uint64_t at = done + bad;
            st = pp5_fail(PP5_E_FORMAT, "%s: voxel %llu (x=%llu y=%llu z=%llu) is NaN or infinite",
                          path, (unsigned long long)at,
                          (unsigned long long)(at % (uint64_t)raw->nx),
                          (unsigned long long)(at / (uint64_t)raw->nx % (uint64_t)raw->ny),
                          (unsigned long long)(at / ((uint64_t)raw->nx * (uint64_t)raw->ny)));
            break;
        }
        done += n;
    }
    /* Anything after the last voxel means the dimensions or type are wrong. */
    if (st == PP5_OK) {
        uint8_t extra;
        int r = gzread(g, &extra, 1);
        if (r > 0)
            st = pp5_fail(PP5_E_FORMAT,
                          "%s: too long: more data after the %llu bytes that %dx%dx%d %s "
                          "voxels need", path, (unsigned long long)expected, raw->nx, raw->ny,
                          raw->nz, voxel_type_name(raw->type));
        else if (r < 0) {
            int errnum;
            const char *msg = gzerror(g, &errnum);
            st = pp5_fail(PP5_E_FORMAT, "%s: corrupt compressed stream at its end: %s", path,
                          msg ? msg : "unknown error");
        }
    }
    free(chunk);
    gzclose(g);
    if (st != PP5_OK) {
        volume_free(&tmp);
        return st;
    }
    for (int a = 0; a < 3; a++)
        tmp.spacing[a] = raw->spacing[a] > 0 ? raw->spacing[a] : 1.0;
    snprintf(tmp.source, sizeof tmp.source, "%.480s", path);
    volume_update_stats(&tmp);
    *out = tmp;
    return PP5_OK;
}

pp5_status_t volume_save_raw_f32(const volume_t *v, const char *path)
{
    outfile_t o;     /* a temporary beside `path`, renamed when complete */
    pp5_status_t st = outfile_open(&o, path, true);
    if (st != PP5_OK)
        return st;
    size_t n = volume_voxel_count(v);
    uint8_t buf[4096];
    size_t fill = 0;
    bool ok = true;
    for (size_t i = 0; i < n && ok; i++) {
        uint32_t bits;
        memcpy(&bits, &v->data[i], sizeof bits);
        for (int b = 0; b < 4; b++)
            buf[fill++] = (uint8_t)(bits >> (8 * b));   /* little-endian on every host */
        if (fill == sizeof buf) {
            ok = fwrite(buf, 1, fill, o.f) == fill;
            fill = 0;
        }
    }
    if (ok && fill)
        ok = fwrite(buf, 1, fill, o.f) == fill;
    if (!ok) {
        outfile_discard(&o);
        return pp5_fail(PP5_E_IO, "%s: write failed", path);
    }
    return outfile_commit(&o);
}
