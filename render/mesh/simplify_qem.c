/* simplify_qem.c: Garland & Heckbert 1997 quadric edge collapse, the baseline.
 *
 * Each vertex carries the sum of the area-weighted plane quadrics of its
 * faces; boundary edges add a plane through the edge perpendicular to its
 * face, weighted by qem_boundary_weight x length^2, which holds boundaries in
 * place (GH97 §6).  The new point minimises the summed quadric when that
 * 3x3 system is well conditioned, else the best of the endpoints and the
 * midpoint.  Edges are re-costed around the new vertex only (GH97 §4). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "simplify_work.h"

typedef struct {
    double q[10];   /* a2 ab ac ad b2 bc bd c2 cd d2 */
} quadric_t;

static void quadric_add_plane(quadric_t *Q, const double n[3], double d, double w)
{
    double a = n[0], b = n[1], c = n[2];
    double t[10] = {a * a, a * b, a * c, a * d, b * b, b * c, b * d, c * c, c * d, d * d};
    for (int i = 0; i < 10; i++)
        Q->q[i] += w * t[i];
}

static double quadric_eval(const quadric_t *Q, const double p[3])
{
    const double *q = Q->q;
    double x = p[0], y = p[1], z = p[2];
    return q[0] * x * x + 2 * q[1] * x * y + 2 * q[2] * x * z + 2 * q[3] * x + q[4] * y * y +
           2 * q[5] * y * z + 2 * q[6] * y + q[7] * z * z + 2 * q[8] * z + q[9];
}

/* Minimiser of the quadric; false when the system is near singular. */
static bool quadric_optimum(const quadric_t *Q, double p[3])
{
    const double *q = Q->q;
    double A[3][3] = {{q[0], q[1], q[2]}, {q[1], q[4], q[5]}, {q[2], q[5], q[7]}};
    double b[3] = {-q[3], -q[6], -q[8]};
    double det = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
                 A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
                 A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
    double scale = fabs(A[0][0]) + fabs(A[1][1]) + fabs(A[2][2]);
    if (!(scale > 0) || fabs(det) < 1e-9 * scale * scale * scale)
        return false;
    for (int k = 0; k < 3; k++) {   /* Cramer's rule */
        double M[3][3];
        memcpy(M, A, sizeof M);
        for (int r = 0; r < 3; r++)
            M[r][k] = b[r];
        p[k] = (M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) -
                M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
                M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0])) / det;
    }
    return isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]);
}

typedef struct {
    sw_t *w;
    quadric_t *Q;
} qem_t;

static double qem_place(const qem_t *s, int a, int b, double p[3])
{
    quadric_t Q;
    for (int i = 0; i < 10; i++)
        Q.q[i] = s->Q[a].q[i] + s->Q[b].q[i];
    const double *pa = s->w->pos + 3 * a, *pb = s->w->pos + 3 * b;
    if (quadric_optimum(&Q, p))
        return fmax(quadric_eval(&Q, p), 0.0);
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
    return fmax(best, 0.0);
}

static void qem_init_quadrics(qem_t *s, double boundary_weight)
{
    sw_t *w = s->w;
    for (int f = 0; f < w->nf; f++) {
        double n[3];
        sw_face_normal(w, f, n);
        double len = sqrt(sw_dot(n, n));
        if (!(len > 0))
            continue;
        double u[3] = {n[0] / len, n[1] / len, n[2] / len};
        const double *p0 = w->pos + 3 * w->tri[3 * f];
        double d = -sw_dot(u, p0), area = 0.5 * len;
        for (int c = 0; c < 3; c++)
            quadric_add_plane(&s->Q[w->tri[3 * f + c]], u, d, area);
        for (int c = 0; c < 3; c++) {
            int a = w->tri[3 * f + c], b = w->tri[3 * f + (c + 1) % 3];
            if (sw_opposite(w, b, a) >= 0)
                continue;
            const double *pa = w->pos + 3 * a, *pb = w->pos + 3 * b;
            double e[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]}, m[3];
            sw_cross(e, u, m);
            double ml = sqrt(sw_dot(m, m));
            if (!(ml > 0))
                continue;
            for (int k = 0; k < 3; k++)
                m[k] /= ml;
            double wgt = boundary_weight * sw_dot(e, e);
            quadric_add_plane(&s->Q[a], m, -sw_dot(m, pa), wgt);
            quadric_add_plane(&s->Q[b], m, -sw_dot(m, pa), wgt);
        }
    }
}

static pp5_status_t qem_push_edge(qem_t *s, int a, int b)
{
    if (a > b) {
        int t = a;
        a = b, b = t;
    }
    double p[3];
    return sw_heap_push(&s->w->heap, sw_edge_entry(s->w, qem_place(s, a, b, p), a, b));
}

pp5_status_t simplify_qem_run(sw_t *w, const mesh_simplify_opts_t *o)
{
    qem_t s = {w, calloc((size_t)w->nv + 1, sizeof(quadric_t))};
    if (!s.Q)
        return pp5_fail(PP5_E_NOMEM, "qem: out of memory for quadrics");
    qem_init_quadrics(&s, o->qem_boundary_weight);
    pp5_status_t st = PP5_OK;
    for (int f = 0; f < w->nf && st == PP5_OK; f++)
        for (int c = 0; c < 3 && st == PP5_OK; c++) {
            int a = w->tri[3 * f + c], b = w->tri[3 * f + (c + 1) % 3];
            if (a < b || sw_opposite(w, b, a) < 0)
                st = qem_push_edge(&s, a, b);
        }
    sw_entry_t e;
    sw_merge_t m;
    while (st == PP5_OK && w->faces_alive > o->target_faces && sw_heap_pop(&w->heap, &e)) {
        if (!sw_entry_current(w, &e))
            continue;
        double p[3];
        qem_place(&s, e.a, e.b, p);
        int32_t S[2] = {e.a, e.b};
        sw_verdict_t v = sw_test_merge(w, S, 2, p, &m);
        if (v != SW_OK) {
            if (v == SW_FOLD)
                w->stats->refused_fold++;
            else
                w->stats->refused_topology++;
            continue;
        }
        st = sw_apply_merge(w, S, 2, p, &m);
        for (int i = 0; i < 10; i++)
            s.Q[e.a].q[i] += s.Q[e.b].q[i];
        w->stamp[e.a]++;
        for (int i = 0; i < m.n_ring && st == PP5_OK; i++)
            st = qem_push_edge(&s, e.a, m.ring[i]);
    }
    free(s.Q);
    return st;
}
