/* mesh_simplify.h: the one interface to pp5's three simplifiers and their
 * collapse records (progressive meshes).
 *
 *   seed 001  triangle collapse, Qian & Luo 2017 (../shared/seeds/001_*.txt)
 *   seed 003  edge deletion with a two-phase control function, independent
 *             sets and butterfly stencils, Cao et al. (../shared/seeds/003_*.txt)
 *   qem       Garland & Heckbert 1997 quadric edge collapse (the baseline)
 *
 * Every method runs the same way: it repeatedly merges a few vertices (two
 * for an edge, three for a triangle) into one new vertex, refusing merges
 * that would break the manifold or flip a face, until the face budget is met
 * or no merge is allowed (the topology floor).  Each merge is recorded, so a
 * mesh_record_t holds every level at once and any face budget is extracted
 * at run time without simplifying again (render/mesh/ARCHITECTURE.md). */
#ifndef PP5_MESH_SIMPLIFY_H
#define PP5_MESH_SIMPLIFY_H

#include <stdbool.h>
#include <stdint.h>
#include "mesh.h"

typedef enum { MESH_QEM, MESH_SEED001, MESH_SEED003 } mesh_method_t;

/* Seed 001's ordering cost: eq. (5) alone, eq. (5) x LRI (7), or eq. (8). */
typedef enum { SEED001_COST_EQ5, SEED001_COST_EQ5_LRI, SEED001_COST_EQ8 } seed001_cost_t;
/* Seed 003's new point: the §2.4 stencils, the edge midpoint, or the better
 * endpoint (the ablation). */
typedef enum { SEED003_POINT_STENCIL, SEED003_POINT_MIDPOINT, SEED003_POINT_ENDPOINT }
    seed003_point_t;

typedef struct {
    mesh_method_t method;
    int target_faces;          /* stop at or below this many faces; 0: to the floor */
    /* Merges are refused when a surviving face's normal turns by more than
     * this (cos of the angle; 0 = refuse any turn past 90 degrees). */
    double fold_cos_min;
    /* qem */
    double qem_boundary_weight; /* weight of the planes that hold boundary edges */
    bool qem_area_weighted;     /* face planes weighted by area (default: unit planes) */
    /* seed 001 */
    seed001_cost_t s001_cost;
    /* seed 003 (§2.1, §2.3: the paper gives no values; ARCHITECTURE.md) */
    double s003_crease_deg;    /* A1 above this: crease (importance 1) */
    double s003_corner_deg;    /* A2 above this: corner (importance 2) */
    double s003_cd[2], s003_cs[2], s003_cl[2]; /* phase 1 and phase 2 weights */
    double s003_switch_fraction; /* phase 2 once faces <= this x input faces; 0 = never */
    bool s003_independent_sets;
    bool s003_pin_corners;     /* corners never move (Table 1 read literally moves them) */
    /* Re-costed edges wait under a lower bound and are costed at the top of
     * the queue (default); false costs each at once: slower, the same
     * deletions (the check of the lazy bookkeeping). */
    bool s003_lazy;
    seed003_point_t s003_point;
} mesh_simplify_opts_t;

void mesh_simplify_defaults(mesh_simplify_opts_t *o, mesh_method_t method);
const char *mesh_method_name(mesh_method_t m);
pp5_status_t mesh_method_parse(const char *name, mesh_method_t *m);

typedef struct {
    int input_faces, output_faces, output_vertices;
    int merges;                 /* vertex merges done (one per record level) */
    long refused_topology, refused_fold, refused_other;
    int phase_switch_merge;     /* seed 003: merges done when phase 2 began (-1: never) */
    int unfreezes;              /* seed 003: independent-set rounds */
    double ms;                  /* wall time of the simplification (one thread) */
    double cpu_ms;              /* its thread CPU time (steadier on a shared host) */
} mesh_simplify_stats_t;

/* Halving MESH_MAX_FACES down to one face takes 26 checkpoints. */
#define MESH_RECORD_CHECKPOINTS 40

/* The collapse record.  Vertices 0..n_input_vertices-1 are the input's; each
 * merge step s (1-based) creates vertex n_input_vertices + s - 1 from two
 * existing ones (a triangle collapse is two steps).  A face lives while
 * step < face_death; faces are stored in decreasing face_death, so the faces
 * of any level are a prefix.  Levels are the step counts at which a whole
 * merge is complete. */
typedef struct {
    int n_input_vertices, n_vertices;
    double *pos;             /* 3 * n_vertices */
    int32_t *parent;         /* vertex -> the vertex it was merged into (-1: never) */
    int32_t *death;          /* step that merged it away (INT32_MAX: never) */
    int n_faces;
    int32_t *tri;            /* 3 * n_faces, input vertex ids, sorted by face_death desc */
    int32_t *face_death;
    int32_t *face_src;       /* index of the face in the input mesh */
    int n_levels;            /* level 0 = the input */
    int32_t *level_step;     /* steps done at each level */
    int32_t *level_faces;    /* faces at each level (non-increasing) */
    int32_t *level_vertices;
    /* Checkpoints, built when the record is made or loaded (not saved):
     * at checkpoint k, after ck_step[k] steps, the first ck_faces[k] faces'
     * corners as the vertices that stand for them then (mesh_record.c).
     * Checkpoint 0 is tri itself (step 0, all faces), checkpoint k > 0 is at
     * ck_tri + ck_off[k], and each has at most half the faces of the one
     * before.  n_checkpoints = 0 extracts from tri alone. */
    int n_checkpoints;
    int32_t ck_step[MESH_RECORD_CHECKPOINTS], ck_faces[MESH_RECORD_CHECKPOINTS];
    size_t ck_off[MESH_RECORD_CHECKPOINTS];
    int32_t *ck_tri;
    /* Extraction scratch (not thread-safe: one extraction at a time). */
    int32_t *scratch_map;    /* record vertex -> its number in the level */
    uint32_t *scratch_mstamp, stamp; /* scratch_map[v] is current when its stamp is */
} mesh_record_t;

/* Simplifies `in` (which must be edge-manifold); out (the mesh at the
 * target) and rec (all levels) may each be NULL. */
pp5_status_t mesh_simplify(const mesh_t *in, const mesh_simplify_opts_t *o, mesh_t *out,
                           mesh_record_t *rec, mesh_simplify_stats_t *stats);

/* The first level with at most `faces` faces (the last level if none). */
int mesh_record_level_for_faces(const mesh_record_t *r, int faces);
/* The mesh at `level`: vertices renumbered densely in order of first use. */
pp5_status_t mesh_record_extract(mesh_record_t *r, int level, mesh_t *out);
void mesh_record_free(mesh_record_t *r);
/* Little-endian binary file (magic, version, counts, arrays); the reader
 * validates every count and link before use. */
pp5_status_t mesh_record_save(const char *path, const mesh_record_t *r);
pp5_status_t mesh_record_load(const char *path, mesh_record_t *r);

#endif
