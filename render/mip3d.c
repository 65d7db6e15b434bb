/* mip3d.c: builds the 3D mip map (classify, viewpoint-independent shading,
 * 2x2x2 box filtering) and draws samples from it. */
#include "mip3d.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "huge_alloc.h"
#include "mip3d_internal.h"
#include "parallel.h"
#include "progress.h"

/* Level-0 voxel (x, y, z): gradient -> classification -> stored components
 * (the float values every format starts from). */
void mip3d_base_voxel(const mip3d_job_t *job, int x, int y, int z, float *o)
{
    const mip3d_t *m = job->m;
    const volume_t *v = job->v;
    const int s = m->stride;
    float g[3], rgb[3], n[3] = {0.0f, 0.0f, 0.0f};
    shade_gradient(v, x, y, z, m->inv_spacing, g);
    float gm = sqrtf(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    float a = classify_voxel(job->tf, volume_at(v, x, y, z), gm, rgb);
    memset(o, 0, sizeof(float) * (size_t)s);
    if (a <= 0.0f)
        return;
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

/* Level 0, one z slice, F32. */
static void mip3d_base_slice(void *ctx, int z, int thread)
{
    (void)thread;
    mip3d_job_t *job = ctx;
    mip3d_level_t *L = &job->m->level[0];
    const int s = job->m->stride;
    for (int y = 0; y < L->ny; y++)
        for (int x = 0; x < L->nx; x++)
            mip3d_base_voxel(job, x, y, z,
                             L->data + (((size_t)z * (size_t)L->ny + (size_t)y) * (size_t)L->nx +
                                        (size_t)x) * (size_t)s);
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

void mip3d_voxel_spacing(const volume_t *v, float spacing[3], float inv_spacing[3])
{
    double sp[3], smin = 0.0;
    for (int a = 0; a < 3; a++) {
        sp[a] = v->spacing[a] > 0.0 && isfinite(v->spacing[a]) ? v->spacing[a] : 1.0;
        if (smin == 0.0 || sp[a] < smin)
            smin = sp[a];
    }
    for (int a = 0; a < 3; a++) {
        spacing[a] = (float)(sp[a] / smin);
        inv_spacing[a] = (float)(smin / sp[a]);
    }
}

/* Rays step from slice to slice, so a sample's eight voxels lie on up to
 * four 4 KiB pages and a frame touches far more pages than the TLB holds;
 * large levels go on 2 MiB pages where the host offers them (huge_alloc,
 * which maps them on their own: advice given to malloc's memory outlives
 * the level and reaches whatever malloc hands out there next).  They
 * measured 4-8% faster casts on CThead. */
void *mip3d_alloc_voxels(size_t bytes)
{
    return huge_alloc(bytes, false);
}

void mip3d_free(mip3d_t *m)
{
    for (int i = 0; i < MIP3D_MAX_LEVELS; i++) {
        huge_free(m->level[i].data, m->level[i].data_bytes);
        huge_free(m->packed[i].data, m->packed[i].data_bytes);
        for (int a = 0; a < 3; a++)
            free(m->packed[i].offset[a]);
    }
    memset(m, 0, sizeof *m);
}

void mip3d_geometry(mip3d_t *m, const volume_t *v)
{
    mip3d_voxel_spacing(v, m->spacing, m->inv_spacing);
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

pp5_status_t mip3d_build_format(mip3d_t *m, const volume_t *v, const classify_tf_t *tf,
                                const shade_params_t *shade, mip3d_format_t format, int threads)
{
    if (format == MIP3D_F32)
        return mip3d_build(m, v, tf, shade, threads);
    return mip3d_build_packed(m, v, tf, shade, format, threads);
}

const char *mip3d_format_name(mip3d_format_t f)
{
    return f == MIP3D_U8 ? "u8" : (f == MIP3D_U16 ? "u16" : "f32");
}

bool mip3d_format_parse(const char *name, mip3d_format_t *f)
{
    static const mip3d_format_t all[] = {MIP3D_F32, MIP3D_U16, MIP3D_U8};
    for (int i = 0; i < 3; i++)
        if (strcmp(name, mip3d_format_name(all[i])) == 0) {
            *f = all[i];
            return true;
        }
    return false;
}

int mip3d_format_bytes(mip3d_format_t f)
{
    return f == MIP3D_U8 ? 1 : (f == MIP3D_U16 ? 2 : 4);
}

bool mip3d_voxel_occupied(const mip3d_t *m, int n, int x, int y, int z)
{
    const mip3d_level_t *L = &m->level[n];
    if (m->format == MIP3D_F32)
        return L->data[(((size_t)z * (size_t)L->ny + (size_t)y) * (size_t)L->nx + (size_t)x) *
                       (size_t)m->stride + MIP3D_A] > 0.0f;
    const mip3d_packed_t *P = &m->packed[n];
    size_t i = ((size_t)P->offset[0][x] + P->offset[1][y] + P->offset[2][z]) *
               (size_t)m->stride + MIP3D_A;
    return m->format == MIP3D_U8 ? ((const uint8_t *)P->data)[i] != 0
                                 : ((const uint16_t *)P->data)[i] != 0;
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
        L->data = mip3d_alloc_voxels(floats);
        L->data_bytes = floats;
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
