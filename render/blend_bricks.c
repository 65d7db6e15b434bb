/* blend_bricks.c: MIP and DEMIP of parallel rays in brick order (see
 * blend_bricks.h for why the result is the reference's). */
#include "blend_bricks.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "blend_fast.h"
#include "gaze2d.h"
#include "parallel.h"

bool blend_bricks_apply(const blend_ctx_t *c)
{
    blend_mode_t m = c->frame.mode;
    return c->skipping && c->camera->projection == PROJECTION_PARALLEL &&
           (m == BLEND_MIP || m == BLEND_DEMIP) && c->pyr->level[0].brick_order;
}

/* ---- binning ---- */

/* Texel coordinate (i or j) of level-0 position p as an affine map: the
 * camera's image axis through the pixel size, then the level's texel
 * spacing (mip2d_texel_point: px = i 2^l + 0.5). */
typedef struct {
    float a[3], a0;
} texel_axis_t;

static texel_axis_t texel_axis(const camera_t *cam, const float axis[3], int image_side,
                               int level2d)
{
    texel_axis_t t;
    float inv = 1.0f / (cam->pixel_size * (float)(1 << level2d)), dot = 0.0f;
    for (int a = 0; a < 3; a++) {
        t.a[a] = axis[a] / cam->inv_spacing[a] * inv;
        dot += cam->centre[a] * axis[a];
    }
    t.a0 = (0.5f * (float)image_side - 0.5f - dot / cam->pixel_size) / (float)(1 << level2d);
    return t;
}

static void texel_range(const texel_axis_t *t, blend_v4f lo, blend_v4f hi, float *mn, float *mx)
{
    *mn = *mx = t->a0;
    for (int a = 0; a < 3; a++) {
        float u = t->a[a] * lo[a], v = t->a[a] * hi[a];
        *mn += u < v ? u : v;
        *mx += u < v ? v : u;
    }
}

/* The brick of rank `rank` in level L's order (node height h): its cells,
 * its position box (the cells' q ranges [c, c + 1) mapped back by
 * mip3d_level_coord, the clamped edge cells reaching one voxel past the
 * volume box) and material. */
static void brick_describe(const blend_ctx_t *c, const scalar_level_t *L, int n, size_t rank,
                           blend_brick_t *b)
{
    const int h = L->brick_height, side = 1 << h;
    const int dims[3] = {L->nx, L->ny, L->nz};
    const int dims0[3] = {c->pyr->level[0].nx, c->pyr->level[0].ny, c->pyr->level[0].nz};
    const float scale = (float)(1 << n);
    const uint16_t *coord = L->brick_coord[rank];
    for (int a = 0; a < 3; a++) {
        b->c0[a] = coord[a] * side;
        b->c1[a] = b->c0[a] + side < dims[a] ? b->c0[a] + side : dims[a];
        b->lo[a] = b->c0[a] == 0 ? -1.0f : ((float)b->c0[a] + 0.5f) * scale - 0.5f - BLEND_BOX_SLACK;
        b->hi[a] = b->c1[a] == dims[a] ? (float)dims0[a]
                                        : ((float)b->c1[a] + 0.5f) * scale - 0.5f + BLEND_BOX_SLACK;
    }
    b->lo[3] = b->hi[3] = 0.0f;
    b->c0[3] = 0;
    b->c1[3] = 1;                 /* fast_cell's lane 3 is cell 0 */
    b->material = blend_material(&c->frame.window, L->node_max[h][L->brick_order[rank]]);
}

static int clamp_int(int v, int lo, int hi)
{
    return v < lo ? lo : (v > hi ? hi : v);
}

static float clamp_float(float v, float lo, float hi)
{
    return v < lo ? lo : (v > hi ? hi : v);
}

/* The (widened) box's texel footprint, widened again by FOOTPRINT_SLACK
 * texels for the rounding of the projection; false when it misses the
 * grid. */
#define FOOTPRINT_SLACK 0.05f
static bool brick_footprint(const texel_axis_t *ti, const texel_axis_t *tj, int tex_w, int tex_h,
                            blend_brick_t *b)
{
    float i0, i1, j0, j1;
    texel_range(ti, b->lo, b->hi, &i0, &i1);
    texel_range(tj, b->lo, b->hi, &j0, &j1);
    if (!(i1 >= -1.0f && j1 >= -1.0f && i0 <= (float)tex_w && j0 <= (float)tex_h))
        return false;
    /* Clamped first, so that the conversions stay in range (the floors of
     * numbers in [-1, size]: mip3d_floor_int, no library call). */
    float lo_i = clamp_float(i0 - FOOTPRINT_SLACK, -1.0f, (float)tex_w);
    float lo_j = clamp_float(j0 - FOOTPRINT_SLACK, -1.0f, (float)tex_h);
    float hi_i = clamp_float(i1 + FOOTPRINT_SLACK, -1.0f, (float)tex_w);
    float hi_j = clamp_float(j1 + FOOTPRINT_SLACK, -1.0f, (float)tex_h);
    b->rect[0] = clamp_int(-mip3d_floor_int(-lo_i), 0, tex_w - 1);
    b->rect[1] = clamp_int(-mip3d_floor_int(-lo_j), 0, tex_h - 1);
    b->rect[2] = clamp_int(mip3d_floor_int(hi_i), 0, tex_w - 1);
    b->rect[3] = clamp_int(mip3d_floor_int(hi_j), 0, tex_h - 1);
    return true;
}

void blend_bins_free(blend_bins_t *b)
{
    free(b->brick);
    free(b->start);
    free(b->entry);
    free(b->next);
    free(b->kept);
    memset(b, 0, sizeof *b);
}

/* Makes *p hold at least n elements of `size` bytes (kept if it does). */
static bool reserve(void **p, size_t *cap, size_t n, size_t size)
{
    if (n <= *cap)
        return true;
    void *q = realloc(*p, n * size);
    if (!q)
        return false;
    *p = q;
    *cap = n;
    return true;
}

/* Runs body with `tile` set to every active tile the brick's footprint covers. */
#define FOR_TILES(bins, br, active, tile, body)                                      \
    for (int ty = (br)->rect[1] / BLEND_TILE; ty <= (br)->rect[3] / BLEND_TILE; ty++) \
        for (int tx = (br)->rect[0] / BLEND_TILE; tx <= (br)->rect[2] / BLEND_TILE; tx++) { \
            int tile = ty * (bins)->tiles_x + tx;                                     \
            if (!(active) || (active)[tile])                                          \
                body;                                                                 \
        }

/* Runs body with i set to every kept brick, in brick order: chunk k's
 * bricks sit at [k BINS_CHUNK, k BINS_CHUNK + kept[k]). */
#define FOR_KEPT(bins, i, body)                                                      \
    for (size_t k_ = 0; k_ < (bins)->chunks; k_++)                                    \
        for (size_t i = k_ * BINS_CHUNK; i < k_ * BINS_CHUNK + (bins)->kept[k_]; i++) \
            body

static pp5_status_t bins_fill(blend_bins_t *b, const uint8_t *active)
{
    size_t tiles = (size_t)b->tiles_x * b->tiles_y, total = 0, cap = b->tile_cap;
    if (!reserve((void **)&b->start, &cap, tiles + 1, sizeof *b->start) ||
        !reserve((void **)&b->next, &b->tile_cap, tiles + 1, sizeof *b->next))
        return pp5_fail(PP5_E_NOMEM, "render: out of memory for the brick bins");
    memset(b->start, 0, (tiles + 1) * sizeof *b->start);
    FOR_KEPT(b, i, FOR_TILES(b, &b->brick[i], active, t, b->start[t + 1]++));
    for (size_t t = 0; t < tiles; t++) {
        total += b->start[t + 1];
        PP5_ASSERT(total <= UINT32_MAX, "brick bins overflow");
        b->start[t + 1] = (uint32_t)total;
    }
    if (!reserve((void **)&b->entry, &b->entry_cap, total ? total : 1, sizeof *b->entry))
        return pp5_fail(PP5_E_NOMEM, "render: out of memory for the brick bins");
    memcpy(b->next, b->start, tiles * sizeof *b->next);
    FOR_KEPT(b, i, FOR_TILES(b, &b->brick[i], active, t, b->entry[b->next[t]++] = (uint32_t)i));
    return PP5_OK;
}

/* A quick test against the active tiles' bounding rectangle, before a
 * brick is described: its centre's texel coordinates (an affine function
 * of its node coordinates) and a radius covering its whole box, edge
 * bricks' extensions included.  A gaze-directed frame casts level 0 only
 * in the sweet spot, so most of the finest level's bricks stop here. */
typedef struct {
    float ci[4], cj[4];           /* centre = c[0..2] . node coords + c[3] */
    float ri, rj;                 /* radius in texels */
    float lo_i, hi_i, lo_j, hi_j; /* the active rectangle, widened by a texel */
} brick_cull_t;

static void bins_cull_init(const blend_bins_t *b, const texel_axis_t *ti, const texel_axis_t *tj,
                           const scalar_level_t *L, int n, const uint8_t *active,
                           brick_cull_t *k)
{
    const float scale = (float)(1 << n), side = (float)(1 << L->brick_height) * scale;
    const float half = 0.5f * side + scale + 1.0f;
    int t0x = b->tiles_x, t1x = -1, t0y = b->tiles_y, t1y = -1;
    for (int ty = 0; ty < b->tiles_y; ty++)
        for (int tx = 0; tx < b->tiles_x; tx++)
            if (!active || active[ty * b->tiles_x + tx]) {
                t0x = tx < t0x ? tx : t0x;
                t1x = tx > t1x ? tx : t1x;
                t0y = ty < t0y ? ty : t0y;
                t1y = ty > t1y ? ty : t1y;
            }
    k->lo_i = (float)(t0x * BLEND_TILE) - 1.0f;
    k->hi_i = (float)((t1x + 1) * BLEND_TILE) + 1.0f;
    k->lo_j = (float)(t0y * BLEND_TILE) - 1.0f;
    k->hi_j = (float)((t1y + 1) * BLEND_TILE) + 1.0f;
    k->ri = k->rj = 0.0f;
    k->ci[3] = ti->a0;
    k->cj[3] = tj->a0;
    for (int a = 0; a < 3; a++) {
        /* Node coordinate x: the box's centre is x side + side / 2 +
         * scale / 2 - 1/2 in level-0 units (brick_describe's box). */
        k->ci[a] = ti->a[a] * side;
        k->cj[a] = tj->a[a] * side;
        k->ci[3] += ti->a[a] * (0.5f * side + 0.5f * scale - 0.5f);
        k->cj[3] += tj->a[a] * (0.5f * side + 0.5f * scale - 0.5f);
        k->ri += fabsf(ti->a[a]) * half;
        k->rj += fabsf(tj->a[a]) * half;
    }
}

static bool brick_culled(const brick_cull_t *k, const uint16_t coord[3])
{
    float x = coord[0], y = coord[1], z = coord[2];
    float ci = k->ci[0] * x + k->ci[1] * y + k->ci[2] * z + k->ci[3];
    float cj = k->cj[0] * x + k->cj[1] * y + k->cj[2] * z + k->cj[3];
    return ci + k->ri < k->lo_i || ci - k->ri > k->hi_i || cj + k->rj < k->lo_j ||
           cj - k->rj > k->hi_j;
}

/* What the chunks of one level's bricks share while they are described. */
typedef struct {
    blend_bins_t *b;
    const blend_ctx_t *c;
    const scalar_level_t *L;
    texel_axis_t ti, tj;
    brick_cull_t cull;
} bins_job_t;

/* Describes chunk k's bricks that may change a ray of an active tile into
 * the chunk's own stretch of b->brick.  The order is by bound, so the first
 * brick of material 0 ends the chunk (and every later chunk at its start). */
static void bins_describe_chunk(void *ctx, int k, int thread)
{
    (void)thread;
    const bins_job_t *job = ctx;
    blend_bins_t *b = job->b;
    const scalar_level_t *L = job->L;
    const int h = L->brick_height;
    size_t i0 = (size_t)k * BINS_CHUNK, i1 = i0 + BINS_CHUNK, kept = 0;
    i1 = i1 < L->brick_count ? i1 : L->brick_count;
    for (size_t i = i0; i < i1; i++) {
        if (!(blend_material(&job->c->frame.window, L->node_max[h][L->brick_order[i]]) > 0.0f))
            break;
        if (brick_culled(&job->cull, L->brick_coord[i]))
            continue;
        blend_brick_t *br = &b->brick[i0 + kept];
        brick_describe(job->c, L, b->level3d, i, br);
        if (brick_footprint(&job->ti, &job->tj, b->tex_w, b->tex_h, br))
            kept++;
    }
    b->kept[k] = (uint32_t)kept;
}

pp5_status_t blend_bins_build(blend_bins_t *b, const blend_ctx_t *c, int level2d, int tex_w,
                              int tex_h, const uint8_t *active, int threads)
{
    const camera_t *cam = c->camera;
    b->bricks = 0;
    b->level2d = level2d;
    b->level3d = (int)blend_level3d(c, level2d);
    b->tex_w = tex_w;
    b->tex_h = tex_h;
    b->tiles_x = (tex_w + BLEND_TILE - 1) / BLEND_TILE;
    b->tiles_y = (tex_h + BLEND_TILE - 1) / BLEND_TILE;
    const scalar_level_t *L = &c->pyr->level[b->level3d];
    bins_job_t job = {.b = b, .c = c, .L = L,
                      .ti = texel_axis(cam, cam->right, cam->width, level2d),
                      .tj = texel_axis(cam, cam->down, cam->height, level2d)};
    b->chunks = (L->brick_count + BINS_CHUNK - 1) / BINS_CHUNK;
    if (!reserve((void **)&b->brick, &b->brick_cap, L->brick_count ? L->brick_count : 1,
                 sizeof *b->brick) ||
        !reserve((void **)&b->kept, &b->kept_cap, b->chunks ? b->chunks : 1, sizeof *b->kept))
        return pp5_fail(PP5_E_NOMEM, "render: out of memory for the brick bins");
    bins_cull_init(b, &job.ti, &job.tj, L, b->level3d, active, &job.cull);
    /* Chunks of a fixed size, each writing only its own stretch and count:
     * the bins are the same for any number of threads. */
    pp5_status_t st = parallel_for(threads, (int)b->chunks, bins_describe_chunk, &job);
    if (st != PP5_OK)
        return st;
    for (size_t k = 0; k < b->chunks; k++)
        b->bricks += b->kept[k];
    return bins_fill(b, active);
}

/* ---- one tile ---- */

#define TILE_TEXELS (BLEND_TILE * BLEND_TILE)

typedef struct {
    blend_geom_t g;
    v4f ov;
    float m_max;
    long k_max;
    long drawn;
    float threshold;              /* DEMIP ray 2 */
    long stop, drawn2;
} tile_ray_t;

typedef struct {
    const blend_ctx_t *c;
    const blend_bins_t *b;
    fast_level_t lv;
    int x0, y0;                   /* the tile's first texel */
    int slot[TILE_TEXELS];        /* texel -> ray, -1 none */
    tile_ray_t *ray;
    v4f inv_dv;                   /* lanes 0-2: the level's 1 / dv (0 where flat) */
    v4i free_axes;                /* lanes a ray's parameter is not bounded by */
    v4f minus_inf, plus_inf;
    int flat;                     /* bit a: dv[a] == 0 */
} tile_t;

/* The run of positions [*k0, *k1] of the ray that may lie in the brick:
 * those whose parameter is inside the widened box's interval.  Axes the
 * rays run parallel to (flat) constrain nothing along the ray; the rays
 * outside the box on such an axis never reach the brick. */
static bool brick_run(const tile_t *t, const tile_ray_t *r, const blend_brick_t *b, long *k0,
                      long *k1)
{
    const fast_level_t *lv = &t->lv;
    if (t->flat) {
        for (int a = 0; a < 3; a++)
            if ((t->flat >> a & 1) && (r->ov[a] < b->lo[a] || r->ov[a] > b->hi[a]))
                return false;
    }
    v4f u = (b->lo - r->ov) * t->inv_dv, v = (b->hi - r->ov) * t->inv_dv;
    v4i lt = u < v;
    v4f near = (v4f)(((v4i)u & lt) | ((v4i)v & ~lt)), far = (v4f)(((v4i)v & lt) | ((v4i)u & ~lt));
    near = (v4f)(((v4i)near & ~t->free_axes) | ((v4i)t->minus_inf & t->free_axes));
    far = (v4f)(((v4i)far & ~t->free_axes) | ((v4i)t->plus_inf & t->free_axes));
    float t_in = near[0] > near[1] ? near[0] : near[1], t_out = far[0] < far[1] ? far[0] : far[1];
    t_in = near[2] > t_in ? near[2] : t_in;
    t_out = far[2] < t_out ? far[2] : t_out;
    if (!(t_in <= t_out))
        return false;
    double x0 = ((double)t_in - r->g.t0) * lv->inv_base, x1 = ((double)t_out - r->g.t0) * lv->inv_base;
    long last = r->g.positions - 1;
    if (!(x0 <= (double)last) || !(x1 >= 0.0))
        return false;             /* (also keeps the conversions in range) */
    *k0 = x0 <= 0.0 ? 0 : (long)x0 + ((double)(long)x0 < x0);    /* ceil */
    *k1 = x1 >= (double)last ? last : (long)x1;                  /* floor of x1 >= 0 */
    return *k0 <= *k1;
}

/* Position k of ray r, when its cell lies in the brick: the cell's bound
 * (as a material) and what is needed to draw it. */
typedef struct {
    v4f q;
    v4i fl;
    float bound;
} brick_pos_t;

static inline bool brick_position(const fast_level_t *lv, const tile_ray_t *r,
                                  const blend_brick_t *b, long k, brick_pos_t *p)
{
    v4i cv = fast_cell(lv, r->ov, r->g.t0 + (float)k * lv->base, &p->q, &p->fl);
    v4i in = (cv >= b->c0) & (cv < b->c1);
    if (!(in[0] & in[1] & in[2]))
        return false;
    const scalar_level_t *L = lv->L;
    size_t cell = ((size_t)cv[2] * (size_t)L->ny + (size_t)cv[1]) * (size_t)L->nx + (size_t)cv[0];
    p->bound = blend_material(&lv->f->window, L->node_max[0][cell]);
    return true;
}

/* The reference's sample at the position. */
static inline float brick_draw(const fast_level_t *lv, const brick_pos_t *p)
{
    float q[3] = {p->q[0], p->q[1], p->q[2]};
    int fl[3] = {p->fl[0], p->fl[1], p->fl[2]};
    return blend_material(&lv->f->window, scalar_trilerp(lv->L, q, fl));
}

/* Ray 2 over one brick that may hold its stop: front to back up to the stop. */
static void ray2_brick(const tile_t *t, tile_ray_t *r, const blend_brick_t *b)
{
    const fast_level_t *lv = &t->lv;
    long k0, k1;
    if (!brick_run(t, r, b, &k0, &k1))
        return;
    if (k1 >= r->stop)
        k1 = r->stop - 1;
    for (long k = k0; k <= k1; k++) {
        brick_pos_t p;
        if (!brick_position(lv, r, b, k, &p) || !demip_ray2_stops(p.bound, r->threshold))
            continue;
        float m = brick_draw(lv, &p);
        r->drawn2++;
        if (demip_ray2_stops(m, r->threshold)) {
            r->stop = k;
            return;
        }
    }
}

/* Runs body with r set to every ray of the tile inside the brick's footprint. */
#define FOR_RAYS_IN(t, br, r, body)                                                 \
    for (int y_ = (br)->rect[1] > (t)->y0 ? (br)->rect[1] : (t)->y0;               \
         y_ <= (br)->rect[3] && y_ < (t)->y0 + BLEND_TILE; y_++)                    \
        for (int x_ = (br)->rect[0] > (t)->x0 ? (br)->rect[0] : (t)->x0;           \
             x_ <= (br)->rect[2] && x_ < (t)->x0 + BLEND_TILE; x_++) {              \
            int s_ = (t)->slot[(y_ - (t)->y0) * BLEND_TILE + (x_ - (t)->x0)];       \
            if (s_ < 0)                                                             \
                continue;                                                           \
            tile_ray_t *r = &(t)->ray[s_];                                          \
            body;                                                                   \
        }

/* Ray 1 over one brick whose bound is at least the ray's maximum.  A
 * position whose cell bound can neither raise the maximum nor reach it in
 * front of k_max is passed. */
static void ray1_brick(const tile_t *t, tile_ray_t *r, const blend_brick_t *b)
{
    const fast_level_t *lv = &t->lv;
    long k0, k1;
    if (!brick_run(t, r, b, &k0, &k1))
        return;
    if (!(b->material > r->m_max) && k1 >= r->k_max)
        k1 = r->k_max - 1;        /* a tie counts only in front of k_max */
    for (long k = k0; k <= k1; k++) {
        brick_pos_t p;
        if (!brick_position(lv, r, b, k, &p) || p.bound < r->m_max ||
            (p.bound == r->m_max && k >= r->k_max))
            continue;
        float m = brick_draw(lv, &p);
        r->drawn++;
        if (m > r->m_max || (m == r->m_max && m > 0.0f && k < r->k_max)) {
            r->m_max = m;
            r->k_max = k;
            if (m >= 1.0f)
                return;           /* later positions of the brick cannot matter */
        }
    }
}

/* Lowest maximum of the tile's rays: a brick below it changes none. */
static float tile_lowest_max(const tile_t *t, int count)
{
    float lo = INFINITY;
    for (int i = 0; i < count; i++)
        if (t->ray[i].g.positions > 0 && t->ray[i].m_max < lo)
            lo = t->ray[i].m_max;
    return lo;
}

/* Pass 1 (ray 1): the tile's bricks, highest bound first. */
static void tile_pass_max(tile_t *t, int tile, int count)
{
    const blend_bins_t *b = t->b;
    float lowest = 0.0f;
    for (uint32_t e = b->start[tile]; e < b->start[tile + 1]; e++) {
        const blend_brick_t *br = &b->brick[b->entry[e]];
        if ((e - b->start[tile]) % 16 == 0)
            lowest = tile_lowest_max(t, count);
        if (br->material < lowest)
            return;               /* every later brick is as low */
        FOR_RAYS_IN(t, br, r, if (!(br->material < r->m_max)) ray1_brick(t, r, br));
    }
}

/* Pass 2 (DEMIP ray 2) visits the bricks front to back, so that a ray's
 * first candidate brick usually holds its stop.  A ray's parameter t is
 * its depth along the view axis less the same constant for every ray (the
 * origins lie in one plane), so a brick's nearest corner gives the least t
 * of any position in it.  Sorted by decreasing -t_near (ties by brick). */
static float brick_t_near(const camera_t *cam, const blend_brick_t *br)
{
    float t = -(cam->centre[0] * cam->forward[0] + cam->centre[1] * cam->forward[1] +
                cam->centre[2] * cam->forward[2]) + cam->radius + 1.0f;
    for (int a = 0; a < 3; a++) {
        float w = cam->forward[a] / cam->inv_spacing[a];   /* lo, hi: level-0 units */
        float u = w * br->lo[a], v = w * br->hi[a];
        t += u < v ? u : v;
    }
    return t;
}

/* Slack on depths: the corner formula and a position's t differ by
 * rounding only (the box is already widened); one step more for safety. */
static float depth_slack(const fast_level_t *lv)
{
    return lv->base + 0.01f;
}

/* Deepest stop of the tile's DEMIP rays (-INFINITY when none is left). */
static float tile_deepest_stop(const tile_t *t, int count)
{
    float hi = -INFINITY;
    for (int i = 0; i < count; i++) {
        const tile_ray_t *r = &t->ray[i];
        if (r->k_max >= 0) {
            float ts = r->g.t0 + (float)r->stop * t->lv.base;
            hi = ts > hi ? ts : hi;
        }
    }
    return hi;
}

static pp5_status_t tile_pass_ray2(tile_t *t, int tile, int count)
{
    const blend_bins_t *b = t->b;
    float lowest = INFINITY;
    for (int i = 0; i < count; i++) {
        tile_ray_t *r = &t->ray[i];
        r->threshold = demip_ray2_threshold(r->m_max, t->c->frame.eps);
        r->stop = r->k_max;
        if (r->k_max >= 0 && r->threshold < lowest)
            lowest = r->threshold;
    }
    uint32_t n = b->start[tile + 1] - b->start[tile], kept = 0;
    scalar_ranked_t *order = malloc((n ? n : 1) * sizeof *order);
    if (!order)
        return pp5_fail(PP5_E_NOMEM, "render: out of memory for a tile of rays");
    for (uint32_t e = b->start[tile]; e < b->start[tile + 1]; e++) {
        const blend_brick_t *br = &b->brick[b->entry[e]];
        if (br->material < lowest)
            break;                /* bound order: no later brick can stop a ray */
        order[kept++] = (scalar_ranked_t){-brick_t_near(t->c->camera, br), b->entry[e]};
    }
    qsort(order, kept, sizeof *order, scalar_ranked_cmp);
    float slack = depth_slack(&t->lv), deepest = INFINITY;
    for (uint32_t e = 0; e < kept; e++) {
        const blend_brick_t *br = &b->brick[order[e].index];
        float t_near = -order[e].key - slack;
        if (e % 16 == 0)
            deepest = tile_deepest_stop(t, count);
        if (t_near > deepest)
            break;                /* behind every ray's stop */
        FOR_RAYS_IN(t, br, r,
                    if (r->k_max >= 0 && demip_ray2_stops(br->material, r->threshold) &&
                        !(t_near > r->g.t0 + (float)r->stop * t->lv.base))
                        ray2_brick(t, r, br));
    }
    free(order);
    return PP5_OK;
}

/* What the tile's rays share: the level, and the slab test's lanes. */
static void tile_level_init(tile_t *t, const blend_geom_t *g)
{
    fast_level_init(t->c, g, &t->lv);
    t->flat = 0;
    for (int a = 0; a < 4; a++) {
        bool flat = a < 3 && t->lv.dv[a] == 0.0f;
        t->flat |= flat ? 1 << a : 0;
        t->inv_dv[a] = a < 3 ? t->lv.inv_dv[a] : 0.0f;
        t->free_axes[a] = flat || a == 3 ? -1 : 0;
        t->minus_inf[a] = -INFINITY;
        t->plus_inf[a] = INFINITY;
    }
}

/* Sets up the tile's rays; false when none hits the volume. */
static bool tile_begin(tile_t *t, int tile, int count, const int *ti, const int *tj)
{
    const blend_bins_t *b = t->b;
    t->x0 = tile % b->tiles_x * BLEND_TILE;
    t->y0 = tile / b->tiles_x * BLEND_TILE;
    for (int g = 0; g < TILE_TEXELS; g++)
        t->slot[g] = -1;
    bool have_level = false;
    for (int i = 0; i < count; i++) {
        tile_ray_t *r = &t->ray[i];
        memset(r, 0, sizeof *r);
        r->k_max = -1;
        float px, py;
        mip2d_texel_point(b->level2d, ti[i], tj[i], &px, &py);
        if (!blend_geom_begin(t->c, px, py, b->level2d, &r->g) || r->g.positions <= 0) {
            r->g.positions = 0;
            continue;
        }
        PP5_ASSERT(ti[i] >= t->x0 && ti[i] < t->x0 + BLEND_TILE && tj[i] >= t->y0 &&
                       tj[i] < t->y0 + BLEND_TILE, "texel outside its tile");
        if (!have_level)
            tile_level_init(t, &r->g);
        have_level = true;
        r->ov = (v4f){r->g.ov[0], r->g.ov[1], r->g.ov[2], 0.0f};
        t->slot[(tj[i] - t->y0) * BLEND_TILE + (ti[i] - t->x0)] = i;
    }
    return have_level;
}

/* Colour and counts of ray i after the passes. */
static void tile_finish(tile_t *t, int i, float rgb[3], raycast_counts_t *counts)
{
    tile_ray_t *r = &t->ray[i];
    counts->rays++;
    rgb[0] = rgb[1] = rgb[2] = 0.0f;
    if (r->g.positions <= 0)
        return;
    if (t->c->frame.mode == BLEND_MIP || r->k_max < 0) {
        counts->samples += (uint64_t)r->drawn;
        counts->samples_skipped += (uint64_t)(r->g.positions - r->drawn);
        rgb[0] = rgb[1] = rgb[2] = r->m_max;
        return;
    }
    fast_ray_t fr;
    memset(&fr, 0, sizeof fr);
    fr.lv = &t->lv;
    fr.g = r->g;
    fr.ov_v = r->ov;
    fr.mip.m_max = r->m_max;
    fr.mip.k_max = r->k_max;
    fast_demip_finish(&fr, r->stop, r->drawn + r->drawn2, r->g.positions, rgb, counts);
}

pp5_status_t blend_trace_tile(const blend_ctx_t *c, const blend_bins_t *b, int tile, int count,
                              const int *ti, const int *tj, float (*rgb)[3],
                              raycast_counts_t *counts)
{
    PP5_ASSERT(count <= TILE_TEXELS, "too many texels for one tile");
    /* One tile's state per thread, reused: a fresh allocation of this size
     * per tile would be fresh pages every time. */
    static _Thread_local tile_t tile_state;
    static _Thread_local tile_ray_t rays[TILE_TEXELS];
    tile_t *t = &tile_state;
    memset(t, 0, sizeof *t);
    t->c = c;
    t->b = b;
    t->ray = rays;
    pp5_status_t st = PP5_OK;
    if (tile_begin(t, tile, count, ti, tj)) {
        tile_pass_max(t, tile, count);
        if (c->frame.mode == BLEND_DEMIP)
            st = tile_pass_ray2(t, tile, count);
    }
    for (int i = 0; st == PP5_OK && i < count; i++)
        tile_finish(t, i, rgb[i], counts);
    return st;
}
