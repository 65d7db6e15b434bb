/* render_mesh_machine.c: `pp5 render --machine --mesh FILE | --scene FILE`:
 * one frame of a polygon scene through the emulated machine's polygon
 * pipeline (firmware/gp/poly_gp.c, firmware/ARCHITECTURE.md "Polygons"),
 * its frame report, and its agreement with the native polygon renderer's
 * frame of the same triangle list.
 *
 * What the machine draws differs from the native frame in two known ways,
 * printed with the result: the pipeline's configuration carries one surface
 * colour for the frame (the first object's), where scenes colour each
 * object; and it has no variable-resolution Z-buffer, so a gaze-directed
 * frame on the machine is the levels of detail at full resolution. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "firmware/host/poly_report.h"
#include "firmware/host/poly_session.h"
#include "firmware/host/poly_soup.h"
#include "render_cmd.h"

pp5_status_t render_mesh_machine(const render_cmd_t *c, const char *scene_name,
                                 const mesh_soup_t *list, const raster_camera_t *cam,
                                 const mesh_render_opts_t *opts, const image8_t *native, FILE *log)
{
    pp5_params_t p;
    pp5_status_t st = pp5_params_build(&c->params, &p);
    poly_tri_in_t *tris = NULL;
    if (st == PP5_OK)
        st = poly_triangles_from_soup(list, &tris);
    if (st != PP5_OK)
        return st;
    raster_style_t style;
    poly_options_t po;
    poly_style_from_render_opts(opts, list, &style, &po);
    poly_session_t s;
    st = poly_session_init(&s, &p, tris, (size_t)list->n_tris, native->width, native->height,
                           cam, &style, &po);
    free(tris);
    if (st != PP5_OK)
        return st;
    image8_t img = {0};
    poly_frame_result_t r;
    st = poly_session_frame(&s, &img, &r);
    poly_compare_t cmp;
    if (st == PP5_OK)
        st = poly_compare_images(&img, native, opts->background, &cmp);
    if (st == PP5_OK) {
        poly_report_print(log, &s, &r);
        fprintf(log, "vs the native polygon renderer on the same %d triangles: PSNR %.2f dB, max "
                "diff %d, %ld of %ld covered pixels drawn by one image only\n",
                list->n_tris, cmp.psnr_db, cmp.max_abs_diff, cmp.covered_one_only,
                cmp.covered_native);
        fprintf(log, "  (the machine draws every object in the first object's colour; scenes "
                "with several colours differ there)\n");
    }
    if (st == PP5_OK && c->out_png)
        st = png_write(c->out_png, &img);
    if (st == PP5_OK && c->report_json)
        st = poly_report_write(c->report_json, &s, &r, scene_name, &cmp);
    image8_free(&img);
    poly_session_free(&s);
    return st;
}
