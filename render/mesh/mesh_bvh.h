/* mesh_bvh.h: an axis-aligned bounding-box tree over a mesh's triangles for
 * exact nearest-point queries (the Hausdorff distance's spatial index). */
#ifndef PP5_MESH_BVH_H
#define PP5_MESH_BVH_H

#include "mesh.h"

typedef struct {
    float lo[3], hi[3];
    int32_t first, count;    /* leaf: triangles order[first..first+count); inner: count = 0,
                                children first and first + 1 */
} mesh_bvh_node_t;

typedef struct {
    const mesh_t *mesh;
    mesh_bvh_node_t *nodes;
    int n_nodes;
    int32_t *order;          /* triangle ids in leaf order */
    double *tri_pos;         /* 9 doubles per triangle, in leaf order */
} mesh_bvh_t;

pp5_status_t mesh_bvh_build(const mesh_t *m, mesh_bvh_t *b);
void mesh_bvh_free(mesh_bvh_t *b);
/* Squared distance from p to the nearest point of the mesh; *hint (a leaf
 * slot, or -1) warms the search with a previous answer and receives this one. */
double mesh_bvh_nearest_sq(const mesh_bvh_t *b, const double p[3], int *hint);
/* Squared distance from p to triangle (a, b, c) (Ericson, Real-Time
 * Collision Detection §5.1.5: closest point by Voronoi region). */
double point_triangle_dist_sq(const double p[3], const double *a, const double *b,
                              const double *c);

#endif
