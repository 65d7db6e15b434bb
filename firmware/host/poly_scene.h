/* poly_scene.h: the throughput scene of `pp5 reproduce polygons`: independent triangles of one screen area at random places, orientations and depths, seen by an orthographic camera over the pixel grid.
 *
 * "100-pixel triangles" is the standard triangle of that era's polygon
 * benchmarks (issue 13): area in pixels, here equilateral, each at its own
 * random rotation, centre and depth; corner normals tilted at random so
 * Gouraud and Phong interpolate real variation.  Deterministic from the
 * seed (a 32-bit linear congruential generator, no host randomness). */
#ifndef PP5_POLY_SCENE_H
#define PP5_POLY_SCENE_H

#include <stddef.h>

#include "firmware/common/poly_config.h"
#include "render/mesh/mesh_raster.h"

/* n triangles of `area` pixels inside a width x height screen (*out: caller
 * frees), and the camera that maps world x, y to pixels. */
pp5_status_t poly_scene_triangles(size_t n, double area, int width, int height, unsigned seed,
                                  poly_tri_in_t **out, raster_camera_t *cam);

#endif
