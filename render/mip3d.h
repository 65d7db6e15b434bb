/* mip3d.h: the 3D mip map (gaze paper §4): a hyperpyramid of shading
 * components, each level a 2x2x2 box filter of the one beneath.
 *
 * Stored components per voxel (paper §5 "Shading issues"), all multiplied by
 * the voxel opacity ("associated" values, so that filtering never lets the
 * colour of a transparent voxel bleed into its neighbours):
 *
 *   SHADE_DIFFUSE_FIXED_LIGHT  (Lambertian, light fixed to the object, only the
 *     observer moves: the whole shading is viewpoint-independent)
 *       stride 4: [a*R, a*G, a*B, a]  with RGB the final diffuse-shaded colour.
 *   SHADE_SPECULAR_FIXED_LIGHT (as above plus specular, which depends on the view)
 *       stride 8: [a*R, a*G, a*B, a, a*Nx, a*Ny, a*Nz, 0]  RGB diffuse-shaded;
 *       per sample the renderer adds a*ks*(N.H)^n from the renormalised normal.
 *   SHADE_MOVING_OBJECT (light and observer fixed, object rotates: diffuse and
 *     specular both change every frame)
 *       stride 8: [a*R, a*G, a*B, a, a*Nx, a*Ny, a*Nz, 0]  RGB = unshaded
 *       reflectance; per sample the renderer evaluates ka + kd*N.L and specular.
 *
 * N is the unit gradient direction in object space.  Levels: level n has
 * ceil(dim / 2^n) voxels per axis (zero-padded where the level beneath is odd)
 * up to a 1x1x1 top.  Voxel j of level n covers level-0 voxels
 * [j*2^n, (j+1)*2^n - 1] and sits at level-0 position (j + 0.5) * 2^n - 0.5.
 * Because the box filter averages non-negative opacities, a voxel's opacity is
 * zero exactly when all eight children are zero: the opacity pyramid is also
 * an occupancy octree (paper §5; octree.h builds the skipping structure). */
#ifndef PP5_MIP3D_H
#define PP5_MIP3D_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "classify.h"
#include "shade.h"
#include "volume.h"

#define MIP3D_MAX_LEVELS 16
enum { MIP3D_R = 0, MIP3D_G, MIP3D_B, MIP3D_A, MIP3D_NX, MIP3D_NY, MIP3D_NZ };

/* How the components are stored.  F32 (the default) keeps the floats, x
 * fastest; it is what the images and tests of the default path are made
 * of.  U16 and U8 are the reduced-precision options (`--voxel-format`):
 * each component a fixed-point fraction of its range (colour and opacity
 * unsigned, a*N signed; rounded to nearest as the machine's RGBA8 voxels
 * are, firmware/common/vr_shade_fixed.h), stored in 4x4x4-voxel bricks so
 * that a trilinear footprint usually lies in one or two cache lines, and
 * sampled by converting each corner to float (value = stored * unit) before
 * the usual trilinear arithmetic.  The diffuse case then takes 4 (U8) or 8
 * (U16) bytes per voxel at level 0 and 8/7 of that over all levels. */
typedef enum { MIP3D_F32 = 0, MIP3D_U16, MIP3D_U8 } mip3d_format_t;
#define MIP3D_BRICK 4         /* brick side of the packed formats, in voxels */

typedef struct {
    int nx, ny, nz;
    float *data;          /* F32: nx*ny*nz*stride floats, x fastest */
    size_t data_bytes;    /* as allocated (huge_alloc) */
} mip3d_level_t;

/* A level in U16/U8: stride components per voxel (uint16_t/int16_t or
 * uint8_t/int8_t), voxel (x, y, z) at index offset[0][x] + offset[1][y] +
 * offset[2][z] (bricked, so the index is a sum of one term per axis). */
typedef struct {
    void *data;
    size_t data_bytes;    /* as allocated (huge_alloc) */
    uint32_t *offset[3];
} mip3d_packed_t;

typedef struct {
    int levels;           /* number of levels, base (0) to the 1x1x1 top */
    int stride;           /* components per voxel: 4 or 8 (see above) */
    mip3d_format_t format;
    /* Packed formats: component k's value is stored * unit[k]; colour and
     * opacity unsigned over [0, range], a*N signed over [-1, 1]. */
    float unit[8];
    shade_case_t lighting;
    float inv_spacing[3]; /* object-space units per voxel, inverted (see shade.h) */
    float spacing[3];     /* object-space size of a level-0 voxel (smallest axis = 1) */
    mip3d_level_t level[MIP3D_MAX_LEVELS];   /* dims always; data in F32 */
    mip3d_packed_t packed[MIP3D_MAX_LEVELS]; /* U16/U8 */
    size_t bytes;
} mip3d_t;

/* Classifies and shades every voxel (viewpoint-independent part only, as
 * above) and filters the pyramid.  Deterministic for any thread count. */
pp5_status_t mip3d_build(mip3d_t *m, const volume_t *v, const classify_tf_t *tf,
                         const shade_params_t *shade, int threads);
/* The same in a given storage format (F32 is mip3d_build). */
pp5_status_t mip3d_build_format(mip3d_t *m, const volume_t *v, const classify_tf_t *tf,
                                const shade_params_t *shade, mip3d_format_t format, int threads);
/* "f32", "u16", "u8"; and back (false: unknown name). */
const char *mip3d_format_name(mip3d_format_t f);
bool mip3d_format_parse(const char *name, mip3d_format_t *f);
/* Bytes one voxel's component takes in the format (4, 2 or 1). */
int mip3d_format_bytes(mip3d_format_t f);
/* Stored opacity of voxel (x, y, z) of level n is non-zero (any format):
 * what the octree's occupancy is built from, so skipping stays exact. */
bool mip3d_voxel_occupied(const mip3d_t *m, int n, int x, int y, int z);
void mip3d_free(mip3d_t *m);
/* The pyramid's shape without its data: spacing (smallest axis = 1; absent or
 * non-finite spacings count as 1), levels down to 1x1x1, each level's dims.
 * mip3d_build uses it; so does the machine's host, which must agree. */
void mip3d_geometry(mip3d_t *m, const volume_t *v);
/* Object-space size of a voxel (smallest axis = 1) and its inverse: the
 * units every pyramid over the volume shares with the camera. */
void mip3d_voxel_spacing(const volume_t *v, float spacing[3], float inv_spacing[3]);

/* Level-n coordinate of a level-0 voxel coordinate p: (p + 0.5) / 2^n - 0.5. */
static inline float mip3d_level_coord(float p, int n)
{
    /* Multiplying by 2^-n is exact, so this equals dividing by 2^n. */
    return (p + 0.5f) * (1.0f / (float)(1 << n)) - 0.5f;
}

/* floor() of a float known to lie well inside the int range, without a libm
 * call: truncate, then step down for negative non-integers. */
static inline int mip3d_floor_int(float x)
{
    int i = (int)x;
    return (float)i > x ? i - 1 : i;
}

/* Voxel index i clamped to an axis of n voxels (edge voxels repeat). */
static inline int mip3d_clamp_index(int i, int n)
{
    return i < 0 ? 0 : (i >= n ? n - 1 : i);
}

/* The trilinear footprint of level-n coordinates (x, y, z): the corner
 * indices per axis clamped to the edge voxels, and the weights. */
typedef struct {
    int x[2], y[2], z[2];
    float w[3];
} mip3d_footprint_t;

static inline void mip3d_footprint(const mip3d_level_t *L, float x, float y, float z,
                                   mip3d_footprint_t *f)
{
    const float q[3] = {x, y, z};
    const int dims[3] = {L->nx, L->ny, L->nz};
    int *out[3] = {f->x, f->y, f->z};
    for (int a = 0; a < 3; a++) {
        int i0 = mip3d_floor_int(q[a]);
        f->w[a] = q[a] - (float)i0;
        out[a][0] = mip3d_clamp_index(i0, dims[a]);
        out[a][1] = mip3d_clamp_index(i0 + 1, dims[a]);
    }
}

/* The `stride` components of packed voxel index i, as floats. */
static inline void mip3d_packed_voxel(const mip3d_t *m, const mip3d_packed_t *P, size_t i,
                                      float *out)
{
    const int s = m->stride;
    if (m->format == MIP3D_U8) {
        const uint8_t *u = (const uint8_t *)P->data + i * (size_t)s;
        for (int k = 0; k < 4; k++)
            out[k] = (float)u[k] * m->unit[k];
        for (int k = 4; k < s; k++)
            out[k] = (float)(int8_t)u[k] * m->unit[k];
    } else {
        const uint16_t *u = (const uint16_t *)P->data + i * (size_t)s;
        for (int k = 0; k < 4; k++)
            out[k] = (float)u[k] * m->unit[k];
        for (int k = 4; k < s; k++)
            out[k] = (float)(int16_t)u[k] * m->unit[k];
    }
}

/* mip3d_trilerp for the packed formats: each of the eight corners (clamped
 * as below) converted to float, then exactly the float arithmetic. */
static inline void mip3d_trilerp_packed(const mip3d_t *m, int n, float x, float y, float z,
                                        float *out)
{
    mip3d_footprint_t fp;
    mip3d_footprint(&m->level[n], x, y, z, &fp);
    const mip3d_packed_t *P = &m->packed[n];
    const uint32_t *ox = P->offset[0], *oy = P->offset[1], *oz = P->offset[2];
    const float wx = fp.w[0], wy = fp.w[1], wz = fp.w[2];
    float c[8][8];                /* corner (x fastest), component */
    for (int i = 0; i < 8; i++)
        mip3d_packed_voxel(m, P, (size_t)ox[fp.x[i & 1]] + oy[fp.y[(i >> 1) & 1]] +
                                     oz[fp.z[i >> 2]], c[i]);
    for (int k = 0; k < m->stride; k++) {
        float a = c[0][k] + wx * (c[1][k] - c[0][k]);
        float b = c[2][k] + wx * (c[3][k] - c[2][k]);
        float cc = c[4][k] + wx * (c[5][k] - c[4][k]);
        float d = c[6][k] + wx * (c[7][k] - c[6][k]);
        float e = a + wy * (b - a);
        float f = cc + wy * (d - cc);
        out[k] = e + wz * (f - e);
    }
}

/* Trilinear interpolation of the `stride` components of level n at level-n
 * coordinates (x, y, z), clamping to the edge voxels. */
static inline void mip3d_trilerp(const mip3d_t *m, int n, float x, float y, float z,
                                 float *out)
{
    if (m->format != MIP3D_F32) {
        mip3d_trilerp_packed(m, n, x, y, z, out);
        return;
    }
    const mip3d_level_t *L = &m->level[n];
    mip3d_footprint_t fp;
    mip3d_footprint(L, x, y, z, &fp);
    const int x0 = fp.x[0], x1 = fp.x[1], y0 = fp.y[0], y1 = fp.y[1], z0 = fp.z[0], z1 = fp.z[1];
    const float wx = fp.w[0], wy = fp.w[1], wz = fp.w[2];
    const int s = m->stride;
    const size_t row = (size_t)L->nx, slice = (size_t)L->nx * (size_t)L->ny;
    const float *c000 = L->data + ((size_t)z0 * slice + (size_t)y0 * row + (size_t)x0) * s;
    const float *c100 = L->data + ((size_t)z0 * slice + (size_t)y0 * row + (size_t)x1) * s;
    const float *c010 = L->data + ((size_t)z0 * slice + (size_t)y1 * row + (size_t)x0) * s;
    const float *c110 = L->data + ((size_t)z0 * slice + (size_t)y1 * row + (size_t)x1) * s;
    const float *c001 = L->data + ((size_t)z1 * slice + (size_t)y0 * row + (size_t)x0) * s;
    const float *c101 = L->data + ((size_t)z1 * slice + (size_t)y0 * row + (size_t)x1) * s;
    const float *c011 = L->data + ((size_t)z1 * slice + (size_t)y1 * row + (size_t)x0) * s;
    const float *c111 = L->data + ((size_t)z1 * slice + (size_t)y1 * row + (size_t)x1) * s;
    for (int k = 0; k < s; k++) {
        float a = c000[k] + wx * (c100[k] - c000[k]);
        float b = c010[k] + wx * (c110[k] - c010[k]);
        float c = c001[k] + wx * (c101[k] - c001[k]);
        float d = c011[k] + wx * (c111[k] - c011[k]);
        float e = a + wy * (b - a);
        float f = c + wy * (d - c);
        out[k] = e + wz * (f - e);
    }
}

/* One 3D sample at level-0 voxel position p and continuous level `level3d`
 * (>= 0): trilinear in floor and ceil levels, linear between them (the paper's
 * Trilirp + Lirp).  Levels beyond the top are clamped to the top. */
void mip3d_sample(const mip3d_t *m, float level3d, const float p[3], float *out);

#endif
