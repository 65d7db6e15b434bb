/* blend_trace_fast.c: the skipping tracer's walk along one parallel MIP,
 * DEMIP or MIDA ray.  It visits the reference's sample positions
 * (t0 + k * base), draws a position exactly as the reference does (same
 * float expressions), and passes positions only where a bound
 * (scalar_pyramid.h) proves that no sample there can change the ray
 * (skip_rule_t).  Material is monotone in the value, so a bound on values
 * bounds materials; a node's bound is at least each of its cells', so a
 * skippable node holds only skippable cells; a brick at chessboard distance
 * d from the nearest brick above threshold j means every brick within d - 1
 * is at most threshold j.  A jump over a box of cells is accepted only after
 * checking that the last position it passes lies in the box: every cell
 * coordinate of position k is a monotone function of k (each float
 * operation in it is), so first and last inside the box means all between
 * are.  Drawing a position that could have been skipped is always allowed,
 * so a brick that may matter is drawn whole, without per-cell tests. */
#include "blend_fast.h"

#include <math.h>
#include <string.h>

void fast_level_init(const blend_ctx_t *c, const blend_geom_t *g, fast_level_t *lv)
{
    memset(lv, 0, sizeof *lv);
    lv->f = &c->frame;
    lv->n = (int)g->level3d;
    lv->L = &c->pyr->level[lv->n];
    lv->dims[0] = lv->L->nx;
    lv->dims[1] = lv->L->ny;
    lv->dims[2] = lv->L->nz;
    lv->base = g->base;
    lv->inv_base = 1.0f / g->base;
    lv->scale = (float)(1 << lv->n);
    lv->inv_scale = 1.0f / lv->scale;
    for (int a = 0; a < 4; a++) {
        bool axis = a < 3;
        if (axis) {
            lv->dv[a] = g->dv[a];
            lv->inv_dv[a] = g->dv[a] != 0.0f ? 1.0f / g->dv[a] : 0.0f;
        }
        lv->dv_v[a] = axis ? g->dv[a] : 0.0f;
        lv->top_v[a] = axis ? lv->dims[a] - 1 : 0;
    }
    for (int j = 0; j < SCALAR_THRESHOLDS; j++)
        lv->threshold_material[j] = blend_material(&c->frame.window, c->pyr->threshold[j]);
}

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

int fast_threshold_level(const fast_level_t *lv, skip_rule_t rule, float param)
{
    int j = SCALAR_THRESHOLDS - 1;
    while (j >= 0 && !skippable_material(rule, param, lv->threshold_material[j]))
        j--;
    return j;
}

static inline v4i position_cell(const fast_ray_t *r, long k, v4f *qv, v4i *flv)
{
    return fast_cell(r->lv, r->ov_v, r->g.t0 + (float)k * r->lv->base, qv, flv);
}

void fast_brick_cube(const int c[3], int d, int first[3], int last[3])
{
    const int s = 1 << SCALAR_BRICK_SHIFT;
    for (int a = 0; a < 3; a++) {
        int b = c[a] >> SCALAR_BRICK_SHIFT;
        first[a] = (b - (d - 1)) * s;
        last[a] = (b + d) * s;
    }
}

static inline bool in_box(const fast_ray_t *r, long k, const int first[3], const int last[3])
{
    v4f qv;
    v4i flv, c = position_cell(r, k, &qv, &flv);
    return c[0] >= first[0] && c[0] < last[0] && c[1] >= first[1] && c[1] < last[1] &&
           c[2] >= first[2] && c[2] < last[2];
}

/* First position at or beyond the exit parameter, at least k + 1 and at most
 * the window's end. */
static inline long first_beyond(const fast_ray_t *r, long k, float t_exit)
{
    const long k_end = r->g.positions;
    float x = (t_exit - r->g.t0) * r->lv->inv_base;
    long kc = !(x < (float)k_end) ? k_end : (x <= 0.0f ? 0 : -(long)mip3d_floor_int(-x));
    return kc > k ? kc : k + 1;
}

/* Position k lies in the box [first, last) whose positions may all be
 * skipped: returns the first position beyond it (or one inside it, which is
 * merely visited again), checked with the exact cell test of the last
 * position passed. */
static long jump_box(const fast_ray_t *r, long k, const int first[3], const int last[3])
{
    float t_exit = fast_box_exit(r->lv, r->ov_v, first, last);
    if (t_exit == INFINITY)
        return r->g.positions;
    long kc = first_beyond(r, k, t_exit);
    /* Rounding may put position kc - 1 just outside: then try one fewer. */
    if (kc > k + 1 && !in_box(r, kc - 1, first, last))
        kc--;
    return kc > k + 1 && !in_box(r, kc - 1, first, last) ? k + 1 : kc;
}

void fast_ray_start(fast_ray_t *r, skip_rule_t rule, float param)
{
    r->rule = rule;
    r->k = 0;
    r->drawn = 0;
    r->all = r->g.positions;
    r->stop = -1;
    r->done = r->g.positions <= 0;
    r->threshold = rule == SKIP_RAY2 ? param : 0.0f;
    mip_ray_init(&r->mip);
    if (rule == SKIP_RAY1)
        r->mip.m_max = param;
    r->rec.count = 0;
    mida_ray_init(&r->mida);
}

/* Feeds the sample at position k to the ray's rule; true when it stops. */
static inline bool feed(fast_ray_t *r, long k, float m)
{
    r->drawn++;
    if (r->rule == SKIP_RAY1) {
        float before = r->mip.m_max;
        bool done = mip_ray_sample(&r->mip, k, m);
        if (r->mip.m_max > before) {
            r->rec.k[r->rec.count % BLEND_RECORDS] = k;
            r->rec.m[r->rec.count % BLEND_RECORDS] = r->mip.m_max;
            r->rec.count++;
        }
        return done;
    }
    if (r->rule == SKIP_RAY2) {
        if (!demip_ray2_stops(m, r->threshold))
            return false;
        r->stop = k;
        return true;
    }
    return mida_ray_sample(&r->mida, m, mida_opacity(m, r->lv->base), r->lv->f->early_termination);
}

float fast_sample(const fast_ray_t *r, long k)
{
    v4f qv;
    v4i flv;
    position_cell(r, k, &qv, &flv);
    float q[3] = {qv[0], qv[1], qv[2]};
    int fl[3] = {flv[0], flv[1], flv[2]};
    return blend_material(&r->lv->f->window, scalar_trilerp(r->lv->L, q, fl));
}

/* Draws positions [k, end) (all of them: see the top), stopping early when
 * the rule says so. */
static void draw_run(fast_ray_t *r, long end)
{
    for (long k = r->k; k < end; k++) {
        if (feed(r, k, fast_sample(r, k))) {
            r->all = k + 1;       /* the reference stops here too */
            r->k = k + 1;
            r->done = true;
            return;
        }
    }
    r->k = end;
}

void fast_ray_step(fast_ray_t *r)
{
    const fast_level_t *lv = r->lv;
    const scalar_level_t *L = lv->L;
    const int bs = SCALAR_BRICK_SHIFT, top = L->heights - 1 < bs ? L->heights - 1 : bs;
    if (r->k >= r->g.positions) {
        r->done = true;
        return;
    }
    float param = fast_ray_param(r);
    v4f qv;
    v4i flv, cv = position_cell(r, r->k, &qv, &flv);
    int c[3] = {cv[0], cv[1], cv[2]}, first[3], last[3];
    int j = L->brick_dist ? fast_threshold_level(lv, r->rule, param) : -1;
    int d = j >= 0 ? scalar_brick_dist(L, j, c[0], c[1], c[2]) : 0;
    if (d > 0) {
        fast_brick_cube(c, d, first, last);
        r->k = jump_box(r, r->k, first, last);
        return;
    }
    for (int a = 0; a < 3; a++) {
        first[a] = (c[a] >> top) << top;
        last[a] = first[a] + (1 << top);
    }
    float bound = scalar_node_max(L, top, c[0], c[1], c[2]);
    if (skippable_material(r->rule, param, blend_material(&lv->f->window, bound))) {
        r->k = jump_box(r, r->k, first, last);
        return;
    }
    /* The brick may hold a sample that matters: draw its positions. */
    float t_exit = fast_box_exit(lv, r->ov_v, first, last);
    draw_run(r, t_exit == INFINITY ? r->g.positions : first_beyond(r, r->k, t_exit));
}

/* The first sample with m >= threshold (> 0) is a record of ray 1 whenever
 * threshold exceeds ray 1's starting maximum g (or g = 0): every sample
 * before it is below threshold, so the running maximum there is below it
 * too, and the sample raises it.  Records rise, so it is the first record
 * that stops ray 2, provided the oldest record kept does not already. */
long fast_stop_from_records(const records_t *rec, float g, float threshold)
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
