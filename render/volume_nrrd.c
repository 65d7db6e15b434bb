/* volume_nrrd.c: NRRD volumes (.nrrd with attached header, .nhdr with a
 * detached data file) through Teem's nrrd library, and the NRRD writer.
 *
 * Teem does the parsing (all encodings it supports: raw, ascii, hex, gzip,
 * bzip2), byte swapping and detached-file handling.  pp5 adds what Teem does
 * not check for us: the header is read first without data (skipData) so that
 * absurd sizes are refused before Teem allocates anything; exactly three axes
 * (a leading axis of size 1 is accepted and dropped); NaN/inf in float data;
 * and, for an attached raw-encoded file, bytes left over after the data. */
#include "volume.h"
#include "pp5_features.h"
#include "volume_io.h"
#include "outfile.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#if PP5_HAVE_TEEM
#include <nrrd.h>

static pp5_status_t teem_failure(pp5_status_t st, const char *path, const char *what)
{
    char *err = biffGetDone(NRRD);
    /* Teem's messages span several lines ("[nrrd] ..."); keep the last,
     * most specific one on our single line. */
    const char *msg = err ? err : "no detail";
    size_t len = strlen(msg);
    while (len > 0 && (msg[len - 1] == '\n' || msg[len - 1] == ' '))
        len--;
    const char *line = msg;
    for (size_t i = 0; i + 1 < len; i++)
        if (msg[i] == '\n')
            line = msg + i + 1;
    int line_len = (int)(len - (size_t)(line - msg));
    pp5_fail(st, "%s: %s: %.*s", path, what, line_len > 300 ? 300 : line_len, line);
    free(err);
    return st;
}

static bool nrrd_to_voxel_type(int t, voxel_type_t *out)
{
    switch (t) {
    case nrrdTypeChar: *out = VOXEL_I8; return true;
    case nrrdTypeUChar: *out = VOXEL_U8; return true;
    case nrrdTypeShort: *out = VOXEL_I16; return true;
    case nrrdTypeUShort: *out = VOXEL_U16; return true;
    case nrrdTypeInt: *out = VOXEL_I32; return true;
    case nrrdTypeUInt: *out = VOXEL_U32; return true;
    case nrrdTypeFloat: *out = VOXEL_F32; return true;
    case nrrdTypeDouble: *out = VOXEL_F64; return true;
    default: return false;
    }
}

/* Checks the header-only parse: type, axes, sizes.  Fills dims and the index
 * of the first spatial axis. */
static pp5_status_t check_header(const char *path, const Nrrd *n, int dims[3], unsigned *first)
{
    voxel_type_t vt;
    if (!nrrd_to_voxel_type(n->type, &vt))
        return pp5_fail(PP5_E_FORMAT, "%s: NRRD type %d is not supported (need an 8/16/32-bit "
                        "integer, float or double scalar)", path, n->type);
    *first = 0;
    if (n->dim == 4 && n->axis[0].size == 1)
        *first = 1;
    else if (n->dim != 3)
        return pp5_fail(PP5_E_FORMAT, "%s: NRRD has %u axes; a volume needs exactly 3", path,
                        n->dim);
    for (int a = 0; a < 3; a++) {
        size_t s = n->axis[*first + (unsigned)a].size;
        if (s < 1 || s > VOLUME_MAX_SIDE)
            return pp5_fail(PP5_E_RANGE, "%s: NRRD axis %d has size %zu, outside 1..%d", path, a,
                            s, VOLUME_MAX_SIDE);
        dims[a] = (int)s;
    }
    return volume_check_dims(path, dims[0], dims[1], dims[2]);
}

/* For an attached header with raw encoding: the data must end the file. */
static pp5_status_t check_attached_raw_length(const char *path, const Nrrd *n,
                                              const NrrdIoState *nio)
{
    if (nio->encoding != nrrdEncodingRaw || nio->dataFNArr->len > 0 || nio->dataFNFormat ||
        nio->byteSkip != 0 || nio->lineSkip != 0)
        return PP5_OK;
    FILE *f = fopen(path, "rb");
    if (!f)
        return PP5_OK;
    /* The header ends at the first empty line. */
    long header_end = -1;
    int prev = -1, c;
    long pos = 0;
    while ((c = fgetc(f)) != EOF) {
        pos++;
        if (c == '\n' && prev == '\n') {
            header_end = pos;
            break;
        }
        if (c != '\r')
            prev = c;
    }
    struct stat sb;
    bool have_size = fstat(fileno(f), &sb) == 0;
    fclose(f);
    if (header_end < 0 || !have_size)
        return PP5_OK;
    unsigned long long want = (unsigned long long)header_end +
                              (unsigned long long)nrrdElementNumber(n) * nrrdElementSize(n);
    if ((unsigned long long)sb.st_size > want)
        return pp5_fail(PP5_E_FORMAT, "%s: too long: %llu bytes after the header, the sizes "
                        "need %llu", path, (unsigned long long)sb.st_size - (unsigned long long)header_end,
                        want - (unsigned long long)header_end);
    return PP5_OK;
}

pp5_status_t volume_load_nrrd(const char *path, volume_t *out, volume_file_info_t *info)
{
    int dims[3];
    unsigned first = 0;
    FILE *exists = fopen(path, "rb");
    if (!exists)
        return pp5_fail(PP5_E_IO, "%s: cannot open: %s", path, strerror(errno));
    fclose(exists);
    pp5_status_t pre = volume_nrrd_precheck(path);
    if (pre != PP5_OK)
        return pre;
    Nrrd *n = nrrdNew();
    NrrdIoState *nio = nrrdIoStateNew();
    if (!n || !nio) {
        nrrdNix(n);
        nrrdIoStateNix(nio);
        return pp5_fail(PP5_E_NOMEM, "%s: cannot allocate NRRD state", path);
    }
    /* Pass 1: header only, so absurd sizes never reach an allocation. */
    nio->skipData = 1;
    pp5_status_t st = PP5_OK;
    if (nrrdLoad(n, path, nio))
        st = teem_failure(PP5_E_FORMAT, path, "bad NRRD header");
    else
        st = check_header(path, n, dims, &first);
    if (st == PP5_OK)
        st = check_attached_raw_length(path, n, nio);
    nrrdNuke(n);
    nrrdIoStateNix(nio);
    if (st != PP5_OK)
        return st;

    /* Pass 2: the data. */
    n = nrrdNew();
    if (nrrdLoad(n, path, NULL)) {
        st = teem_failure(PP5_E_FORMAT, path, "cannot read NRRD data");
        nrrdNuke(n);
        return st;
    }
    int dims2[3];
    st = check_header(path, n, dims2, &first);
    if (st == PP5_OK && (dims2[0] != dims[0] || dims2[1] != dims[1] || dims2[2] != dims[2]))
        st = pp5_fail(PP5_E_IO, "%s: changed while being read", path);
    volume_t tmp;
    if (st == PP5_OK)
        st = volume_alloc(&tmp, dims[0], dims[1], dims[2]);
    if (st == PP5_OK) {
        voxel_type_t vt = VOXEL_U8;   /* set by nrrd_to_voxel_type: check_header accepted the type */
        nrrd_to_voxel_type(n->type, &vt);
        const uint16_t probe = 1;
        bool host_big_endian = *(const uint8_t *)&probe == 0;
        size_t bad;
        if (!voxels_to_float((const uint8_t *)n->data, volume_voxel_count(&tmp), vt,
                             host_big_endian, tmp.data, &bad)) {
            st = pp5_fail(PP5_E_FORMAT, "%s: voxel %zu is NaN or infinite", path, bad);
            volume_free(&tmp);
        }
    }
    if (st == PP5_OK) {
        for (int a = 0; a < 3; a++) {
            double spacing = 1.0, dir[NRRD_SPACE_DIM_MAX];
            int ss = nrrdSpacingCalculate(n, first + (unsigned)a, &spacing, dir);
            if ((ss == nrrdSpacingStatusScalarNoSpace || ss == nrrdSpacingStatusScalarWithSpace ||
                 ss == nrrdSpacingStatusDirection) && isfinite(spacing) && spacing != 0)
                tmp.spacing[a] = fabs(spacing);
            else
                tmp.spacing[a] = 1.0;
        }
        snprintf(tmp.source, sizeof tmp.source, "%.480s", path);
        volume_update_stats(&tmp);
        voxel_type_t vt = VOXEL_U8;   /* set by nrrd_to_voxel_type: check_header accepted the type */
        nrrd_to_voxel_type(n->type, &vt);
        const uint16_t probe = 1;
        volume_set_info(info, "nrrd", vt, *(const uint8_t *)&probe == 0);
        *out = tmp;
    }
    nrrdNuke(n);
    return st;
}

pp5_status_t volume_save_nrrd(const volume_t *v, const char *path)
{
    Nrrd *n = nrrdNew();
    if (!n)
        return pp5_fail(PP5_E_NOMEM, "%s: cannot allocate NRRD state", path);
    /* nrrdWrap does not copy and nrrdNix does not free the data. */
    if (nrrdWrap_va(n, v->data, nrrdTypeFloat, 3, (size_t)v->nx, (size_t)v->ny, (size_t)v->nz)) {
        nrrdNix(n);
        return teem_failure(PP5_E_IO, path, "cannot describe volume");
    }
    nrrdAxisInfoSet_va(n, nrrdAxisInfoSpacing, v->spacing[0], v->spacing[1], v->spacing[2]);
    /* Teem writes a temporary beside `path` (its name keeps the .nrrd ending,
     * which tells Teem the format), renamed once complete.  A .nhdr would name
     * its data file after the temporary, so it is written in place. */
    outfile_t o;
    pp5_status_t st = outfile_open(&o, path, true);
    if (st != PP5_OK) {
        nrrdNix(n);
        return st;
    }
    bool detached = strlen(path) > 5 && strcasecmp(path + strlen(path) - 5, ".nhdr") == 0;
    outfile_release_stream(&o);
    if (detached)
        outfile_discard(&o);
    if (nrrdSave(detached ? path : outfile_write_path(&o), n, NULL)) {
        st = teem_failure(PP5_E_IO, path, "cannot write NRRD");
        outfile_discard(&o);
    } else if (!detached) {
        st = outfile_commit(&o);
    }
    nrrdNix(n);
    return st;
}

#else

pp5_status_t volume_load_nrrd(const char *path, volume_t *out, volume_file_info_t *info)
{
    (void)out;
    (void)info;
    return pp5_fail(PP5_E_UNSUPPORTED, "%s: NRRD support needs Teem (libteem-dev); rebuild "
                    "after installing it", path);
}

pp5_status_t volume_save_nrrd(const volume_t *v, const char *path)
{
    (void)v;
    return pp5_fail(PP5_E_UNSUPPORTED, "%s: NRRD support needs Teem (libteem-dev)", path);
}

#endif
