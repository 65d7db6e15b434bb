/* volume_slices.c: slice-series volumes in the Stanford volume archive layout:
 * one headerless file per slice, named STEM.1 .. STEM.N (e.g. CThead.1 ..
 * CThead.113), 16-bit big-endian ("Mac byte order"), square slices.
 *
 * The series is found by listing the stem's directory, so a missing slice in
 * the middle (CThead.1..CThead.40, CThead.42..) is an error naming the gap
 * rather than a silently shorter volume.  Numbering must be contiguous; it
 * may start at 0 or 1.  Every slice must have the same, exact size.  Without
 * a raw spec the side is taken from the file size (size = 2 * side^2); with
 * one, its nx, ny, type, endianness and spacing are used (nz is the count). */
#include "volume.h"
#include "volume_io.h"

#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* Splits "dir/CThead.7" or "dir/CThead" into stem "dir/CThead"; returns the
 * numeric suffix in *index (-1 when the path is the stem itself). */
static void split_stem(const char *path, char *stem, size_t stem_size, long *index)
{
    snprintf(stem, stem_size, "%s", path);
    *index = -1;
    char *dot = strrchr(stem, '.');
    char *slash = strrchr(stem, '/');
    if (!dot || (slash && dot < slash) || !dot[1])
        return;
    for (const char *p = dot + 1; *p; p++)
        if (!isdigit((unsigned char)*p))
            return;
    *index = strtol(dot + 1, NULL, 10);
    *dot = '\0';
}

static bool regular_file(const char *path, off_t *size)
{
    struct stat sb;
    if (stat(path, &sb) != 0 || !S_ISREG(sb.st_mode))
        return false;
    if (size)
        *size = sb.st_size;
    return true;
}

bool volume_is_slice_series(const char *path)
{
    char stem[1024], first[1100];
    long index;
    split_stem(path, stem, sizeof stem, &index);
    if (index >= 0)
        return regular_file(path, NULL);
    snprintf(first, sizeof first, "%s.1", path);
    if (regular_file(first, NULL))
        return true;
    snprintf(first, sizeof first, "%s.0", path);
    return regular_file(first, NULL);
}

/* Lists STEM.<digits> in the stem's directory: lowest and highest index and
 * how many distinct indices there are. */
static pp5_status_t scan_series(const char *stem, long *lo, long *hi, long *count)
{
    char dir[1024];
    const char *base;
    const char *slash = strrchr(stem, '/');
    if (slash) {
        snprintf(dir, sizeof dir, "%.*s", (int)(slash - stem), stem);
        if (!dir[0])
            snprintf(dir, sizeof dir, "/");
        base = slash + 1;
    } else {
        snprintf(dir, sizeof dir, ".");
        base = stem;
    }
    DIR *d = opendir(dir);
    if (!d)
        return pp5_fail(PP5_E_IO, "%s: cannot list directory %s: %s", stem, dir, strerror(errno));
    size_t blen = strlen(base);
    *lo = -1;
    *hi = -1;
    *count = 0;
    /* Track which indices were seen to reject duplicates such as CThead.1 and CThead.01. */
    uint8_t seen[VOLUME_MAX_SIDE + 1];
    memset(seen, 0, sizeof seen);
    pp5_status_t st = PP5_OK;
    struct dirent *e;
    while ((e = readdir(d)) != NULL && st == PP5_OK) {
        const char *name = e->d_name;
        if (strncmp(name, base, blen) != 0 || name[blen] != '.' || !name[blen + 1])
            continue;
        const char *num = name + blen + 1;
        bool digits = true;
        for (const char *p = num; *p; p++)
            digits = digits && isdigit((unsigned char)*p);
        if (!digits)
            continue;
        if (strlen(num) > 6 || strtol(num, NULL, 10) > VOLUME_MAX_SIDE) {
            st = pp5_fail(PP5_E_RANGE, "%s: slice %s.%s: index above the %d-slice limit", stem,
                          base, num, VOLUME_MAX_SIDE);
            break;
        }
        long k = strtol(num, NULL, 10);
        if (seen[k]) {
            st = pp5_fail(PP5_E_FORMAT, "%s: slice index %ld appears twice (e.g. %s)", stem, k,
                          name);
            break;
        }
        seen[k] = 1;
        (*count)++;
        if (*lo < 0 || k < *lo)
            *lo = k;
        if (k > *hi)
            *hi = k;
    }
    closedir(d);
    if (st != PP5_OK)
        return st;
    if (*count == 0)
        return pp5_fail(PP5_E_IO, "%s: no slice files %s.1, %s.2, ... found in %s", stem, base,
                        base, dir);
    if (*lo > 1)
        return pp5_fail(PP5_E_FORMAT, "%s: missing slices: numbering starts at %ld, not 0 or 1",
                        stem, *lo);
    if (*count != *hi - *lo + 1) {
        for (long k = *lo; k <= *hi; k++)
            if (!seen[k])
                return pp5_fail(PP5_E_FORMAT, "%s: missing slice %s.%ld (have %ld of %ld..%ld)",
                                stem, base, k, *count, *lo, *hi);
    }
    return PP5_OK;
}

pp5_status_t volume_load_slices(const char *path, const volume_raw_spec_t *raw, volume_t *out,
                                volume_file_info_t *info)
{
    char stem[1024];
    long index;
    split_stem(path, stem, sizeof stem, &index);
    if (index < 0)
        snprintf(stem, sizeof stem, "%s", path);
    long lo = 0, hi = -1, count = 0;
    pp5_status_t st = scan_series(stem, &lo, &hi, &count);
    if (st != PP5_OK)
        return st;

    char name[1100];
    snprintf(name, sizeof name, "%s.%ld", stem, lo);
    off_t first_size = 0;
    if (!regular_file(name, &first_size))
        return pp5_fail(PP5_E_IO, "%s: not a regular file", name);
    int nx, ny;
    voxel_type_t type = VOXEL_U16;
    bool big_endian = true;
    double spacing[3] = {1, 1, 1};
    if (raw && raw->nx > 0 && raw->ny > 0) {
        nx = raw->nx;
        ny = raw->ny;
        type = raw->type;
        big_endian = raw->big_endian;
        for (int a = 0; a < 3; a++)
            spacing[a] = raw->spacing[a] > 0 ? raw->spacing[a] : 1.0;
        if ((int)type < (int)VOXEL_U8 || (int)type > (int)VOXEL_F64)
            return pp5_fail(PP5_E_FORMAT, "%s: unknown voxel type code %d", path, (int)type);
    } else {
        /* Stanford layout: square 16-bit slices. */
        long long pixels = (long long)first_size / 2;
        long long side = (long long)llround(sqrt((double)pixels));
        if (first_size % 2 != 0 || side * side != pixels || side < 1)
            return pp5_fail(PP5_E_FORMAT, "%s: %lld bytes is not a square 16-bit slice; give the "
                            "slice size and type explicitly", name, (long long)first_size);
        if (side > VOLUME_MAX_SIDE)
            return pp5_fail(PP5_E_RANGE, "%s: slice side %lld exceeds %d", name, side,
                            VOLUME_MAX_SIDE);
        nx = ny = (int)side;
    }
    st = volume_check_dims(stem, nx, ny, count);
    if (st != PP5_OK)
        return st;
    size_t slice_voxels = (size_t)nx * (size_t)ny;
    size_t slice_bytes = slice_voxels * voxel_type_bytes(type);
    volume_t tmp;
    st = volume_alloc(&tmp, nx, ny, (int)count);
    if (st != PP5_OK)
        return st;
    uint8_t *buf = malloc(slice_bytes);
    if (!buf) {
        volume_free(&tmp);
        return pp5_fail(PP5_E_NOMEM, "%s: cannot allocate a slice buffer", stem);
    }
    for (long k = lo; k <= hi && st == PP5_OK; k++) {
        snprintf(name, sizeof name, "%s.%ld", stem, k);
        off_t size = 0;
        if (!regular_file(name, &size)) {
            st = pp5_fail(PP5_E_IO, "%s: missing or not a regular file", name);
            break;
        }
        if ((unsigned long long)size != slice_bytes) {
            st = pp5_fail(PP5_E_FORMAT, "%s: %lld bytes, but a %dx%d %s slice has %zu (%s)", name,
                          (long long)size, nx, ny, voxel_type_name(type), slice_bytes,
                          (unsigned long long)size < slice_bytes ? "truncated" : "too long");
            break;
        }
        FILE *f = fopen(name, "rb");
        if (!f || fread(buf, 1, slice_bytes, f) != slice_bytes) {
            st = pp5_fail(PP5_E_IO, "%s: cannot read: %s", name, strerror(errno));
            if (f)
                fclose(f);
            break;
        }
        fclose(f);
        size_t bad;
        if (!voxels_to_float(buf, slice_voxels, type, big_endian,
                             tmp.data + (size_t)(k - lo) * slice_voxels, &bad))
            st = pp5_fail(PP5_E_FORMAT, "%s: voxel %zu is NaN or infinite", name, bad);
    }
    free(buf);
    if (st != PP5_OK) {
        volume_free(&tmp);
        return st;
    }
    memcpy(tmp.spacing, spacing, sizeof spacing);
    snprintf(tmp.source, sizeof tmp.source, "%.480s.%ld..%ld", stem, lo, hi);
    volume_update_stats(&tmp);
    volume_set_info(info, "slices", type, big_endian);
    *out = tmp;
    return PP5_OK;
}
