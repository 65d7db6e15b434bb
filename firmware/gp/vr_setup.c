/* vr_setup.c: once per sequence on the GPs: the slab's 3D mip-map levels built and written into the renderers' backing store, then the octree and the brick table gathered on GP 0 and sent to every GP.
 *
 * Paper: seed 004 §4 last paragraph (division of work), §5 (octree), §6.
 * Partitioning, PP memory layout and the per-frame message sequence are in
 * firmware/ARCHITECTURE.md. */
#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "vr_gp_internal.h"
#include "vr_setup_kernels.h"

/* Span counts of the build so far become operations (before every charge,
 * so that each brick leaves after the work that made it). */
static void charge_spans(gp_t *gp, fw_ops_t *ops, vr_spans_t *sp)
{
    vr_spans_charge(ops, sp);
    memset(sp, 0, sizeof *sp);
    fw_charge(gp, ops);
    memset(ops, 0, sizeof *ops);
}

static int brick_id(const vr_state_t *s, int n, int bx, int by, int bz)
{
    const vr_level_geom_t *g = &s->geom[n];
    return s->brick_base[n] + (bz * g->gy + by) * g->gx + bx;
}

/* A level-0 voxel into o (its components) and its backing-store words;
 * true when it may hold anything (the octree grids' bit: opacity > 0, or,
 * for a blend, a value that is not cold). */
static bool level0_voxel(vr_state_t *s, int x, int y, int z, float *o, uint32_t *qa, uint32_t *qn,
                         const vr_mem_t *mem, vr_spans_t *sp)
{
    if (vr_is_blend(s)) {
        vr_value_voxel(s, x, y, z, o, mem, sp, NULL);
        return vr_value_word(s, o, qa, sp, NULL);
    }
    vr_base_voxel(s, x, y, z, o, mem, sp, NULL);
    vr_quantise(o, s->stride, qa, qn, sp, NULL);
    return o[3] > 0.0f;
}

/* The finer level a voxel of level n >= 1 is reduced from: its rows are
 * stored from slice z_off and row y_off on, `rows` rows per slice. */
typedef struct {
    const float *data;
    int nx, ny, nz, z_off, y_off, rows;
} level_src_t;

/* Voxel (x, y, z) of level n >= 1 from its children: the mip map's box
 * filter, or the value pyramid's max (or box) reduction; its words and
 * occupancy as level0_voxel's. */
static bool reduced_voxel(vr_state_t *s, const level_src_t *c, int x, int y, int z, float *o,
                          uint32_t *qa, uint32_t *qn, vr_spans_t *sp)
{
    if (vr_is_blend(s) && s->cfg.pyramid == VR_PYRAMID_MAX)
        vr_max_voxel(c->data, c->nx, c->ny, c->nz, c->z_off, c->y_off, c->rows, x, y, z, o, sp,
                     NULL);
    else
        vr_filter_voxel(c->data, c->nx, c->ny, c->nz, c->z_off, c->y_off, c->rows, x, y, z,
                        s->stride, o, sp, NULL);
    if (vr_is_blend(s))
        return vr_value_word(s, o, qa, sp, NULL);
    vr_quantise(o, s->stride, qa, qn, sp, NULL);
    return o[3] > 0.0f;
}

/* Where a brick's voxels are copied from: a level's quantised words for
 * slices [z_first, ...) and rows [y_first, y_first + rows) of each. */
typedef struct {
    const uint32_t *qa, *qn;
    int z_first, y_first, rows;
} brick_src_t;

/* Copies brick (n, bx, by, bz) from src into blk (and blkn when src has
 * normals) and charges the copy; true when the brick must be written. */
static bool gather_brick(gp_t *gp, const vr_state_t *s, int n, int bx, int by, int bz,
                         const brick_src_t *src, uint32_t *blk, uint32_t *blkn, fw_ops_t *ops,
                         vr_spans_t *sp)
{
    const vr_level_geom_t *g = &s->geom[n];
    /* Every brick of a blend is written: a cold voxel's value still enters
     * the trilinear samples of the cells beside it. */
    bool any = vr_is_blend(s);
    for (int lz = 0; lz < g->bz; lz++)
        for (int ly = 0; ly < g->by; ly++)
            for (int lx = 0; lx < g->bx; lx++) {
                int x = bx * g->bx + lx, y = by * g->by + ly, z = bz * g->bz + lz;
                size_t i = ((size_t)lz * g->by + ly) * g->bx + lx;
                if (x >= g->nx || y >= g->ny || z >= g->nz || y < src->y_first ||
                    y >= src->y_first + src->rows)
                    continue;
                size_t si =
                    ((size_t)(z - src->z_first) * src->rows + (y - src->y_first)) * g->nx + x;
                blk[i] = src->qa[si];
                if (src->qn)
                    blkn[i] = src->qn[si];
                any |= (src->qa[si] >> 24) != 0;
            }
    ops->loads += VR_BRICK_VOXELS * 2u;
    ops->stores += VR_BRICK_VOXELS * 2u;
    ops->int_ops += VR_BRICK_VOXELS * 4u;
    charge_spans(gp, ops, sp);
    return any;
}

/* Sends brick (n, bx, by, bz) to its renderer from a quantised level array
 * covering slices [z_first, ...) of the level. */
static fw_status_t write_brick(gp_t *gp, vr_state_t *s, int n, int bx, int by, int bz,
                               const uint32_t *qa, const uint32_t *qn, int z_first, fw_ops_t *ops,
                               vr_spans_t *sp)
{
    uint32_t *blk = fw_alloc(gp, VR_BRICK_VOXELS * 4u * 2u);
    if (!blk)
        return FW_ERROR;
    uint32_t *blkn = blk + VR_BRICK_VOXELS;
    const brick_src_t src = {qa, qn, z_first, 0, s->geom[n].ny};
    bool any = gather_brick(gp, s, n, bx, by, bz, &src, blk, blkn, ops, sp);
    fw_status_t rc = FW_OK;
    if (any) {
        int id = brick_id(s, n, bx, by, bz);
        unsigned r = (unsigned)id % (unsigned)s->n_r, slot = (unsigned)id / (unsigned)s->n_r;
        unsigned base = slot * (unsigned)s->blocks_per_slot;
        uint32_t args[RING_MSG_ARGS] = {base, 0, 0, 0, 0, 0};
        rc = fw_send(gp, ring_addr(RING_NODE_RENDERER, r), RING_MSG_RENDERER_WRITE_BS, args, blk,
                     VR_BRICK_VOXELS * 4u);
        if (rc == FW_OK && qn) {
            args[0] = base + 1;
            rc = fw_send(gp, ring_addr(RING_NODE_RENDERER, r), RING_MSG_RENDERER_WRITE_BS, args,
                         blkn, VR_BRICK_VOXELS * 4u);
        }
        vr_stat_add(gp, s, VR_STAT_SETUP_BRICKS, 1);
    }
    fw_free(gp, blk);
    return rc;
}

static size_t level_voxels(const vr_level_geom_t *g, int slices)
{
    return (size_t)g->nx * (size_t)g->ny * (size_t)slices;
}

/* What the steps of build_slab share: each level's slices, the strip's
 * shape and the buffers the level-0 strip and levels 1..K are built in. */
typedef struct {
    int K;                              /* levels 0..K are built on the slab GPs */
    int zs[VR_MAX_LEVELS], ts[VR_MAX_LEVELS]; /* level n's first slice and slice count here */
    /* brow: rows of one level-0 brick row (quantised blocks are staged until
     * a brick row is complete); rows: rows of float components built at a
     * time (2^K, so every level's rows are complete per strip). */
    int brow, rows;
    float *lvl[VR_MAX_LEVELS];          /* levels 1..K, float components */
    int lrow0[VR_MAX_LEVELS], lrows[VR_MAX_LEVELS]; /* first row and rows held of lvl[n] */
    uint8_t *occb[VR_MAX_LEVELS];       /* levels 1..K, occupancy bits of the slab */
    float *strip;                       /* level 0, one strip of float components */
    uint32_t *sqa, *sqn;                /* level 0, one brick row of quantised words */
    uint8_t *occ0;                      /* level 0, occupancy bits of the whole slab */
    size_t occ0_count;
    fw_ops_t ops;
    vr_mem_t mem;
    vr_spans_t sp;
} slab_build_t;

/* Slices [zs[n], zs[n] + ts[n]) of each level 0..K: the slab's share, cut
 * at the level's depth. */
static void slab_levels_extent(const vr_state_t *s, slab_build_t *b)
{
    int z0 = s->g * s->cfg.slab_t;
    for (int n = 0; n <= b->K; n++) {
        const vr_level_geom_t *g = &s->geom[n];
        b->zs[n] = z0 >> n;
        b->ts[n] = g->slab_t;
        if (b->zs[n] + b->ts[n] > g->nz)
            b->ts[n] = g->nz - b->zs[n];
        if (b->ts[n] < 0)
            b->ts[n] = 0;
    }
}

/* Strip height: one level-0 brick row (32 rows), or the whole slice when a
 * brick holds every row (small volumes); a multiple of 2^K so that every
 * level's strip rows are complete. */
static void slab_strip_shape(const vr_state_t *s, slab_build_t *b)
{
    int unit = 1 << b->K;
    b->brow = s->geom[0].by >= s->geom[0].ny ? ((s->geom[0].ny + unit - 1) / unit) * unit
                                             : s->geom[0].by;
    b->rows = b->brow % unit == 0 ? unit : b->brow;
}

/* Storage for levels 1..K: floats for one strip's rows (the whole slab at
 * level K, which goes to GP 0), and the slab's quantised words and
 * occupancy bits. */
static fw_status_t slab_alloc_coarse_levels(gp_t *gp, vr_state_t *s, slab_build_t *b)
{
    int K = b->K;
    for (int n = 1; n <= K; n++) {
        int ts = b->ts[n];
        size_t cnt = level_voxels(&s->geom[n], ts > 0 ? ts : 1);
        b->lrows[n] = n < K ? ((b->rows + (1 << n) - 1) >> n) : s->geom[n].ny;
        if (b->lrows[n] < 1)
            b->lrows[n] = 1;
        size_t lcnt = (size_t)s->geom[n].nx * b->lrows[n] * (ts > 0 ? ts : 1);
        b->lvl[n] = fw_alloc(gp, lcnt * (size_t)s->stride * sizeof(float));
        b->occb[n] = fw_alloc(gp, cnt / 8 + 1);
        if (!b->occb[n])
            return FW_ERROR;
        s->qa[n] = fw_alloc(gp, cnt * 4);
        s->qn[n] = s->stride == 8 ? fw_alloc(gp, cnt * 4) : NULL;
        if (!b->lvl[n] || !s->qa[n] || (s->stride == 8 && !s->qn[n]))
            return FW_ERROR;
    }
    return FW_OK;
}

/* Storage for level 0: one strip of floats, one brick row of quantised
 * words, and the slab's occupancy bits (sent to GP 0 at the end). */
static fw_status_t slab_alloc_level0(gp_t *gp, const vr_state_t *s, slab_build_t *b)
{
    const vr_level_geom_t *g0 = &s->geom[0];
    int ts0 = b->ts[0] > 0 ? b->ts[0] : 1;
    size_t strip_vox = (size_t)g0->nx * b->rows * ts0;
    size_t stage_vox = (size_t)g0->nx * b->brow * ts0;
    b->strip = fw_alloc(gp, strip_vox * (size_t)s->stride * sizeof(float));
    b->sqa = fw_alloc(gp, stage_vox * 4);
    b->sqn = s->stride == 8 ? fw_alloc(gp, stage_vox * 4) : NULL;
    b->occ0_count = level_voxels(g0, b->ts[0]);
    b->occ0 = fw_alloc(gp, b->occ0_count / 8 + 1);
    if (!b->strip || !b->sqa || (s->stride == 8 && !b->sqn) || !b->occ0)
        return FW_ERROR;
    return FW_OK;
}

/* Level 0 of rows [sy, sy + ry) of every slab slice: floats into the strip,
 * words into the brick-row stage (from row brow0 on), occupancy bits. */
static void slab_build_level0_rows(gp_t *gp, vr_state_t *s, slab_build_t *b, int sy, int ry,
                                   int brow0)
{
    const vr_level_geom_t *g0 = &s->geom[0];
    for (int z = 0; z < b->ts[0]; z++)
        for (int y = 0; y < ry; y++)
            for (int x = 0; x < g0->nx; x++) {
                size_t i = ((size_t)z * b->rows + y) * g0->nx + x;
                size_t qi = ((size_t)z * b->brow + (sy + y - brow0)) * g0->nx + x;
                float *o = b->strip + i * s->stride;
                if (level0_voxel(s, x, sy + y, b->zs[0] + z, o, &b->sqa[qi],
                                 b->sqn ? &b->sqn[qi] : NULL, &b->mem, &b->sp)) {
                    size_t gi = ((size_t)z * g0->ny + sy + y) * g0->nx + x;
                    b->occ0[gi >> 3] |= (uint8_t)(1u << (gi & 7));
                }
            }
    vr_stat_add(gp, s, VR_STAT_SETUP_VOXELS, (uint64_t)b->ts[0] * ry * g0->nx);
}

/* Sends level-0 brick (bx, by, bz) to its renderer from the brick-row
 * stage, which holds rows [brow0, brow0 + brow) from slice zs[0] on (a
 * send that fails returns at once, as it always did here). */
static fw_status_t slab_write_level0_brick(gp_t *gp, vr_state_t *s, slab_build_t *b, int bx,
                                           int by, int bz, int brow0)
{
    uint32_t *blk = fw_alloc(gp, VR_BRICK_VOXELS * 8u);
    if (!blk)
        return FW_ERROR;
    uint32_t *blkn = blk + VR_BRICK_VOXELS;
    const brick_src_t src = {b->sqa, b->sqn, b->zs[0], brow0, b->brow};
    if (gather_brick(gp, s, 0, bx, by, bz, &src, blk, blkn, &b->ops, &b->sp)) {
        int id = brick_id(s, 0, bx, by, bz);
        unsigned r = (unsigned)id % (unsigned)s->n_r;
        unsigned base = ((unsigned)id / (unsigned)s->n_r) * (unsigned)s->blocks_per_slot;
        uint32_t args[RING_MSG_ARGS] = {base, 0, 0, 0, 0, 0};
        if (fw_send(gp, ring_addr(RING_NODE_RENDERER, r), RING_MSG_RENDERER_WRITE_BS, args, blk,
                    VR_BRICK_VOXELS * 4u) != FW_OK)
            return FW_ERROR;
        if (b->sqn) {
            args[0] = base + 1;
            if (fw_send(gp, ring_addr(RING_NODE_RENDERER, r), RING_MSG_RENDERER_WRITE_BS, args,
                        blkn, VR_BRICK_VOXELS * 4u) != FW_OK)
                return FW_ERROR;
        }
        vr_stat_add(gp, s, VR_STAT_SETUP_BRICKS, 1);
    }
    fw_free(gp, blk);
    return FW_OK;
}

/* Every level-0 brick of the completed brick row starting at row brow0,
 * over the slab's slices. */
static fw_status_t slab_write_level0_brick_row(gp_t *gp, vr_state_t *s, slab_build_t *b,
                                               int brow0)
{
    const vr_level_geom_t *g0 = &s->geom[0];
    for (int bz = b->zs[0] / g0->bz; bz * g0->bz < b->zs[0] + b->ts[0]; bz++)
        for (int by = brow0 / g0->by; by * g0->by < brow0 + b->brow && by < g0->gy; by++)
            for (int bx = 0; bx < g0->gx; bx++)
                if (slab_write_level0_brick(gp, s, b, bx, by, bz, brow0) != FW_OK)
                    return FW_ERROR;
    return FW_OK;
}

/* Levels 1..K of the strip starting at level-0 row sy, each reduced from
 * the one below (level 1 from the strip): floats, words, occupancy bits. */
static void slab_reduce_strip_levels(vr_state_t *s, slab_build_t *b, int sy)
{
    const float *src = b->strip;
    int srows = b->rows, sy_n = sy;
    for (int n = 1; n <= b->K; n++) {
        const vr_level_geom_t *g = &s->geom[n], *gs = &s->geom[n - 1];
        int ny0 = sy_n / 2, nrows = (srows + 1) / 2;
        if (n < b->K)
            b->lrow0[n] = ny0;
        for (int z = 0; z < b->ts[n]; z++)
            for (int y = ny0; y < ny0 + nrows && y < g->ny; y++)
                for (int x = 0; x < g->nx; x++) {
                    size_t i = ((size_t)z * g->ny + y) * g->nx + x;
                    float *o = b->lvl[n] +
                               (((size_t)z * b->lrows[n] + (y - b->lrow0[n])) * g->nx + x) * s->stride;
                    /* children rows 2y, 2y+1 of the source strip/level */
                    level_src_t from = n == 1 ? (level_src_t){src, gs->nx, gs->ny, gs->nz, b->zs[0],
                                                              sy, b->rows}
                                              : (level_src_t){b->lvl[n - 1], gs->nx, gs->ny, gs->nz,
                                                              b->zs[n - 1], b->lrow0[n - 1],
                                                              b->lrows[n - 1]};
                    if (reduced_voxel(s, &from, x, y, b->zs[n] + z, o, &s->qa[n][i],
                                      s->qn[n] ? &s->qn[n][i] : NULL, &b->sp))
                        b->occb[n][i >> 3] |= (uint8_t)(1u << (i & 7));
                }
        sy_n = ny0;
        srows = nrows;
    }
}

/* After the last strip: level-0 occupancy to GP 0; levels 1..K's bricks to
 * the renderers' backing store and their occupancy to GP 0; level K's
 * floats to GP 0 (it builds the levels above). */
static fw_status_t slab_send_levels(gp_t *gp, vr_state_t *s, slab_build_t *b)
{
    int K = b->K;
    if (vr_send_gp(gp, 0, VR_MSG_OCC, 0, (uint32_t)b->zs[0], b->occ0, (b->occ0_count + 7) / 8) !=
        FW_OK)
        return FW_ERROR;
    fw_free(gp, b->occ0);
    for (int n = 1; n <= K; n++) {
        const vr_level_geom_t *g = &s->geom[n];
        if (b->ts[n] > 0) {
            for (int bz = b->zs[n] / g->bz; bz * g->bz < b->zs[n] + b->ts[n]; bz++)
                for (int by = 0; by < g->gy; by++)
                    for (int bx = 0; bx < g->gx; bx++)
                        if (write_brick(gp, s, n, bx, by, bz, s->qa[n], s->qn[n], b->zs[n], &b->ops,
                                        &b->sp) != FW_OK)
                            return FW_ERROR;
            if (vr_send_gp(gp, 0, VR_MSG_OCC, (uint32_t)n, (uint32_t)b->zs[n], b->occb[n],
                           (level_voxels(g, b->ts[n]) + 7) / 8) != FW_OK)
                return FW_ERROR;
        }
        fw_free(gp, s->qa[n]);
        if (s->qn[n])
            fw_free(gp, s->qn[n]);
        s->qa[n] = s->qn[n] = NULL;
    }
    if (b->ts[K] > 0 && K + 1 < s->cfg.levels) {
        size_t cnt = level_voxels(&s->geom[K], b->ts[K]);
        if (vr_send_gp(gp, 0, VR_MSG_LEVELK, (uint32_t)b->zs[K], (uint32_t)b->ts[K], b->lvl[K],
                       cnt * (size_t)s->stride * sizeof(float)) != FW_OK)
            return FW_ERROR;
    }
    for (int n = 1; n <= K; n++) {
        fw_free(gp, b->lvl[n]);
        fw_free(gp, b->occb[n]);
    }
    return FW_OK;
}

/* Builds this GP's slab: level 0 strip by strip, levels 1..K from each
 * strip, bricks written to the renderers as soon as they are complete. */
static fw_status_t build_slab(gp_t *gp, vr_state_t *s)
{
    slab_build_t b;
    memset(&b, 0, sizeof b);
    b.K = s->cfg.slab_k;
    b.mem = (vr_mem_t){gp, &b.ops};
    slab_levels_extent(s, &b);
    slab_strip_shape(s, &b);
    if (slab_alloc_coarse_levels(gp, s, &b) != FW_OK || slab_alloc_level0(gp, s, &b) != FW_OK)
        return FW_ERROR;
    const vr_level_geom_t *g0 = &s->geom[0];
    for (int sy = 0; sy < g0->ny; sy += b.rows) {
        int ry = g0->ny - sy < b.rows ? g0->ny - sy : b.rows;
        int brow0 = (sy / b.brow) * b.brow;
        slab_build_level0_rows(gp, s, &b, sy, ry, brow0);
        /* Level-0 bricks of this strip: rows [sy, sy + ry) cover whole
         * brick rows because by_0 divides the strip (32 = by when bz = 8,
         * bx = 64; otherwise bricks are written from a gathered copy). */
        bool row_done = sy + ry >= brow0 + b.brow || sy + ry >= g0->ny;
        if (b.brow % b.rows != 0 || (g0->by != b.brow && g0->by < g0->ny))
            return fw_fail(gp, "vr: level-0 brick height %d does not match the %d-row strip",
                           g0->by, b.rows);
        if (row_done && slab_write_level0_brick_row(gp, s, &b, brow0) != FW_OK)
            return FW_ERROR;
        slab_reduce_strip_levels(s, &b, sy);
        charge_spans(gp, &b.ops, &b.sp);
    }
    fw_free(gp, b.strip);
    fw_free(gp, b.sqa);
    if (b.sqn)
        fw_free(gp, b.sqn);
    return slab_send_levels(gp, s, &b);
}

/* GP 0, once every level-K slab arrived: levels K+1..top, their bricks and
 * occupancy. */
static fw_status_t build_upper(gp_t *gp, vr_state_t *s)
{
    const vr_config_t *c = &s->cfg;
    fw_ops_t ops = {0};
    vr_spans_t sp;
    memset(&sp, 0, sizeof sp);
    for (int n = c->slab_k + 1; n < c->levels; n++) {
        const vr_level_geom_t *g = &s->geom[n], *gs = &s->geom[n - 1];
        size_t cnt = level_voxels(g, g->nz);
        s->upper[n] = fw_alloc(gp, cnt * (size_t)s->stride * sizeof(float));
        uint32_t *qa = fw_alloc(gp, cnt * 4), *qn = s->stride == 8 ? fw_alloc(gp, cnt * 4) : NULL;
        if (!s->upper[n] || !qa || (s->stride == 8 && !qn))
            return FW_ERROR;
        for (int z = 0; z < g->nz; z++)
            for (int y = 0; y < g->ny; y++)
                for (int x = 0; x < g->nx; x++) {
                    size_t i = ((size_t)z * g->ny + y) * g->nx + x;
                    const level_src_t from = {s->upper[n - 1], gs->nx, gs->ny, gs->nz, 0, 0, gs->ny};
                    if (reduced_voxel(s, &from, x, y, z, s->upper[n] + i * s->stride, &qa[i],
                                      qn ? &qn[i] : NULL, &sp))
                        vr_bits_set(&s->occ[n], x, y, z);
                }
        for (int bz = 0; bz < g->gz; bz++)
            for (int by = 0; by < g->gy; by++)
                for (int bx = 0; bx < g->gx; bx++)
                    if (write_brick(gp, s, n, bx, by, bz, qa, qn, 0, &ops, &sp) != FW_OK)
                        return FW_ERROR;
        fw_free(gp, qa);
        if (qn)
            fw_free(gp, qn);
    }
    charge_spans(gp, &ops, &sp);
    for (int n = c->slab_k; n < c->levels; n++) {
        fw_free(gp, s->upper[n]);
        s->upper[n] = NULL;
    }
    return FW_OK;
}

/* A blend's bricks worth fetching: those holding a corner of a cell the
 * rays may sample (set in the exact grid), since a trilinear sample there
 * reads all eight corners' true values, cold ones too. */
static void nonempty_table_blend(vr_state_t *s)
{
    for (int n = 0; n < s->cfg.levels; n++) {
        const vr_level_geom_t *g = &s->geom[n];
        const bits_t *cells = &s->exact[n].occ[0];
        uint8_t *t = s->brick_nonempty[n];
        for (int z = 0; z < g->nz; z++)
            for (int y = 0; y < g->ny; y++)
                for (int x = 0; x < g->nx; x++) {
                    if (!vr_bits_get(cells, x, y, z))
                        continue;
                    for (int k = 0; k < 8; k++) {
                        int cx = vr_clampi(x + (k & 1), g->nx), cy = vr_clampi(y + ((k >> 1) & 1), g->ny);
                        int cz = vr_clampi(z + (k >> 2), g->nz);
                        t[((cz / g->bz) * g->gy + cy / g->by) * g->gx + cx / g->bx] = 1;
                    }
                }
    }
}

static void nonempty_table(vr_state_t *s)
{
    if (vr_is_blend(s)) {
        nonempty_table_blend(s);
        return;
    }
    for (int n = 0; n < s->cfg.levels; n++) {
        const vr_level_geom_t *g = &s->geom[n];
        uint8_t *t = s->brick_nonempty[n];
        for (int z = 0; z < g->nz; z++)
            for (int y = 0; y < g->ny; y++)
                for (int x = 0; x < g->nx; x++)
                    if (vr_bits_get(&s->occ[n], x, y, z))
                        t[((z / g->bz) * g->gy + y / g->by) * g->gx + x / g->bx] = 1;
    }
}

static fw_status_t alloc_shared(gp_t *gp, vr_state_t *s, bool with_grids)
{
    for (int n = 0; n < s->cfg.levels; n++) {
        const vr_level_geom_t *g = &s->geom[n];
        s->brick_nonempty[n] = fw_alloc(gp, (size_t)g->gx * g->gy * g->gz);
        if (!s->brick_nonempty[n])
            return FW_ERROR;
        if (!with_grids)
            continue;
        octgrid_t *gs[2] = {&s->grid[n], &s->exact[n]};
        for (int k = s->cfg.perspective ? 0 : 1; k < 2; k++) {
            int nx = g->nx, ny = g->ny, nz = g->nz;
            gs[k]->heights = 0;
            for (int h = 0; h < VR_MAX_LEVELS; h++) {
                if (!vr_bits_alloc(gp, &gs[k]->occ[h], nx, ny, nz))
                    return FW_ERROR;
                gs[k]->heights = h + 1;
                if (nx == 1 && ny == 1 && nz == 1)
                    break;
                nx = (nx + 1) / 2;
                ny = (ny + 1) / 2;
                nz = (nz + 1) / 2;
            }
        }
    }
    return FW_OK;
}

static fw_status_t finish_octree(gp_t *gp, vr_state_t *s)
{
    fw_ops_t ops = {0};
    if (alloc_shared(gp, s, false) != FW_OK)
        return FW_ERROR;
    for (int n = 0; n < s->cfg.levels; n++) {
        /* The blended-level grids serve perspective views only: a parallel
         * view samples integer 3D levels (raycast.h), which read the exact
         * grids.  Not building them saves about 1 MB per GP at 256^2 x 109. */
        if ((s->cfg.perspective && !vr_grid_build(gp, &s->grid[n], &s->occ[n], 2, 3, &ops)) ||
            !vr_grid_build(gp, &s->exact[n], &s->occ[n], 0, 1, &ops))
            return FW_ERROR;
    }
    nonempty_table(s);
    for (int n = 0; n < s->cfg.levels; n++) {
        fw_free(gp, s->occ[n].w);
        s->occ[n].w = NULL;
    }
    fw_charge(gp, &ops);
    s->have_octree = true;
    /* Broadcast: one message per grid height and one per brick table,
     * straight from the octree's memory (fw_send copies the payload). */
    for (int h = 1; h < s->n_gp; h++) {
        for (int n = 0; n < s->cfg.levels; n++) {
            octgrid_t *gs[2] = {&s->grid[n], &s->exact[n]};
            for (int k = s->cfg.perspective ? 0 : 1; k < 2; k++)
                for (int hh = 0; hh < gs[k]->heights; hh++) {
                    const bits_t *b = &gs[k]->occ[hh];
                    if (vr_send_gp(gp, (unsigned)h, VR_MSG_OCC, 0xffffffffu,
                                (uint32_t)(n << 8 | k << 7 | hh), b->w,
                                vr_bits_words(b->nx, b->ny, b->nz) * 8) != FW_OK)
                        return FW_ERROR;
                }
            const vr_level_geom_t *g = &s->geom[n];
            if (vr_send_gp(gp, (unsigned)h, VR_MSG_OCC, 0xfffffffeu, (uint32_t)n,
                        s->brick_nonempty[n], (size_t)g->gx * g->gy * g->gz) != FW_OK)
                return FW_ERROR;
        }
    }
    /* The units the frames will fetch (after the broadcast: not on its path). */
    return vr_units_init(gp, s);
}

/* 2DLevel's two tables (seed 004 §4; vr_kernels.h), once per sequence:
 * distances for every integer offset within the image, levels by
 * distance out to the periphery radius. */
static fw_status_t build_level_tables(gp_t *gp, vr_state_t *s)
{
    return vr_level_tables_build(gp, &s->cfg, s->cfg.width, s->cfg.height, &s->level_tables);
}

fw_status_t vr_setup_start(gp_t *gp)
{
    size_t bytes = 0;
    const uint8_t *data = fw_host_data(gp, &bytes);
    if (!data || bytes < sizeof(vr_config_t))
        return fw_fail(gp, "vr: host data missing or short (%zu bytes)", bytes);
    vr_state_t *s = fw_alloc(gp, sizeof *s);
    if (!s)
        return FW_ERROR;
    fw_set_state(gp, s);
#define VR_STAT_DECLARE(id, name, kind, unit, meaning) \
    s->stat[VR_STAT_##id] = fw_stat_declare(gp, name, kind, unit, meaning);
    VR_STATS(VR_STAT_DECLARE)
#undef VR_STAT_DECLARE
    memcpy(&s->cfg, data, sizeof s->cfg);
    const vr_config_t *c = &s->cfg;
    if (c->magic != VR_MAGIC || c->levels < 1 || c->levels > VR_MAX_LEVELS)
        return fw_fail(gp, "vr: bad configuration block");
    const fw_machine_info_t *mi = fw_machine_info(gp);
    s->g = (int)fw_gp_index(gp);
    s->n_gp = (int)mi->n_gp;
    s->n_r = (int)mi->n_renderers;
    /* A blend keeps one float per voxel (the value pyramid) in one block. */
    s->stride = vr_is_blend(s) ? 1 : c->lighting == VR_LIGHT_DIFFUSE ? 4 : 8;
    s->blocks_per_slot = vr_is_blend(s) || c->lighting == VR_LIGHT_DIFFUSE ? 1 : 3;
    if (vr_is_blend(s) && (c->lighting != VR_LIGHT_DIFFUSE ||
                           c->division == VR_DIVISION_OBJECT_SLABS))
        return fw_fail(gp, "vr: a blend casts on the value pyramid with no shading, and not "
                           "in object slabs (firmware/ARCHITECTURE.md \"Blends\")");
    vr_geometry(c, s->geom);
    int id = 0;
    for (int n = 0; n < c->levels; n++) {
        s->brick_base[n] = id;
        id += s->geom[n].gx * s->geom[n].gy * s->geom[n].gz;
    }
    s->n_bricks = id;
    vr_stat_set(gp, s, VR_STAT_BRICKS_TOTAL, (uint64_t)id);
    unsigned slots = (unsigned)((id + s->n_r - 1) / s->n_r);
    vr_stat_set(gp, s, VR_STAT_SLOTS_USED, slots);
    unsigned bs_blocks = fw_machine_info(gp)->pp_bs_blocks;
    if (slots * (unsigned)s->blocks_per_slot > bs_blocks)
        return fw_fail(gp, "vr: the 3D mip map needs %u backing-store blocks per PP "
                           "(%d bricks of %u voxels over %d renderers, %d blocks each); "
                           "a PP has %u (facts §3.1)",
                       slots * (unsigned)s->blocks_per_slot, id, VR_BRICK_VOXELS, s->n_r,
                       s->blocks_per_slot, bs_blocks);
    /* Opacity-correction table (raycast_ctx_init) and byte->float table. */
    fw_ops_t ops = {0};
    vr_spans_t sp;
    memset(&sp, 0, sizeof sp);
    vr_alpha_lut_fill(s, &sp, NULL);
    vr_spans_charge(&ops, &sp);
    for (int i = 0; i < 256; i++)
        s->u8_to_f[i] = (float)i / 255.0f;
    ops.fdiv += 256;
    fw_charge(gp, &ops);
    if (c->level_tables && build_level_tables(gp, s) != FW_OK)
        return FW_ERROR;
    if (s->g == 0) {
        for (int n = 0; n < c->levels; n++)
            if (!vr_bits_alloc(gp, &s->occ[n], s->geom[n].nx, s->geom[n].ny, s->geom[n].nz))
                return FW_ERROR;
        s->occ_pending = 0;
        for (int h = 0; h < c->n_slab_gps; h++)
            for (int n = 0; n <= c->slab_k && n < c->levels; n++) {
                int z0 = (h * c->slab_t) >> n;
                if (z0 < s->geom[n].nz)
                    s->occ_pending++;
            }
        s->levk_pending = c->slab_k + 1 < c->levels ? c->n_slab_gps : 0;
        if (c->slab_k + 1 < c->levels) {
            const vr_level_geom_t *gk = &s->geom[c->slab_k];
            s->upper[c->slab_k] = fw_alloc(gp, level_voxels(gk, gk->nz) * (size_t)s->stride * sizeof(float));
            if (!s->upper[c->slab_k])
                return FW_ERROR;
        }
    }
    s->tables_pending = s->g == 0 ? 0 : c->levels;
    vr_stat_set(gp, s, VR_STAT_SETUP_CYCLES, fw_cycles(gp));
    return FW_OK;
}

/* The host's slab (slices [data_z0, data_z1)) arrives as one message: it is
 * copied into local memory, the slab's mip levels are built and sent, and
 * the copy is freed (it is not needed per frame). */
fw_status_t vr_setup_on_slab(gp_t *gp, vr_state_t *s, const ring_msg_t *m)
{
    const vr_config_t *c = &s->cfg;
    size_t need = (size_t)(c->data_z1 - c->data_z0) * c->nx * c->ny * sizeof(float);
    if (m->payload_bytes != need || s->g >= c->n_slab_gps)
        return fw_fail(gp, "vr: slab message of %zu bytes, expected %zu", m->payload_bytes, need);
    float *copy = fw_alloc(gp, need);
    if (!copy)
        return fw_fail(gp, "vr: GP %d cannot hold its %zu-byte slab", s->g, need);
    memcpy(copy, m->payload, need);
    fw_ops_t ops = {0};
    fw_rx_deposit(gp, &ops, copy, 0, need);   /* gp.rx_dma (fw_api.h) */
    fw_charge(gp, &ops);
    s->slab = copy;
    fw_status_t rc = build_slab(gp, s);
    fw_free(gp, copy);
    s->slab = NULL;
    return rc;
}

static fw_status_t maybe_finish_setup(gp_t *gp, vr_state_t *s)
{
    if (s->g != 0 || s->have_octree || s->levk_pending > 0 || s->occ_pending > 0)
        return FW_OK;
    return finish_octree(gp, s);
}

fw_status_t vr_setup_on_levelk(gp_t *gp, vr_state_t *s, const ring_msg_t *m)
{
    const vr_level_geom_t *gk = &s->geom[s->cfg.slab_k];
    /* args[1] = first slice, args[2] = slices */
    size_t slice_floats = (size_t)gk->nx * gk->ny * (size_t)s->stride;
    size_t z_first = m->args[1], z_count = m->args[2];
    if (z_first + z_count > (size_t)gk->nz || m->payload_bytes != z_count * slice_floats * sizeof(float))
        return fw_fail(gp, "vr: malformed level-K slab message");
    memcpy(s->upper[s->cfg.slab_k] + z_first * slice_floats, m->payload, m->payload_bytes);
    fw_ops_t ops = {0};
    fw_rx_deposit(gp, &ops, s->upper[s->cfg.slab_k], z_first * slice_floats * sizeof(float),
                  m->payload_bytes);   /* gp.rx_dma (fw_api.h) */
    fw_charge(gp, &ops);
    if (--s->levk_pending == 0 && build_upper(gp, s) != FW_OK)
        return FW_ERROR;
    return maybe_finish_setup(gp, s);
}

fw_status_t vr_setup_on_occ(gp_t *gp, vr_state_t *s, const ring_msg_t *m)
{
    if (m->args[1] == 0xffffffffu || m->args[1] == 0xfffffffeu) {
        /* octree broadcast from GP 0: one grid height or one brick table */
        if (!s->brick_nonempty[0] && alloc_shared(gp, s, true) != FW_OK)
            return FW_ERROR;
        void *dst;
        size_t want;
        if (m->args[1] == 0xfffffffeu) {
            int n = (int)m->args[2];
            if (n < 0 || n >= s->cfg.levels)
                return fw_fail(gp, "vr: brick table for level %d", n);
            const vr_level_geom_t *g = &s->geom[n];
            dst = s->brick_nonempty[n];
            want = (size_t)g->gx * g->gy * g->gz;
            s->tables_pending--;
        } else {
            int n = (int)(m->args[2] >> 8), k = (int)((m->args[2] >> 7) & 1), hh = (int)(m->args[2] & 127);
            octgrid_t *gr = k ? &s->exact[n] : &s->grid[n];
            if (n >= s->cfg.levels || hh >= gr->heights)
                return fw_fail(gp, "vr: octree grid message (%d, %d, %d)", n, k, hh);
            dst = gr->occ[hh].w;
            want = vr_bits_words(gr->occ[hh].nx, gr->occ[hh].ny, gr->occ[hh].nz) * 8;
        }
        if (m->payload_bytes != want)
            return fw_fail(gp, "vr: octree message of %zu bytes, expected %zu", m->payload_bytes, want);
        memcpy(dst, m->payload, want);
        fw_ops_t ops = {0};
        fw_rx_deposit(gp, &ops, dst, 0, want);   /* gp.rx_dma (fw_api.h) */
        fw_charge(gp, &ops);
        if (s->tables_pending == 0) {
            s->have_octree = true;
            return vr_units_init(gp, s);
        }
        return FW_OK;
    }
    int n = (int)m->args[1], z0 = (int)m->args[2];
    if (n < 0 || n >= s->cfg.levels)
        return fw_fail(gp, "vr: occupancy for level %d", n);
    const vr_level_geom_t *g = &s->geom[n];
    const uint8_t *b = m->payload;
    size_t count = m->payload_bytes * 8;
    size_t plane = (size_t)g->nx * g->ny;
    fw_ops_t ops = {0};
    for (size_t i = 0; i < count; i++) {
        if (!((b[i >> 3] >> (i & 7)) & 1))
            continue;
        size_t z = (size_t)z0 + i / plane, r = i % plane;
        if (z >= (size_t)g->nz)
            break;
        vr_bits_set(&s->occ[n], (int)(r % g->nx), (int)(r / g->nx), (int)z);
        ops.int_ops += 6;
    }
    ops.loads += m->payload_bytes;
    ops.load_use += m->payload_bytes;    /* each byte's bits tested at once */
    ops.int_ops += m->payload_bytes * 8;
    fw_rx_deposit(gp, &ops, NULL, 0, m->payload_bytes);   /* read where the port left it */
    fw_charge(gp, &ops);
    s->occ_pending--;
    return maybe_finish_setup(gp, s);
}
