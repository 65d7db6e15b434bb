/* volume_io.h: the per-format volume loaders behind volume_load (private to
 * render/ and the tests; callers normally use volume_load). */
#ifndef PP5_VOLUME_IO_H
#define PP5_VOLUME_IO_H

#include "volume.h"

/* Every loader parses and validates into a temporary and writes *out only on
 * success (with source, spacing, min/max and hash filled in). */
pp5_status_t volume_load_nrrd(const char *path, volume_t *out, volume_file_info_t *info);
/* What volume_load_nrrd checks before Teem sees the file
 * (volume_nrrd_header.c): magic, header size (PP5_MAX_HEADER_BYTES), and the
 * detached data files (count within PP5_MAX_DATA_FILES, never the header
 * itself, never another header). */
pp5_status_t volume_nrrd_precheck(const char *path);
pp5_status_t volume_load_nifti(const char *path, volume_t *out, volume_file_info_t *info);
pp5_status_t volume_load_den(const char *path, volume_t *out, volume_file_info_t *info);
/* `path` is the first slice ("dir/CThead.1") or the stem ("dir/CThead").
 * `raw` may give nx, ny, type and endianness; otherwise slices are 16-bit
 * big-endian and square (side from the file size), as in the Stanford archive. */
pp5_status_t volume_load_slices(const char *path, const volume_raw_spec_t *raw, volume_t *out,
                                volume_file_info_t *info);
bool volume_is_slice_series(const char *path);
/* Fills *info (if not NULL). */
void volume_set_info(volume_file_info_t *info, const char *format, voxel_type_t type,
                     bool big_endian);

/* PP5_E_RANGE naming `what` unless 1 <= n <= VOLUME_MAX_SIDE on every axis and
 * the product is within the PP5_MAX_VOXELS limit (input_limits.h). */
pp5_status_t volume_check_dims(const char *what, long long nx, long long ny, long long nz);
/* Converts n voxels of `type` from `bytes` (file byte order given by
 * big_endian) to float; false (and *bad_index set) at the first NaN/inf. */
bool voxels_to_float(const uint8_t *bytes, size_t n, voxel_type_t type, bool big_endian,
                     float *dst, size_t *bad_index);

#endif
