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

#include "huge_alloc.h"
#include "seed003_queue.h"
#include "seed003_stencil.h"

static const double PI = 3.14159265358979323846;

/* Queue ids (edge corners) set aside while frozen (§2.3), to be costed
 * at the thaw. */
enum { S003_LIVE = 0, S003_DEFERRED };

/* What re-costing an edge reads and writes of its corner c (the edge
 * tri[c] -> sw_nextv(w, c)), side by side: 32 bytes on one cache line, not a
 * line in each of six arrays:
 * - len, round: for the faces alive, the edge's length and its face's
 *   roundness for it, so a re-costed edge reads S and L instead of
 *   measuring them;
 * - qpos: where the edge is queued (seed003_queue.h), if it is; its
 *   queue entry carries the index of its new point (points), or -1 while
 *   it waits under a lower bound, not yet costed (waiting, here too);
 * - dstate: frozen (§2.3) and set aside;
 * - twin: for an edge queued under a lower bound or set aside dirty, its
 *   other corner (-1 on a boundary) as it was then.  Still the twin at the
 *   thaw: the face across an edge changes only in a merge with an end of
 *   the edge in its update set, which re-costs the edge and records the
 *   twin again. */
typedef struct {
    double len, round;
    int64_t qpos;
    int32_t twin;
    uint8_t dstate, waiting;
} s003_corner_t;

typedef struct {
    sw_t *w;
    const mesh_simplify_opts_t *o;
    s003_context_t ctx;
    uint8_t *importance, *corner;
    uint32_t *frozen, epoch;      /* vertex frozen while frozen[v] == epoch */
    uint32_t *mark, mark_epoch;   /* vertices in the current update set */
    double mean_edge;
    double smooth_cos;            /* smooth_cos_for the crease angle */
    int phase;
    bool lazy;                    /* asked for, and Cd >= 0 in both phases: the bound holds */
    s003_corner_t *hot;           /* per corner */
    /* The new points edges were costed at, in the order of costing; a
     * costed edge's queue entry carries the index of its point.  Emptied
     * whenever the queue is (the thaw, the phase switch): written in turn,
     * not scattered over a per-corner array. */
    double *points;
    int n_points, points_cap;
    s003_queue_t queue;           /* edges by their corner ids (the shared queue is not used) */
    int32_t *dlist;
    int dn, dcap;
    struct requeue *requeue_list; /* the edges a deletion re-queues (s003_refresh) */
    size_t requeue_cap;
    double ring_table[S003_RING_TABLE_SIZE];
} s003_t;

/* fmax without the libm call: the larger, or the number if one is NaN. */
static inline double max_num(double a, double b)
{
    return a != a ? b : b > a ? b : a;
}

/* The cosine between two vectors from their dot product and squared
 * lengths, clamped to [-1, 1]; 1 where a length is zero. */
static double cos_from(double dot, double len2_a, double len2_b)
{
    double l = sqrt(len2_a * len2_b);
    if (!(l > 0))
        return 1.0;
    double c = dot / l;
    return c > 1 ? 1 : c < -1 ? -1 : c;
}

static double cos_between(const double a[3], const double b[3])
{
    return cos_from(sw_dot(a, b), sw_dot(a, a), sw_dot(b, b));
}

static double angle_between(const double a[3], const double b[3])
{
    return acos(cos_between(a, b));
}

/* The ends of v's boundary path (two boundary neighbours), or false. */
static bool boundary_ends(const sw_t *w, int v, int nb[2])
{
    const int32_t *fan = sw_fan(w, v);
    int n = 0;
    if (w->fan_kind[v] == SW_FAN_PATH) {
        nb[0] = sw_nextv(w, fan[0]);
        nb[1] = sw_prevv(w, fan[w->fan_n[v] - 1]);
        return true;
    }
    for (int i = 0; i < w->fan_n[v] && n < 2; i++)
        for (int k = 0; k < 2 && n < 2; k++) {
            int x = (k ? sw_prevv(w, fan[i]) : sw_nextv(w, fan[i]));
            if ((n == 0 || nb[0] != x) && sw_edge_faces(w, v, x) == 1)
                nb[n++] = x;
        }
    return n == 2;
}

/* The angle between the two boundary edges at v (0 on a straight boundary). */
static double boundary_turn(const sw_t *w, int v)
{
    int nb[2];
    if (!boundary_ends(w, v, nb))
        return PI;
    const double *p = w->pos + 3 * v, *a = w->pos + 3 * nb[0], *b = w->pos + 3 * nb[1];
    double u[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
    double t[3] = {b[0] - p[0], b[1] - p[1], b[2] - p[2]};
    return angle_between(u, t);
}

/* The face normals around a vertex and, for a fan of at most
 * NORMALS_CACHED faces, the cosines between every two (cos_between's
 * doubles, which do not depend on the order of the pair). */
#define NORMALS_CACHED 24
typedef struct {
    int n;
    const double *nr[SW_MAX_FAN];
    double cosines[NORMALS_CACHED][NORMALS_CACHED];
} vertex_normals_t;

static double normals_cos(const vertex_normals_t *vn, int i, int j)
{
    return vn->n <= NORMALS_CACHED ? vn->cosines[i][j] : cos_between(vn->nr[i], vn->nr[j]);
}

/* Faces in index order; their normals are sw_init's (no merge yet).  Each
 * normal's squared length is taken once (cos_from gets the same doubles as
 * cos_between computes). */
static void gather_normals(const sw_t *w, int v, vertex_normals_t *vn)
{
    int n = w->fan_n[v] < SW_MAX_FAN ? w->fan_n[v] : SW_MAX_FAN;
    int32_t faces[SW_MAX_FAN];
    const int32_t *fan = sw_fan(w, v);
    for (int i = 0; i < n; i++) {
        int j = i;
        for (; j > 0 && faces[j - 1] > fan[i] / 3; j--)
            faces[j] = faces[j - 1];
        faces[j] = fan[i] / 3;
    }
    vn->n = n;
    for (int i = 0; i < n; i++)
        vn->nr[i] = w->fnormal + 3 * faces[i];
    if (n > NORMALS_CACHED)
        return;
    double len2[NORMALS_CACHED];
    for (int i = 0; i < n; i++)
        len2[i] = sw_dot(vn->nr[i], vn->nr[i]);
    for (int i = 0; i < n; i++)
        for (int j = i; j < n; j++)
            vn->cosines[i][j] = vn->cosines[j][i] =
                cos_from(sw_dot(vn->nr[i], vn->nr[j]), len2[i], len2[j]);
}

/* A1 (§2.1), the widest angle between two of the normals, and the first
 * pair in index order that spans it (0, 0 if every angle is 0).  acos falls
 * monotonically (glibc's is correctly rounded), so the widest angle is that
 * of the smallest cosine; another pair spans the same double only if its
 * cosine is within 1e-12 of it (|d acos / dc| >= 1), and only there is acos
 * taken again.  The same pair as comparing every pair's angle in order. */
static double widest_pair(const vertex_normals_t *vn, int *bi, int *bj)
{
    int n = vn->n;
    double cmin = 1.0;
    for (int i = 0; i < n; i++)
        for (int j = i + 1; j < n; j++) {
            double c = normals_cos(vn, i, j);
            if (c < cmin)   /* a NaN cosine (overflowed normals) spans nothing */
                cmin = c;
        }
    double a1 = acos(cmin);
    *bi = *bj = 0;
    if (!(a1 > 0))
        return 0;
    for (int i = 0; i < n; i++)
        for (int j = i + 1; j < n; j++) {
            double c = normals_cos(vn, i, j);
            if (c == cmin || (c - cmin <= 1e-12 && acos(c) == a1)) {
                *bi = i, *bj = j;
                return a1;
            }
        }
    return a1;
}

/* A2 (§2.1): the others join the nearer of the widest pair's normals, and
 * A2 is the wider of the two groups' cones. */
static double group_cone(const vertex_normals_t *vn, int bi, int bj)
{
    int n = vn->n, group[SW_MAX_FAN];
    for (int i = 0; i < n; i++) {
        double cj = normals_cos(vn, i, bj), ci = normals_cos(vn, i, bi);
        /* |d acos / dc| >= 1: cosines this far apart order their angles */
        group[i] = cj - ci > 1e-12 ? 1 : ci - cj > 1e-12 ? 0 : acos(cj) < acos(ci);
    }
    double c2 = 1.0;   /* a2 = acos of the smallest cosine within a group */
    for (int i = 0; i < n; i++)
        for (int j = i + 1; j < n; j++)
            if (group[i] == group[j])
                c2 = sw_min(c2, normals_cos(vn, i, j));
    return acos(c2);
}

/* The cosine above which two normals surely meet at less than the crease
 * angle: cos(crease) + 1e-9 where acos of it is below the crease angle
 * (acos falls monotonically), else 2 (no shortcut). */
static double smooth_cos_for(double crease)
{
    double c = cos(crease) + 1e-9;
    return c < 1 && acos(c) < crease ? c : 2.0;
}

/* Is A1 surely below the crease angle?  True when every pair of the face
 * normals at v passes dot > 0 and dot^2 > c^2 |n_i|^2 |n_j|^2 with c a
 * further 1e-9 above smooth_cos: then the cosine classify_vertex would
 * compute (cos_from: a quotient and a square root, each rounded once) is
 * above smooth_cos, its acos below the crease angle.  No square root or
 * division per pair; lengths outside 1e-150 .. 1e150 (where the products
 * could leave the normal range of doubles) and fans of over 32 faces are
 * left to the full test.  Most vertices of a scan end here. */
static bool surely_smooth(const s003_t *s, int v)
{
    const sw_t *w = s->w;
    int n = w->fan_n[v];
    if (s->smooth_cos > 1 || n > 32)
        return false;
    const double c = s->smooth_cos + 1e-9, c2 = c * c;
    const int32_t *fan = sw_fan(w, v);
    const double *nr[32];
    double len2[32];
    for (int i = 0; i < n; i++) {
        nr[i] = w->fnormal + 3 * (fan[i] / 3);
        len2[i] = sw_dot(nr[i], nr[i]);
        if (!(len2[i] > 1e-150 && len2[i] < 1e150))
            return false;
    }
    for (int i = 0; i < n; i++)
        for (int j = i + 1; j < n; j++) {
            double d = sw_dot(nr[i], nr[j]);
            if (!(d > 0 && d * d > c2 * len2[i] * len2[j]))
                return false;
        }
    return true;
}

/* §2.1: ordinary (A1 below the crease angle), crease or corner (A2 above
 * the corner angle).  Faces are taken in index order (the first widest
 * pair wins a tie).  A2 matters only past the crease angle, so a smooth
 * vertex, most of any scan, never groups its normals, and one that is
 * surely smooth is not measured further. */
static void classify_vertex(s003_t *s, int v)
{
    const sw_t *w = s->w;
    double crease = s->o->s003_crease_deg * PI / 180, corner = s->o->s003_corner_deg * PI / 180;
    int imp = 0;
    if (!surely_smooth(s, v)) {
        vertex_normals_t vn;
        gather_normals(w, v, &vn);
        int bi, bj;
        double a1 = widest_pair(&vn, &bi, &bj);
        imp = a1 < crease ? 0 : group_cone(&vn, bi, bj) > corner ? 2 : 1;
    }
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

static double dist(const double *a, const double *b)
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

/* The roundness L_e / L_max (§2.3) of the three edges of the face of
 * corner c, after measuring the two edges at c's vertex (c and the corner
 * before it); the third keeps its length (its ends have not moved since
 * the face was last measured: a vertex that moves is a merged one, and
 * every face around it is measured).  Lengths are the same doubles as
 * measuring from the endpoints in either order (a difference squares to
 * the same number both ways round). */
static void measure_face_at(s003_t *s, int c0)
{
    const sw_t *w = s->w;
    int f = c0 / 3;
    s->hot[c0].len = dist(w->pos + 3 * w->tri[c0], w->pos + 3 * sw_nextv(w, c0));
    s->hot[sw_prev(c0)].len = dist(w->pos + 3 * sw_prevv(w, c0), w->pos + 3 * w->tri[c0]);
    for (int c = 3 * f; c < 3 * f + 3; c++) {
        double lmax = max_num(s->hot[sw_prev(c)].len, s->hot[sw_next(c)].len);
        s->hot[c].round = lmax > 0 ? s->hot[c].len / lmax : 0;
    }
}

/* The lengths and roundness of face f's three edges. */
static void measure_face(s003_t *s, int f)
{
    const sw_t *w = s->w;
    for (int c = 3 * f; c < 3 * f + 3; c++)
        s->hot[c].len = dist(w->pos + 3 * w->tri[c], w->pos + 3 * sw_nextv(w, c));
    for (int c = 3 * f; c < 3 * f + 3; c++) {
        double lmax = max_num(s->hot[sw_prev(c)].len, s->hot[sw_next(c)].len);
        s->hot[c].round = lmax > 0 ? s->hot[c].len / lmax : 0;
    }
}

/* F without its D term, Cs S + Cl L, for the edge of corner id (twin: its
 * other corner, or -1): neither depends on the new point, D is >= 0, and
 * rounding is monotone, so this is <= the F that control_function computes
 * (its sum is (Cd D + Cs S) + Cl L, in that order).  Queued under it, an
 * edge is costed only when it reaches the top of the queue, and the order
 * of deletions is the same as costing at once. */
static double lower_bound(const s003_t *s, int id, int twin)
{
    double smax = max_num(0, s->hot[id].round);
    if (twin >= 0)
        smax = max_num(smax, s->hot[twin].round);
    int ph = s->phase;
    return s->o->s003_cs[ph] * smax + s->o->s003_cl[ph] * s->hot[id].len / s->mean_edge;
}

/* The cosine of the turn of the face of corner c when c's vertex moves to
 * p, or false where the face folds: the merge test's fold rule on the
 * same doubles (sw_test_merge). */
static bool face_turn(const sw_t *w, int c, const double p[3], double *cos_turn)
{
    double n_new[3], d, len2;
    if (!sw_face_turn(w, c, p, n_new, &d, &len2))
        return false;
    double l = sqrt(len2), cs = l > 0 ? d / l : 1.0;
    *cos_turn = cs > 1 ? 1 : cs < -1 ? -1 : cs;
    return true;
}

/* F(e) at new point p for edge a-b of corner id, or false if a face would
 * fold.  The link (topology) test waits for the deletion: it does not
 * depend on p, an edge that fails it is dropped when it is popped, and it
 * changes nothing else, so deletions come in the same order.  The faces
 * that stay are those at a or b without the other: the merge test's. */
static bool control_function(s003_t *s, int id, int a, int b, const double p[3], double *F)
{
    const sw_t *w = s->w;
    if (w->fan_n[a] + w->fan_n[b] > SW_MAX_FAN) {   /* too many for the merge test */
        sw_merge_t m;
        int32_t S[2] = {a, b};
        if (sw_test_merge(w, S, 2, p, &m) != SW_OK)
            return false;
    }
    /* D: the largest turn, from the smallest cosine (acos falls monotonically) */
    double cmin = 1.0, smax = 0, cs;
    for (int k = 0; k < 2; k++) {
        int x = k ? b : a, y = k ? a : b;
        const int32_t *fan = sw_fan(w, x);
        for (int i = 0; i < w->fan_n[x]; i++) {
            int c = fan[i];
            if (sw_nextv(w, c) == y || sw_prevv(w, c) == y) {
                /* a face of the edge (seen from a): S from its roundness */
                if (k == 0)
                    smax = max_num(smax, s->hot[sw_nextv(w, c) == y ? c : sw_prev(c)].round);
                continue;
            }
            if (!face_turn(w, c, p, &cs))
                return false;
            cmin = sw_min(cmin, cs);
        }
    }
    double dmax = acos(cmin) / PI;
    int ph = s->phase;
    *F = s->o->s003_cd[ph] * dmax + s->o->s003_cs[ph] * smax +
         s->o->s003_cl[ph] * s->hot[id].len / s->mean_edge;
    return true;
}

/* The new point for deleting (a, b) (a < b, id: a corner of it) under the
 * chosen rule and its cost. */
static bool s003_evaluate(s003_t *s, int id, int a, int b, double p[3], double *F)
{
    s003_stencil_t st;
    if (!s003_stencil(&s->ctx, a, b, &st))
        return false;
    seed003_point_t mode = s->o->s003_point;
    if (st.which == S003_CASE_PINNED || mode == SEED003_POINT_STENCIL) {
        stencil_point(s, &st, p);
        return control_function(s, id, a, b, p, F);
    }
    const double *pa = s->w->pos + 3 * a, *pb = s->w->pos + 3 * b;
    if (mode == SEED003_POINT_MIDPOINT) {
        for (int k = 0; k < 3; k++)
            p[k] = 0.5 * (pa[k] + pb[k]);
        return control_function(s, id, a, b, p, F);
    }
    double fa, fb;   /* the better endpoint */
    bool oka = control_function(s, id, a, b, pa, &fa), okb = control_function(s, id, a, b, pb, &fb);
    if (!oka && !okb)
        return false;
    bool use_a = oka && (!okb || fa <= fb);
    memcpy(p, use_a ? pa : pb, 3 * sizeof *p);
    *F = use_a ? fa : fb;
    return true;
}

static bool s003_frozen(const s003_t *s, int a, int b)
{
    return s->o->s003_independent_sets && s->frozen[a] == s->epoch && s->frozen[b] == s->epoch;
}

static pp5_status_t s003_defer(s003_t *s, int id)
{
    if (s->hot[id].dstate == S003_LIVE) {
        if (s->dn == s->dcap) {
            int cap = s->dcap ? 2 * s->dcap : 4096;
            int32_t *nl = realloc(s->dlist, sizeof *nl * (size_t)cap);
            if (!nl)
                return pp5_fail(PP5_E_NOMEM, "seed003: out of memory for frozen edges");
            s->dlist = nl, s->dcap = cap;
        }
        s->dlist[s->dn++] = id;
    }
    s->hot[id].dstate = S003_DEFERRED;
    return PP5_OK;
}

/* Puts id in the queue under (cost, tie).  The keys are distinct (one id
 * per edge, ties on its vertices), so the pops do not depend on the order
 * edges were queued in or on how the queue keeps them. */
static pp5_status_t queue_put(s003_t *s, int id, double cost, uint64_t tie)
{
    return s003_queue_set(&s->queue, id, cost, tie, -1);
}

static void queue_drop(s003_t *s, int id)
{
    s003_queue_remove(&s->queue, id);
}

static void s003_forget(s003_t *s, int id)
{
    queue_drop(s, id);
    s->hot[id].dstate = S003_LIVE;   /* a stale dlist entry is skipped at the thaw */
}

/* Queues live edge id (a < b; twin: its other corner, or -1) under its
 * cost, or under the lower bound. */
static pp5_status_t s003_cost(s003_t *s, int id, int twin, int a, int b, bool now)
{
    if (!now && s->lazy) {
        double lb = lower_bound(s, id, twin);
        uint64_t tie = sw_edge_tie(a, b);
        s->hot[id].twin = twin;
        s->hot[id].waiting = 1;
        /* A key already queued at or below the bound (with the same tie) is
         * still a lower bound of F: left in place (only marked as not
         * costed), the edge only reaches the top sooner to be costed, and
         * deletions keep their order. */
        if (s003_queue_has(&s->queue, id)) {
            s003_qentry_t key = s003_queue_key(&s->queue, id);
            if (key.tie == tie && key.cost <= lb)
                return key.data < 0 ? PP5_OK : s003_queue_set(&s->queue, id, key.cost, tie, -1);
        }
        return queue_put(s, id, lb, tie);
    }
    double F;
    s->hot[id].waiting = 0;
    if (s->n_points == s->points_cap) {
        int cap = 2 * s->points_cap;
        double *np = huge_grow(s->points, sizeof *np * 3 * (size_t)s->n_points,
                                   sizeof *np * 3 * (size_t)s->points_cap,
                                   sizeof *np * 3 * (size_t)cap);
        if (!np)
            return pp5_fail(PP5_E_NOMEM, "seed003: out of memory for new points");
        s->points = np, s->points_cap = cap;
    }
    if (s003_evaluate(s, id, a, b, s->points + 3 * (size_t)s->n_points, &F))
        return s003_queue_set(&s->queue, id, F, sw_edge_tie(a, b), s->n_points++);
    queue_drop(s, id);
    return PP5_OK;
}

/* Re-costs the edge of canonical id `id` (sw_edge_id) now, or at the thaw if
 * it is frozen; `twin`, the edge's other corner (-1: a boundary edge),
 * leaves the queue. */
static pp5_status_t s003_queue(s003_t *s, int id, int twin)
{
    sw_t *w = s->w;
    if (twin >= 0)
        s003_forget(s, twin);
    int a = w->tri[id], b = sw_nextv(w, id);
    if (a > b) {
        int t = a;
        a = b, b = t;
    }
    if (s003_frozen(s, a, b)) {
        queue_drop(s, id);
        s->hot[id].twin = twin;
        return s003_defer(s, id);
    }
    return s003_cost(s, id, twin, a, b, false);
}

/* Queues every edge (the queue is empty), vertex by vertex: in an ordered
 * fan the twin of corner i (x -> y) is the corner before it in the previous
 * face (y -> x), and a path's first corner is a boundary edge, so no fan is
 * searched.  A pinched (BROKEN) fan asks corner by corner.  Each edge is
 * queued once, under its canonical corner (sw_edge_id), as before; the
 * order of queueing does not matter (queue_put). */
static pp5_status_t queue_all_edges(s003_t *s)
{
    sw_t *w = s->w;
    pp5_status_t st = PP5_OK;
    for (int x = 0; x < w->nv && st == PP5_OK; x++) {
        const int32_t *fan = sw_fan(w, x);
        int n = w->fan_n[x];
        uint8_t kind = w->fan_kind[x];
        for (int i = 0; i < n && st == PP5_OK; i++) {
            int c = fan[i], y = sw_nextv(w, c);
            if (kind == SW_FAN_BROKEN) {
                if (sw_corner_on_boundary(w, c))
                    st = s003_queue(s, c, -1);
                else if (x < y)
                    st = s003_queue(s, c, sw_find_corner(w, y, x));
            } else if (i == 0 && kind == SW_FAN_PATH) {
                st = s003_queue(s, c, -1);
            } else if (x < y) {
                st = s003_queue(s, c, sw_prev(fan[i > 0 ? i - 1 : n - 1]));
            }
        }
    }
    return st;
}

/* An edge to re-queue after a deletion: its canonical corner (sw_edge_id),
 * its other corner (-1 on a boundary), its ends (a < b), and whether an end
 * is the new vertex. */
typedef struct requeue {
    int32_t id, twin, a, b;
    bool at_new;
    bool reaches_out;   /* an end outside the update set */
} requeue_t;

/* The update set of a deletion is marked with mark_epoch (a vertex that
 * freezes now) or mark_epoch + 1 (one frozen before, this epoch). */
static bool in_update_set(const s003_t *s, int y)
{
    return (s->mark[y] | 1) == (s->mark_epoch | 1);
}

static bool frozen_before(const s003_t *s, int y)
{
    return in_update_set(s, y) ? s->mark[y] & 1 : s->frozen[y] == s->epoch;
}

/* Lists edge x-y of canonical corner id; `out`: y is outside the update set. */
static inline void requeue_add(s003_t *s, requeue_t *list, int *n, int id, int twin, int x, int y,
                               int v, bool out)
{
    /* the record is read when the list is worked through: fetched now, the
     * records of all the edges come in together */
    __builtin_prefetch(&s->hot[id]);
    list[(*n)++] = (requeue_t){id, twin, x < y ? x : y, x < y ? y : x, x == v || y == v, out};
}

/* The edges at x to re-queue; an edge between two vertices of the update
 * set goes from its smaller end only.  In x's fan (counter-clockwise)
 * corner i is the edge x -> r_i and the corner before it holds the twin
 * r_i -> x.  An edge whose ends both froze before this deletion, neither
 * of them the new vertex v, is left out: when its second end froze it was
 * set aside for the thaw, with its twin, and the twin has not changed (the
 * faces of an edge change only in a merge at one of its ends, and only
 * edges at v change their corners). */
static int requeue_collect_at(s003_t *s, int x, int v, requeue_t *list, int n)
{
    sw_t *w = s->w;
    const int32_t *fan = sw_fan(w, x);
    int k = w->fan_n[x];
    uint8_t kind = w->fan_kind[x];
    bool x_before = x != v && frozen_before(s, x);
    for (int i = 0; i < k; i++) {
        int out = fan[i], y = sw_nextv(w, out), in;
        if (kind == SW_FAN_BROKEN)
            in = sw_find_corner(w, y, x);
        else
            in = i > 0 ? sw_prev(fan[i - 1]) : kind == SW_FAN_CYCLE ? sw_prev(fan[k - 1]) : -1;
        bool y_in = in_update_set(s, y);
        if (!(y_in && y < x && in >= 0) && !(x_before && y != v && frozen_before(s, y))) {
            int id = x < y || in < 0 ? out : in;
            requeue_add(s, list, &n, id, id == out ? in : out, x, y, v, !y_in);
        }
        /* a boundary edge into x from outside the set is no out-edge of the set */
        int pc = sw_prev(out), z = w->tri[pc];
        if (kind != SW_FAN_CYCLE && !in_update_set(s, z) && sw_corner_on_boundary(w, pc) &&
            !(x_before && frozen_before(s, z)))
            requeue_add(s, list, &n, pc, -1, z, x, v, true);
    }
    return n;
}

/* s003_queue for a listed edge.  Only an edge at the new vertex can have
 * changed its canonical corner, so only there can the twin be queued.  A
 * live edge reaching out of the update set that waits under its lower
 * bound stays as it is: that bound is unchanged (neither end moved, and
 * its faces, whose third vertices are common neighbours of its ends, are
 * not around the new vertex), so s003_cost would leave it in place. */
static pp5_status_t requeue(s003_t *s, const requeue_t *e)
{
    if (e->at_new && e->twin >= 0)
        s003_forget(s, e->twin);
    if (s003_frozen(s, e->a, e->b)) {
        queue_drop(s, e->id);
        s->hot[e->id].twin = e->twin;
        return s003_defer(s, e->id);
    }
    const s003_corner_t *h = &s->hot[e->id];
    if (s->lazy && e->reaches_out && h->waiting && h->qpos != S003_QPOS_NONE && h->twin == e->twin)
        return PP5_OK;
    return s003_cost(s, e->id, e->twin, e->a, e->b, false);
}

/* After deleting an edge into v: v inherits the higher importance; v and
 * its ring freeze; every edge with an end in {v} u ring is re-costed (their
 * stencils, D, S and L terms reach only that far: ARCHITECTURE.md).  The
 * edges are listed first and then re-queued in the same order, so the
 * records they read are fetched side by side. */
static pp5_status_t s003_refresh(s003_t *s, int v, int gone, const sw_merge_t *m)
{
    sw_t *w = s->w;
    /* the second and third stages after s003_take_top's first: the ring's
     * fans, then, behind the measuring, their corners' next vertices */
    for (int i = 0; i < m->n_ring; i++)
        __builtin_prefetch(sw_fan(w, m->ring[i]));
    const int32_t *fan = sw_fan(w, v);
    for (int i = 0; i < w->fan_n[v]; i++)   /* the faces that moved or changed a vertex */
        measure_face_at(s, fan[i]);
    for (int i = 0; i < m->n_ring; i++) {
        const int32_t *rf = sw_fan(w, m->ring[i]);
        for (int j = 0; j < w->fan_n[m->ring[i]]; j++)
            __builtin_prefetch(&w->tri[sw_next(rf[j])]);
    }
    if (s->importance[gone] > s->importance[v])
        s->importance[v] = s->importance[gone];
    s->corner[v] |= s->corner[gone];
    if (s->mark_epoch >= UINT32_MAX - 2)
        memset(s->mark, 0, sizeof *s->mark * (size_t)w->nv), s->mark_epoch = 0;
    s->mark_epoch += 2;
    int32_t set[SW_MAX_FAN + 2];
    int n = 0;
    set[n++] = v;
    for (int i = 0; i < m->n_ring; i++)
        set[n++] = m->ring[i];
    for (int i = 0; i < n; i++) {
        bool before = s->o->s003_independent_sets && s->frozen[set[i]] == s->epoch;
        s->mark[set[i]] = s->mark_epoch + before;
        if (s->o->s003_independent_sets)
            s->frozen[set[i]] = s->epoch;
    }
    size_t most = 0;   /* each vertex lists at most two edges per corner */
    for (int i = 0; i < n; i++)
        most += 2 * (size_t)w->fan_n[set[i]];
    if (most > s->requeue_cap) {
        requeue_t *nl = realloc(s->requeue_list, sizeof *nl * most);
        if (!nl)
            return pp5_fail(PP5_E_NOMEM, "seed003: out of memory for re-queued edges");
        s->requeue_list = nl, s->requeue_cap = most;
    }
    int k = 0;
    for (int i = 0; i < n; i++)
        k = requeue_collect_at(s, set[i], v, s->requeue_list, k);
    pp5_status_t st = PP5_OK;
    for (int i = 0; i < k && st == PP5_OK; i++)
        st = requeue(s, &s->requeue_list[i]);
    return st;
}

/* Every queued edge is frozen: thaw them all (§2.3) into the empty queue. */
static pp5_status_t s003_thaw(s003_t *s)
{
    sw_t *w = s->w;
    pp5_status_t st = PP5_OK;
    s->epoch++;
    s->n_points = 0;   /* the queue is empty: no costed edge needs its point */
    w->stats->unfreezes++;
    /* the list is in no order over the mesh: each edge's record, ends and
     * twin's record are fetched ahead, in two stages */
    enum { AHEAD = 16 };
    for (int i = 0; i < s->dn && i < AHEAD / 2; i++)
        __builtin_prefetch(&s->hot[s->dlist[i]]);
    for (int i = 0; i < s->dn && st == PP5_OK; i++) {
        if (i + AHEAD < s->dn)
            __builtin_prefetch(&s->hot[s->dlist[i + AHEAD]]);
        if (i + AHEAD / 2 < s->dn) {
            int ahead = s->dlist[i + AHEAD / 2], twin = s->hot[ahead].twin;
            __builtin_prefetch(&w->tri[ahead]), __builtin_prefetch(&w->tri[sw_next(ahead)]);
            __builtin_prefetch(&s->hot[twin >= 0 ? twin : ahead]);
        }
        int id = s->dlist[i];
        if (s->hot[id].dstate != S003_DEFERRED)
            continue;   /* forgotten since it was set aside */
        s->hot[id].dstate = S003_LIVE;
        int a = w->tri[id], b = sw_nextv(w, id);
        st = s003_cost(s, id, s->hot[id].twin, a < b ? a : b, a < b ? b : a, false);
    }
    s->dn = 0;
    return st;
}

/* Phase 2 (§2.3): new weights, every edge re-costed and re-sorted. */
static pp5_status_t s003_switch_phase(s003_t *s)
{
    sw_t *w = s->w;
    s->phase = 1;
    w->stats->phase_switch_merge = w->stats->merges;
    s003_queue_clear(&s->queue);
    s->n_points = 0;
    for (int i = 0; i < s->dn; i++)
        s->hot[s->dlist[i]].dstate = S003_LIVE;
    s->dn = 0;
    s->epoch++;
    return queue_all_edges(s);
}

/* Edges waiting under lower bounds that are costed together (cost_batch). */
enum { COST_BATCH = 16 };

/* Fetches what costing the edges of entries e[0..n) reads (their ends, the
 * ends' fans, the faces of the fans and their vertices), stage by stage:
 * each stage reads what the stage before fetched, and the loads of all n
 * edges in a stage are in flight at once.  An edge costed at the top of
 * the queue was queued long before, so all of it is cold; fetched as the
 * costing reached it, each line was a miss waited for on its own.  The
 * ends of edge i are end[2 i], end[2 i + 1] (so the compiler, which does
 * not count prefetching as an effect, keeps the function). */
static void prefetch_neighbourhoods(const s003_t *s, const s003_qentry_t *e, int n, int32_t *end)
{
    const sw_t *w = s->w;
    for (int i = 0; i < n; i++) {
        __builtin_prefetch(&w->tri[e[i].id]), __builtin_prefetch(&w->tri[sw_next(e[i].id)]);
        __builtin_prefetch(&s->hot[e[i].id]);
    }
    for (int i = 0; i < n; i++)
        end[2 * i] = w->tri[e[i].id], end[2 * i + 1] = sw_nextv(w, e[i].id);
    for (int j = 0; j < 2 * n; j++) {
        int v = end[j];
        __builtin_prefetch(&w->fan_off[v]), __builtin_prefetch(&w->fan_n[v]);
        __builtin_prefetch(&w->pos[3 * v]), __builtin_prefetch(&s->frozen[v]);
    }
    for (int j = 0; j < 2 * n; j++)
        __builtin_prefetch(sw_fan(w, end[j]));
    for (int j = 0; j < 2 * n; j++) {
        const int32_t *fan = sw_fan(w, end[j]);
        int k = w->fan_n[end[j]] < SW_MAX_FAN ? w->fan_n[end[j]] : SW_MAX_FAN;
        for (int i = 0; i < k; i++) {
            __builtin_prefetch(&w->tri[3 * (fan[i] / 3)]);   /* the face's three vertices */
        }
    }
    /* the vertices around (around an inner vertex each is some corner's
     * next vertex) and the roundness of the edge's faces */
    for (int j = 0; j < 2 * n; j++) {
        const int32_t *fan = sw_fan(w, end[j]);
        int other = end[j ^ 1];
        int k = w->fan_n[end[j]] < SW_MAX_FAN ? w->fan_n[end[j]] : SW_MAX_FAN;
        for (int i = 0; i < k; i++) {
            int c = fan[i], x = sw_nextv(w, c);
            __builtin_prefetch(&w->pos[3 * x]);
            if (x == other) {   /* the face before holds the twin, other -> end[j] */
                __builtin_prefetch(&s->hot[c]);
                __builtin_prefetch(&s->hot[sw_prev(fan[i ? i - 1 : k - 1])]);
            }
        }
    }
}

/* Takes the edge at the top of the queue: sets it aside if it is frozen,
 * costs it in place if its key was a lower bound, else deletes it if it
 * may go (its new point is the one its cost was found at). */
static pp5_status_t s003_take_top(s003_t *s, s003_qentry_t e)
{
    sw_t *w = s->w;
    int a = w->tri[e.id], b = sw_nextv(w, e.id);
    if (a > b) {
        int t = a;
        a = b, b = t;
    }
    if (s003_frozen(s, a, b)) {
        /* Not reached: an edge is set aside when its second end freezes
         * (s003_refresh).  Were it reached, costing the edge again at the
         * thaw would find the same cost: anything it depends on that
         * changes re-queues it, recording its twin. */
        queue_drop(s, e.id);
        return s003_defer(s, e.id);
    }
    if (e.data < 0)   /* moves down to its cost, or leaves */
        return s003_cost(s, e.id, -1, a, b, true);
    queue_drop(s, e.id);
    /* the merge test reads what costing read (the ends' fans, faces and
     * vertices), most of it cold again: fetched together, not miss by miss */
    int32_t end[2];
    prefetch_neighbourhoods(s, &e, 1, end);
    const double *p = s->points + 3 * (size_t)e.data;
    sw_merge_t m;
    int32_t S[2] = {a, b};
    if (sw_test_merge(w, S, 2, p, &m) != SW_OK)
        return PP5_OK;   /* the link test, left for now (control_function) */
    /* The first stage of fetching what the refresh reads: the ring's fan
     * records, marks and freeze stamps, and the records of the corners of
     * the faces that stay (measure_face_at).  The fans follow when their
     * places are in (s003_refresh), each stage behind work that gives the
     * one before time to arrive. */
    for (int i = 0; i < m.n_ring; i++) {
        int r = m.ring[i];
        __builtin_prefetch(&w->fan_off[r]), __builtin_prefetch(&w->fan_n[r]);
        __builtin_prefetch(&w->fan_kind[r]), __builtin_prefetch(&s->mark[r]);
        __builtin_prefetch(&s->frozen[r]);
    }
    for (int i = 0; i < m.n_keep; i++) {
        const s003_corner_t *h = s->hot + 3 * (m.keep[i] / 3);
        __builtin_prefetch(h), __builtin_prefetch(h + 2);
    }
    pp5_status_t st = sw_apply_merge(w, S, 2, p, &m);
    for (int r = 0; r < m.n_removed; r++)
        for (int c = 3 * m.removed[r]; c < 3 * m.removed[r] + 3; c++)
            s003_forget(s, c);
    return st == PP5_OK ? s003_refresh(s, a, b, &m) : st;
}

/* The edge at the top waits under a lower bound: it and the next ones that
 * do (up to COST_BATCH) leave the queue, their neighbourhoods are fetched,
 * and each is costed and queued under its cost.  Nothing changes the mesh
 * between them, so each gets the cost it would have got alone.  Should the
 * deletion of one of them come first and reach another, that one is
 * re-queued as after any deletion, so the deletions keep their order. */
static pp5_status_t s003_cost_batch(s003_t *s, s003_qentry_t top)
{
    s003_qentry_t batch[COST_BATCH];
    int n = 0;
    do {
        batch[n++] = top;
        queue_drop(s, top.id);
    } while (n < COST_BATCH && s003_queue_top(&s->queue, &top) && top.data < 0);
    int32_t end[2 * COST_BATCH];
    prefetch_neighbourhoods(s, batch, n, end);
    pp5_status_t st = PP5_OK;
    for (int i = 0; i < n && st == PP5_OK; i++) {
        int id = batch[i].id, a = end[2 * i], b = end[2 * i + 1];
        if (a > b) {
            int t = a;
            a = b, b = t;
        }
        /* a frozen one as s003_take_top would (not reached) */
        st = s003_frozen(s, a, b) ? s003_defer(s, id) : s003_cost(s, id, -1, a, b, true);
    }
    return st;
}

static pp5_status_t s003_loop(s003_t *s)
{
    sw_t *w = s->w;
    const mesh_simplify_opts_t *o = s->o;
    pp5_status_t st = PP5_OK;
    double switch_at = o->s003_switch_fraction * w->input_faces;
    while (st == PP5_OK && w->faces_alive > o->target_faces) {
        if (s->phase == 0 && o->s003_switch_fraction > 0 && w->faces_alive <= switch_at) {
            st = s003_switch_phase(s);
            continue;
        }
        s003_qentry_t top;
        if (s003_queue_top(&s->queue, &top)) {
            st = top.data < 0 && s->lazy ? s003_cost_batch(s, top) : s003_take_top(s, top);
            continue;
        }
        if (s->dn == 0)
            break;
        st = s003_thaw(s);
    }
    return st;
}

/* Measures every face; the input's mean edge length. */
static double measure_all(s003_t *s)
{
    const sw_t *w = s->w;
    double total = 0;
    long edges = 0;
    for (int f = 0; f < w->nf; f++)
        measure_face(s, f);
    for (int c = 0; c < 3 * w->nf; c++) {
        total += s->hot[c].len;
        edges++;
    }
    return edges && total > 0 ? total / (double)edges : 1.0;
}

pp5_status_t simplify_seed003_run(sw_t *w, const mesh_simplify_opts_t *o)
{
    s003_t *s = calloc(1, sizeof *s);
    if (!s)
        return pp5_fail(PP5_E_NOMEM, "seed003: out of memory");
    s->w = w, s->o = o, s->epoch = 1;
    s->lazy = o->s003_lazy && o->s003_cd[0] >= 0 && o->s003_cd[1] >= 0;
    size_t nv = (size_t)w->nv + 1, nc = 3 * (size_t)w->nf + 1;
    s->importance = calloc(nv, 1);
    s->corner = calloc(nv, 1);
    s->frozen = calloc(nv, sizeof *s->frozen);
    s->mark = calloc(nv, sizeof *s->mark);
    s->hot = huge_alloc(nc * sizeof *s->hot, false);
    s->points_cap = (int)(nc / 4) + 64;
    s->points = huge_alloc(sizeof *s->points * 3 * (size_t)s->points_cap, false);
    pp5_status_t st = PP5_OK;
    if (!s->importance || !s->corner || !s->frozen || !s->mark || !s->hot ||
        !s->points)
        st = pp5_fail(PP5_E_NOMEM, "seed003: out of memory");
    /* This run keeps its own queue; without the shared one the merge
     * (sw_apply_merge) has no entries to drop, and take_top drops ours. */
    sw_queue_free(&w->queue);
    if (st == PP5_OK) {
        for (size_t c = 0; c < nc; c++)
            s->hot[c] = (s003_corner_t){.qpos = S003_QPOS_NONE, .twin = -1};
        st = s003_queue_init(&s->queue, (int)nc, &s->hot[0].qpos, sizeof *s->hot);
    }
    s->mean_edge = st == PP5_OK ? measure_all(s) : 1.0;
    s->smooth_cos = smooth_cos_for(o->s003_crease_deg * PI / 180);
    for (int v = 0; v < w->nv && st == PP5_OK; v++)
        if (w->vert_alive[v])
            classify_vertex(s, v);
    s003_ring_table_fill(s->ring_table);
    s->ctx = (s003_context_t){w, s->importance, s->corner, o->s003_pin_corners,
                              cos(o->s003_crease_deg * PI / 180), s->ring_table};
    if (st == PP5_OK)
        st = queue_all_edges(s);
    if (st == PP5_OK)
        st = s003_loop(s);
    free(s->importance), free(s->corner), free(s->frozen), free(s->mark);
    huge_free(s->hot, nc * sizeof *s->hot);
    huge_free(s->points, sizeof *s->points * 3 * (size_t)s->points_cap);
    free(s->dlist);
    free(s->requeue_list);
    s003_queue_free(&s->queue);
    free(s);
    return st;
}
