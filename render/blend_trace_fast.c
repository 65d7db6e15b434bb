/* blend_trace_fast.c: the skipping tracer for parallel MIP, DEMIP and MIDA
 * rays.  It visits the reference's sample positions (t0 + k * base), draws a
 * position exactly as the reference does (same float expressions), and
 * passes positions only where a node bound (scalar_pyramid.h) proves that
 * no sample there can change the ray:
 *   ray 1:  material(bound) <= m_max            (mip_ray_can_skip)
 *   ray 2:  !demip_ray2_stops(material(bound))  (cannot be ray 2's stop)
 *   MIDA:   material(bound) = 0                 (adds nothing: beta = 1, a = 0)
 * Material is monotone in the value, so a bound on values bounds materials;
 * a node's bound is at least each of its cells', so a skippable node holds
 * only skippable cells.  A jump over a node is accepted only after checking
 * that the last position it passes lies in the node: every cell coordinate
 * of position k is a monotone function of k (each float operation in it is),
 * so first and last inside the node means all between are. */
#include "blend_trace.h"

#include <math.h>
#include <string.h>

typedef float v4f __attribute__((vector_size(16)));
typedef int v4i __attribute__((vector_size(16)));

typedef enum { SKIP_RAY1, SKIP_RAY2, SKIP_EMPTY } skip_rule_t;

typedef struct {
    const blend_frame_t *f;
    const scalar_level_t *L;
    const blend_geom_t *g;
    int n;                        /* 3D level read */
    float scale, inv_scale, inv_base;
    float inv_dv[3];
    int dims[3];
    float threshold_material[SCALAR_THRESHOLDS];  /* of the distance-map levels */
    v4f ov_v, dv_v;               /* ray origin and direction, lane 3 = 0 */
    v4i top_v;                    /* dims - 1 (lane 3 = 0) */
} fast_ray_t;

static inline bool skippable_material(skip_rule_t rule, float param, float m)
{
    if (rule == SKIP_RAY1) {
        mip_ray_t state = {param, 0};
        return mip_ray_can_skip(&state, m);
    }
    if (rule == SKIP_RAY2)
        return !demip_ray2_stops(m, param);
    return m <= 0.0f;
}

static inline bool skippable(const fast_ray_t *r, skip_rule_t rule, float param, float bound)
{
    return skippable_material(rule, param, blend_material(&r->f->window, bound));
}

/* Level coordinates, floors and clamped cell of position k, three axes side
 * by side: each lane does exactly the scalar operations of the reference
 * (ISO C mode: no fused multiply-add). */
static inline v4i cell_v(const fast_ray_t *r, long k, v4f *qv, v4i *flv)
{
    const blend_geom_t *g = r->g;
    float t = g->t0 + (float)k * g->base;
    v4f tv = {t, t, t, t};
    v4f pv = r->ov_v + tv * r->dv_v;
    *qv = (pv + 0.5f) * r->inv_scale - 0.5f;
    v4i iv = __builtin_convertvector(*qv, v4i);
    *flv = iv + (__builtin_convertvector(iv, v4f) > *qv);   /* -1 where truncation rounded up */
    v4i cv = *flv & ~(*flv < 0);
    v4i over = cv > r->top_v;
    return (cv & ~over) | (r->top_v & over);
}

static inline void position_cell(const fast_ray_t *r, long k, float q[3], int fl[3], int c[3])
{
    v4f qv;
    v4i flv, cv = cell_v(r, k, &qv, &flv);
    for (int a = 0; a < 3; a++) {
        q[a] = qv[a];
        fl[a] = flv[a];
        c[a] = cv[a];
    }
}

/* Parameter where the ray leaves the box of cells [first, last) (INFINITY
 * when it never does: faces on the grid's edge hold the clamped cells
 * beyond). */
static inline float box_exit(const fast_ray_t *r, const int first[3], const int last[3])
{
    float t_exit = INFINITY;
    for (int a = 0; a < 3; a++) {
        float dv = r->g->dv[a];
        int cell;
        if (dv > 0.0f && last[a] < r->dims[a])
            cell = last[a];
        else if (dv < 0.0f && first[a] > 0)
            cell = first[a];
        else
            continue;
        float bound = ((float)cell + 0.5f) * r->scale - 0.5f;
        float te = (bound - r->g->ov[a]) * r->inv_dv[a];
        t_exit = te < t_exit ? te : t_exit;
    }
    return t_exit;
}

static inline bool in_box(const fast_ray_t *r, long k, const int first[3], const int last[3])
{
    float q[3];
    int fl[3], c[3];
    position_cell(r, k, q, fl, c);
    return c[0] >= first[0] && c[0] < last[0] && c[1] >= first[1] && c[1] < last[1] &&
           c[2] >= first[2] && c[2] < last[2];
}

/* Position k lies in the box [first, last) whose positions may all be
 * skipped: returns the first position beyond it (or one inside it, which is
 * merely visited again).  The estimate from the exit parameter is checked
 * with the exact cell test of its last position; by monotonicity (see the
 * top), positions k..kc-1 are then all inside. */
static inline long jump_box(const fast_ray_t *r, long k, const int first[3], const int last[3])
{
    const long k_end = r->g->positions;
    float t_exit = box_exit(r, first, last);
    if (t_exit == INFINITY)
        return k_end;
    float x = (t_exit - r->g->t0) * r->inv_base;
    long kc = !(x < (float)k_end) ? k_end : (x <= 0.0f ? 0 : -(long)mip3d_floor_int(-x));
    if (kc <= k)
        kc = k + 1;
    /* Rounding may put position kc - 1 just outside: then try one fewer. */
    if (kc > k + 1 && !in_box(r, kc - 1, first, last))
        kc--;
    return kc > k + 1 && !in_box(r, kc - 1, first, last) ? k + 1 : kc;
}

/* The highest threshold level whose materials `rule` may skip (-1: none). */
static inline int threshold_level(const fast_ray_t *r, skip_rule_t rule, float param)
{
    int j = SCALAR_THRESHOLDS - 1;
    while (j >= 0 && !skippable_material(rule, param, r->threshold_material[j]))
        j--;
    return j;
}

/* From position *k, passes the positions `rule` lets the ray skip, a brick
 * (or a cube of bricks) at a time; returns true with [*k, *run_end) the
 * positions of the next brick that may hold a sample that matters (all are
 * drawn: drawing a skippable sample is always allowed), or false when the
 * window [0, positions) is exhausted. */
static bool advance(const fast_ray_t *r, skip_rule_t rule, float param, long *k_io,
                    long *run_end)
{
    const scalar_level_t *L = r->L;
    const long k_end = r->g->positions;
    const int bs = SCALAR_BRICK_SHIFT;
    const int j = L->brick_dist ? threshold_level(r, rule, param) : -1;
    const int top = L->heights - 1 < bs ? L->heights - 1 : bs;
    long k = *k_io;
    while (k < k_end) {
        int c[3], first[3], last[3], fl[3];
        float q[3];
        position_cell(r, k, q, fl, c);
        int d = j >= 0 ? scalar_brick_dist(L, j, c[0], c[1], c[2]) : 0;
        if (d > 0) {
            /* Every brick within chessboard distance d - 1 is skippable. */
            for (int a = 0; a < 3; a++) {
                int b = c[a] >> bs;
                first[a] = (b - (d - 1)) << bs;
                last[a] = (b + d) << bs;
            }
            k = jump_box(r, k, first, last);
            continue;
        }
        for (int a = 0; a < 3; a++) {
            first[a] = (c[a] >> top) << top;
            last[a] = first[a] + (1 << top);
        }
        if (skippable(r, rule, param, scalar_node_max(L, top, c[0], c[1], c[2]))) {
            k = jump_box(r, k, first, last);
            continue;
        }
        /* Draw the brick's positions: up to its exit, at least one. */
        float t_exit = box_exit(r, first, last);
        float x = (t_exit - r->g->t0) * r->inv_base;
        long kc = !(x < (float)k_end) ? k_end : (x <= 0.0f ? 0 : -(long)mip3d_floor_int(-x));
        *k_io = k;
        *run_end = kc > k ? kc : k + 1;
        return true;
    }
    *k_io = k;
    return false;
}

/* Material of the sample at position k: the reference's float expressions. */
static inline float sample_at(const fast_ray_t *r, long k)
{
    float q[3];
    int fl[3], c[3];
    position_cell(r, k, q, fl, c);
    return blend_material(&r->f->window, scalar_trilerp(r->L, q, fl));
}

static void trace_mida(const fast_ray_t *r, float rgb[3], raycast_counts_t *counts)
{
    mida_ray_t s;
    mida_ray_init(&s);
    long k = 0, run = 0, drawn = 0, all = r->g->positions;
    bool done = false;
    while (!done && advance(r, SKIP_EMPTY, 0.0f, &k, &run)) {
        for (; k < run; k++) {
            float m = sample_at(r, k);
            drawn++;
            if (mida_ray_sample(&s, m, mida_opacity(m, r->g->base), r->f->early_termination)) {
                all = k + 1;
                done = true;
                break;
            }
        }
    }
    counts->samples += (uint64_t)drawn;
    counts->samples_skipped += (uint64_t)(all - drawn);
    rgb[0] = rgb[1] = rgb[2] = s.colour;
}

/* Ray 1's running-maximum records (samples that raised m_max), the last
 * BLEND_RECORDS of them: what DEMIP's ray 2 is read from (trace_mip_demip). */
#define BLEND_RECORDS 32
typedef struct {
    long k[BLEND_RECORDS];
    float m[BLEND_RECORDS];
    int count;                    /* records made (may exceed BLEND_RECORDS) */
} records_t;

/* Ray 1 from position 0; returns the positions drawn, *all the positions a
 * ray without skipping draws. */
static long ray1(const fast_ray_t *r, mip_ray_t *ray, long *all, records_t *rec)
{
    long k = 0, run = 0, drawn = 0;
    *all = r->g->positions;
    rec->count = 0;
    while (advance(r, SKIP_RAY1, ray->m_max, &k, &run))
        for (; k < run; k++) {
            drawn++;
            float before = ray->m_max;
            bool done = mip_ray_sample(ray, k, sample_at(r, k));
            if (ray->m_max > before) {
                rec->k[rec->count % BLEND_RECORDS] = k;
                rec->m[rec->count % BLEND_RECORDS] = ray->m_max;
                rec->count++;
            }
            if (done) {
                *all = k + 1;     /* the reference stops here too */
                return drawn;
            }
        }
    return drawn;
}

/* Ray 2's stop from ray 1's records, or -1 when they cannot tell.  The first
 * sample with m >= threshold (> 0) is a record of ray 1 whenever threshold
 * exceeds ray 1's starting maximum g (or g = 0): every sample before it is
 * below threshold, so the running maximum there is below it too, and the
 * sample raises it.  Records rise, so it is the first record that stops
 * ray 2, provided the oldest record kept does not already stop it. */
static long stop_from_records(const records_t *rec, float g, float threshold)
{
    if (!(g == 0.0f || threshold > g) || rec->count == 0)
        return -1;
    int n = rec->count < BLEND_RECORDS ? rec->count : BLEND_RECORDS;
    int oldest = rec->count - n;
    for (int i = oldest; i < rec->count; i++)
        if (demip_ray2_stops(rec->m[i % BLEND_RECORDS], threshold))
            return i == oldest && rec->count > BLEND_RECORDS ? -1 : rec->k[i % BLEND_RECORDS];
    return -1;
}

/* Ray 2: the index of its stop; *drawn += positions drawn. */
static long ray2(const fast_ray_t *r, float threshold, long *drawn)
{
    long k = 0, run = 0;
    while (advance(r, SKIP_RAY2, threshold, &k, &run))
        for (; k < run; k++) {
            (*drawn)++;
            if (demip_ray2_stops(sample_at(r, k), threshold))
                return k;
        }
    return -1;
}

/* Ray 1 then (DEMIP) ray 2.  Ray 1 first runs with m_max = guess: every
 * sample above the guess is still drawn, in order, so if one exists the
 * result (m_max, k_max) is exactly the reference's; if none does, the ray
 * runs again from m_max = 0.  Ray 2's stop is read from ray 1's records
 * when they can tell (stop_from_records) and traced otherwise; either way it
 * is the reference's.  Returns m_max. */
static float trace_mip_demip(const fast_ray_t *r, float guess, float rgb[3],
                             raycast_counts_t *counts)
{
    mip_ray_t ray;
    records_t rec;
    mip_ray_init(&ray);
    float g = guess > 0.0f && guess < 1.0f ? guess : 0.0f;
    ray.m_max = g;
    long all, drawn = ray1(r, &ray, &all, &rec);
    if (ray.k_max < 0 && g > 0.0f) {
        counts->samples_retraced += (uint64_t)drawn;
        counts->samples += (uint64_t)drawn;
        mip_ray_init(&ray);
        g = 0.0f;
        drawn = ray1(r, &ray, &all, &rec);
    }
    if (r->f->mode == BLEND_MIP || ray.k_max < 0) {
        counts->samples += (uint64_t)drawn;
        counts->samples_skipped += (uint64_t)(all - drawn);
        rgb[0] = rgb[1] = rgb[2] = ray.m_max;
        return ray.m_max;
    }
    float threshold = demip_ray2_threshold(ray.m_max, r->f->eps);
    long j = stop_from_records(&rec, g, threshold);
    if (j < 0)
        j = ray2(r, threshold, &drawn);
    PP5_ASSERT(j >= 0 && j <= ray.k_max, "DEMIP ray 2 passed the maximum");
    all += j + 1;
    bool occluded = false;
    if (r->f->reading == DEMIP_READING_B)
        for (long k = j + 1; k < ray.k_max; k++) {
            drawn++;
            all++;
            if (demip_is_gap(sample_at(r, k), threshold)) {
                occluded = true;
                break;
            }
        }
    counts->samples += (uint64_t)drawn;
    counts->samples_skipped += (uint64_t)(all - drawn);
    const blend_geom_t *gm = r->g;
    float t_hit = gm->t0 + (float)j * gm->base;
    demip_colour(r->f, gm->o, gm->d, gm->t0, t_hit, ray.m_max, occluded, rgb);
    return ray.m_max;
}

float blend_trace_fast(const blend_ctx_t *c, float px, float py, int level2d, float guess,
                       float rgb[3], raycast_counts_t *counts)
{
    blend_geom_t g;
    counts->rays++;
    rgb[0] = rgb[1] = rgb[2] = 0.0f;
    if (!blend_geom_begin(c, px, py, level2d, &g) || g.positions <= 0)
        return 0.0f;
    fast_ray_t r;
    memset(&r, 0, sizeof r);
    r.f = &c->frame;
    r.g = &g;
    r.n = (int)g.level3d;
    r.L = &c->pyr->level[r.n];
    r.scale = (float)(1 << r.n);
    r.inv_scale = 1.0f / r.scale;
    r.inv_base = 1.0f / g.base;
    r.dims[0] = r.L->nx;
    r.dims[1] = r.L->ny;
    r.dims[2] = r.L->nz;
    for (int j = 0; j < SCALAR_THRESHOLDS; j++)
        r.threshold_material[j] = blend_material(&c->frame.window, c->pyr->threshold[j]);
    for (int a = 0; a < 4; a++) {
        bool axis = a < 3;
        if (axis)
            r.inv_dv[a] = g.dv[a] != 0.0f ? 1.0f / g.dv[a] : 0.0f;
        r.ov_v[a] = axis ? g.ov[a] : 0.0f;
        r.dv_v[a] = axis ? g.dv[a] : 0.0f;
        r.top_v[a] = axis ? r.dims[a] - 1 : 0;
    }
    if (c->frame.mode == BLEND_MIDA) {
        trace_mida(&r, rgb, counts);
        return 0.0f;
    }
    return trace_mip_demip(&r, guess, rgb, counts);
}
