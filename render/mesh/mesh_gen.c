/* mesh_gen.c: generated meshes (spheres, tori, grids, cubes) and hole filling. */
#include "mesh_gen.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_info.h"

static const double PI = 3.14159265358979323846;

pp5_status_t mesh_gen_uv_sphere(int slices, int stacks, double radius, mesh_t *m)
{
    if (slices < 3 || stacks < 2 || slices > 4096 || stacks > 4096)
        return pp5_fail(PP5_E_RANGE, "uv sphere: %d slices x %d stacks (3..4096, 2..4096)",
                        slices, stacks);
    int rings = stacks - 1;
    pp5_status_t st = mesh_alloc(m, 2 + slices * rings, 2 * slices * rings);
    if (st != PP5_OK)
        return st;
    double *p = m->pos;
    p[0] = 0, p[1] = 0, p[2] = radius;                 /* north pole: vertex 0 */
    for (int r = 0; r < rings; r++)
        for (int s = 0; s < slices; s++) {
            double th = PI * (r + 1) / stacks, ph = 2 * PI * s / slices;
            double *q = p + 3 * (1 + r * slices + s);
            q[0] = radius * sin(th) * cos(ph);
            q[1] = radius * sin(th) * sin(ph);
            q[2] = radius * cos(th);
        }
    int south = 1 + rings * slices;
    p[3 * south] = 0, p[3 * south + 1] = 0, p[3 * south + 2] = -radius;
    int32_t *t = m->tri;
    for (int s = 0; s < slices; s++) {
        int s1 = (s + 1) % slices;
        *t++ = 0, *t++ = 1 + s, *t++ = 1 + s1;
        for (int r = 0; r + 1 < rings; r++) {
            int a = 1 + r * slices + s, b = 1 + r * slices + s1;
            int c = a + slices, d = b + slices;
            *t++ = a, *t++ = c, *t++ = d;
            *t++ = a, *t++ = d, *t++ = b;
        }
        int a = 1 + (rings - 1) * slices + s, b = 1 + (rings - 1) * slices + s1;
        *t++ = a, *t++ = south, *t++ = b;
    }
    snprintf(m->source, sizeof m->source, "uv sphere %dx%d", slices, stacks);
    return PP5_OK;
}

pp5_status_t mesh_gen_torus(int nu, int nv, double R, double r, mesh_t *m)
{
    if (nu < 3 || nv < 3 || nu > 4096 || nv > 4096)
        return pp5_fail(PP5_E_RANGE, "torus: %d x %d (3..4096 each)", nu, nv);
    pp5_status_t st = mesh_alloc(m, nu * nv, 2 * nu * nv);
    if (st != PP5_OK)
        return st;
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nv; j++) {
            double u = 2 * PI * i / nu, w = 2 * PI * j / nv;
            double *q = m->pos + 3 * (i * nv + j);
            q[0] = (R + r * cos(w)) * cos(u);
            q[1] = (R + r * cos(w)) * sin(u);
            q[2] = r * sin(w);
        }
    int32_t *t = m->tri;
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nv; j++) {
            int a = i * nv + j, b = ((i + 1) % nu) * nv + j;
            int c = ((i + 1) % nu) * nv + (j + 1) % nv, d = i * nv + (j + 1) % nv;
            *t++ = a, *t++ = b, *t++ = c;
            *t++ = a, *t++ = c, *t++ = d;
        }
    snprintf(m->source, sizeof m->source, "torus %dx%d", nu, nv);
    return PP5_OK;
}

pp5_status_t mesh_gen_grid(int nx, int ny, double sx, double sy, mesh_t *m)
{
    if (nx < 1 || ny < 1 || nx > 4096 || ny > 4096)
        return pp5_fail(PP5_E_RANGE, "grid: %d x %d (1..4096 each)", nx, ny);
    pp5_status_t st = mesh_alloc(m, (nx + 1) * (ny + 1), 2 * nx * ny);
    if (st != PP5_OK)
        return st;
    for (int j = 0; j <= ny; j++)
        for (int i = 0; i <= nx; i++) {
            double *q = m->pos + 3 * (j * (nx + 1) + i);
            q[0] = sx * i / nx, q[1] = sy * j / ny, q[2] = 0.0;
        }
    int32_t *t = m->tri;
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++) {
            int a = j * (nx + 1) + i, b = a + 1, c = a + nx + 2, d = a + nx + 1;
            if ((i + j) % 2 == 0) {
                *t++ = a, *t++ = b, *t++ = c;
                *t++ = a, *t++ = c, *t++ = d;
            } else {
                *t++ = a, *t++ = b, *t++ = d;
                *t++ = b, *t++ = c, *t++ = d;
            }
        }
    snprintf(m->source, sizeof m->source, "grid %dx%d", nx, ny);
    return PP5_OK;
}

/* Vertex index of grid point (i, j) on cube face `f` (shared along edges). */
static int cube_vertex(double *pos, int *n_used, int n, int f, int i, int j, int *lookup)
{
    /* face f: axis = f/2, sign = f%2 ? +1 : -1; (u, v) span the other two axes */
    int axis = f / 2, ua = (axis + 1) % 3, va = (axis + 2) % 3;
    double sign = f % 2 ? 1.0 : -1.0;
    int c[3];
    c[axis] = sign > 0 ? n : 0;
    c[ua] = i, c[va] = j;
    int key = (c[0] * (n + 1) + c[1]) * (n + 1) + c[2];
    if (lookup[key] < 0) {
        lookup[key] = (*n_used)++;
        for (int k = 0; k < 3; k++)
            pos[3 * lookup[key] + k] = -1.0 + 2.0 * c[k] / n;
    }
    return lookup[key];
}

pp5_status_t mesh_gen_cube(int n, mesh_t *m)
{
    if (n < 1 || n > 512)
        return pp5_fail(PP5_E_RANGE, "cube: %d divisions per side (1..512)", n);
    int nv = 6 * n * n + 2;   /* Euler: V = F/2 + 2 */
    pp5_status_t st = mesh_alloc(m, nv, 12 * n * n);
    if (st != PP5_OK)
        return st;
    int cells = (n + 1) * (n + 1) * (n + 1);
    int *lookup = malloc(sizeof *lookup * (size_t)cells);
    if (!lookup) {
        mesh_free(m);
        return pp5_fail(PP5_E_NOMEM, "cube: out of memory");
    }
    for (int i = 0; i < cells; i++)
        lookup[i] = -1;
    int used = 0;
    int32_t *t = m->tri;
    for (int f = 0; f < 6; f++)
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++) {
                int a = cube_vertex(m->pos, &used, n, f, i, j, lookup);
                int b = cube_vertex(m->pos, &used, n, f, i + 1, j, lookup);
                int c = cube_vertex(m->pos, &used, n, f, i + 1, j + 1, lookup);
                int d = cube_vertex(m->pos, &used, n, f, i, j + 1, lookup);
                /* (u, v, axis) is right-handed: counter-clockwise seen from +axis */
                if (f % 2) {
                    *t++ = a, *t++ = b, *t++ = c, *t++ = a, *t++ = c, *t++ = d;
                } else {
                    *t++ = a, *t++ = c, *t++ = b, *t++ = a, *t++ = d, *t++ = c;
                }
            }
    free(lookup);
    m->n_vertices = used;
    snprintf(m->source, sizeof m->source, "cube %dx%d per face", n, n);
    return PP5_OK;
}

pp5_status_t mesh_gen_fill_hole(mesh_t *m, int hole_edges)
{
    int dropped;
    pp5_status_t st = mesh_drop_unused(m, &dropped);
    mesh_loops_t loops;
    if (st == PP5_OK)
        st = mesh_boundary_loops(m, &loops);
    if (st != PP5_OK)
        return st;
    int which = -1, matches = 0;
    for (int i = 0; i < loops.n_loops; i++)
        if (loops.start[i + 1] - loops.start[i] == hole_edges)
            which = which < 0 ? i : which, matches++;
    if (matches != 1) {
        mesh_loops_free(&loops);
        return pp5_fail(PP5_E_FORMAT, "%s: %d boundary loops of %d edges (need exactly one)",
                        m->source, matches, hole_edges);
    }
    mesh_t out;
    st = mesh_alloc(&out, m->n_vertices + 1, m->n_faces + hole_edges);
    if (st != PP5_OK) {
        mesh_loops_free(&loops);
        return st;
    }
    memcpy(out.pos, m->pos, sizeof *m->pos * 3 * (size_t)m->n_vertices);
    memcpy(out.tri, m->tri, sizeof *m->tri * 3 * (size_t)m->n_faces);
    const int32_t *loop = loops.verts + loops.start[which];
    double *c = out.pos + 3 * m->n_vertices;
    for (int i = 0; i < hole_edges; i++)
        for (int k = 0; k < 3; k++)
            c[k] += m->pos[3 * loop[i] + k] / hole_edges;
    /* The loop runs along its faces' orientation, so the fan runs against it. */
    for (int i = 0; i < hole_edges; i++) {
        int32_t *t = out.tri + 3 * (m->n_faces + i);
        t[0] = loop[(i + 1) % hole_edges], t[1] = loop[i], t[2] = m->n_vertices;
    }
    snprintf(out.source, sizeof out.source, "%.200s, hole of %d edges filled", m->source,
             hole_edges);
    mesh_loops_free(&loops);
    mesh_free(m);
    *m = out;
    return PP5_OK;
}

pp5_status_t mesh_gen_by_name(const char *name, mesh_t *m)
{
    if (strncmp(name, "gen:", 4) != 0)
        return pp5_fail(PP5_E_CONFIG, "%s: not a generated mesh name (gen:NAME)", name);
    const char *g = name + 4;
    if (strcmp(g, "sphere") == 0)
        return mesh_gen_uv_sphere(20, 20, 1.0, m);
    if (strcmp(g, "torus") == 0)
        return mesh_gen_torus(48, 24, 1.0, 0.35, m);
    if (strcmp(g, "grid") == 0)
        return mesh_gen_grid(32, 32, 1.0, 1.0, m);
    if (strcmp(g, "cube") == 0)
        return mesh_gen_cube(8, m);
    return pp5_fail(PP5_E_CONFIG, "%s: unknown generated mesh (sphere, torus, grid, cube)",
                    name);
}
