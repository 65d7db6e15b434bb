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

typedef enum { SKIP_RAY1, SKIP_RAY2, SKIP_EMPTY } skip_rule_t;

typedef struct {
    const blend_frame_t *f;
    const scalar_level_t *L;
    const blend_geom_t *g;
    int n;                        /* 3D level read */
    float scale, inv_scale, inv_base;
    float inv_dv[3];
    int dims[3];
} fast_ray_t;

static inline bool skippable(const fast_ray_t *r, skip_rule_t rule, float param, float bound)
{
    float m = blend_material(&r->f->window, bound);
    if (rule == SKIP_RAY1) {
        mip_ray_t state = {param, 0};
        return mip_ray_can_skip(&state, m);
    }
    if (rule == SKIP_RAY2)
        return !demip_ray2_stops(m, param);
    return m <= 0.0f;
}

/* Level-0 position, level coordinates, floors and clamped cell of position k. */
static inline void position_cell(const fast_ray_t *r, long k, float q[3], int fl[3], int c[3])
{
    const blend_geom_t *g = r->g;
    float t = g->t0 + (float)k * g->base;
    float p[3] = {g->ov[0] + t * g->dv[0], g->ov[1] + t * g->dv[1], g->ov[2] + t * g->dv[2]};
    scalar_level_coords(p, r->n, q, fl);
    for (int a = 0; a < 3; a++)
        c[a] = fl[a] < 0 ? 0 : (fl[a] >= r->dims[a] ? r->dims[a] - 1 : fl[a]);
}

/* Parameter where the ray leaves the node of height h holding cell c
 * (INFINITY when it never does: faces on the grid's edge hold the clamped
 * cells beyond); the node's cell range [first, last) per axis. */
static inline float node_exit(const fast_ray_t *r, const int c[3], int h, int first[3],
                              int last[3])
{
    float t_exit = INFINITY;
    for (int a = 0; a < 3; a++) {
        first[a] = (c[a] >> h) << h;
        last[a] = first[a] + (1 << h);
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

/* From position *k, passes the positions `rule` lets the ray skip; returns
 * true with *k at the next position to draw (its coordinates in q, fl), or
 * false when the window [0, positions) is exhausted. */
static bool advance(const fast_ray_t *r, skip_rule_t rule, float param, long *k_io, float q[3],
                    int fl[3])
{
    const scalar_level_t *L = r->L;
    const long k_end = r->g->positions;
    long k = *k_io;
    while (k < k_end) {
        int c[3];
        position_cell(r, k, q, fl, c);
        if (!skippable(r, rule, param, scalar_node_max(L, 0, c[0], c[1], c[2]))) {
            *k_io = k;
            return true;
        }
        int h = 0;
        while (h + 1 < L->heights &&
               skippable(r, rule, param, scalar_node_max(L, h + 1, c[0], c[1], c[2])))
            h++;
        if (h == 0) {
            k++;
            continue;
        }
        int first[3], last[3];
        float t_exit = node_exit(r, c, h, first, last);
        if (t_exit == INFINITY) {
            k = k_end;
            break;
        }
        /* First position at or beyond a hair inside the exit, checked below. */
        float x = (t_exit - 1e-3f - r->g->t0) * r->inv_base;
        long kc = x >= (float)k_end ? k_end : (x <= 0.0f ? 0 : -(long)mip3d_floor_int(-x));
        if (kc > k + 1) {
            float q2[3];
            int fl2[3], c2[3];
            position_cell(r, kc - 1, q2, fl2, c2);
            bool inside = true;
            for (int a = 0; a < 3; a++)
                inside = inside && c2[a] >= first[a] && c2[a] < last[a];
            k = inside ? kc : k + 1;
        } else {
            k++;
        }
    }
    *k_io = k;
    return false;
}

static float draw(const fast_ray_t *r, const float q[3], const int fl[3])
{
    return blend_material(&r->f->window, scalar_trilerp(r->L, q, fl));
}

static void trace_mida(const fast_ray_t *r, float rgb[3], raycast_counts_t *counts)
{
    mida_ray_t s;
    mida_ray_init(&s);
    long k = 0, drawn = 0, all = r->g->positions;
    float q[3];
    int fl[3];
    while (advance(r, SKIP_EMPTY, 0.0f, &k, q, fl)) {
        float m = draw(r, q, fl);
        drawn++;
        if (mida_ray_sample(&s, m, mida_opacity(m, r->g->base), r->f->early_termination)) {
            all = k + 1;
            break;
        }
        k++;
    }
    counts->samples += (uint64_t)drawn;
    counts->samples_skipped += (uint64_t)(all - drawn);
    rgb[0] = rgb[1] = rgb[2] = s.colour;
}

static void trace_mip_demip(const fast_ray_t *r, float rgb[3], raycast_counts_t *counts)
{
    mip_ray_t ray;
    mip_ray_init(&ray);
    long k = 0, drawn = 0, all = r->g->positions;
    float q[3];
    int fl[3];
    while (advance(r, SKIP_RAY1, ray.m_max, &k, q, fl)) {
        drawn++;
        if (mip_ray_sample(&ray, k, draw(r, q, fl))) {
            all = k + 1;          /* the reference stops here too */
            break;
        }
        k++;
    }
    if (r->f->mode == BLEND_MIP || ray.k_max < 0) {
        counts->samples += (uint64_t)drawn;
        counts->samples_skipped += (uint64_t)(all - drawn);
        rgb[0] = rgb[1] = rgb[2] = ray.m_max;
        return;
    }
    float threshold = demip_ray2_threshold(ray.m_max, r->f->eps);
    long j = 0;
    while (advance(r, SKIP_RAY2, threshold, &j, q, fl)) {
        drawn++;
        if (demip_ray2_stops(draw(r, q, fl), threshold))
            break;
        j++;
    }
    PP5_ASSERT(j <= ray.k_max, "DEMIP ray 2 passed the maximum");
    all += j + 1;
    counts->samples += (uint64_t)drawn;
    counts->samples_skipped += (uint64_t)(all - drawn);
    const blend_geom_t *g = r->g;
    float t_hit = g->t0 + (float)j * g->base;
    demip_colour(r->f, g->o, g->d, g->t0, t_hit, ray.m_max, j < ray.k_max, rgb);
}

void blend_trace_fast(const blend_ctx_t *c, float px, float py, int level2d, float rgb[3],
                      raycast_counts_t *counts)
{
    blend_geom_t g;
    counts->rays++;
    rgb[0] = rgb[1] = rgb[2] = 0.0f;
    if (!blend_geom_begin(c, px, py, level2d, &g) || g.positions <= 0)
        return;
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
    for (int a = 0; a < 3; a++)
        r.inv_dv[a] = g.dv[a] != 0.0f ? 1.0f / g.dv[a] : 0.0f;
    if (c->frame.mode == BLEND_MIDA)
        trace_mida(&r, rgb, counts);
    else
        trace_mip_demip(&r, rgb, counts);
}
