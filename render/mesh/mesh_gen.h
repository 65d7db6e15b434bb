/* mesh_gen.h: meshes made in code for the tests, the demo and seed 003's
 * tables (which need no external data): UV spheres, tori, grids, cubes, and
 * the hole-filled Stanford bunny of seed 003's Table 3. */
#ifndef PP5_MESH_GEN_H
#define PP5_MESH_GEN_H

#include "mesh.h"

/* A UV sphere of `slices` meridians and `stacks` bands, pole fans at both
 * ends: 2 + slices*(stacks-1) vertices, 2*slices*(stacks-1) faces (20x20:
 * 382 vertices, 760 faces, seed 003 Table 2). */
pp5_status_t mesh_gen_uv_sphere(int slices, int stacks, double radius, mesh_t *m);
/* A torus, major radius R, tube radius r, nu x nv quads split in two. */
pp5_status_t mesh_gen_torus(int nu, int nv, double R, double r, mesh_t *m);
/* A flat nx x ny grid of quads over [0,sx] x [0,sy] at z = 0, diagonals
 * alternating (a rotationally varied triangulation). */
pp5_status_t mesh_gen_grid(int nx, int ny, double sx, double sy, mesh_t *m);
/* The cube [-1,1]^3, each face an n x n grid. */
pp5_status_t mesh_gen_cube(int n, mesh_t *m);
/* bun_zipper with its unused vertices dropped and its boundary loop of
 * `hole_edges` edges closed by a fan around one new vertex at the loop's
 * centroid (hole_edges = 22 gives seed 003's 69,473 faces, 34,835 vertices). */
pp5_status_t mesh_gen_fill_hole(mesh_t *m, int hole_edges);
/* gen:sphere (20x20 UV sphere, radius 1), gen:torus (48x24, R 1, r 0.35),
 * gen:grid (32x32 over the unit square), gen:cube (8x8 a side); any other
 * name is an error naming the choices. */
pp5_status_t mesh_gen_by_name(const char *name, mesh_t *m);

#endif
