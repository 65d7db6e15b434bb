/* poly_soup.h: a flattened polygon scene (render/mesh/mesh_scene.h's
 * triangle list and the native renderer's light and colours) in the form
 * the machine's polygon pipeline takes (poly_session.h).
 *
 * Each triangle carries its object's colour (poly_tri_in_t.rgb; Phong
 * shades it per pixel), so a scene's objects keep their own colours; the
 * configuration's front and back colours (the first object's, grey for an
 * empty list) serve triangles without one.  Not carried: mesh_render's
 * specular term (the pipeline lights ambient + diffuse). */
#ifndef PP5_POLY_SOUP_H
#define PP5_POLY_SOUP_H

#include "firmware/host/poly_session.h"
#include "render/mesh/mesh_render.h"

/* The list's triangles, corner by corner (*out: caller frees; at least one
 * element is allocated so an empty list is not NULL). */
pp5_status_t poly_triangles_from_soup(const mesh_soup_t *s, poly_tri_in_t **out);
/* The native frame's light, colours, shading, culling and background as the
 * pipeline's style and options. */
void poly_style_from_render_opts(const mesh_render_opts_t *o, const mesh_soup_t *s,
                                 raster_style_t *st, poly_options_t *po);

#endif
