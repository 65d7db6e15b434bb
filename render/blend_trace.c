/* blend_trace.c: ray set-up and the reference tracer for MIP, DEMIP and MIDA
 * (every sample position drawn; see blend_trace.h). */
#include "blend_trace.h"

#include <math.h>
#include <string.h>

#include "raycast_internal.h"

void blend_ctx_init(blend_ctx_t *c, const scalar_pyramid_t *p, const camera_t *cam,
                    const view_params_t *v, const blend_settings_t *b)
{
    memset(c, 0, sizeof *c);
    c->pyr = p;
    c->camera = cam;
    c->sample_step = v->sample_step > 0.0f ? v->sample_step : 1.0f;
    c->level3d_offset = log2f(c->sample_step);
    c->skipping = v->use_octree;
    blend_frame_init(&c->frame, b, cam, p->min_value, p->max_value, v->early_termination);
}

float blend_level3d(const blend_ctx_t *c, int level2d)
{
    float top = (float)(c->pyr->levels - 1);
    float level3d = log2f(c->sample_step * (float)(1 << level2d)) - c->level3d_offset;
    return level3d < 0.0f ? 0.0f : (level3d > top ? top : level3d);
}

bool blend_geom_begin(const blend_ctx_t *c, float px, float py, int level2d, blend_geom_t *g)
{
    const camera_t *cam = c->camera;
    memset(g, 0, sizeof *g);
    g->perspective = cam->projection == PROJECTION_PERSPECTIVE;
    camera_ray(cam, px, py, g->o, g->d);
    if (!raycast_clip_box(g->o, g->d, cam->box_hi, &g->t0, &g->t1))
        return false;
    for (int a = 0; a < 3; a++) {
        g->ov[a] = g->o[a] * cam->inv_spacing[a];
        g->dv[a] = g->d[a] * cam->inv_spacing[a];
    }
    /* The compositing tracer's lattice (raycast.c ray_begin). */
    g->base = c->sample_step * (float)(1 << level2d);
    g->growth = 1.0f + g->base / cam->eye_distance;
    g->t_start = g->t0;
    if (g->perspective && g->t_start < 1e-3f)
        g->t_start = 1e-3f;
    g->level3d = blend_level3d(c, level2d);
    g->positions = g->perspective ? -1 : raycast_parallel_positions(g->t0, g->t1, g->base);
    return true;
}

/* The reference's walk over sample positions: index k at parameter t. */
typedef struct {
    long k;
    float t;
} walk_t;

static void walk_start(const blend_geom_t *g, walk_t *w)
{
    w->k = 0;
    w->t = g->t_start;
}

static bool walk_valid(const blend_geom_t *g, const walk_t *w)
{
    return w->t <= g->t1;
}

static void walk_next(const blend_geom_t *g, walk_t *w)
{
    w->k++;
    w->t = g->perspective ? w->t * g->growth : g->t0 + (float)w->k * g->base;
}

/* Material of the sample at w, and the object-space length it stands for. */
static float walk_material(const blend_ctx_t *c, const blend_geom_t *g, const walk_t *w,
                           float *spacing)
{
    float level3d = g->level3d, sp = g->base;
    if (g->perspective) {
        float top = (float)(c->pyr->levels - 1);
        sp = w->t * (g->growth - 1.0f);
        level3d = log2f(sp) - c->level3d_offset;
        level3d = level3d < 0.0f ? 0.0f : (level3d > top ? top : level3d);
    }
    float p[3] = {g->ov[0] + w->t * g->dv[0], g->ov[1] + w->t * g->dv[1],
                  g->ov[2] + w->t * g->dv[2]};
    *spacing = sp;
    return blend_material(&c->frame.window, scalar_pyramid_sample(c->pyr, level3d, p));
}

static void set_grey(float rgb[3], float v)
{
    rgb[0] = rgb[1] = rgb[2] = v;
}

static void reference_mida(const blend_ctx_t *c, blend_ray_info_t *info)
{
    const blend_geom_t *g = &info->geom;
    mida_ray_t s;
    mida_ray_init(&s);
    walk_t w;
    float sp;
    for (walk_start(g, &w); walk_valid(g, &w); walk_next(g, &w)) {
        info->samples++;
        float m = walk_material(c, g, &w, &sp);
        if (mida_ray_sample(&s, m, mida_opacity(m, sp), c->frame.early_termination))
            break;
    }
    set_grey(info->rgb, s.colour);
}

void blend_trace_reference_info(const blend_ctx_t *c, float px, float py, int level2d,
                                blend_ray_info_t *info)
{
    memset(info, 0, sizeof *info);
    info->k_max = info->k_stop = -1;
    if (!blend_geom_begin(c, px, py, level2d, &info->geom))
        return;
    info->hit_box = true;
    const blend_geom_t *g = &info->geom;
    const blend_frame_t *f = &c->frame;
    if (f->mode == BLEND_MIDA) {
        reference_mida(c, info);
        return;
    }
    mip_ray_t r;
    mip_ray_init(&r);
    walk_t w;
    float sp;
    for (walk_start(g, &w); walk_valid(g, &w); walk_next(g, &w)) {
        info->samples++;
        if (mip_ray_sample(&r, w.k, walk_material(c, g, &w, &sp)))
            break;
    }
    info->m_max = r.m_max;
    info->k_max = r.k_max;
    if (f->mode != BLEND_DEMIP || r.k_max < 0) {
        set_grey(info->rgb, r.m_max);
        return;
    }
    float threshold = demip_ray2_threshold(r.m_max, f->eps);
    for (walk_start(g, &w); walk_valid(g, &w); walk_next(g, &w)) {
        info->samples++;
        if (demip_ray2_stops(walk_material(c, g, &w, &sp), threshold))
            break;
    }
    PP5_ASSERT(walk_valid(g, &w) && w.k <= r.k_max, "DEMIP ray 2 passed the maximum");
    info->k_stop = w.k;
    info->t_hit = w.t;
    if (f->reading == DEMIP_READING_B)
        for (walk_next(g, &w); w.k < r.k_max; walk_next(g, &w)) {
            info->samples++;
            if (demip_is_gap(walk_material(c, g, &w, &sp), threshold)) {
                info->occluded = true;
                break;
            }
        }
    demip_colour(f, g->o, g->d, g->t0, info->t_hit, r.m_max, info->occluded, info->rgb);
}

void blend_trace_reference(const blend_ctx_t *c, float px, float py, int level2d, float rgb[3],
                           raycast_counts_t *counts)
{
    blend_ray_info_t info;
    blend_trace_reference_info(c, px, py, level2d, &info);
    counts->rays++;
    counts->samples += info.samples;
    memcpy(rgb, info.rgb, sizeof info.rgb);
}

long blend_ray_materials(const blend_ctx_t *c, float px, float py, int level2d, float *m,
                         long max)
{
    blend_geom_t g;
    if (!blend_geom_begin(c, px, py, level2d, &g))
        return 0;
    if (g.perspective)
        return -1;
    walk_t w;
    float sp;
    for (walk_start(&g, &w); walk_valid(&g, &w); walk_next(&g, &w))
        if (w.k < max)
            m[w.k] = walk_material(c, &g, &w, &sp);
    return w.k;
}

void blend_trace_batch(const blend_ctx_t *c, int count, const float *px, const float *py,
                       int level2d, float (*rgb)[3], float *guess_io, raycast_counts_t *counts)
{
    if (c->skipping && c->camera->projection == PROJECTION_PARALLEL) {
        /* DEMIP guesses below its neighbour's ray-2 threshold, so that ray 2
         * can be read from ray 1's records (blend_trace_fast.c). */
        float eps = c->frame.mode == BLEND_DEMIP ? c->frame.eps : 0.0f;
        float m = blend_trace_fast_batch(c, count, px, py, level2d, guess_io ? *guess_io : 0.0f,
                                         rgb, counts);
        if (guess_io)
            *guess_io = BLEND_GUESS_FRACTION * (m - eps);
        return;
    }
    for (int i = 0; i < count; i++)
        blend_trace_reference(c, px[i], py[i], level2d, rgb[i], counts);
}
