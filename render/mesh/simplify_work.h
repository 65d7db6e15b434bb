/* simplify_work.h: the working mesh the three simplifiers share: corner
 * fans kept in rotational order, the merge test (manifold link, fold-over),
 * the merge itself with its record entry, and an indexed priority queue of
 * candidate merges.
 *
 * Layout (render/mesh/ARCHITECTURE.md, "Speed"): corner c = 3 f + k is vertex
 * tri[c] of face f; the face is (tri[c], tri[sw_next(c)], tri[sw_prev(c)])
 * counter-clockwise, and corner c also names the directed edge
 * tri[c] -> tri[sw_next(c)] (sw_nextv, sw_prevv: a face's three vertices
 * share one cache line, which the simplifiers' random walks over the mesh
 * miss far more often than they pay for the index arithmetic).  Each vertex keeps the corners at it in
 * counter-clockwise order (a cycle inside, a path starting at the boundary
 * on the boundary), so its ring, valence and the third vertex of any of its
 * faces are read off in O(valence) without searching faces.  The queue holds
 * each candidate once under a fixed id (a corner for edges, a face for
 * triangles) and re-costing moves it in place, so no stale entries pile up. */
#ifndef PP5_SIMPLIFY_WORK_H
#define PP5_SIMPLIFY_WORK_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include "mesh_simplify.h"

#define SW_MAX_FAN 256     /* faces around a merge; larger neighbourhoods are refused */

/* Corner ids are never negative: the unsigned remainder needs no sign fix. */
static inline int sw_next(int c)
{
    return (unsigned)c % 3u == 2 ? c - 2 : c + 1;
}
static inline int sw_prev(int c)
{
    return (unsigned)c % 3u == 0 ? c + 2 : c - 1;
}

/* How the corners at a vertex fit together. */
enum { SW_FAN_CYCLE, SW_FAN_PATH, SW_FAN_BROKEN };

/* ---- the candidate queue: an indexed 4-ary min-heap on (cost, tie) ---- */
typedef struct {
    double cost;
    uint64_t tie;          /* ties break on this (lower vertex / face ids first) */
    int32_t id;
} sw_qentry_t;

/* A heap slot: 16 bytes, so a node's four children fill one cache line
 * (simplify_queue.c aligns them); the tie, needed only when costs are
 * equal, stays beside the id in tie[]. */
typedef struct {
    double cost;
    int32_t id, unused;
} sw_qslot_t;

typedef struct {
    sw_qslot_t *e;         /* the heap: e[0] is the least */
    void *block;           /* the allocation e points into */
    uint64_t *tie;         /* id -> its tie key */
    int32_t *where;        /* id -> index in e, or -1 */
    int n, n_ids;
} sw_queue_t;

pp5_status_t sw_queue_init(sw_queue_t *q, int n_ids);
void sw_queue_free(sw_queue_t *q);
/* Inserts id or moves it to its new key. */
void sw_queue_set(sw_queue_t *q, int id, double cost, uint64_t tie);
void sw_queue_remove(sw_queue_t *q, int id);
/* Building a queue at once: append each id once, then heapify (O(n)). */
void sw_queue_append(sw_queue_t *q, int id, double cost, uint64_t tie);
void sw_queue_heapify(sw_queue_t *q);
bool sw_queue_pop(sw_queue_t *q, sw_qentry_t *out);
/* The least entry, left in place (the queue must not be empty). */
static inline sw_qentry_t sw_queue_top(const sw_queue_t *q)
{
    return (sw_qentry_t){q->e[0].cost, q->tie[q->e[0].id], q->e[0].id};
}
static inline bool sw_queue_has(const sw_queue_t *q, int id)
{
    return q->where[id] >= 0;
}
/* The cost id is queued under (the queue must hold it). */
static inline double sw_queue_cost(const sw_queue_t *q, int id)
{
    return q->e[q->where[id]].cost;
}
static inline uint64_t sw_edge_tie(int a, int b)
{
    return a < b ? (uint64_t)a << 32 | (uint32_t)b : (uint64_t)b << 32 | (uint32_t)a;
}

/* What a merge test found: the surviving faces (as their corner at the
 * merged set, in fan order) and the removed ones. */
typedef struct {
    int n_keep, n_removed;
    int32_t keep[SW_MAX_FAN], removed[SW_MAX_FAN];
    int n_ring;
    int32_t ring[SW_MAX_FAN + 1]; /* the link vertices (the new vertex's neighbours), in order */
    bool boundary;                /* the new vertex lies on a boundary */
} sw_merge_t;

typedef enum { SW_OK, SW_TOPOLOGY, SW_FOLD } sw_verdict_t;

typedef struct {
    int nv, nf, faces_alive, input_faces;
    double *pos;
    int32_t *tri;                        /* per corner: its vertex */
    uint8_t *face_alive, *vert_alive;
    uint8_t *fan_kind;                   /* SW_FAN_* per vertex */
    int32_t *fan_off, *fan_n, *fan_cap;  /* per vertex: corners in pool[off .. off+n) */
    int32_t *pool;
    size_t pool_n, pool_cap;
    int32_t *rec_id;                     /* vertex slot -> record vertex id */
    bool manifold;                       /* no edge direction twice at any vertex (input) */
    double *fnormal;                     /* per face: sw_face_normal at sw_init (not kept
                                            current: read before the first merge only) */
    double fold_cos_min;
    sw_queue_t queue;
    /* the record being built */
    bool recording;
    double *r_pos;
    int32_t *r_parent, *r_death, *r_face_death;
    size_t r_nv, r_cap;
    int32_t *r_level_step, *r_level_faces, *r_level_vertices;
    int r_levels, r_level_cap, step, verts_alive;
    mesh_simplify_stats_t *stats;
} sw_t;

/* The other two vertices of corner c's face: the head of the edge c names,
 * and the vertex before c. */
static inline int sw_nextv(const sw_t *w, int c)
{
    return w->tri[sw_next(c)];
}
static inline int sw_prevv(const sw_t *w, int c)
{
    return w->tri[sw_prev(c)];
}

/* queue_ids: how many ids the candidate queue takes (3 nf for edges, nf for faces). */
pp5_status_t sw_init(sw_t *w, const mesh_t *in, bool recording, int queue_ids,
                     mesh_simplify_stats_t *st);
void sw_free(sw_t *w);
/* Every edge in at most two faces, each direction in at most one. */
pp5_status_t sw_check_edge_manifold(const sw_t *w, const char *source);

static inline const int32_t *sw_fan(const sw_t *w, int v)
{
    return w->pool + w->fan_off[v];
}
/* How many faces hold both a and b. */
int sw_edge_faces(const sw_t *w, int a, int b);
bool sw_vertex_on_boundary(const sw_t *w, int v);
/* The corner of directed edge a -> b, or -1. */
int sw_find_corner(const sw_t *w, int a, int b);
/* The third vertex of the face holding directed edge a->b, or -1. */
static inline int sw_opposite(const sw_t *w, int a, int b)
{
    int c = sw_find_corner(w, a, b);
    return c < 0 ? -1 : w->tri[sw_prev(c)];
}
/* Does directed edge c (tri[c] -> tri[next c]) lack a twin? */
bool sw_corner_on_boundary(const sw_t *w, int c);
/* The queue id of undirected edge a-b: the corner a -> b when a < b and it
 * exists, else the only corner (a boundary edge); -1 if a-b is no edge. */
int sw_edge_id(const sw_t *w, int a, int b);
/* The 1-ring of interior vertex v in order, starting at `first` (a neighbour);
 * returns its length, or -1 if v is on a boundary or the ring is not one cycle. */
int sw_ring(const sw_t *w, int v, int first, int32_t *ring, int cap);

/* Tests merging the k vertices S into one at p.  Fills m (may be used for
 * costs) and returns the verdict. */
sw_verdict_t sw_test_merge(const sw_t *w, const int32_t *S, int k, const double p[3],
                           sw_merge_t *m);
/* sw_test_merge, counting a refusal in the statistics (folds apart from
 * topology); true when the merge may go ahead. */
bool sw_merge_allowed(sw_t *w, const int32_t *S, int k, const double p[3], sw_merge_t *m);
/* Performs a tested merge: S[0] survives at p; records k-1 steps.  Queue
 * entries of the removed faces' corners are dropped. */
pp5_status_t sw_apply_merge(sw_t *w, const int32_t *S, int k, const double p[3],
                            const sw_merge_t *m);

void sw_face_normal(const sw_t *w, int f, double n[3]);

/* The working mesh as it stands (alive vertices renumbered in slot order). */
pp5_status_t sw_to_mesh(const sw_t *w, mesh_t *out);
/* Moves the record out of the working mesh. */
pp5_status_t sw_take_record(sw_t *w, const mesh_t *in, mesh_record_t *r);

/* Method entry points (simplify_qem.c, simplify_seed001.c, simplify_seed003.c). */
pp5_status_t simplify_qem_run(sw_t *w, const mesh_simplify_opts_t *o);
pp5_status_t simplify_seed001_run(sw_t *w, const mesh_simplify_opts_t *o);
pp5_status_t simplify_seed003_run(sw_t *w, const mesh_simplify_opts_t *o);

static inline double sw_dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
static inline void sw_cross(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}
/* max/min without the libm call (no NaN reaches them here) */
static inline double sw_max(double a, double b)
{
    return a > b ? a : b;
}
static inline double sw_min(double a, double b)
{
    return a < b ? a : b;
}

/* The turn of the face of corner c when c's vertex moves to p: its new
 * normal, n_old . n_new and |n_old|^2 |n_new|^2 (the cosine of the turn is
 * dot / sqrt(len2)).  False where the face folds: no area left, or turned
 * to fold_cos_min or past it.  The merge test (sw_test_merge) and seed
 * 003's costing both decide folds by it. */
static inline bool sw_face_turn(const sw_t *w, int c, const double p[3], double n_new[3],
                                double *dot, double *len2)
{
    int f = c / 3, at = c - 3 * f;
    const int32_t *tv = w->tri + 3 * f;
    const double *o0 = w->pos + 3 * tv[0], *o1 = w->pos + 3 * tv[1], *o2 = w->pos + 3 * tv[2];
    const double *q0 = at == 0 ? p : o0, *q1 = at == 1 ? p : o1, *q2 = at == 2 ? p : o2;
    /* The normal before the move, from the positions the new one reads
     * anyway (sw_face_normal's expression, so the same doubles): a cached
     * normal per face cost a cold cache line per face tested. */
    double uo[3] = {o1[0] - o0[0], o1[1] - o0[1], o1[2] - o0[2]};
    double to[3] = {o2[0] - o0[0], o2[1] - o0[1], o2[2] - o0[2]}, n_old[3];
    sw_cross(uo, to, n_old);
    double u[3] = {q1[0] - q0[0], q1[1] - q0[1], q1[2] - q0[2]};
    double t[3] = {q2[0] - q0[0], q2[1] - q0[1], q2[2] - q0[2]};
    sw_cross(u, t, n_new);
    double lo = sw_dot(n_old, n_old), ln = sw_dot(n_new, n_new);
    /* a new face of (almost) no area has no orientation left to keep */
    if (ln <= 1e-24 * (lo > 0 ? lo : 1.0) || ln == 0.0)
        return false;
    double d = sw_dot(n_old, n_new);
    *dot = d, *len2 = lo * ln;
    return !(lo > 0 && d <= (w->fold_cos_min == 0 ? 0.0 : w->fold_cos_min * sqrt(lo * ln)));
}

#endif
