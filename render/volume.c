/* volume.c: volume allocation, statistics, trilinear resampling, and
 * volume_load's choice of loader from the file name. */
#include "volume.h"
#include "volume_io.h"
#include "input_limits.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

pp5_status_t volume_check_dims(const char *what, long long nx, long long ny, long long nz)
{
    if (nx < 1 || ny < 1 || nz < 1 || nx > VOLUME_MAX_SIDE || ny > VOLUME_MAX_SIDE ||
        nz > VOLUME_MAX_SIDE)
        return pp5_fail(PP5_E_RANGE, "%s: dimensions %lldx%lldx%lld outside 1..%d per side",
                        what, nx, ny, nz, VOLUME_MAX_SIDE);
    /* Each side is <= 4096, so the product fits in 64 bits without overflow. */
    unsigned long long voxels = (unsigned long long)nx * (unsigned long long)ny *
                                (unsigned long long)nz;
    char where[700];
    snprintf(where, sizeof where, "%.600s: %lldx%lldx%lld", what, nx, ny, nz);
    return pp5_limit_check(PP5_LIMIT_VOXELS, voxels, where);
}

pp5_status_t volume_alloc(volume_t *v, int nx, int ny, int nz)
{
    memset(v, 0, sizeof *v);
    pp5_status_t st = volume_check_dims("volume_alloc", nx, ny, nz);
    if (st != PP5_OK)
        return st;
    size_t count, bytes;
    if (!pp5_mul3_size((size_t)nx, (size_t)ny, (size_t)nz, &count) ||
        !pp5_mul_size(count, sizeof(float), &bytes))
        return pp5_fail(PP5_E_NOMEM, "volume %dx%dx%d is too large for this host", nx, ny, nz);
    v->data = calloc(count, sizeof(float));
    if (!v->data)
        return pp5_fail(PP5_E_NOMEM, "cannot allocate a %dx%dx%d volume (%zu bytes)", nx, ny, nz,
                        bytes);
    v->nx = nx;
    v->ny = ny;
    v->nz = nz;
    v->spacing[0] = v->spacing[1] = v->spacing[2] = 1.0;
    return PP5_OK;
}

void volume_free(volume_t *v)
{
    if (!v)
        return;
    free(v->data);
    memset(v, 0, sizeof *v);
}

size_t volume_voxel_count(const volume_t *v)
{
    return (size_t)v->nx * (size_t)v->ny * (size_t)v->nz;
}

void volume_update_stats(volume_t *v)
{
    size_t n = volume_voxel_count(v);
    float lo = INFINITY, hi = -INFINITY;
    /* FNV-1a 64 over each float's IEEE bits taken as little-endian bytes, so the
     * hash of the same volume is the same on any host. */
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < n; i++) {
        float f = v->data[i];
        if (f < lo)
            lo = f;
        if (f > hi)
            hi = f;
        uint32_t bits;
        memcpy(&bits, &f, sizeof bits);
        for (int b = 0; b < 4; b++) {
            h ^= (bits >> (8 * b)) & 0xffu;
            h *= 1099511628211ull;
        }
    }
    v->min_value = n ? lo : 0.0f;
    v->max_value = n ? hi : 0.0f;
    v->hash = h;
}

/* Grid position of output sample i on an input axis of n_in samples: the end
 * samples of both grids coincide (corner alignment), so a resampled volume
 * spans the same physical extent and the spacing scales by (n_in-1)/(n_out-1). */
static double resample_coord(int i, int n_in, int n_out)
{
    if (n_out == 1 || n_in == 1)
        return (n_in - 1) * 0.5;
    return (double)i * (double)(n_in - 1) / (double)(n_out - 1);
}

pp5_status_t volume_resample(const volume_t *in, int nx, int ny, int nz, volume_t *out)
{
    if (!in || !in->data)
        return pp5_fail(PP5_E_RANGE, "volume_resample: empty input volume");
    volume_t tmp;
    pp5_status_t st = volume_alloc(&tmp, nx, ny, nz);
    if (st != PP5_OK)
        return st;
    const int n_out[3] = {nx, ny, nz};
    const int n_in[3] = {in->nx, in->ny, in->nz};
    for (int a = 0; a < 3; a++) {
        double s = in->spacing[a] > 0 ? in->spacing[a] : 1.0;
        tmp.spacing[a] = (n_out[a] > 1 && n_in[a] > 1)
                             ? s * (double)(n_in[a] - 1) / (double)(n_out[a] - 1)
                             : s * n_in[a] / n_out[a];
    }
    for (int z = 0; z < nz; z++) {
        double fz = resample_coord(z, in->nz, nz);
        int z0 = (int)floor(fz);
        if (z0 > in->nz - 2)
            z0 = in->nz > 1 ? in->nz - 2 : 0;
        double tz = in->nz > 1 ? fz - z0 : 0.0;
        int z1 = in->nz > 1 ? z0 + 1 : 0;
        for (int y = 0; y < ny; y++) {
            double fy = resample_coord(y, in->ny, ny);
            int y0 = (int)floor(fy);
            if (y0 > in->ny - 2)
                y0 = in->ny > 1 ? in->ny - 2 : 0;
            double ty = in->ny > 1 ? fy - y0 : 0.0;
            int y1 = in->ny > 1 ? y0 + 1 : 0;
            for (int x = 0; x < nx; x++) {
                double fx = resample_coord(x, in->nx, nx);
                int x0 = (int)floor(fx);
                if (x0 > in->nx - 2)
                    x0 = in->nx > 1 ? in->nx - 2 : 0;
                double tx = in->nx > 1 ? fx - x0 : 0.0;
                int x1 = in->nx > 1 ? x0 + 1 : 0;
                double c00 = volume_at(in, x0, y0, z0) * (1 - tx) + volume_at(in, x1, y0, z0) * tx;
                double c10 = volume_at(in, x0, y1, z0) * (1 - tx) + volume_at(in, x1, y1, z0) * tx;
                double c01 = volume_at(in, x0, y0, z1) * (1 - tx) + volume_at(in, x1, y0, z1) * tx;
                double c11 = volume_at(in, x0, y1, z1) * (1 - tx) + volume_at(in, x1, y1, z1) * tx;
                double c0 = c00 * (1 - ty) + c10 * ty;
                double c1 = c01 * (1 - ty) + c11 * ty;
                tmp.data[((size_t)z * ny + y) * nx + x] = (float)(c0 * (1 - tz) + c1 * tz);
            }
        }
    }
    snprintf(tmp.source, sizeof tmp.source, "%.400s resampled to %dx%dx%d", in->source, nx, ny,
             nz);
    volume_update_stats(&tmp);
    *out = tmp;
    return PP5_OK;
}

static bool ends_with(const char *s, const char *suffix)
{
    size_t ls = strlen(s), lx = strlen(suffix);
    return ls >= lx && strcasecmp(s + ls - lx, suffix) == 0;
}

static bool file_exists(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0 && S_ISREG(sb.st_mode);
}

void volume_set_info(volume_file_info_t *info, const char *format, voxel_type_t type,
                     bool big_endian)
{
    if (!info)
        return;
    snprintf(info->format, sizeof info->format, "%s", format);
    info->stored_type = type;
    info->big_endian = big_endian;
}

static bool starts_gzip(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return false;
    unsigned char m[2];
    bool gz = fread(m, 1, 2, f) == 2 && m[0] == 0x1f && m[1] == 0x8b;
    fclose(f);
    return gz;
}

static pp5_status_t load_raw_info(const char *path, const volume_raw_spec_t *spec, volume_t *out,
                                  volume_file_info_t *info)
{
    pp5_status_t st = volume_load_raw(path, spec, out);
    if (st == PP5_OK)
        volume_set_info(info, starts_gzip(path) ? "raw.gz" : "raw", spec->type, spec->big_endian);
    return st;
}

pp5_status_t volume_load(const char *path, const volume_raw_spec_t *raw, volume_t *out)
{
    return volume_load_info(path, raw, out, NULL);
}

pp5_status_t volume_load_info(const char *path, const volume_raw_spec_t *raw, volume_t *out,
                              volume_file_info_t *info)
{
    if (!path || !*path)
        return pp5_fail(PP5_E_CONFIG, "volume_load: no file name given");
    /* Self-describing formats first: their headers win over any raw spec. */
    if (ends_with(path, ".nrrd") || ends_with(path, ".nhdr"))
        return volume_load_nrrd(path, out, info);
    if (ends_with(path, ".nii") || ends_with(path, ".nii.gz"))
        return volume_load_nifti(path, out, info);
    if (ends_with(path, ".den") || ends_with(path, ".den.gz"))
        return volume_load_den(path, out, info);
    /* Stanford slice series: "dir/CThead.1" or the stem "dir/CThead" (a raw
     * spec, if given, describes one slice). */
    if (volume_is_slice_series(path))
        return volume_load_slices(path, raw, out, info);
    if (raw && raw->nx > 0)
        return load_raw_info(path, raw, out, info);
    /* Raw files whose name states the layout, as in shared/data:
     * cthead_256x256x113_u16be.raw.gz. */
    volume_raw_spec_t spec;
    pp5_status_t named = volume_raw_spec_from_name(path, &spec);
    if (named == PP5_OK)
        return load_raw_info(path, &spec, out, info);
    if (named == PP5_E_RANGE)
        return named;      /* the name states a layout over the limits: say so */
    if (!file_exists(path))
        return pp5_fail(PP5_E_IO, "%s: no such file (and no slice series %s.1, %s.2, ...)", path,
                        path, path);
    return pp5_fail(PP5_E_FORMAT,
                    "%s: unknown volume format (expected .nrrd, .nhdr, .nii, .nii.gz, .den, "
                    "a slice series NAME.1..NAME.N, a name like vol_64x64x32_u16be.raw, or raw "
                    "dimensions and type given explicitly)", path);
}

const char *voxel_type_name(voxel_type_t t)
{
    switch (t) {
    case VOXEL_U8: return "u8";
    case VOXEL_I8: return "i8";
    case VOXEL_U16: return "u16";
    case VOXEL_I16: return "i16";
    case VOXEL_U32: return "u32";
    case VOXEL_I32: return "i32";
    case VOXEL_F32: return "f32";
    case VOXEL_F64: return "f64";
    }
    return "?";
}

size_t voxel_type_bytes(voxel_type_t t)
{
    switch (t) {
    case VOXEL_U8: case VOXEL_I8: return 1;
    case VOXEL_U16: case VOXEL_I16: return 2;
    case VOXEL_U32: case VOXEL_I32: case VOXEL_F32: return 4;
    case VOXEL_F64: return 8;
    }
    return 0;
}

pp5_status_t voxel_type_parse(const char *text, voxel_type_t *type)
{
    static const struct { const char *name; voxel_type_t t; } names[] = {
        {"u8", VOXEL_U8}, {"uint8", VOXEL_U8}, {"uchar", VOXEL_U8},
        {"i8", VOXEL_I8}, {"int8", VOXEL_I8}, {"char", VOXEL_I8},
        {"u16", VOXEL_U16}, {"uint16", VOXEL_U16}, {"ushort", VOXEL_U16},
        {"i16", VOXEL_I16}, {"int16", VOXEL_I16}, {"short", VOXEL_I16},
        {"u32", VOXEL_U32}, {"uint32", VOXEL_U32}, {"uint", VOXEL_U32},
        {"i32", VOXEL_I32}, {"int32", VOXEL_I32}, {"int", VOXEL_I32},
        {"f32", VOXEL_F32}, {"float32", VOXEL_F32}, {"float", VOXEL_F32},
        {"f64", VOXEL_F64}, {"float64", VOXEL_F64}, {"double", VOXEL_F64},
    };
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        if (strcasecmp(text, names[i].name) == 0) {
            *type = names[i].t;
            return PP5_OK;
        }
    }
    return pp5_fail(PP5_E_CONFIG,
                    "unknown voxel type '%s' (expected u8, i8, u16, i16, u32, i32, f32 or f64)",
                    text);
}

/* Finds "_NXxNYxNZ_TYPE" with an optional "be"/"le" suffix on TYPE in the file
 * name (directory excluded), e.g. brainsmall_128x128x84_u8.raw.gz. */
pp5_status_t volume_raw_spec_from_name(const char *path, volume_raw_spec_t *spec)
{
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    for (const char *p = base; *p; p++) {
        if (*p != '_')
            continue;
        int nx, ny, nz, used = 0;
        char type[16];
        if (sscanf(p, "_%dx%dx%d_%15[a-zA-Z0-9]%n", &nx, &ny, &nz, type, &used) != 4)
            continue;
        char next = p[used];
        if (next != '.' && next != '_' && next != '\0')
            continue;
        volume_raw_spec_t s;
        memset(&s, 0, sizeof s);
        s.nx = nx;
        s.ny = ny;
        s.nz = nz;
        size_t tl = strlen(type);
        s.big_endian = false;
        if (tl > 2 && (strcasecmp(type + tl - 2, "be") == 0 || strcasecmp(type + tl - 2, "le") == 0)) {
            s.big_endian = strcasecmp(type + tl - 2, "be") == 0;
            type[tl - 2] = '\0';
        }
        if (voxel_type_parse(type, &s.type) != PP5_OK)
            continue;
        if (volume_check_dims(path, nx, ny, nz) != PP5_OK)
            return PP5_E_RANGE;
        *spec = s;
        return PP5_OK;
    }
    return pp5_fail(PP5_E_FORMAT, "%s: name does not state _NXxNYxNZ_TYPE", path);
}

pp5_status_t volume_parse_size3(const char *opt, const char *text, int *nx, int *ny, int *nz)
{
    long v[3];
    const char *p = text ? text : "";
    for (int a = 0; a < 3; a++) {
        char *end;
        if (*p < '0' || *p > '9')
            goto bad;
        errno = 0;
        v[a] = strtol(p, &end, 10);
        if (errno == ERANGE || end == p)
            goto bad;
        if (a < 2 && *end != 'x' && *end != 'X')
            goto bad;
        if (a == 2 && *end != '\0')
            goto bad;
        p = end + (a < 2 ? 1 : 0);
        if (v[a] < 1 || v[a] > VOLUME_MAX_SIDE)
            return pp5_fail(PP5_E_CONFIG, "%s: side %ld is outside 1..%d", opt, v[a],
                            VOLUME_MAX_SIDE);
    }
    char where[300];
    snprintf(where, sizeof where, "%s %.200s", opt, text);
    if (pp5_limit_check(PP5_LIMIT_VOXELS, (uint64_t)v[0] * (uint64_t)v[1] * (uint64_t)v[2],
                        where) != PP5_OK)
        return PP5_E_CONFIG;
    *nx = (int)v[0];
    *ny = (int)v[1];
    *nz = (int)v[2];
    return PP5_OK;
bad:
    return pp5_fail(PP5_E_CONFIG, "%s: expected NXxNYxNZ (e.g. 256x256x113), got '%s'", opt,
                    text ? text : "");
}

pp5_status_t volume_parse_spacing3(const char *opt, const char *text, double spacing[3])
{
    double v[3];
    const char *p = text ? text : "";
    for (int a = 0; a < 3; a++) {
        char *end;
        errno = 0;
        v[a] = strtod(p, &end);
        if (end == p || errno == ERANGE || !isfinite(v[a]) || v[a] <= 0 ||
            (a < 2 && *end != ',') || (a == 2 && *end != '\0'))
            return pp5_fail(PP5_E_CONFIG, "%s: expected three positive numbers SX,SY,SZ, got "
                            "'%s'", opt, text ? text : "");
        p = end + 1;
    }
    memcpy(spacing, v, sizeof v);
    return PP5_OK;
}
