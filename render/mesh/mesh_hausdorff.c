/* mesh_hausdorff.c: bounded-error one-sided maxima by triangle refinement,
 * and area-uniform sample means. */
#include "mesh_hausdorff.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_bvh.h"

void mesh_distance_defaults(mesh_distance_opts_t *o)
{
    o->bound_rel = 1e-5;
    o->mean_samples = 200000;
    o->max_cells = 4000000;   /* enough for the bunny at 50 % to reach 1e-5 (about 45 MB) */
}

typedef struct {
    double p[3][3];
    double d[3];
    int slot[3];     /* nearest triangle (leaf slot in the other mesh's tree) per corner */
    double ub;
} cell_t;

typedef struct {
    cell_t *c;
    size_t n, cap;
} cell_heap_t;

static double dist3(const double *a, const double *b)
{
    double x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
    return sqrt(x * x + y * y + z * z);
}

/* The largest distance any point of the cell can have: d is 1-Lipschitz, so
 * d(x) <= d(p_i) + |x - p_i|; x is within L/sqrt(3) of some corner (the
 * circumradius bound) and within max_j |p_j - p_i| of corner i. */
static double cell_upper(const mesh_bvh_t *bb, const cell_t *c)
{
    double l01 = dist3(c->p[0], c->p[1]), l12 = dist3(c->p[1], c->p[2]),
           l02 = dist3(c->p[0], c->p[2]);
    double lmax = fmax(l01, fmax(l12, l02));
    double dmax = fmax(c->d[0], fmax(c->d[1], c->d[2]));
    double ub = dmax + lmax / sqrt(3.0);
    ub = fmin(ub, c->d[0] + fmax(l01, l02));
    ub = fmin(ub, c->d[1] + fmax(l01, l12));
    ub = fmin(ub, c->d[2] + fmax(l02, l12));
    /* Tighter: the distance to one fixed triangle is convex, so over a convex
     * piece it peaks at the piece's corners.  The cell is split into three
     * quads (corner k, the midpoints of its two edges, the centroid), and
     * quad k is bounded by corner k's nearest triangle. */
    double g[3], mid[3][3];
    for (int j = 0; j < 3; j++) {
        g[j] = (c->p[0][j] + c->p[1][j] + c->p[2][j]) / 3.0;
        for (int k = 0; k < 3; k++)
            mid[k][j] = 0.5 * (c->p[k][j] + c->p[(k + 1) % 3][j]);
    }
    double quads = c->d[0];
    for (int k = 0; k < 3 && quads < ub; k++) {
        if (c->slot[k] < 0) {
            quads = INFINITY;
            break;
        }
        const double *t = bb->tri_pos + 9 * c->slot[k];
        const double *q[3] = {mid[k], g, mid[(k + 2) % 3]};
        quads = fmax(quads, c->d[k]);
        for (int j = 0; j < 3 && quads < ub; j++)
            quads = fmax(quads, sqrt(point_triangle_dist_sq(q[j], t, t + 3, t + 6)));
    }
    ub = fmin(ub, quads);
    /* ... and the whole cell by any one corner's nearest triangle */
    for (int k = 0; k < 3; k++) {
        if (c->slot[k] < 0 || (k > 0 && c->slot[k] == c->slot[k - 1]))
            continue;
        const double *t = bb->tri_pos + 9 * c->slot[k];
        double worst = 0;
        for (int j = 0; j < 3 && worst < ub; j++)
            worst = fmax(worst, sqrt(point_triangle_dist_sq(c->p[j], t, t + 3, t + 6)));
        ub = fmin(ub, worst);
    }
    return ub;
}

static int heap_push(cell_heap_t *h, const cell_t *c)
{
    if (h->n == h->cap) {
        size_t cap = h->cap ? 2 * h->cap : 1024;
        cell_t *nc = realloc(h->c, sizeof *nc * cap);
        if (!nc)
            return 0;
        h->c = nc, h->cap = cap;
    }
    size_t i = h->n++;
    while (i > 0 && h->c[(i - 1) / 2].ub < c->ub) {
        h->c[i] = h->c[(i - 1) / 2];
        i = (i - 1) / 2;
    }
    h->c[i] = *c;
    return 1;
}

static cell_t heap_pop(cell_heap_t *h)
{
    cell_t top = h->c[0], last = h->c[--h->n];
    size_t i = 0;
    for (;;) {
        size_t k = 2 * i + 1;
        if (k >= h->n)
            break;
        if (k + 1 < h->n && h->c[k + 1].ub > h->c[k].ub)
            k++;
        if (h->c[k].ub <= last.ub)
            break;
        h->c[i] = h->c[k];
        i = k;
    }
    if (h->n)
        h->c[i] = last;
    return top;
}

/* max over A of the distance to B, within *bound above the returned value. */
static pp5_status_t one_sided_max(const mesh_t *a, const mesh_bvh_t *bb, double eps,
                                  long max_cells, double sampled_max, double *h, double *bound,
                                  long *cells)
{
    double *vd = malloc(sizeof *vd * ((size_t)a->n_vertices + 1));
    int *vslot = malloc(sizeof *vslot * ((size_t)a->n_vertices + 1));
    cell_heap_t heap = {0};
    if (!vd || !vslot) {
        free(vd), free(vslot);
        return pp5_fail(PP5_E_NOMEM, "hausdorff: out of memory");
    }
    int hint = -1;
    double lb = sampled_max;
    for (int v = 0; v < a->n_vertices; v++)
        vslot[v] = -2;
    for (int c = 0; c < 3 * a->n_faces; c++)
        vslot[a->tri[c]] = -1;   /* only vertices that faces use are on the surface */
    for (int v = 0; v < a->n_vertices; v++) {
        if (vslot[v] == -2)
            continue;
        vd[v] = sqrt(mesh_bvh_nearest_sq(bb, a->pos + 3 * v, &hint));
        vslot[v] = hint;
        lb = fmax(lb, vd[v]);
    }
    pp5_status_t st = PP5_OK;
    for (int f = 0; f < a->n_faces && st == PP5_OK; f++) {
        cell_t c;
        for (int k = 0; k < 3; k++) {
            memcpy(c.p[k], a->pos + 3 * a->tri[3 * f + k], sizeof c.p[k]);
            c.d[k] = vd[a->tri[3 * f + k]];
            c.slot[k] = vslot[a->tri[3 * f + k]];
        }
        c.ub = cell_upper(bb, &c);
        if (c.ub > lb + eps && !heap_push(&heap, &c))
            st = pp5_fail(PP5_E_NOMEM, "hausdorff: out of memory");
    }
    long n = a->n_faces;
    while (st == PP5_OK && heap.n > 0 && heap.c[0].ub > lb + eps && n < max_cells) {
        cell_t c = heap_pop(&heap);
        double m[3][3], md[3];
        int ms[3];
        for (int k = 0; k < 3; k++) {
            for (int j = 0; j < 3; j++)
                m[k][j] = 0.5 * (c.p[k][j] + c.p[(k + 1) % 3][j]);
            hint = c.slot[k];
            md[k] = sqrt(mesh_bvh_nearest_sq(bb, m[k], &hint));
            ms[k] = hint;
            lb = fmax(lb, md[k]);
        }
        /* four children: three corners and the middle */
        for (int k = 0; k < 4 && st == PP5_OK; k++) {
            cell_t s;
            if (k < 3) {
                memcpy(s.p[0], c.p[k], sizeof s.p[0]);
                memcpy(s.p[1], m[k], sizeof s.p[1]);
                memcpy(s.p[2], m[(k + 2) % 3], sizeof s.p[2]);
                s.d[0] = c.d[k], s.d[1] = md[k], s.d[2] = md[(k + 2) % 3];
                s.slot[0] = c.slot[k], s.slot[1] = ms[k], s.slot[2] = ms[(k + 2) % 3];
            } else {
                memcpy(s.p, m, sizeof s.p);
                memcpy(s.d, md, sizeof s.d);
                memcpy(s.slot, ms, sizeof s.slot);
            }
            s.ub = cell_upper(bb, &s);
            if (s.ub > lb + eps && !heap_push(&heap, &s))
                st = pp5_fail(PP5_E_NOMEM, "hausdorff: out of memory");
        }
        n += 4;
    }
    *h = lb;
    /* every cell set aside had an upper bound within eps of the best found */
    *bound = heap.n > 0 && heap.c[0].ub > lb + eps ? heap.c[0].ub - lb : eps;
    *cells = n;
    free(heap.c);
    free(vd);
    free(vslot);
    return st;
}

static uint64_t splitmix64(uint64_t *s)
{
    uint64_t z = (*s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static double unit_random(uint64_t *s)
{
    return (double)(splitmix64(s) >> 11) * (1.0 / 9007199254740992.0);
}

/* Area-weighted mean distance from A to B over about n uniform samples;
 * triangles get samples in proportion to area (error diffusion keeps the
 * total exact), at uniform barycentric positions from a fixed seed. */
static double one_sided_mean(const mesh_t *a, const mesh_bvh_t *bb, long n, double *max)
{
    double total = mesh_area(a), acc = 0, sum = 0;
    *max = 0;
    long taken = 0;
    uint64_t seed = 0x5eed0001ull;
    int hint = -1;
    if (!(total > 0))
        return 0.0;
    for (int f = 0; f < a->n_faces; f++) {
        double nrm[3];
        mesh_face_normal(a, f, nrm);
        acc += 0.5 * sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]) / total *
               (double)n;
        long k = (long)floor(acc);
        acc -= (double)k;
        const double *p0 = a->pos + 3 * a->tri[3 * f], *p1 = a->pos + 3 * a->tri[3 * f + 1],
                     *p2 = a->pos + 3 * a->tri[3 * f + 2];
        for (long i = 0; i < k; i++) {
            double u = unit_random(&seed), v = unit_random(&seed);
            if (u + v > 1)
                u = 1 - u, v = 1 - v;
            double q[3];
            for (int j = 0; j < 3; j++)
                q[j] = p0[j] + u * (p1[j] - p0[j]) + v * (p2[j] - p0[j]);
            double dq = sqrt(mesh_bvh_nearest_sq(bb, q, &hint));
            sum += dq;
            *max = fmax(*max, dq);
            taken++;
        }
    }
    return taken ? sum / (double)taken : 0.0;
}

pp5_status_t mesh_distance(const mesh_t *a, const mesh_t *b, const mesh_distance_opts_t *o,
                           mesh_distance_t *d)
{
    mesh_distance_opts_t def;
    if (!o) {
        mesh_distance_defaults(&def);
        o = &def;
    }
    memset(d, 0, sizeof *d);
    if (a->n_faces == 0 || b->n_faces == 0)
        return pp5_fail(PP5_E_FORMAT, "hausdorff: a mesh without faces (%d, %d)", a->n_faces,
                        b->n_faces);
    d->diagonal = mesh_diagonal(a);
    double eps = o->bound_rel * (d->diagonal > 0 ? d->diagonal : 1.0);
    mesh_bvh_t ba, bb;
    pp5_status_t st = mesh_bvh_build(a, &ba);
    if (st != PP5_OK)
        return st;
    st = mesh_bvh_build(b, &bb);
    if (st != PP5_OK) {
        mesh_bvh_free(&ba);
        return st;
    }
    /* the samples' largest distances start the refinement's lower bounds */
    double smax_ab, smax_ba;
    d->mean_ab = one_sided_mean(a, &bb, o->mean_samples, &smax_ab);
    d->mean_ba = one_sided_mean(b, &ba, o->mean_samples, &smax_ba);
    st = one_sided_max(a, &bb, eps, o->max_cells, smax_ab, &d->h_ab, &d->bound_ab,
                       &d->cells_ab);
    if (st == PP5_OK)
        st = one_sided_max(b, &ba, eps, o->max_cells, smax_ba, &d->h_ba, &d->bound_ba,
                           &d->cells_ba);
    d->hausdorff = fmax(d->h_ab, d->h_ba);
    mesh_bvh_free(&ba);
    mesh_bvh_free(&bb);
    return st;
}
