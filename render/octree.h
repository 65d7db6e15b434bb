/* octree.h: empty-space skipping with the opacity pyramid (gaze paper §5).
 *
 * The opacity component of the 3D mip map is a box-filtered pyramid of
 * non-negative values, so a voxel is zero exactly when every voxel it was
 * filtered from is zero: a hierarchical occupancy map.  A sample, however,
 * reads more than one voxel: trilinear interpolation in the floor level n
 * touches a 2x2x2 neighbourhood and the ceil level n+1 another 2x2x2 whose
 * children reach two level-n voxels further.  So for each mip level n we keep
 * a "cell" grid: cell i (the sample's level-n coordinate lies in [i, i+1) per
 * axis) is occupied when any level-n voxel in [i-2, i+3]^3 has opacity > 0.
 * That is conservative: a sample in an empty cell is exactly zero in both
 * levels.  A sample at an integer level (always so under parallel
 * projection) reads only level n, so a second, tighter grid marks cell i
 * occupied when a voxel in [i, i+1]^3 is: far fewer cells are occupied and
 * skipping goes further.  Above each cell grid sits an OR pyramid up to a
 * single node.
 *
 * Per sample the ray tracer asks for the largest empty node containing the
 * sample's cell.  The answer is the one the paper's top-down descent finds
 * (the first empty node on the path from the root), precomputed per cell
 * at build time (empty_height) so that each query is a single lookup.  The
 * ray then jumps to its first sample beyond that node; since skipped samples
 * are exactly zero the image is bit-identical to a run without skipping. */
#ifndef PP5_OCTREE_H
#define PP5_OCTREE_H

#include <stdbool.h>
#include <math.h>
#include <stdint.h>
#include "mip3d.h"

#define OCTREE_MAX_HEIGHT 16

typedef struct {
    int level;                         /* the mip level n whose samples this grid serves */
    int heights;                       /* number of pyramid levels over this cell grid */
    int nx[OCTREE_MAX_HEIGHT], ny[OCTREE_MAX_HEIGHT], nz[OCTREE_MAX_HEIGHT];
    /* Build-time tables, freed once the block map below is made (NULL
     * after octree_build): */
    uint8_t *occupied[OCTREE_MAX_HEIGHT]; /* 1 = may hold a non-zero sample */
    int8_t *empty_height;              /* per cell: -1 occupied, else largest empty ancestor */
    /* Extent of the occupied cells in level-0 voxel coordinates (+-INFINITY
     * where it reaches a clamped face); any_occupied false: all empty. */
    bool any_occupied;
    float box_lo[3], box_hi[3];
    /* The same cell occupancy as a flat two-level map for the fast parallel
     * tracer (raycast_parallel.c): blocks of 4x4x4 cells, per block one
     * int8 (-1: some cell occupied; else the cells' common empty_height,
     * >= 2) and 64 bits (bit 16*(z&3) + 4*(y&3) + (x&3): cell occupied).
     * About 1/7 the bytes of empty_height, so it stays in cache. */
    int block_nx, block_ny, block_nz;
    int8_t *block_height;
    uint64_t *block_bits;
} octree_grid_t;

/* Block index and bit of cell (x, y, z) in octree_grid_t's block map. */
static inline size_t octree_block_index(const octree_grid_t *g, int x, int y, int z)
{
    return ((size_t)(z >> 2) * (size_t)g->block_ny + (size_t)(y >> 2)) * (size_t)g->block_nx +
           (size_t)(x >> 2);
}

static inline int octree_block_bit(int x, int y, int z)
{
    return ((z & 3) << 4) | ((y & 3) << 2) | (x & 3);
}

/* The largest empty ancestor of cell (x, y, z) (-1: occupied), from the
 * block map alone.  An all-empty block is the aligned height-2 node, so its
 * cells share the block's height; in a mixed block (the height-2 node and
 * every node above it occupied) an empty cell's answer is its aligned 2x2x2
 * node (height 1) when all eight of its bits are clear, else the cell
 * itself (0).  Cells beyond the grid's edge have clear bits, as the
 * pyramid counts them empty. */
static inline int octree_cell_height(const octree_grid_t *g, int x, int y, int z)
{
    size_t b = octree_block_index(g, x, y, z);
    int h = g->block_height[b];
    if (h >= 0)
        return h;
    uint64_t bits = g->block_bits[b];
    int bit = octree_block_bit(x, y, z);
    if ((bits >> bit) & 1)
        return -1;
    /* The 2x2x2 node's bits: x pair 0x3, y pair 0x33, z pair 0x330033. */
    uint64_t node = (uint64_t)0x330033 << octree_block_bit(x & ~1, y & ~1, z & ~1);
    return (bits & node) == 0 && g->heights > 1 ? 1 : 0;
}

typedef struct {
    int mip_levels;
    octree_grid_t grid[MIP3D_MAX_LEVELS];  /* blended samples: floor level n, [i-2, i+3] */
    octree_grid_t exact[MIP3D_MAX_LEVELS]; /* samples at exactly level n: [i, i+1] */
    size_t bytes;
} octree_t;

pp5_status_t octree_build(octree_t *o, const mip3d_t *m, int threads);
void octree_free(octree_t *o);

/* For a sample at level-0 voxel position p whose floor 3D level is n
 * (`exact`: the 3D level is exactly n, so only level n is read): returns
 * -1 if the sample may be non-zero, else the height (0 = a single cell) of
 * the largest empty node containing it, with the node's extent in level-0
 * voxel coordinates in lo/hi (+-INFINITY on faces that extend to the edge of
 * the clamped grid). */
static inline int octree_empty_node(const octree_t *o, int n, bool exact, const float p[3],
                                    float lo[3], float hi[3])
{
    if (n >= o->mip_levels)
        n = o->mip_levels - 1;
    const octree_grid_t *g = exact ? &o->exact[n] : &o->grid[n];
    int c[3], dims[3] = {g->nx[0], g->ny[0], g->nz[0]};
    for (int a = 0; a < 3; a++) {
        int i = mip3d_floor_int(mip3d_level_coord(p[a], n));
        c[a] = i < 0 ? 0 : (i >= dims[a] ? dims[a] - 1 : i);
    }
    int h = octree_cell_height(g, c[0], c[1], c[2]);
    if (h < 0)
        return -1;
    float scale = (float)(1 << n);
    for (int a = 0; a < 3; a++) {
        int first = (c[a] >> h) << h;
        int last = first + (1 << h);      /* exclusive, in level-n cell units */
        lo[a] = first == 0 ? -INFINITY : ((float)first + 0.5f) * scale - 0.5f;
        hi[a] = last >= dims[a] ? INFINITY : ((float)last + 0.5f) * scale - 0.5f;
    }
    return h;
}

#endif
