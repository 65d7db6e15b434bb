/* mesh.c: the indexed triangle mesh: allocation, validation, bounds, areas. */
#include "mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

pp5_status_t mesh_alloc(mesh_t *m, int nv, int nf)
{
    memset(m, 0, sizeof *m);
    if (nv < 0 || nv > MESH_MAX_VERTICES)
        return pp5_fail(PP5_E_RANGE, "mesh: %d vertices (at most %d)", nv, MESH_MAX_VERTICES);
    if (nf < 0 || nf > MESH_MAX_FACES)
        return pp5_fail(PP5_E_RANGE, "mesh: %d faces (at most %d)", nf, MESH_MAX_FACES);
    m->pos = calloc((size_t)nv * 3 + 1, sizeof *m->pos);
    m->tri = calloc((size_t)nf * 3 + 1, sizeof *m->tri);
    if (!m->pos || !m->tri) {
        mesh_free(m);
        return pp5_fail(PP5_E_NOMEM, "mesh: out of memory for %d vertices, %d faces", nv, nf);
    }
    m->n_vertices = nv;
    m->n_faces = nf;
    return PP5_OK;
}

void mesh_free(mesh_t *m)
{
    free(m->pos);
    free(m->tri);
    memset(m, 0, sizeof *m);
}

pp5_status_t mesh_copy(const mesh_t *src, mesh_t *dst)
{
    pp5_status_t st = mesh_alloc(dst, src->n_vertices, src->n_faces);
    if (st != PP5_OK)
        return st;
    memcpy(dst->pos, src->pos, sizeof *src->pos * 3 * (size_t)src->n_vertices);
    memcpy(dst->tri, src->tri, sizeof *src->tri * 3 * (size_t)src->n_faces);
    memcpy(dst->source, src->source, sizeof dst->source);
    return PP5_OK;
}

pp5_status_t mesh_validate(const mesh_t *m, const char *what)
{
    for (int v = 0; v < 3 * m->n_vertices; v++)
        if (!isfinite(m->pos[v]))
            return pp5_fail(PP5_E_FORMAT, "%s: vertex %d has a non-finite coordinate", what,
                            v / 3 + 1);
    for (int f = 0; f < m->n_faces; f++) {
        const int32_t *t = m->tri + 3 * f;
        for (int k = 0; k < 3; k++)
            if (t[k] < 0 || t[k] >= m->n_vertices)
                return pp5_fail(PP5_E_FORMAT, "%s: face %d uses vertex %d of %d", what, f + 1,
                                (int)t[k] + 1, m->n_vertices);
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
            return pp5_fail(PP5_E_FORMAT, "%s: face %d repeats a vertex (%d %d %d)", what,
                            f + 1, (int)t[0] + 1, (int)t[1] + 1, (int)t[2] + 1);
    }
    return PP5_OK;
}

void mesh_bounds(const mesh_t *m, double lo[3], double hi[3])
{
    for (int k = 0; k < 3; k++) {
        lo[k] = INFINITY;
        hi[k] = -INFINITY;
    }
    for (int c = 0; c < 3 * m->n_faces; c++) {
        const double *p = m->pos + 3 * m->tri[c];
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], p[k]);
            hi[k] = fmax(hi[k], p[k]);
        }
    }
    if (m->n_faces == 0)
        for (int v = 0; v < m->n_vertices; v++)
            for (int k = 0; k < 3; k++) {
                lo[k] = fmin(lo[k], m->pos[3 * v + k]);
                hi[k] = fmax(hi[k], m->pos[3 * v + k]);
            }
    if (lo[0] > hi[0])
        for (int k = 0; k < 3; k++)
            lo[k] = hi[k] = 0.0;
}

double mesh_diagonal(const mesh_t *m)
{
    double lo[3], hi[3];
    mesh_bounds(m, lo, hi);
    return sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

pp5_status_t mesh_drop_unused(mesh_t *m, int *dropped)
{
    int32_t *map = malloc(sizeof *map * ((size_t)m->n_vertices + 1));
    if (!map)
        return pp5_fail(PP5_E_NOMEM, "mesh: out of memory");
    for (int v = 0; v < m->n_vertices; v++)
        map[v] = -1;
    for (int c = 0; c < 3 * m->n_faces; c++)
        map[m->tri[c]] = 0;
    int n = 0;
    for (int v = 0; v < m->n_vertices; v++)
        if (map[v] == 0) {
            map[v] = n;
            memmove(m->pos + 3 * n, m->pos + 3 * v, 3 * sizeof *m->pos);
            n++;
        }
    for (int c = 0; c < 3 * m->n_faces; c++)
        m->tri[c] = map[m->tri[c]];
    if (dropped)
        *dropped = m->n_vertices - n;
    m->n_vertices = n;
    free(map);
    return PP5_OK;
}

void mesh_face_normal(const mesh_t *m, int f, double n[3])
{
    const double *a = m->pos + 3 * m->tri[3 * f], *b = m->pos + 3 * m->tri[3 * f + 1],
                 *c = m->pos + 3 * m->tri[3 * f + 2];
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    n[0] = u[1] * w[2] - u[2] * w[1];
    n[1] = u[2] * w[0] - u[0] * w[2];
    n[2] = u[0] * w[1] - u[1] * w[0];
}

double mesh_area(const mesh_t *m)
{
    double a = 0.0;
    for (int f = 0; f < m->n_faces; f++) {
        double n[3];
        mesh_face_normal(m, f, n);
        a += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    }
    return a;
}

double mesh_signed_volume(const mesh_t *m)
{
    double v = 0;
    for (int f = 0; f < m->n_faces; f++) {
        const double *a = m->pos + 3 * m->tri[3 * f], *b = m->pos + 3 * m->tri[3 * f + 1],
                     *c = m->pos + 3 * m->tri[3 * f + 2];
        v += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
             a[2] * (b[0] * c[1] - b[1] * c[0]);
    }
    return v / 6;
}
