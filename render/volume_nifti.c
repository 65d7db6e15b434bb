/* volume_nifti.c: NIfTI-1 volumes (.nii, .nii.gz) through niftilib (niftiio).
 *
 * niftilib parses the 348-byte header, swaps bytes and reads the data; pp5
 * reads the header first without data so that absurd dimensions are refused
 * before the library allocates, accepts 1..3 dimensions (a 4th..7th only of
 * size 1), applies scl_slope/scl_inter (a slope of 0 means "no scaling" per
 * the NIfTI-1 standard), refuses NaN/inf, and for an uncompressed .nii checks
 * that the file ends where the data ends (niftilib itself ignores extra
 * bytes; a .nii.gz is only checked for truncation). */
#include "volume.h"
#include "pp5_features.h"
#include "volume_io.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <zlib.h>

#if PP5_HAVE_NIFTI
#include <nifti1_io.h>

static bool nifti_to_voxel_type(int dt, voxel_type_t *out)
{
    switch (dt) {
    case DT_UINT8: *out = VOXEL_U8; return true;
    case DT_INT8: *out = VOXEL_I8; return true;
    case DT_INT16: *out = VOXEL_I16; return true;
    case DT_UINT16: *out = VOXEL_U16; return true;
    case DT_INT32: *out = VOXEL_I32; return true;
    case DT_UINT32: *out = VOXEL_U32; return true;
    case DT_FLOAT32: *out = VOXEL_F32; return true;
    case DT_FLOAT64: *out = VOXEL_F64; return true;
    default: return false;
    }
}

static pp5_status_t check_header(const char *path, const nifti_image *nim, int dims[3],
                                 voxel_type_t *vt)
{
    if (!nifti_to_voxel_type(nim->datatype, vt))
        return pp5_fail(PP5_E_FORMAT, "%s: NIfTI datatype %d (%s) is not supported (need an "
                        "8/16/32-bit integer, float32 or float64 scalar)", path, nim->datatype,
                        nifti_datatype_string(nim->datatype));
    int nd = nim->dim[0];
    if (nd < 1 || nd > 7)
        return pp5_fail(PP5_E_FORMAT, "%s: NIfTI dim[0] = %d, must be 1..7", path, nd);
    for (int d = 1; d <= nd; d++) {
        if (nim->dim[d] < 1)
            return pp5_fail(PP5_E_RANGE, "%s: NIfTI dim[%d] = %d, must be >= 1", path, d,
                            nim->dim[d]);
        if (d > 3 && nim->dim[d] != 1)
            return pp5_fail(PP5_E_FORMAT, "%s: NIfTI has %d dimensions with dim[%d] = %d; a "
                            "volume needs 3 (time series are not supported)", path, nd, d,
                            nim->dim[d]);
    }
    for (int a = 0; a < 3; a++)
        dims[a] = a + 1 <= nd ? nim->dim[a + 1] : 1;
    if (!isfinite(nim->scl_slope) || !isfinite(nim->scl_inter))
        return pp5_fail(PP5_E_FORMAT, "%s: NIfTI scl_slope/scl_inter is NaN or infinite", path);
    return volume_check_dims(path, dims[0], dims[1], dims[2]);
}

static bool has_suffix(const char *s, const char *suffix)
{
    size_t ls = strlen(s), lx = strlen(suffix);
    return ls >= lx && strcasecmp(s + ls - lx, suffix) == 0;
}

/* Checks the fixed part of the 348-byte header ourselves first: clearer
 * messages than niftilib's (which it prints to stderr whatever the debug
 * level), and no library call on a file that is not NIfTI-1 at all. */
static pp5_status_t precheck_header(const char *path)
{
    gzFile g = gzopen(path, "rb");
    if (!g)
        return pp5_fail(PP5_E_IO, "%s: cannot open", path);
    uint8_t h[348];
    int got = gzread(g, h, sizeof h);
    gzclose(g);
    if (got != (int)sizeof h)
        return pp5_fail(PP5_E_FORMAT, "%s: truncated: %d bytes, a NIfTI-1 header needs 348",
                        path, got < 0 ? 0 : got);
    uint32_t le = (uint32_t)h[0] | (uint32_t)h[1] << 8 | (uint32_t)h[2] << 16 |
                  (uint32_t)h[3] << 24;
    uint32_t be = (uint32_t)h[3] | (uint32_t)h[2] << 8 | (uint32_t)h[1] << 16 |
                  (uint32_t)h[0] << 24;
    if (le != 348 && be != 348)
        return pp5_fail(PP5_E_FORMAT, "%s: not NIfTI-1: sizeof_hdr is %u, not 348", path,
                        (unsigned)le);
    bool big = le != 348;
    if (memcmp(h + 344, "n+1", 4) != 0 && memcmp(h + 344, "ni1", 4) != 0)
        return pp5_fail(PP5_E_FORMAT, "%s: not NIfTI-1: magic is not \"n+1\" or \"ni1\"",
                        path);
    int dim[8];
    for (int i = 0; i < 8; i++) {
        const uint8_t *p = h + 40 + 2 * i;
        dim[i] = (int16_t)(big ? (p[0] << 8 | p[1]) : (p[1] << 8 | p[0]));
    }
    if (dim[0] < 1 || dim[0] > 7)
        return pp5_fail(PP5_E_FORMAT, "%s: NIfTI dim[0] = %d, must be 1..7", path, dim[0]);
    for (int i = 1; i <= dim[0]; i++)
        if (dim[i] < 1)
            return pp5_fail(PP5_E_RANGE, "%s: NIfTI dim[%d] = %d, must be >= 1", path, i, dim[i]);
    return PP5_OK;
}

pp5_status_t volume_load_nifti(const char *path, volume_t *out, volume_file_info_t *info)
{
    /* niftilib prints its own diagnostics at debug level >= 1; pp5 reports
     * through pp5_fail instead. */
    nifti_set_debug_level(0);
    FILE *probe = fopen(path, "rb");
    if (!probe)
        return pp5_fail(PP5_E_IO, "%s: cannot open: %s", path, strerror(errno));
    fclose(probe);
    pp5_status_t pre = precheck_header(path);
    if (pre != PP5_OK)
        return pre;
    nifti_image *nim = nifti_image_read(path, 0);
    if (!nim)
        return pp5_fail(PP5_E_FORMAT, "%s: not a readable NIfTI-1 header", path);
    int dims[3] = {0, 0, 0};
    voxel_type_t vt = VOXEL_U8;
    pp5_status_t st = check_header(path, nim, dims, &vt);
    size_t voxels = (size_t)dims[0] * (size_t)dims[1] * (size_t)dims[2];
    if (st == PP5_OK && nim->iname_offset < 0)
        st = pp5_fail(PP5_E_FORMAT, "%s: negative vox_offset %d", path, nim->iname_offset);
    if (st == PP5_OK && has_suffix(path, ".nii") && nim->iname && strcmp(nim->iname, path) == 0) {
        struct stat sb;
        unsigned long long want = (unsigned long long)nim->iname_offset +
                                  (unsigned long long)voxels * voxel_type_bytes(vt);
        if (stat(path, &sb) == 0 && (unsigned long long)sb.st_size != want)
            st = pp5_fail(PP5_E_FORMAT, "%s: file has %llu bytes, header says %llu (%s)", path,
                          (unsigned long long)sb.st_size, want,
                          (unsigned long long)sb.st_size < want ? "truncated" : "too long");
    }
    if (st == PP5_OK && nifti_image_load(nim) != 0)
        st = pp5_fail(PP5_E_FORMAT, "%s: NIfTI data missing or truncated", path);
    volume_t tmp;
    if (st == PP5_OK)
        st = volume_alloc(&tmp, dims[0], dims[1], dims[2]);
    if (st == PP5_OK) {
        /* niftilib has already swapped the data to host order. */
        const uint16_t one = 1;
        bool host_big_endian = *(const uint8_t *)&one == 0;
        size_t bad;
        if (!voxels_to_float((const uint8_t *)nim->data, voxels, vt, host_big_endian, tmp.data,
                             &bad))
            st = pp5_fail(PP5_E_FORMAT, "%s: voxel %zu is NaN or infinite", path, bad);
        else if (nim->scl_slope != 0.0f) {
            for (size_t i = 0; i < voxels && st == PP5_OK; i++) {
                float f = (float)((double)nim->scl_slope * tmp.data[i] + nim->scl_inter);
                if (!isfinite(f))
                    st = pp5_fail(PP5_E_FORMAT, "%s: voxel %zu overflows after scl_slope", path, i);
                tmp.data[i] = f;
            }
        }
        if (st != PP5_OK)
            volume_free(&tmp);
    }
    if (st == PP5_OK) {
        const float pix[3] = {nim->dx, nim->dy, nim->dz};
        for (int a = 0; a < 3; a++)
            tmp.spacing[a] = (isfinite(pix[a]) && pix[a] != 0.0f) ? fabs((double)pix[a]) : 1.0;
        snprintf(tmp.source, sizeof tmp.source, "%.480s", path);
        volume_update_stats(&tmp);
        volume_set_info(info, "nifti", vt, nim->byteorder == 2 /* MSB_FIRST in niftilib */);
        *out = tmp;
    }
    nifti_image_free(nim);
    return st;
}

#else

pp5_status_t volume_load_nifti(const char *path, volume_t *out, volume_file_info_t *info)
{
    (void)out;
    (void)info;
    return pp5_fail(PP5_E_UNSUPPORTED, "%s: NIfTI support needs niftilib (libniftiio-dev); "
                    "rebuild after installing it", path);
}

#endif
