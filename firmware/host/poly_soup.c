/* poly_soup.c: a flattened scene as the polygon pipeline's input (poly_soup.h). */
#include "poly_soup.h"

#include <stdlib.h>
#include <string.h>

pp5_status_t poly_triangles_from_soup(const mesh_soup_t *s, poly_tri_in_t **out)
{
    *out = calloc(s->n_tris > 0 ? (size_t)s->n_tris : 1, sizeof **out);
    if (!*out)
        return pp5_fail(PP5_E_NOMEM, "polygons: out of memory for %d triangles", s->n_tris);
    for (int t = 0; t < s->n_tris; t++)
        for (int k = 0; k < 3; k++)
            for (int d = 0; d < 3; d++) {
                (*out)[t].p[k][d] = (float)s->pos[9 * t + 3 * k + d];
                (*out)[t].n[k][d] = (float)s->nrm[9 * t + 3 * k + d];
            }
    /* the object's colour (the first corner's: a scene colours objects) */
    for (int t = 0; t < s->n_tris; t++) {
        uint32_t rgb = POLY_RGB_OWN;
        for (int k = 0; k < 3; k++)
            rgb |= (uint32_t)(255.0 * s->rgb[9 * t + k] + 0.5) << (8 * k);
        (*out)[t].rgb = rgb;
    }
    return PP5_OK;
}

void poly_style_from_render_opts(const mesh_render_opts_t *o, const mesh_soup_t *s,
                                 raster_style_t *st, poly_options_t *po)
{
    raster_style_default(st, o->shading);
    for (int k = 0; k < 3; k++) {
        st->light_dir[k] = o->light_dir[k];
        st->front_rgb[k] = st->back_rgb[k] =
            (uint8_t)(s->n_tris > 0 ? 255.0 * s->rgb[k] + 0.5 : 200);
    }
    st->ambient = o->ambient;
    st->diffuse = o->diffuse;
    poly_options_default(po);
    po->shading = o->shading == RASTER_PHONG ? POLY_PHONG
                  : o->shading == RASTER_GOURAUD ? POLY_GOURAUD : POLY_FLAT;
    po->cull_back = o->cull_back;
    po->colour_per_pixel = true;
    memcpy(po->background, o->background, 3);
}
