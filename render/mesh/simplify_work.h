/* simplify_work.h: the working mesh the three simplifiers share: vertex
 * fans, the merge test (manifold link, fold-over), the merge itself with its
 * record entry, and a lazy-deletion priority queue of candidate merges. */
#ifndef PP5_SIMPLIFY_WORK_H
#define PP5_SIMPLIFY_WORK_H

#include <stdbool.h>
#include <stdint.h>
#include "mesh_simplify.h"

#define SW_MAX_FAN 256     /* faces around a merge; larger neighbourhoods are refused */

typedef struct {
    double cost;
    int32_t a, b;          /* edge (a, b) or face a (b = -1) */
    uint32_t sa, sb;       /* stamps when the entry was made */
} sw_entry_t;

typedef struct {
    sw_entry_t *e;
    size_t n, cap;
} sw_heap_t;

/* What a merge test found: the surviving faces (with their normals before
 * and after) and the removed ones. */
typedef struct {
    int n_keep, n_removed;
    int32_t keep[SW_MAX_FAN], removed[SW_MAX_FAN];
    double n_old[SW_MAX_FAN][3], n_new[SW_MAX_FAN][3];
    int n_ring;
    int32_t ring[SW_MAX_FAN];  /* the link vertices (the new vertex's neighbours) */
    bool boundary;             /* the new vertex lies on a boundary */
} sw_merge_t;

typedef enum { SW_OK, SW_TOPOLOGY, SW_FOLD } sw_verdict_t;

typedef struct {
    int nv, nf, faces_alive, input_faces;
    double *pos;
    int32_t *tri;
    uint8_t *face_alive, *vert_alive;
    int32_t *fan_off, *fan_n, *fan_cap;  /* per vertex: faces in pool[off .. off+n) */
    int32_t *pool;
    size_t pool_n, pool_cap;
    uint32_t *stamp;                     /* per vertex (edge methods) */
    uint32_t *fstamp;                    /* per face (face methods) */
    int32_t *rec_id;                     /* vertex slot -> record vertex id */
    double fold_cos_min;
    /* the record being built */
    bool recording;
    double *r_pos;
    int32_t *r_parent, *r_death, *r_face_death;
    size_t r_nv, r_cap;
    int32_t *r_level_step, *r_level_faces, *r_level_vertices;
    int r_levels, r_level_cap, step, verts_alive;
    sw_heap_t heap;
    mesh_simplify_stats_t *stats;
} sw_t;

pp5_status_t sw_init(sw_t *w, const mesh_t *in, bool recording, mesh_simplify_stats_t *st);
void sw_free(sw_t *w);

/* Is vertex b in a face with a? *n_shared = how many faces hold both. */
int sw_edge_faces(const sw_t *w, int a, int b);
bool sw_vertex_on_boundary(const sw_t *w, int v);
/* The third vertex of the face holding directed edge a->b, or -1. */
int sw_opposite(const sw_t *w, int a, int b);
/* The 1-ring of interior vertex v in order, starting at `first` (a neighbour);
 * returns its length, or -1 if v is on a boundary or the ring is not one cycle. */
int sw_ring(const sw_t *w, int v, int first, int32_t *ring, int cap);

/* Tests merging the k vertices S into one at p.  Fills m (may be used for
 * costs) and returns the verdict. */
sw_verdict_t sw_test_merge(const sw_t *w, const int32_t *S, int k, const double p[3],
                           sw_merge_t *m);
/* Performs a tested merge: S[0] survives at p; records k-1 steps. */
pp5_status_t sw_apply_merge(sw_t *w, const int32_t *S, int k, const double p[3],
                            const sw_merge_t *m);

void sw_face_normal(const sw_t *w, int f, double n[3]);

pp5_status_t sw_heap_push(sw_heap_t *h, sw_entry_t e);
bool sw_heap_pop(sw_heap_t *h, sw_entry_t *out);
void sw_heap_free(sw_heap_t *h);
/* An edge entry with the current stamps. */
static inline sw_entry_t sw_edge_entry(const sw_t *w, double cost, int a, int b)
{
    sw_entry_t e = {cost, a, b, w->stamp[a], w->stamp[b]};
    return e;
}
static inline bool sw_entry_current(const sw_t *w, const sw_entry_t *e)
{
    if (e->b < 0)
        return w->face_alive[e->a] && w->fstamp[e->a] == e->sa;
    return w->vert_alive[e->a] && w->vert_alive[e->b] && w->stamp[e->a] == e->sa &&
           w->stamp[e->b] == e->sb;
}

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

#endif
