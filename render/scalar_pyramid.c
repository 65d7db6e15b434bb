/* scalar_pyramid.c: builds the max (or box) pyramid of voxel values and its
 * node bounds for skipping (see scalar_pyramid.h). */
#include "scalar_pyramid.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "parallel.h"

typedef struct {
    scalar_pyramid_t *p;
    int level, height;        /* what the current parallel pass fills */
} pyramid_job_t;

/* Level job->level from the one beneath, one z slice. */
static void filter_slice(void *ctx, int z, int thread)
{
    (void)thread;
    const pyramid_job_t *job = ctx;
    const scalar_level_t *S = &job->p->level[job->level - 1];
    scalar_level_t *D = &job->p->level[job->level];
    bool use_max = job->p->kind == SCALAR_PYRAMID_MAX;
    for (int y = 0; y < D->ny; y++)
        for (int x = 0; x < D->nx; x++) {
            float acc = use_max ? -INFINITY : 0.0f;
            for (int dz = 0; dz < 2 && 2 * z + dz < S->nz; dz++)
                for (int dy = 0; dy < 2 && 2 * y + dy < S->ny; dy++)
                    for (int dx = 0; dx < 2 && 2 * x + dx < S->nx; dx++) {
                        float c = scalar_at(S, 2 * x + dx, 2 * y + dy, 2 * z + dz);
                        acc = use_max ? (c > acc ? c : acc) : acc + c;
                    }
            D->value[((size_t)z * D->ny + y) * D->nx + x] = use_max ? acc : acc * 0.125f;
        }
}

/* Cell bounds of level job->level, one z slice: max over the trilinear
 * footprint [i, i+1]^3, raised by the rounding margin. */
static void cell_slice(void *ctx, int z, int thread)
{
    (void)thread;
    const pyramid_job_t *job = ctx;
    scalar_level_t *L = &job->p->level[job->level];
    int z1 = z + 1 < L->nz ? z + 1 : z;
    for (int y = 0; y < L->ny; y++) {
        int y1 = y + 1 < L->ny ? y + 1 : y;
        for (int x = 0; x < L->nx; x++) {
            int x1 = x + 1 < L->nx ? x + 1 : x;
            int xs[2] = {x, x1}, ys[2] = {y, y1}, zs[2] = {z, z1};
            float hi = -INFINITY, lo = INFINITY;
            for (int k = 0; k < 8; k++) {
                float c = scalar_at(L, xs[k & 1], ys[(k >> 1) & 1], zs[k >> 2]);
                hi = c > hi ? c : hi;
                lo = c < lo ? c : lo;
            }
            float margin = (fabsf(hi) + fabsf(lo)) * (1.0f / 131072.0f);
            L->node_max[0][((size_t)z * L->ny + y) * L->nx + x] = hi + margin;
        }
    }
}

/* Node bounds of height job->height from the height beneath, one z slice. */
static void node_slice(void *ctx, int z, int thread)
{
    (void)thread;
    const pyramid_job_t *job = ctx;
    scalar_level_t *L = &job->p->level[job->level];
    int h = job->height;
    const float *src = L->node_max[h - 1];
    for (int y = 0; y < L->hy[h]; y++)
        for (int x = 0; x < L->hx[h]; x++) {
            float acc = -INFINITY;
            for (int dz = 0; dz < 2 && 2 * z + dz < L->hz[h - 1]; dz++)
                for (int dy = 0; dy < 2 && 2 * y + dy < L->hy[h - 1]; dy++)
                    for (int dx = 0; dx < 2 && 2 * x + dx < L->hx[h - 1]; dx++) {
                        float c = src[((size_t)(2 * z + dz) * L->hy[h - 1] + (size_t)(2 * y + dy)) *
                                          L->hx[h - 1] + (size_t)(2 * x + dx)];
                        acc = c > acc ? c : acc;
                    }
            L->node_max[h][((size_t)z * L->hy[h] + y) * L->hx[h] + x] = acc;
        }
}

/* Distance map of threshold j (= item) at level job->level: two raster
 * passes with the 13 earlier / 13 later neighbours give the exact
 * chessboard distance (each pass propagates distance + 1 along every
 * direction of its half of the 26-neighbourhood). */
static void distance_map(void *ctx, int j, int thread)
{
    (void)thread;
    const pyramid_job_t *job = ctx;
    scalar_level_t *L = &job->p->level[job->level];
    const int s = SCALAR_BRICK_SHIFT, bx = L->hx[s], by = L->hy[s], bz = L->hz[s];
    const float *bound = L->node_max[s];
    const float thr = job->p->threshold[j];
    uint8_t *d = L->brick_dist + (size_t)j * bx * by * bz;
    for (size_t i = 0; i < (size_t)bx * by * bz; i++)
        d[i] = bound[i] > thr ? 0 : 255;
    for (int pass = 0; pass < 2; pass++) {
        int dir = pass == 0 ? 1 : -1;
        for (int zi = 0; zi < bz; zi++)
            for (int yi = 0; yi < by; yi++)
                for (int xi = 0; xi < bx; xi++) {
                    int z = pass == 0 ? zi : bz - 1 - zi, y = pass == 0 ? yi : by - 1 - yi;
                    int x = pass == 0 ? xi : bx - 1 - xi;
                    uint8_t *here = d + ((size_t)z * by + y) * bx + x;
                    int best = *here;
                    /* Neighbours visited earlier in this pass: offset o with
                     * (dz, dy, dx) lexicographically before 0 along dir. */
                    for (int o = 0; o < 13; o++) {
                        int dz = o / 9 - 1, dy = (o / 3) % 3 - 1, dx = o % 3 - 1;
                        int nz = z + dir * dz, ny = y + dir * dy, nx = x + dir * dx;
                        if (nx < 0 || ny < 0 || nz < 0 || nx >= bx || ny >= by || nz >= bz)
                            continue;
                        int v = d[((size_t)nz * by + ny) * bx + nx] + 1;
                        best = v < best ? v : best;
                    }
                    *here = (uint8_t)(best > 255 ? 255 : best);
                }
    }
}

int scalar_ranked_cmp(const void *a, const void *b)
{
    const scalar_ranked_t *x = a, *y = b;
    if (x->key != y->key)
        return x->key > y->key ? -1 : 1;
    return x->index < y->index ? -1 : (x->index > y->index ? 1 : 0);
}

static pp5_status_t order_bricks(scalar_pyramid_t *p, scalar_level_t *L)
{
    int h = L->heights - 1 < SCALAR_BRICK_SHIFT ? L->heights - 1 : SCALAR_BRICK_SHIFT;
    size_t n = (size_t)L->hx[h] * L->hy[h] * L->hz[h];
    scalar_ranked_t *rank = malloc(n * sizeof *rank);
    L->brick_order = malloc(n * sizeof *L->brick_order);
    L->brick_coord = malloc(n * sizeof *L->brick_coord);
    if (!rank || !L->brick_order || !L->brick_coord) {
        free(rank);
        return pp5_fail(PP5_E_NOMEM, "scalar pyramid: cannot allocate the brick order");
    }
    for (size_t i = 0; i < n; i++)
        rank[i] = (scalar_ranked_t){L->node_max[h][i], (uint32_t)i};
    qsort(rank, n, sizeof *rank, scalar_ranked_cmp);
    for (size_t i = 0; i < n; i++) {
        uint32_t x = rank[i].index;
        L->brick_order[i] = x;
        L->brick_coord[i][0] = (uint16_t)(x % (uint32_t)L->hx[h]);
        L->brick_coord[i][1] = (uint16_t)(x / (uint32_t)L->hx[h] % (uint32_t)L->hy[h]);
        L->brick_coord[i][2] = (uint16_t)(x / ((uint32_t)L->hx[h] * (uint32_t)L->hy[h]));
    }
    free(rank);
    L->brick_height = h;
    L->brick_count = n;
    p->bytes += n * (sizeof *L->brick_order + sizeof *L->brick_coord);
    return PP5_OK;
}

void scalar_pyramid_free(scalar_pyramid_t *p)
{
    for (int n = 0; n < MIP3D_MAX_LEVELS; n++) {
        free(p->level[n].brick_order);
        free(p->level[n].brick_coord);
        free(p->level[n].value);
        free(p->level[n].brick_dist);
        for (int h = 0; h < OCTREE_MAX_HEIGHT; h++)
            free(p->level[n].node_max[h]);
    }
    memset(p, 0, sizeof *p);
}

static float *alloc_floats(int nx, int ny, int nz, size_t *bytes)
{
    size_t n, b;
    if (!pp5_mul3_size((size_t)nx, (size_t)ny, (size_t)nz, &n) ||
        !pp5_mul_size(n, sizeof(float), &b))
        return NULL;
    *bytes += b;
    return malloc(b);
}

/* Allocates level n's values and node bounds. */
static pp5_status_t alloc_level(scalar_pyramid_t *p, int n, int nx, int ny, int nz)
{
    scalar_level_t *L = &p->level[n];
    L->nx = nx, L->ny = ny, L->nz = nz;
    L->value = alloc_floats(nx, ny, nz, &p->bytes);
    for (int h = 0; L->value && h < OCTREE_MAX_HEIGHT; h++) {
        L->hx[h] = nx, L->hy[h] = ny, L->hz[h] = nz;
        L->node_max[h] = alloc_floats(nx, ny, nz, &p->bytes);
        if (!L->node_max[h])
            return pp5_fail(PP5_E_NOMEM, "scalar pyramid: cannot allocate level %d", n);
        L->heights = h + 1;
        if (nx == 1 && ny == 1 && nz == 1)
            break;
        nx = (nx + 1) / 2, ny = (ny + 1) / 2, nz = (nz + 1) / 2;
    }
    if (!L->value)
        return pp5_fail(PP5_E_NOMEM, "scalar pyramid: cannot allocate level %d", n);
    PP5_ASSERT(L->hx[L->heights - 1] == 1 && L->hy[L->heights - 1] == 1 &&
               L->hz[L->heights - 1] == 1, "node pyramid deeper than OCTREE_MAX_HEIGHT");
    return PP5_OK;
}

static pp5_status_t build_levels(scalar_pyramid_t *p, const volume_t *v, int threads)
{
    int nx = v->nx, ny = v->ny, nz = v->nz;
    pp5_status_t st = PP5_OK;
    for (int n = 0; st == PP5_OK && n < MIP3D_MAX_LEVELS; n++) {
        st = alloc_level(p, n, nx, ny, nz);
        if (st != PP5_OK)
            break;
        p->levels = n + 1;
        pyramid_job_t job = {p, n, 0};
        if (n == 0)
            memcpy(p->level[0].value, v->data, (size_t)nx * ny * nz * sizeof(float));
        else
            st = parallel_for(threads, nz, filter_slice, &job);
        if (st == PP5_OK)
            st = parallel_for(threads, nz, cell_slice, &job);
        for (int h = 1; st == PP5_OK && h < p->level[n].heights; h++) {
            job.height = h;
            st = parallel_for(threads, p->level[n].hz[h], node_slice, &job);
        }
        scalar_level_t *L = &p->level[n];
        if (st == PP5_OK && L->heights > SCALAR_BRICK_SHIFT) {
            const int b = SCALAR_BRICK_SHIFT;
            L->brick_dist = malloc((size_t)SCALAR_THRESHOLDS * L->hx[b] * L->hy[b] * L->hz[b]);
            if (!L->brick_dist)
                return pp5_fail(PP5_E_NOMEM, "scalar pyramid: cannot allocate distance maps");
            p->bytes += (size_t)SCALAR_THRESHOLDS * L->hx[b] * L->hy[b] * L->hz[b];
            st = parallel_for(threads, SCALAR_THRESHOLDS, distance_map, &job);
        }
        if (st == PP5_OK)
            st = order_bricks(p, L);
        if (nx == 1 && ny == 1 && nz == 1)
            break;
        nx = (nx + 1) / 2, ny = (ny + 1) / 2, nz = (nz + 1) / 2;
    }
    return st;
}

pp5_status_t scalar_pyramid_build(scalar_pyramid_t *p, const volume_t *v,
                                  scalar_pyramid_kind_t kind, int threads)
{
    memset(p, 0, sizeof *p);
    if (!v->data || v->nx < 1 || v->ny < 1 || v->nz < 1)
        return pp5_fail(PP5_E_RANGE, "scalar pyramid: empty volume");
    if (kind != SCALAR_PYRAMID_MAX && kind != SCALAR_PYRAMID_BOX)
        return pp5_fail(PP5_E_RANGE, "scalar pyramid: unknown kind %d", (int)kind);
    p->kind = kind;
    mip3d_voxel_spacing(v, p->spacing, p->inv_spacing);
    p->min_value = v->min_value;
    p->max_value = v->max_value;
    for (int j = 0; j < SCALAR_THRESHOLDS; j++)
        p->threshold[j] = v->min_value + (v->max_value - v->min_value) * (float)(j + 1) /
                                             (float)(SCALAR_THRESHOLDS + 1);
    pp5_status_t st = build_levels(p, v, threads);
    if (st != PP5_OK)
        scalar_pyramid_free(p);
    return st;
}

float scalar_pyramid_sample(const scalar_pyramid_t *p, float level3d, const float pos[3])
{
    float top = (float)(p->levels - 1);
    level3d = level3d < 0.0f ? 0.0f : (level3d > top ? top : level3d);
    int lo = (int)level3d;
    float t = level3d - (float)lo, q[3];
    int fl[3];
    scalar_level_coords(pos, lo, q, fl);
    float v = scalar_trilerp(&p->level[lo], q, fl);
    if (t > 0.0f && lo + 1 < p->levels) {
        scalar_level_coords(pos, lo + 1, q, fl);
        float w = scalar_trilerp(&p->level[lo + 1], q, fl);
        v += t * (w - v);
    }
    return v;
}
