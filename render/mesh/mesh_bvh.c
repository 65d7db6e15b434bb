/* mesh_bvh.c: median-split bounding-box tree and exact nearest-point queries. */
#include "mesh_bvh.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define BVH_LEAF 4
#define BVH_STACK 128

static inline double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

double point_triangle_dist_sq(const double p[3], const double *a, const double *b,
                              const double *c)
{
    double ab[3], ac[3], ap[3], q[3];
    for (int k = 0; k < 3; k++)
        ab[k] = b[k] - a[k], ac[k] = c[k] - a[k], ap[k] = p[k] - a[k];
    double d1 = dot3(ab, ap), d2 = dot3(ac, ap);
    if (d1 <= 0 && d2 <= 0)
        return dot3(ap, ap);
    double bp[3] = {p[0] - b[0], p[1] - b[1], p[2] - b[2]};
    double d3 = dot3(ab, bp), d4 = dot3(ac, bp);
    if (d3 >= 0 && d4 <= d3)
        return dot3(bp, bp);
    double vc = d1 * d4 - d3 * d2;
    double v, w;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        v = d1 / (d1 - d3);
        for (int k = 0; k < 3; k++)
            q[k] = a[k] + v * ab[k] - p[k];
        return dot3(q, q);
    }
    double cp[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
    double d5 = dot3(ab, cp), d6 = dot3(ac, cp);
    if (d6 >= 0 && d5 <= d6)
        return dot3(cp, cp);
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        w = d2 / (d2 - d6);
        for (int k = 0; k < 3; k++)
            q[k] = a[k] + w * ac[k] - p[k];
        return dot3(q, q);
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (int k = 0; k < 3; k++)
            q[k] = b[k] + w * (c[k] - b[k]) - p[k];
        return dot3(q, q);
    }
    double denom = va + vb + vc;
    if (!(denom > 0))   /* degenerate triangle: the nearest of its edges */
        return fmin(point_triangle_dist_sq(p, a, b, b), point_triangle_dist_sq(p, b, c, c));
    v = vb / denom;
    w = vc / denom;
    for (int k = 0; k < 3; k++)
        q[k] = a[k] + v * ab[k] + w * ac[k] - p[k];
    return dot3(q, q);
}

typedef struct {
    const mesh_bvh_t *b;
    float *centroid;   /* 3 per triangle */
} bvh_build_t;

static void node_bounds(bvh_build_t *bb, mesh_bvh_node_t *n, int first, int count)
{
    const mesh_t *m = bb->b->mesh;
    for (int k = 0; k < 3; k++)
        n->lo[k] = FLT_MAX, n->hi[k] = -FLT_MAX;
    for (int i = first; i < first + count; i++)
        for (int c = 0; c < 3; c++) {
            const double *p = m->pos + 3 * m->tri[3 * bb->b->order[i] + c];
            for (int k = 0; k < 3; k++) {
                /* float boxes rounded outwards so they still contain the points */
                float lo = (float)p[k], hi = (float)p[k];
                if ((double)lo > p[k])
                    lo = nextafterf(lo, -FLT_MAX);
                if ((double)hi < p[k])
                    hi = nextafterf(hi, FLT_MAX);
                n->lo[k] = fminf(n->lo[k], lo);
                n->hi[k] = fmaxf(n->hi[k], hi);
            }
        }
}

/* Partitions order[first..first+count) about the median centroid on `axis`. */
static void median_split(bvh_build_t *bb, int first, int count, int axis)
{
    int32_t *o = bb->b->order;
    int lo = first, hi = first + count - 1, k = first + count / 2;
    while (lo < hi) {
        float pivot = bb->centroid[3 * o[(lo + hi) / 2] + axis];
        int i = lo, j = hi;
        while (i <= j) {
            while (bb->centroid[3 * o[i] + axis] < pivot)
                i++;
            while (bb->centroid[3 * o[j] + axis] > pivot)
                j--;
            if (i <= j) {
                int32_t t = o[i];
                o[i] = o[j], o[j] = t;
                i++, j--;
            }
        }
        if (k <= j)
            hi = j;
        else if (k >= i)
            lo = i;
        else
            break;
    }
}

static void build_node(bvh_build_t *bb, mesh_bvh_t *b, int node, int first, int count)
{
    mesh_bvh_node_t *n = &b->nodes[node];
    node_bounds(bb, n, first, count);
    if (count <= BVH_LEAF) {
        n->first = first, n->count = count;
        return;
    }
    int axis = 0;
    for (int k = 1; k < 3; k++)
        if (n->hi[k] - n->lo[k] > n->hi[axis] - n->lo[axis])
            axis = k;
    median_split(bb, first, count, axis);
    int left = b->n_nodes;
    b->n_nodes += 2;
    n->first = left, n->count = 0;
    int half = count / 2;
    build_node(bb, b, left, first, half);
    build_node(bb, b, left + 1, first + half, count - half);
}

pp5_status_t mesh_bvh_build(const mesh_t *m, mesh_bvh_t *b)
{
    memset(b, 0, sizeof *b);
    b->mesh = m;
    size_t nf = (size_t)m->n_faces + 1;
    b->nodes = malloc(sizeof *b->nodes * 2 * nf);
    b->order = malloc(sizeof *b->order * nf);
    b->tri_pos = malloc(sizeof *b->tri_pos * 9 * nf);
    bvh_build_t bb = {b, malloc(sizeof(float) * 3 * nf)};
    if (!b->nodes || !b->order || !b->tri_pos || !bb.centroid) {
        free(bb.centroid);
        mesh_bvh_free(b);
        return pp5_fail(PP5_E_NOMEM, "bvh: out of memory for %d faces", m->n_faces);
    }
    for (int f = 0; f < m->n_faces; f++) {
        b->order[f] = f;
        for (int k = 0; k < 3; k++)
            bb.centroid[3 * f + k] = (float)((m->pos[3 * m->tri[3 * f] + k] +
                                              m->pos[3 * m->tri[3 * f + 1] + k] +
                                              m->pos[3 * m->tri[3 * f + 2] + k]) / 3.0);
    }
    b->n_nodes = 1;
    build_node(&bb, b, 0, 0, m->n_faces);
    for (int i = 0; i < m->n_faces; i++)
        for (int c = 0; c < 3; c++)
            memcpy(b->tri_pos + 9 * i + 3 * c, m->pos + 3 * m->tri[3 * b->order[i] + c],
                   3 * sizeof(double));
    free(bb.centroid);
    return PP5_OK;
}

void mesh_bvh_free(mesh_bvh_t *b)
{
    free(b->nodes), free(b->order), free(b->tri_pos);
    memset(b, 0, sizeof *b);
}

static double box_dist_sq(const mesh_bvh_node_t *n, const double p[3])
{
    double d = 0;
    for (int k = 0; k < 3; k++) {
        double e = p[k] < n->lo[k] ? n->lo[k] - p[k] : p[k] > n->hi[k] ? p[k] - n->hi[k] : 0;
        d += e * e;
    }
    return d;
}

double mesh_bvh_nearest_sq(const mesh_bvh_t *b, const double p[3], int *hint)
{
    double best = INFINITY;
    int best_slot = -1;
    if (hint && *hint >= 0 && *hint < b->mesh->n_faces) {
        const double *t = b->tri_pos + 9 * *hint;
        best = point_triangle_dist_sq(p, t, t + 3, t + 6);
        best_slot = *hint;
    }
    int stack[BVH_STACK], sp = 0;
    stack[sp++] = 0;
    while (sp > 0) {
        const mesh_bvh_node_t *n = &b->nodes[stack[--sp]];
        if (box_dist_sq(n, p) >= best)
            continue;
        if (n->count > 0) {
            for (int i = n->first; i < n->first + n->count; i++) {
                const double *t = b->tri_pos + 9 * i;
                double d = point_triangle_dist_sq(p, t, t + 3, t + 6);
                if (d < best)
                    best = d, best_slot = i;
            }
            continue;
        }
        double dl = box_dist_sq(&b->nodes[n->first], p);
        double dr = box_dist_sq(&b->nodes[n->first + 1], p);
        /* nearer child on top of the stack, so it is searched first */
        int near = dl <= dr ? n->first : n->first + 1, far = near == n->first ? n->first + 1
                                                                                : n->first;
        if (sp + 2 <= BVH_STACK) {
            stack[sp++] = far;
            stack[sp++] = near;
        }
    }
    if (hint)
        *hint = best_slot;
    return best;
}
