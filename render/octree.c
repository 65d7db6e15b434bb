/* octree.c: occupancy cell grids (dilated opacity) and their OR pyramids. */
#include "octree.h"

#include "parallel.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Dilation windows of a cell relative to its index (see octree.h): blended
 * samples read [i-2, i+3], exact-level samples [i, i+1]. */
#define OCTREE_BLEND_LO 2
#define OCTREE_BLEND_HI 3
#define OCTREE_EXACT_LO 0
#define OCTREE_EXACT_HI 1

/* The same dilation across whole rows or slices: block i of `size` bytes
 * becomes the OR of blocks [i-lo, i+hi]; contiguous, so it vectorises. */
static void dilate_blocks(const uint8_t *in, uint8_t *out, int n, size_t size, int lo, int hi)
{
    for (int i = 0; i < n; i++) {
        int a = i - lo < 0 ? 0 : i - lo, b = i + hi > n - 1 ? n - 1 : i + hi;
        uint8_t *o = out + (size_t)i * size;
        memcpy(o, in + (size_t)a * size, size);
        for (int j = a + 1; j <= b; j++) {
            const uint8_t *src = in + (size_t)j * size;
            for (size_t k = 0; k < size; k++)
                o[k] |= src[k];
        }
    }
}

static void dilate_line(const uint8_t *in, uint8_t *out, int n, int lo, int hi)
{
    /* out[i] = OR of in[i-lo .. i+hi], as shifted whole-row ORs (vectorise). */
    memcpy(out, in, (size_t)n);
    for (int s = 1; s <= hi && s < n; s++)
        for (int i = 0; i < n - s; i++)
            out[i] |= in[i + s];
    for (int s = 1; s <= lo && s < n; s++)
        for (int i = s; i < n; i++)
            out[i] |= in[i - s];
}

static void grid_free(octree_grid_t *g)
{
    free(g->block_height);
    free(g->block_bits);
    free(g->empty_height);
    for (int h = 0; h < OCTREE_MAX_HEIGHT; h++)
        free(g->occupied[h]);
    memset(g, 0, sizeof *g);
}

void octree_free(octree_t *o)
{
    for (int n = 0; n < MIP3D_MAX_LEVELS; n++) {
        grid_free(&o->grid[n]);
        grid_free(&o->exact[n]);
    }
    memset(o, 0, sizeof *o);
}

/* The 4x4x4-cell block map of octree.h from occupied[0] and empty_height.
 * An all-empty block is the pyramid's aligned height-2 node, so its cells
 * share one largest empty ancestor of height >= 2. */
static pp5_status_t block_map_build(octree_grid_t *g, size_t *bytes)
{
    int nx = g->nx[0], ny = g->ny[0], nz = g->nz[0];
    g->block_nx = (nx + 3) / 4;
    g->block_ny = (ny + 3) / 4;
    g->block_nz = (nz + 3) / 4;
    size_t count = (size_t)g->block_nx * g->block_ny * g->block_nz;
    /* Three bytes of padding: the AVX2 walk reads each byte as the low
     * byte of a 32-bit gather (raycast_walk_avx2.c). */
    g->block_height = calloc(count + 3, 1);
    g->block_bits = calloc(count, sizeof *g->block_bits);
    if (!g->block_height || !g->block_bits)
        return pp5_fail(PP5_E_NOMEM, "octree: cannot allocate the block map");
    const uint8_t *occ = g->occupied[0];
    for (int z = 0; z < nz; z++)
        for (int y = 0; y < ny; y++) {
            size_t row = ((size_t)z * ny + y) * nx;
            for (int x = 0; x < nx; x++)
                if (occ[row + x])
                    g->block_bits[octree_block_index(g, x, y, z)] |=
                        (uint64_t)1 << octree_block_bit(x, y, z);
        }
    for (int bz = 0; bz < g->block_nz; bz++)
        for (int by = 0; by < g->block_ny; by++)
            for (int bx = 0; bx < g->block_nx; bx++) {
                size_t b = ((size_t)bz * g->block_ny + by) * g->block_nx + bx;
                int8_t h = g->empty_height[((size_t)(4 * bz) * ny + (size_t)(4 * by)) * nx +
                                           (size_t)(4 * bx)];
                if (g->block_bits[b] != 0) {
                    h = -1;
                } else {
                    /* A grid of one or two cells per axis has no height-2
                     * node; its empty blocks then cover the whole grid. */
                    PP5_ASSERT(h >= 2 || g->heights <= 2, "empty block below height 2");
                }
                g->block_height[b] = h;
            }
    *bytes += count * (1 + sizeof *g->block_bits);
    return PP5_OK;
}

/* Per cell: -1 if occupied, else the height of its largest empty ancestor
 * (the node a top-down descent stops at), so a query is one lookup. */
static pp5_status_t empty_height_build(octree_grid_t *g, size_t *bytes)
{
    int nx = g->nx[0], ny = g->ny[0], nz = g->nz[0];
    size_t count = (size_t)nx * ny * nz;
    /* Top-down: a node inherits its parent's answer when the parent lies in
     * an empty subtree, else it is its own height (empty) or -1. */
    int8_t *level[OCTREE_MAX_HEIGHT] = {0};
    int top = g->heights - 1;
    pp5_status_t st = PP5_OK;
    for (int h = top; h >= 0 && st == PP5_OK; h--) {
        int cx = g->nx[h], cy = g->ny[h], cz = g->nz[h];
        int8_t *e = malloc((size_t)cx * cy * cz);
        if (!e) {
            st = pp5_fail(PP5_E_NOMEM, "octree: cannot allocate %zu bytes", count);
            break;
        }
        level[h] = e;
        const uint8_t *occ = g->occupied[h];
        const int8_t *up = h < top ? level[h + 1] : NULL;
        for (int z = 0; z < cz; z++)
            for (int y = 0; y < cy; y++) {
                size_t row = ((size_t)z * cy + y) * cx;
                const int8_t *uprow = up ? up + ((size_t)(z >> 1) * g->ny[h + 1] + (size_t)(y >> 1)) *
                                                    g->nx[h + 1]
                                         : NULL;
                for (int x = 0; x < cx; x++) {
                    int8_t v = uprow ? uprow[x >> 1] : -1;
                    e[row + x] = v >= 0 ? v : (occ[row + x] ? -1 : (int8_t)h);
                }
            }
    }
    for (int h = 1; h <= top; h++)
        free(level[h]);
    if (st != PP5_OK) {
        free(level[0]);
        return st;
    }
    int8_t *e = level[0];
    g->empty_height = e;
    *bytes += count;
    /* Bounding box of the occupied cells (see octree.h). */
    int lo[3] = {nx, ny, nz}, hi[3] = {-1, -1, -1};
    for (int z = 0; z < nz; z++)
        for (int y = 0; y < ny; y++)
            for (int x = 0; x < nx; x++) {
                if (e[((size_t)z * ny + y) * nx + x] >= 0)
                    continue;
                int c[3] = {x, y, z};
                for (int a = 0; a < 3; a++) {
                    if (c[a] < lo[a])
                        lo[a] = c[a];
                    if (c[a] > hi[a])
                        hi[a] = c[a];
                }
            }
    g->any_occupied = hi[0] >= 0;
    pp5_status_t bst = block_map_build(g, bytes);
    if (bst != PP5_OK)
        return bst;
    int dims[3] = {nx, ny, nz};
    float scale = (float)(1 << g->level);
    for (int a = 0; a < 3 && g->any_occupied; a++) {
        g->box_lo[a] = lo[a] == 0 ? -INFINITY : ((float)lo[a] + 0.5f) * scale - 0.5f;
        g->box_hi[a] = hi[a] + 1 >= dims[a] ? INFINITY : ((float)(hi[a] + 1) + 0.5f) * scale - 0.5f;
    }
    return PP5_OK;
}

static pp5_status_t grid_build(octree_grid_t *g, const mip3d_t *m, int n, int lo, int hi,
                               size_t *bytes)
{
    const mip3d_level_t *L = &m->level[n];
    int nx = L->nx, ny = L->ny, nz = L->nz;
    size_t count = (size_t)nx * (size_t)ny * (size_t)nz;
    uint8_t *a = malloc(count), *b = malloc(count);
    if (!a || !b) {
        free(a);
        free(b);
        return pp5_fail(PP5_E_NOMEM, "octree: cannot allocate %zu bytes", count);
    }
    if (m->format == MIP3D_F32) {
        for (size_t i = 0; i < count; i++)
            a[i] = L->data[i * (size_t)m->stride + MIP3D_A] > 0.0f;
    } else {
        for (int z = 0; z < nz; z++)
            for (int y = 0; y < ny; y++)
                for (int x = 0; x < nx; x++)
                    a[((size_t)z * ny + y) * nx + x] = mip3d_voxel_occupied(m, n, x, y, z);
    }
    /* Separable box dilation: x into b, y into a, z into b. */
    for (int z = 0; z < nz; z++)
        for (int y = 0; y < ny; y++) {
            size_t base = ((size_t)z * ny + y) * nx;
            dilate_line(a + base, b + base, nx, lo, hi);
        }
    for (int z = 0; z < nz; z++) {
        size_t base = (size_t)z * ny * nx;
        dilate_blocks(b + base, a + base, ny, (size_t)nx, lo, hi);
    }
    dilate_blocks(a, b, nz, (size_t)nx * ny, lo, hi);
    free(a);
    g->occupied[0] = b;
    g->nx[0] = nx;
    g->ny[0] = ny;
    g->nz[0] = nz;
    g->heights = 1;
    *bytes += count;
    for (int h = 1; h < OCTREE_MAX_HEIGHT; h++) {
        int px = g->nx[h - 1], py = g->ny[h - 1], pz = g->nz[h - 1];
        if (px == 1 && py == 1 && pz == 1)
            break;
        int cx = (px + 1) / 2, cy = (py + 1) / 2, cz = (pz + 1) / 2;
        size_t c = (size_t)cx * cy * cz;
        uint8_t *o = calloc(c, 1);
        if (!o)
            return pp5_fail(PP5_E_NOMEM, "octree: cannot allocate %zu bytes", c);
        const uint8_t *in = g->occupied[h - 1];
        for (int z = 0; z < pz; z++)
            for (int y = 0; y < py; y++)
                for (int x = 0; x < px; x++)
                    if (in[((size_t)z * py + y) * px + x])
                        o[((size_t)(z / 2) * cy + y / 2) * cx + x / 2] = 1;
        g->occupied[h] = o;
        g->nx[h] = cx;
        g->ny[h] = cy;
        g->nz[h] = cz;
        g->heights = h + 1;
        *bytes += c;
    }
    pp5_status_t st = empty_height_build(g, bytes);
    if (st != PP5_OK)
        return st;
    /* The block map answers every query (octree_empty_node), so the per-cell
     * tables are dropped: for CThead's levels about 37 MB of the 39. */
    size_t cells = (size_t)nx * ny * nz;
    free(g->empty_height);
    g->empty_height = NULL;
    *bytes -= cells;
    for (int h = 0; h < g->heights; h++) {
        free(g->occupied[h]);
        g->occupied[h] = NULL;
        *bytes -= (size_t)g->nx[h] * g->ny[h] * g->nz[h];
    }
    return PP5_OK;
}

typedef struct {
    octree_t *o;
    const mip3d_t *m;
    pp5_status_t status[2 * MIP3D_MAX_LEVELS];
    size_t bytes[2 * MIP3D_MAX_LEVELS];
} octree_job_t;

/* Item 2n builds the blend grid of level n, item 2n+1 its exact grid. */
static void octree_build_item(void *ctx, int item, int thread)
{
    (void)thread;
    octree_job_t *job = ctx;
    int n = item / 2;
    bool exact = item % 2;
    octree_grid_t *g = exact ? &job->o->exact[n] : &job->o->grid[n];
    g->level = n;
    job->status[item] = grid_build(g, job->m, n, exact ? OCTREE_EXACT_LO : OCTREE_BLEND_LO,
                                   exact ? OCTREE_EXACT_HI : OCTREE_BLEND_HI, &job->bytes[item]);
}

pp5_status_t octree_build(octree_t *o, const mip3d_t *m, int threads)
{
    memset(o, 0, sizeof *o);
    octree_job_t *job = calloc(1, sizeof *job);
    if (!job)
        return pp5_fail(PP5_E_NOMEM, "octree: out of memory");
    job->o = o;
    job->m = m;
    o->mip_levels = m->levels;
    pp5_status_t st = parallel_for(threads, 2 * m->levels, octree_build_item, job);
    for (int i = 0; i < 2 * m->levels; i++) {
        o->bytes += job->bytes[i];
        if (st == PP5_OK && job->status[i] != PP5_OK)
            st = pp5_fail(job->status[i], "octree: cannot allocate the occupancy grids");
    }
    free(job);
    if (st != PP5_OK)
        octree_free(o);
    return st;
}
