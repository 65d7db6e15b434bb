/* volume.h: the volume type every renderer uses, its loaders, and the
 * procedural phantoms.
 *
 * Voxels are converted to float on load (x fastest, then y, then z) and keep
 * their original units (CT numbers, MR intensities, 0..255 for 8-bit data), so
 * classification presets can be written in the data's own units.  Loaders
 * parse and validate completely before they return, so a truncated or
 * inconsistent file never yields a half-filled volume. */
#ifndef PP5_VOLUME_H
#define PP5_VOLUME_H

#include <stdbool.h>
#include <stdint.h>
#include "status.h"

/* Largest accepted side: far beyond any data pp5 expects.  The voxel count is
 * bounded by the PP5_MAX_VOXELS limit (input_limits.h), which a user can
 * raise, so an absurd header is refused before any allocation. */
#define VOLUME_MAX_SIDE 4096

typedef enum { VOXEL_U8, VOXEL_I8, VOXEL_U16, VOXEL_I16, VOXEL_U32, VOXEL_I32, VOXEL_F32,
               VOXEL_F64 } voxel_type_t;

typedef struct {
    int nx, ny, nz;
    double spacing[3];     /* voxel spacing (x, y, z), in the file's units (mm if known) */
    float *data;           /* nx*ny*nz values, x fastest */
    float min_value, max_value;
    char source[512];      /* what was loaded: path or "phantom shepp-logan 256x256x109" */
    uint64_t hash;         /* FNV-1a 64 of the float data, for reports */
} volume_t;

/* How to read a headerless raw file (also used for .gz raw files). */
typedef struct {
    int nx, ny, nz;
    voxel_type_t type;
    bool big_endian;
    double spacing[3];     /* 0 means 1 */
    uint64_t header_bytes; /* bytes to skip before the voxels */
} volume_raw_spec_t;

/* Loads by file name: .nrrd/.nhdr (Teem), .nii/.nii.gz (niftilib), .den
 * (VolPack), a Stanford slice series given as its first slice or stem
 * (CThead.1 .. CThead.N), or raw (needs `raw`; .gz is decompressed).
 * `raw` may be NULL for self-describing formats. */
pp5_status_t volume_load(const char *path, const volume_raw_spec_t *raw, volume_t *out);
pp5_status_t volume_load_raw(const char *path, const volume_raw_spec_t *raw, volume_t *out);
/* Allocates an nx*ny*nz volume of zeros (checked sizes). */
pp5_status_t volume_alloc(volume_t *v, int nx, int ny, int nz);
void volume_free(volume_t *v);
/* Recomputes min_value, max_value and hash after the data changed. */
void volume_update_stats(volume_t *v);
/* Resamples to new dimensions (trilinear), e.g. 128x128x84 -> 128x128x109. */
pp5_status_t volume_resample(const volume_t *in, int nx, int ny, int nz, volume_t *out);

static inline float volume_at(const volume_t *v, int x, int y, int z)
{
    return v->data[((size_t)z * (size_t)v->ny + (size_t)y) * (size_t)v->nx + (size_t)x];
}

/* Procedural phantoms: "shepp-logan" (3D, MR-like; default 256x256x109),
 * "marschner-lobb" (default 41x41x41), "sphere-shell" (default 64^3).
 * nx/ny/nz of 0 mean the default size. */
pp5_status_t phantom_make(const char *name, int nx, int ny, int nz, volume_t *out);
/* Comma-separated list of phantom names, for --help texts. */
const char *phantom_names(void);


/* ---- Voxel types, raw layouts, writers, file info, option parsing, hashing ---- */
#include <stddef.h>

size_t volume_voxel_count(const volume_t *v);
const char *voxel_type_name(voxel_type_t t);      /* "u8", "i16", "f32", ... */
size_t voxel_type_bytes(voxel_type_t t);
/* Parses "u8"/"uint8"/"uchar", "i16"/"int16"/"short", "f32"/"float", ... */
pp5_status_t voxel_type_parse(const char *text, voxel_type_t *type);
/* Reads the layout from a name like "cthead_256x256x113_u16be.raw.gz"
 * (_NXxNYxNZ_TYPE, TYPE optionally suffixed be/le; little-endian by default). */
pp5_status_t volume_raw_spec_from_name(const char *path, volume_raw_spec_t *spec);
/* Writers (used by `pp5 volume phantom`): NRRD via Teem (float, raw encoding,
 * spacings), or headerless little-endian float32 raw. */
pp5_status_t volume_save_nrrd(const volume_t *v, const char *path);
pp5_status_t volume_save_raw_f32(const volume_t *v, const char *path);
/* What a loader found in the file (for `pp5 volume info` and reports). */
typedef struct {
    char format[32];          /* "raw", "raw.gz", "nrrd", "nifti", "den", "slices" */
    voxel_type_t stored_type; /* voxel type in the file, before conversion to float */
    bool big_endian;          /* byte order in the file (when it matters) */
} volume_file_info_t;
/* volume_load that also reports the file's format and stored type (info may be NULL). */
pp5_status_t volume_load_info(const char *path, const volume_raw_spec_t *raw, volume_t *out,
                              volume_file_info_t *info);
/* Strict command-line parsing for raw options: "NXxNYxNZ" (each 1..VOLUME_MAX_SIDE,
 * used for --dims and --size) and "SX,SY,SZ" (finite, > 0).  PP5_E_CONFIG naming `opt`. */
pp5_status_t volume_parse_size3(const char *opt, const char *text, int *nx, int *ny, int *nz);
pp5_status_t volume_parse_spacing3(const char *opt, const char *text, double spacing[3]);
/* SHA-256 of a byte stream: the hash PROVENANCE.md records for the data. */
void volume_sha256(const void *data, size_t n, uint8_t digest[32]);
/* The Marschner-Lobb test function at (x,y,z) in [-1,1]^3 (values 0..1), the
 * exact field the "marschner-lobb" phantom samples. */
double phantom_marschner_lobb(double x, double y, double z);

#endif
