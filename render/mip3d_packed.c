/* mip3d_packed.c: the reduced-precision formats of the 3D mip map (U16, U8;
 * mip3d.h): units per component, the bricked layout, level 0 computed a
 * slice at a time straight into fixed point (no float copy of the volume's
 * components is ever held), and the 2x2x2 box filter in integers. */
#include "mip3d_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "parallel.h"

/* Largest stored value of an unsigned and of a signed component. */
static int unsigned_max(mip3d_format_t f)
{
    return f == MIP3D_U8 ? 255 : 65535;
}

static int signed_max(mip3d_format_t f)
{
    return f == MIP3D_U8 ? 127 : 32767;
}

/* Ranges: opacity is at most 1; the colour at most the brightest contour
 * colour times the largest diffuse factor (ka + kd, with N.L <= 1) unless
 * the colour is stored unshaded (moving object); a*N lies in [-1, 1]. */
static void packed_units(mip3d_t *m, const classify_tf_t *tf, const shade_params_t *shade)
{
    float colour = 0.0f;
    for (int i = 0; i < tf->count; i++)
        for (int k = 0; k < 3; k++)
            colour = tf->contour[i].rgb[k] > colour ? tf->contour[i].rgb[k] : colour;
    if (m->lighting != SHADE_MOVING_OBJECT && shade->ambient + shade->diffuse > 1.0f)
        colour *= shade->ambient + shade->diffuse;
    if (!(colour > 0.0f))
        colour = 1.0f;
    float um = (float)unsigned_max(m->format), sm = (float)signed_max(m->format);
    for (int k = 0; k < 3; k++)
        m->unit[MIP3D_R + k] = colour / um;
    m->unit[MIP3D_A] = 1.0f / um;
    for (int k = MIP3D_NX; k < 8; k++)
        m->unit[k] = 1.0f / sm;
}

/* Fixed point of x in units of `unit`: rounded to nearest and clamped, as
 * the machine's vr_q8 rounds (v * 255 + 0.5); zero stays zero. */
static int quantise(float x, float unit, int lo, int hi)
{
    float v = x / unit;
    if (!(v > (float)lo))
        return lo;                /* also NaN */
    if (v >= (float)hi)
        return hi;
    return v >= 0.0f ? (int)(v + 0.5f) : -(int)(-v + 0.5f);
}

static void store(mip3d_t *m, mip3d_packed_t *L, size_t i, const int *q)
{
    size_t base = i * (size_t)m->stride;
    for (int k = 0; k < m->stride; k++) {
        if (m->format == MIP3D_U8)
            ((uint8_t *)L->data)[base + (size_t)k] = (uint8_t)(k < 4 ? q[k] : (q[k] & 0xff));
        else
            ((uint16_t *)L->data)[base + (size_t)k] = (uint16_t)(k < 4 ? q[k] : (q[k] & 0xffff));
    }
}

static int load(const mip3d_t *m, const mip3d_packed_t *L, size_t i, int k)
{
    size_t j = i * (size_t)m->stride + (size_t)k;
    if (m->format == MIP3D_U8)
        return k < 4 ? ((const uint8_t *)L->data)[j] : ((const int8_t *)L->data)[j];
    return k < 4 ? ((const uint16_t *)L->data)[j] : ((const int16_t *)L->data)[j];
}

static size_t voxel_index(const mip3d_packed_t *L, int x, int y, int z)
{
    return (size_t)L->offset[0][x] + L->offset[1][y] + L->offset[2][z];
}

static void packed_base_slice(void *ctx, int z, int thread)
{
    (void)thread;
    mip3d_job_t *job = ctx;
    mip3d_t *m = job->m;
    const mip3d_level_t *L = &m->level[0];
    mip3d_packed_t *P = &m->packed[0];
    int um = unsigned_max(m->format), sm = signed_max(m->format);
    for (int y = 0; y < L->ny; y++)
        for (int x = 0; x < L->nx; x++) {
            float o[8];
            int q[8];
            mip3d_base_voxel(job, x, y, z, o);
            for (int k = 0; k < m->stride; k++)
                q[k] = k < 4 ? quantise(o[k], m->unit[k], 0, um)
                             : quantise(o[k], m->unit[k], -sm, sm);
            store(m, P, voxel_index(P, x, y, z), q);
        }
}

/* The mean of the 2x2x2 children (zero beyond an odd edge), rounded to
 * nearest (halves away from zero): all-zero children give zero, and a
 * non-zero mean needs a non-zero child, as octree.h's occupancy requires. */
static void packed_filter_slice(void *ctx, int z, int thread)
{
    (void)thread;
    mip3d_job_t *job = ctx;
    mip3d_t *m = job->m;
    const mip3d_level_t *S = &m->level[job->dst - 1], *D = &m->level[job->dst];
    const mip3d_packed_t *PS = &m->packed[job->dst - 1];
    mip3d_packed_t *PD = &m->packed[job->dst];
    for (int y = 0; y < D->ny; y++)
        for (int x = 0; x < D->nx; x++) {
            int sum[8] = {0}, q[8];
            for (int d = 0; d < 8; d++) {
                int cx = 2 * x + (d & 1), cy = 2 * y + ((d >> 1) & 1), cz = 2 * z + (d >> 2);
                if (cx >= S->nx || cy >= S->ny || cz >= S->nz)
                    continue;
                size_t i = voxel_index(PS, cx, cy, cz);
                for (int k = 0; k < m->stride; k++)
                    sum[k] += load(m, PS, i, k);
            }
            for (int k = 0; k < m->stride; k++)
                q[k] = sum[k] >= 0 ? (sum[k] + 4) / 8 : -((-sum[k] + 4) / 8);
            store(m, PD, voxel_index(PD, x, y, z), q);
        }
}

/* Brick layout: voxel (x, y, z) in brick (x/4, y/4, z/4), x fastest inside
 * and across bricks; the index is a sum of one term per axis. */
static pp5_status_t packed_level_alloc(mip3d_t *m, int level)
{
    const mip3d_level_t *L = &m->level[level];
    mip3d_packed_t *P = &m->packed[level];
    const int b = MIP3D_BRICK;
    int n[3] = {L->nx, L->ny, L->nz}, bricks[3];
    for (int a = 0; a < 3; a++)
        bricks[a] = (n[a] + b - 1) / b;
    size_t voxels, bytes;
    if (!pp5_mul3_size((size_t)bricks[0], (size_t)bricks[1], (size_t)bricks[2], &voxels) ||
        !pp5_mul_size(voxels, (size_t)(b * b * b), &voxels) ||
        !pp5_mul_size(voxels, (size_t)m->stride * (size_t)mip3d_format_bytes(m->format), &bytes) ||
        voxels > UINT32_MAX)
        return pp5_fail(PP5_E_NOMEM, "mip3d: level %dx%dx%d too large", n[0], n[1], n[2]);
    P->data = mip3d_alloc_voxels(bytes);
    P->data_bytes = bytes;
    if (P->data)
        memset(P->data, 0, bytes);    /* bricks' padding voxels stay zero */
    size_t step[3] = {(size_t)b * b * b, (size_t)b * b * b * (size_t)bricks[0],
                      (size_t)b * b * b * (size_t)bricks[0] * (size_t)bricks[1]};
    size_t inner[3] = {1, (size_t)b, (size_t)b * b};
    for (int a = 0; a < 3; a++) {
        P->offset[a] = malloc((size_t)n[a] * sizeof(uint32_t));
        if (!P->offset[a])
            break;
        for (int i = 0; i < n[a]; i++)
            P->offset[a][i] = (uint32_t)((size_t)(i / b) * step[a] + (size_t)(i % b) * inner[a]);
    }
    if (!P->data || !P->offset[0] || !P->offset[1] || !P->offset[2])
        return pp5_fail(PP5_E_NOMEM, "mip3d: cannot allocate %zu bytes", bytes);
    m->bytes += bytes + (size_t)(n[0] + n[1] + n[2]) * sizeof(uint32_t);
    return PP5_OK;
}

pp5_status_t mip3d_build_packed(mip3d_t *m, const volume_t *v, const classify_tf_t *tf,
                                const shade_params_t *shade, mip3d_format_t format, int threads)
{
    memset(m, 0, sizeof *m);
    if (!v->data || v->nx < 1 || v->ny < 1 || v->nz < 1)
        return pp5_fail(PP5_E_RANGE, "mip3d: empty volume");
    m->lighting = shade->lighting;
    m->stride = shade->lighting == SHADE_DIFFUSE_FIXED_LIGHT ? 4 : 8;
    m->format = format;
    mip3d_geometry(m, v);
    packed_units(m, tf, shade);
    pp5_status_t st = PP5_OK;
    for (int n = 0; st == PP5_OK && n < m->levels; n++)
        st = packed_level_alloc(m, n);
    mip3d_job_t job = {m, v, tf, shade, 0, 0};
    if (st == PP5_OK)
        st = parallel_for(threads, v->nz, packed_base_slice, &job);
    for (int n = 1; st == PP5_OK && n < m->levels; n++) {
        job.dst = n;
        st = parallel_for(threads, m->level[n].nz, packed_filter_slice, &job);
    }
    if (st != PP5_OK)
        mip3d_free(m);
    return st;
}
