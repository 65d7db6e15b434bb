/* simplify_work.c: the working mesh of the simplifiers: corner fans in
 * rotational order, neighbourhood queries, the merge test (one manifold link,
 * no fold-over), and the merge with its record steps. */
#include "simplify_work.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static pp5_status_t sw_alloc(sw_t *w, int queue_ids)
{
    size_t nv = (size_t)w->nv + 1, nf = (size_t)w->nf + 1;
    w->pos = malloc(sizeof *w->pos * 3 * nv);
    w->tri = malloc(sizeof *w->tri * 3 * nf);
    w->face_alive = malloc(nf);
    w->vert_alive = calloc(nv, 1);
    w->fan_kind = calloc(nv, 1);
    w->fan_off = malloc(sizeof *w->fan_off * nv);
    w->fan_n = calloc(nv, sizeof *w->fan_n);
    w->fan_cap = malloc(sizeof *w->fan_cap * nv);
    w->rec_id = malloc(sizeof *w->rec_id * nv);
    w->fnormal = malloc(sizeof *w->fnormal * 3 * nf);
    w->pool_cap = 3 * nf + 2 * nv + 64;
    w->pool = malloc(sizeof *w->pool * w->pool_cap);
    if (!w->pos || !w->tri || !w->face_alive || !w->vert_alive ||
        !w->fan_kind || !w->fan_off || !w->fan_n || !w->fan_cap || !w->rec_id || !w->pool ||
        !w->fnormal)
        return pp5_fail(PP5_E_NOMEM, "simplify: out of memory for %d vertices", w->nv);
    pp5_status_t st = sw_queue_init(&w->queue, queue_ids);
    if (st != PP5_OK || !w->recording)
        return st;
    w->r_cap = 2 * nv;
    w->r_pos = malloc(sizeof *w->r_pos * 3 * w->r_cap);
    w->r_parent = malloc(sizeof *w->r_parent * w->r_cap);
    w->r_death = malloc(sizeof *w->r_death * w->r_cap);
    w->r_face_death = malloc(sizeof *w->r_face_death * nf);
    w->r_level_cap = w->nv + 2;
    w->r_level_step = malloc(sizeof *w->r_level_step * (size_t)w->r_level_cap);
    w->r_level_faces = malloc(sizeof *w->r_level_faces * (size_t)w->r_level_cap);
    w->r_level_vertices = malloc(sizeof *w->r_level_vertices * (size_t)w->r_level_cap);
    if (!w->r_pos || !w->r_parent || !w->r_death || !w->r_face_death || !w->r_level_step ||
        !w->r_level_faces || !w->r_level_vertices)
        return pp5_fail(PP5_E_NOMEM, "simplify: out of memory for the record");
    return PP5_OK;
}

static void sw_push_level(sw_t *w)
{
    if (!w->recording || w->r_levels >= w->r_level_cap)
        return;
    w->r_level_step[w->r_levels] = w->step;
    w->r_level_faces[w->r_levels] = w->faces_alive;
    w->r_level_vertices[w->r_levels] = w->verts_alive;
    w->r_levels++;
}

/* Successors for a short fan by direct search (a valence-6 vertex needs 36
 * comparisons, cheaper than sorting); false if two next vertices are equal. */
#define FAN_SCAN 16
static bool fan_successors_scan(const sw_t *w, const int32_t *fan, int n, const int32_t *nxt,
                                int32_t *succ)
{
    bool unique = true;
    for (int j = 0; j < n; j++) {
        int z = sw_prevv(w, fan[j]);
        int found = -1;
        for (int i = n - 1; i >= 0; i--)   /* a select, not a branch: matches are unpredictable */
            found = nxt[i] == z ? i : found;
        succ[j] = found;
        for (int i = j + 1; i < n; i++)
            unique &= nxt[i] != nxt[j];
    }
    return unique;
}

/* The same for a long fan: corners sorted by their next vertex (stably, so
 * the lowest of equal ones comes first), then a binary search per corner. */
static bool fan_successors_sorted(const sw_t *w, const int32_t *fan, int n, const int32_t *nxt,
                                  int32_t *succ)
{
    int32_t by_next[SW_MAX_FAN];
    for (int i = 0; i < n; i++) {
        int j = i;
        for (; j > 0 && nxt[by_next[j - 1]] > nxt[i]; j--)
            by_next[j] = by_next[j - 1];
        by_next[j] = i;
    }
    bool unique = true;
    for (int i = 1; i < n; i++)
        unique &= nxt[by_next[i - 1]] != nxt[by_next[i]];
    for (int j = 0; j < n; j++) {
        int z = sw_prevv(w, fan[j]), lo = 0, hi = n;
        while (lo < hi) {
            int mid = (lo + hi) / 2;
            if (nxt[by_next[mid]] < z)
                lo = mid + 1;
            else
                hi = mid;
        }
        succ[j] = lo < n && nxt[by_next[lo]] == z ? by_next[lo] : -1;
    }
    return unique;
}

/* Puts the corners at v in counter-clockwise order: the successor of corner
 * c is the corner whose edge leaves v toward tri[prev c].  A path starts at
 * the corner with no predecessor (its edge is on the boundary); a cycle
 * starts at its lowest corner, so the order depends only on the mesh, not
 * on the merges that made it.  Anything else (several pieces: a pinched
 * vertex) is BROKEN and left in ascending corner order.  Returns false if
 * two corners leave v toward the same vertex (an edge with three faces or
 * two faces of opposite orientation). */
static bool order_fan(sw_t *w, int v)
{
    int32_t *fan = w->pool + w->fan_off[v];
    int n = w->fan_n[v];
    if (n > SW_MAX_FAN) {   /* too many faces to merge anyway: not worth ordering */
        w->fan_kind[v] = SW_FAN_BROKEN;
        return true;
    }
    /* the successor of corner j is the (lowest) corner whose next vertex is
     * j's previous vertex */
    int32_t nxt[SW_MAX_FAN], succ[SW_MAX_FAN], ordered[SW_MAX_FAN];
    bool has_pred[SW_MAX_FAN];
    int lowest = 0;
    for (int i = 0; i < n; i++) {
        nxt[i] = sw_nextv(w, fan[i]);
        has_pred[i] = false;
        if (fan[i] < fan[lowest])
            lowest = i;
    }
    bool unique = n <= FAN_SCAN ? fan_successors_scan(w, fan, n, nxt, succ)
                                : fan_successors_sorted(w, fan, n, nxt, succ);
    for (int j = 0; j < n; j++)
        if (succ[j] >= 0)
            has_pred[succ[j]] = true;
    int start = -1, starts = 0;
    for (int i = 0; i < n; i++)
        if (!has_pred[i] && starts++ == 0)
            start = i;
    int got = 0;
    if (n > 0 && starts <= 1 && unique) {
        int at = starts ? start : lowest;
        ordered[got++] = fan[at];
        while (got <= n) {
            at = succ[at];
            if (at < 0 || fan[at] == ordered[0])
                break;
            ordered[got++] = fan[at];
        }
    }
    if (n > 0 && got == n) {
        memcpy(fan, ordered, sizeof *fan * (size_t)n);
        w->fan_kind[v] = starts ? SW_FAN_PATH : SW_FAN_CYCLE;
        return unique;
    }
    for (int i = 1; i < n; i++)   /* insertion sort: fans are short */
        for (int j = i; j > 0 && fan[j - 1] > fan[j]; j--) {
            int32_t t = fan[j];
            fan[j] = fan[j - 1], fan[j - 1] = t;
        }
    w->fan_kind[v] = SW_FAN_BROKEN;
    return unique;
}

/* A cycle starts again at its lowest corner (after a face left it). */
static void restart_cycle(sw_t *w, int v)
{
    int32_t *fan = w->pool + w->fan_off[v];
    int n = w->fan_n[v], lowest = 0;
    if (w->fan_kind[v] != SW_FAN_CYCLE)
        return;
    for (int i = 1; i < n; i++)
        if (fan[i] < fan[lowest])
            lowest = i;
    if (lowest == 0)
        return;
    int32_t tmp[SW_MAX_FAN];
    memcpy(tmp, fan, sizeof *fan * (size_t)lowest);
    memmove(fan, fan + lowest, sizeof *fan * (size_t)(n - lowest));
    memcpy(fan + n - lowest, tmp, sizeof *fan * (size_t)lowest);
}

pp5_status_t sw_init(sw_t *w, const mesh_t *in, bool recording, int queue_ids,
                     mesh_simplify_stats_t *st)
{
    memset(w, 0, sizeof *w);
    w->nv = in->n_vertices;
    w->nf = in->n_faces;
    w->recording = recording;
    w->stats = st;
    pp5_status_t s = sw_alloc(w, queue_ids);
    if (s != PP5_OK) {
        sw_free(w);
        return s;
    }
    memcpy(w->pos, in->pos, sizeof *w->pos * 3 * (size_t)w->nv);
    memcpy(w->tri, in->tri, sizeof *w->tri * 3 * (size_t)w->nf);
    memset(w->face_alive, 1, (size_t)w->nf);
    w->faces_alive = w->input_faces = w->nf;
    for (int c = 0; c < 3 * w->nf; c++)
        w->fan_n[w->tri[c]]++;
    size_t off = 0;
    for (int v = 0; v < w->nv; v++) {
        w->fan_off[v] = (int32_t)off;
        w->fan_cap[v] = w->fan_n[v] + 2;   /* room for small growth in place */
        off += (size_t)w->fan_cap[v];
        w->vert_alive[v] = w->fan_n[v] > 0;
        w->verts_alive += w->vert_alive[v];
        w->fan_n[v] = 0;
        w->rec_id[v] = v;
    }
    w->pool_n = off;
    for (int c = 0; c < 3 * w->nf; c++) {
        int v = w->tri[c];
        w->pool[w->fan_off[v] + w->fan_n[v]++] = c;
    }
    for (int f = 0; f < w->nf; f++)
        sw_face_normal(w, f, w->fnormal + 3 * f);
    w->manifold = true;
    for (int v = 0; v < w->nv; v++)
        w->manifold &= order_fan(w, v);
    if (recording) {
        memcpy(w->r_pos, in->pos, sizeof *w->r_pos * 3 * (size_t)w->nv);
        for (int v = 0; v < w->nv; v++)
            w->r_parent[v] = -1, w->r_death[v] = INT32_MAX;
        for (int f = 0; f < w->nf; f++)
            w->r_face_death[f] = INT32_MAX;
        w->r_nv = (size_t)w->nv;
    }
    sw_push_level(w);
    return PP5_OK;
}

void sw_free(sw_t *w)
{
    free(w->pos), free(w->tri);
    free(w->face_alive), free(w->vert_alive), free(w->fan_kind);
    free(w->fan_off), free(w->fan_n), free(w->fan_cap), free(w->pool), free(w->rec_id);
    free(w->fnormal);
    free(w->r_pos), free(w->r_parent), free(w->r_death), free(w->r_face_death);
    free(w->r_level_step), free(w->r_level_faces), free(w->r_level_vertices);
    sw_queue_free(&w->queue);
    memset(w, 0, sizeof *w);
}

pp5_status_t sw_check_edge_manifold(const sw_t *w, const char *source)
{
    /* An edge with three faces, or two of opposite orientation, has some
     * direction twice: sw_init saw it.  The scan below names the first. */
    if (w->manifold)
        return PP5_OK;
    for (int c = 0; c < 3 * w->nf; c++) {
        int a = w->tri[c], b = sw_nextv(w, c);
        int same = 0, faces = sw_edge_faces(w, a, b);
        const int32_t *fan = sw_fan(w, a);
        for (int i = 0; i < w->fan_n[a]; i++)
            same += sw_nextv(w, fan[i]) == b;
        if (a < b && faces > 2)
            return pp5_fail(PP5_E_FORMAT, "%s: edge %d-%d has %d faces (the simplifiers need an "
                            "edge-manifold mesh)", source, a + 1, b + 1, faces);
        if (same > 1)
            return pp5_fail(PP5_E_FORMAT, "%s: edge %d-%d is traversed the same way by two "
                            "faces (inconsistent orientation)", source, a + 1, b + 1);
    }
    return PP5_OK;
}

void sw_face_normal(const sw_t *w, int f, double n[3])
{
    const double *a = w->pos + 3 * w->tri[3 * f], *b = w->pos + 3 * w->tri[3 * f + 1],
                 *c = w->pos + 3 * w->tri[3 * f + 2];
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    sw_cross(u, v, n);
}

int sw_edge_faces(const sw_t *w, int a, int b)
{
    int n = 0;
    const int32_t *fan = sw_fan(w, a);
    for (int i = 0; i < w->fan_n[a]; i++)
        n += sw_nextv(w, fan[i]) == b || sw_prevv(w, fan[i]) == b;
    return n;
}

int sw_find_corner(const sw_t *w, int a, int b)
{
    const int32_t *fan = sw_fan(w, a);
    for (int i = 0; i < w->fan_n[a]; i++)
        if (sw_nextv(w, fan[i]) == b)
            return fan[i];
    return -1;
}

bool sw_corner_on_boundary(const sw_t *w, int c)
{
    int v = w->tri[c];
    if (w->fan_kind[v] == SW_FAN_CYCLE)
        return false;
    if (w->fan_kind[v] == SW_FAN_PATH)
        return sw_fan(w, v)[0] == c;
    return sw_find_corner(w, sw_nextv(w, c), v) < 0;
}

bool sw_vertex_on_boundary(const sw_t *w, int v)
{
    if (w->fan_kind[v] != SW_FAN_BROKEN)
        return w->fan_kind[v] == SW_FAN_PATH;
    const int32_t *fan = sw_fan(w, v);
    for (int i = 0; i < w->fan_n[v]; i++)
        if (sw_corner_on_boundary(w, fan[i]))
            return true;
    return false;
}

int sw_edge_id(const sw_t *w, int a, int b)
{
    int lo = a < b ? a : b, hi = a < b ? b : a;
    int c = sw_find_corner(w, lo, hi);
    return c >= 0 ? c : sw_find_corner(w, hi, lo);
}

int sw_ring(const sw_t *w, int v, int first, int32_t *ring, int cap)
{
    int n = w->fan_n[v];
    if (w->fan_kind[v] != SW_FAN_CYCLE || n > cap)
        return -1;
    const int32_t *fan = sw_fan(w, v);
    int at = -1;
    for (int i = 0; i < n && at < 0; i++)
        if (sw_nextv(w, fan[i]) == first)
            at = i;
    if (at < 0)
        return -1;
    for (int j = 0, i = at; j < n; j++, i = i + 1 < n ? i + 1 : 0)
        ring[j] = sw_nextv(w, fan[i]);
    return n;
}

static int in_set(const int32_t *S, int k, int v)
{
    for (int i = 0; i < k; i++)
        if (S[i] == v)
            return i;
    return -1;
}

/* Which of the faces around S survive, and the link of the merged vertex. */
static sw_verdict_t gather_faces(const sw_t *w, const int32_t *S, int k, sw_merge_t *m,
                                 int32_t *src, int32_t *dst)
{
    m->n_keep = m->n_removed = 0;
    for (int i = 0; i < k; i++) {
        const int32_t *fan = sw_fan(w, S[i]);
        for (int j = 0; j < w->fan_n[S[i]]; j++) {
            int c = fan[j], cn = sw_next(c), cp = sw_prev(c);
            bool yn = in_set(S, k, sw_nextv(w, c)) >= 0, yp = in_set(S, k, sw_prevv(w, c)) >= 0;
            if (yn || yp) {
                /* a face shared by several of S is seen once, from the member
                 * at its lowest corner */
                int first = c;
                if (yn && cn < first)
                    first = cn;
                if (yp && cp < first)
                    first = cp;
                if (first != c)
                    continue;
                if (m->n_removed == SW_MAX_FAN)
                    return SW_TOPOLOGY;
                m->removed[m->n_removed++] = c / 3;
                continue;
            }
            if (m->n_keep == SW_MAX_FAN)
                return SW_TOPOLOGY;
            src[m->n_keep] = sw_nextv(w, c);
            dst[m->n_keep] = sw_prevv(w, c);
            m->keep[m->n_keep++] = c;
        }
    }
    return m->n_keep ? SW_OK : SW_TOPOLOGY;
}

/* For each link edge i: next[i] = the edge starting where i ends (-1: none);
 * as_dst[i] = how many edges end where i starts.  False if two edges start
 * at one vertex.  Small links go through a 64-slot hash of vertex ids. */
#define LINK_SLOTS 64
static bool link_successors(int n, const int32_t *src, const int32_t *dst, int32_t *next,
                            int32_t *as_dst)
{
    if (n > LINK_SLOTS / 3) {
        for (int i = 0; i < n; i++) {
            next[i] = -1, as_dst[i] = 0;
            for (int j = 0; j < n; j++) {
                if (j != i && src[j] == src[i])
                    return false;
                as_dst[i] += dst[j] == src[i];
                if (src[j] == dst[i])
                    next[i] = j;
            }
        }
        return true;
    }
    int32_t key[LINK_SLOTS], idx[LINK_SLOTS];
    memset(key, -1, sizeof key);
    for (int i = 0; i < n; i++) {
        unsigned h = ((uint32_t)src[i] * 2654435761u) >> 26;
        while (key[h] >= 0 && key[h] != src[i])
            h = (h + 1) & (LINK_SLOTS - 1);
        if (key[h] == src[i])
            return false;
        key[h] = src[i], idx[h] = i, as_dst[i] = 0;
    }
    for (int i = 0; i < n; i++) {
        unsigned h = ((uint32_t)dst[i] * 2654435761u) >> 26;
        while (key[h] >= 0 && key[h] != dst[i])
            h = (h + 1) & (LINK_SLOTS - 1);
        next[i] = key[h] == dst[i] ? idx[h] : -1;
        if (next[i] >= 0)
            as_dst[next[i]]++;
    }
    return true;
}

/* The link (src -> dst edges) must be one cycle of >= 3 edges or one path. */
static sw_verdict_t check_link(sw_merge_t *m, const int32_t *src, const int32_t *dst)
{
    int n = m->n_keep, start = -1;
    int32_t next[SW_MAX_FAN], as_dst[SW_MAX_FAN];
    if (!link_successors(n, src, dst, next, as_dst))
        return SW_TOPOLOGY;
    for (int i = 0; i < n; i++) {
        if (as_dst[i] > 1)
            return SW_TOPOLOGY;
        if (as_dst[i] == 0) {
            if (start >= 0)
                return SW_TOPOLOGY;   /* two path starts: the link has two pieces */
            start = i;
        }
    }
    m->boundary = start >= 0;
    if (!m->boundary && n < 3)
        return SW_TOPOLOGY;
    int at = m->boundary ? start : 0, walked = 0;
    int32_t order[SW_MAX_FAN];
    m->n_ring = 0;
    m->ring[m->n_ring++] = src[at];
    order[0] = at;
    while (walked < n) {
        walked++;
        int nx = next[at];
        if (nx < 0 || nx == (m->boundary ? -1 : 0))
            break;
        m->ring[m->n_ring++] = src[nx];
        order[walked] = at = nx;
    }
    if (walked != n)
        return SW_TOPOLOGY;
    if (m->boundary)
        m->ring[m->n_ring++] = dst[at];
    /* the kept faces in walk order: the merged vertex's fan, counter-clockwise */
    int32_t keep[SW_MAX_FAN];
    for (int i = 0; i < n; i++)
        keep[i] = m->keep[order[i]];
    memcpy(m->keep, keep, sizeof *keep * (size_t)n);
    return SW_OK;
}

/* The same verdict, faces and link as gather_faces + check_link for an edge
 * a-b inside the mesh (both fans cycles), read off the fans: a's faces after
 * (a, b, o1) round to (a, o2, b) give the link path o1 .. o2, b's faces after
 * (b, a, o2) round to (b, o1, a) the path o2 .. o1, and the link is one cycle
 * unless the two paths share an inner vertex.  -1: the shortcut does not
 * apply (a boundary, a tiny fan); the general test decides. */
static int edge_link_fast(const sw_t *w, int a, int b, sw_merge_t *m)
{
    int na = w->fan_n[a], nb = w->fan_n[b];
    if (w->fan_kind[a] != SW_FAN_CYCLE || w->fan_kind[b] != SW_FAN_CYCLE || na < 3 || nb < 3)
        return -1;
    const int32_t *fa = sw_fan(w, a), *fb = sw_fan(w, b);
    int ib = -1, ia = -1;
    for (int i = 0; i < na && ib < 0; i++)
        if (sw_nextv(w, fa[i]) == b)
            ib = i;
    for (int i = 0; i < nb && ia < 0; i++)
        if (sw_nextv(w, fb[i]) == a)
            ia = i;
    if (ib < 0 || ia < 0 || sw_prevv(w, fa[ib]) == sw_prevv(w, fb[ia]))
        return -1;
    /* the two fans from the corner after the removed face: corners a_1 ..
     * a_(na-2) and b_1 .. b_(nb-2) stay, and their ring vertices r_1 ..
     * r_(n-1) run o1 .. o2 and o2 .. o1 */
    int32_t ca[SW_MAX_FAN], cb[SW_MAX_FAN], ra[SW_MAX_FAN], rb[SW_MAX_FAN];
    for (int i = 0, k = ib; i < na; i++, k = k + 1 < na ? k + 1 : 0)
        ca[i] = fa[k], ra[i] = sw_nextv(w, fa[k]);
    for (int i = 0, k = ia; i < nb; i++, k = k + 1 < nb ? k + 1 : 0)
        cb[i] = fb[k], rb[i] = sw_nextv(w, fb[k]);
    for (int i = 2; i <= na - 2; i++)   /* inner vertices must differ */
        for (int j = 2; j <= nb - 2; j++)
            if (ra[i] == rb[j])
                return SW_TOPOLOGY;
    int n = na + nb - 4;
    if (n < 3)
        return SW_TOPOLOGY;
    /* walk order from a's first kept face in its fan order, as check_link walks */
    int first = 0;   /* a's lowest fan index whose face stays */
    while (first == ib || first == (ib + na - 1) % na)
        first++;
    int lead = first > ib ? first - ib - 1 : first + na - ib - 1;
    int32_t seq[SW_MAX_FAN];
    int q = 0;
    for (int i = 1; i <= na - 2; i++)
        seq[q++] = ca[i];
    for (int i = 1; i <= nb - 2; i++)
        seq[q++] = cb[i];
    for (int i = 0, k = lead; i < n; i++, k = k + 1 < n ? k + 1 : 0) {
        m->keep[i] = seq[k];
        m->ring[i] = sw_nextv(w, seq[k]);
    }
    m->n_keep = m->n_ring = n;
    m->n_removed = 2;
    m->removed[0] = fa[ib] / 3, m->removed[1] = fb[ia] / 3;
    m->boundary = false;
    return SW_OK;
}

sw_verdict_t sw_test_merge(const sw_t *w, const int32_t *S, int k, const double p[3],
                           sw_merge_t *m)
{
    int fast = k == 2 && w->fan_n[S[0]] + w->fan_n[S[1]] - 4 <= SW_MAX_FAN
                   ? edge_link_fast(w, S[0], S[1], m) : -1;
    sw_verdict_t v = (sw_verdict_t)fast;
    if (fast < 0) {
        int32_t src[SW_MAX_FAN], dst[SW_MAX_FAN];
        v = gather_faces(w, S, k, m, src, dst);
        if (v == SW_OK)
            v = check_link(m, src, dst);
    }
    if (v != SW_OK)
        return v;
    for (int i = 0; i < m->n_keep; i++) {   /* the one corner of each face in S moves to p */
        double n_new[3], dot, len2;
        if (!sw_face_turn(w, m->keep[i], p, n_new, &dot, &len2))
            return SW_FOLD;
    }
    return SW_OK;
}

/* Drops corner c from its vertex's fan, keeping the order of the rest. */
static void fan_remove(sw_t *w, int v, int c)
{
    int32_t *fan = w->pool + w->fan_off[v];
    int n = w->fan_n[v];
    for (int i = 0; i < n; i++)
        if (fan[i] == c) {
            memmove(fan + i, fan + i + 1, sizeof *fan * (size_t)(n - 1 - i));
            w->fan_n[v]--;
            return;
        }
}

static pp5_status_t fan_set(sw_t *w, int v, const int32_t *corners, int n)
{
    if (n > w->fan_cap[v]) {
        size_t cap = (size_t)n * 2;
        if (w->pool_n + cap > w->pool_cap) {
            size_t nc = (w->pool_cap + cap) * 2;
            int32_t *np = realloc(w->pool, sizeof *np * nc);
            if (!np)
                return pp5_fail(PP5_E_NOMEM, "simplify: out of memory for fans");
            w->pool = np;
            w->pool_cap = nc;
        }
        w->fan_off[v] = (int32_t)w->pool_n;
        w->fan_cap[v] = (int32_t)cap;
        w->pool_n += cap;
    }
    memcpy(w->pool + w->fan_off[v], corners, sizeof *corners * (size_t)n);
    w->fan_n[v] = n;
    return PP5_OK;
}

/* Record: k-1 steps, each merging the running vertex with S[i]. */
static void record_steps(sw_t *w, const int32_t *S, int k, const double p[3],
                         const sw_merge_t *m)
{
    int32_t cur = w->rec_id[S[0]];
    int base = w->step;
    for (int i = 1; i < k; i++) {
        int32_t nid = (int32_t)w->r_nv++;
        memcpy(w->r_pos + 3 * nid, p, 3 * sizeof *p);
        w->r_parent[nid] = -1;
        w->r_death[nid] = INT32_MAX;
        int32_t other = w->rec_id[S[i]];
        w->r_parent[cur] = w->r_parent[other] = nid;
        w->r_death[cur] = w->r_death[other] = base + i;
        cur = nid;
    }
    for (int r = 0; r < m->n_removed; r++) {
        /* a face dies at the step that brings its second member of S in */
        const int32_t *t = w->tri + 3 * m->removed[r];
        int idx[3], n = 0;
        for (int c = 0; c < 3; c++) {
            int s = in_set(S, k, t[c]);
            if (s >= 0)
                idx[n++] = s;
        }
        for (int a = 0; a < n; a++)
            for (int b = a + 1; b < n; b++)
                if (idx[b] < idx[a]) {
                    int tmp = idx[a];
                    idx[a] = idx[b], idx[b] = tmp;
                }
        int hi = idx[1];
        w->r_face_death[m->removed[r]] = base + (hi < 1 ? 1 : hi);
    }
    w->rec_id[S[0]] = cur;
}

/* The removed faces leave the fans of their other vertices (whose order
 * stays rotational: the faces either side of a removed one become
 * neighbours) and the queue. */
static void remove_faces(sw_t *w, const int32_t *S, int k, const sw_merge_t *m)
{
    bool by_face = w->queue.n_ids == w->nf;
    for (int r = 0; r < m->n_removed; r++) {
        int f = m->removed[r];
        w->face_alive[f] = 0;
        w->faces_alive--;
        if (w->queue.n_ids > 0 && by_face)
            sw_queue_remove(&w->queue, f);
        for (int c = 3 * f; c < 3 * f + 3; c++) {
            if (w->queue.n_ids > 0 && !by_face)
                sw_queue_remove(&w->queue, c);
            int v = w->tri[c];
            if (in_set(S, k, v) >= 0)
                continue;
            fan_remove(w, v, c);
            if (w->fan_n[v] == 0) {   /* an ear's tip: no face left */
                w->vert_alive[v] = 0;
                w->verts_alive--;
                w->fan_kind[v] = SW_FAN_BROKEN;
            }
        }
    }
}

bool sw_merge_allowed(sw_t *w, const int32_t *S, int k, const double p[3], sw_merge_t *m)
{
    sw_verdict_t v = sw_test_merge(w, S, k, p, m);
    if (v == SW_FOLD)
        w->stats->refused_fold++;
    else if (v != SW_OK)
        w->stats->refused_topology++;
    return v == SW_OK;
}

pp5_status_t sw_apply_merge(sw_t *w, const int32_t *S, int k, const double p[3],
                            const sw_merge_t *m)
{
    if (w->recording)
        record_steps(w, S, k, p, m);
    remove_faces(w, S, k, m);
    for (int i = 0; i < m->n_keep; i++)
        w->tri[m->keep[i]] = S[0];
    pp5_status_t st = fan_set(w, S[0], m->keep, m->n_keep);
    if (st != PP5_OK)
        return st;
    /* The new fan is the link's walk, counter-clockwise.  The fans that lost
     * a face keep their order (the faces either side of it now share an edge
     * to S[0]); a cycle's canonical start, its lowest corner, may have gone. */
    w->fan_kind[S[0]] = m->boundary ? SW_FAN_PATH : SW_FAN_CYCLE;
    restart_cycle(w, S[0]);
    for (int r = 0; r < m->n_removed; r++)
        for (int c = 3 * m->removed[r]; c < 3 * m->removed[r] + 3; c++)
            if (in_set(S, k, w->tri[c]) < 0 && w->fan_n[w->tri[c]] > 0) {
                if (w->fan_kind[w->tri[c]] == SW_FAN_BROKEN)
                    order_fan(w, w->tri[c]);   /* a pinch may have gone with the face */
                else
                    restart_cycle(w, w->tri[c]);
            }
    for (int i = 1; i < k; i++) {
        w->vert_alive[S[i]] = 0;
        w->fan_n[S[i]] = 0;
        w->fan_kind[S[i]] = SW_FAN_BROKEN;
    }
    memcpy(w->pos + 3 * S[0], p, 3 * sizeof *p);
    w->verts_alive -= k - 1;
    w->step += k - 1;
    if (w->stats)
        w->stats->merges++;
    sw_push_level(w);
    return PP5_OK;
}

pp5_status_t sw_to_mesh(const sw_t *w, mesh_t *out)
{
    pp5_status_t st = mesh_alloc(out, w->verts_alive, w->faces_alive);
    if (st != PP5_OK)
        return st;
    int32_t *map = malloc(sizeof *map * ((size_t)w->nv + 1));
    if (!map) {
        mesh_free(out);
        return pp5_fail(PP5_E_NOMEM, "simplify: out of memory");
    }
    int n = 0;
    for (int v = 0; v < w->nv; v++) {
        map[v] = -1;
        if (w->vert_alive[v] && w->fan_n[v] > 0) {
            memcpy(out->pos + 3 * n, w->pos + 3 * v, 3 * sizeof *out->pos);
            map[v] = n++;
        }
    }
    int f_out = 0;
    for (int f = 0; f < w->nf; f++)
        if (w->face_alive[f]) {
            for (int c = 0; c < 3; c++)
                out->tri[3 * f_out + c] = map[w->tri[3 * f + c]];
            f_out++;
        }
    out->n_vertices = n;
    free(map);
    return PP5_OK;
}
