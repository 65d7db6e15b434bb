/* blend_trace_packet.c: the skipping tracer for a batch of parallel MIP,
 * DEMIP or MIDA rays of one 2D level: packets that pass empty space
 * together, ray 1's threshold guess, and ray 2 read from ray 1's records.
 *
 * Packets.  Rays of one level share their direction, so at equal t they sit
 * at fixed offsets from one another.  When every ray of the batch lies
 * within PACKET_RADIUS level cells of the batch's centre line (per axis),
 * the cell of any ray at parameter t is within 3 cells of the centre's, so
 * its brick (4 cells) is at most one brick from the centre's.  If the
 * centre's brick is at distance d >= 2 from the nearest brick above the
 * threshold level every ray may skip at, each ray's brick stays within
 * d - 1 of it as long as the centre stays within d - 2: the whole batch
 * passes that stretch in one step, with no per-ray cell tests (the slack
 * of one cell per side absorbs any rounding).  Otherwise every ray walks
 * alone up to where the centre leaves its current brick, and the batch
 * tries again.  Per ray, samples are still drawn in order, so the result is
 * exactly the lone walk's, which is exactly the reference's (tested). */
#include "blend_fast.h"

#include <math.h>
#include <string.h>

#define PACKET_RADIUS 2.9f

/* min and max of numbers known not to be NaN (fminf/fmaxf are library calls
 * at -O2). */
static inline float min_f(float a, float b)
{
    return b < a ? b : a;
}

static inline float max_f(float a, float b)
{
    return b > a ? b : a;
}

/* The centre line of the used rays, or false when they are too far apart. */
static bool packet_centre(const fast_ray_t *rays, const bool *use, int count, v4f *centre)
{
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    int used = 0;
    const fast_level_t *lv = NULL;
    for (int i = 0; i < count; i++) {
        if (!use[i])
            continue;
        used++;
        lv = rays[i].lv;
        for (int a = 0; a < 3; a++) {
            lo[a] = min_f(lo[a], rays[i].g.ov[a]);
            hi[a] = max_f(hi[a], rays[i].g.ov[a]);
        }
    }
    if (used < 2)
        return false;
    for (int a = 0; a < 3; a++)
        if (!(0.5f * (hi[a] - lo[a]) * lv->inv_scale <= PACKET_RADIUS))
            return false;
    *centre = (v4f){0.5f * (lo[0] + hi[0]), 0.5f * (lo[1] + hi[1]), 0.5f * (lo[2] + hi[2]), 0};
    return true;
}

/* Every used ray passes its positions before t_exit. */
static void packet_skip(fast_ray_t *rays, const bool *use, int count, float t_exit)
{
    for (int i = 0; i < count; i++) {
        fast_ray_t *r = &rays[i];
        if (!use[i] || r->done)
            continue;
        long k_end = r->g.positions;
        float x = (t_exit - r->g.t0) * r->lv->inv_base;
        long kc = t_exit == INFINITY || !(x < (float)k_end)
                      ? k_end
                      : (x <= 0.0f ? 0 : -(long)mip3d_floor_int(-x));
        if (kc > r->k)
            r->k = kc;
        if (r->k >= k_end)
            r->done = true;
    }
}

/* Each used ray walks alone over its positions before t_w. */
static void packet_window(fast_ray_t *rays, const bool *use, int count, float t_w)
{
    for (int i = 0; i < count; i++) {
        fast_ray_t *r = &rays[i];
        while (use[i] && !r->done && r->g.t0 + (float)r->k * r->lv->base < t_w)
            fast_ray_step(r);
    }
}

/* Walks the used rays (all under the same rule) to their ends. */
static void walk(fast_ray_t *rays, const bool *use, int count)
{
    v4f centre;
    if (!packet_centre(rays, use, count, &centre)) {
        for (int i = 0; i < count; i++)
            if (use[i])
                fast_ray_run(&rays[i]);
        return;
    }
    const fast_level_t *lv = NULL;
    float t_cur = INFINITY;
    for (int i = 0; i < count; i++)
        if (use[i]) {
            lv = rays[i].lv;
            t_cur = min_f(t_cur, rays[i].g.t0 + (float)rays[i].k * lv->base);
        }
    const scalar_level_t *L = lv->L;
    for (;;) {
        skip_rule_t rule = SKIP_EMPTY;
        float param = INFINITY;
        bool live = false;
        for (int i = 0; i < count; i++)
            if (use[i] && !rays[i].done) {
                live = true;
                rule = rays[i].rule;
                param = min_f(param, fast_ray_param(&rays[i]));
            }
        if (!live)
            return;
        v4f qv;
        v4i flv, cv = fast_cell(lv, centre, t_cur, &qv, &flv);
        int c[3] = {cv[0], cv[1], cv[2]}, first[3], last[3];
        int j = L->brick_dist ? fast_threshold_level(lv, rule, param) : -1;
        int d = j >= 0 ? scalar_brick_dist(L, j, c[0], c[1], c[2]) : 0;
        if (d >= 2) {
            fast_brick_cube(c, d - 1, first, last);       /* bricks within d - 2 */
            float t_exit = fast_box_exit(lv, centre, first, last);
            if (t_exit > t_cur) {
                packet_skip(rays, use, count, t_exit);
                if (t_exit == INFINITY)
                    return;
                t_cur = t_exit;
                continue;
            }
        }
        fast_brick_cube(c, 1, first, last);               /* the centre's brick */
        float t_w = fast_box_exit(lv, centre, first, last);
        if (!(t_w > t_cur + lv->base))
            t_w = t_cur + lv->base;
        packet_window(rays, use, count, t_w);
        t_cur = t_w;
    }
}

static void count_ray(const fast_ray_t *r, raycast_counts_t *counts)
{
    counts->samples += (uint64_t)r->drawn;
    counts->samples_skipped += (uint64_t)(r->all - r->drawn);
}

/* Ray 2, reading B's gap test and the colour of one DEMIP ray after ray 1. */
static void finish_demip(fast_ray_t *r, float g, float rgb[3], raycast_counts_t *counts)
{
    long drawn = r->drawn, all = r->all;
    float threshold = demip_ray2_threshold(r->mip.m_max, r->lv->f->eps);
    long j = fast_stop_from_records(&r->rec, g, threshold);
    mip_ray_t ray1 = r->mip;
    if (j < 0) {
        fast_ray_start(r, SKIP_RAY2, threshold);
        fast_ray_run(r);
        j = r->stop;
        drawn += r->drawn;
    }
    r->mip = ray1;
    fast_demip_finish(r, j, drawn, all, rgb, counts);
}

void fast_demip_finish(const fast_ray_t *r, long j, long drawn, long all, float rgb[3],
                       raycast_counts_t *counts)
{
    const mip_ray_t *ray1 = &r->mip;
    float threshold = demip_ray2_threshold(ray1->m_max, r->lv->f->eps);
    PP5_ASSERT(j >= 0 && j <= ray1->k_max, "DEMIP ray 2 passed the maximum");
    all += j + 1;
    bool occluded = false;
    if (r->lv->f->reading == DEMIP_READING_B)
        for (long k = j + 1; k < ray1->k_max; k++) {
            drawn++;
            all++;
            if (demip_is_gap(fast_sample(r, k), threshold)) {
                occluded = true;
                break;
            }
        }
    counts->samples += (uint64_t)drawn;
    counts->samples_skipped += (uint64_t)(all - drawn);
    const blend_geom_t *gm = &r->g;
    float t_hit = gm->t0 + (float)j * gm->base;
    demip_colour(r->lv->f, gm->o, gm->d, gm->t0, t_hit, ray1->m_max, occluded, rgb);
}

/* Ray 1 of MIP/DEMIP from the guess, again from 0 where nothing exceeded
 * it (every sample above the guess is drawn in order, so when one exists
 * m_max and k_max are exactly the reference's). */
static float trace_mip_demip(fast_ray_t *rays, const bool *use, int count, float guess,
                             float (*rgb)[3], raycast_counts_t *counts)
{
    float last = 0.0f;
    float g = guess > 0.0f && guess < 1.0f ? guess : 0.0f;
    for (int i = 0; i < count; i++)
        if (use[i])
            fast_ray_start(&rays[i], SKIP_RAY1, g);
    walk(rays, use, count);
    for (int i = 0; i < count; i++) {
        fast_ray_t *r = &rays[i];
        if (!use[i])
            continue;
        float gi = g;
        if (r->mip.k_max < 0 && g > 0.0f) {
            counts->samples_retraced += (uint64_t)r->drawn;
            counts->samples += (uint64_t)r->drawn;
            fast_ray_start(r, SKIP_RAY1, 0.0f);
            fast_ray_run(r);
            gi = 0.0f;
        }
        last = r->mip.m_max;
        if (r->lv->f->mode == BLEND_MIP || r->mip.k_max < 0) {
            count_ray(r, counts);
            rgb[i][0] = rgb[i][1] = rgb[i][2] = r->mip.m_max;
        } else {
            finish_demip(r, gi, rgb[i], counts);
        }
    }
    return last;
}

float blend_trace_fast_batch(const blend_ctx_t *c, int count, const float *px, const float *py,
                             int level2d, float guess, float (*rgb)[3], raycast_counts_t *counts)
{
    fast_ray_t rays[BLEND_BATCH];
    bool use[BLEND_BATCH];
    fast_level_t lv;
    bool have_level = false;
    count = count < BLEND_BATCH ? count : BLEND_BATCH;
    for (int i = 0; i < count; i++) {
        counts->rays++;
        rgb[i][0] = rgb[i][1] = rgb[i][2] = 0.0f;
        fast_ray_t *r = &rays[i];
        memset(r, 0, sizeof *r);
        use[i] = blend_geom_begin(c, px[i], py[i], level2d, &r->g) && r->g.positions > 0;
        if (!use[i])
            continue;
        if (!have_level)
            fast_level_init(c, &r->g, &lv);
        have_level = true;
        r->lv = &lv;
        r->ov_v = (v4f){r->g.ov[0], r->g.ov[1], r->g.ov[2], 0.0f};
    }
    if (!have_level)
        return 0.0f;
    if (c->frame.mode == BLEND_MIDA) {
        for (int i = 0; i < count; i++)
            if (use[i])
                fast_ray_start(&rays[i], SKIP_EMPTY, 0.0f);
        walk(rays, use, count);
        for (int i = 0; i < count; i++)
            if (use[i]) {
                count_ray(&rays[i], counts);
                rgb[i][0] = rgb[i][1] = rgb[i][2] = rays[i].mida.colour;
            }
        return 0.0f;
    }
    return trace_mip_demip(rays, use, count, guess, rgb, counts);
}

float blend_trace_fast(const blend_ctx_t *c, float px, float py, int level2d, float guess,
                       float rgb[3], raycast_counts_t *counts)
{
    float out[1][3];
    float m = blend_trace_fast_batch(c, 1, &px, &py, level2d, guess, out, counts);
    memcpy(rgb, out[0], sizeof out[0]);
    return m;
}
