/* mip3d.c: builds the 3D mip map (classify, viewpoint-independent shading,
 * 2x2x2 box filtering) and draws samples from it. */
#include "mip3d.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "parallel.h"
#include "progress.h"

typedef struct {
    mip3d_t *m;
    const volume_t *v;
    const classify_tf_t *tf;
    const shade_params_t *shade;
    int dst;              /* level being filled (filter jobs) */
    int z0;               /* first slice of the chunk (base jobs) */
} mip3d_job_t;

/* Level 0, one z slice: gradient -> classification -> stored components. */
static void mip3d_base_slice(void *ctx, int z, int thread)
{
    (void)thread;
    mip3d_job_t *job = ctx;
    mip3d_t *m = job->m;
    const volume_t *v = job->v;
    mip3d_level_t *L = &m->level[0];
    const int s = m->stride;
    for (int y = 0; y < v->ny; y++) {
        for (int x = 0; x < v->nx; x++) {
            float g[3], rgb[3], n[3] = {0.0f, 0.0f, 0.0f};
            shade_gradient(v, x, y, z, m->inv_spacing, g);
            float gm = sqrtf(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
            float a = classify_voxel(job->tf, volume_at(v, x, y, z), gm, rgb);
            float *o = L->data + (((size_t)z * (size_t)L->ny + (size_t)y) * (size_t)L->nx +
                                  (size_t)x) * (size_t)s;
            memset(o, 0, sizeof(float) * (size_t)s);
            if (a <= 0.0f)
                continue;
            if (gm > 0.0f)
                for (int k = 0; k < 3; k++)
                    n[k] = g[k] / gm;
            float shade = 1.0f;
            if (m->lighting != SHADE_MOVING_OBJECT)
                shade = shade_diffuse(job->shade, n, job->shade->light_dir);
            for (int k = 0; k < 3; k++)
                o[MIP3D_R + k] = a * rgb[k] * shade;
            o[MIP3D_A] = a;
            if (s == 8)
                for (int k = 0; k < 3; k++)
                    o[MIP3D_NX + k] = a * n[k];
        }
    }
}

static void mip3d_base_chunk_slice(void *ctx, int z, int thread)
{
    mip3d_base_slice(ctx, ((mip3d_job_t *)ctx)->z0 + z, thread);
}

/* Level dst from dst-1, one z slice: mean of the 2x2x2 children, children
 * beyond an odd edge counting as zero (so "zero" still means "all empty"). */
static void mip3d_filter_slice(void *ctx, int z, int thread)
{
    (void)thread;
    mip3d_job_t *job = ctx;
    const mip3d_level_t *S = &job->m->level[job->dst - 1];
    mip3d_level_t *D = &job->m->level[job->dst];
    const int s = job->m->stride;
    for (int y = 0; y < D->ny; y++) {
        for (int x = 0; x < D->nx; x++) {
            float acc[8] = {0};
            for (int dz = 0; dz < 2; dz++) {
                int cz = 2 * z + dz;
                if (cz >= S->nz)
                    continue;
                for (int dy = 0; dy < 2; dy++) {
                    int cy = 2 * y + dy;
                    if (cy >= S->ny)
                        continue;
                    for (int dx = 0; dx < 2; dx++) {
                        int cx = 2 * x + dx;
                        if (cx >= S->nx)
                            continue;
                        const float *c = S->data + (((size_t)cz * (size_t)S->ny + (size_t)cy) *
                                                    (size_t)S->nx + (size_t)cx) * (size_t)s;
                        for (int k = 0; k < s; k++)
                            acc[k] += c[k];
                    }
                }
            }
            float *o = D->data + (((size_t)z * (size_t)D->ny + (size_t)y) * (size_t)D->nx +
                                  (size_t)x) * (size_t)s;
            for (int k = 0; k < s; k++)
                o[k] = acc[k] * 0.125f;
        }
    }
}

void mip3d_free(mip3d_t *m)
{
    for (int i = 0; i < MIP3D_MAX_LEVELS; i++)
        free(m->level[i].data);
    memset(m, 0, sizeof *m);
}

void mip3d_geometry(mip3d_t *m, const volume_t *v)
{
    double sp[3], smin = 0.0;
    for (int a = 0; a < 3; a++) {
        sp[a] = v->spacing[a] > 0.0 && isfinite(v->spacing[a]) ? v->spacing[a] : 1.0;
        if (smin == 0.0 || sp[a] < smin)
            smin = sp[a];
    }
    for (int a = 0; a < 3; a++) {
        m->spacing[a] = (float)(sp[a] / smin);
        m->inv_spacing[a] = (float)(smin / sp[a]);
    }
    int nx = v->nx, ny = v->ny, nz = v->nz;
    m->levels = 0;
    for (int n = 0; n < MIP3D_MAX_LEVELS; n++) {
        m->level[n].nx = nx;
        m->level[n].ny = ny;
        m->level[n].nz = nz;
        m->levels = n + 1;
        if (nx == 1 && ny == 1 && nz == 1)
            break;
        nx = (nx + 1) / 2;
        ny = (ny + 1) / 2;
        nz = (nz + 1) / 2;
    }
}

pp5_status_t mip3d_build(mip3d_t *m, const volume_t *v, const classify_tf_t *tf,
                         const shade_params_t *shade, int threads)
{
    memset(m, 0, sizeof *m);
    if (!v->data || v->nx < 1 || v->ny < 1 || v->nz < 1)
        return pp5_fail(PP5_E_RANGE, "mip3d: empty volume");
    m->lighting = shade->lighting;
    m->stride = shade->lighting == SHADE_DIFFUSE_FIXED_LIGHT ? 4 : 8;
    mip3d_geometry(m, v);
    for (int n = 0; n < m->levels; n++) {
        mip3d_level_t *L = &m->level[n];
        size_t voxels, floats;
        if (!pp5_mul3_size((size_t)L->nx, (size_t)L->ny, (size_t)L->nz, &voxels) ||
            !pp5_mul_size(voxels, (size_t)m->stride * sizeof(float), &floats)) {
            mip3d_free(m);
            return pp5_fail(PP5_E_NOMEM, "mip3d: level %d too large", n);
        }
        L->data = malloc(floats);
        if (!L->data) {
            mip3d_free(m);
            return pp5_fail(PP5_E_NOMEM, "mip3d: cannot allocate %zu bytes for level %d",
                            floats, n);
        }
        m->bytes += floats;
    }
    /* Level 0 in chunks of slices, for the progress line on large volumes
     * (each slice writes only its own voxels: the chunking changes nothing). */
    enum { CHUNK = 8 };
    int chunks = (v->nz + CHUNK - 1) / CHUNK;
    progress_t pr;
    progress_begin(&pr, "3D mip map", chunks + m->levels - 1);
    mip3d_job_t job = {m, v, tf, shade, 0, 0};
    pp5_status_t st = PP5_OK;
    for (int c = 0; st == PP5_OK && c < chunks; c++) {
        job.z0 = c * CHUNK;
        int n = v->nz - job.z0 < CHUNK ? v->nz - job.z0 : CHUNK;
        st = parallel_for(threads, n, mip3d_base_chunk_slice, &job);
        progress_step(&pr, "level 0: classify and shade");
    }
    for (int n = 1; st == PP5_OK && n < m->levels; n++) {
        job.dst = n;
        st = parallel_for(threads, m->level[n].nz, mip3d_filter_slice, &job);
        progress_step(&pr, "coarser levels");
    }
    progress_end(&pr);
    if (st != PP5_OK)
        mip3d_free(m);
    return st;
}

void mip3d_sample(const mip3d_t *m, float level3d, const float p[3], float *out)
{
    float top = (float)(m->levels - 1);
    if (level3d < 0.0f)
        level3d = 0.0f;
    if (level3d > top)
        level3d = top;
    int lo = (int)level3d;
    float t = level3d - (float)lo;
    mip3d_trilerp(m, lo, mip3d_level_coord(p[0], lo), mip3d_level_coord(p[1], lo),
                  mip3d_level_coord(p[2], lo), out);
    if (t > 0.0f && lo + 1 < m->levels) {
        float hi[8];
        int n = lo + 1;
        mip3d_trilerp(m, n, mip3d_level_coord(p[0], n), mip3d_level_coord(p[1], n),
                      mip3d_level_coord(p[2], n), hi);
        for (int k = 0; k < m->stride; k++)
            out[k] += t * (hi[k] - out[k]);
    }
}
