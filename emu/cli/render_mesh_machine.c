/* render_mesh_machine.c: `pp5 render --machine --mesh FILE | --scene FILE`:
 * a polygon frame through the emulated machine's polygon pipeline
 * (firmware/gp/poly_gp.c, firmware/ARCHITECTURE.md "Polygons"), its frame
 * report, and its agreement with the native polygon renderer's frame of the
 * same triangle list.  Gaze-directed (--mode gaze), the machine draws the
 * levels of detail into its variable-resolution Z-buffer
 * (firmware/gp/poly_vrz.c); with --compare it also runs full detail at full
 * resolution, each saving alone, and prints the savings table.
 *
 * Each object keeps its colour (poly_soup.h); the machine lights ambient +
 * diffuse only (no specular term). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "firmware/host/poly_report.h"
#include "firmware/host/poly_session.h"
#include "firmware/host/poly_soup.h"
#include "render/quality.h"
#include "render_cmd.h"

/* One frame of `list` on a new machine; vrz: into the variable-resolution
 * Z-buffer.  The session stays open for its report (caller frees). */
static pp5_status_t machine_frame(const render_cmd_t *c, const render_mesh_frame_t *f,
                                  const mesh_soup_t *list, bool vrz, poly_session_t *s,
                                  image8_t *img, poly_frame_result_t *r)
{
    memset(s, 0, sizeof *s);
    pp5_params_t p;
    pp5_status_t st = pp5_params_build(&c->params, &p);
    poly_tri_in_t *tris = NULL;
    if (st == PP5_OK)
        st = poly_triangles_from_soup(list, &tris);
    if (st != PP5_OK)
        return st;
    raster_style_t style;
    poly_options_t po;
    poly_style_from_render_opts(f->opts, list, &style, &po);
    po.gaze = vrz;
    po.level_tables = c->fw.level_tables;   /* --set level_tables=0: 2DLevel exactly */
    po.gaze_model = *f->gaze;
    po.gaze_x = f->gaze_x, po.gaze_y = f->gaze_y;
    st = poly_session_init(s, &p, tris, (size_t)list->n_tris, f->width, f->height, f->cam, &style,
                           &po);
    free(tris);
    if (st == PP5_OK)
        st = poly_session_frame(s, img, r);
    return st;
}

/* --compare: the four frames on the machine, the savings table. */
static pp5_status_t savings_table(const render_cmd_t *c, const render_mesh_frame_t *f, FILE *log)
{
    static const char *const what[4] = {"full detail, full res", "LOD, full res",
                                        "full detail, VRZ", "LOD + VRZ"};
    image8_t img[4] = {{0}};
    poly_frame_result_t r[4];
    pp5_status_t st = PP5_OK;
    for (int k = 0; k < 4 && st == PP5_OK; k++) {
        poly_session_t s;
        st = machine_frame(c, f, k & 1 ? f->lod : f->full, k >= 2, &s, &img[k], &r[k]);
        poly_session_free(&s);
    }
    if (st == PP5_OK) {
        fprintf(log, "on the emulated machine, against full detail at full resolution:\n");
        fprintf(log, "%-22s %10s %8s %11s %10s %9s %8s %9s  %s\n", "variant", "triangles",
                "regions", "PP pixels", "ring KB", "frame ms", "PSNR dB", "AW-PSNR", "bottleneck");
    }
    for (int k = 0; k < 4 && st == PP5_OK; k++) {
        quality_t q = {0};
        if (k > 0)
            st = quality_compare(&img[k], &img[0], f->gaze, f->gaze_x, f->gaze_y, &q);
        fprintf(log, "%-22s %10llu %8llu %11llu %10.1f %9.3f", what[k],
                (unsigned long long)r[k].tris_in, (unsigned long long)r[k].regions_drawn,
                (unsigned long long)r[k].regions_drawn * 16384ull,
                (double)r[k].ring_bytes_total / 1024.0, 1e3 * r[k].frame_time_s);
        if (k > 0)
            fprintf(log, " %8.2f %9.2f  %s\n", q.psnr_db, q.aw_psnr_db, r[k].bottleneck);
        else
            fprintf(log, " %8s %9s  %s\n", "-", "-", r[k].bottleneck);
    }
    if (st == PP5_OK)
        fprintf(log, "(PP pixels: the rasterised regions' pixels, all of which the SIMD array "
                "evaluates; frame ms: one frame alone, emulated)\n");
    for (int k = 0; k < 4; k++)
        image8_free(&img[k]);
    return st;
}

pp5_status_t render_mesh_machine(const render_cmd_t *c, const render_mesh_frame_t *f, FILE *log)
{
    bool vrz = f->gaze_directed;
    const mesh_soup_t *list = vrz ? f->lod : f->full;
    poly_session_t s;
    image8_t img = {0};
    poly_frame_result_t r;
    pp5_status_t st = machine_frame(c, f, list, vrz, &s, &img, &r);
    poly_compare_t cmp;
    if (st == PP5_OK)
        st = poly_compare_images(&img, f->native, f->opts->background, &cmp);
    if (st == PP5_OK) {
        poly_report_print(log, &s, &r);
        fprintf(log, "vs the native polygon renderer on the same %d triangles%s: PSNR %.2f dB, max "
                "diff %d, %ld of %ld covered pixels drawn by one image only\n", list->n_tris,
                vrz ? " (its variable-resolution Z-buffer)" : "", cmp.psnr_db, cmp.max_abs_diff,
                cmp.covered_one_only, cmp.covered_native);
        if (f->opts->specular > 0)
            fprintf(log, "  (the machine has no specular term: the native frame's highlights "
                    "differ)\n");
    }
    if (st == PP5_OK && c->out_png)
        st = png_write(c->out_png, &img);
    if (st == PP5_OK && c->report_json)
        st = poly_report_write(c->report_json, &s, &r, f->scene_name, &cmp);
    image8_free(&img);
    poly_session_free(&s);
    if (st == PP5_OK && vrz && c->compare)
        st = savings_table(c, f, log);
    return st;
}
