/* mesh_raster.h: a small z-buffered triangle rasteriser, flat, Gouraud or
 * Phong shading under one directional light.
 *
 * It draws meshes into a viewport of an RGB image (so level images can sit
 * side by side) through a camera given as a view and a projection matrix.
 * The stages are the ones a native polygon renderer needs and are kept apart
 * so one can grow from them: vertex transform and lighting, clipping against
 * the near plane in homogeneous coordinates, viewport mapping, edge-function
 * rasterisation with the top-left fill rule (a shared edge's pixels belong
 * to exactly one of its triangles, so meshes are watertight), the depth
 * test, perspective-correct colour interpolation.  Everything is double
 * precision and single-threaded, so the same input gives the same pixels. */
#ifndef PP5_MESH_RASTER_H
#define PP5_MESH_RASTER_H

#include <stdbool.h>
#include <stdint.h>

#include "mesh.h"
#include "png_io.h"

/* RASTER_PHONG interpolates the camera-space vertex normal perspective-
 * correctly and lights every pixel with it (mesh_tri.h). */
typedef enum { RASTER_FLAT, RASTER_GOURAUD, RASTER_PHONG } raster_shading_t;

/* An RGB image with its depth buffer (depth = z/w in [-1, 1], smaller is
 * nearer; +infinity where nothing was drawn). */
typedef struct {
    image8_t image;
    double *depth;
} mesh_raster_t;

/* camera = view x (x, y, z, 1) (right-handed, looking down -z), clip =
 * proj x camera; both row-major.  The light is given in camera coordinates,
 * so the shading looks the same from every side. */
typedef struct {
    double view[16], proj[16];
} raster_camera_t;

typedef struct {
    raster_shading_t shading;
    double light_dir[3];       /* toward the light, camera coordinates (normalised when used) */
    double ambient, diffuse;   /* intensity = ambient + diffuse max(0, n.l) */
    uint8_t front_rgb[3];      /* surface colour of faces seen from the front */
    uint8_t back_rgb[3];       /* ... and from behind (the inside, through holes) */
    /* Phong only: a white highlight specular max(0, r.v)^shininess, r the
     * light reflected about the pixel's normal, v = +z (a viewer at infinity,
     * so the highlight needs no per-pixel position); added while n.l > 0.
     * raster_style_default sets specular = 0 (no highlight), shininess = 32. */
    double specular, shininess;
} raster_style_t;

/* A rectangle of the image: x0, y0 (top-left pixel), width, height. */
typedef struct {
    int x0, y0, width, height;
} raster_viewport_t;

pp5_status_t mesh_raster_init(mesh_raster_t *r, int width, int height);
void mesh_raster_free(mesh_raster_t *r);
/* Fills the viewport (clipped to the image) with a colour and empties its depth. */
void mesh_raster_clear(mesh_raster_t *r, const raster_viewport_t *vp, const uint8_t rgb[3]);

/* A camera that looks at the mesh's bounding sphere from `yaw_deg` about the
 * y axis (0: from +z) and `pitch_deg` above the horizon, filling a viewport
 * of the given aspect (width / height); perspective with a 30 degree field
 * of view, or orthographic. */
void raster_camera_fit(const mesh_t *m, double yaw_deg, double pitch_deg, double aspect,
                       bool perspective, raster_camera_t *cam);
/* An orthographic camera looking down -z (view = identity) at the box
 * [x0,x1] x [y0,y1], depths z from -z_near to -z_far. */
void raster_camera_ortho(double x0, double x1, double y0, double y1, double z_near,
                         double z_far, raster_camera_t *cam);
/* A perspective camera looking down -z (view = identity): vertical field of
 * view fovy_deg, aspect width / height, near and far distances. */
void raster_camera_perspective(double fovy_deg, double aspect, double z_near, double z_far,
                               raster_camera_t *cam);

/* Light from the upper left, in front of the camera; grey faces, darker backs. */
void raster_style_default(raster_style_t *s, raster_shading_t shading);
/* Swaps the two colours when m's faces point inward (negative signed volume,
 * as bun_zipper's do), so the outside is always drawn grey. */
void raster_style_orient(raster_style_t *s, const mesh_t *m);

/* Draws every face of m into the viewport.  Faces are two-sided: a face seen
 * from behind is lit with its normal reversed and given back_rgb.  Errors:
 * an invalid mesh or viewport. */
pp5_status_t mesh_raster_draw(mesh_raster_t *r, const raster_viewport_t *vp, const mesh_t *m,
                              const raster_camera_t *cam, const raster_style_t *style);

#endif
