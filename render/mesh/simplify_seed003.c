/* simplify_seed003.c: edge deletion of Cao, Liu, Bao, Peng
 * (../shared/seeds/003_97c17de217dc9b5f.txt, §2.1-§2.4).
 *
 * Vertex importance (§2.1) from the spread of the face normals around each
 * vertex; the new point from the interpolating stencils (seed003_stencil.c);
 * the order from the control function (§2.3)
 *   F(e) = Cd max D(t) + Cs S(e) + Cl L(e),
 * D = the turn of each face around the new point (angle / pi), S = the largest
 * L_e / L_max of the faces containing e, L = |e| / the input's mean edge
 * length; the weights change once (phase 2) and every edge is re-costed;
 * independent sets (§2.3): each deletion freezes the edges of the faces around
 * the new point until every queued edge is frozen.  The paper's unset values
 * and the rules it leaves open are in ARCHITECTURE.md. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "seed003_stencil.h"

static const double PI = 3.14159265358979323846;

typedef struct {
    sw_t *w;
    const mesh_simplify_opts_t *o;
    s003_context_t ctx;
    uint8_t *importance, *corner;
    uint32_t *frozen, epoch;      /* vertex frozen while frozen[v] == epoch */
    uint32_t *mark, mark_epoch;   /* vertices in the current update set */
    double mean_edge;
    int phase;
    sw_heap_t deferred;
} s003_t;

static double angle_between(const double a[3], const double b[3])
{
    double l = sqrt(sw_dot(a, a) * sw_dot(b, b));
    if (!(l > 0))
        return 0;
    double c = sw_dot(a, b) / l;
    return acos(c > 1 ? 1 : c < -1 ? -1 : c);
}

/* The angle between the two boundary edges at v (0 on a straight boundary). */
static double boundary_turn(const sw_t *w, int v)
{
    int nb[2], n = 0;
    const int32_t *fan = w->pool + w->fan_off[v];
    for (int i = 0; i < w->fan_n[v] && n < 2; i++)
        for (int k = 0; k < 3; k++) {
            int x = w->tri[3 * fan[i] + k];
            if (x != v && (n == 0 || nb[0] != x) && sw_edge_faces(w, v, x) == 1 && n < 2)
                nb[n++] = x;
        }
    if (n < 2)
        return PI;
    const double *p = w->pos + 3 * v, *a = w->pos + 3 * nb[0], *b = w->pos + 3 * nb[1];
    double u[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
    double t[3] = {b[0] - p[0], b[1] - p[1], b[2] - p[2]};
    return angle_between(u, t);
}

/* §2.1: A1 = the widest pair of face normals; the others join the nearer of
 * the two; A2 = the wider of the two groups' cones. */
static void classify_vertex(s003_t *s, int v)
{
    const sw_t *w = s->w;
    int n = w->fan_n[v] < SW_MAX_FAN ? w->fan_n[v] : SW_MAX_FAN;
    double nr[SW_MAX_FAN][3];
    const int32_t *fan = w->pool + w->fan_off[v];
    for (int i = 0; i < n; i++)
        sw_face_normal(w, fan[i], nr[i]);
    double a1 = 0;
    int bi = 0, bj = 0;
    for (int i = 0; i < n; i++)
        for (int j = i + 1; j < n; j++) {
            double t = angle_between(nr[i], nr[j]);
            if (t > a1)
                a1 = t, bi = i, bj = j;
        }
    int group[SW_MAX_FAN];
    for (int i = 0; i < n; i++)
        group[i] = angle_between(nr[i], nr[bj]) < angle_between(nr[i], nr[bi]);
    double a2 = 0;
    for (int i = 0; i < n; i++)
        for (int j = i + 1; j < n; j++)
            if (group[i] == group[j])
                a2 = fmax(a2, angle_between(nr[i], nr[j]));
    double crease = s->o->s003_crease_deg * PI / 180, corner = s->o->s003_corner_deg * PI / 180;
    int imp = a1 < crease ? 0 : a2 > corner ? 2 : 1;
    s->corner[v] = imp == 2;
    if (imp < 2 && sw_vertex_on_boundary(w, v)) {
        imp++;
        /* Added rule: where the boundary itself turns by more than the crease
         * angle the vertex is a corner, though its normals may all agree (a
         * flat sheet's corner); §2.1 would give it importance 1 and case 4
         * would round it off. */
        if (boundary_turn(w, v) > crease)
            imp = 2, s->corner[v] = 1;
    }
    s->importance[v] = (uint8_t)imp;
}

static void stencil_point(const s003_t *s, const s003_stencil_t *st, double p[3])
{
    p[0] = p[1] = p[2] = 0;
    for (int i = 0; i < st->n; i++)
        for (int k = 0; k < 3; k++)
            p[k] += st->w[i] * s->w->pos[3 * st->v[i] + k];
}

/* F(e) at new point p, or false if the merge is not allowed there. */
static bool control_function(s003_t *s, int a, int b, const double p[3], double *F)
{
    const sw_t *w = s->w;
    int32_t S[2] = {a, b};
    sw_merge_t m;
    if (sw_test_merge(w, S, 2, p, &m) != SW_OK)
        return false;
    double dmax = 0, smax = 0;
    for (int i = 0; i < m.n_keep; i++)
        dmax = fmax(dmax, angle_between(m.n_old[i], m.n_new[i]) / PI);
    const double *pa = w->pos + 3 * a, *pb = w->pos + 3 * b;
    double le = sqrt((pa[0] - pb[0]) * (pa[0] - pb[0]) + (pa[1] - pb[1]) * (pa[1] - pb[1]) +
                     (pa[2] - pb[2]) * (pa[2] - pb[2]));
    for (int i = 0; i < m.n_removed; i++) {
        const int32_t *t = w->tri + 3 * m.removed[i];
        int o = t[0] != a && t[0] != b ? t[0] : t[1] != a && t[1] != b ? t[1] : t[2];
        const double *po = w->pos + 3 * o;
        double l1 = sqrt((pa[0] - po[0]) * (pa[0] - po[0]) + (pa[1] - po[1]) * (pa[1] - po[1]) +
                         (pa[2] - po[2]) * (pa[2] - po[2]));
        double l2 = sqrt((pb[0] - po[0]) * (pb[0] - po[0]) + (pb[1] - po[1]) * (pb[1] - po[1]) +
                         (pb[2] - po[2]) * (pb[2] - po[2]));
        double lmax = fmax(l1, l2);
        smax = fmax(smax, lmax > 0 ? le / lmax : 0);   /* Roundness = L_e / L_max */
    }
    int ph = s->phase;
    *F = s->o->s003_cd[ph] * dmax + s->o->s003_cs[ph] * smax +
         s->o->s003_cl[ph] * le / s->mean_edge;
    return true;
}

/* The new point for deleting (a, b) under the chosen rule, and its cost. */
static bool s003_evaluate(s003_t *s, int a, int b, double p[3], double *F)
{
    s003_stencil_t st;
    if (!s003_stencil(&s->ctx, a, b, &st))
        return false;
    seed003_point_t mode = s->o->s003_point;
    if (st.which == S003_CASE_PINNED || mode == SEED003_POINT_STENCIL) {
        stencil_point(s, &st, p);
        return control_function(s, a, b, p, F);
    }
    const double *pa = s->w->pos + 3 * a, *pb = s->w->pos + 3 * b;
    if (mode == SEED003_POINT_MIDPOINT) {
        for (int k = 0; k < 3; k++)
            p[k] = 0.5 * (pa[k] + pb[k]);
        return control_function(s, a, b, p, F);
    }
    double fa, fb;   /* the better endpoint */
    bool oka = control_function(s, a, b, pa, &fa), okb = control_function(s, a, b, pb, &fb);
    if (!oka && !okb)
        return false;
    bool use_a = oka && (!okb || fa <= fb);
    memcpy(p, use_a ? pa : pb, 3 * sizeof *p);
    *F = use_a ? fa : fb;
    return true;
}

static pp5_status_t s003_push(s003_t *s, int a, int b)
{
    if (a > b) {
        int t = a;
        a = b, b = t;
    }
    double p[3], F;
    if (!s003_evaluate(s, a, b, p, &F))
        return PP5_OK;
    return sw_heap_push(&s->w->heap, sw_edge_entry(s->w, F, a, b));
}

static pp5_status_t push_all_edges(s003_t *s)
{
    sw_t *w = s->w;
    pp5_status_t st = PP5_OK;
    for (int f = 0; f < w->nf && st == PP5_OK; f++) {
        if (!w->face_alive[f])
            continue;
        for (int c = 0; c < 3 && st == PP5_OK; c++) {
            int a = w->tri[3 * f + c], b = w->tri[3 * f + (c + 1) % 3];
            if (a < b || sw_opposite(w, b, a) < 0)
                st = s003_push(s, a, b);
        }
    }
    return st;
}

/* After deleting an edge into v: v inherits the higher importance, and every
 * edge at v or at its ring is re-costed (their stencils and D terms reach
 * the moved faces). */
static pp5_status_t s003_refresh(s003_t *s, int v, int gone, const sw_merge_t *m)
{
    sw_t *w = s->w;
    if (s->importance[gone] > s->importance[v])
        s->importance[v] = s->importance[gone];
    s->corner[v] |= s->corner[gone];
    if (++s->mark_epoch == 0)
        memset(s->mark, 0, sizeof *s->mark * (size_t)w->nv), s->mark_epoch = 1;
    int32_t set[SW_MAX_FAN + 1];
    int n = 0;
    set[n++] = v;
    for (int i = 0; i < m->n_ring; i++)
        set[n++] = m->ring[i];
    for (int i = 0; i < n; i++) {
        s->mark[set[i]] = s->mark_epoch;
        w->stamp[set[i]]++;
        if (s->o->s003_independent_sets)
            s->frozen[set[i]] = s->epoch;
    }
    pp5_status_t st = PP5_OK;
    for (int i = 0; i < n && st == PP5_OK; i++) {
        int x = set[i];
        const int32_t *fan = w->pool + w->fan_off[x];
        for (int j = 0; j < w->fan_n[x] && st == PP5_OK; j++)
            for (int c = 0; c < 3 && st == PP5_OK; c++) {
                int y = w->tri[3 * fan[j] + c];
                /* each edge once: from x toward the next corner only, and from
                 * the smaller end when both ends are in the set */
                if (y == x || w->tri[3 * fan[j] + (c + 2) % 3] != x)
                    continue;
                if (s->mark[y] == s->mark_epoch && y < x && sw_opposite(w, y, x) >= 0)
                    continue;
                st = s003_push(s, x, y);
                if (st == PP5_OK && sw_opposite(w, y, x) < 0) {
                    /* boundary edge into x: also reached from its other side */
                }
            }
        /* boundary edges where x is the far end */
        const int32_t *fan2 = w->pool + w->fan_off[x];
        for (int j = 0; j < w->fan_n[x] && st == PP5_OK; j++)
            for (int c = 0; c < 3 && st == PP5_OK; c++)
                if (w->tri[3 * fan2[j] + c] == x) {
                    int prev = w->tri[3 * fan2[j] + (c + 2) % 3];
                    if (sw_opposite(w, x, prev) < 0 && s->mark[prev] != s->mark_epoch)
                        st = s003_push(s, prev, x);
                }
    }
    return st;
}

static bool s003_frozen(const s003_t *s, const sw_entry_t *e)
{
    return s->o->s003_independent_sets && s->frozen[e->a] == s->epoch &&
           s->frozen[e->b] == s->epoch;
}

/* Phase 2 (§2.3): new weights, every queued edge re-costed and re-sorted. */
static pp5_status_t s003_switch_phase(s003_t *s)
{
    s->phase = 1;
    s->w->stats->phase_switch_merge = s->w->stats->merges;
    s->w->heap.n = 0;
    s->deferred.n = 0;
    s->epoch++;
    return push_all_edges(s);
}

static pp5_status_t s003_loop(s003_t *s)
{
    sw_t *w = s->w;
    const mesh_simplify_opts_t *o = s->o;
    pp5_status_t st = PP5_OK;
    sw_entry_t e;
    sw_merge_t m;
    double switch_at = o->s003_switch_fraction * w->input_faces;
    while (st == PP5_OK && w->faces_alive > o->target_faces) {
        if (s->phase == 0 && o->s003_switch_fraction > 0 && w->faces_alive <= switch_at) {
            st = s003_switch_phase(s);
            continue;
        }
        if (!sw_heap_pop(&w->heap, &e)) {
            if (s->deferred.n == 0)
                break;
            /* every queued edge is frozen: thaw them all (§2.3) */
            s->epoch++;
            w->stats->unfreezes++;
            for (size_t i = 0; i < s->deferred.n && st == PP5_OK; i++)
                st = sw_heap_push(&w->heap, s->deferred.e[i]);
            s->deferred.n = 0;
            continue;
        }
        if (!sw_entry_current(w, &e))
            continue;
        if (s003_frozen(s, &e)) {
            st = sw_heap_push(&s->deferred, e);
            continue;
        }
        double p[3], F;
        if (!s003_evaluate(s, e.a, e.b, p, &F)) {
            w->stats->refused_other++;
            continue;
        }
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
        if (st == PP5_OK)
            st = s003_refresh(s, e.a, e.b, &m);
    }
    return st;
}

pp5_status_t simplify_seed003_run(sw_t *w, const mesh_simplify_opts_t *o)
{
    s003_t s;
    memset(&s, 0, sizeof s);
    s.w = w, s.o = o, s.epoch = 1;
    s.importance = calloc((size_t)w->nv + 1, 1);
    s.corner = calloc((size_t)w->nv + 1, 1);
    s.frozen = calloc((size_t)w->nv + 1, sizeof *s.frozen);
    s.mark = calloc((size_t)w->nv + 1, sizeof *s.mark);
    pp5_status_t st = PP5_OK;
    if (!s.importance || !s.corner || !s.frozen || !s.mark)
        st = pp5_fail(PP5_E_NOMEM, "seed003: out of memory");
    double total = 0;
    long edges = 0;
    for (int f = 0; f < w->nf && st == PP5_OK; f++)
        for (int c = 0; c < 3; c++) {
            const double *pa = w->pos + 3 * w->tri[3 * f], *pb;
            pa = w->pos + 3 * w->tri[3 * f + c];
            pb = w->pos + 3 * w->tri[3 * f + (c + 1) % 3];
            total += sqrt((pa[0] - pb[0]) * (pa[0] - pb[0]) + (pa[1] - pb[1]) * (pa[1] - pb[1]) +
                          (pa[2] - pb[2]) * (pa[2] - pb[2]));
            edges++;
        }
    s.mean_edge = edges && total > 0 ? total / (double)edges : 1.0;
    for (int v = 0; v < w->nv && st == PP5_OK; v++)
        if (w->vert_alive[v])
            classify_vertex(&s, v);
    s.ctx = (s003_context_t){w, s.importance, s.corner, o->s003_pin_corners,
                             cos(o->s003_crease_deg * PI / 180)};
    if (st == PP5_OK)
        st = push_all_edges(&s);
    if (st == PP5_OK)
        st = s003_loop(&s);
    free(s.importance), free(s.corner), free(s.frozen), free(s.mark);
    sw_heap_free(&s.deferred);
    return st;
}
