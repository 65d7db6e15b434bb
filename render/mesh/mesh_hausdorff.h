/* mesh_hausdorff.h: symmetric Hausdorff and mean distance between two meshes,
 * reported (by the callers) as % of the first mesh's bounding-box diagonal,
 * the Metro convention (Cignoni, Rocchini, Scopigno 1998).
 *
 * The maximum is bounded, not just sampled: every vertex is measured, and
 * each triangle is refined (split in four) while the largest distance it
 * could still hide, bounded through the 1-Lipschitz distance function,
 * exceeds the best found by more than the error bound.  The mean comes from
 * dense area-uniform samples (deterministic, fixed seed).  Distances to the
 * other mesh are exact, through its bounding-box tree (mesh_bvh.h). */
#ifndef PP5_MESH_HAUSDORFF_H
#define PP5_MESH_HAUSDORFF_H

#include "mesh.h"

typedef struct {
    double bound_rel;     /* wanted error bound on each maximum, x A's diagonal (1e-5) */
    long mean_samples;    /* area-uniform samples per direction (default 200,000) */
    long max_cells;       /* refinement budget per direction (default 4,000,000); when it
                             runs out, bound_* says how far the maximum may still be */
} mesh_distance_opts_t;

typedef struct {
    double h_ab, h_ba, hausdorff;  /* max over A of the distance to B, the reverse, their max */
    double mean_ab, mean_ba;       /* area-weighted mean distances */
    double bound_ab, bound_ba;     /* the true maximum is within this above h (absolute) */
    double diagonal;               /* bounding-box diagonal of A */
    long cells_ab, cells_ba;       /* triangles examined by the refinement */
} mesh_distance_t;

void mesh_distance_defaults(mesh_distance_opts_t *o);
pp5_status_t mesh_distance(const mesh_t *a, const mesh_t *b, const mesh_distance_opts_t *o,
                           mesh_distance_t *d);

#endif
