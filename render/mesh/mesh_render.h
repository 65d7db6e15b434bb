/* mesh_render.h: the native polygon renderer: a world-space triangle list
 * (mesh_scene_flatten) through one camera into an RGB image, flat, Gouraud
 * or Phong, into a full-resolution Z-buffer or into the gaze paper's
 * variable-resolution Z-buffer (seed 004 §7).
 *
 * Pipeline, per triangle: transform to clip space; clip against the near
 * plane (Sutherland-Hodgman, attributes interpolated in clip space);
 * project; back faces dropped when opts.cull_back, otherwise lit with the
 * normal reversed (two-sided, as mesh_raster.h); lighting per face (flat),
 * per vertex (Gouraud) or per sample from the perspective-correct normal
 * (Phong); rasterise with the top-left rule (mesh_tri.h) and Z-compare.
 * Shading is deferred: a sample keeps the attributes of its nearest
 * fragment and is shaded once after the last triangle, so "pixels shaded"
 * counts visible samples, and "fragments" counts the samples scan-converted
 * and Z-compared (the cost the paper's §7 wants to cut).
 *
 * The light is one directional light plus ambient with an optional white
 * highlight: I = colour (ambient + diffuse max(0, n.l)) + specular
 * max(0, r.v)^shininess, r = 2 (n.l) n - l, v = +z (viewer at infinity).
 *
 * Variable-resolution Z-buffer (mesh_render_vrz): the 2D mip map of the
 * volume renderer (gaze2d.h) with a depth and the attributes per texel.
 * 2DLevel per pixel marks the texels the image needs (mip2d_mark_row); each
 * triangle is sampled only at those texels, level by level, its scanlines
 * cut into the runs of populated texels (a segment never crosses a level's
 * boundary); after shading, the image is resampled from the partially
 * populated mip map exactly as the volume renderer does (mip2d_render_row).
 * A pixel whose 2DLevel is 0 reads its own level-0 texel only, so it equals
 * the full-resolution render there (tested). */
#ifndef PP5_MESH_RENDER_H
#define PP5_MESH_RENDER_H

#include <stdbool.h>
#include <stdint.h>

#include "render/gaze2d.h"
#include "mesh_raster.h"
#include "mesh_scene.h"
#include "mesh_tri.h"
#include "png_io.h"

typedef struct {
    raster_shading_t shading;
    double light_dir[3];       /* toward the light, camera coordinates */
    double ambient, diffuse, specular, shininess;
    uint8_t background[3];
    bool cull_back;
} mesh_render_opts_t;

typedef struct {
    uint64_t triangles_in;     /* in the list */
    uint64_t triangles_drawn;  /* reached the rasteriser (not culled, clipped away or degenerate) */
    uint64_t fragments;        /* samples covered: scan-converted and Z-compared */
    uint64_t pixels_shaded;    /* visible samples, each shaded once */
    uint64_t samples;          /* samples in the Z-buffer (pixels, or populated texels) */
    double ms;                 /* host wall time of the render */
    double cpu_ms;             /* its thread CPU time (steadier on a shared host) */
    double cpu_ms_triangles;   /* of which: transform, set-up, scan conversion, Z */

} mesh_render_stats_t;

/* The scene's light and colours, the light turned into the camera's frame. */
void mesh_render_opts_from_scene(const mesh_scene_t *s, const raster_camera_t *cam,
                                 raster_shading_t shading, mesh_render_opts_t *o);

/* Renders into img (allocated here: width x height, RGB). */
pp5_status_t mesh_render_full(const mesh_soup_t *soup, const raster_camera_t *cam,
                              const mesh_render_opts_t *o, int width, int height, image8_t *img,
                              mesh_render_stats_t *st);
/* The same through the variable-resolution Z-buffer for a gaze at pixel
 * (gaze_x, gaze_y) under the acuity model g (its width and height are the
 * image's). */
pp5_status_t mesh_render_vrz(const mesh_soup_t *soup, const raster_camera_t *cam,
                             const mesh_render_opts_t *o, const gaze_model_t *g, double gaze_x,
                             double gaze_y, image8_t *img, mesh_render_stats_t *st);

/* ---- shared by mesh_render.c and mesh_render_vrz.c ---- */

/* Attributes per sample: flat and Gouraud keep the lit colour (3), Phong the
 * normal and the colour (6). */
static inline int mesh_render_attrs(raster_shading_t s)
{
    return s == RASTER_PHONG ? 6 : 3;
}
/* Where the triangles go: called with each set-up screen triangle. */
typedef void (*mesh_render_sink_fn)(void *ctx, const tri_setup_t *t);
/* Transforms, clips, culls, lights and sets up every triangle of the list for
 * a width x height image, handing each to sink. */
void mesh_render_triangles(const mesh_soup_t *soup, const raster_camera_t *cam,
                           const mesh_render_opts_t *o, int width, int height,
                           mesh_render_sink_fn sink, void *ctx, mesh_render_stats_t *st);
/* The 8-bit colour of a sample from its attributes. */
void mesh_render_shade(const mesh_render_opts_t *o, const float *attrs, uint8_t rgb[3]);
double mesh_render_now_ms(void);
double mesh_render_cpu_ms(void);   /* this thread's CPU time */

#endif
