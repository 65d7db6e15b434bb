/* scalar_pyramid.h: the 3D pyramid of voxel values that MIP, DEMIP and MIDA
 * rays sample, and its conservative octree for skipping.
 *
 * Levels.  Level 0 holds the volume's values; level n+1 voxel j covers the
 * 2x2x2 level-n voxels 2j..2j+1 (those that exist at odd edges), as in the
 * 3D mip map (mip3d.h), and holds
 *   SCALAR_PYRAMID_MAX: their maximum (default).  A coarse ray of gaze-
 *     directed MIP then sees every maximum the fine rays would: no coarse
 *     voxel is below any voxel it covers (tested);
 *   SCALAR_PYRAMID_BOX: their mean with missing children counted as zero,
 *     the box filter of the 3D mip map.  It lowers maxima (a one-voxel vessel
 *     fades to 1/8 per level); kept to measure the difference.
 *
 * Skipping.  A sample at level-n coordinates q (mip3d_level_coord) reads the
 * level-n voxels floor(q)..floor(q)+1, clamped, and trilinear interpolation
 * is a convex combination, so the sample is at most their maximum.  Cell i
 * (floor(q) = i, clamped to the grid) therefore gets the bound
 *     node_max[0][i] = max over voxels [i, i+1]^3 (clamped) + margin,
 * the margin (2^-17 of the largest magnitude there) covering the rounding
 * of the seven float lerps; node_max[h] is the maximum over 2x2x2 nodes of
 * height h-1, up to one node.  A ray may pass a whole node when its bound
 * cannot change the ray (blend_ray.h: below the running maximum for MIP ray
 * 1, below the threshold for ray 2, material 0 for MIDA): skipping is exact.
 * With the max kind the levels themselves are an octree of maxima; the node
 * bounds are the same idea over trilinear footprints, per level.
 *
 * Aligned nodes make a ray through mixed regions take many small jumps, so
 * each level also keeps, for SCALAR_THRESHOLDS value levels, the chessboard
 * distance from every 4x4x4-cell brick to the nearest brick whose bound
 * exceeds the level (proximity clouds, Cohen & Sheffer 1994, one per
 * threshold): a ray whose rule can skip everything up to threshold j may
 * pass the whole cube of bricks within that distance, aligned or not. */
#ifndef PP5_SCALAR_PYRAMID_H
#define PP5_SCALAR_PYRAMID_H

#include <stddef.h>
#include <stdint.h>
#include "blend.h"
#include "mip3d.h"
#include "octree.h"
#include "volume.h"

#define SCALAR_BRICK_SHIFT 2                /* bricks of 4x4x4 cells: node height 2 */
#define SCALAR_THRESHOLDS 16

typedef struct {
    int nx, ny, nz;
    float *value;                          /* nx*ny*nz, x fastest */
    int heights;                           /* node heights 0 .. heights-1 */
    int hx[OCTREE_MAX_HEIGHT], hy[OCTREE_MAX_HEIGHT], hz[OCTREE_MAX_HEIGHT];
    float *node_max[OCTREE_MAX_HEIGHT];    /* [0]: per cell (nx*ny*nz) */
    /* Per threshold j, per brick (node of height SCALAR_BRICK_SHIFT): the
     * chessboard distance in bricks to the nearest brick whose bound
     * exceeds threshold[j] (0: this one does; 255: none within 255).  NULL
     * when the level has no bricks of that height. */
    uint8_t *brick_dist;                   /* [j][bz][by][bx] */
} scalar_level_t;

typedef struct {
    scalar_pyramid_kind_t kind;
    int levels;
    float spacing[3], inv_spacing[3];      /* as mip3d_t's: the camera's units */
    float min_value, max_value;            /* of the volume */
    /* Value levels of the brick distance maps: evenly spaced strictly
     * inside [min_value, max_value]. */
    float threshold[SCALAR_THRESHOLDS];
    scalar_level_t level[MIP3D_MAX_LEVELS];
    size_t bytes;
} scalar_pyramid_t;

/* Deterministic for any thread count. */
pp5_status_t scalar_pyramid_build(scalar_pyramid_t *p, const volume_t *v,
                                  scalar_pyramid_kind_t kind, int threads);
void scalar_pyramid_free(scalar_pyramid_t *p);

static inline float scalar_at(const scalar_level_t *L, int x, int y, int z)
{
    return L->value[((size_t)z * (size_t)L->ny + (size_t)y) * (size_t)L->nx + (size_t)x];
}

/* Trilinear interpolation at level coordinates q whose floors are fl,
 * clamping to the edge voxels: mip3d_trilerp's arithmetic, one component. */
static inline float scalar_trilerp(const scalar_level_t *L, const float q[3], const int fl[3])
{
    int x0 = fl[0], y0 = fl[1], z0 = fl[2];
    float wx = q[0] - (float)x0, wy = q[1] - (float)y0, wz = q[2] - (float)z0;
    int x1 = mip3d_clamp_index(x0 + 1, L->nx), y1 = mip3d_clamp_index(y0 + 1, L->ny);
    int z1 = mip3d_clamp_index(z0 + 1, L->nz);
    x0 = mip3d_clamp_index(x0, L->nx);
    y0 = mip3d_clamp_index(y0, L->ny);
    z0 = mip3d_clamp_index(z0, L->nz);
    float c000 = scalar_at(L, x0, y0, z0), c100 = scalar_at(L, x1, y0, z0);
    float c010 = scalar_at(L, x0, y1, z0), c110 = scalar_at(L, x1, y1, z0);
    float c001 = scalar_at(L, x0, y0, z1), c101 = scalar_at(L, x1, y0, z1);
    float c011 = scalar_at(L, x0, y1, z1), c111 = scalar_at(L, x1, y1, z1);
    float a = c000 + wx * (c100 - c000);
    float b = c010 + wx * (c110 - c010);
    float c = c001 + wx * (c101 - c001);
    float d = c011 + wx * (c111 - c011);
    float e = a + wy * (b - a);
    float f = c + wy * (d - c);
    return e + wz * (f - e);
}

/* Level-n coordinates and floors of level-0 position p. */
static inline void scalar_level_coords(const float p[3], int n, float q[3], int fl[3])
{
    for (int a = 0; a < 3; a++) {
        q[a] = mip3d_level_coord(p[a], n);
        fl[a] = mip3d_floor_int(q[a]);
    }
}

/* Bound of node height h holding cell (cx, cy, cz) (cells already clamped). */
static inline float scalar_node_max(const scalar_level_t *L, int h, int cx, int cy, int cz)
{
    return L->node_max[h][((size_t)(cz >> h) * (size_t)L->hy[h] + (size_t)(cy >> h)) *
                              (size_t)L->hx[h] + (size_t)(cx >> h)];
}

/* Distance map entry of threshold j for the brick holding cell (cx, cy, cz). */
static inline int scalar_brick_dist(const scalar_level_t *L, int j, int cx, int cy, int cz)
{
    const int s = SCALAR_BRICK_SHIFT;
    size_t per = (size_t)L->hx[s] * (size_t)L->hy[s] * (size_t)L->hz[s];
    return L->brick_dist[(size_t)j * per +
                         ((size_t)(cz >> s) * (size_t)L->hy[s] + (size_t)(cy >> s)) *
                             (size_t)L->hx[s] + (size_t)(cx >> s)];
}

/* One sample at level-0 position p and continuous level level3d: trilinear
 * in the floor and ceil levels, linear between them (as mip3d_sample). */
float scalar_pyramid_sample(const scalar_pyramid_t *p, float level3d, const float pos[3]);

#endif
