/* raycast_parallel.h: what the fast parallel tracer's pieces share
 * (raycast_parallel.c: ray set-up, packets, the portable walk;
 * raycast_walk_avx2.c: eight rays side by side): per-level invariants, per-ray
 * state, and the cell, jump and trilinear helpers, each doing exactly the
 * reference's float operations (raycast.c) so every path draws the same
 * samples with the same values. */
#ifndef PP5_RAYCAST_PARALLEL_H
#define PP5_RAYCAST_PARALLEL_H

#include <math.h>
#include <string.h>

#include "raycast_internal.h"
#include "vec4.h"

/* Whether raycast_walk_avx2.c builds its AVX2 walk (GCC on x86-64, as the PP
 * kernels' copies; PP5_NO_CLONES disables both). */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(PP5_NO_CLONES)
#define RAYCAST_HAVE_AVX2_WALK 1
#else
#define RAYCAST_HAVE_AVX2_WALK 0
#endif

/* What all parallel rays of one 2D level share (the reference recomputes it
 * per ray, with the same expressions).  Its vectors (vec4.h) hold the three
 * axes side by side, lane 3 unused. */
typedef struct {
    const octree_grid_t *g;
    const octree_grid_t *blend;   /* level n's blend grid: the exact grid dilated by 2 */
    float dv[4], inv_dv[3], half[3];   /* dv[3] = 0 */
    float base, inv_base, level3d;
    float alpha_spacing;          /* base / opacity_unit: the opacity correction's exponent */
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

/* The eight corners of the trilinear footprint at level-n coordinates q
 * with floors fl (x fastest, then y, then z: c000, c100, c010, c110, ...),
 * clamped to the edge voxels as mip3d_trilerp clamps them, and the weights. */
static inline void corners(const mip3d_level_t *L, int stride, const float q[3], const int fl[3],
                           float w[3], const float *c[8])
{
    const int dims[3] = {L->nx, L->ny, L->nz};
    int lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        w[a] = q[a] - (float)fl[a];
        int h = fl[a] + 1;
        lo[a] = fl[a] < 0 ? 0 : (fl[a] >= dims[a] ? dims[a] - 1 : fl[a]);
        hi[a] = h < 0 ? 0 : (h >= dims[a] ? dims[a] - 1 : h);
    }
    const size_t row = (size_t)L->nx, slice = (size_t)L->nx * (size_t)L->ny, st = (size_t)stride;
    for (int i = 0; i < 8; i++)
        c[i] = L->data + ((size_t)(i & 4 ? hi[2] : lo[2]) * slice +
                          (size_t)(i & 2 ? hi[1] : lo[1]) * row +
                          (size_t)(i & 1 ? hi[0] : lo[0])) * st;
}

/* Components k..k+3 of the trilinear sample from the corners: lane j does
 * exactly mip3d_trilerp's arithmetic for out[k + j], in the same order. */
static inline v4f lerp_corners(const float *const c[8], int k, const float w[3])
{
    v4f v[8];
    for (int i = 0; i < 8; i++)
        memcpy(&v[i], c[i] + k, sizeof v[i]);
    v4f a = v[0] + w[0] * (v[1] - v[0]);
    v4f b = v[2] + w[0] * (v[3] - v[2]);
    v4f cc = v[4] + w[0] * (v[5] - v[4]);
    v4f d = v[6] + w[0] * (v[7] - v[6]);
    v4f e = a + w[1] * (b - a);
    v4f f = cc + w[1] * (d - cc);
    return e + w[2] * (f - e);
}

/* mip3d_trilerp at level n for F32 levels of stride 4 or 8, reusing the
 * floors the cell test computed. */
static inline void trilerp(const mip3d_level_t *L, int stride, const float q[3], const int fl[3],
                           float *out)
{
    float w[3];
    const float *c[8];
    corners(L, stride, q, fl, w, c);
    for (int k = 0; k < stride; k += 4) {
        v4f res = lerp_corners(c, k, w);
        memcpy(out + k, &res, sizeof res);
    }
}

static inline void trilerp4(const mip3d_level_t *L, const float q[3], const int fl[3],
                            float out[4])
{
    trilerp(L, 4, q, fl, out);
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

/* Draws, shades and composites the sample at position k (level-0 position
 * p, level-n coordinates q with floors fl); true when the ray has reached
 * early termination. */
static inline bool draw_sample(const raycast_ctx_t *r, const par_level_t *L, par_ray_t *s,
                               const float p[3], const float q[3], const int fl[3])
{
    float comp[8];
    if (r->mip->format != MIP3D_F32 && L->exact)
        mip3d_trilerp(r->mip, L->n, q[0], q[1], q[2], comp);
    else if (L->exact && r->mip->stride == 4)
        trilerp4(&r->mip->level[L->n], q, fl, comp);
    else if (L->exact && r->mip->stride == 8)
        trilerp(&r->mip->level[L->n], 8, q, fl, comp);
    else if (L->exact)
        mip3d_trilerp(r->mip, L->n, q[0], q[1], q[2], comp);
    else
        mip3d_sample(r->mip, L->level3d, p, comp);
    s->n_samples++;
    return raycast_accumulate(r, comp, L->half, L->level2d, false, L->alpha_spacing, s->acc,
                              &s->acc_a);
}

/* The walk with eight rays side by side (raycast_walk_avx2.c): runs every
 * live ray of s[0..count) from its k to its end, drawing exactly the samples
 * the portable walk draws.  Only call it when raycast_walk_avx2_supported()
 * says the host can. */
bool raycast_walk_avx2_supported(void);
void raycast_walk_avx2(const raycast_ctx_t *r, const par_level_t *L, par_ray_t *s,
                       const bool *live, int count);

#endif
