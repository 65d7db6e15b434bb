/* mip3d_internal.h: what the two builders of the 3D mip map share
 * (mip3d.c: F32; mip3d_packed.c: the U16/U8 formats). */
#ifndef PP5_MIP3D_INTERNAL_H
#define PP5_MIP3D_INTERNAL_H

#include "mip3d.h"

typedef struct {
    mip3d_t *m;
    const volume_t *v;
    const classify_tf_t *tf;
    const shade_params_t *shade;
    int dst;              /* level being filled (filter jobs) */
    int z0;               /* first slice of the chunk (base jobs) */
} mip3d_job_t;

/* The float components of level-0 voxel (x, y, z) (classification and the
 * viewpoint-independent shading; mip3d.h's table). */
void mip3d_base_voxel(const mip3d_job_t *job, int x, int y, int z, float *o);

/* Storage for a level's voxels (large ones on huge pages); free() frees it. */
void *mip3d_alloc_voxels(size_t bytes);

/* mip3d_build_format for U16 and U8. */
pp5_status_t mip3d_build_packed(mip3d_t *m, const volume_t *v, const classify_tf_t *tf,
                                const shade_params_t *shade, mip3d_format_t format, int threads);

#endif
