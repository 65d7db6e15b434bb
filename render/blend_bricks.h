/* blend_bricks.h: MIP and DEMIP of parallel rays in brick order.
 *
 * A MIP ray's result does not depend on the order in which its samples are
 * drawn: m_max is the largest material, k_max the smallest position
 * reaching it.  So instead of walking each ray front to back, the texels of
 * a tile visit the pyramid level's bricks (scalar_level_t.brick_order) from
 * the highest bound down.  A ray draws its positions inside a brick only
 * while the brick's bound can still raise its maximum, or equal it at an
 * earlier position.  After the first few bricks the ray's maximum is above
 * the bound of everything left, and the tile stops when that holds for all
 * its rays.  No per-ray walk, distance map or threshold guess is needed.
 *
 * Exactness.  A position is drawn with the reference's float expressions
 * (blend_fast.h), so each sample is the reference's.  A brick's bound is at
 * least every sample whose cell lies in it (scalar_pyramid.h); a ray's
 * positions in a brick are one run of k (cell coordinates are monotone in
 * k); the run is found from the brick's box with a slack of one position
 * each way and each candidate is kept only if its own cell lies in the
 * brick, so every position is drawn at most once per pass.  Bricks are
 * binned to tiles by their image footprint with a texel of slack.  The
 * update rule "m > m_max, or m = m_max > 0 at a smaller k" gives the
 * reference's (m_max, k_max) in any order (tested bit for bit).
 *
 * DEMIP's ray 2 (the first position with m >= m_max - eps) is a second pass
 * over the same bricks: a brick that may hold such a sample is drawn up to
 * the ray's current stop, front to back, and the earliest stop found wins.
 *
 * Counts.  samples: positions drawn (both passes for DEMIP).
 * samples_skipped: the ray window's positions not drawn.  A reference MIP
 * ray stops at m_max = 1; in brick order the positions behind it are
 * counted as skipped, so drawn + skipped = the positions of every window.
 * samples_retraced stays 0. */
#ifndef PP5_BLEND_BRICKS_H
#define PP5_BLEND_BRICKS_H

#include <stdbool.h>
#include <stdint.h>
#include "blend_trace.h"

#define BLEND_TILE 32             /* texels per tile side */

typedef float blend_v4f __attribute__((vector_size(16)));
typedef int blend_v4i __attribute__((vector_size(16)));

/* One brick of the level, as the tiles read it (lane 3 unused). */
typedef struct {
    blend_v4f lo, hi;             /* level-0 position box, widened by BLEND_BOX_SLACK
                                   * (edge bricks reach past the volume) */
    blend_v4i c0, c1;             /* its cells [c0, c1) at the level */
    float material;               /* material of its bound */
    int rect[4];                  /* texel footprint i0, j0, i1, j1 (inclusive) */
} blend_brick_t;

/* A drawn position lies within about 1e-4 voxels of its ray's exact line
 * (float rounding of ov + t dv at coordinates of a few hundred); the box is
 * widened by a hundred times that, so no position whose computed cell is in
 * the brick falls outside it. */
#define BLEND_BOX_SLACK 0.01f

/* The bricks of one 2D level's 3D level binned to the level's tiles, in
 * brick order; bricks of material 0 (they change no ray) and bricks whose
 * footprint misses every active tile are left out. */
typedef struct {
    int level2d, level3d;
    int tex_w, tex_h, tiles_x, tiles_y;
    blend_brick_t *brick;         /* chunk k's kept bricks at [k BINS_CHUNK, + kept[k]) */
    size_t bricks;                /* kept, over all chunks */
    uint32_t *kept;               /* per chunk of the level's brick order */
    size_t chunks;
    uint32_t *start;              /* per tile, tiles + 1 offsets into entry */
    uint32_t *entry;              /* indices into brick */
    uint32_t *next;               /* scratch: per tile, the next entry to fill */
    /* Allocated sizes, kept from frame to frame: a frame's bins are rebuilt
     * in place (fresh pages would cost more than the binning itself). */
    size_t brick_cap, tile_cap, entry_cap, kept_cap;
} blend_bins_t;

/* Bricks per chunk of the level's order, described by one thread: fixed,
 * so that the bins do not depend on the thread count. */
#define BINS_CHUNK 256

/* True when brick order applies: MIP or DEMIP, parallel, skipping on. */
bool blend_bricks_apply(const blend_ctx_t *c);
/* Bins level2d's bricks for a tex_w x tex_h texel grid; `active` (one byte
 * per tile, may be NULL for all) leaves idle tiles empty.  `b` is zeroed
 * or a previous frame's bins, whose memory is reused.  The bricks are
 * described on `threads` threads (parallel_for's meaning). */
pp5_status_t blend_bins_build(blend_bins_t *b, const blend_ctx_t *c, int level2d, int tex_w,
                              int tex_h, const uint8_t *active, int threads);
void blend_bins_free(blend_bins_t *b);
/* Traces texels (ti[k], tj[k]), k < count, all in tile `tile` (at most
 * BLEND_TILE^2), into rgb[k]. */
pp5_status_t blend_trace_tile(const blend_ctx_t *c, const blend_bins_t *b, int tile, int count,
                              const int *ti, const int *tj, float (*rgb)[3],
                              raycast_counts_t *counts);

#endif
