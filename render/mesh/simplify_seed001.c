/* simplify_seed001.c: triangle collapse of Qian & Luo 2017
 * (../shared/seeds/001_2cfb54a79f74d617.txt, §1.2-§2.3).
 *
 * A triangle T0 collapses to one point v0: T0 and its edge-neighbours go (4
 * faces and 2 vertices for an interior triangle), its vertex-neighbours
 * follow v0.  For each vertex v_j of T0 the weight is eqs. (1)-(3)
 * generalised to any valence:
 *   lambda_j = (sum of w over the vertex-neighbours at v_j
 *              + 1/2 sum of w over the edge-neighbours through v_j) / sum of w,
 *   w = <n0, ni> = 1 - |n0 . ni|  (the text's normalised form),
 * v0 = sum lambda_j v_j (eq. 4).  The cost is eq. (8) = eq. (5) x LAR (6) x
 * LRI (7), eq. (5) being the largest squared distance from v0 to the planes
 * of the neighbourhood.  What the paper leaves open (ARCHITECTURE.md):
 * flat neighbourhoods (sum of w = 0) use the centroid; a triangle with one
 * boundary vertex collapses onto it and one with two or more is kept, so
 * boundaries stay exactly; ties go to the lower face index; collapses that
 * break the manifold or flip a face are refused (simplify_work.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "huge_alloc.h"
#include "simplify_work.h"

/* Inlined whatever the compiler's size limits say: the fan walks are the
 * hot loop, and only inlined do their constant arguments fold away and
 * their running sums stay in registers. */
#define S001_INLINE static inline __attribute__((always_inline))

/* The evaluation is compiled twice, for AVX2 and for any x86-64, and the
 * loader picks the copy the host runs best (GCC on x86-64; PP5_NO_CLONES
 * keeps one).  Both do the same double operations in the same order (no
 * fused multiply-add: ISO C mode does not contract, and neither copy
 * enables FMA), so every cost is the same bits on any host; the AVX2 copy
 * needs fewer instructions (three-operand forms, wider vectors).  Not
 * under ThreadSanitizer: the loader runs the clones' resolver before the
 * TSan runtime is set up, and the instrumented resolver then faults. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && \
    !defined(PP5_NO_CLONES) && !defined(__SANITIZE_THREAD__)
#define S001_CLONED __attribute__((target_clones("avx2", "default")))
#else
#define S001_CLONED
#endif

/* What an evaluation reads of a face, in one cache line: its unit normal n,
 * plane offset -n.p0 and area, its vertices, where each of its corners
 * sits in its vertex's fan (so a walk needs no search for f; the walk by
 * position needs fans of at most SW_MAX_FAN, so a byte holds the place),
 * and the mark that de-duplicates a refresh's faces (kept here because
 * the face is evaluated right after it is marked). */
typedef struct {
    _Alignas(64) double n[3];
    double offset, area;
    int32_t v[3];
    uint32_t mark;
    uint8_t at[3];   /* corner 3f + j is sw_fan(w, v[j])[at[j]] */
} s001_face_t;

/* What an evaluation reads of a vertex, in one record: where its fan's
 * faces are in fan_face, how many, whether the walk by position applies
 * (an interior cycle of 3 .. SW_MAX_FAN faces), and the boundary flag. */
typedef struct {
    int32_t fan, n;
    uint8_t cycle, on_boundary;
} s001_vertex_t;

typedef struct {
    sw_t *w;
    seed001_cost_t cost;
    s001_vertex_t *vert;    /* per vertex: fan fields as fan_face, on_boundary kept current */
    uint32_t epoch;         /* the last refresh's mark */
    s001_face_t *face;      /* per face, kept current for the faces alive */
    /* w->pool's twin: the face of each corner there (so a walk reads a
     * neighbour's record without dividing its corner by 3); current for
     * every fan whose places are recorded */
    int32_t *fan_face;
    size_t fan_face_cap;
} s001_t;

/* Renews f's record from the working mesh (after f was built or moved; its
 * vertices' records first).  The normal is computed afresh: w->fnormal
 * holds the input's only (simplify_work.h). */
static void s001_face_update(s001_t *s, int f)
{
    const sw_t *w = s->w;
    s001_face_t *fc = s->face + f;
    double n[3];
    sw_face_normal(w, f, n);
    double len = sqrt(sw_dot(n, n));
    fc->area = 0.5 * len;
    if (len > 0)
        for (int k = 0; k < 3; k++)
            n[k] /= len;
    memcpy(fc->n, n, sizeof n);
    fc->offset = -sw_dot(n, w->pos + 3 * w->tri[3 * f]);
    memcpy(fc->v, w->tri + 3 * f, sizeof fc->v);
}

/* Records u's fan in its vertex record and fan_face, and where each of its
 * corners sits in the face's at, or in by_corner[corner] if given (the
 * first indexing: the records are then written in face order, not at
 * random).  A place is cut to a byte only where no walk by place reads it. */
static void s001_index_fan(s001_t *s, int u, uint8_t *by_corner)
{
    const sw_t *w = s->w;
    const int32_t *fan = sw_fan(w, u);
    int32_t *fan_face = s->fan_face + w->fan_off[u];
    s001_vertex_t *vr = s->vert + u;
    vr->fan = w->fan_off[u], vr->n = w->fan_n[u];
    vr->cycle = w->fan_kind[u] == SW_FAN_CYCLE && vr->n >= 3 && vr->n <= SW_MAX_FAN;
    for (int i = 0; i < w->fan_n[u]; i++) {
        fan_face[i] = fan[i] / 3;
        if (by_corner)
            by_corner[fan[i]] = (uint8_t)i;
        else
            s->face[fan[i] / 3].at[fan[i] % 3] = (uint8_t)i;
    }
}

/* fan_face grows with w->pool (a fan that outgrew its place moved to the
 * pool's end). */
static pp5_status_t s001_fit_fan_face(s001_t *s)
{
    if (s->fan_face_cap >= s->w->pool_cap)
        return PP5_OK;
    int32_t *grown = realloc(s->fan_face, sizeof *grown * s->w->pool_cap);
    if (!grown)
        return pp5_fail(PP5_E_NOMEM, "seed001: out of memory");
    s->fan_face = grown;
    s->fan_face_cap = s->w->pool_cap;
    return PP5_OK;
}

static uint32_t s001_next_epoch(s001_t *s)
{
    if (++s->epoch == 0) {
        for (int f = 0; f < s->w->nf; f++)
            s->face[f].mark = 0;
        s->epoch = 1;
    }
    return s->epoch;
}

/* A face's neighbourhood as it is summed: eqs. (1)-(3) and (6)-(7)'s sums,
 * and the neighbours for eq. (5) (room for a vector's padding after them). */
typedef struct {
    const double *n0;
    double sum_w, max_w, area_sum, lam[3];
    int k;
    const s001_face_t *nb[3 * SW_MAX_FAN + 4];
} s001_hood_t;

/* Neighbour g of f shares f's vertex j and, if second >= 0, that one too. */
static inline void s001_hood_add(s001_hood_t *h, const s001_face_t *g, int j, int second)
{
    double wt = 1.0 - fabs(sw_dot(h->n0, g->n));
    if (second < 0)
        h->lam[j] += wt;
    else
        h->lam[j] += 0.5 * wt, h->lam[second] += 0.5 * wt;
    h->sum_w += wt;
    h->max_w = sw_max(h->max_w, wt);
    h->area_sum += g->area;
    h->nb[h->k++] = g;
}

/* The faces at f's vertex j, any fan: a face's other corners name the
 * second vertex it shares with f, if any; an edge-neighbour is in two of
 * the fans and counts from the first. */
static void s001_hood_fan_any(s001_hood_t *h, const s001_t *s, int f, int j)
{
    const sw_t *w = s->w;
    const int32_t *t = s->face[f].v, *fan = sw_fan(w, t[j]);
    int n = w->fan_n[t[j]], lo = j == 0 ? 1 : 0, hi = j == 2 ? 1 : 2;
    int t_lo = t[lo], t_hi = t[hi];
    for (int i = 0; i < n && h->k < 3 * SW_MAX_FAN; i++) {
        int c = fan[i], g = c / 3;
        if (g == f)
            continue;
        int y = sw_nextv(w, c), z = sw_prevv(w, c);
        int second = t_hi == y || t_hi == z ? hi : t_lo == y || t_lo == z ? lo : -1;
        if (second >= 0 && second < j)
            continue;
        s001_hood_add(h, s->face + g, j, second);
    }
}

/* The running sums of an interior neighbourhood, kept in registers. */
typedef struct {
    const double *n0;
    double lam_j, sum_w, max_w, area_sum;
    const s001_face_t **nb;
    int k;
} s001_walk_t;

/* Neighbour g, counting `share` (1 or 1/2) of its weight for the fan's
 * vertex; returns the weight. */
static inline double s001_walk_add(s001_walk_t *r, const s001_face_t *g, double share)
{
    double wt = 1.0 - fabs(sw_dot(r->n0, g->n));
    r->lam_j += share * wt;   /* 1.0 * wt is wt */
    r->sum_w += wt;
    r->max_w = sw_max(r->max_w, wt);
    r->area_sum += g->area;
    r->nb[r->k++] = g;
    return wt;
}

/* The faces of fan[a .. b) (fan: the fan's faces, fan_face): vertex-neighbours,
 * the whole weight to the fan's vertex. */
static inline void s001_walk_range(s001_walk_t *r, const s001_face_t *faces,
                                   const int32_t *fan, int a, int b)
{
    for (int i = a; i < b; i++)
        s001_walk_add(r, faces + fan[i], 1.0);
}

/* The edge-neighbour at fan[i], half its weight to the fan's vertex, if it
 * counts here; returns its weight (0 if not). */
static inline double s001_walk_edge(s001_walk_t *r, const s001_face_t *faces,
                                    const int32_t *fan, int i, bool counts)
{
    return counts ? s001_walk_add(r, faces + fan[i], 0.5) : 0;
}

/* Walk j over the interior fan of f's vertex j (n faces, f's corner at
 * position p), in fan order from the fan's canonical start, without f.
 * The rotational order with distinct ring vertices puts the two faces
 * sharing an edge with f either side of f's corner (the one after holds
 * f's vertex j + 2, the one before j + 1) and no other face of the fan
 * holds f's other vertices, so positions alone tell the neighbours apart
 * and the rest are summed in plain loops.  An edge-neighbour counts in the
 * walk of the lower of its two vertices of f: walk 0 counts both, walk 1
 * the one before, walk 2 neither.  Returns lambda_j; the counted
 * edge-neighbours' weights go to wt_after and wt_before. */
S001_INLINE double s001_walk_fan(s001_walk_t *r, const s001_face_t *faces, const int32_t *fan,
                                 int n, int p, const int j, double lam_j, double *wt_after,
                                 double *wt_before)
{
    const bool count_after = j == 0, count_before = j < 2;
    r->lam_j = lam_j;
    if (p == 0) {
        *wt_after = s001_walk_edge(r, faces, fan, 1, count_after);
        s001_walk_range(r, faces, fan, 2, n - 1);
        *wt_before = s001_walk_edge(r, faces, fan, n - 1, count_before);
    } else if (p == n - 1) {
        *wt_after = s001_walk_edge(r, faces, fan, 0, count_after);
        s001_walk_range(r, faces, fan, 1, n - 2);
        *wt_before = s001_walk_edge(r, faces, fan, n - 2, count_before);
    } else {
        s001_walk_range(r, faces, fan, 0, p - 1);
        *wt_before = s001_walk_edge(r, faces, fan, p - 1, count_before);
        *wt_after = s001_walk_edge(r, faces, fan, p + 1, count_after);
        s001_walk_range(r, faces, fan, p + 2, n);
    }
    return r->lam_j;
}

/* f's neighbourhood when all three of its fans (vr: its vertices' records)
 * are interior cycles: the same sums in the same order as
 * s001_hood_fan_any (an edge-neighbour's other half reaches the later
 * vertex's lambda before that vertex's walk adds anything).  f's vertices
 * are distinct (mesh_validate refuses a face that repeats one, and a merge
 * removes every face with two merged vertices).  False if a fan is not an
 * interior cycle or a recorded place does not hold f (the general walk
 * decides then). */
S001_INLINE bool s001_hood_interior(s001_hood_t *h, const s001_t *s, int f,
                                    const s001_vertex_t *const vr[3])
{
    const s001_face_t *fc = s->face + f, *faces = s->face;
    const int32_t *fan[3];
    int n[3];
    for (int j = 0; j < 3; j++) {
        n[j] = vr[j]->n, fan[j] = s->fan_face + vr[j]->fan;
        if (!vr[j]->cycle || fc->at[j] >= n[j] || fan[j][fc->at[j]] != f)
            return false;
    }
    s001_walk_t r = {h->n0, 0, 0, 0, h->area_sum, h->nb, 0};
    double after0, before0, after1, before1, after2, before2;
    h->lam[0] = s001_walk_fan(&r, faces, fan[0], n[0], fc->at[0], 0, 0.0, &after0, &before0);
    h->lam[1] = s001_walk_fan(&r, faces, fan[1], n[1], fc->at[1], 1, 0.5 * before0, &after1,
                              &before1);
    h->lam[2] = s001_walk_fan(&r, faces, fan[2], n[2], fc->at[2], 2,
                              0.5 * after0 + 0.5 * before1, &after2, &before2);
    h->sum_w = r.sum_w, h->max_w = r.max_w, h->area_sum = r.area_sum;
    h->k = r.k;
    return true;
}

/* Four doubles side by side (GCC's vector extension: AVX2 lanes in that
 * copy of the evaluation, SSE2 pairs in the other). */
typedef double s001_v4 __attribute__((vector_size(32)));
#if defined(__clang__)
#define S001_SHUFFLE(a, b, i0, i1, i2, i3) __builtin_shufflevector(a, b, i0, i1, i2, i3)
#else
typedef int64_t s001_v4_index __attribute__((vector_size(32)));
#define S001_SHUFFLE(a, b, i0, i1, i2, i3) __builtin_shuffle(a, b, (s001_v4_index){i0, i1, i2, i3})
#endif

/* The first 32 bytes of four face records (unit normal and offset) as four
 * vectors: the normals' x, y and z, and the offsets. */
S001_INLINE void s001_transpose(const s001_face_t *const *g, s001_v4 *x, s001_v4 *y, s001_v4 *z,
                                s001_v4 *offset)
{
    const s001_v4 r0 = *(const s001_v4 *)g[0]->n, r1 = *(const s001_v4 *)g[1]->n,
                  r2 = *(const s001_v4 *)g[2]->n, r3 = *(const s001_v4 *)g[3]->n;
    s001_v4 xz01 = S001_SHUFFLE(r0, r1, 0, 4, 2, 6), yd01 = S001_SHUFFLE(r0, r1, 1, 5, 3, 7);
    s001_v4 xz23 = S001_SHUFFLE(r2, r3, 0, 4, 2, 6), yd23 = S001_SHUFFLE(r2, r3, 1, 5, 3, 7);
    *x = S001_SHUFFLE(xz01, xz23, 0, 1, 4, 5), *z = S001_SHUFFLE(xz01, xz23, 2, 3, 6, 7);
    *y = S001_SHUFFLE(yd01, yd23, 0, 1, 4, 5), *offset = S001_SHUFFLE(yd01, yd23, 2, 3, 6, 7);
}

/* The squared distances from p to the planes of four records, computed
 * as sw_dot(n, p) + offset, squared, lane by lane. */
S001_INLINE void s001_plane_errors(const s001_face_t *const *g, const s001_v4 p[3], s001_v4 *e2)
{
    s001_v4 x, y, z, offset;
    s001_transpose(g, &x, &y, &z, &offset);
    s001_v4 e = x * p[0] + y * p[1] + z * p[2] + offset;
    *e2 = e * e;
}

/* Eq. (5): the largest squared distance from v0 to the planes of nb[0 ..
 * k), four planes at a time but the maximum taken in list order, as one
 * plane at a time would (the same bits even where a NaN came in).  The
 * last four are padded with the last plane: taking a value into the
 * maximum a second time right after the first changes nothing. */
S001_INLINE double s001_largest_plane_error(const s001_face_t **nb, int k, const double v0[3])
{
    if (k == 0)
        return 0;
    nb[k] = nb[k + 1] = nb[k + 2] = nb[k - 1];
    const s001_v4 p[3] = {{v0[0], v0[0], v0[0], v0[0]}, {v0[1], v0[1], v0[1], v0[1]},
                          {v0[2], v0[2], v0[2], v0[2]}};
    double largest = 0;
    for (int i = 0; i < k; i += 4) {
        s001_v4 e;
        s001_plane_errors(nb + i, p, &e);
        largest = sw_max(sw_max(sw_max(sw_max(largest, e[0]), e[1]), e[2]), e[3]);
    }
    return largest;
}

/* The collapse point and cost of face f; false if f may not collapse. */
S001_CLONED static bool s001_evaluate(s001_t *s, int f, double v0[3], double *cost)
{
    const s001_face_t *f0 = s->face + f;
    const int32_t *t = f0->v;
    const s001_vertex_t *const vr[3] = {s->vert + t[0], s->vert + t[1], s->vert + t[2]};
    int n_boundary = 0, pinned = -1;
    for (int j = 0; j < 3; j++)
        if (vr[j]->on_boundary)
            n_boundary++, pinned = j;
    if (n_boundary >= 2)
        return false;
    double a0 = f0->area;
    s001_hood_t h;
    h.n0 = f0->n, h.sum_w = 0, h.max_w = 0, h.area_sum = a0;
    h.lam[0] = h.lam[1] = h.lam[2] = 0, h.k = 0;
    if (!s001_hood_interior(&h, s, f, vr)) {
        s001_hood_fan_any(&h, s, f, 0);
        s001_hood_fan_any(&h, s, f, 1);
        s001_hood_fan_any(&h, s, f, 2);
    }
    double *lam = h.lam, sum_w = h.sum_w;
    int k = h.k;
    if (pinned >= 0) {
        lam[0] = lam[1] = lam[2] = 0;
        lam[pinned] = 1;
    } else if (sum_w > 1e-12) {
        for (int j = 0; j < 3; j++)
            lam[j] /= sum_w;
    } else {
        lam[0] = lam[1] = lam[2] = 1.0 / 3.0;   /* flat: eqs. (1)-(3) are 0/0 */
    }
    const double *p0 = s->w->pos + 3 * t[0], *p1 = s->w->pos + 3 * t[1],
                 *p2 = s->w->pos + 3 * t[2];
    for (int c = 0; c < 3; c++)
        v0[c] = lam[0] * p0[c] + lam[1] * p1[c] + lam[2] * p2[c];
    double delta = s001_largest_plane_error(h.nb, k, v0);
    double lar = h.area_sum > 0 ? a0 / h.area_sum : 0;          /* eq. (6) */
    double lri = k > 0 ? sum_w / k + h.max_w : 0;               /* eq. (7) */
    *cost = s->cost == SEED001_COST_EQ5 ? delta
          : s->cost == SEED001_COST_EQ5_LRI ? delta * lri : delta * lar * lri; /* eq. (8) */
    return true;
}

static void s001_queue(s001_t *s, int f)
{
    double v0[3], cost;
    if (s001_evaluate(s, f, v0, &cost))
        sw_queue_set(&s->w->queue, f, cost, (uint64_t)f);
    else
        sw_queue_remove(&s->w->queue, f);
}

/* The queue's top during a refresh is, most of the time, the next face to
 * collapse (on the bunny, the top before the refresh is it for 69 % of
 * the collapses); its neighbourhood is cold, and its evaluation, the merge
 * test and the merge would fetch it one miss after another.  So between
 * the refresh's evaluations it is asked for in stages, each stage for the
 * lines whose addresses the previous one brought in: the face's record,
 * its vertices, their fans, the fans' faces (records, corners, normals),
 * those faces' vertices, then (s001_warm_ring_step) the fans around them,
 * which the refresh after that collapse reads.  A wrong guess costs only
 * the asking. */
typedef struct {
    int face, stage;
} s001_warm_t;

static void s001_warm_step(const s001_t *s, s001_warm_t *wm)
{
    const sw_t *w = s->w;
    const int f = wm->face, *t = s->face[f].v, stage = wm->stage++;
    switch (stage) {
    case 0:
        __builtin_prefetch(s->face + f);
        break;
    case 1:
        for (int j = 0; j < 3; j++) {
            __builtin_prefetch(s->vert + t[j]);
            __builtin_prefetch(w->fan_off + t[j]);
            __builtin_prefetch(w->fan_n + t[j]);
            __builtin_prefetch(w->pos + 3 * t[j]);
        }
        break;
    case 2:
        for (int j = 0; j < 3; j++) {
            const s001_vertex_t *vr = s->vert + t[j];
            __builtin_prefetch(s->fan_face + vr->fan);
            __builtin_prefetch(s->fan_face + vr->fan + vr->n - 1);
            __builtin_prefetch(w->pool + w->fan_off[t[j]]);
            __builtin_prefetch(w->pool + w->fan_off[t[j]] + w->fan_n[t[j]] - 1);
        }
        break;
    default:
        for (int j = 0; j < 3; j++) {
            const s001_vertex_t *vr = s->vert + t[j];
            const int32_t *fan = s->fan_face + vr->fan;
            for (int i = 0; i < vr->n; i++) {
                int g = fan[i];
                if (stage == 3) {   /* the fan's faces */
                    __builtin_prefetch(s->face + g);
                    __builtin_prefetch(w->tri + 3 * g);
                } else {            /* their vertices */
                    for (int k = 0; k < 3; k++) {
                        __builtin_prefetch(w->pos + 3 * s->face[g].v[k]);
                        __builtin_prefetch(s->vert + s->face[g].v[k]);
                    }
                }
            }
        }
        break;
    }
}

/* The next refresh's region if the top collapses: the fans of the top's
 * ring (the vertices after its vertices in their faces), asked for in
 * three more stages: their places, their fans, the fans' faces. */
static void s001_warm_ring_step(const s001_t *s, s001_warm_t *wm)
{
    const sw_t *w = s->w;
    const int *t = s->face[wm->face].v, stage = wm->stage++;
    for (int j = 0; j < 3; j++) {
        const int32_t *fan = sw_fan(w, t[j]);
        for (int i = 0; i < w->fan_n[t[j]]; i++) {
            int x = sw_nextv(w, fan[i]);
            const s001_vertex_t *xr = s->vert + x;
            if (stage == 5) {
                __builtin_prefetch(xr);
                __builtin_prefetch(w->fan_off + x);
            } else if (stage == 6) {
                __builtin_prefetch(s->fan_face + xr->fan);
                __builtin_prefetch(w->pool + w->fan_off[x]);
            } else {
                const int32_t *xfan = s->fan_face + xr->fan;
                for (int l = 0; l < xr->n; l++)
                    __builtin_prefetch(s->face + xfan[l]);
            }
        }
    }
}

/* After a collapse at v: v's faces moved; every face touching v or its ring
 * has a new neighbourhood, so their boundary flags and costs are renewed. */
static pp5_status_t s001_refresh(s001_t *s, int v, const sw_merge_t *m)
{
    sw_t *w = s->w;
    pp5_status_t st = s001_fit_fan_face(s);
    if (st != PP5_OK)
        return st;
    int32_t verts[SW_MAX_FAN + 2];
    int nv = 0;
    verts[nv++] = v;
    for (int i = 0; i < m->n_ring; i++)
        verts[nv++] = m->ring[i];
    for (int i = 0; i < nv; i++)
        s->vert[verts[i]].on_boundary = sw_vertex_on_boundary(w, verts[i]);
    /* the fans that changed: v's, and those that lost a removed face */
    s001_index_fan(s, v, NULL);
    for (int r = 0; r < m->n_removed; r++)
        for (int c = 3 * m->removed[r]; c < 3 * m->removed[r] + 3; c++)
            if (w->tri[c] != v)
                s001_index_fan(s, w->tri[c], NULL);
    const int32_t *vfan = s->fan_face + s->vert[v].fan;
    for (int i = 0; i < s->vert[v].n; i++)
        s001_face_update(s, vfan[i]);
    uint32_t ep = s001_next_epoch(s);
    int32_t faces[4 * SW_MAX_FAN];
    int nf = 0;
    for (int i = 0; i < nv; i++) {
        const s001_vertex_t *vr = s->vert + verts[i];
        const int32_t *fan = s->fan_face + vr->fan;
        for (int j = 0; j < vr->n && nf < 4 * SW_MAX_FAN; j++)
            if (s->face[fan[j]].mark != ep) {
                s->face[fan[j]].mark = ep;
                faces[nf++] = fan[j];
            }
    }
    /* Each re-costed face moves in the queue, whose where[] and heap slot
     * would be two misses one after the other: where[] is asked for at
     * once, a slot two evaluations ahead. */
    const sw_queue_t *q = &w->queue;
    for (int i = 0; i < nf; i++)
        __builtin_prefetch(q->where + faces[i]);
    s001_warm_t warm = {-1, 0};
    for (int i = 0; i < nf; i++) {
        if (i + 2 < nf && q->where[faces[i + 2]] >= 0)
            __builtin_prefetch(q->e + q->where[faces[i + 2]]);
        if (i % 3 == 0 && w->queue.n > 0) {
            int top = sw_queue_top(&w->queue).id;
            if (top != warm.face)   /* a re-costed face went to the top: start on it */
                warm.face = top, warm.stage = 0;
            if (warm.stage < 5)
                s001_warm_step(s, &warm);
            else if (warm.stage < 8)
                s001_warm_ring_step(s, &warm);
        }
        s001_queue(s, faces[i]);
    }
    return PP5_OK;
}

/* The records of every vertex and face, and every face costed. */
static pp5_status_t s001_start(s001_t *s)
{
    const sw_t *w = s->w;
    uint8_t *by_corner = malloc(3 * (size_t)w->nf + 1);
    pp5_status_t st = !s->vert || !s->face || !by_corner
                          ? pp5_fail(PP5_E_NOMEM, "seed001: out of memory")
                          : s001_fit_fan_face(s);
    if (st != PP5_OK) {
        free(by_corner);
        return st;
    }
    for (int v = 0; v < w->nv; v++) {
        s->vert[v].on_boundary = w->vert_alive[v] && sw_vertex_on_boundary(w, v);
        s001_index_fan(s, v, by_corner);
    }
    for (int f = 0; f < w->nf; f++) {
        s001_face_update(s, f);
        s->face[f].mark = 0;
        memcpy(s->face[f].at, by_corner + 3 * f, sizeof s->face[f].at);
    }
    free(by_corner);
    /* the queue built at once: its pops are the same, as (cost, face)
     * orders every pair of faces */
    for (int f = 0; f < w->nf; f++) {
        double v0[3], cost;
        if (s001_evaluate(s, f, v0, &cost))
            sw_queue_append(&s->w->queue, f, cost, (uint64_t)f);
    }
    sw_queue_heapify(&s->w->queue);
    return PP5_OK;
}

pp5_status_t simplify_seed001_run(sw_t *w, const mesh_simplify_opts_t *o)
{
    s001_t s = {.w = w, .cost = o->s001_cost,
                .vert = calloc((size_t)w->nv + 1, sizeof(s001_vertex_t)),
                .face = huge_alloc(sizeof(s001_face_t) * ((size_t)w->nf + 1), false)};
    pp5_status_t st = s001_start(&s);
    sw_qentry_t e;
    sw_merge_t m;
    while (st == PP5_OK && w->faces_alive > o->target_faces && sw_queue_pop(&w->queue, &e)) {
        double v0[3], cost;
        if (!s001_evaluate(&s, e.id, v0, &cost))
            continue;
        int32_t S[3] = {w->tri[3 * e.id], w->tri[3 * e.id + 1], w->tri[3 * e.id + 2]};
        if (!sw_merge_allowed(w, S, 3, v0, &m))
            continue;
        st = sw_apply_merge(w, S, 3, v0, &m);
        if (st == PP5_OK)
            st = s001_refresh(&s, S[0], &m);
    }
    free(s.vert);
    huge_free(s.face, sizeof(s001_face_t) * ((size_t)w->nf + 1));
    free(s.fan_face);
    return st;
}
