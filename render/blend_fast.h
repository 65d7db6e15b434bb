/* blend_fast.h: the skipping tracer's per-ray machinery, shared by the lone
 * ray walk (blend_trace_fast.c) and the packet driver (blend_trace_packet.c).
 * Internal to render/; see blend_trace_fast.c for why skipping is exact. */
#ifndef PP5_BLEND_FAST_H
#define PP5_BLEND_FAST_H

#include <math.h>
#include <stdbool.h>
#include "blend_trace.h"
#include "vec4.h"

/* Which samples a ray may pass without drawing. */
typedef enum {
    SKIP_RAY1,                /* material(bound) <= m_max (mip_ray_can_skip) */
    SKIP_RAY2,                /* cannot be ray 2's stop (demip_ray2_stops) */
    SKIP_EMPTY                /* material 0: MIDA (beta = 1, a = 0) */
} skip_rule_t;

/* What the parallel rays of one 2D level share. */
typedef struct {
    const blend_frame_t *f;
    const scalar_level_t *L;
    int n, dims[3];           /* 3D level read and its voxel counts */
    float base, inv_base, scale, inv_scale;
    float dv[3], inv_dv[3];   /* direction in level-0 voxel units */
    v4f dv_v;
    v4i top_v;                /* dims - 1 (lane 3 = 0) */
    size_t row, slice;        /* cells per row and per slice: a cell's index strides */
    float threshold_material[SCALAR_THRESHOLDS];
} fast_level_t;

/* Ray 1's running-maximum records, the last BLEND_RECORDS of them. */
#define BLEND_RECORDS 32
typedef struct {
    long k[BLEND_RECORDS];
    float m[BLEND_RECORDS];
    int count;                /* records made (may exceed BLEND_RECORDS) */
} records_t;

/* One ray and its walk. */
typedef struct {
    const fast_level_t *lv;
    blend_geom_t g;
    v4f ov_v;                 /* origin, level-0 voxel units (lane 3 = 0) */
    skip_rule_t rule;
    float threshold;          /* SKIP_RAY2's */
    long k;                   /* next position */
    long drawn, all;          /* drawn; drawn by a ray without skipping */
    long stop;                /* SKIP_RAY2: ray 2's stop (-1 none) */
    bool done;
    mip_ray_t mip;
    records_t rec;
    mida_ray_t mida;
} fast_ray_t;

void fast_level_init(const blend_ctx_t *c, const blend_geom_t *g, fast_level_t *lv);
/* Starts a ray's walk under `rule` (ray 1 from m_max = guess). */
void fast_ray_start(fast_ray_t *r, skip_rule_t rule, float param);
/* One step of the walk: a jump over skippable bricks, or the draws of one
 * brick's positions; sets done at the end of the window or an early stop. */
void fast_ray_step(fast_ray_t *r);

static inline void fast_ray_run(fast_ray_t *r)
{
    while (!r->done)
        fast_ray_step(r);
}

/* The walk's current skipping parameter (ray 1: m_max). */
static inline float fast_ray_param(const fast_ray_t *r)
{
    return r->rule == SKIP_RAY1 ? r->mip.m_max : (r->rule == SKIP_RAY2 ? r->threshold : 0.0f);
}

/* Level cell (clamped) of the point ov + t dv, with level coordinates and
 * floors.  The three axes side by side: each lane does exactly the scalar
 * operations of the reference (ISO C mode: no fused multiply-add). */
static inline v4i fast_cell(const fast_level_t *lv, v4f ov, float t, v4f *qv, v4i *flv)
{
    v4f tv = {t, t, t, t};
    v4f pv = ov + tv * lv->dv_v;
    *qv = (pv + 0.5f) * lv->inv_scale - 0.5f;
    v4i iv = __builtin_convertvector(*qv, v4i);
    *flv = iv + (__builtin_convertvector(iv, v4f) > *qv);   /* -1 where truncation rounded up */
    v4i cv = *flv & ~(*flv < 0);
    v4i over = cv > lv->top_v;
    return (cv & ~over) | (lv->top_v & over);
}

/* scalar_trilerp at level coordinates qv with floors flv (fast_cell's),
 * its seven lerps done four and then two side by side.  The lanes do the
 * scalar expressions' operations on the same floats in the same order, so
 * the sample is scalar_trilerp's to the bit; the edge voxels (clamped
 * indices) go through scalar_trilerp itself.  A sample is the brick-order
 * tracer's most frequent step, and the scalar form spent most of its time
 * moving lanes in and out of vectors. */
static inline float fast_trilerp(const fast_level_t *lv, v4f qv, v4i flv)
{
#if defined(__SSE2__)
    if (v4i_all3((flv >= 0) & (flv < lv->top_v))) {
        const float *v = lv->L->value + (size_t)flv[2] * lv->slice + (size_t)flv[1] * lv->row +
                         (size_t)flv[0];
        size_t sy = lv->row, sz = lv->slice;
        /* c0 c1 | c2 c3 and c4 c5 | c6 c7: x-neighbours are adjacent floats */
        __m128 lo = _mm_loadh_pi(_mm_loadl_pi(_mm_setzero_ps(), (const __m64 *)v),
                                 (const __m64 *)(v + sy));
        __m128 hi = _mm_loadh_pi(_mm_loadl_pi(_mm_setzero_ps(), (const __m64 *)(v + sz)),
                                 (const __m64 *)(v + sz + sy));
        v4f even = (v4f)_mm_shuffle_ps(lo, hi, _MM_SHUFFLE(2, 0, 2, 0));   /* c0 c2 c4 c6 */
        v4f odd = (v4f)_mm_shuffle_ps(lo, hi, _MM_SHUFFLE(3, 1, 3, 1));    /* c1 c3 c5 c7 */
        v4f w = qv - __builtin_convertvector(flv, v4f);
        v4f wx = {w[0], w[0], w[0], w[0]}, wy = {w[1], w[1], w[1], w[1]};
        v4f abde = even + wx * (odd - even);                                /* a b d e */
        v4f ad = (v4f)_mm_shuffle_ps((__m128)abde, (__m128)abde, _MM_SHUFFLE(2, 0, 2, 0));
        v4f be = (v4f)_mm_shuffle_ps((__m128)abde, (__m128)abde, _MM_SHUFFLE(3, 1, 3, 1));
        v4f fg = ad + wy * (be - ad);                                       /* f g f g */
        return fg[0] + w[2] * (fg[1] - fg[0]);
    }
#endif
    float q[3] = {qv[0], qv[1], qv[2]};
    int fl[3] = {flv[0], flv[1], flv[2]};
    return scalar_trilerp(lv->L, q, fl);
}

/* Where ov + t dv leaves the box of cells [first, last) (INFINITY: never;
 * faces on the grid's edge hold the clamped cells beyond). */
static inline float fast_box_exit(const fast_level_t *lv, v4f ov, const int first[3],
                                  const int last[3])
{
    float t_exit = INFINITY;
    for (int a = 0; a < 3; a++) {
        int cell;
        if (lv->dv[a] > 0.0f && last[a] < lv->dims[a])
            cell = last[a];
        else if (lv->dv[a] < 0.0f && first[a] > 0)
            cell = first[a];
        else
            continue;
        float bound = ((float)cell + 0.5f) * lv->scale - 0.5f;
        float te = (bound - ov[a]) * lv->inv_dv[a];
        t_exit = te < t_exit ? te : t_exit;
    }
    return t_exit;
}
/* The highest distance-map level `rule` may skip at `param` (-1: none). */
int fast_threshold_level(const fast_level_t *lv, skip_rule_t rule, float param);
/* The cube of bricks within d - 1 of the brick holding cell c, as cells. */
void fast_brick_cube(const int c[3], int d, int first[3], int last[3]);

/* Material of the sample at position k (the reference's expressions). */
float fast_sample(const fast_ray_t *r, long k);
/* DEMIP after ray 1 (r->mip) and ray 2 (stop j): reading B's gap test, the
 * counts (drawn and all so far, plus the j + 1 positions of ray 2) and the
 * colour. */
void fast_demip_finish(const fast_ray_t *r, long j, long drawn, long all, float rgb[3],
                       raycast_counts_t *counts);
/* Ray 2's stop from ray 1's records (see blend_trace_fast.c), or -1. */
long fast_stop_from_records(const records_t *rec, float g, float threshold);

#endif
