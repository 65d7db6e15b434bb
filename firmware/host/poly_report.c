/* poly_report.c: the polygon frame report (poly_report.h). */
#include "poly_report.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"
#include "outfile.h"
#include "stats.h"

pp5_status_t poly_compare_images(const image8_t *machine, const image8_t *native,
                                 const uint8_t background[3], poly_compare_t *out)
{
    memset(out, 0, sizeof *out);
    if (machine->width != native->width || machine->height != native->height ||
        machine->channels != 3 || native->channels != 3)
        return pp5_fail(PP5_E_RANGE, "polygons: images of %dx%d and %dx%d cannot be compared",
                        machine->width, machine->height, native->width, native->height);
    double se = 0;
    size_t n = (size_t)machine->width * (size_t)machine->height;
    for (size_t i = 0; i < n; i++) {
        const uint8_t *a = machine->pixels + 3 * i, *b = native->pixels + 3 * i;
        bool ca = memcmp(a, background, 3) != 0, cb = memcmp(b, background, 3) != 0;
        out->covered_native += cb;
        out->covered_one_only += ca != cb;
        for (int k = 0; k < 3; k++) {
            int d = abs(a[k] - b[k]);
            out->max_abs_diff = d > out->max_abs_diff ? d : out->max_abs_diff;
            se += (double)d * d;
        }
    }
    out->psnr_db = se > 0 ? 10 * log10(255.0 * 255.0 * 3.0 * (double)n / se) : INFINITY;
    out->have = true;
    return PP5_OK;
}

void poly_report_print(FILE *log, const poly_session_t *s, const poly_frame_result_t *r)
{
    double gp_hz = s->params.gp_clock_hz, rn_hz = s->params.renderer_clock_hz;
    fprintf(log, "machine frame: %.3f ms alone; pipelined frames: %.0f triangles/s, bottleneck %s\n",
            1e3 * r->frame_time_s, r->tris_per_s_pipelined, r->bottleneck);
    fprintf(log, "  triangles: %llu in, %llu set up (clipped, culled), %llu (triangle, region) pairs "
            "binned, %llu sent with %llu edge expressions\n", (unsigned long long)r->tris_in,
            (unsigned long long)r->tris_setup, (unsigned long long)r->pairs_binned,
            (unsigned long long)r->pairs_sent, (unsigned long long)r->edges_sent);
    fprintf(log, "  GP transform and sort   %10.3f ms (busiest GP; %.0f cycles per input triangle "
            "over all GPs)\n", 1e3 * r->gp_transform_sort_s_max,
            r->tris_in ? (double)(r->cycles_transform + r->cycles_sort) / (double)r->tris_in : 0);
    fprintf(log, "  GP region streams       %10.3f ms (busiest GP; %.0f cycles per pair)\n",
            1e3 * r->gp_encode_s_max,
            r->pairs_sent ? (double)r->cycles_encode / (double)r->pairs_sent : 0);
    fprintf(log, "  GP busy                 %10.3f ms max, %.3f ms mean (clock %.0f MHz)\n",
            1e3 * r->gp_busy_s_max, 1e3 * r->gp_busy_s_mean, gp_hz / 1e6);
    fprintf(log, "  ring command bytes      %10llu (%llu stream words), GP tokens %llu bytes\n",
            (unsigned long long)r->ring_bytes[RING_CLASS_COMMAND], (unsigned long long)r->stream_words,
            (unsigned long long)r->ring_bytes[RING_CLASS_GP]);
    fprintf(log, "  PP rasterisation        %10.3f ms busiest renderer (%llu cycles; %llu over all, "
            "%.0f per pair)\n", 1e3 * (double)r->rn_exec_cycles_max / rn_hz,
            (unsigned long long)r->rn_exec_cycles_max, (unsigned long long)r->rn_exec_cycles_total,
            r->pairs_sent ? (double)r->rn_exec_cycles_total / (double)r->pairs_sent : 0);
    fprintf(log, "  region transfer         %10llu pixel bytes, %.3f ms of channel time\n",
            (unsigned long long)r->ring_bytes[RING_CLASS_PIXELS], 1e3 * r->ring_class_busy_s[RING_CLASS_PIXELS]);
    if (s->cfg.gaze)
        fprintf(log, "  variable-resolution Z  %llu level tiles drawn (%llu PP pixels), %llu texels "
                "to the GPs (%llu bytes), planning %.3f ms and resampling %.3f ms (GP cycles over "
                "all GPs / GPs)\n", (unsigned long long)r->regions_drawn,
                (unsigned long long)r->regions_drawn * 16384ull, (unsigned long long)r->texels_in,
                (unsigned long long)r->ring_bytes[RING_CLASS_DATA],
                1e3 * (double)r->cycles_levels / gp_hz / s->m.n_gp,
                1e3 * (double)r->cycles_resample / gp_hz / s->m.n_gp);
    for (int k = 0; k < POLY_STAGE_COUNT; k++)
        fprintf(log, "  stage %-38s %9.3f ms\n", poly_stage_name((poly_stage_t)k), 1e3 * r->stage_s[k]);
}

static void write_result(json_writer_t *j, const poly_session_t *s, const poly_frame_result_t *r)
{
    json_kv_double(j, "frame_time_s", r->frame_time_s);
    json_kv_string(j, "bottleneck", r->bottleneck);
    json_kv_double(j, "triangles_per_s_pipelined", r->tris_per_s_pipelined);
    json_kv_double(j, "triangles_per_s_single_frame", r->tris_per_s_frame);
    json_key(j, "stages_s");
    json_begin_object(j);
    json_kv_double(j, "gp_busiest", r->stage_s[POLY_STAGE_GP]);
    json_kv_double(j, "renderer_busiest", r->stage_s[POLY_STAGE_RENDERER]);
    json_kv_double(j, "ring_channel_time_per_channel", r->stage_s[POLY_STAGE_RING]);
    json_kv_double(j, "renderer_port_busiest", r->stage_s[POLY_STAGE_RN_PORT]);
    json_end_object(j);
    json_key(j, "gp");
    json_begin_object(j);
    json_kv_uint(j, "triangles_in", r->tris_in);
    json_kv_uint(j, "triangles_set_up", r->tris_setup);
    json_kv_uint(j, "pairs_binned", r->pairs_binned);
    json_kv_uint(j, "pairs_sent", r->pairs_sent);
    json_kv_uint(j, "edges_sent", r->edges_sent);
    json_kv_uint(j, "cycles_transform", r->cycles_transform);
    json_kv_uint(j, "cycles_sort", r->cycles_sort);
    json_kv_uint(j, "cycles_encode", r->cycles_encode);
    json_kv_uint(j, "cycles_levels", r->cycles_levels);
    json_kv_uint(j, "cycles_resample", r->cycles_resample);
    json_kv_uint(j, "regions_drawn", r->regions_drawn);
    json_kv_uint(j, "texels_in", r->texels_in);
    json_kv_double(j, "transform_and_sort_s_busiest", r->gp_transform_sort_s_max);
    json_kv_double(j, "encode_s_busiest", r->gp_encode_s_max);
    json_kv_double(j, "sorted_by_s", r->gp_sorted_s_max);
    json_kv_double(j, "busy_s_max", r->gp_busy_s_max);
    json_kv_double(j, "busy_s_mean", r->gp_busy_s_mean);
    json_end_object(j);
    json_key(j, "renderers");
    json_begin_object(j);
    json_kv_uint(j, "rasterisation_cycles_total", r->rn_exec_cycles_total);
    json_kv_uint(j, "rasterisation_cycles_busiest", r->rn_exec_cycles_max);
    json_kv_uint(j, "port_cycles_total", r->rn_port_cycles_total);
    json_kv_uint(j, "region_streams", r->regions);
    json_kv_double(j, "busy_s_max", r->rn_busy_s_max);
    json_kv_double(j, "busy_s_mean", r->rn_busy_s_mean);
    json_end_object(j);
    json_key(j, "ring");
    json_begin_object(j);
    json_kv_uint(j, "bytes_total", r->ring_bytes_total);
    json_kv_uint(j, "command_bytes", r->ring_bytes[RING_CLASS_COMMAND]);
    json_kv_uint(j, "stream_words", r->stream_words);
    json_kv_uint(j, "region_transfer_bytes", r->ring_bytes[RING_CLASS_PIXELS]);
    json_kv_uint(j, "gp_token_bytes", r->ring_bytes[RING_CLASS_GP]);
    json_key(j, "channel_time_s_by_class");
    json_begin_object(j);
    for (unsigned k = 0; k < RING_CLASS_COUNT; k++)
        json_kv_double(j, stats_class_name(k), r->ring_class_busy_s[k]);
    json_end_object(j);
    json_kv_double(j, "utilization", r->ring_util_total);
    json_end_object(j);
    (void)s;
}

pp5_status_t poly_report_write(const char *path, const poly_session_t *s, const poly_frame_result_t *r,
                               const char *scene_name, const poly_compare_t *cmp)
{
    outfile_t o;
    pp5_status_t st = outfile_open(&o, path, false);
    if (st != PP5_OK)
        return st;
    json_writer_t j;
    json_init(&j, o.f, true);
    json_begin_object(&j);
    json_kv_string(&j, "workload", "polygons (firmware/gp/poly_gp.c)");
    json_kv_string(&j, "scene", scene_name ? scene_name : "");
    json_kv_string(&j, "shading", poly_shading_name((poly_shading_t)s->cfg.shading));
    json_kv_bool(&j, "cull_back", s->cfg.cull_back != 0);
    json_kv_string(&j, "z_buffer", s->cfg.gaze ? "variable resolution" : "full resolution");
    if (s->cfg.gaze) {
        json_kv_double(&j, "gaze_x", s->cfg.gaze_x);
        json_kv_double(&j, "gaze_y", s->cfg.gaze_y);
        json_kv_int(&j, "levels2d", s->cfg.levels2d);
    }
    json_kv_uint(&j, "triangles", s->n_tris);
    json_kv_int(&j, "width", s->cfg.width);
    json_kv_int(&j, "height", s->cfg.height);
    json_kv_double(&j, "load_time_s", s->load_s);
    json_key(&j, "frame");
    json_begin_object(&j);
    write_result(&j, s, r);
    json_end_object(&j);
    if (cmp && cmp->have) {
        json_key(&j, "image_vs_mesh_raster");
        json_begin_object(&j);
        json_kv_double(&j, "psnr_db", isfinite(cmp->psnr_db) ? cmp->psnr_db : 999.0);
        json_kv_int(&j, "max_abs_diff", cmp->max_abs_diff);
        json_kv_int(&j, "pixels_covered_native", cmp->covered_native);
        json_kv_int(&j, "pixels_covered_by_one_only", cmp->covered_one_only);
        json_end_object(&j);
    }
    json_key(&j, "machine");
    pp5_params_write_json(&s->params, &j);
    json_end_object(&j);
    fputc('\n', o.f);
    return outfile_commit(&o);
}
