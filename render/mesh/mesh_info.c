/* mesh_info.c: edges by sorting half-edges, boundary loops, fans per vertex,
 * components by union-find, Euler characteristic and genus. */
#include "mesh_info.h"

#include <stdlib.h>
#include <string.h>

static inline int32_t he_from(const mesh_t *m, int h) { return m->tri[h]; }
static inline int32_t he_to(const mesh_t *m, int h)
{
    return m->tri[h - h % 3 + (h % 3 + 1) % 3];
}
static uint64_t he_key(const mesh_t *m, int h)
{
    uint32_t a = (uint32_t)he_from(m, h), b = (uint32_t)he_to(m, h);
    return a < b ? ((uint64_t)a << 32 | b) : ((uint64_t)b << 32 | a);
}

/* LSD radix sort of half-edges by key: 4 passes of 16 bits. */
static pp5_status_t sort_half_edges(const mesh_t *m, int32_t *order, int n)
{
    int32_t *tmp = malloc(sizeof *tmp * ((size_t)n + 1));
    uint64_t *keys = malloc(sizeof *keys * ((size_t)n + 1));
    uint64_t *ktmp = malloc(sizeof *ktmp * ((size_t)n + 1));
    size_t *count = malloc(sizeof *count * 65537);
    if (!tmp || !keys || !ktmp || !count) {
        free(tmp), free(keys), free(ktmp), free(count);
        return pp5_fail(PP5_E_NOMEM, "mesh: out of memory sorting edges");
    }
    for (int i = 0; i < n; i++)
        order[i] = i, keys[i] = he_key(m, i);
    for (int pass = 0; pass < 4; pass++) {
        int sh = 16 * pass;
        memset(count, 0, sizeof *count * 65537);
        for (int i = 0; i < n; i++)
            count[((keys[i] >> sh) & 0xffff) + 1]++;
        for (int b = 0; b < 65536; b++)
            count[b + 1] += count[b];
        for (int i = 0; i < n; i++) {
            size_t d = count[(keys[i] >> sh) & 0xffff]++;
            tmp[d] = order[i];
            ktmp[d] = keys[i];
        }
        memcpy(order, tmp, sizeof *order * (size_t)n);
        memcpy(keys, ktmp, sizeof *keys * (size_t)n);
    }
    free(tmp), free(keys), free(ktmp), free(count);
    return PP5_OK;
}

pp5_status_t mesh_edges_build(const mesh_t *m, mesh_edges_t *e)
{
    memset(e, 0, sizeof *e);
    e->n_half = 3 * m->n_faces;
    e->order = malloc(sizeof *e->order * ((size_t)e->n_half + 1));
    e->edge_start = malloc(sizeof *e->edge_start * ((size_t)e->n_half + 2));
    if (!e->order || !e->edge_start) {
        mesh_edges_free(e);
        return pp5_fail(PP5_E_NOMEM, "mesh: out of memory for edges");
    }
    pp5_status_t st = sort_half_edges(m, e->order, e->n_half);
    if (st != PP5_OK) {
        mesh_edges_free(e);
        return st;
    }
    for (int i = 0; i < e->n_half; i++)
        if (i == 0 || he_key(m, e->order[i]) != he_key(m, e->order[i - 1]))
            e->edge_start[e->n_edges++] = i;
    e->edge_start[e->n_edges] = e->n_half;
    return PP5_OK;
}

void mesh_edges_free(mesh_edges_t *e)
{
    free(e->order);
    free(e->edge_start);
    memset(e, 0, sizeof *e);
}

static int uf_find(int *p, int x)
{
    while (p[x] != x)
        x = p[x] = p[p[x]];
    return x;
}

/* Fans around each vertex: faces at v joined when they share an edge at v
 * that has exactly two faces.  Returns the number of vertices with > 1 fan. */
static int count_nonmanifold_vertices(const mesh_t *m, const mesh_edges_t *e, int *uf)
{
    /* A global union-find over corners: corners (v in face f) and (v in face g)
     * join across each two-face edge through v. */
    for (int h = 0; h < e->n_half; h++)
        uf[h] = h;
    for (int k = 0; k < e->n_edges; k++) {
        int s = e->edge_start[k];
        if (e->edge_start[k + 1] - s != 2)
            continue;
        int h0 = e->order[s], h1 = e->order[s + 1];
        int32_t a = he_from(m, h0);
        /* corners of a and of the other endpoint in both faces */
        for (int end = 0; end < 2; end++) {
            int32_t v = end == 0 ? a : he_to(m, h0);
            int c0 = -1, c1 = -1;
            for (int i = 0; i < 3; i++) {
                if (m->tri[h0 - h0 % 3 + i] == v)
                    c0 = h0 - h0 % 3 + i;
                if (m->tri[h1 - h1 % 3 + i] == v)
                    c1 = h1 - h1 % 3 + i;
            }
            uf[uf_find(uf, c0)] = uf_find(uf, c1);
        }
    }
    int *fans = calloc((size_t)m->n_vertices + 1, sizeof *fans);
    if (!fans)
        return -1;
    for (int h = 0; h < e->n_half; h++)
        if (uf_find(uf, h) == h)
            fans[m->tri[h]]++;
    int bad = 0;
    for (int v = 0; v < m->n_vertices; v++)
        bad += fans[v] > 1;
    free(fans);
    return bad;
}

static int count_components(const mesh_t *m, int *uf, int *n_used)
{
    for (int v = 0; v < m->n_vertices; v++)
        uf[v] = -1;
    for (int c = 0; c < 3 * m->n_faces; c++)
        uf[m->tri[c]] = m->tri[c];
    for (int f = 0; f < m->n_faces; f++)
        for (int k = 1; k < 3; k++)
            uf[uf_find(uf, m->tri[3 * f + k])] = uf_find(uf, m->tri[3 * f]);
    int comps = 0, used = 0;
    for (int v = 0; v < m->n_vertices; v++) {
        used += uf[v] >= 0;
        comps += uf[v] == v;
    }
    *n_used = used;
    return comps;
}

pp5_status_t mesh_info(const mesh_t *m, mesh_info_t *info)
{
    memset(info, 0, sizeof *info);
    info->n_vertices = m->n_vertices;
    info->n_faces = m->n_faces;
    mesh_edges_t e;
    pp5_status_t st = mesh_edges_build(m, &e);
    if (st != PP5_OK)
        return st;
    size_t nuf = (size_t)(e.n_half > m->n_vertices ? e.n_half : m->n_vertices) + 1;
    int *uf = malloc(sizeof *uf * nuf);
    if (!uf) {
        mesh_edges_free(&e);
        return pp5_fail(PP5_E_NOMEM, "mesh: out of memory");
    }
    info->n_edges = e.n_edges;
    for (int k = 0; k < e.n_edges; k++) {
        int n = e.edge_start[k + 1] - e.edge_start[k];
        if (n == 1)
            info->n_boundary_edges++;
        else if (n > 2)
            info->n_nonmanifold_edges++;
        else {
            int h0 = e.order[e.edge_start[k]], h1 = e.order[e.edge_start[k] + 1];
            info->n_misoriented_edges += he_from(m, h0) == he_from(m, h1);
        }
    }
    info->n_nonmanifold_vertices = count_nonmanifold_vertices(m, &e, uf);
    info->n_components = count_components(m, uf, &info->n_used_vertices);
    info->euler = info->n_used_vertices - info->n_edges + info->n_faces;
    info->manifold = info->n_nonmanifold_edges == 0 && info->n_nonmanifold_vertices == 0;
    info->orientable = info->n_misoriented_edges == 0;
    free(uf);
    mesh_edges_free(&e);
    info->genus = -1;
    if (info->manifold) {
        mesh_loops_t loops;
        st = mesh_boundary_loops(m, &loops);
        if (st != PP5_OK)
            return st;
        info->n_boundary_loops = loops.n_loops;
        for (int i = 0; i < loops.n_loops; i++) {
            int len = loops.start[i + 1] - loops.start[i];
            if (i == 0 || len > info->longest_loop)
                info->longest_loop = len;
            if (i == 0 || len < info->shortest_loop)
                info->shortest_loop = len;
        }
        mesh_loops_free(&loops);
        /* chi = sum over components of (2 - 2g - b) */
        if (info->orientable)
            info->genus = (2 * info->n_components - info->euler - info->n_boundary_loops) / 2;
    }
    return PP5_OK;
}

pp5_status_t mesh_boundary_loops(const mesh_t *m, mesh_loops_t *loops)
{
    memset(loops, 0, sizeof *loops);
    mesh_edges_t e;
    pp5_status_t st = mesh_edges_build(m, &e);
    if (st != PP5_OK)
        return st;
    /* next[v] = the vertex a boundary half-edge leaves v for */
    int32_t *next = malloc(sizeof *next * ((size_t)m->n_vertices + 1));
    loops->start = malloc(sizeof *loops->start * ((size_t)e.n_edges + 2));
    loops->verts = malloc(sizeof *loops->verts * ((size_t)e.n_edges + 1));
    if (!next || !loops->start || !loops->verts) {
        st = pp5_fail(PP5_E_NOMEM, "mesh: out of memory for boundary loops");
        goto done;
    }
    for (int v = 0; v < m->n_vertices; v++)
        next[v] = -1;
    for (int k = 0; k < e.n_edges && st == PP5_OK; k++) {
        if (e.edge_start[k + 1] - e.edge_start[k] != 1)
            continue;
        int h = e.order[e.edge_start[k]];
        if (next[he_from(m, h)] >= 0)
            st = pp5_fail(PP5_E_FORMAT, "%s: vertex %d is on two boundary loops (not manifold)",
                          m->source, (int)he_from(m, h) + 1);
        next[he_from(m, h)] = he_to(m, h);
    }
    int n = 0;
    for (int v = 0; v < m->n_vertices && st == PP5_OK; v++) {
        if (next[v] < 0)
            continue;
        loops->start[loops->n_loops++] = n;
        for (int32_t w = v; next[w] >= 0;) {
            loops->verts[n++] = w;
            int32_t nx = next[w];
            next[w] = -1;
            w = nx;
        }
    }
    if (loops->start)
        loops->start[loops->n_loops] = n;
done:
    free(next);
    mesh_edges_free(&e);
    if (st != PP5_OK)
        mesh_loops_free(loops);
    return st;
}

void mesh_loops_free(mesh_loops_t *loops)
{
    free(loops->start);
    free(loops->verts);
    memset(loops, 0, sizeof *loops);
}
