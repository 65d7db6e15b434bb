/* simplify_work.c: the working mesh of the simplifiers: fans, the merge test
 * (one manifold link, no fold-over), the merge and its record steps, and the
 * candidate queue. */
#include "simplify_work.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static pp5_status_t sw_alloc(sw_t *w)
{
    size_t nv = (size_t)w->nv + 1, nf = (size_t)w->nf + 1;
    w->pos = malloc(sizeof *w->pos * 3 * nv);
    w->tri = malloc(sizeof *w->tri * 3 * nf);
    w->face_alive = malloc(nf);
    w->vert_alive = calloc(nv, 1);
    w->fan_off = malloc(sizeof *w->fan_off * nv);
    w->fan_n = calloc(nv, sizeof *w->fan_n);
    w->fan_cap = malloc(sizeof *w->fan_cap * nv);
    w->stamp = calloc(nv, sizeof *w->stamp);
    w->fstamp = calloc(nf, sizeof *w->fstamp);
    w->rec_id = malloc(sizeof *w->rec_id * nv);
    w->pool_cap = 2 * 3 * nf + 64;
    w->pool = malloc(sizeof *w->pool * w->pool_cap);
    if (!w->pos || !w->tri || !w->face_alive || !w->vert_alive || !w->fan_off || !w->fan_n ||
        !w->fan_cap || !w->stamp || !w->fstamp || !w->rec_id || !w->pool)
        return pp5_fail(PP5_E_NOMEM, "simplify: out of memory for %d vertices", w->nv);
    if (!w->recording)
        return PP5_OK;
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

pp5_status_t sw_init(sw_t *w, const mesh_t *in, bool recording, mesh_simplify_stats_t *st)
{
    memset(w, 0, sizeof *w);
    w->nv = in->n_vertices;
    w->nf = in->n_faces;
    w->recording = recording;
    w->stats = st;
    pp5_status_t s = sw_alloc(w);
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
    for (int f = 0; f < w->nf; f++)
        for (int k = 0; k < 3; k++) {
            int v = w->tri[3 * f + k];
            w->pool[w->fan_off[v] + w->fan_n[v]++] = f;
        }
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
    free(w->pos), free(w->tri), free(w->face_alive), free(w->vert_alive);
    free(w->fan_off), free(w->fan_n), free(w->fan_cap), free(w->pool);
    free(w->stamp), free(w->fstamp), free(w->rec_id);
    free(w->r_pos), free(w->r_parent), free(w->r_death), free(w->r_face_death);
    free(w->r_level_step), free(w->r_level_faces), free(w->r_level_vertices);
    sw_heap_free(&w->heap);
    memset(w, 0, sizeof *w);
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
    const int32_t *fan = w->pool + w->fan_off[a];
    for (int i = 0; i < w->fan_n[a]; i++) {
        const int32_t *t = w->tri + 3 * fan[i];
        n += t[0] == b || t[1] == b || t[2] == b;
    }
    return n;
}

int sw_opposite(const sw_t *w, int a, int b)
{
    const int32_t *fan = w->pool + w->fan_off[a];
    for (int i = 0; i < w->fan_n[a]; i++) {
        const int32_t *t = w->tri + 3 * fan[i];
        for (int k = 0; k < 3; k++)
            if (t[k] == a && t[(k + 1) % 3] == b)
                return t[(k + 2) % 3];
    }
    return -1;
}

bool sw_vertex_on_boundary(const sw_t *w, int v)
{
    const int32_t *fan = w->pool + w->fan_off[v];
    for (int i = 0; i < w->fan_n[v]; i++) {
        const int32_t *t = w->tri + 3 * fan[i];
        int k = t[0] == v ? 0 : t[1] == v ? 1 : 2;
        if (sw_opposite(w, t[(k + 1) % 3], v) < 0)
            return true;
    }
    return false;
}

int sw_ring(const sw_t *w, int v, int first, int32_t *ring, int cap)
{
    int n = 0, x = first;
    do {
        if (n == cap)
            return -1;
        ring[n++] = x;
        x = sw_opposite(w, v, x);
        if (x < 0)
            return -1;
    } while (x != first && n <= w->fan_n[v]);
    return x == first && n == w->fan_n[v] ? n : -1;
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
        const int32_t *fan = w->pool + w->fan_off[S[i]];
        for (int j = 0; j < w->fan_n[S[i]]; j++) {
            int f = fan[j];
            const int32_t *t = w->tri + 3 * f;
            int members = 0, first_member = 3;
            for (int c = 0; c < 3; c++)
                if (in_set(S, k, t[c]) >= 0)
                    members++, first_member = c < first_member ? c : first_member;
            /* a face shared by several of S is seen once, from its first member */
            if (in_set(S, k, t[first_member]) != i)
                continue;
            if (members >= 2) {
                if (m->n_removed == SW_MAX_FAN)
                    return SW_TOPOLOGY;
                m->removed[m->n_removed++] = f;
                continue;
            }
            if (m->n_keep == SW_MAX_FAN)
                return SW_TOPOLOGY;
            int c = first_member;
            src[m->n_keep] = t[(c + 1) % 3];
            dst[m->n_keep] = t[(c + 2) % 3];
            m->keep[m->n_keep++] = f;
        }
    }
    return m->n_keep ? SW_OK : SW_TOPOLOGY;
}

/* The link (src -> dst edges) must be one cycle of >= 3 edges or one path. */
static sw_verdict_t check_link(sw_merge_t *m, const int32_t *src, const int32_t *dst)
{
    int n = m->n_keep, start = -1;
    for (int i = 0; i < n; i++) {
        int as_src = 0, as_dst = 0;
        for (int j = 0; j < n; j++) {
            as_src += src[j] == src[i];
            as_dst += dst[j] == src[i];
        }
        if (as_src > 1 || as_dst > 1)
            return SW_TOPOLOGY;
        if (as_dst == 0) {
            if (start >= 0)
                return SW_TOPOLOGY;   /* two path starts: the link has two pieces */
            start = i;
        }
    }
    m->boundary = start >= 0;
    if (!m->boundary && n < 3)
        return SW_TOPOLOGY;
    int at = m->boundary ? start : 0, walked = 0;
    m->n_ring = 0;
    m->ring[m->n_ring++] = src[at];
    while (walked < n) {
        walked++;
        int next = -1;
        for (int j = 0; j < n; j++)
            if (src[j] == dst[at])
                next = j;
        if (next < 0 || next == (m->boundary ? -1 : 0))
            break;
        m->ring[m->n_ring++] = src[next];
        at = next;
    }
    if (walked != n)
        return SW_TOPOLOGY;
    if (m->boundary)
        m->ring[m->n_ring++] = dst[at];
    return SW_OK;
}

sw_verdict_t sw_test_merge(const sw_t *w, const int32_t *S, int k, const double p[3],
                           sw_merge_t *m)
{
    int32_t src[SW_MAX_FAN], dst[SW_MAX_FAN];
    sw_verdict_t v = gather_faces(w, S, k, m, src, dst);
    if (v == SW_OK)
        v = check_link(m, src, dst);
    if (v != SW_OK)
        return v;
    for (int i = 0; i < m->n_keep; i++) {
        int f = m->keep[i];
        double q[3][3];
        for (int c = 0; c < 3; c++) {
            int vert = w->tri[3 * f + c];
            const double *src_p = in_set(S, k, vert) >= 0 ? p : w->pos + 3 * vert;
            memcpy(q[c], src_p, sizeof q[c]);
        }
        sw_face_normal(w, f, m->n_old[i]);
        double u[3] = {q[1][0] - q[0][0], q[1][1] - q[0][1], q[1][2] - q[0][2]};
        double t[3] = {q[2][0] - q[0][0], q[2][1] - q[0][1], q[2][2] - q[0][2]};
        sw_cross(u, t, m->n_new[i]);
        double lo = sw_dot(m->n_old[i], m->n_old[i]), ln = sw_dot(m->n_new[i], m->n_new[i]);
        /* a new face of (almost) no area has no orientation left to keep */
        if (ln <= 1e-24 * (lo > 0 ? lo : 1.0) || ln == 0.0)
            return SW_FOLD;
        if (lo > 0 && sw_dot(m->n_old[i], m->n_new[i]) <= w->fold_cos_min * sqrt(lo * ln))
            return SW_FOLD;
    }
    return SW_OK;
}

static void fan_remove(sw_t *w, int v, int f)
{
    int32_t *fan = w->pool + w->fan_off[v];
    for (int i = 0; i < w->fan_n[v]; i++)
        if (fan[i] == f) {
            fan[i] = fan[--w->fan_n[v]];
            return;
        }
}

static pp5_status_t fan_set(sw_t *w, int v, const int32_t *faces, int n)
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
    memcpy(w->pool + w->fan_off[v], faces, sizeof *faces * (size_t)n);
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

pp5_status_t sw_apply_merge(sw_t *w, const int32_t *S, int k, const double p[3],
                            const sw_merge_t *m)
{
    if (w->recording)
        record_steps(w, S, k, p, m);
    for (int r = 0; r < m->n_removed; r++) {
        int f = m->removed[r];
        w->face_alive[f] = 0;
        w->faces_alive--;
        for (int c = 0; c < 3; c++) {
            int v = w->tri[3 * f + c];
            if (in_set(S, k, v) < 0) {
                fan_remove(w, v, f);
                if (w->fan_n[v] == 0) {   /* an ear's tip: no face left */
                    w->vert_alive[v] = 0;
                    w->verts_alive--;
                }
            }
        }
    }
    for (int i = 0; i < m->n_keep; i++) {
        int32_t *t = w->tri + 3 * m->keep[i];
        for (int c = 0; c < 3; c++)
            if (in_set(S, k, t[c]) > 0)
                t[c] = S[0];
    }
    pp5_status_t st = fan_set(w, S[0], m->keep, m->n_keep);
    if (st != PP5_OK)
        return st;
    for (int i = 1; i < k; i++) {
        w->vert_alive[S[i]] = 0;
        w->fan_n[S[i]] = 0;
    }
    memcpy(w->pos + 3 * S[0], p, 3 * sizeof *p);
    w->verts_alive -= k - 1;
    w->step += k - 1;
    if (w->stats)
        w->stats->merges++;
    sw_push_level(w);
    return PP5_OK;
}

/* ---- the candidate queue: a binary min-heap on (cost, a, b) ---- */

static bool entry_less(const sw_entry_t *x, const sw_entry_t *y)
{
    if (x->cost != y->cost)
        return x->cost < y->cost;
    if (x->a != y->a)
        return x->a < y->a;
    return x->b < y->b;
}

pp5_status_t sw_heap_push(sw_heap_t *h, sw_entry_t e)
{
    if (!(e.cost == e.cost))
        e.cost = INFINITY;   /* NaN costs sort last instead of breaking the order */
    if (h->n == h->cap) {
        size_t cap = h->cap ? 2 * h->cap : 4096;
        sw_entry_t *ne = realloc(h->e, sizeof *ne * cap);
        if (!ne)
            return pp5_fail(PP5_E_NOMEM, "simplify: out of memory for the queue");
        h->e = ne;
        h->cap = cap;
    }
    size_t i = h->n++;
    while (i > 0) {
        size_t up = (i - 1) / 2;
        if (!entry_less(&e, &h->e[up]))
            break;
        h->e[i] = h->e[up];
        i = up;
    }
    h->e[i] = e;
    return PP5_OK;
}

bool sw_heap_pop(sw_heap_t *h, sw_entry_t *out)
{
    if (h->n == 0)
        return false;
    *out = h->e[0];
    sw_entry_t last = h->e[--h->n];
    size_t i = 0;
    for (;;) {
        size_t c = 2 * i + 1;
        if (c >= h->n)
            break;
        if (c + 1 < h->n && entry_less(&h->e[c + 1], &h->e[c]))
            c++;
        if (!entry_less(&h->e[c], &last))
            break;
        h->e[i] = h->e[c];
        i = c;
    }
    if (h->n)
        h->e[i] = last;
    return true;
}

void sw_heap_free(sw_heap_t *h)
{
    free(h->e);
    memset(h, 0, sizeof *h);
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
