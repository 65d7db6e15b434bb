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
#include "raycast_parallel.h"

#include <math.h>
#include <string.h>

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
    L->alpha_spacing = L->base / r->opacity_unit;
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
    if (draw_sample(r, L, s, p, q, fl)) {
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

/* The portable walk: up to RAYCAST_BATCH rays advanced one position each in
 * turns, so that their latency chains overlap. */
static void walk_in_turns(const raycast_ctx_t *r, const par_level_t *L, par_ray_t *s,
                          const bool *live_in, int count)
{
    bool live[RAYCAST_BATCH];
    int remaining = 0;
    for (int i = 0; i < count; i++)
        remaining += live[i] = live_in[i];
    while (remaining > 0)
        for (int i = 0; i < count; i++)
            if (live[i] && !ray_step(r, L, &s[i])) {
                live[i] = false;
                remaining--;
            }
}

void raycast_parallel_batch(const raycast_ctx_t *r, int count, const float *px, const float *py,
                            int level2d, float (*rgb)[3], raycast_counts_t *counts)
{
    par_level_t L;
    level_setup(r, level2d, &L);
    par_ray_t s[RAYCAST_CHUNK];
    bool live[RAYCAST_CHUNK];
    for (int i = 0; i < count; i++)
        live[i] = ray_begin(r, &L, px[i], py[i], &s[i]);
    if (L.exact && count > 1)
        packets_skip(&L, s, live, count);
    if (r->simd_walk)
        raycast_walk_avx2(r, &L, s, live, count);
    else
        for (int i0 = 0; i0 < count; i0 += RAYCAST_BATCH)
            walk_in_turns(r, &L, s + i0, live + i0,
                          count - i0 < RAYCAST_BATCH ? count - i0 : RAYCAST_BATCH);
    for (int i = 0; i < count; i++)
        ray_end(&L, &s[i], rgb[i], counts);
}
