/* simplify_qem.c: Garland & Heckbert 1997 quadric edge collapse, the baseline.
 *
 * Each vertex carries the sum of the plane quadrics of its faces (unit
 * planes, as GH97 §5 and CGAL's GarlandHeckbert_plane_policies; area-weighted
 * planes, Garland's later variant, with qem_area_weighted).  Boundary edges
 * add a plane through the edge perpendicular to its face, weighted by
 * qem_boundary_weight (x the edge's length squared when the faces are
 * area-weighted), which holds boundaries in place (GH97 §6).  The new point
 * (GH97 §4) minimises the summed quadric when that 3x3 system is well
 * conditioned, else along the edge, else it is the best of the endpoints and
 * the midpoint.  Edges are re-costed around the new vertex only. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "simplify_work.h"

typedef struct {
    double q[10];   /* a2 ab ac ad b2 bc bd c2 cd d2 */
} quadric_t;

/* The plane n.x + d = 0 as a quadric (GH97 eq. 2's K_p), to be added with
 * a weight to each vertex it touches. */
static void quadric_of_plane(const double n[3], double d, quadric_t *K)
{
    double a = n[0], b = n[1], c = n[2];
    double *q = K->q;
    q[0] = a * a, q[1] = a * b, q[2] = a * c, q[3] = a * d, q[4] = b * b;
    q[5] = b * c, q[6] = b * d, q[7] = c * c, q[8] = c * d, q[9] = d * d;
}

static void quadric_add(quadric_t *Q, const quadric_t *K, double w)
{
    for (int i = 0; i < 10; i++)
        Q->q[i] += w * K->q[i];
}

/* Written out: the compiler keeps a 10-step loop as a loop at -O2. */
static inline void quadric_sum(const quadric_t *A, const quadric_t *B, quadric_t *S)
{
    const double *a = A->q, *b = B->q;
    double *q = S->q;
    q[0] = a[0] + b[0], q[1] = a[1] + b[1], q[2] = a[2] + b[2], q[3] = a[3] + b[3];
    q[4] = a[4] + b[4], q[5] = a[5] + b[5], q[6] = a[6] + b[6], q[7] = a[7] + b[7];
    q[8] = a[8] + b[8], q[9] = a[9] + b[9];
}

static inline double quadric_eval(const quadric_t *Q, const double p[3])
{
    const double *q = Q->q;
    double x = p[0], y = p[1], z = p[2];
    return q[0] * x * x + 2 * q[1] * x * y + 2 * q[2] * x * z + 2 * q[3] * x + q[4] * y * y +
           2 * q[5] * y * z + 2 * q[6] * y + q[7] * z * z + 2 * q[8] * z + q[9];
}

/* The determinant of rows (a b c), (d e f), (g h i), expanded along the first row. */
static inline double det3(double a, double b, double c, double d, double e, double f, double g,
                          double h, double i)
{
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
}

/* Minimiser of the quadric; false when the system is near singular. */
static bool quadric_optimum(const quadric_t *Q, double p[3])
{
    const double *q = Q->q;
    double b0 = -q[3], b1 = -q[6], b2 = -q[8];
    double det = det3(q[0], q[1], q[2], q[1], q[4], q[5], q[2], q[5], q[7]);
    double scale = fabs(q[0]) + fabs(q[4]) + fabs(q[7]);
    if (!(scale > 0) || fabs(det) < 1e-9 * scale * scale * scale)
        return false;
    /* Cramer's rule: column k replaced by b */
    p[0] = det3(b0, q[1], q[2], b1, q[4], q[5], b2, q[5], q[7]) / det;
    p[1] = det3(q[0], b0, q[2], q[1], b1, q[5], q[2], b2, q[7]) / det;
    p[2] = det3(q[0], q[1], b0, q[1], q[4], b1, q[2], q[5], b2) / det;
    return isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]);
}

typedef struct {
    sw_t *w;
    quadric_t *Q;
} qem_t;

/* A rounded quadric error may dip below zero; it is a squared distance.
 * (fmax is a library call at -O2, and NaN becomes 0 here as there.) */
static inline double not_below_zero(double e)
{
    return e > 0 ? e : 0.0;
}

static double qem_place(const qem_t *s, int a, int b, double p[3])
{
    quadric_t Q;
    quadric_sum(&s->Q[a], &s->Q[b], &Q);
    const double *pa = s->w->pos + 3 * a, *pb = s->w->pos + 3 * b;
    if (quadric_optimum(&Q, p))
        return not_below_zero(quadric_eval(&Q, p));
    {   /* the best point of the edge: Q(pa + t d) is a parabola in t */
        const double *q = Q.q;
        double d[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
        double Ad[3] = {q[0] * d[0] + q[1] * d[1] + q[2] * d[2],
                        q[1] * d[0] + q[4] * d[1] + q[5] * d[2],
                        q[2] * d[0] + q[5] * d[1] + q[7] * d[2]};
        double qa = sw_dot(d, Ad);
        double g[3] = {q[0] * pa[0] + q[1] * pa[1] + q[2] * pa[2] + q[3],
                       q[1] * pa[0] + q[4] * pa[1] + q[5] * pa[2] + q[6],
                       q[2] * pa[0] + q[5] * pa[1] + q[7] * pa[2] + q[8]};
        double qb = sw_dot(d, g);
        if (qa > 1e-12 * (fabs(q[0]) + fabs(q[4]) + fabs(q[7])) * sw_dot(d, d)) {
            double t = -qb / qa;
            t = t < 0 ? 0 : t > 1 ? 1 : t;
            for (int k = 0; k < 3; k++)
                p[k] = pa[k] + t * d[k];
            return not_below_zero(quadric_eval(&Q, p));
        }
    }
    double cand[3][3] = {{pa[0], pa[1], pa[2]}, {pb[0], pb[1], pb[2]},
                         {0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1]), 0.5 * (pa[2] + pb[2])}};
    double best = INFINITY;
    for (int i = 0; i < 3; i++) {
        double e = quadric_eval(&Q, cand[i]);
        if (e < best) {
            best = e;
            memcpy(p, cand[i], 3 * sizeof *p);
        }
    }
    return not_below_zero(best);
}

static void qem_init_quadrics(qem_t *s, double boundary_weight, bool area_weighted)
{
    sw_t *w = s->w;
    for (int f = 0; f < w->nf; f++) {
        const double *n = w->fnormal + 3 * f;   /* sw_face_normal, from sw_init */
        double len = sqrt(sw_dot(n, n));
        if (!(len > 0))
            continue;
        double u[3] = {n[0] / len, n[1] / len, n[2] / len};
        const double *p0 = w->pos + 3 * w->tri[3 * f];
        double d = -sw_dot(u, p0), area = area_weighted ? 0.5 * len : 1.0;
        quadric_t K;
        quadric_of_plane(u, d, &K);
        for (int c = 0; c < 3; c++)
            quadric_add(&s->Q[w->tri[3 * f + c]], &K, area);
        for (int c = 3 * f; c < 3 * f + 3; c++) {
            if (!sw_corner_on_boundary(w, c))
                continue;
            int a = w->tri[c], b = sw_nextv(w, c);
            const double *pa = w->pos + 3 * a, *pb = w->pos + 3 * b;
            double e[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]}, m[3];
            sw_cross(e, u, m);
            double ml = sqrt(sw_dot(m, m));
            if (!(ml > 0))
                continue;
            for (int k = 0; k < 3; k++)
                m[k] /= ml;
            double wgt = boundary_weight * (area_weighted ? sw_dot(e, e) : 1.0);
            quadric_of_plane(m, -sw_dot(m, pa), &K);
            quadric_add(&s->Q[a], &K, wgt);
            quadric_add(&s->Q[b], &K, wgt);
        }
    }
}

/* Queues edge id (a corner) at its cost. */
static void qem_queue(qem_t *s, int id)
{
    sw_t *w = s->w;
    int a = w->tri[id], b = sw_nextv(w, id);
    double p[3];
    sw_queue_set(&w->queue, id, qem_place(s, a < b ? a : b, a < b ? b : a, p),
                 sw_edge_tie(a, b));
}

/* After merging into v every edge at v has a new quadric sum.  In v's fan
 * (counter-clockwise) corner i is the edge v -> r_i and the corner before
 * it holds the twin r_i -> v; the canonical id (sw_edge_id) of each is
 * queued and the other dropped. */
static void qem_requeue_at(qem_t *s, int v)
{
    sw_t *w = s->w;
    const int32_t *fan = sw_fan(w, v);
    int n = w->fan_n[v];
    bool cycle = w->fan_kind[v] == SW_FAN_CYCLE;
    if (w->fan_kind[v] == SW_FAN_BROKEN) {   /* cannot happen after a merge; be safe */
        for (int i = 0; i < n; i++) {
            int c = fan[i], x = sw_nextv(w, c), id = sw_edge_id(w, v, x);
            int twin = id == c ? sw_find_corner(w, x, v) : c;
            if (twin >= 0 && twin != id)
                sw_queue_remove(&w->queue, twin);
            qem_queue(s, id);
        }
        return;
    }
    /* the neighbours' quadrics are scattered through memory: ask for them
     * all before the first is needed */
    for (int i = 0; i < n; i++) {
        const quadric_t *qx = &s->Q[sw_nextv(w, fan[i])];
        __builtin_prefetch(qx->q), __builtin_prefetch(qx->q + 8);
    }
    for (int i = 0; i < n; i++) {
        int out = fan[i], x = sw_nextv(w, out);
        int in = i > 0 ? sw_prev(fan[i - 1]) : cycle ? sw_prev(fan[n - 1]) : -1;
        int id = v < x || in < 0 ? out : in;
        if (in >= 0)
            sw_queue_remove(&w->queue, id == out ? in : out);
        qem_queue(s, id);
    }
    if (!cycle)   /* the path's last edge, r_n -> v, has no corner at v */
        qem_queue(s, sw_prev(fan[n - 1]));
}

/* The edge at the top of the queue is most likely the next to go, and all
 * it will read is cold: the merges jump across the mesh.  While the current
 * merge goes on, the main loop asks for its lines one dependency level at a
 * time, each reading only what the level before fetched: its face (after
 * the current edge is placed), the quadrics, fans and positions of its ends
 * (after the merge test), the faces of those fans (after the merge).  A
 * further level, the fans' vertices, made runs slower.  Hints only: the top
 * may change meanwhile.  Always inlined: GCC finds a function that only
 * prefetches free of side effects and drops its calls before inlining. */
#define QEM_PREFETCHER static inline __attribute__((always_inline)) void
QEM_PREFETCHER qem_prefetch_ends(const sw_t *w, const quadric_t *Q, int id)
{
    int a = w->tri[id], b = sw_nextv(w, id);
    __builtin_prefetch(Q[a].q), __builtin_prefetch(Q[a].q + 8);
    __builtin_prefetch(Q[b].q), __builtin_prefetch(Q[b].q + 8);
    __builtin_prefetch(w->pool + w->fan_off[a]), __builtin_prefetch(w->pool + w->fan_off[b]);
    __builtin_prefetch(w->pos + 3 * a), __builtin_prefetch(w->pos + 3 * b);
}

QEM_PREFETCHER qem_prefetch_fans(const sw_t *w, int id)
{
    for (int k = 0; k < 2; k++) {
        int x = w->tri[k ? sw_next(id) : id];
        const int32_t *fan = sw_fan(w, x);
        for (int i = 0; i < w->fan_n[x]; i++)
            __builtin_prefetch(w->tri + fan[i]);
    }
}

pp5_status_t simplify_qem_run(sw_t *w, const mesh_simplify_opts_t *o)
{
    qem_t s = {w, calloc((size_t)w->nv + 1, sizeof(quadric_t))};
    if (!s.Q)
        return pp5_fail(PP5_E_NOMEM, "qem: out of memory for quadrics");
    qem_init_quadrics(&s, o->qem_boundary_weight, o->qem_area_weighted);
    for (int c = 0; c < 3 * w->nf; c++) {   /* each edge once, under its canonical id */
        int a = w->tri[c], b = sw_nextv(w, c);
        if (a < b || sw_corner_on_boundary(w, c)) {
            double p[3];
            sw_queue_append(&w->queue, c, qem_place(&s, a < b ? a : b, a < b ? b : a, p),
                            sw_edge_tie(a, b));
        }
    }
    sw_queue_heapify(&w->queue);
    pp5_status_t st = PP5_OK;
    sw_qentry_t e;
    sw_merge_t m;
    while (st == PP5_OK && w->faces_alive > o->target_faces && sw_queue_pop(&w->queue, &e)) {
        int a = w->tri[e.id], b = sw_nextv(w, e.id);
        if (a > b) {
            int t = a;
            a = b, b = t;
        }
        double p[3];
        qem_place(&s, a, b, p);
        if (w->queue.n > 0)
            __builtin_prefetch(w->tri + w->queue.e[0].id);
        int32_t S[2] = {a, b};
        if (!sw_merge_allowed(w, S, 2, p, &m))
            continue;
        if (w->queue.n > 0)
            qem_prefetch_ends(w, s.Q, w->queue.e[0].id);
        st = sw_apply_merge(w, S, 2, p, &m);
        if (w->queue.n > 0)
            qem_prefetch_fans(w, w->queue.e[0].id);
        quadric_sum(&s.Q[a], &s.Q[b], &s.Q[a]);
        if (st == PP5_OK)
            qem_requeue_at(&s, a);
    }
    free(s.Q);
    return st;
}
