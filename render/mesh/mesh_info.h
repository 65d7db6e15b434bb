/* mesh_info.h: topology of a triangle mesh: edges, boundary loops,
 * manifoldness, orientation, components, Euler characteristic and genus
 * (`pp5 mesh info`, the simplifier tests and the bunny's hole filling). */
#ifndef PP5_MESH_INFO_H
#define PP5_MESH_INFO_H

#include <stdbool.h>
#include "mesh.h"

typedef struct {
    int n_vertices, n_used_vertices, n_faces, n_edges;
    int n_boundary_edges;
    int n_boundary_loops;
    int longest_loop, shortest_loop;  /* edges; 0 when closed */
    int n_nonmanifold_edges;          /* edges with more than two faces */
    int n_nonmanifold_vertices;       /* faces around the vertex form more than one fan */
    int n_misoriented_edges;          /* two faces traverse the edge the same way */
    int n_components;
    int euler;                        /* V (used) - E + F */
    bool manifold, orientable;        /* manifold: no bad edge or vertex */
    int genus;                        /* sum over components; -1 unless manifold+orientable */
} mesh_info_t;

pp5_status_t mesh_info(const mesh_t *m, mesh_info_t *info);

/* Boundary loops as vertex sequences: loop i is verts[start[i] .. start[i+1]),
 * ordered along the faces' orientation.  Needs a manifold boundary (every
 * boundary vertex on one boundary loop once), else PP5_E_FORMAT. */
typedef struct {
    int n_loops;
    int *start;      /* n_loops + 1 */
    int32_t *verts;
} mesh_loops_t;
pp5_status_t mesh_boundary_loops(const mesh_t *m, mesh_loops_t *loops);
void mesh_loops_free(mesh_loops_t *loops);

/* Edges as sorted half-edge groups (shared by info and the loop finder):
 * half-edge h = 3*face + corner goes from tri[h] to tri[face*3 + (corner+1)%3]. */
typedef struct {
    int n_half;
    int32_t *order;    /* half-edges sorted by undirected key (then by index) */
    int n_edges;
    int *edge_start;   /* n_edges + 1 offsets into order */
} mesh_edges_t;
pp5_status_t mesh_edges_build(const mesh_t *m, mesh_edges_t *e);
void mesh_edges_free(mesh_edges_t *e);

#endif
