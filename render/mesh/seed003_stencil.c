/* seed003_stencil.c: seed 003's six stencil cases (§2.4, Fig. 2, Table 1).
 *
 * Readings of the paper (ARCHITECTURE.md): case 3 says V = V1 + V2, whose
 * weights sum to 2; we average, V = (V1 + V2)/2, as Zorin et al. do.  Case 5's
 * c is the weight of the feature-line neighbour beyond each endpoint (then
 * a + b + 2c = 1 in all three rows of Table 1); where an endpoint has no
 * single such neighbour its c goes to the endpoint.  When a stencil vertex
 * is missing (a butterfly wing on a boundary), the case-3 form of the two
 * endpoints' rings is used (S003_CASE_FALLBACK), and the midpoint when even
 * that is missing. */
#include "seed003_stencil.h"

#include <math.h>
#include <string.h>

static const double PI = 3.14159265358979323846;

double s003_ring_weights(int K, double *s)
{
    double sum = 0;
    for (int j = 0; j < K; j++) {
        if (K == 4)
            s[j] = j == 0 ? 3.0 / 8.0 : j == 2 ? -1.0 / 8.0 : 0.0;
        else if (K == 3)
            s[j] = j == 0 ? 5.0 / 12.0 : -1.0 / 12.0;
        else
            s[j] = (0.25 + cos(2 * PI * j / K) + 0.5 * cos(4 * PI * j / K)) / K;
        sum += s[j];
    }
    return 1.0 - sum;
}

int s003_ring_table_offset(int K)
{
    return (K - 3) * (K + 4) / 2;   /* sum over k = 3 .. K-1 of (k + 1) entries */
}

void s003_ring_table_fill(double *table)
{
    for (int K = 3; K <= S003_RING_TABLE_K; K++) {
        double *t = table + s003_ring_table_offset(K);
        t[0] = s003_ring_weights(K, t + 1);
    }
}

static void add(s003_stencil_t *s, int v, double w)
{
    if (s->distinct) {   /* the caller knows v is new */
        if (s->n < S003_STENCIL_MAX)
            s->v[s->n] = v, s->w[s->n] = w, s->n++;
        return;
    }
    for (int i = 0; i < s->n; i++)
        if (s->v[i] == v) {
            s->w[i] += w;
            return;
        }
    if (s->n < S003_STENCIL_MAX)
        s->v[s->n] = v, s->w[s->n] = w, s->n++;
}

bool s003_feature_edge(const s003_context_t *c, int a, int b)
{
    int f1 = sw_opposite(c->w, a, b), f2 = sw_opposite(c->w, b, a);
    if (f1 < 0 || f2 < 0)
        return true;
    const double *pa = c->w->pos + 3 * a, *pb = c->w->pos + 3 * b;
    const double *p1 = c->w->pos + 3 * f1, *p2 = c->w->pos + 3 * f2;
    double e[3], u[3], v[3], n1[3], n2[3];
    for (int k = 0; k < 3; k++)
        e[k] = pb[k] - pa[k], u[k] = p1[k] - pa[k], v[k] = p2[k] - pa[k];
    sw_cross(e, u, n1);   /* face (a, b, f1) */
    sw_cross(v, e, n2);   /* face (b, a, f2) */
    double l = sqrt(sw_dot(n1, n1) * sw_dot(n2, n2));
    return !(l > 0) || sw_dot(n1, n2) < c->cos_crease * l;
}

/* The endpoint's stencil of case 2 (weights x scale) around `v`, ring from `other`. */
static bool ring_stencil(const s003_context_t *c, int v, int other, double scale,
                         s003_stencil_t *s)
{
    int32_t ring[SW_MAX_FAN];
    double w[SW_MAX_FAN];
    int K = sw_ring(c->w, v, other, ring, SW_MAX_FAN);
    if (K < 3)
        return false;
    double q;
    if (c->ring_table && K <= S003_RING_TABLE_K) {   /* the same numbers, computed once */
        const double *t = c->ring_table + s003_ring_table_offset(K);
        q = t[0];
        memcpy(w, t + 1, sizeof *w * (size_t)K);
    } else {
        q = s003_ring_weights(K, w);
    }
    s->distinct = s->n == 0;   /* a vertex and its ring: no repeats */
    add(s, v, q * scale);
    for (int j = 0; j < K; j++)
        add(s, ring[j], w[j] * scale);
    s->distinct = false;
    return true;
}

/* sw_ring's length without the ring: v's valence if it is interior (other,
 * a neighbour of v, is always in its ring), else -1. */
static int valence(const s003_context_t *c, int v)
{
    return c->w->fan_kind[v] == SW_FAN_CYCLE ? c->w->fan_n[v] : -1;
}

/* The index in v's fan of the corner v -> x, or -1. */
static int fan_index(const sw_t *w, int v, int x)
{
    const int32_t *fan = sw_fan(w, v);
    for (int i = 0; i < w->fan_n[v]; i++)
        if (sw_nextv(w, fan[i]) == x)
            return i;
    return -1;
}

/* The butterfly (case 1): a = 1/2, b = 1/8, c = -1/16, d = w = 0.  a and b
 * are interior of valence 6, so the wings are read off their ordered fans
 * (corner i + 1 leaves v toward corner i's previous vertex): the faces
 * sw_opposite would find, without searching the neighbours' fans. */
static bool butterfly(const s003_context_t *c, int a, int b, s003_stencil_t *s)
{
    const sw_t *w = c->w;
    int i = fan_index(w, a, b), j = fan_index(w, b, a);
    if (i < 0 || j < 0)
        return false;
    const int32_t *fa = sw_fan(w, a), *fb = sw_fan(w, b);
    int o1 = sw_prevv(w, fa[i]), o2 = sw_prevv(w, fb[j]);
    int wings[4] = {sw_prevv(w, fa[(i + 1) % 6]),    /* across a -> o1 */
                    sw_nextv(w, fb[(j + 4) % 6]),    /* across o1 -> b */
                    sw_nextv(w, fa[(i + 4) % 6]),    /* across o2 -> a */
                    sw_prevv(w, fb[(j + 1) % 6])};   /* across b -> o2 */
    add(s, a, 0.5), add(s, b, 0.5), add(s, o1, 0.125), add(s, o2, 0.125);
    for (int k = 0; k < 4; k++)
        add(s, wings[k], -1.0 / 16.0);
    return true;
}

/* The one other vertex x of v (x != skip) with (v, x) a feature edge, or -1. */
static int feature_neighbour(const s003_context_t *c, int v, int skip)
{
    const sw_t *w = c->w;
    int found = -1, count = 0;
    const int32_t *fan = sw_fan(w, v);
    for (int i = 0; i < w->fan_n[v]; i++)
        for (int k = 0; k < 2; k++) {
            int x = (k ? sw_prevv(w, fan[i]) : sw_nextv(w, fan[i]));
            if (x == skip || x == found)
                continue;
            if (s003_feature_edge(c, v, x)) {
                /* each neighbour appears in two faces: count it once */
                if (found < 0)
                    found = x, count = 1;
                else
                    count++;
            }
        }
    return count == 1 ? found : -1;
}

/* v's neighbour across a boundary edge other than skip, or -1. */
static int boundary_neighbour(const sw_t *w, int v, int skip)
{
    const int32_t *fan = sw_fan(w, v);
    int n = w->fan_n[v];
    if (w->fan_kind[v] == SW_FAN_PATH) {   /* the path's two ends */
        int first = sw_nextv(w, fan[0]), last = sw_prevv(w, fan[n - 1]);
        return first != skip ? first : last != skip ? last : -1;
    }
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 2; k++) {
            int x = (k ? sw_prevv(w, fan[i]) : sw_nextv(w, fan[i]));
            if (x != skip && sw_edge_faces(w, v, x) == 1)
                return x;
        }
    return -1;
}

static void feature_case(const s003_context_t *c, int a, int b, s003_stencil_t *s)
{
    int ia = c->importance[a], ib = c->importance[b];
    double wa, wb, cw;
    if (ia == 1 && ib == 1)
        wa = wb = 3.0 / 8.0, cw = 1.0 / 8.0;                  /* Table 1 (1) */
    else if (ia == 2 && ib == 2)
        wa = wb = 0.5, cw = 0.0;                              /* (2) */
    else
        wa = ia > ib ? 5.0 / 8.0 : 3.0 / 8.0, wb = 1.0 - wa, cw = 0.0; /* (3) */
    add(s, a, wa), add(s, b, wb);
    if (cw > 0) {
        int na = feature_neighbour(c, a, b), nb = feature_neighbour(c, b, a);
        add(s, na >= 0 ? na : a, cw);
        add(s, nb >= 0 ? nb : b, cw);
    }
    s->which = S003_CASE_FEATURE;
}

static void stencil_clear(s003_stencil_t *s)
{
    s->n = 0;
    s->which = 0;
    s->distinct = false;
}

bool s003_stencil(const s003_context_t *c, int a, int b, s003_stencil_t *s)
{
    stencil_clear(s);
    int ia = c->importance[a], ib = c->importance[b];
    if (c->pin_corners && (c->corner[a] || c->corner[b])) {
        if (c->corner[a] && c->corner[b])
            return false;             /* two corners: the edge is kept */
        add(s, c->corner[a] ? a : b, 1.0);
        s->which = S003_CASE_PINNED;
        return true;
    }
    if ((ia == 0) != (ib == 0)) {     /* case 6: q = 1 at the important endpoint */
        add(s, ia ? a : b, 1.0);
        s->which = S003_CASE_PINNED;
        return true;
    }
    if (ia > 0) {
        /* two important endpoints joined by a non-feature edge would cut
         * across the surface between two feature lines: kept */
        if (!s003_feature_edge(c, a, b))
            return false;
        bool boundary_edge = sw_opposite(c->w, a, b) < 0 || sw_opposite(c->w, b, a) < 0;
        if (boundary_edge && ia == 1 && ib == 1) {
            /* case 4: 4-point rule along the boundary */
            int pa = boundary_neighbour(c->w, a, b), pb = boundary_neighbour(c->w, b, a);
            if (pa >= 0 && pb >= 0 && pa != pb) {
                add(s, pa, -1.0 / 16.0), add(s, a, 9.0 / 16.0);
                add(s, b, 9.0 / 16.0), add(s, pb, -1.0 / 16.0);
                s->which = S003_CASE_BOUNDARY;
                return true;
            }
            add(s, a, 0.5), add(s, b, 0.5);
            s->which = S003_CASE_FALLBACK;
            return true;
        }
        feature_case(c, a, b, s);
        return true;
    }
    int ka = valence(c, a), kb = valence(c, b);
    if (ka == 6 && kb == 6 && butterfly(c, a, b, s)) {
        s->which = S003_CASE_REGULAR;
        return true;
    }
    stencil_clear(s);
    if (ka >= 3 && kb >= 3 && (ka == 6) != (kb == 6)) {
        if (ring_stencil(c, ka != 6 ? a : b, ka != 6 ? b : a, 1.0, s)) {
            s->which = S003_CASE_ONE_IRREGULAR;
            return true;
        }
    }
    stencil_clear(s);
    if (ka >= 3 && kb >= 3 && ring_stencil(c, a, b, 0.5, s) && ring_stencil(c, b, a, 0.5, s)) {
        s->which = ka != 6 && kb != 6 ? S003_CASE_TWO_IRREGULAR : S003_CASE_FALLBACK;
        return true;
    }
    stencil_clear(s);
    add(s, a, 0.5), add(s, b, 0.5);
    s->which = S003_CASE_FALLBACK;
    return true;
}
