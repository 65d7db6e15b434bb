/* raycast.c: camera setup and TraceRay (sampling, shading, compositing,
 * early termination, octree skipping). */
#include "raycast.h"

#include "raycast_internal.h"
#include "raycast_parallel.h"

#include <math.h>
#include <string.h>

void view_defaults(view_params_t *v)
{
    memset(v, 0, sizeof *v);
    v->projection = PROJECTION_PARALLEL;
    v->zoom = 1.0f;
    v->eye_distance = 3.0f;
    v->sample_step = 1.0f;
    v->early_termination = 0.95f;
    v->use_octree = true;
    v->opacity_unit = 1.0f;
}

const char *projection_name(projection_t p)
{
    return p == PROJECTION_PERSPECTIVE ? "perspective" : "parallel";
}

static void rotate(float m[3][3], int axis, float deg)
{
    float r = deg * (float)(M_PI / 180.0);
    float c = cosf(r), s = sinf(r);
    float R[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    int i = (axis + 1) % 3, j = (axis + 2) % 3;
    R[i][i] = c;
    R[i][j] = -s;
    R[j][i] = s;
    R[j][j] = c;
    float out[3][3];
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            out[a][b] = R[a][0] * m[0][b] + R[a][1] * m[1][b] + R[a][2] * m[2][b];
    memcpy(m, out, sizeof out);
}

void view_basis(const view_params_t *v, float right[3], float down[3], float forward[3])
{
    /* Columns of M are the camera axes; M = Rz * Rx * Ry (Ry acts first). */
    float M[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    rotate(M, 1, v->rot_y_deg);
    rotate(M, 0, v->rot_x_deg);
    rotate(M, 2, v->rot_z_deg);
    for (int a = 0; a < 3; a++) {
        right[a] = M[a][0];
        down[a] = M[a][1];
        forward[a] = M[a][2];
    }
}

void camera_setup(camera_t *c, const view_params_t *v, const mip3d_t *m, int width, int height)
{
    memset(c, 0, sizeof *c);
    c->width = width;
    c->height = height;
    c->projection = v->projection;
    view_basis(v, c->right, c->down, c->forward);
    const mip3d_level_t *L = &m->level[0];
    int dims[3] = {L->nx, L->ny, L->nz};
    float extent = 0.0f, r2 = 0.0f;
    for (int a = 0; a < 3; a++) {
        c->box_hi[a] = (float)(dims[a] - 1) * m->spacing[a];
        c->centre[a] = 0.5f * c->box_hi[a];
        c->inv_spacing[a] = 1.0f / m->spacing[a];
        float e = (float)dims[a] * m->spacing[a];
        if (e > extent)
            extent = e;
        r2 += 0.25f * e * e;
    }
    c->radius = sqrtf(r2);
    int side = width < height ? width : height;
    float zoom = v->zoom > 0.0f ? v->zoom : 1.0f;
    c->pixel_size = extent / (float)side / zoom;
    c->eye_distance = (v->eye_distance > 1.0f ? v->eye_distance : 1.0f) * c->radius;
    for (int a = 0; a < 3; a++)
        c->eye[a] = c->centre[a] - c->eye_distance * c->forward[a];
}

void camera_ray(const camera_t *c, float px, float py, float origin[3], float dir[3])
{
    float dx = (px - 0.5f * (float)c->width) * c->pixel_size;
    float dy = (py - 0.5f * (float)c->height) * c->pixel_size;
    float P[3];
    for (int a = 0; a < 3; a++)
        P[a] = c->centre[a] + dx * c->right[a] + dy * c->down[a];
    if (c->projection == PROJECTION_PARALLEL) {
        for (int a = 0; a < 3; a++) {
            origin[a] = P[a] - (c->radius + 1.0f) * c->forward[a];
            dir[a] = c->forward[a];
        }
        return;
    }
    float d[3], n = 0.0f;
    for (int a = 0; a < 3; a++) {
        d[a] = P[a] - c->eye[a];
        n += d[a] * d[a];
    }
    n = sqrtf(n);
    for (int a = 0; a < 3; a++) {
        origin[a] = c->eye[a];
        dir[a] = d[a] / n;
    }
}

void raycast_ctx_init(raycast_ctx_t *r, const mip3d_t *m, const octree_t *o, const camera_t *c,
                      const shade_params_t *s, const view_params_t *v)
{
    memset(r, 0, sizeof *r);
    r->mip = m;
    r->octree = v->use_octree ? o : NULL;
    r->camera = c;
    r->shade = s;
    r->sample_step = v->sample_step > 0.0f ? v->sample_step : 1.0f;
    r->level3d_offset = log2f(r->sample_step);
    r->early_termination = v->early_termination;
    r->opacity_unit = v->opacity_unit > 0.0f ? v->opacity_unit : 1.0f;
    r->simd_walk = raycast_walk_avx2_supported();
    if (s->lighting == SHADE_MOVING_OBJECT) {
        /* Light given in eye space: carry it into object space for this view. */
        for (int a = 0; a < 3; a++)
            r->light_obj[a] = s->light_dir[0] * c->right[a] + s->light_dir[1] * c->down[a] +
                              s->light_dir[2] * c->forward[a];
    } else {
        memcpy(r->light_obj, s->light_dir, sizeof r->light_obj);
    }
    if (c->projection == PROJECTION_PERSPECTIVE)
        raycast_perspective_tables(r);
    for (int l = 0; l < RAYCAST_LUT_LEVELS; l++) {
        double spacing = (double)r->sample_step * (double)(1 << l) / (double)r->opacity_unit;
        for (int i = 0; i <= RAYCAST_LUT_SIZE; i++)
            r->alpha_lut[l][i] = (float)(1.0 - pow(1.0 - (double)i / RAYCAST_LUT_SIZE, spacing));
    }
}

/* Number of sample positions t0 + k * base (k = 0, 1, ...) with t <= t1,
 * evaluated with exactly the tracer's float expression: what a ray without
 * skipping would visit (0 when t1 < t0). */
long raycast_parallel_positions(float t0, float t1, float base)
{
    if (!(t0 <= t1))
        return 0;
    double est = floor(((double)t1 - (double)t0) / (double)base);
    long k = est > 1e15 ? (long)1e15 : (long)est;
    while (k > 0 && t0 + (float)k * base > t1)
        k--;
    while (t0 + (float)(k + 1) * base <= t1)
        k++;
    return k + 1;
}

/* The same for perspective rays, t_{k+1} = t_k * growth from t_start. */
static long perspective_positions(float t_start, float t1, float growth)
{
    long n = 0;
    for (float t = t_start; t <= t1; t *= growth)
        n++;
    return n;
}

/* One ray's marching state, so that several rays can advance in turns (their
 * dependency chains then overlap in the CPU) with exactly the arithmetic a
 * lone ray would do. */
typedef struct {
    float ov[3], dv[3], inv_dv[3], half[3];
    float t0, t1, t1_volume, t_start, t, base, inv_base, growth, spacing, level3d, top;
    long k;
    int level2d;
    bool perspective, terminated;
    float acc[3], acc_a;
    uint64_t n_samples, n_skipped;
} ray_state_t;

/* Sets the ray up; false if it misses the volume or everything it could
 * sample is empty (its colour is then black). */
static inline bool ray_begin(const raycast_ctx_t *r, float px, float py, int level2d,
                             ray_state_t *s)
{
    const camera_t *cam = r->camera;
    s->acc[0] = s->acc[1] = s->acc[2] = 0.0f;
    s->acc_a = 0.0f;
    s->n_samples = s->n_skipped = 0;
    s->level2d = level2d;
    s->terminated = false;
    s->t0 = s->t_start = 0.0f;
    s->t1_volume = -1.0f;       /* no positions until the ray meets the volume */
    s->perspective = cam->projection == PROJECTION_PERSPECTIVE;
    s->base = 1.0f;             /* set below for rays that meet the volume */
    s->growth = 2.0f;
    /* Level-0 voxel coordinates along the ray: ov + t * dv. */
    if (!raycast_ray_setup(r, px, py, &s->t0, &s->t1, s->ov, s->dv, s->inv_dv, s->half))
        return false;
    s->t1_volume = s->t1;
    s->perspective = cam->projection == PROJECTION_PERSPECTIVE;
    s->base = r->sample_step * (float)(1 << level2d);
    s->inv_base = 1.0f / s->base;
    /* Parallel: spacing `base` everywhere.  Perspective: spacing proportional
     * to the distance t from the eye, equal to `base` at the volume centre, so
     * t_{k+1} = t_k * growth. */
    s->growth = 1.0f + s->base / cam->eye_distance;
    s->top = (float)(r->mip->levels - 1);
    s->k = 0;
    s->t = s->t0;
    if (s->perspective && s->t < 1e-3f)
        s->t = 1e-3f;
    s->t_start = s->t;
    /* Parallel: spacing and 3DLevel are constant along the ray. */
    s->spacing = s->base;
    s->level3d = log2f(s->spacing) - r->level3d_offset;
    s->level3d = s->level3d < 0.0f ? 0.0f : (s->level3d > s->top ? s->top : s->level3d);
    if (r->octree && !s->perspective) {
        /* Parallel rays sample one level: start and stop at the occupied
         * cells' bounding box of that level's grid, on the same sample
         * lattice (samples outside it are exactly zero). */
        int n = (int)s->level3d;
        const octree_grid_t *g = s->level3d == (float)n ? &r->octree->exact[n]
                                                        : &r->octree->grid[n];
        if (!g->any_occupied)
            return false;
        float a = -INFINITY, b = INFINITY;
        for (int ax = 0; ax < 3; ax++) {
            if (s->dv[ax] == 0.0f)
                continue;
            float ta = (g->box_lo[ax] - s->ov[ax]) * s->inv_dv[ax];
            float tb = (g->box_hi[ax] - s->ov[ax]) * s->inv_dv[ax];
            if (ta > tb) {
                float sw = ta;
                ta = tb;
                tb = sw;
            }
            a = fmaxf(a, ta);
            b = fminf(b, tb);
        }
        /* Margins of 1e-3 keep rounding from dropping a boundary sample.
         * A start beyond the end leaves nothing to sample (and would
         * overflow the position index for near-axial rays). */
        if (a - 1e-3f > s->t1)
            return false;
        if (a - 1e-3f > s->t0) {
            s->k = -(long)mip3d_floor_int(-(a - 1e-3f - s->t0) / s->base);
            s->t = s->t0 + (float)s->k * s->base;
            s->n_skipped += (uint64_t)s->k;
        }
        if (b + 1e-3f < s->t1)
            s->t1 = b + 1e-3f;
    }
    return true;
}

/* Advances the ray to its next sample position (octree jump) or draws,
 * shades and composites one sample; false when the ray is finished. */
static inline bool ray_step(const raycast_ctx_t *r, ray_state_t *s)
{
    if (!(s->t <= s->t1))
        return false;
    if (s->perspective) {
        s->spacing = s->t * (s->growth - 1.0f);
        s->level3d = log2f(s->spacing) - r->level3d_offset;
        s->level3d = s->level3d < 0.0f ? 0.0f : (s->level3d > s->top ? s->top : s->level3d);
    }
    const float t = s->t;
    float p[3] = {s->ov[0] + t * s->dv[0], s->ov[1] + t * s->dv[1], s->ov[2] + t * s->dv[2]};
    if (r->octree) {
        float lo[3], hi[3];
        int n = (int)s->level3d;
        int height = octree_empty_node(r->octree, n, s->level3d == (float)n, p, lo, hi);
        if (height == 0 && !s->perspective) {
            /* A single empty cell: this sample is zero; stepping over it
             * is cheaper than computing the cell's exit. */
            s->n_skipped++;
            s->k++;
            s->t = s->t0 + (float)s->k * s->base;
            return true;
        }
        if (height >= 0) {
            float t_exit = raycast_node_exit(s->ov, s->dv, s->inv_dv, lo, hi);
            if (!(t_exit <= s->t1))
                return false;     /* empty all the way out of the volume */
            /* Stay a hair inside the node so rounding never skips a
             * sample that lands in the neighbouring cell. */
            t_exit -= 1e-3f;
            if (s->perspective) {
                /* The floor level must not change inside the jump. */
                float t_level = exp2f((float)(n + 1) + r->level3d_offset) / (s->growth - 1.0f);
                if (n + 1 <= (int)s->top && t_level < t_exit)
                    t_exit = t_level;
                do {
                    s->t *= s->growth;
                    s->n_skipped++;
                } while (s->t < t_exit && s->t <= s->t1);
            } else {
                /* ceil; a multiply instead of a divide: the 1e-3 margin
                 * above dwarfs its rounding. */
                long k_new = -(long)mip3d_floor_int(-(t_exit - s->t0) * s->inv_base);
                if (k_new <= s->k)
                    k_new = s->k + 1;
                s->n_skipped += (uint64_t)(k_new - s->k);
                s->k = k_new;
                s->t = s->t0 + (float)s->k * s->base;
            }
            return true;
        }
    }
    float comp[8];
    mip3d_sample(r->mip, s->level3d, p, comp);
    s->n_samples++;
    if (raycast_accumulate(r, comp, s->half, s->level2d, s->perspective,
                           s->spacing / r->opacity_unit, s->acc,
                           &s->acc_a)) {
        s->terminated = true;
        return false;
    }
    if (s->perspective) {
        s->t *= s->growth;
    } else {
        s->k++;
        s->t = s->t0 + (float)s->k * s->base;
    }
    return true;
}

static inline void ray_end(const ray_state_t *s, float rgb[3], raycast_counts_t *counts)
{
    counts->rays++;
    counts->samples += s->n_samples;
    /* Skipped = the positions a ray without skipping would have visited
     * (all of them in the volume unless it terminated early, when the
     * counts already add up) minus those sampled. */
    uint64_t skipped = s->n_skipped;
    if (!s->terminated) {
        long all = s->perspective ? perspective_positions(s->t_start, s->t1_volume, s->growth)
                                  : raycast_parallel_positions(s->t0, s->t1_volume, s->base);
        skipped = (uint64_t)all - s->n_samples;
    }
    counts->samples_skipped += skipped;
    rgb[0] = s->acc[0];
    rgb[1] = s->acc[1];
    rgb[2] = s->acc[2];
}

void raycast_trace_reference(const raycast_ctx_t *r, float px, float py, int level2d,
                             float rgb[3], raycast_counts_t *counts)
{
    ray_state_t s;
    if (ray_begin(r, px, py, level2d, &s))
        while (ray_step(r, &s))
            ;
    ray_end(&s, rgb, counts);
}

/* The reference tracer, `count` rays in turns. */
static void reference_batch(const raycast_ctx_t *r, int count, const float *px, const float *py,
                            int level2d, float (*rgb)[3], raycast_counts_t *counts)
{
    ray_state_t s[RAYCAST_BATCH];
    bool live[RAYCAST_BATCH];
    int remaining = 0;
    for (int i = 0; i < count; i++) {
        live[i] = ray_begin(r, px[i], py[i], level2d, &s[i]);
        remaining += live[i];
    }
    while (remaining > 0)
        for (int i = 0; i < count; i++)
            if (live[i] && !ray_step(r, &s[i])) {
                live[i] = false;
                remaining--;
            }
    for (int i = 0; i < count; i++)
        ray_end(&s[i], rgb[i], counts);
}

void raycast_trace_batch(const raycast_ctx_t *r, int count, const float *px, const float *py,
                         int level2d, float (*rgb)[3], raycast_counts_t *counts)
{
    if (count > RAYCAST_BATCH)
        count = RAYCAST_BATCH;
    if (count <= 0)
        return;
    if (r->octree && r->camera->projection == PROJECTION_PARALLEL)
        raycast_parallel_batch(r, count, px, py, level2d, rgb, counts);
    else if (r->octree)
        raycast_perspective_batch(r, count, px, py, level2d, rgb, counts);
    else
        reference_batch(r, count, px, py, level2d, rgb, counts);
}

void raycast_trace_rays(const raycast_ctx_t *r, int count, const float *px, const float *py,
                        int level2d, float (*rgb)[3], raycast_counts_t *counts)
{
    bool parallel = r->camera->projection == PROJECTION_PARALLEL;
    int chunk = r->octree ? RAYCAST_CHUNK : RAYCAST_BATCH;
    for (int i = 0; i < count; i += chunk) {
        int n = count - i < chunk ? count - i : chunk;
        if (r->octree && parallel)
            raycast_parallel_batch(r, n, px + i, py + i, level2d, rgb + i, counts);
        else if (r->octree)
            raycast_perspective_batch(r, n, px + i, py + i, level2d, rgb + i, counts);
        else
            reference_batch(r, n, px + i, py + i, level2d, rgb + i, counts);
    }
}

void raycast_trace(const raycast_ctx_t *r, float px, float py, int level2d, float rgb[3],
                   raycast_counts_t *counts)
{
    float out[1][3];
    raycast_trace_batch(r, 1, &px, &py, level2d, out, counts);
    rgb[0] = out[0][0];
    rgb[1] = out[0][1];
    rgb[2] = out[0][2];
}
