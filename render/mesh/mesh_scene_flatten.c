/* mesh_scene_flatten.c: a scene as one world-space triangle list
 * (mesh_scene_flatten, mesh_scene.h), every object at its level of detail. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_scene.h"

/* One mesh at one level, with its object-space vertex normals. */
typedef struct {
    int mesh, level;
    mesh_t m;
    bool owned;            /* extracted (freed here) or the scene's own mesh */
    double *normals;       /* 3 per vertex, unit (zero where no face uses it) */
} level_mesh_t;

typedef struct {
    level_mesh_t *items;
    int n, cap;
} level_cache_t;

static double *vertex_normals(const mesh_t *m)
{
    double *n = calloc((size_t)m->n_vertices * 3 + 3, sizeof *n);
    if (!n)
        return NULL;
    for (int f = 0; f < m->n_faces; f++) {
        double fn[3];   /* length 2 x area: the sum is area-weighted */
        mesh_face_normal(m, f, fn);
        for (int c = 0; c < 3; c++)
            for (int k = 0; k < 3; k++)
                n[3 * m->tri[3 * f + c] + k] += fn[k];
    }
    for (int v = 0; v < m->n_vertices; v++) {
        double *p = n + 3 * v, l = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        if (l > 0)
            p[0] /= l, p[1] /= l, p[2] /= l;
    }
    return n;
}

static void cache_free(level_cache_t *c)
{
    for (int i = 0; i < c->n; i++) {
        if (c->items[i].owned)
            mesh_free(&c->items[i].m);
        free(c->items[i].normals);
    }
    free(c->items);
    memset(c, 0, sizeof *c);
}

/* The index in c of mesh `mesh` at `level` (extracted on first use; an
 * index, as the cache moves when it grows). */
static pp5_status_t cache_get(level_cache_t *c, mesh_scene_t *s, int mesh, int level, int *out)
{
    scene_mesh_t *sm = &s->meshes[mesh];
    if (!sm->have_rec || level < 0)
        level = 0;
    if (sm->have_rec && level >= sm->rec.n_levels)
        level = sm->rec.n_levels - 1;
    for (int i = 0; i < c->n; i++)
        if (c->items[i].mesh == mesh && c->items[i].level == level)
            return *out = i, PP5_OK;
    if (c->n == c->cap) {
        int cap = c->cap ? 2 * c->cap : 16;
        level_mesh_t *grown = realloc(c->items, sizeof *grown * (size_t)cap);
        if (!grown)
            return pp5_fail(PP5_E_NOMEM, "%s: out of memory for levels of detail", s->source);
        c->items = grown, c->cap = cap;
    }
    level_mesh_t *lm = &c->items[c->n];
    memset(lm, 0, sizeof *lm);
    lm->mesh = mesh, lm->level = level;
    if (level == 0) {
        lm->m = sm->mesh;
    } else {
        pp5_status_t st = mesh_record_extract(&sm->rec, level, &lm->m);
        if (st != PP5_OK)
            return st;
        lm->owned = true;
    }
    lm->normals = vertex_normals(&lm->m);
    if (!lm->normals) {
        if (lm->owned)
            mesh_free(&lm->m);
        return pp5_fail(PP5_E_NOMEM, "%s: out of memory for vertex normals", s->source);
    }
    *out = c->n++;
    return PP5_OK;
}

/* The cofactor matrix of m's upper 3x3 (det x the inverse transpose): it
 * carries normals through any invertible transform; returns det. */
static double normal_matrix(const double m[16], double c[9])
{
    const double a = m[0], b = m[1], d = m[2], e = m[4], f = m[5], g = m[6];
    const double h = m[8], i = m[9], j = m[10];
    c[0] = f * j - g * i, c[1] = g * h - e * j, c[2] = e * i - f * h;
    c[3] = d * i - b * j, c[4] = a * j - d * h, c[5] = b * h - a * i;
    c[6] = b * g - d * f, c[7] = d * e - a * g, c[8] = a * f - b * e;
    return a * c[0] + b * c[1] + d * c[2];
}

static void put_object(const scene_object_t *o, const level_mesh_t *lm, int32_t index,
                       mesh_soup_t *out, int *t)
{
    double nm[9];
    double det = normal_matrix(o->xform, nm), sign = det < 0 ? -1 : 1;
    const double *x = o->xform;
    for (int f = 0; f < lm->m.n_faces; f++, (*t)++) {
        for (int c = 0; c < 3; c++) {
            /* a mirroring transform turns the winding: swap two corners */
            int cc = det < 0 && c > 0 ? 3 - c : c;
            int v = lm->m.tri[3 * f + cc];
            const double *p = lm->m.pos + 3 * v, *n = lm->normals + 3 * v;
            size_t k = 9 * (size_t)*t + 3 * (size_t)c;
            double wn[3], l = 0;
            for (int r = 0; r < 3; r++) {
                out->pos[k + r] = x[4 * r] * p[0] + x[4 * r + 1] * p[1] + x[4 * r + 2] * p[2] +
                                  x[4 * r + 3];
                wn[r] = sign * (nm[3 * r] * n[0] + nm[3 * r + 1] * n[1] + nm[3 * r + 2] * n[2]);
                l += wn[r] * wn[r];
            }
            l = l > 0 ? 1 / sqrt(l) : 0;
            for (int r = 0; r < 3; r++) {
                out->nrm[k + r] = wn[r] * l;
                out->rgb[k + r] = o->rgb[r];
            }
        }
        out->object[*t] = index;
    }
}

pp5_status_t mesh_scene_flatten(mesh_scene_t *s, const int *levels, mesh_soup_t *out)
{
    memset(out, 0, sizeof *out);
    level_cache_t cache = {0};
    int *per = calloc((size_t)s->n_objects + 1, sizeof *per);
    if (!per)
        return pp5_fail(PP5_E_NOMEM, "%s: out of memory", s->source);
    long total = 0;
    pp5_status_t st = PP5_OK;
    for (int o = 0; o < s->n_objects && st == PP5_OK; o++) {
        st = cache_get(&cache, s, s->objects[o].mesh, levels ? levels[o] : 0, &per[o]);
        if (st == PP5_OK)
            total += cache.items[per[o]].m.n_faces;
    }
    if (st == PP5_OK && total > MESH_MAX_FACES)
        st = pp5_fail(PP5_E_RANGE, "%s: %ld triangles in all (at most %d)", s->source, total,
                      MESH_MAX_FACES);
    if (st == PP5_OK) {
        size_t n = (size_t)total;
        out->pos = malloc(sizeof *out->pos * 9 * n + 1);
        out->nrm = malloc(sizeof *out->nrm * 9 * n + 1);
        out->rgb = malloc(sizeof *out->rgb * 9 * n + 1);
        out->object = malloc(sizeof *out->object * n + 1);
        if (!out->pos || !out->nrm || !out->rgb || !out->object)
            st = pp5_fail(PP5_E_NOMEM, "%s: out of memory for %ld triangles", s->source, total);
    }
    int t = 0;
    for (int o = 0; o < s->n_objects && st == PP5_OK; o++)
        put_object(&s->objects[o], &cache.items[per[o]], o, out, &t);
    out->n_tris = t;
    free(per);
    cache_free(&cache);
    if (st != PP5_OK)
        mesh_soup_free(out);
    return st;
}

void mesh_soup_free(mesh_soup_t *soup)
{
    free(soup->pos);
    free(soup->nrm);
    free(soup->rgb);
    free(soup->object);
    memset(soup, 0, sizeof *soup);
}
