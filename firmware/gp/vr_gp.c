/* vr_gp.c: the gaze-directed volume renderer's GP program: builds the 3D mip map into PP backing store once, then per frame fetches shaded bricks, casts rays and ships display sections.
 *
 * Paper: seed 004 §4 last paragraph (division of work), §5 (octree), §6.
 * Partitioning, PP memory layout and the per-frame message sequence are in
 * firmware/ARCHITECTURE.md. */
#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "common/vr_config.h"
#include "common/vr_cost.h"
#include "common/vr_gp.h"
#include "common/vr_kernels.h"
#include "common/vr_shade_fixed.h"
#include "common/vr_shade_pp.h"
#include "fw_api.h"
#include "pp_encode.h"
#include "ring_msg.h"

#define VR_STRIP_ROWS 32          /* level-0 rows built at a time (multiple of 2^slab_k) */

/* A bit volume with rows padded to 64-bit words. */
typedef struct {
    int nx, ny, nz, wpr;
    uint64_t *w;
} bits_t;

typedef struct {
    int heights;
    bits_t occ[VR_MAX_LEVELS];
} octgrid_t;

typedef struct {
    vr_config_t cfg;
    vr_level_geom_t geom[VR_MAX_LEVELS];
    int g, n_gp, n_r, stride, blocks_per_slot;
    const float *slab;                    /* host data: slices [data_z0, data_z1) */
    /* setup */
    float *strip[VR_MAX_LEVELS];          /* current strip of each local level */
    uint32_t *qa[VR_MAX_LEVELS], *qn[VR_MAX_LEVELS]; /* quantised slab of levels 1..K */
    float *upper[VR_MAX_LEVELS];          /* GP 0: levels K..top, whole */
    bits_t occ[VR_MAX_LEVELS];            /* GP 0: global occupancy */
    int levk_pending, occ_pending;
    /* shared after setup */
    uint8_t *brick_nonempty[VR_MAX_LEVELS];
    int brick_base[VR_MAX_LEVELS];        /* global brick id of a level's first brick */
    int n_bricks;
    octgrid_t grid[VR_MAX_LEVELS], exact[VR_MAX_LEVELS];
    bool have_octree;
    float alpha_lut[VR_LUT_LEVELS][VR_LUT_SIZE + 1];
    float u8_to_f[256];
    /* frame */
    vr_frame_t fr;
    int frame;
    bool exec_sent;
    uint32_t *pending_req;                /* requests that arrived before our EXEC */
    size_t pending_req_n, pending_req_cap;
    uint32_t **cache;                     /* per global brick: shaded words or NULL */
    uint32_t **cache_n;                   /* GP split: N blocks waiting for shading */
    int bricks_pending;
    bool cast_done, boundary_ok;
    int levels2d, maxm;
    int y0, y1;                           /* own pixel rows */
    int ly0, ly1;                         /* pixel rows with a computed level */
    float *level;                         /* per pixel in [ly0, ly1) */
    int jlo[VR_MAX_2D_LEVELS], jhi[VR_MAX_2D_LEVELS]; /* own texel rows [jlo, jhi] */
    int tw[VR_MAX_2D_LEVELS], th[VR_MAX_2D_LEVELS];
    float *texel[VR_MAX_2D_LEVELS];       /* rows jlo..jhi+1 (+1: the next GP's first row) */
    uint8_t *need[VR_MAX_2D_LEVELS];
    uint8_t *castf[VR_MAX_2D_LEVELS];     /* the paper's flag F: texel's ray cast (kept when progressive) */
    int pass, n_passes;                   /* passes = column ranges x depth segments (memory) */
    int n_cols, n_segs;                   /* pass q: columns q / n_segs, depth segment q % n_segs */
    float seg_t0, seg_len;                /* depth (ray parameter t) covered by the segments */
    /* Per own texel: a ray resumed segment by segment (0 new, 1 started, 2 done). */
    uint8_t *ray_state[VR_MAX_2D_LEVELS];
    float *ray_a[VR_MAX_2D_LEVELS], *ray_t[VR_MAX_2D_LEVELS];
    int32_t *ray_k[VR_MAX_2D_LEVELS];
    int tables_pending;                   /* brick tables still to come from GP 0 */
    uint64_t t_pass_req;                  /* when this pass's requests were out */
    vr_shade_consts_t shade_consts;
    vr_probe_t probe;
} vr_state_t;

const vr_probe_t *vr_probe(const void *state)
{
    return state ? &((const vr_state_t *)state)->probe : NULL;
}

/* ---- bit volumes --------------------------------------------------------- */

static size_t bits_words(int nx, int ny, int nz)
{
    return (size_t)((nx + 63) / 64) * (size_t)ny * (size_t)nz;
}

static bool bits_alloc(gp_t *gp, bits_t *b, int nx, int ny, int nz)
{
    b->nx = nx;
    b->ny = ny;
    b->nz = nz;
    b->wpr = (nx + 63) / 64;
    b->w = fw_alloc(gp, bits_words(nx, ny, nz) * 8);
    return b->w != NULL;
}

static inline bool bits_get(const bits_t *b, int x, int y, int z)
{
    return (b->w[((size_t)z * b->ny + y) * b->wpr + (x >> 6)] >> (x & 63)) & 1u;
}

static inline void bits_set(bits_t *b, int x, int y, int z)
{
    b->w[((size_t)z * b->ny + y) * b->wpr + (x >> 6)] |= 1ull << (x & 63);
}

/* Box dilation [i-lo, i+hi] per axis (render/octree.c's window, clamped to
 * the grid), word-parallel. */
static void dilate(const bits_t *in, bits_t *out, int lo, int hi, fw_ops_t *ops)
{
    int wpr = in->wpr;
    size_t rows = (size_t)in->ny * in->nz;
    uint64_t tmp[64];
    /* x: out bit i = OR of in bits i-lo .. i+hi */
    for (size_t r = 0; r < rows; r++) {
        const uint64_t *src = in->w + r * wpr;
        uint64_t *dst = out->w + r * wpr;
        for (int k = 0; k < wpr; k++)
            tmp[k] = 0;
        for (int s = -lo; s <= hi; s++) {
            /* bit i takes in bit i + s */
            for (int k = 0; k < wpr; k++) {
                uint64_t v;
                if (s >= 0) {
                    v = src[k] >> s;
                    if (s > 0 && k + 1 < wpr)
                        v |= src[k + 1] << (64 - s);
                } else {
                    int t = -s;
                    v = src[k] << t;
                    if (k > 0)
                        v |= src[k - 1] >> (64 - t);
                }
                tmp[k] |= v;
            }
        }
        for (int k = 0; k < wpr; k++)
            dst[k] = tmp[k];
        /* clear padding beyond nx */
        if (in->nx & 63)
            dst[wpr - 1] &= (1ull << (in->nx & 63)) - 1;
    }
    ops->int_ops += rows * (size_t)wpr * (size_t)(lo + hi + 1) * 3;
    ops->loads += rows * (size_t)wpr * (size_t)(lo + hi + 1);
    ops->stores += rows * (size_t)wpr;
}

static void dilate_rows(const bits_t *in, bits_t *out, int axis, int lo, int hi, fw_ops_t *ops)
{
    int wpr = in->wpr, n = axis == 1 ? in->ny : in->nz;
    for (int z = 0; z < in->nz; z++)
        for (int y = 0; y < in->ny; y++) {
            int i = axis == 1 ? y : z;
            int a = i - lo < 0 ? 0 : i - lo, b = i + hi > n - 1 ? n - 1 : i + hi;
            uint64_t *dst = out->w + ((size_t)z * in->ny + y) * wpr;
            for (int k = 0; k < wpr; k++)
                dst[k] = 0;
            for (int j = a; j <= b; j++) {
                const uint64_t *src = axis == 1 ? in->w + ((size_t)z * in->ny + j) * wpr
                                                : in->w + ((size_t)j * in->ny + y) * wpr;
                for (int k = 0; k < wpr; k++)
                    dst[k] |= src[k];
            }
            ops->loads += (uint64_t)(b - a + 1) * wpr;
            ops->int_ops += (uint64_t)(b - a + 1) * wpr + 6;
            ops->stores += wpr;
        }
}

static bool grid_build(gp_t *gp, octgrid_t *g, const bits_t *occ, int lo, int hi, fw_ops_t *ops)
{
    bits_t t;
    if (!bits_alloc(gp, &t, occ->nx, occ->ny, occ->nz) ||
        !bits_alloc(gp, &g->occ[0], occ->nx, occ->ny, occ->nz))
        return false;
    dilate(occ, &g->occ[0], lo, hi, ops);
    dilate_rows(&g->occ[0], &t, 1, lo, hi, ops);
    dilate_rows(&t, &g->occ[0], 2, lo, hi, ops);
    fw_free(gp, t.w);
    g->heights = 1;
    for (int h = 1; h < VR_MAX_LEVELS; h++) {
        const bits_t *in = &g->occ[h - 1];
        if (in->nx == 1 && in->ny == 1 && in->nz == 1)
            break;
        bits_t *o = &g->occ[h];
        if (!bits_alloc(gp, o, (in->nx + 1) / 2, (in->ny + 1) / 2, (in->nz + 1) / 2))
            return false;
        for (int z = 0; z < in->nz; z++)
            for (int y = 0; y < in->ny; y++)
                for (int k = 0; k < in->wpr; k++) {
                    uint64_t v = in->w[((size_t)z * in->ny + y) * in->wpr + k];
                    ops->loads++;
                    ops->branches++;
                    while (v) {
                        int bit = __builtin_ctzll(v);
                        v &= v - 1;
                        bits_set(o, (k * 64 + bit) / 2, y / 2, z / 2);
                        ops->int_ops += 6;
                        ops->stores++;
                    }
                }
        g->heights = h + 1;
    }
    return true;
}

/* octree_empty_node (render/octree.c) on bit grids. */
static inline int oct_empty_node(const vr_state_t *s, int n, bool exact, const float p[3],
                                 float lo[3], float hi[3], uint32_t *ups)
{
    if (n >= s->cfg.levels)
        n = s->cfg.levels - 1;
    const octgrid_t *g = exact ? &s->exact[n] : &s->grid[n];
    const bits_t *b0 = &g->occ[0];
    int c[3], dims[3] = {b0->nx, b0->ny, b0->nz};
    for (int a = 0; a < 3; a++) {
        float q = vr_level_coord(p[a], n);
        float f = floorf(q);
        c[a] = f < 0.0f ? 0 : (f >= (float)dims[a] ? dims[a] - 1 : (int)f);
    }
    if (bits_get(b0, c[0], c[1], c[2]))
        return -1;
    int h = 0;
    while (h + 1 < g->heights) {
        (*ups)++;
        if (bits_get(&g->occ[h + 1], c[0] >> (h + 1), c[1] >> (h + 1), c[2] >> (h + 1)))
            break;
        h++;
    }
    float scale = (float)(1 << n);
    for (int a = 0; a < 3; a++) {
        int first = (c[a] >> h) << h;
        int last = first + (1 << h);
        lo[a] = first == 0 ? -INFINITY : ((float)first + 0.5f) * scale - 0.5f;
        hi[a] = last >= dims[a] ? INFINITY : ((float)last + 0.5f) * scale - 0.5f;
    }
    return h;
}

/* ---- messages ------------------------------------------------------------ */

static fw_status_t send_gp(gp_t *gp, unsigned dst, uint32_t sub, uint32_t a1, uint32_t a2,
                           const void *payload, size_t bytes)
{
    uint32_t args[RING_MSG_ARGS] = {sub, a1, a2, 0, 0, 0};
    return fw_send(gp, ring_addr(RING_NODE_GP, dst), RING_MSG_GP_USER, args, payload, bytes);
}

/* ---- setup: mip-map build ------------------------------------------------ */

static inline float slab_at(const vr_state_t *s, int x, int y, int z)
{
    const vr_config_t *c = &s->cfg;
    return s->slab[((size_t)(z - c->data_z0) * c->ny + y) * c->nx + x];
}

/* Level-0 components of one voxel (render/mip3d.c mip3d_base_slice with
 * shade_gradient inlined). */
static void base_voxel(const vr_state_t *s, int x, int y, int z, float *o, fw_ops_t *ops)
{
    const vr_config_t *c = &s->cfg;
    int p[3] = {x, y, z}, n[3] = {c->nx, c->ny, c->nz};
    float g[3];
    for (int a = 0; a < 3; a++) {
        int lo[3] = {x, y, z}, hi[3] = {x, y, z};
        lo[a] = p[a] > 0 ? p[a] - 1 : p[a];
        hi[a] = p[a] < n[a] - 1 ? p[a] + 1 : p[a];
        int span = hi[a] - lo[a];
        if (span == 0) {
            g[a] = 0.0f;
            continue;
        }
        float d = slab_at(s, hi[0], hi[1], hi[2]) - slab_at(s, lo[0], lo[1], lo[2]);
        g[a] = d / (float)span * c->inv_spacing[a];
    }
    float rgb[3], nn[3] = {0.0f, 0.0f, 0.0f};
    float gm = sqrtf(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    float a = vr_classify(c, slab_at(s, x, y, z), gm, rgb);
    vr_cost_add(ops, &VR_COST_VOXEL, 1);
    vr_cost_add(ops, &VR_COST_CONTOUR, (uint64_t)c->tf_count);
    for (int k = 0; k < s->stride; k++)
        o[k] = 0.0f;
    if (a <= 0.0f)
        return;
    if (gm > 0.0f)
        for (int k = 0; k < 3; k++)
            nn[k] = g[k] / gm;
    float shade = 1.0f;
    if (c->lighting != VR_LIGHT_MOVING)
        shade = vr_diffuse(c, nn, c->light_dir);
    for (int k = 0; k < 3; k++)
        o[k] = a * rgb[k] * shade;
    o[3] = a;
    if (s->stride == 8)
        for (int k = 0; k < 3; k++)
            o[4 + k] = a * nn[k];
}

/* One output voxel of the 2x2x2 box filter (mip3d_filter_slice). src is the
 * finer level with dims (snx, sny, snz) and z offset szo (its first slice). */
static void filter_voxel(const float *src, int snx, int sny, int snz, int szo, int x, int y,
                         int z, int stride, float *o, fw_ops_t *ops)
{
    float acc[8] = {0};
    for (int dz = 0; dz < 2; dz++) {
        int cz = 2 * z + dz;
        if (cz >= snz)
            continue;
        for (int dy = 0; dy < 2; dy++) {
            int cy = 2 * y + dy;
            if (cy >= sny)
                continue;
            for (int dx = 0; dx < 2; dx++) {
                int cx = 2 * x + dx;
                if (cx >= snx)
                    continue;
                const float *cc = src + (((size_t)(cz - szo) * sny + cy) * snx + cx) * stride;
                for (int k = 0; k < stride; k++)
                    acc[k] += cc[k];
            }
        }
    }
    for (int k = 0; k < stride; k++)
        o[k] = acc[k] * 0.125f;
    vr_cost_add(ops, &VR_COST_FILTER_COMPONENT, (uint64_t)stride);
}

/* Quantise one voxel's components into blocks A and N (vr_shade_fixed.h). */
static void quantise(const float *o, int stride, uint32_t *qa, uint32_t *qn, fw_ops_t *ops)
{
    *qa = vr_q8(o[0]) | vr_q8(o[1]) << 8 | vr_q8(o[2]) << 16 | vr_q8(o[3]) << 24;
    if (stride == 8 && qn) {
        float n[3] = {o[4], o[5], o[6]};
        float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (len > 0.0f)
            for (int k = 0; k < 3; k++)
                n[k] /= len;
        *qn = vr_pack_normal(n);
    }
    vr_cost_add(ops, &VR_COST_QUANTISE, 1);
}

static int brick_id(const vr_state_t *s, int n, int bx, int by, int bz)
{
    const vr_level_geom_t *g = &s->geom[n];
    return s->brick_base[n] + (bz * g->gy + by) * g->gx + bx;
}

/* Sends brick (n, bx, by, bz) to its renderer from a quantised level array
 * covering slices [z_first, ...) of the level. */
static fw_status_t write_brick(gp_t *gp, vr_state_t *s, int n, int bx, int by, int bz,
                               const uint32_t *qa, const uint32_t *qn, int z_first, fw_ops_t *ops)
{
    const vr_level_geom_t *g = &s->geom[n];
    uint32_t *blk = fw_alloc(gp, VR_BRICK_VOXELS * 4u * 2u);
    if (!blk)
        return FW_ERROR;
    uint32_t *blkn = blk + VR_BRICK_VOXELS;
    bool any = false;
    for (int lz = 0; lz < g->bz; lz++)
        for (int ly = 0; ly < g->by; ly++)
            for (int lx = 0; lx < g->bx; lx++) {
                int x = bx * g->bx + lx, y = by * g->by + ly, z = bz * g->bz + lz;
                size_t i = ((size_t)lz * g->by + ly) * g->bx + lx;
                if (x >= g->nx || y >= g->ny || z >= g->nz)
                    continue;
                size_t src = ((size_t)(z - z_first) * g->ny + y) * g->nx + x;
                blk[i] = qa[src];
                if (qn)
                    blkn[i] = qn[src];
                any |= (qa[src] >> 24) != 0;
            }
    ops->loads += VR_BRICK_VOXELS * 2u;
    ops->stores += VR_BRICK_VOXELS * 2u;
    ops->int_ops += VR_BRICK_VOXELS * 4u;
    fw_charge(gp, ops);
    memset(ops, 0, sizeof *ops);
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
        s->probe.setup_bricks_written++;
    }
    fw_free(gp, blk);
    return rc;
}

static size_t level_voxels(const vr_level_geom_t *g, int slices)
{
    return (size_t)g->nx * (size_t)g->ny * (size_t)slices;
}

/* Occupancy bits of a quantised level part (opacity byte non-zero); the
 * float opacity is > 0 exactly where... see ARCHITECTURE.md: occupancy is
 * taken from the float opacity, before quantisation. */

/* Builds this GP's slab: level 0 strip by strip, levels 1..K from each
 * strip, bricks written to the renderers as soon as they are complete. */
static fw_status_t build_slab(gp_t *gp, vr_state_t *s)
{
    const vr_config_t *c = &s->cfg;
    int K = c->slab_k, T = c->slab_t, z0 = s->g * T;
    fw_ops_t ops = {0};
    int zs[VR_MAX_LEVELS], ts[VR_MAX_LEVELS];
    for (int n = 0; n <= K; n++) {
        const vr_level_geom_t *g = &s->geom[n];
        zs[n] = z0 >> n;
        ts[n] = g->slab_t;
        if (zs[n] + ts[n] > g->nz)
            ts[n] = g->nz - zs[n];
        if (ts[n] < 0)
            ts[n] = 0;
    }
    /* Whole-slab float storage for levels 1..K (small), quantised A/N for
     * the same; level 0 lives one strip at a time. */
    /* Strip height: one level-0 brick row (32 rows), or the whole slice when
     * a brick holds every row (small volumes); a multiple of 2^K so that every
     * level's strip rows are complete. */
    int unit = 1 << K;
    /* brow: rows of one level-0 brick row (quantised blocks are staged until
     * a brick row is complete); rows: rows of float components built at a
     * time (2^K, so every level's rows are complete per strip). */
    int brow = s->geom[0].by >= s->geom[0].ny ? ((s->geom[0].ny + unit - 1) / unit) * unit
                                              : s->geom[0].by;
    int rows = brow % unit == 0 ? unit : brow;
    float *lvl[VR_MAX_LEVELS] = {0};
    int lrow0[VR_MAX_LEVELS] = {0}, lrows[VR_MAX_LEVELS] = {0};
    uint8_t *occb[VR_MAX_LEVELS] = {0};
    for (int n = 1; n <= K; n++) {
        size_t cnt = level_voxels(&s->geom[n], ts[n] > 0 ? ts[n] : 1);
        /* Levels below K: one strip's rows; level K: the whole slab (it goes to GP 0). */
        lrows[n] = n < K ? ((rows + (1 << n) - 1) >> n) : s->geom[n].ny;
        if (lrows[n] < 1)
            lrows[n] = 1;
        size_t lcnt = (size_t)s->geom[n].nx * lrows[n] * (ts[n] > 0 ? ts[n] : 1);
        lvl[n] = fw_alloc(gp, lcnt * (size_t)s->stride * sizeof(float));
        occb[n] = fw_alloc(gp, cnt / 8 + 1);
        if (!occb[n])
            return FW_ERROR;
        s->qa[n] = fw_alloc(gp, cnt * 4);
        s->qn[n] = s->stride == 8 ? fw_alloc(gp, cnt * 4) : NULL;
        if (!lvl[n] || !s->qa[n] || (s->stride == 8 && !s->qn[n]))
            return FW_ERROR;
    }
    const vr_level_geom_t *g0 = &s->geom[0];
    size_t strip_vox = (size_t)g0->nx * rows * (ts[0] > 0 ? ts[0] : 1);
    size_t stage_vox = (size_t)g0->nx * brow * (ts[0] > 0 ? ts[0] : 1);
    float *strip = fw_alloc(gp, strip_vox * (size_t)s->stride * sizeof(float));
    uint32_t *sqa = fw_alloc(gp, stage_vox * 4), *sqn = s->stride == 8 ? fw_alloc(gp, stage_vox * 4) : NULL;
    /* Full-slab level-0 occupancy bits to send to GP 0. */
    size_t occ0_count = level_voxels(g0, ts[0]);
    uint8_t *occ0 = fw_alloc(gp, occ0_count / 8 + 1);
    if (!strip || !sqa || (s->stride == 8 && !sqn) || !occ0)
        return FW_ERROR;
    for (int sy = 0; sy < g0->ny; sy += rows) {
        int ry = g0->ny - sy < rows ? g0->ny - sy : rows;
        int brow0 = (sy / brow) * brow;
        for (int z = 0; z < ts[0]; z++)
            for (int y = 0; y < ry; y++)
                for (int x = 0; x < g0->nx; x++) {
                    size_t i = ((size_t)z * rows + y) * g0->nx + x;
                    size_t qi = ((size_t)z * brow + (sy + y - brow0)) * g0->nx + x;
                    float *o = strip + i * s->stride;
                    base_voxel(s, x, sy + y, zs[0] + z, o, &ops);
                    quantise(o, s->stride, &sqa[qi], sqn ? &sqn[qi] : NULL, &ops);
                    if (o[3] > 0.0f) {
                        size_t gi = ((size_t)z * g0->ny + sy + y) * g0->nx + x;
                        occ0[gi >> 3] |= (uint8_t)(1u << (gi & 7));
                    }
                }
        s->probe.setup_voxels_built += (uint64_t)ts[0] * ry * g0->nx;
        /* Level-0 bricks of this strip: rows [sy, sy + ry) cover whole
         * brick rows because by_0 divides the strip (32 = by when bz = 8,
         * bx = 64; otherwise bricks are written from a gathered copy). */
        bool row_done = sy + ry >= brow0 + brow || sy + ry >= g0->ny;
        if (brow % rows != 0 || (g0->by != brow && g0->by < g0->ny)) {
            return fw_fail(gp, "vr: level-0 brick height %d does not match the %d-row strip",
                           g0->by, rows);
        } else if (row_done) {
            for (int bz = zs[0] / g0->bz; bz * g0->bz < zs[0] + ts[0]; bz++)
                for (int by = brow0 / g0->by; by * g0->by < brow0 + brow && by < g0->gy; by++)
                    for (int bx = 0; bx < g0->gx; bx++) {
                        /* view the strip as a level array starting at slice zs[0], row sy */
                        const vr_level_geom_t *g = g0;
                        uint32_t *blk = fw_alloc(gp, VR_BRICK_VOXELS * 8u);
                        if (!blk)
                            return FW_ERROR;
                        uint32_t *blkn = blk + VR_BRICK_VOXELS;
                        bool any = false;
                        for (int lz = 0; lz < g->bz; lz++)
                            for (int ly = 0; ly < g->by; ly++)
                                for (int lx = 0; lx < g->bx; lx++) {
                                    int x = bx * g->bx + lx, y = by * g->by + ly,
                                        z = bz * g->bz + lz;
                                    size_t bi = ((size_t)lz * g->by + ly) * g->bx + lx;
                                    if (x >= g->nx || y >= g->ny || z >= g->nz || y < brow0 ||
                                        y >= brow0 + brow)
                                        continue;
                                    size_t si = ((size_t)(z - zs[0]) * brow + (y - brow0)) * g->nx + x;
                                    blk[bi] = sqa[si];
                                    if (sqn)
                                        blkn[bi] = sqn[si];
                                    any |= (sqa[si] >> 24) != 0;
                                }
                        ops.loads += VR_BRICK_VOXELS * 2u;
                        ops.stores += VR_BRICK_VOXELS * 2u;
                        ops.int_ops += VR_BRICK_VOXELS * 4u;
                        fw_charge(gp, &ops);
                        memset(&ops, 0, sizeof ops);
                        if (any) {
                            int id = brick_id(s, 0, bx, by, bz);
                            unsigned r = (unsigned)id % (unsigned)s->n_r;
                            unsigned base = ((unsigned)id / (unsigned)s->n_r) * (unsigned)s->blocks_per_slot;
                            uint32_t args[RING_MSG_ARGS] = {base, 0, 0, 0, 0, 0};
                            if (fw_send(gp, ring_addr(RING_NODE_RENDERER, r), RING_MSG_RENDERER_WRITE_BS,
                                        args, blk, VR_BRICK_VOXELS * 4u) != FW_OK)
                                return FW_ERROR;
                            if (sqn) {
                                args[0] = base + 1;
                                if (fw_send(gp, ring_addr(RING_NODE_RENDERER, r),
                                            RING_MSG_RENDERER_WRITE_BS, args, blkn,
                                            VR_BRICK_VOXELS * 4u) != FW_OK)
                                    return FW_ERROR;
                            }
                            s->probe.setup_bricks_written++;
                        }
                        fw_free(gp, blk);
                    }
        }
        /* Levels 1..K of this strip. */
        const float *src = strip;
        int srows = rows, sy_n = sy;
        for (int n = 1; n <= K; n++) {
            const vr_level_geom_t *g = &s->geom[n], *gs = &s->geom[n - 1];
            int ny0 = sy_n / 2, nrows = (srows + 1) / 2;
            if (n < K)
                lrow0[n] = ny0;
            for (int z = 0; z < ts[n]; z++)
                for (int y = ny0; y < ny0 + nrows && y < g->ny; y++)
                    for (int x = 0; x < g->nx; x++) {
                        size_t i = ((size_t)z * g->ny + y) * g->nx + x;
                        float *o = lvl[n] + (((size_t)z * lrows[n] + (y - lrow0[n])) * g->nx + x) * s->stride;
                        /* children rows 2y, 2y+1 of the source strip/level */
                        float acc[8] = {0};
                        for (int dz = 0; dz < 2; dz++) {
                            int cz = 2 * (zs[n] + z) + dz;
                            if (cz >= gs->nz)
                                continue;
                            for (int dy = 0; dy < 2; dy++) {
                                int cy = 2 * y + dy;
                                if (cy >= gs->ny)
                                    continue;
                                for (int dx = 0; dx < 2; dx++) {
                                    int cx = 2 * x + dx;
                                    if (cx >= gs->nx)
                                        continue;
                                    const float *cc;
                                    if (n == 1)
                                        cc = src + (((size_t)(cz - zs[0]) * rows + (cy - sy)) * gs->nx + cx) * s->stride;
                                    else
                                        cc = lvl[n - 1] + (((size_t)(cz - zs[n - 1]) * lrows[n - 1] + (cy - lrow0[n - 1])) * gs->nx + cx) * s->stride;
                                    for (int k = 0; k < s->stride; k++)
                                        acc[k] += cc[k];
                                }
                            }
                        }
                        for (int k = 0; k < s->stride; k++)
                            o[k] = acc[k] * 0.125f;
                        vr_cost_add(&ops, &VR_COST_FILTER_COMPONENT, (uint64_t)s->stride);
                        quantise(o, s->stride, &s->qa[n][i], s->qn[n] ? &s->qn[n][i] : NULL, &ops);
                        if (o[3] > 0.0f)
                            occb[n][i >> 3] |= (uint8_t)(1u << (i & 7));
                    }
            sy_n = ny0;
            srows = nrows;
        }
        fw_charge(gp, &ops);
        memset(&ops, 0, sizeof ops);
    }
    fw_free(gp, strip);
    fw_free(gp, sqa);
    if (sqn)
        fw_free(gp, sqn);
    /* Level-0 occupancy to GP 0. */
    if (send_gp(gp, 0, VR_MSG_OCC, 0, (uint32_t)zs[0], occ0, (occ0_count + 7) / 8) != FW_OK)
        return FW_ERROR;
    fw_free(gp, occ0);
    /* Levels 1..K: bricks, occupancy; level K floats to GP 0. */
    for (int n = 1; n <= K; n++) {
        const vr_level_geom_t *g = &s->geom[n];
        if (ts[n] > 0) {
            for (int bz = zs[n] / g->bz; bz * g->bz < zs[n] + ts[n]; bz++)
                for (int by = 0; by < g->gy; by++)
                    for (int bx = 0; bx < g->gx; bx++)
                        if (write_brick(gp, s, n, bx, by, bz, s->qa[n], s->qn[n], zs[n], &ops) != FW_OK)
                            return FW_ERROR;
            if (send_gp(gp, 0, VR_MSG_OCC, (uint32_t)n, (uint32_t)zs[n], occb[n],
                        (level_voxels(g, ts[n]) + 7) / 8) != FW_OK)
                return FW_ERROR;
        }
        fw_free(gp, s->qa[n]);
        if (s->qn[n])
            fw_free(gp, s->qn[n]);
        s->qa[n] = s->qn[n] = NULL;
    }
    if (ts[K] > 0 && K + 1 < c->levels) {
        size_t cnt = level_voxels(&s->geom[K], ts[K]);
        if (send_gp(gp, 0, VR_MSG_LEVELK, (uint32_t)zs[K], (uint32_t)ts[K], lvl[K],
                    cnt * (size_t)s->stride * sizeof(float)) != FW_OK)
            return FW_ERROR;
    }
    for (int n = 1; n <= K; n++) {
        fw_free(gp, lvl[n]);
        fw_free(gp, occb[n]);
    }
    return FW_OK;
}

/* GP 0, once every level-K slab arrived: levels K+1..top, their bricks and
 * occupancy. */
static fw_status_t build_upper(gp_t *gp, vr_state_t *s)
{
    const vr_config_t *c = &s->cfg;
    fw_ops_t ops = {0};
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
                    filter_voxel(s->upper[n - 1], gs->nx, gs->ny, gs->nz, 0, x, y, z, s->stride,
                                 s->upper[n] + i * s->stride, &ops);
                    quantise(s->upper[n] + i * s->stride, s->stride, &qa[i], qn ? &qn[i] : NULL, &ops);
                    if (s->upper[n][i * s->stride + 3] > 0.0f)
                        bits_set(&s->occ[n], x, y, z);
                }
        for (int bz = 0; bz < g->gz; bz++)
            for (int by = 0; by < g->gy; by++)
                for (int bx = 0; bx < g->gx; bx++)
                    if (write_brick(gp, s, n, bx, by, bz, qa, qn, 0, &ops) != FW_OK)
                        return FW_ERROR;
        fw_free(gp, qa);
        if (qn)
            fw_free(gp, qn);
    }
    fw_charge(gp, &ops);
    for (int n = c->slab_k; n < c->levels; n++) {
        fw_free(gp, s->upper[n]);
        s->upper[n] = NULL;
    }
    return FW_OK;
}

/* GP 0, once all occupancy is in: octree and non-empty brick table, sent to
 * every GP as one message each (the same bytes every GP then holds). */

static void nonempty_table(vr_state_t *s)
{
    for (int n = 0; n < s->cfg.levels; n++) {
        const vr_level_geom_t *g = &s->geom[n];
        uint8_t *t = s->brick_nonempty[n];
        for (int z = 0; z < g->nz; z++)
            for (int y = 0; y < g->ny; y++)
                for (int x = 0; x < g->nx; x++)
                    if (bits_get(&s->occ[n], x, y, z))
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
                if (!bits_alloc(gp, &gs[k]->occ[h], nx, ny, nz))
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

/* Serialise or deserialise (to = false) the octree and the brick table. */

static fw_status_t finish_octree(gp_t *gp, vr_state_t *s)
{
    fw_ops_t ops = {0};
    if (alloc_shared(gp, s, false) != FW_OK)
        return FW_ERROR;
    for (int n = 0; n < s->cfg.levels; n++) {
        /* The blended-level grids serve perspective views only: a parallel
         * view samples integer 3D levels (raycast.h), which read the exact
         * grids.  Not building them saves about 1 MB per GP at 256^2 x 109. */
        if ((s->cfg.perspective && !grid_build(gp, &s->grid[n], &s->occ[n], 2, 3, &ops)) ||
            !grid_build(gp, &s->exact[n], &s->occ[n], 0, 1, &ops))
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
                    if (send_gp(gp, (unsigned)h, VR_MSG_OCC, 0xffffffffu,
                                (uint32_t)(n << 8 | k << 7 | hh), b->w,
                                bits_words(b->nx, b->ny, b->nz) * 8) != FW_OK)
                        return FW_ERROR;
                }
            const vr_level_geom_t *g = &s->geom[n];
            if (send_gp(gp, (unsigned)h, VR_MSG_OCC, 0xfffffffeu, (uint32_t)n,
                        s->brick_nonempty[n], (size_t)g->gx * g->gy * g->gz) != FW_OK)
                return FW_ERROR;
        }
    }
    return FW_OK;
}

/* ---- start --------------------------------------------------------------- */

static fw_status_t vr_start(gp_t *gp)
{
    size_t bytes = 0;
    const uint8_t *data = fw_host_data(gp, &bytes);
    if (!data || bytes < sizeof(vr_config_t))
        return fw_fail(gp, "vr: host data missing or short (%zu bytes)", bytes);
    vr_state_t *s = fw_alloc(gp, sizeof *s);
    if (!s)
        return FW_ERROR;
    fw_set_state(gp, s);
    memcpy(&s->cfg, data, sizeof s->cfg);
    const vr_config_t *c = &s->cfg;
    if (c->magic != VR_MAGIC || c->levels < 1 || c->levels > VR_MAX_LEVELS)
        return fw_fail(gp, "vr: bad configuration block");
    const fw_machine_info_t *mi = fw_machine_info(gp);
    s->g = (int)fw_gp_index(gp);
    s->n_gp = (int)mi->n_gp;
    s->n_r = (int)mi->n_renderers;
    s->stride = c->lighting == VR_LIGHT_DIFFUSE ? 4 : 8;
    s->blocks_per_slot = c->lighting == VR_LIGHT_DIFFUSE ? 1 : 3;
    vr_geometry(c, s->geom);
    int id = 0;
    for (int n = 0; n < c->levels; n++) {
        s->brick_base[n] = id;
        id += s->geom[n].gx * s->geom[n].gy * s->geom[n].gz;
    }
    s->n_bricks = id;
    s->probe.n_bricks_total = (uint64_t)id;
    unsigned slots = (unsigned)((id + s->n_r - 1) / s->n_r);
    s->probe.max_slots_used = slots;
    unsigned bs_blocks = fw_machine_info(gp)->pp_bs_blocks;
    if (slots * (unsigned)s->blocks_per_slot > bs_blocks)
        return fw_fail(gp, "vr: the 3D mip map needs %u backing-store blocks per PP "
                           "(%d bricks of %u voxels over %d renderers, %d blocks each); "
                           "a PP has %u (facts §3.1)",
                       slots * (unsigned)s->blocks_per_slot, id, VR_BRICK_VOXELS, s->n_r,
                       s->blocks_per_slot, bs_blocks);
    /* Opacity-correction table (raycast_ctx_init) and byte->float table. */
    fw_ops_t ops = {0};
    for (int l = 0; l < VR_LUT_LEVELS; l++) {
        double spacing = (double)c->sample_step * (double)(1 << l);
        for (int i = 0; i <= VR_LUT_SIZE; i++)
            s->alpha_lut[l][i] = (float)(1.0 - pow(1.0 - (double)i / VR_LUT_SIZE, spacing));
    }
    vr_cost_add(&ops, &VR_COST_LEVEL_TRANS, (uint64_t)VR_LUT_LEVELS * (VR_LUT_SIZE + 1));
    for (int i = 0; i < 256; i++)
        s->u8_to_f[i] = (float)i / 255.0f;
    ops.fdiv += 256;
    fw_charge(gp, &ops);
    s->cache = fw_alloc(gp, (size_t)id * sizeof(uint32_t *));
    s->cache_n = fw_alloc(gp, (size_t)id * sizeof(uint32_t *));
    if (!s->cache || !s->cache_n)
        return FW_ERROR;
    if (s->g == 0) {
        for (int n = 0; n < c->levels; n++)
            if (!bits_alloc(gp, &s->occ[n], s->geom[n].nx, s->geom[n].ny, s->geom[n].nz))
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
    s->probe.setup_cycles = fw_cycles(gp);
    return FW_OK;
}

/* The host's slab (slices [data_z0, data_z1)) arrives as one message: it is
 * copied into local memory, the slab's mip levels are built and sent, and
 * the copy is freed (it is not needed per frame). */
static fw_status_t on_slab(gp_t *gp, vr_state_t *s, const ring_msg_t *m)
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
    ops.ext_bytes = need;
    fw_charge(gp, &ops);
    s->slab = copy;
    fw_status_t rc = build_slab(gp, s);
    fw_free(gp, copy);
    s->slab = NULL;
    return rc;
}

/* ---- setup messages ------------------------------------------------------ */

static fw_status_t maybe_finish_setup(gp_t *gp, vr_state_t *s)
{
    if (s->g != 0 || s->have_octree || s->levk_pending > 0 || s->occ_pending > 0)
        return FW_OK;
    return finish_octree(gp, s);
}

static fw_status_t on_levelk(gp_t *gp, vr_state_t *s, const ring_msg_t *m)
{
    const vr_level_geom_t *gk = &s->geom[s->cfg.slab_k];
    /* args[1] = first slice, args[2] = slices */
    size_t slice_floats = (size_t)gk->nx * gk->ny * (size_t)s->stride;
    size_t z_first = m->args[1], z_count = m->args[2];
    if (z_first + z_count > (size_t)gk->nz || m->payload_bytes != z_count * slice_floats * sizeof(float))
        return fw_fail(gp, "vr: malformed level-K slab message");
    memcpy(s->upper[s->cfg.slab_k] + z_first * slice_floats, m->payload, m->payload_bytes);
    fw_ops_t ops = {0};
    ops.loads = ops.stores = m->payload_bytes / 4;
    fw_charge(gp, &ops);
    if (--s->levk_pending == 0 && build_upper(gp, s) != FW_OK)
        return FW_ERROR;
    return maybe_finish_setup(gp, s);
}

static fw_status_t on_occ(gp_t *gp, vr_state_t *s, const ring_msg_t *m)
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
            want = bits_words(gr->occ[hh].nx, gr->occ[hh].ny, gr->occ[hh].nz) * 8;
        }
        if (m->payload_bytes != want)
            return fw_fail(gp, "vr: octree message of %zu bytes, expected %zu", m->payload_bytes, want);
        memcpy(dst, m->payload, want);
        fw_ops_t ops = {0};
        ops.ext_bytes = want;
        fw_charge(gp, &ops);
        if (s->tables_pending == 0)
            s->have_octree = true;
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
        bits_set(&s->occ[n], (int)(r % g->nx), (int)(r / g->nx), (int)z);
        ops.int_ops += 6;
    }
    ops.loads += m->payload_bytes;
    ops.int_ops += m->payload_bytes * 8;
    fw_charge(gp, &ops);
    s->occ_pending--;
    return maybe_finish_setup(gp, s);
}

/* ---- frame --------------------------------------------------------------- */

static void frame_free(gp_t *gp, vr_state_t *s, bool keep_view)
{
    for (int i = 0; i < s->n_bricks; i++) {
        if (s->cache[i]) {
            fw_free(gp, s->cache[i]);
            s->cache[i] = NULL;
        }
        if (s->cache_n[i]) {
            fw_free(gp, s->cache_n[i]);
            s->cache_n[i] = NULL;
        }
    }
    for (int m = 0; m < VR_MAX_2D_LEVELS; m++) {
        if (s->ray_state[m])
            fw_free(gp, s->ray_state[m]);
        if (s->ray_a[m])
            fw_free(gp, s->ray_a[m]);
        if (s->ray_t[m])
            fw_free(gp, s->ray_t[m]);
        if (s->ray_k[m])
            fw_free(gp, s->ray_k[m]);
        s->ray_state[m] = NULL;
        s->ray_a[m] = s->ray_t[m] = NULL;
        s->ray_k[m] = NULL;
    }
    if (keep_view)
        return;
    for (int m = 0; m < VR_MAX_2D_LEVELS; m++) {
        if (s->texel[m])
            fw_free(gp, s->texel[m]);
        if (s->need[m])
            fw_free(gp, s->need[m]);
        if (s->castf[m])
            fw_free(gp, s->castf[m]);
        s->texel[m] = NULL;
        s->need[m] = NULL;
        s->castf[m] = NULL;
    }
    if (s->level)
        fw_free(gp, s->level);
    s->level = NULL;
}

static bool uses_exec(const vr_state_t *s)
{
    return s->cfg.lighting != VR_LIGHT_DIFFUSE && s->cfg.split == VR_SPLIT_PP;
}

/* Backing-store block a GP reads for brick id (and the N block, GP split). */
static unsigned brick_block(const vr_state_t *s, int id, int which)
{
    unsigned slot = (unsigned)id / (unsigned)s->n_r;
    unsigned base = slot * (unsigned)s->blocks_per_slot;
    if (s->cfg.lighting == VR_LIGHT_DIFFUSE)
        return base;
    if (s->cfg.split == VR_SPLIT_PP)
        return base + 2;
    return base + (unsigned)which;
}

static fw_status_t send_read(gp_t *gp, vr_state_t *s, int id, unsigned requester)
{
    unsigned r = (unsigned)id % (unsigned)s->n_r;
    int reads = (s->cfg.lighting != VR_LIGHT_DIFFUSE && s->cfg.split == VR_SPLIT_GP) ? 2 : 1;
    for (int w = 0; w < reads; w++) {
        uint32_t args[RING_MSG_ARGS] = {brick_block(s, id, w), 0,
                                        ring_addr_pack(ring_addr(RING_NODE_GP, requester)),
                                        (uint32_t)id * 2u + (uint32_t)w, 0, 0};
        if (fw_send(gp, ring_addr(RING_NODE_RENDERER, r), RING_MSG_RENDERER_READ_BS, args, NULL, 0) != FW_OK)
            return FW_ERROR;
    }
    return FW_OK;
}

static fw_status_t forward_requests(gp_t *gp, vr_state_t *s, const uint32_t *ids, size_t n,
                                    unsigned requester)
{
    fw_ops_t ops = {0};
    uint64_t c0 = fw_cycles(gp);
    for (size_t i = 0; i < n; i++) {
        if ((int)ids[i] >= s->n_bricks)
            return fw_fail(gp, "vr: request for brick %u", ids[i]);
        ops.loads++;
        ops.int_ops += 4;
        if (send_read(gp, s, (int)ids[i], requester) != FW_OK)
            return FW_ERROR;
    }
    fw_charge(gp, &ops);
    s->probe.cyc_forward += fw_cycles(gp) - c0;
    return FW_OK;
}

/* Driver GP of renderer r. */
static unsigned driver_of(const vr_state_t *s, unsigned r)
{
    return r % (unsigned)s->n_gp;
}

static fw_status_t send_exec(gp_t *gp, vr_state_t *s)
{
    uint64_t c0 = fw_cycles(gp);
    fw_ops_t ops = {0};
    ops.fadd += 8;
    ops.fmul += 10;
    ops.fsqrt += 1;
    ops.fdiv += 3;
    pp_stream_t st;
    pp_stream_init(&st);
    uint32_t *slots = fw_alloc(gp, fw_machine_info(gp)->pp_bs_blocks * sizeof(uint32_t));
    if (!slots)
        return FW_ERROR;
    fw_status_t rc = FW_OK;
    for (int r = s->g; r < s->n_r && rc == FW_OK; r += s->n_gp) {
        size_t n = 0;
        for (int id = r; id < s->n_bricks; id += s->n_r) {
            /* non-empty? */
            int n3 = 0;
            while (n3 + 1 < s->cfg.levels && id >= s->brick_base[n3 + 1])
                n3++;
            ops.int_ops += 4;
            ops.branches += 2;
            if (s->brick_nonempty[n3][id - s->brick_base[n3]])
                slots[n++] = (uint32_t)(id / s->n_r);
        }
        pp_stream_clear(&st);
        vr_pp_shade_stream(&st, &s->shade_consts, slots, n);
        ops.int_ops += 2 * st.n_words;
        ops.stores += st.n_words;
        fw_charge(gp, &ops);
        memset(&ops, 0, sizeof ops);
        if (!pp_stream_ok(&st)) {
            rc = fw_fail(gp, "vr: shading stream: %s", pp_stream_error(&st));
            break;
        }
        s->probe.pp_stream_words += st.n_words;
        size_t bytes = st.n_words * 4;
        uint32_t *local = fw_alloc(gp, bytes);
        if (!local) {
            rc = FW_ERROR;
            break;
        }
        memcpy(local, st.words, bytes);
        rc = fw_send(gp, ring_addr(RING_NODE_RENDERER, (unsigned)r), RING_MSG_RENDERER_EXEC, NULL,
                     local, bytes);
        fw_free(gp, local);
    }
    fw_free(gp, slots);
    pp_stream_free(&st);
    s->probe.cyc_exec_build += fw_cycles(gp) - c0;
    return rc;
}

/* Project object-space point to image coordinates (inverse of camera_ray). */
static void project(const vr_state_t *s, const float P[3], float *px, float *py)
{
    const vr_frame_t *f = &s->fr;
    float d[3];
    if (f->projection == 0) {
        for (int a = 0; a < 3; a++)
            d[a] = P[a] - f->centre[a];
        *px = (d[0] * f->right[0] + d[1] * f->right[1] + d[2] * f->right[2]) / f->pixel_size +
              0.5f * (float)s->cfg.width;
        *py = (d[0] * f->down[0] + d[1] * f->down[1] + d[2] * f->down[2]) / f->pixel_size +
              0.5f * (float)s->cfg.height;
        return;
    }
    for (int a = 0; a < 3; a++)
        d[a] = P[a] - f->eye[a];
    float z = d[0] * f->forward[0] + d[1] * f->forward[1] + d[2] * f->forward[2];
    if (z < 1e-3f)
        z = 1e-3f;
    float k = f->eye_distance / z;
    *px = k * (d[0] * f->right[0] + d[1] * f->right[1] + d[2] * f->right[2]) / f->pixel_size +
          0.5f * (float)s->cfg.width;
    *py = k * (d[0] * f->down[0] + d[1] * f->down[1] + d[2] * f->down[2]) / f->pixel_size +
          0.5f * (float)s->cfg.height;
}

/* Does brick (n, bx, by, bz), padded by one level-n voxel, project onto the
 * rectangle [x0, x1] x [y0, y1] of image points? */
static bool brick_hits(const vr_state_t *s, int n, int bx, int by, int bz, const float rect[4],
                       const float tseg[2], fw_ops_t *ops)
{
    const vr_level_geom_t *g = &s->geom[n];
    float sc = (float)(1 << n);
    int lo[3] = {bx * g->bx, by * g->by, bz * g->bz};
    int hi[3] = {lo[0] + g->bx - 1, lo[1] + g->by - 1, lo[2] + g->bz - 1};
    float plo[3], phi[3];
    for (int a = 0; a < 3; a++) {
        /* level-0 voxel positions, padded by one level-n spacing and a margin */
        plo[a] = (((float)lo[a] + 0.5f) * sc - 0.5f - sc - 1.0f) * s->cfg.spacing[a];
        phi[a] = (((float)hi[a] + 0.5f) * sc - 0.5f + sc + 1.0f) * s->cfg.spacing[a];
    }
    float mnx = INFINITY, mxx = -INFINITY, mny = INFINITY, mxy = -INFINITY;
    float tmin = INFINITY, tmax = -INFINITY;
    const vr_frame_t *f = &s->fr;
    for (int k = 0; k < 8; k++) {
        float P[3] = {(k & 1) ? phi[0] : plo[0], (k & 2) ? phi[1] : plo[1], (k & 4) ? phi[2] : plo[2]};
        float px, py;
        project(s, P, &px, &py);
        /* Ray parameter of the corner: parallel t = depth + radius + 1;
         * perspective: between the depth along the view axis (a lower
         * bound, minimal at a corner) and the distance (maximal at one). */
        float tl, th;
        if (f->projection == 0) {
            tl = th = (P[0] - f->centre[0]) * f->forward[0] + (P[1] - f->centre[1]) * f->forward[1] +
                      (P[2] - f->centre[2]) * f->forward[2] + f->radius + 1.0f;
        } else {
            float d[3] = {P[0] - f->eye[0], P[1] - f->eye[1], P[2] - f->eye[2]};
            tl = d[0] * f->forward[0] + d[1] * f->forward[1] + d[2] * f->forward[2];
            th = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        }
        tmin = tl < tmin ? tl : tmin;
        tmax = th > tmax ? th : tmax;
        mnx = px < mnx ? px : mnx;
        mxx = px > mxx ? px : mxx;
        mny = py < mny ? py : mny;
        mxy = py > mxy ? py : mxy;
    }
    ops->fadd += 8 * 8;
    ops->fmul += 8 * 8;
    ops->fdiv += 8 * 2;
    ops->branches += 8 * 4 + 4;
    if (tmax < tseg[0] - 1.0f || tmin > tseg[1] + 1.0f)
        return false;
    return !(mxx < rect[0] - 2.0f || mnx > rect[1] + 2.0f || mxy < rect[2] - 2.0f || mny > rect[3] + 2.0f);
}

static fw_status_t start_cast_if_ready(gp_t *gp, vr_state_t *s);
static fw_status_t footprint(gp_t *gp, vr_state_t *s, uint32_t *want, size_t *n_out);
static fw_status_t request_pass(gp_t *gp, vr_state_t *s);

static fw_status_t vr_frame_start(gp_t *gp, vr_state_t *s, uint32_t frame)
{
    const vr_config_t *c = &s->cfg;
    /* Progressive refinement (paper §7): keep the 2D mip map, its flags and
     * each pixel's finest level while the bands stay the same. */
    bool reuse = (s->fr.progressive_keep & 2) && s->level &&
                 s->y0 == s->fr.band_y0[s->g] && s->y1 == s->fr.band_y0[s->g + 1];
    frame_free(gp, s, reuse);
    memset(&s->probe.t_start, 0, sizeof(uint64_t) * 6);
    s->probe.cyc_prep = s->probe.cyc_exec_build = s->probe.cyc_forward = s->probe.cyc_unpack = 0;
    s->probe.cyc_shade = s->probe.cyc_cast = s->probe.cyc_pixels = 0;
    s->probe.rays = s->probe.samples = s->probe.skipped = 0;
    s->probe.bricks_fetched = s->probe.bytes_fetched = s->probe.fb_bytes = 0;
    s->probe.pp_stream_words = 0;
    s->probe.wait_ps = s->probe.cast_ps = s->probe.passes = 0;
    s->probe.frame_done = 0;
    s->probe.t_start = fw_time_ps(gp);
    s->frame = (int)frame;
    s->cast_done = false;
    s->boundary_ok = false;
    if (!s->have_octree)
        return fw_fail(gp, "vr: frame started before the mip map was distributed");
    if ((s->fr.projection != 0) != (c->perspective != 0))
        return fw_fail(gp, "vr: the projection is fixed per sequence (octree grids)");
    if (c->lighting != VR_LIGHT_DIFFUSE) {
        /* Fixed light: light_dir is in object space.  Moving object: it is in
         * eye space; carry it into object space for this view
         * (raycast_ctx_init). */
        float light[3];
        for (int a = 0; a < 3; a++)
            light[a] = c->lighting == VR_LIGHT_MOVING
                           ? c->light_dir[0] * s->fr.right[a] + c->light_dir[1] * s->fr.down[a] +
                                 c->light_dir[2] * s->fr.forward[a]
                           : c->light_dir[a];
        float view[3] = {-s->fr.forward[0], -s->fr.forward[1], -s->fr.forward[2]}, half[3];
        vr_half_vector(light, view, half);
        vr_shade_consts(&s->shade_consts, half, c->specular, (int)c->specular_exponent, c->two_sided);
        if (c->lighting == VR_LIGHT_MOVING)
            vr_shade_consts_diffuse(&s->shade_consts, light, c->ambient, c->diffuse);
        fw_ops_t lo = {0};
        lo.fmul = 9 + 12;
        lo.fadd = 6 + 8;
        lo.fsqrt = 1;
        lo.fdiv = 3;
        fw_charge(gp, &lo);
    }
    if (uses_exec(s) && send_exec(gp, s) != FW_OK)
        return FW_ERROR;
    s->exec_sent = true;
    if (s->pending_req_n) {
        /* requests that overtook our FRAME_START: [requester, count, ids...] records */
        size_t i = 0;
        while (i + 2 <= s->pending_req_n) {
            unsigned req = s->pending_req[i], cnt = s->pending_req[i + 1];
            if (forward_requests(gp, s, s->pending_req + i + 2, cnt, req) != FW_OK)
                return FW_ERROR;
            i += 2 + cnt;
        }
        s->pending_req_n = 0;
    }
    uint64_t c0 = fw_cycles(gp);
    fw_ops_t ops = {0};
    /* Own rows and texel rows. */
    s->levels2d = s->fr.mode == VR_MODE_GAZE ? c->levels2d : 1;
    s->maxm = s->levels2d - 1;
    s->y0 = s->fr.band_y0[s->g];
    s->y1 = s->fr.band_y0[s->g + 1];
    bool last = s->g + 1 >= s->n_gp || s->fr.band_y0[s->g + 2] == s->fr.band_y0[s->g + 1] ||
                s->y1 >= c->height;
    int W = c->width, H = c->height;
    if (s->y0 >= s->y1) {
        s->probe.t_prep_done = s->probe.t_data_done = s->probe.t_cast_done = fw_time_ps(gp);
        s->probe.t_boundary = s->probe.t_done = fw_time_ps(gp);
        s->probe.frame_done = 1;
        s->probe.all_level0 = 1;
        return FW_OK;
    }
    int span = 1 << s->maxm;
    s->ly0 = s->y0 - span < 0 ? 0 : s->y0 - span;
    s->ly1 = s->y1 + span > H ? H : s->y1 + span;
    if (!reuse) {
        s->level = fw_alloc(gp, (size_t)(s->ly1 - s->ly0) * W * sizeof(float));
        if (!s->level)
            return FW_ERROR;
        for (size_t i = 0; i < (size_t)(s->ly1 - s->ly0) * W; i++)
            s->level[i] = INFINITY;
    }
    uint64_t n_level = 0, n_trans = 0;
    for (int y = s->ly0; y < s->ly1; y++) {
        float *row = s->level + (size_t)(y - s->ly0) * W;
        for (int x = 0; x < W; x++) {
            float level = 0.0f;
            if (s->fr.mode == VR_MODE_GAZE) {
                double dx = (double)x - s->fr.gaze_x, dy = (double)y - s->fr.gaze_y;
                int tr = 0;
                level = vr_gaze_level(c, sqrt(dx * dx + dy * dy) / s->fr.gaze_scale, &tr);
                n_trans += (uint64_t)tr;
            }
            if (level < row[x])
                row[x] = level;    /* finest level so far (render/: level_best) */
        }
        n_level += (uint64_t)W;
    }
    if (s->fr.mode == VR_MODE_GAZE) {
        vr_cost_add(&ops, &VR_COST_LEVEL, n_level);
        vr_cost_add(&ops, &VR_COST_LEVEL_TRANS, n_trans);
    }
    /* Texel rows and marks (mip2d_mark_pixel, own rows only). */
    for (int m = 0; m < s->levels2d; m++) {
        s->tw[m] = ((W - 1) >> m) + 2;
        s->th[m] = ((H - 1) >> m) + 2;
        s->jlo[m] = (s->y0 + (1 << m) - 1) >> m;
        s->jhi[m] = last ? s->th[m] - 1 : ((s->y1 + (1 << m) - 1) >> m) - 1;
        int rows = s->jhi[m] - s->jlo[m] + 2;
        if (reuse) {
            memset(s->need[m], 0, (size_t)rows * s->tw[m]);
            continue;
        }
        s->texel[m] = fw_alloc(gp, (size_t)rows * s->tw[m] * 3 * sizeof(float));
        s->need[m] = fw_alloc(gp, (size_t)rows * s->tw[m]);
        s->castf[m] = fw_alloc(gp, (size_t)rows * s->tw[m]);
        if (!s->texel[m] || !s->need[m] || !s->castf[m])
            return FW_ERROR;
    }
    for (int m = 0; m < s->levels2d; m++) {
        size_t n = (size_t)(s->jhi[m] - s->jlo[m] + 1) * s->tw[m];
        s->ray_state[m] = fw_alloc(gp, n);
        s->ray_a[m] = fw_alloc(gp, n * sizeof(float));
        s->ray_t[m] = fw_alloc(gp, n * sizeof(float));
        s->ray_k[m] = fw_alloc(gp, n * sizeof(int32_t));
        if (!s->ray_state[m] || !s->ray_a[m] || !s->ray_t[m] || !s->ray_k[m])
            return FW_ERROR;
    }
    uint64_t n_mark = 0;
    for (int y = s->ly0; y < s->ly1; y++) {
        const float *row = s->level + (size_t)(y - s->ly0) * W;
        for (int x = 0; x < W; x++) {
            float level = row[x];
            int lo = (int)level;
            if (lo >= s->levels2d)
                lo = s->levels2d - 1;
            for (int pass = 0; pass < 2; pass++) {
                int l = lo + pass;
                if (pass == 1 && !(level > (float)lo && lo + 1 < s->levels2d))
                    break;
                int i = x >> l, j = y >> l;
                bool fx = (x & ((1 << l) - 1)) != 0, fy = (y & ((1 << l) - 1)) != 0;
                for (int dj = 0; dj <= (fy ? 1 : 0); dj++) {
                    int jj = j + dj;
                    if (jj < s->jlo[l] || jj > s->jhi[l])
                        continue;
                    uint8_t *nd = s->need[l] + (size_t)(jj - s->jlo[l]) * s->tw[l];
                    nd[i] = 1;
                    if (fx)
                        nd[i + 1] = 1;
                }
            }
            n_mark++;
        }
    }
    vr_cost_add(&ops, &VR_COST_MARK, n_mark);
    fw_charge(gp, &ops);
    s->probe.cyc_prep += fw_cycles(gp) - c0;
    /* Passes (column ranges x depth segments) so that one pass's bricks fit
     * in memory: first try one pass. */
    s->n_passes = s->n_cols = s->n_segs = 1;
    s->pass = 0;
    {
        const vr_frame_t *f = &s->fr;
        if (f->projection == 0) {
            s->seg_t0 = 0.0f;
            s->seg_len = 2.0f * (f->radius + 1.0f);
        } else {
            float lo = f->eye_distance - f->radius - 1.0f;
            s->seg_t0 = lo > 0.0f ? lo : 0.0f;
            s->seg_len = f->eye_distance + f->radius + 1.0f - s->seg_t0;
        }
    }

    size_t n_all = 0;
    if (footprint(gp, s, NULL, &n_all) != FW_OK)
        return FW_ERROR;
    uint64_t cap = fw_machine_info(gp)->local_mem_bytes, used = fw_mem_used_bytes(gp);
    uint64_t reserve = 256u * 1024u;
    uint64_t avail;
    /* GP split: a brick's N block arrives right behind its A block (same
     * renderer FIFO) and is freed once shaded, so one N is live at a time. */
    uint64_t per = VR_BRICK_VOXELS * 4u;
    if (c->lighting != VR_LIGHT_DIFFUSE && c->split == VR_SPLIT_GP)
        reserve += VR_BRICK_VOXELS * 4u;
    avail = cap > used + reserve ? cap - used - reserve : 0;
    /* The host may cap a pass's bricks below what memory allows (studies of
     * the pass machinery; 0 = memory decides). */
    if (c->max_pass_bricks > 0 && avail > (uint64_t)c->max_pass_bricks * per)
        avail = (uint64_t)c->max_pass_bricks * per;
    /* Passes: the fewest (depth segments x column ranges), both powers of
     * two, whose largest footprint fits (each footprint is charged).  Depth
     * segments split rays front to back (a ray resumes where it stopped), so
     * they shrink footprints along the view direction; columns across it. */
    bool fits = (uint64_t)n_all * per <= avail;
    /* Search up to 64 passes (the search itself is charged GP work). */
    for (int total = 2; !fits && total <= 64; total *= 2) {
        for (int segs = total; segs >= 1 && !fits; segs /= 2) {
            int cols = total / segs;
            if (segs > 16)
                continue;
            s->n_segs = segs;
            s->n_cols = cols;
            s->n_passes = segs * cols;
            n_all = 0;
            for (s->pass = 0; s->pass < s->n_passes; s->pass++) {
                size_t n = 0;
                if (footprint(gp, s, NULL, &n) != FW_OK)
                    return FW_ERROR;
                n_all = n > n_all ? n : n_all;
            }
            fits = (uint64_t)n_all * per <= avail;
        }
    }
    if (!fits)
        return fw_fail(gp, "vr: GP %d: the bricks of its partition do not fit in local memory "
                           "(%llu bytes free after a %llu-byte working set; %zu bricks of %llu "
                           "bytes in the largest of %d passes)",
                       s->g, (unsigned long long)avail, (unsigned long long)used, n_all,
                       (unsigned long long)per, s->n_passes);
    s->pass = 0;
    s->probe.t_prep_done = fw_time_ps(gp);
    return request_pass(gp, s);
}

/* Pixel x range of pass p. */
/* Ray-parameter range [t0, t1) of pass q's depth segment. */
static void seg_range(const vr_state_t *s, int q, float *t0, float *t1)
{
    int d = q % s->n_segs;
    *t0 = d == 0 ? -INFINITY : s->seg_t0 + s->seg_len * (float)d / (float)s->n_segs;
    *t1 = d + 1 == s->n_segs ? INFINITY : s->seg_t0 + s->seg_len * (float)(d + 1) / (float)s->n_segs;
}

static void pass_range(const vr_state_t *s, int q, float *x0, float *x1)
{
    int W = s->cfg.width;
    int p = q / s->n_segs;
    *x0 = p == 0 ? -INFINITY : (float)((long)W * p / s->n_cols);
    *x1 = p + 1 == s->n_cols ? INFINITY : (float)((long)W * (p + 1) / s->n_cols);
}

/* Footprint of the current pass: bounding rectangle of its marked texel
 * points per 2D level, then the non-empty bricks of the 3D levels those rays
 * read whose padded projection meets the rectangle.  want = NULL: count only. */
static fw_status_t footprint(gp_t *gp, vr_state_t *s, uint32_t *want, size_t *n_out)
{
    const vr_config_t *c = &s->cfg;
    fw_ops_t ops = {0};
    float px0, px1, tseg[2];
    pass_range(s, s->pass, &px0, &px1);
    seg_range(s, s->pass, &tseg[0], &tseg[1]);
    float rect[VR_MAX_2D_LEVELS][4];
    bool any_level[VR_MAX_2D_LEVELS] = {false};
    for (int m = 0; m < s->levels2d; m++) {
        rect[m][0] = rect[m][2] = INFINITY;
        rect[m][1] = rect[m][3] = -INFINITY;
        for (int j = s->jlo[m]; j <= s->jhi[m]; j++) {
            const uint8_t *nd = s->need[m] + (size_t)(j - s->jlo[m]) * s->tw[m];
            const uint8_t *cf = s->castf[m] + (size_t)(j - s->jlo[m]) * s->tw[m];
            const uint8_t *rsx = s->ray_state[m] + (size_t)(j - s->jlo[m]) * s->tw[m];
            for (int i = 0; i < s->tw[m]; i++) {
                if (!nd[i] || cf[i] || rsx[i] == 2)
                    continue;
                float px = (float)(i << m) + 0.5f, py = (float)(j << m) + 0.5f;
                if (px < px0 || px >= px1)
                    continue;
                rect[m][0] = px < rect[m][0] ? px : rect[m][0];
                rect[m][1] = px > rect[m][1] ? px : rect[m][1];
                rect[m][2] = py < rect[m][2] ? py : rect[m][2];
                rect[m][3] = py > rect[m][3] ? py : rect[m][3];
                any_level[m] = true;
            }
            ops.loads += (uint64_t)s->tw[m];
            ops.branches += (uint64_t)s->tw[m];
        }
    }
    uint8_t *wanted = fw_alloc(gp, (size_t)s->n_bricks);
    if (!wanted)
        return FW_ERROR;
    size_t n_want = 0;
    float lstep = log2f(c->sample_step);
    for (int m = 0; m < s->levels2d; m++) {
        if (!any_level[m])
            continue;
        /* 3D levels a level-m ray reads: m exactly under parallel projection
         * (raycast.h); perspective spacing varies along the ray, so m-1..m+1
         * (eye distance >= 1 radius keeps the ratio within 2). */
        float base3d = log2f(c->sample_step * (float)(1 << m)) - lstep;
        int n_lo = (int)floorf(base3d), n_hi = n_lo;
        if (s->fr.projection != 0) {
            /* Perspective: spacing t * base / eye_distance for t within the
             * bounding sphere, so levels floor(L(t_near)) .. ceil(L(t_far)). */
            float base = c->sample_step * (float)(1 << m);
            float ed = s->fr.eye_distance, rad = s->fr.radius + 1.0f;
            float t_near = ed - rad > 1e-3f ? ed - rad : 1e-3f, t_far = ed + rad;
            n_lo = (int)floorf(log2f(t_near * base / ed) - lstep);
            n_hi = (int)floorf(log2f(t_far * base / ed) - lstep) + 1;
        }
        for (int n = n_lo; n <= n_hi; n++) {
            int nn = n < 0 ? 0 : (n >= c->levels ? c->levels - 1 : n);
            const vr_level_geom_t *g = &s->geom[nn];
            for (int bz = 0; bz < g->gz; bz++)
                for (int by = 0; by < g->gy; by++)
                    for (int bx = 0; bx < g->gx; bx++) {
                        int local = (bz * g->gy + by) * g->gx + bx;
                        int id = s->brick_base[nn] + local;
                        ops.loads++;
                        ops.branches++;
                        if (wanted[id] || !s->brick_nonempty[nn][local])
                            continue;
                        if (!brick_hits(s, nn, bx, by, bz, rect[m], tseg, &ops))
                            continue;
                        wanted[id] = 1;
                        if (want)
                            want[n_want] = (uint32_t)id;
                        n_want++;
                    }
        }
    }
    fw_charge(gp, &ops);
    fw_free(gp, wanted);
    *n_out = n_want;
    return FW_OK;
}

static fw_status_t request_pass(gp_t *gp, vr_state_t *s)
{
    const vr_config_t *c = &s->cfg;
    uint64_t c0 = fw_cycles(gp);
    uint32_t *want = fw_alloc(gp, (size_t)s->n_bricks * sizeof(uint32_t));
    if (!want)
        return FW_ERROR;
    size_t n_want = 0;
    if (footprint(gp, s, want, &n_want) != FW_OK)
        return FW_ERROR;
    s->probe.cyc_prep += fw_cycles(gp) - c0;
    uint32_t frame = (uint32_t)s->frame;
    /* Requests: via the renderer's driver GP when the PPs shade this frame
     * (its READ_BS then follows its EXEC in the same FIFO), else direct. */
    s->bricks_pending = (int)n_want * ((c->lighting != VR_LIGHT_DIFFUSE && c->split == VR_SPLIT_GP) ? 2 : 1);
    if (uses_exec(s)) {
        uint32_t *list = fw_alloc(gp, (n_want + 1) * sizeof(uint32_t));
        if (!list)
            return FW_ERROR;
        for (int d = 0; d < s->n_gp && d < s->n_r; d++) {
            size_t k = 0;
            for (size_t i = 0; i < n_want; i++)
                if (driver_of(s, want[i] % (unsigned)s->n_r) == (unsigned)d)
                    list[k++] = want[i];
            if (k == 0)
                continue;
            if (d == s->g) {
                if (forward_requests(gp, s, list, k, (unsigned)s->g) != FW_OK)
                    return FW_ERROR;
            } else if (send_gp(gp, (unsigned)d, VR_MSG_REQUEST, (uint32_t)frame, 0, list,
                               k * sizeof(uint32_t)) != FW_OK) {
                return FW_ERROR;
            }
        }
        fw_free(gp, list);
    } else {
        for (size_t i = 0; i < n_want; i++)
            if (send_read(gp, s, (int)want[i], (unsigned)s->g) != FW_OK)
                return FW_ERROR;
    }
    fw_free(gp, want);
    s->probe.bricks_fetched += n_want;
    s->t_pass_req = fw_time_ps(gp);
    return start_cast_if_ready(gp, s);
}

/* ---- ray casting (raycast_trace on bricks) ------------------------------- */

typedef struct {
    uint64_t samples, skipped, trilerp, blend, oct_leaf, oct_up, skips, composites;
} cast_counts_t;

static inline void fetch4(const vr_state_t *s, int n, int x, int y, int z, float *out)
{
    const vr_level_geom_t *g = &s->geom[n];
    int bx = x / g->bx, by = y / g->by, bz = z / g->bz;
    const uint32_t *b = s->cache[s->brick_base[n] + (bz * g->gy + by) * g->gx + bx];
    if (!b) {
        out[0] = out[1] = out[2] = out[3] = 0.0f;
        return;
    }
    uint32_t w = b[((z - bz * g->bz) * g->by + (y - by * g->by)) * g->bx + (x - bx * g->bx)];
    out[0] = s->u8_to_f[w & 255u];
    out[1] = s->u8_to_f[(w >> 8) & 255u];
    out[2] = s->u8_to_f[(w >> 16) & 255u];
    out[3] = s->u8_to_f[w >> 24];
}

/* mip3d_trilerp for 4 components (render/mip3d.h). */
static inline void trilerp(const vr_state_t *s, int n, float x, float y, float z, float *out)
{
    const vr_level_geom_t *L = &s->geom[n];
    float fx = floorf(x), fy = floorf(y), fz = floorf(z);
    float wx = x - fx, wy = y - fy, wz = z - fz;
    int x0 = (int)fx, y0 = (int)fy, z0 = (int)fz;
    int x1 = x0 + 1, y1 = y0 + 1, z1 = z0 + 1;
    x0 = x0 < 0 ? 0 : (x0 >= L->nx ? L->nx - 1 : x0);
    x1 = x1 < 0 ? 0 : (x1 >= L->nx ? L->nx - 1 : x1);
    y0 = y0 < 0 ? 0 : (y0 >= L->ny ? L->ny - 1 : y0);
    y1 = y1 < 0 ? 0 : (y1 >= L->ny ? L->ny - 1 : y1);
    z0 = z0 < 0 ? 0 : (z0 >= L->nz ? L->nz - 1 : z0);
    z1 = z1 < 0 ? 0 : (z1 >= L->nz ? L->nz - 1 : z1);
    float c000[4], c100[4], c010[4], c110[4], c001[4], c101[4], c011[4], c111[4];
    fetch4(s, n, x0, y0, z0, c000);
    fetch4(s, n, x1, y0, z0, c100);
    fetch4(s, n, x0, y1, z0, c010);
    fetch4(s, n, x1, y1, z0, c110);
    fetch4(s, n, x0, y0, z1, c001);
    fetch4(s, n, x1, y0, z1, c101);
    fetch4(s, n, x0, y1, z1, c011);
    fetch4(s, n, x1, y1, z1, c111);
    for (int k = 0; k < 4; k++) {
        float a = c000[k] + wx * (c100[k] - c000[k]);
        float b = c010[k] + wx * (c110[k] - c010[k]);
        float c = c001[k] + wx * (c101[k] - c001[k]);
        float d = c011[k] + wx * (c111[k] - c011[k]);
        float e = a + wy * (b - a);
        float f = c + wy * (d - c);
        out[k] = e + wz * (f - e);
    }
}

static inline void sample3d(const vr_state_t *s, float level3d, const float p[3], float *out,
                            cast_counts_t *cc)
{
    float top = (float)(s->cfg.levels - 1);
    if (level3d < 0.0f)
        level3d = 0.0f;
    if (level3d > top)
        level3d = top;
    int lo = (int)level3d;
    float t = level3d - (float)lo;
    trilerp(s, lo, vr_level_coord(p[0], lo), vr_level_coord(p[1], lo), vr_level_coord(p[2], lo), out);
    cc->trilerp++;
    if (t > 0.0f && lo + 1 < s->cfg.levels) {
        float hi[4];
        int n = lo + 1;
        trilerp(s, n, vr_level_coord(p[0], n), vr_level_coord(p[1], n), vr_level_coord(p[2], n), hi);
        cc->trilerp++;
        cc->blend++;
        for (int k = 0; k < 4; k++)
            out[k] += t * (hi[k] - out[k]);
    }
}

static inline float correct_alpha(const vr_state_t *s, int level2d, bool perspective, float spacing,
                                  float a)
{
    if (a >= 1.0f)
        return 1.0f;
    if (perspective || level2d >= VR_LUT_LEVELS)
        return 1.0f - powf(1.0f - a, spacing);
    float x = a * (float)VR_LUT_SIZE;
    int i = (int)x;
    if (i >= VR_LUT_SIZE)
        i = VR_LUT_SIZE - 1;
    float f = x - (float)i;
    const float *t = s->alpha_lut[level2d];
    return t[i] + f * (t[i + 1] - t[i]);
}

/* TraceRay (raycast_trace) for the samples with ray parameter t < t_stop.
 * A ray stopped at t_stop keeps its accumulated colour in rgb and its
 * opacity and position in *io_a, *io_t, *io_k, and resumes there (resume =
 * true) with exactly the same arithmetic.  Returns true when the ray is done. */
static bool trace(const vr_state_t *s, float px, float py, int level2d, float rgb[3],
                  cast_counts_t *cc, bool resume, float t_stop, float *io_a, float *io_t,
                  int32_t *io_k)
{
    const vr_config_t *c = &s->cfg;
    const vr_frame_t *f = &s->fr;
    float o[3], d[3], t0, t1;
    if (!resume)
        rgb[0] = rgb[1] = rgb[2] = 0.0f;
    vr_camera_ray(f, c->width, c->height, px, py, o, d);
    if (!vr_clip_box(o, d, f->box_hi, &t0, &t1))
        return true;
    float ov[3], dv[3];
    for (int k = 0; k < 3; k++) {
        ov[k] = o[k] * c->inv_spacing[k];
        dv[k] = d[k] * c->inv_spacing[k];
    }
    const bool perspective = f->projection != 0;
    const float step = c->sample_step > 0.0f ? c->sample_step : 1.0f;
    const float offset = log2f(step);
    const float base = step * (float)(1 << level2d);
    const float growth = 1.0f + base / f->eye_distance;
    const float top = (float)(c->levels - 1);
    float acc[3] = {0.0f, 0.0f, 0.0f}, acc_a = 0.0f;
    float comp[4];
    long k = 0;
    float t = t0;
    if (perspective && t < 1e-3f)
        t = 1e-3f;
    if (resume) {
        acc[0] = rgb[0];
        acc[1] = rgb[1];
        acc[2] = rgb[2];
        acc_a = *io_a;
        k = *io_k;
        t = perspective ? *io_t : t0 + (float)k * base;
    }
    float spacing = base;
    float level3d = log2f(spacing) - offset;
    level3d = level3d < 0.0f ? 0.0f : (level3d > top ? top : level3d);
    uint32_t ups = 0;
    while (t <= t1) {
        if (t >= t_stop) {
            /* end of this depth segment: park the ray */
            rgb[0] = acc[0];
            rgb[1] = acc[1];
            rgb[2] = acc[2];
            *io_a = acc_a;
            *io_k = (int32_t)k;
            *io_t = t;
            cc->oct_up += ups;
            return false;
        }
        if (perspective) {
            spacing = t * (growth - 1.0f);
            level3d = log2f(spacing) - offset;
            level3d = level3d < 0.0f ? 0.0f : (level3d > top ? top : level3d);
        }
        float p[3] = {ov[0] + t * dv[0], ov[1] + t * dv[1], ov[2] + t * dv[2]};
        if (c->use_octree) {
            float lo[3], hi[3];
            int n = (int)level3d;
            cc->oct_leaf++;
            if (oct_empty_node(s, n, level3d == (float)n, p, lo, hi, &ups) >= 0) {
                cc->skips++;
                float t_exit = INFINITY;
                for (int a = 0; a < 3; a++) {
                    float te = INFINITY;
                    if (dv[a] > 0.0f && isfinite(hi[a]))
                        te = (hi[a] - ov[a]) / dv[a];
                    else if (dv[a] < 0.0f && isfinite(lo[a]))
                        te = (lo[a] - ov[a]) / dv[a];
                    if (te < t_exit)
                        t_exit = te;
                }
                if (!(t_exit <= t1))
                    break;
                t_exit -= 1e-3f;
                if (perspective) {
                    float t_level = exp2f((float)(n + 1) + offset) / (growth - 1.0f);
                    if (n + 1 <= (int)top && t_level < t_exit)
                        t_exit = t_level;
                    do {
                        t *= growth;
                        cc->skipped++;
                    } while (t < t_exit && t <= t1);
                } else {
                    long k_new = (long)ceilf((t_exit - t0) / base);
                    if (k_new <= k)
                        k_new = k + 1;
                    cc->skipped += (uint64_t)(k_new - k);
                    k = k_new;
                    t = t0 + (float)k * base;
                }
                continue;
            }
        }
        sample3d(s, level3d, p, comp, cc);
        cc->samples++;
        float col[3] = {comp[0], comp[1], comp[2]};
        float a = comp[3];
        if (a > 0.0f) {
            if (spacing != 1.0f) {
                float ac = correct_alpha(s, level2d, perspective, spacing, a);
                float scale = ac / a;
                col[0] *= scale;
                col[1] *= scale;
                col[2] *= scale;
                a = ac;
            }
            float tt = 1.0f - acc_a;
            acc[0] += tt * col[0];
            acc[1] += tt * col[1];
            acc[2] += tt * col[2];
            acc_a += tt * a;
            cc->composites++;
            if (acc_a >= c->early_termination)
                break;
        }
        if (perspective) {
            t *= growth;
        } else {
            k++;
            t = t0 + (float)k * base;
        }
    }
    cc->oct_up += ups;
    rgb[0] = acc[0];
    rgb[1] = acc[1];
    rgb[2] = acc[2];
    return true;
}

static fw_status_t reconstruct_if_ready(gp_t *gp, vr_state_t *s);

static fw_status_t cast_all(gp_t *gp, vr_state_t *s)
{
    uint64_t c0 = fw_cycles(gp);
    cast_counts_t cc;
    memset(&cc, 0, sizeof cc);
    uint64_t rays = 0, calls = 0;
    float px0, px1, tseg[2];
    pass_range(s, s->pass, &px0, &px1);
    seg_range(s, s->pass, &tseg[0], &tseg[1]);
    for (int m = 0; m < s->levels2d; m++) {
        for (int j = s->jlo[m]; j <= s->jhi[m]; j++) {
            size_t row = (size_t)(j - s->jlo[m]) * s->tw[m];
            const uint8_t *nd = s->need[m] + row;
            uint8_t *cf = s->castf[m] + row, *rsx = s->ray_state[m] + row;
            float *tx = s->texel[m] + row * 3;
            for (int i = 0; i < s->tw[m]; i++) {
                float px = (float)(i << m) + 0.5f;
                if (!nd[i] || cf[i] || rsx[i] == 2 || px < px0 || px >= px1)
                    continue;
                bool resume = rsx[i] == 1;
                if (!resume)
                    rays++;
                calls++;
                bool done = trace(s, px, (float)(j << m) + 0.5f, m, tx + 3 * i, &cc, resume, tseg[1],
                                  s->ray_a[m] + row + i, s->ray_t[m] + row + i, s->ray_k[m] + row + i);
                if (done) {
                    rsx[i] = 2;
                    cf[i] = 1;
                } else {
                    rsx[i] = 1;
                }
            }
        }
    }
    fw_ops_t ops = {0};
    vr_cost_add(&ops, &VR_COST_RAY, calls);
    vr_cost_add(&ops, &VR_COST_SAMPLE, cc.samples + cc.skips);
    vr_cost_add(&ops, &VR_COST_TRILERP, cc.trilerp);
    vr_cost_add(&ops, &VR_COST_LEVEL_BLEND, cc.blend);
    vr_cost_add(&ops, &VR_COST_OCT_LEAF, cc.oct_leaf);
    vr_cost_add(&ops, &VR_COST_OCT_UP, cc.oct_up);
    vr_cost_add(&ops, &VR_COST_SKIP, cc.skips);
    vr_cost_add(&ops, &VR_COST_COMPOSITE, cc.composites);
    fw_charge(gp, &ops);
    s->probe.cyc_cast += fw_cycles(gp) - c0;
    s->probe.rays += rays;
    s->probe.samples += cc.samples;
    s->probe.skipped += cc.skipped;
    s->probe.cast_ps += fw_time_ps(gp) - s->probe.t_data_done;
    s->probe.passes = (uint64_t)s->n_passes;
    if (s->pass + 1 < s->n_passes) {
        /* Drop this pass's bricks and fetch the next column range's. */
        for (int i = 0; i < s->n_bricks; i++)
            if (s->cache[i]) {
                fw_free(gp, s->cache[i]);
                s->cache[i] = NULL;
            }
        s->pass++;
        return request_pass(gp, s);
    }
    s->cast_done = true;
    s->probe.t_cast_done = fw_time_ps(gp);
    /* Our first texel row of each level goes to the GP above. */
    if (s->g > 0) {
        size_t floats = 0;
        for (int m = 0; m < s->levels2d; m++)
            floats += (size_t)s->tw[m] * 3;
        float *buf = fw_alloc(gp, floats * sizeof(float));
        if (!buf)
            return FW_ERROR;
        size_t off = 0;
        for (int m = 0; m < s->levels2d; m++) {
            memcpy(buf + off, s->texel[m], (size_t)s->tw[m] * 3 * sizeof(float));
            off += (size_t)s->tw[m] * 3;
        }
        fw_ops_t o2 = {0};
        o2.loads = o2.stores = floats;
        fw_charge(gp, &o2);
        fw_status_t rc = send_gp(gp, (unsigned)(s->g - 1), VR_MSG_BOUNDARY, (uint32_t)s->frame, 0,
                                 buf, floats * sizeof(float));
        fw_free(gp, buf);
        if (rc != FW_OK)
            return rc;
    }
    bool last = s->g + 1 >= s->n_gp || s->fr.band_y0[s->g + 2] == s->fr.band_y0[s->g + 1] ||
                s->y1 >= s->cfg.height;
    if (last)
        s->boundary_ok = true;
    return reconstruct_if_ready(gp, s);
}

static fw_status_t start_cast_if_ready(gp_t *gp, vr_state_t *s)
{
    if (s->bricks_pending > 0 || s->cast_done)
        return FW_OK;
    s->probe.t_data_done = fw_time_ps(gp);
    s->probe.wait_ps += s->probe.t_data_done - s->t_pass_req;
    return cast_all(gp, s);
}

static void bilerp(const vr_state_t *s, int l, int x, int y, float rgb[3])
{
    int i = x >> l, j = y >> l;
    float sc = (float)(1 << l);
    float u = (float)(x - (i << l)) / sc, v = (float)(y - (j << l)) / sc;
    int w = s->tw[l];
    const float *c00 = s->texel[l] + ((size_t)(j - s->jlo[l]) * w + i) * 3;
    const float *c10 = u > 0.0f ? c00 + 3 : c00;
    const float *c01 = v > 0.0f ? c00 + (size_t)w * 3 : c00;
    const float *c11 = (u > 0.0f && v > 0.0f) ? c00 + ((size_t)w + 1) * 3 : (u > 0.0f ? c10 : c01);
    for (int k = 0; k < 3; k++) {
        float a = c00[k] + u * (c10[k] - c00[k]);
        float b = c01[k] + u * (c11[k] - c01[k]);
        rgb[k] = a + v * (b - a);
    }
}

static inline uint8_t to_u8(float v)
{
    if (!(v > 0.0f))
        return 0;
    if (v >= 1.0f)
        return 255;
    return (uint8_t)(v * 255.0f + 0.5f);
}

static fw_status_t reconstruct_if_ready(gp_t *gp, vr_state_t *s)
{
    if (!s->cast_done || !s->boundary_ok || s->probe.frame_done)
        return FW_OK;
    s->probe.t_boundary = fw_time_ps(gp);
    uint64_t c0 = fw_cycles(gp);
    const vr_config_t *c = &s->cfg;
    int W = c->width, rows = s->y1 - s->y0;
    /* Sections of at most 128 columns (one renderer region wide). */
    for (int sx = 0; sx < W; sx += 128) {
        int sw = W - sx < 128 ? W - sx : 128;
        size_t bytes = (size_t)sw * rows * 3;
        uint8_t *px = fw_alloc(gp, bytes);
        if (!px)
            return FW_ERROR;
        for (int y = s->y0; y < s->y1; y++) {
            const float *lrow = s->level + (size_t)(y - s->ly0) * W;
            for (int x = sx; x < sx + sw; x++) {
                float level = lrow[x], rgb[3];
                int lo = (int)level;
                if (lo >= s->levels2d)
                    lo = s->levels2d - 1;
                bilerp(s, lo, x, y, rgb);
                float t = level - (float)lo;
                if (t > 0.0f && lo + 1 < s->levels2d) {
                    float hi[3];
                    bilerp(s, lo + 1, x, y, hi);
                    for (int k = 0; k < 3; k++)
                        rgb[k] += t * (hi[k] - rgb[k]);
                }
                uint8_t *o = px + ((size_t)(y - s->y0) * sw + (x - sx)) * 3;
                o[0] = to_u8(rgb[0]);
                o[1] = to_u8(rgb[1]);
                o[2] = to_u8(rgb[2]);
            }
        }
        fw_ops_t ops = {0};
        vr_cost_add(&ops, &VR_COST_PIXEL, (uint64_t)sw * rows);
        fw_charge(gp, &ops);
        uint32_t args[RING_MSG_ARGS] = {(uint32_t)(c->fb_x0 + sx), (uint32_t)(c->fb_y0 + s->y0),
                                        (uint32_t)sw, (uint32_t)rows, 0, 0};
        fw_status_t rc = fw_send(gp, ring_addr(RING_NODE_FB, 0), RING_MSG_FB_PIXELS, args, px, bytes);
        fw_free(gp, px);
        if (rc != FW_OK)
            return rc;
        s->probe.fb_bytes += bytes;
    }
    s->probe.cyc_pixels += fw_cycles(gp) - c0;
    s->probe.t_done = fw_time_ps(gp);
    s->probe.frame_done = 1;
    /* Free the frame's brick cache now (memory is per frame); keep the 2D
     * mip map when the host runs a progressive sequence. */
    int all0 = 1;
    for (int y = s->y0; y < s->y1 && all0; y++)
        for (int x = 0; x < W; x++)
            if (s->level[(size_t)(y - s->ly0) * W + x] > 0.0f) {
                all0 = 0;
                break;
            }
    s->probe.all_level0 = all0;
    frame_free(gp, s, (s->fr.progressive_keep & 1) != 0);
    return FW_OK;
}

static fw_status_t on_data(gp_t *gp, vr_state_t *s, const ring_msg_t *m)
{
    uint32_t tag = m->args[0];
    int id = (int)(tag / 2u), which = (int)(tag & 1u);
    if (id >= s->n_bricks || m->payload_bytes != VR_BRICK_VOXELS * 4u)
        return fw_fail(gp, "vr: unexpected data message (tag %u, %zu bytes)", tag, m->payload_bytes);
    uint64_t c0 = fw_cycles(gp);
    uint32_t *dst = fw_alloc(gp, VR_BRICK_VOXELS * 4u);
    if (!dst)
        return fw_fail(gp, "vr: GP %d local memory (%llu bytes) cannot hold brick %d of this "
                           "frame's footprint: partition does not fit",
                       s->g, (unsigned long long)fw_machine_info(gp)->local_mem_bytes, id);
    memcpy(dst, m->payload, VR_BRICK_VOXELS * 4u);
    /* The ring port deposits the brick in local memory over the i860's
     * external bus (DMA-like, [I]); the GP pays the bus time, not a copy loop. */
    fw_ops_t ops = {0};
    ops.ext_bytes = VR_BRICK_VOXELS * 4u;
    ops.int_ops = 8;
    fw_charge(gp, &ops);
    s->probe.cyc_unpack += fw_cycles(gp) - c0;
    s->probe.bytes_fetched += m->payload_bytes;
    bool gp_shade = s->cfg.lighting != VR_LIGHT_DIFFUSE && s->cfg.split == VR_SPLIT_GP;
    if (!gp_shade) {
        s->cache[id] = dst;
    } else {
        if (which == 0)
            s->cache[id] = dst;
        else
            s->cache_n[id] = dst;
        if (s->cache[id] && s->cache_n[id]) {
            /* Viewpoint-dependent shading on the GP: same integer function
             * as the PP stream (vr_shade_fixed.h). */
            uint64_t c1 = fw_cycles(gp);
            uint32_t *a = s->cache[id];
            const uint32_t *nb = s->cache_n[id];
            for (unsigned i = 0; i < VR_BRICK_VOXELS; i++)
                a[i] = vr_shade_voxel(&s->shade_consts, a[i], nb[i]);
            fw_ops_t o2 = {0};
            vr_cost_add(&o2, &VR_COST_SHADE_VOXEL, VR_BRICK_VOXELS);
            fw_charge(gp, &o2);
            fw_free(gp, s->cache_n[id]);
            s->cache_n[id] = NULL;
            s->probe.cyc_shade += fw_cycles(gp) - c1;
        }
    }
    s->bricks_pending--;
    return start_cast_if_ready(gp, s);
}

static fw_status_t on_boundary(gp_t *gp, vr_state_t *s, const ring_msg_t *m)
{
    size_t floats = 0;
    for (int mm = 0; mm < s->levels2d; mm++)
        floats += (size_t)s->tw[mm] * 3;
    if (m->payload_bytes != floats * sizeof(float) || !s->texel[0])
        return fw_fail(gp, "vr: boundary message of %zu bytes", m->payload_bytes);
    const float *src = m->payload;
    size_t off = 0;
    for (int mm = 0; mm < s->levels2d; mm++) {
        int rows = s->jhi[mm] - s->jlo[mm] + 1;
        memcpy(s->texel[mm] + (size_t)rows * s->tw[mm] * 3, src + off, (size_t)s->tw[mm] * 3 * sizeof(float));
        off += (size_t)s->tw[mm] * 3;
    }
    fw_ops_t ops = {0};
    ops.loads = ops.stores = floats;
    fw_charge(gp, &ops);
    s->boundary_ok = true;
    return reconstruct_if_ready(gp, s);
}

static fw_status_t vr_message(gp_t *gp, const ring_msg_t *m)
{
    vr_state_t *s = fw_state(gp);
    if (!s)
        return fw_fail(gp, "vr: message before start");
    switch (m->kind) {
    case RING_MSG_FRAME_START:
        return vr_frame_start(gp, s, m->args[0]);
    case RING_MSG_RENDERER_DATA:
        return on_data(gp, s, m);
    case RING_MSG_GP_USER:
        switch (m->args[0]) {
        case VR_MSG_FRAME_PARAMS:
            if (m->payload_bytes != sizeof(vr_frame_t))
                return fw_fail(gp, "vr: frame parameters of %zu bytes", m->payload_bytes);
            memcpy(&s->fr, m->payload, sizeof s->fr);
            s->exec_sent = false;
            return FW_OK;
        case VR_MSG_LEVELK:
            return on_levelk(gp, s, m);
        case VR_MSG_SLAB:
            return on_slab(gp, s, m);
        case VR_MSG_OCC:
            return on_occ(gp, s, m);
        case VR_MSG_REQUEST: {
            const uint32_t *ids = m->payload;
            size_t n = m->payload_bytes / 4;
            unsigned req = m->src.index;
            if (s->exec_sent)
                return forward_requests(gp, s, ids, n, req);
            /* Keep it until our EXEC is out (ordering in the FIFO to the renderer). */
            size_t need = s->pending_req_n + n + 2;
            if (need > s->pending_req_cap) {
                size_t cap = need * 2;
                uint32_t *nb = fw_alloc(gp, cap * 4);
                if (!nb)
                    return FW_ERROR;
                if (s->pending_req) {
                    memcpy(nb, s->pending_req, s->pending_req_n * 4);
                    fw_free(gp, s->pending_req);
                }
                s->pending_req = nb;
                s->pending_req_cap = cap;
            }
            s->pending_req[s->pending_req_n++] = req;
            s->pending_req[s->pending_req_n++] = (uint32_t)n;
            memcpy(s->pending_req + s->pending_req_n, ids, n * 4);
            s->pending_req_n += n;
            return FW_OK;
        }
        case VR_MSG_BOUNDARY:
            return on_boundary(gp, s, m);
        default:
            return fw_fail(gp, "vr: unknown GP message %u", m->args[0]);
        }
    default:
        return fw_fail(gp, "vr: unexpected message kind %s", ring_msg_kind_name(m->kind));
    }
}

const fw_program_t vr_program = {
    .name = "gaze-volume",
    .image_bytes = 65536,         /* [U] stand-in size of the i860 binary */
    .on_start = vr_start,
    .on_message = vr_message,
};
