/* raycast_parallel.c: the fast tracer for parallel projection with octree
 * skipping.  It draws exactly the samples raycast_trace_reference draws (same
 * positions, same values, same order of floating-point operations); only the
 * way it finds them differs.
 *
 * Why this is exact: the reference samples position k (t = t0 + k * base on
 * the ray's lattice, inside its window [k_first, k_last]) exactly when the
 * grid cell containing it is occupied, because every sample in an empty cell
 * is zero (octree.h) and its jumps never pass an occupied cell.  Here each
 * position visited is tested with the same float expression for its cell, and
 * a jump over an empty node is accepted only after checking the last position
 * it passes: each cell coordinate of a position is a monotonic function of k
 * (every float operation in it is monotonic), so if the first and last
 * positions of a run lie in the node's box, all between do too. */
#include "raycast_internal.h"

#include <math.h>
#include <string.h>

/* Three axes side by side (lane 3 unused): each lane does exactly the
 * scalar operations (no fused multiply-add in ISO C mode). */
typedef float v4f __attribute__((vector_size(16)));
typedef int v4i __attribute__((vector_size(16)));

/* What all parallel rays of one 2D level share (the reference recomputes it
 * per ray, with the same expressions). */
typedef struct {
    const octree_grid_t *g;
    const octree_grid_t *blend;   /* level n's blend grid: the exact grid dilated by 2 */
    float dv[4], inv_dv[3], half[3];   /* dv[3] = 0 */
    float base, inv_base, level3d;
    float scale, inv_scale;       /* 2^n and 2^-n for level-n coordinates */
    int n, level2d, dims[3];
    bool exact;                   /* integer 3D level: samples read level n only */
    v4f dv_v, inv_dv_v;           /* dv, inv_dv as vectors (lane 3 = 0) */
    v4i dir_pos, dir_neg;         /* lanes moving up / down the axis (-1 = yes) */
    v4i dims_v, top_v;            /* dims and dims - 1 */
} par_level_t;

typedef struct {
    float ov[4];                  /* level-0 voxel coordinates of the origin; [3] = 0 */
    float t0, t1_volume;
    long k, k_last;               /* next position; last position of the window */
    long k_end;                   /* positions visited by a ray without skipping */
    float acc[3], acc_a;
    uint64_t n_samples;
} par_ray_t;

/* Minimum and maximum of two numbers known not to be NaN (fminf and fmaxf
 * are library calls at -O2). */
static inline float min_f(float a, float b)
{
    return b < a ? b : a;
}

static inline float max_f(float a, float b)
{
    return b > a ? b : a;
}

static void level_setup(const raycast_ctx_t *r, int level2d, par_level_t *L)
{
    const camera_t *cam = r->camera;
    L->dv[3] = 0.0f;
    for (int a = 0; a < 3; a++) {
        L->dv[a] = cam->forward[a] * cam->inv_spacing[a];
        L->inv_dv[a] = L->dv[a] != 0.0f ? 1.0f / L->dv[a] : 0.0f;
    }
    float view[3] = {-cam->forward[0], -cam->forward[1], -cam->forward[2]};
    shade_half_vector(r->light_obj, view, L->half);
    L->level2d = level2d;
    L->base = r->sample_step * (float)(1 << level2d);
    L->inv_base = 1.0f / L->base;
    float top = (float)(r->mip->levels - 1);
    float level3d = log2f(L->base) - r->level3d_offset;
    L->level3d = level3d < 0.0f ? 0.0f : (level3d > top ? top : level3d);
    L->n = (int)L->level3d;
    L->exact = L->level3d == (float)L->n;
    L->g = L->exact ? &r->octree->exact[L->n] : &r->octree->grid[L->n];
    L->blend = &r->octree->grid[L->n];
    L->scale = (float)(1 << L->n);
    L->inv_scale = 1.0f / L->scale;
    L->dims[0] = L->g->nx[0];
    L->dims[1] = L->g->ny[0];
    L->dims[2] = L->g->nz[0];
    for (int a = 0; a < 4; a++) {
        bool axis = a < 3;
        L->dv_v[a] = axis ? L->dv[a] : 0.0f;
        L->inv_dv_v[a] = axis ? L->inv_dv[a] : 0.0f;
        L->dir_pos[a] = axis && L->dv[a] > 0.0f ? -1 : 0;
        L->dir_neg[a] = axis && L->dv[a] < 0.0f ? -1 : 0;
        L->dims_v[a] = axis ? L->dims[a] : 1;
        L->top_v[a] = axis ? L->dims[a] - 1 : 0;
    }
}

/* raycast_parallel_positions with a float first guess: the adjustment
 * loops evaluate the tracer's exact expression, so the count is the same. */
static inline long positions(const par_level_t *L, float t0, float t1)
{
    if (!(t0 <= t1))
        return 0;
    float est = (t1 - t0) * L->inv_base;
    long k = est < 1e9f ? (long)est : 1000000000L;
    while (k > 0 && t0 + (float)k * L->base > t1)
        k--;
    while (t0 + (float)(k + 1) * L->base <= t1)
        k++;
    return k + 1;
}

/* The reference's ray_begin for this ray: volume clip, then the window of
 * positions inside the occupied cells' bounding box.  False: nothing to draw. */
static bool ray_begin(const raycast_ctx_t *r, const par_level_t *L, float px, float py,
                      par_ray_t *s)
{
    const camera_t *cam = r->camera;
    float o[3], d[3], t1;
    s->acc[0] = s->acc[1] = s->acc[2] = 0.0f;
    s->acc_a = 0.0f;
    s->n_samples = 0;
    s->k_end = 0;
    camera_ray(cam, px, py, o, d);
    if (!raycast_clip_box(o, d, cam->box_hi, &s->t0, &t1))
        return false;
    for (int a = 0; a < 3; a++)
        s->ov[a] = o[a] * cam->inv_spacing[a];
    s->ov[3] = 0.0f;
    s->t1_volume = t1;
    s->k_end = -1;                /* all positions, counted when the ray ends */
    const octree_grid_t *g = L->g;
    if (!g->any_occupied)
        return false;
    float a = -INFINITY, b = INFINITY;
    for (int ax = 0; ax < 3; ax++) {
        if (L->dv[ax] == 0.0f)
            continue;
        float ta = (g->box_lo[ax] - s->ov[ax]) * L->inv_dv[ax];
        float tb = (g->box_hi[ax] - s->ov[ax]) * L->inv_dv[ax];
        if (ta > tb) {
            float sw = ta;
            ta = tb;
            tb = sw;
        }
        /* fmaxf/fminf without the libm calls: no operand is NaN here
         * (dv != 0, the box faces are finite or infinite). */
        a = ta > a ? ta : a;
        b = tb < b ? tb : b;
    }
    if (a - 1e-3f > t1)
        return false;
    s->k = 0;
    if (a - 1e-3f > s->t0)
        s->k = -(long)mip3d_floor_int(-(a - 1e-3f - s->t0) / L->base);
    if (b + 1e-3f < t1)
        t1 = b + 1e-3f;
    s->k_last = positions(L, s->t0, t1) - 1;
    return s->k <= s->k_last;
}

/* Level-n cell of position k: continuous coordinates q (as mip3d_sample
 * computes them), their floors, and the floors clamped to the grid (as
 * octree_empty_node clamps them).  Returns the level-0 position in p. */
/* Clamped level-n cell (lanes 0-2) of level-0 position ov + t * dv, with
 * the continuous coordinates and floors on the way. */
static inline v4i cell_of(const par_level_t *L, v4f ov, float t, v4f *pv, v4f *qv, v4i *flv)
{
    v4f tv = {t, t, t, t};
    *pv = ov + tv * L->dv_v;
    *qv = (*pv + 0.5f) * L->inv_scale - 0.5f;
    v4i iv = __builtin_convertvector(*qv, v4i);
    *flv = iv + (__builtin_convertvector(iv, v4f) > *qv);   /* -1 where truncation rounded up */
    v4i cv = *flv & ~(*flv < 0);
    v4i over = cv > L->top_v;
    return (cv & ~over) | (L->top_v & over);
}

static inline void position_cell(const par_level_t *L, const par_ray_t *s, long k, float p[3],
                                 float q[3], int fl[3], int c[3])
{
    v4f ov, pv, qv;
    v4i flv;
    memcpy(&ov, s->ov, sizeof ov);
    v4i cv = cell_of(L, ov, s->t0 + (float)k * L->base, &pv, &qv, &flv);
    for (int a = 0; a < 3; a++) {
        p[a] = pv[a];
        q[a] = qv[a];
        fl[a] = flv[a];
        c[a] = cv[a];
    }
}

/* Where the ray ov + t * dv leaves the node of height h holding cell c
 * (faces on the grid's edge count as infinitely far); the node's cell
 * range [first, last) per lane. */
static inline float node_exit(const par_level_t *L, v4f ov, v4i cv, int h, v4i *first,
                              v4i *last)
{
    *first = (cv >> h) << h;
    *last = *first + (1 << h);
    v4i cell = (*last & L->dir_pos) | (*first & ~L->dir_pos);
    v4i valid = (L->dir_pos & (*last < L->dims_v)) | (L->dir_neg & (*first > 0));
    v4f bound = (__builtin_convertvector(cell, v4f) + 0.5f) * L->scale - 0.5f;
    v4f te = (bound - ov) * L->inv_dv_v;
    v4f inf = {INFINITY, INFINITY, INFINITY, INFINITY};
    te = (v4f)(((v4i)te & valid) | ((v4i)inf & ~valid));
    float t_exit = te[0] < te[1] ? te[0] : te[1];
    return te[2] < t_exit ? te[2] : t_exit;
}

/* mip3d_trilerp for 4 components (the diffuse case), reusing the floors the
 * cell test computed: the same operations in the same order per component,
 * with a constant trip count the compiler can turn into vector code (each
 * lane still does exactly the scalar arithmetic). */
static inline void trilerp4(const mip3d_level_t *L, const float q[3], const int fl[3],
                            float out[4])
{
    int x0 = fl[0], y0 = fl[1], z0 = fl[2];
    float wx = q[0] - (float)x0, wy = q[1] - (float)y0, wz = q[2] - (float)z0;
    int x1 = x0 + 1, y1 = y0 + 1, z1 = z0 + 1;
    x0 = x0 < 0 ? 0 : (x0 >= L->nx ? L->nx - 1 : x0);
    x1 = x1 < 0 ? 0 : (x1 >= L->nx ? L->nx - 1 : x1);
    y0 = y0 < 0 ? 0 : (y0 >= L->ny ? L->ny - 1 : y0);
    y1 = y1 < 0 ? 0 : (y1 >= L->ny ? L->ny - 1 : y1);
    z0 = z0 < 0 ? 0 : (z0 >= L->nz ? L->nz - 1 : z0);
    z1 = z1 < 0 ? 0 : (z1 >= L->nz ? L->nz - 1 : z1);
    const size_t row = (size_t)L->nx, slice = (size_t)L->nx * (size_t)L->ny;
    const float *c000 = L->data + ((size_t)z0 * slice + (size_t)y0 * row + (size_t)x0) * 4;
    const float *c100 = L->data + ((size_t)z0 * slice + (size_t)y0 * row + (size_t)x1) * 4;
    const float *c010 = L->data + ((size_t)z0 * slice + (size_t)y1 * row + (size_t)x0) * 4;
    const float *c110 = L->data + ((size_t)z0 * slice + (size_t)y1 * row + (size_t)x1) * 4;
    const float *c001 = L->data + ((size_t)z1 * slice + (size_t)y0 * row + (size_t)x0) * 4;
    const float *c101 = L->data + ((size_t)z1 * slice + (size_t)y0 * row + (size_t)x1) * 4;
    const float *c011 = L->data + ((size_t)z1 * slice + (size_t)y1 * row + (size_t)x0) * 4;
    const float *c111 = L->data + ((size_t)z1 * slice + (size_t)y1 * row + (size_t)x1) * 4;
    /* The four components side by side: lane k computes exactly
     * mip3d_trilerp's out[k]. */
    v4f v000, v100, v010, v110, v001, v101, v011, v111;
    memcpy(&v000, c000, sizeof v000);
    memcpy(&v100, c100, sizeof v100);
    memcpy(&v010, c010, sizeof v010);
    memcpy(&v110, c110, sizeof v110);
    memcpy(&v001, c001, sizeof v001);
    memcpy(&v101, c101, sizeof v101);
    memcpy(&v011, c011, sizeof v011);
    memcpy(&v111, c111, sizeof v111);
    v4f a = v000 + wx * (v100 - v000);
    v4f b = v010 + wx * (v110 - v010);
    v4f c = v001 + wx * (v101 - v001);
    v4f d = v011 + wx * (v111 - v011);
    v4f e = a + wy * (b - a);
    v4f f = c + wy * (d - c);
    v4f res = e + wz * (f - e);
    memcpy(out, &res, sizeof res);
}

/* mip3d_trilerp at level n for stride 8 (specular and moving-object cases), reusing the floors the cell
 * test computed.  Four components side by side in one vector: lane k does
 * exactly mip3d_trilerp's arithmetic for out[k], in the same order. */
static inline v4f lerp_corners(const float *const c[8], int k, float wx, float wy, float wz)
{
    v4f v[8];
    for (int i = 0; i < 8; i++)
        memcpy(&v[i], c[i] + k, sizeof v[i]);
    v4f a = v[0] + wx * (v[1] - v[0]);
    v4f b = v[2] + wx * (v[3] - v[2]);
    v4f cc = v[4] + wx * (v[5] - v[4]);
    v4f d = v[6] + wx * (v[7] - v[6]);
    v4f e = a + wy * (b - a);
    v4f f = cc + wy * (d - cc);
    return e + wz * (f - e);
}

static inline void trilerp(const mip3d_level_t *L, int stride, const float q[3], const int fl[3],
                           float *out)
{
    int x0 = fl[0], y0 = fl[1], z0 = fl[2];
    float wx = q[0] - (float)x0, wy = q[1] - (float)y0, wz = q[2] - (float)z0;
    int x1 = x0 + 1, y1 = y0 + 1, z1 = z0 + 1;
    x0 = x0 < 0 ? 0 : (x0 >= L->nx ? L->nx - 1 : x0);
    x1 = x1 < 0 ? 0 : (x1 >= L->nx ? L->nx - 1 : x1);
    y0 = y0 < 0 ? 0 : (y0 >= L->ny ? L->ny - 1 : y0);
    y1 = y1 < 0 ? 0 : (y1 >= L->ny ? L->ny - 1 : y1);
    z0 = z0 < 0 ? 0 : (z0 >= L->nz ? L->nz - 1 : z0);
    z1 = z1 < 0 ? 0 : (z1 >= L->nz ? L->nz - 1 : z1);
    const size_t row = (size_t)L->nx, slice = (size_t)L->nx * (size_t)L->ny, st = (size_t)stride;
    /* Corner order: x fastest, then y, then z (c000, c100, c010, c110, ...). */
    const float *const c[8] = {
        L->data + ((size_t)z0 * slice + (size_t)y0 * row + (size_t)x0) * st,
        L->data + ((size_t)z0 * slice + (size_t)y0 * row + (size_t)x1) * st,
        L->data + ((size_t)z0 * slice + (size_t)y1 * row + (size_t)x0) * st,
        L->data + ((size_t)z0 * slice + (size_t)y1 * row + (size_t)x1) * st,
        L->data + ((size_t)z1 * slice + (size_t)y0 * row + (size_t)x0) * st,
        L->data + ((size_t)z1 * slice + (size_t)y0 * row + (size_t)x1) * st,
        L->data + ((size_t)z1 * slice + (size_t)y1 * row + (size_t)x0) * st,
        L->data + ((size_t)z1 * slice + (size_t)y1 * row + (size_t)x1) * st,
    };
    for (int k = 0; k < stride; k += 4) {
        v4f res = lerp_corners(c, k, wx, wy, wz);
        memcpy(out + k, &res, sizeof res);
    }
}

/* Jumps from empty position k (cell c, in an empty node of height h) to the
 * first position beyond the node, or ends the window. */
static inline void jump(const par_level_t *L, par_ray_t *s, const int c[3], int h)
{
    v4f ov;
    memcpy(&ov, s->ov, sizeof ov);
    v4i cv = {c[0], c[1], c[2], 0}, first, last;
    float t_exit = node_exit(L, ov, cv, h, &first, &last);
    long k = s->k, k_new = s->k_last + 1;
    /* A hair inside the node, so that the check below rarely fails. */
    float t_in = t_exit - 1e-3f;
    if (t_in - s->t0 < (float)(k_new - k) * L->base + (float)k * L->base) {
        long kc = -(long)mip3d_floor_int(-(t_in - s->t0) * L->inv_base);
        if (kc < k_new)
            k_new = kc;
    }
    if (k_new > k + 1) {
        v4f pv, qv;
        v4i flv;
        v4i cl = cell_of(L, ov, s->t0 + (float)(k_new - 1) * L->base, &pv, &qv, &flv);
        v4i outside = (cl < first) | (cl >= last);
        if (outside[0] | outside[1] | outside[2])
            k_new = k + 1;        /* rounding: fall back to one step */
    } else {
        k_new = k + 1;
    }
    s->k = k_new;
}

/* Visits position k: steps over it, jumps past its empty node, or draws,
 * shades and composites its sample.  False when the ray is finished. */
static inline bool ray_step(const raycast_ctx_t *r, const par_level_t *L, par_ray_t *s)
{
    if (s->k > s->k_last)
        return false;
    float p[3], q[3];
    int fl[3], c[3];
    position_cell(L, s, s->k, p, q, fl, c);
    const octree_grid_t *g = L->g;
    size_t b = octree_block_index(g, c[0], c[1], c[2]);
    int h = g->block_height[b];
    if (h >= 0) {
        jump(L, s, c, h);
        return true;
    }
    if (!((g->block_bits[b] >> octree_block_bit(c[0], c[1], c[2])) & 1)) {
        s->k++;
        return true;
    }
    float comp[8];
    if (L->exact && r->mip->stride == 4)
        trilerp4(&r->mip->level[L->n], q, fl, comp);
    else if (L->exact && r->mip->stride == 8)
        trilerp(&r->mip->level[L->n], 8, q, fl, comp);
    else if (L->exact)
        mip3d_trilerp(r->mip, L->n, q[0], q[1], q[2], comp);
    else
        mip3d_sample(r->mip, L->level3d, p, comp);
    s->n_samples++;
    if (raycast_accumulate(r, comp, L->half, L->level2d, false, L->base, s->acc, &s->acc_a)) {
        s->k_end = s->k + 1;
        return false;
    }
    s->k++;
    return true;
}

static void ray_end(const par_level_t *L, const par_ray_t *s, float rgb[3],
                    raycast_counts_t *counts)
{
    long all = s->k_end >= 0 ? s->k_end
                             : positions(L, s->t0, s->t1_volume);
    counts->rays++;
    counts->samples += s->n_samples;
    counts->samples_skipped += (uint64_t)all - s->n_samples;
    rgb[0] = s->acc[0];
    rgb[1] = s->acc[1];
    rgb[2] = s->acc[2];
}

/* Packets: rays of one level share a direction, so at equal t they sit at
 * fixed offsets from one another.  The blend grid of level n (octree.h:
 * cell i occupied when a level-n voxel in [i-2, i+3]^3 is) is the exact
 * grid dilated by two cells: where it is empty, every exact cell within two
 * cells is empty.  So one "beam" ray at the packet's centre, walked through
 * the blend grid, proves empty space for all rays whose level-n coordinates
 * stay within BEAM_RADIUS < 2 of it; they skip it together, and each then
 * continues alone from where the beam met an occupied blend cell.  The
 * slack 2 - BEAM_RADIUS lets the beam step a little past each node's exit
 * (BEAM_STEP cells, far above float rounding) without losing the proof. */
#define BEAM_RADIUS 1.98f
#define BEAM_STEP 0.01f

/* Walks the beam from t_start; returns the t before which every packet
 * position is proven empty (INFINITY: all up to t_end). */
static float beam_walk(const par_level_t *L, const octree_grid_t *g, const float centre[3],
                       float t_start, float t_end)
{
    const float step = BEAM_STEP * L->scale;   /* |dv| <= 1: moves <= BEAM_STEP cells */
    v4f ov = {centre[0], centre[1], centre[2], 0.0f}, pv, qv;
    v4i flv, first, last;
    float t = t_start;
    while (t <= t_end) {
        v4i c = cell_of(L, ov, t, &pv, &qv, &flv);
        size_t b = octree_block_index(g, c[0], c[1], c[2]);
        int h = g->block_height[b];
        if (h < 0) {
            if ((g->block_bits[b] >> octree_block_bit(c[0], c[1], c[2])) & 1)
                return t - step;
            h = 0;
        }
        float t_exit = node_exit(L, ov, c, h, &first, &last);
        if (!(t_exit + step > t))
            return t - step;     /* no progress (rounding): let the rays go on */
        t = t_exit + step;
    }
    return INFINITY;
}

/* Groups consecutive live rays into packets narrow enough for the beam and
 * moves each ray past the empty space its packet's beam proved. */
static void packets_skip(const par_level_t *L, par_ray_t *s, const bool *live, int count)
{
    const octree_grid_t *g = L->blend;
    /* The same rays walked backwards (u = -t, direction -dv): a beam from
     * the far end proves the tail of the packet's window empty too. */
    par_level_t back = *L;
    back.dv_v = -L->dv_v;
    back.inv_dv_v = -L->inv_dv_v;
    back.dir_pos = L->dir_neg;
    back.dir_neg = L->dir_pos;
    int i = 0;
    while (i < count) {
        if (!live[i]) {
            i++;
            continue;
        }
        float lo[3], hi[3];
        for (int a = 0; a < 3; a++)
            lo[a] = hi[a] = s[i].ov[a];
        int j = i + 1;
        for (; j < count && live[j]; j++) {
            bool fits = true;
            for (int a = 0; a < 3; a++) {
                float l = min_f(lo[a], s[j].ov[a]), h = max_f(hi[a], s[j].ov[a]);
                if (0.5f * (h - l) * L->inv_scale > BEAM_RADIUS)
                    fits = false;
            }
            if (!fits)
                break;
            for (int a = 0; a < 3; a++) {
                lo[a] = min_f(lo[a], s[j].ov[a]);
                hi[a] = max_f(hi[a], s[j].ov[a]);
            }
        }
        if (j - i >= 2) {
            float centre[3], t_start = INFINITY, t_end = -INFINITY;
            for (int a = 0; a < 3; a++)
                centre[a] = 0.5f * (lo[a] + hi[a]);
            for (int m = i; m < j; m++) {
                float ta = s[m].t0 + (float)s[m].k * L->base;
                float tb = s[m].t0 + (float)s[m].k_last * L->base;
                t_start = min_f(t_start, ta);
                t_end = max_f(t_end, tb);
            }
            float t_clear = beam_walk(L, g, centre, t_start, t_end);
            /* Positions beyond t_tail are proven empty. */
            float t_tail = t_clear == INFINITY ? -INFINITY
                                                : -beam_walk(&back, g, centre, -t_end, -t_clear);
            for (int m = i; m < j; m++) {
                if (t_clear == INFINITY) {
                    s[m].k = s[m].k_last + 1;
                    continue;
                }
                if (t_tail != -INFINITY) {
                    /* One position to spare: testing more is always safe. */
                    long kt = mip3d_floor_int((t_tail - s[m].t0) * L->inv_base) + 1;
                    if (kt < s[m].k_last)
                        s[m].k_last = kt;
                }
                float ts = s[m].t0 + (float)s[m].k * L->base;
                if (t_clear > ts) {
                    long kc = -(long)mip3d_floor_int(-(t_clear - s[m].t0) * L->inv_base);
                    if (kc > s[m].k)
                        s[m].k = kc;
                }
            }
        }
        i = j;
    }
}

void raycast_parallel_batch(const raycast_ctx_t *r, int count, const float *px, const float *py,
                            int level2d, float (*rgb)[3], raycast_counts_t *counts)
{
    par_level_t L;
    level_setup(r, level2d, &L);
    par_ray_t s[RAYCAST_BATCH];
    bool live[RAYCAST_BATCH];
    int remaining = 0;
    for (int i = 0; i < count; i++) {
        live[i] = ray_begin(r, &L, px[i], py[i], &s[i]);
        remaining += live[i];
    }
    if (L.exact && count > 1)
        packets_skip(&L, s, live, count);
    while (remaining > 0)
        for (int i = 0; i < count; i++)
            if (live[i] && !ray_step(r, &L, &s[i])) {
                live[i] = false;
                remaining--;
            }
    for (int i = 0; i < count; i++)
        ray_end(&L, &s[i], rgb[i], counts);
}
