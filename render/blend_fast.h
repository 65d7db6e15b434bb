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
