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
    /* Every node of height brick_height (SCALAR_BRICK_SHIFT, or the top
     * when the level is smaller) by decreasing bound, ties by index: the
     * order in which brick-order MIP (blend_bricks.h) visits them.  Bounds
     * do not depend on the window, so one order serves every frame. */
    int brick_height;
    uint32_t *brick_order;
    uint16_t (*brick_coord)[3];           /* per rank: the brick's node coordinates (a side
                                           * has at most 2^(OCTREE_MAX_HEIGHT - 1) cells) */
    size_t brick_count;
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

/* A key and an index, ordered by decreasing key, ties by increasing index:
 * a total order, so qsort's result is the same on every host.  The brick
 * order uses the bounds as keys. */
typedef struct {
    float key;
    uint32_t index;
} scalar_ranked_t;
int scalar_ranked_cmp(const void *a, const void *b);

/* Deterministic for any thread count. */
pp5_status_t scalar_pyramid_build(scalar_pyramid_t *p, const volume_t *v,
                                  scalar_pyramid_kind_t kind, int threads);
void scalar_pyramid_free(scalar_pyramid_t *p);

static inline float scalar_at(const scalar_level_t *L, int x, int y, int z)
{
    return L->value[((size_t)z * (size_t)L->ny + (size_t)y) * (size_t)L->nx + (size_t)x];
}

/* The seven lerps of a trilinear sample, in mip3d_trilerp's order. */
static inline float scalar_lerp8(const float c[8], float wx, float wy, float wz)
{
    float a = c[0] + wx * (c[1] - c[0]);
    float b = c[2] + wx * (c[3] - c[2]);
    float d = c[4] + wx * (c[5] - c[4]);
    float e = c[6] + wx * (c[7] - c[6]);
    float f = a + wy * (b - a);
    float g = d + wy * (e - d);
    return f + wz * (g - f);
}

/* Trilinear interpolation at level coordinates q whose floors are fl,
 * clamping to the edge voxels: mip3d_trilerp's arithmetic, one component.
 * Away from the edges no index needs clamping, so the eight voxels sit at
 * fixed strides from the first (the same voxels, so the same value). */
static inline float scalar_trilerp(const scalar_level_t *L, const float q[3], const int fl[3])
{
    int x0 = fl[0], y0 = fl[1], z0 = fl[2];
    float wx = q[0] - (float)x0, wy = q[1] - (float)y0, wz = q[2] - (float)z0;
    float c[8];
    if (x0 >= 0 && y0 >= 0 && z0 >= 0 && x0 < L->nx - 1 && y0 < L->ny - 1 && z0 < L->nz - 1) {
        size_t sy = (size_t)L->nx, sz = sy * (size_t)L->ny;
        const float *v = L->value + (size_t)z0 * sz + (size_t)y0 * sy + (size_t)x0;
        c[0] = v[0], c[1] = v[1], c[2] = v[sy], c[3] = v[sy + 1];
        c[4] = v[sz], c[5] = v[sz + 1], c[6] = v[sz + sy], c[7] = v[sz + sy + 1];
        return scalar_lerp8(c, wx, wy, wz);
    }
    int x1 = mip3d_clamp_index(x0 + 1, L->nx), y1 = mip3d_clamp_index(y0 + 1, L->ny);
    int z1 = mip3d_clamp_index(z0 + 1, L->nz);
    x0 = mip3d_clamp_index(x0, L->nx);
    y0 = mip3d_clamp_index(y0, L->ny);
    z0 = mip3d_clamp_index(z0, L->nz);
    c[0] = scalar_at(L, x0, y0, z0), c[1] = scalar_at(L, x1, y0, z0);
    c[2] = scalar_at(L, x0, y1, z0), c[3] = scalar_at(L, x1, y1, z0);
    c[4] = scalar_at(L, x0, y0, z1), c[5] = scalar_at(L, x1, y0, z1);
    c[6] = scalar_at(L, x0, y1, z1), c[7] = scalar_at(L, x1, y1, z1);
    return scalar_lerp8(c, wx, wy, wz);
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
