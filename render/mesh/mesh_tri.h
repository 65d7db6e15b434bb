/* mesh_tri.h: one screen-space triangle set up for sampling on any grid:
 * edge functions with the top-left fill rule, depth, and perspective-correct
 * interpolation of any number of per-vertex attributes.
 *
 * The polygon renderer (mesh_render.h) samples a triangle at pixel centres
 * (x + 0.5, y + 0.5) for the full-resolution Z-buffer and at the texel
 * points (i 2^m + 0.5, j 2^m + 0.5) of level m of the variable-resolution
 * Z-buffer (gaze paper §7, seed 004); both ask tri_cover at a point.  The
 * edge function is the same expression as mesh_raster.c's, so a point's
 * coverage does not depend on which grid asks.
 *
 * Perspective-correct interpolation: screen-space barycentrics b are affine
 * in x and y, but an attribute a is affine in camera space, so
 *     a(x, y) = sum b_k a_k / w_k  /  sum b_k / w_k
 * (a / w and 1 / w are affine on the screen; w = the clip w = camera depth). */
#ifndef PP5_MESH_TRI_H
#define PP5_MESH_TRI_H

#include <stdbool.h>

#define TRI_MAX_ATTRS 8

/* A projected vertex: screen x, y (pixels, y down), z = z/w (depth, smaller
 * is nearer), inv_w = 1/w, and its attributes (not divided by w). */
typedef struct {
    double x, y, z, inv_w;
    double attr[TRI_MAX_ATTRS];
} tri_vertex_t;

typedef struct tri_setup_s {
    tri_vertex_t v[3];
    int n_attrs;
    double sign;        /* makes the edge functions positive inside */
    double inv_area;    /* 1 / |twice the signed area| */
    bool own[3];        /* the edge opposite vertex k owns the points exactly on it */
    bool front;         /* counter-clockwise on the screen with y up */
    double xmin, xmax, ymin, ymax;
} tri_setup_t;

/* Sets up the triangle a, b, c with n_attrs attributes; false when its area
 * is zero or not finite (nothing to draw). */
bool tri_setup(tri_setup_t *t, const tri_vertex_t *a, const tri_vertex_t *b,
               const tri_vertex_t *c, int n_attrs);
/* Is (px, py) inside (top-left rule on the edges)?  If so, b receives the
 * screen-space barycentrics of the three vertices. */
bool tri_cover(const tri_setup_t *t, double px, double py, double b[3]);
/* Depth (z/w, affine on the screen) at barycentrics b. */
double tri_depth(const tri_setup_t *t, const double b[3]);
/* The perspective-correct attributes at barycentrics b (t->n_attrs values). */
void tri_attrs(const tri_setup_t *t, const double b[3], double *out);
/* Perspective-correct interpolation of n attributes given per vertex (attr[k]
 * points to vertex k's n values) with 1/w per vertex: out = sum b_k a_k inv_w_k
 * / sum b_k inv_w_k. */
void tri_interp_perspective(const double b[3], const double inv_w[3], const double *const attr[3],
                            int n, double *out);

#endif
