/* fw_report.c: the machine render's JSON report (fw_report.h). */
#include "fw_report.h"

#include <math.h>
#include <stdio.h>

#include "json.h"
#include "outfile.h"
#include "stats.h"

static void write_class_bytes(json_writer_t *j, const char *key, const fw_frame_result_t *r)
{
    json_key(j, key);
    json_begin_object(j);
    for (unsigned k = 0; k < RING_CLASS_COUNT; k++)
        json_kv_uint(j, stats_class_name(k), r->ring_bytes[k]);
    json_end_object(j);
}

static void write_gp(json_writer_t *j, const fw_gp_frame_t *p, unsigned g)
{
    json_begin_object(j);
    json_kv_int(j, "index", g);
    json_kv_int(j, "band_y0", p->band_y0);
    json_kv_int(j, "band_y1", p->band_y1);
    json_kv_uint(j, "rays", p->rays);
    json_kv_uint(j, "samples_3d", p->samples);
    json_kv_uint(j, "bricks_fetched", p->bricks_fetched);
    json_kv_uint(j, "cycles_prep", p->cycles_prep);
    json_kv_uint(j, "cycles_pp_stream_build", p->cycles_pp_stream_build);
    json_kv_uint(j, "cycles_forward", p->cycles_forward);
    json_kv_uint(j, "cycles_receive", p->cycles_receive);
    json_kv_uint(j, "cycles_shade", p->cycles_shade);
    json_kv_uint(j, "cycles_cast", p->cycles_cast);
    json_kv_uint(j, "cycles_resample", p->cycles_resample);
    json_kv_double(j, "busy_s", p->busy_s);
    json_kv_double(j, "done_s", p->done_s);
    json_kv_uint(j, "mem_peak_bytes", p->mem_peak_bytes);
    json_end_object(j);
}

static void write_frame(json_writer_t *j, const fw_session_t *s, const fw_frame_result_t *r)
{
    json_kv_double(j, "frame_time_s", r->frame_time_s);
    json_kv_double(j, "frames_per_s", r->frame_time_s > 0 ? 1.0 / r->frame_time_s : 0);
    json_kv_string(j, "bottleneck", r->bottleneck);
    json_kv_int(j, "critical_gp", r->critical_gp);
    json_key(j, "phases_s");
    json_begin_object(j);
    for (int k = 0; k < FW_PHASE_COUNT; k++)
        json_kv_double(j, fw_phase_name((fw_phase_t)k), r->phase_s[k]);
    json_end_object(j);
    json_kv_uint(j, "rays", r->rays);
    json_kv_uint(j, "samples_3d", r->samples);
    json_kv_uint(j, "samples_skipped_by_octree", r->samples_skipped);
    json_kv_uint(j, "bricks_fetched", r->bricks_fetched);
    json_kv_uint(j, "brick_bytes_fetched", r->bytes_fetched);
    json_kv_uint(j, "pp_stream_words", r->pp_stream_words);
    json_kv_uint(j, "column_passes_max", r->passes_max);
    if (s->cfg.blend != VR_BLEND_COMPOSITE) {
        json_kv_uint(j, "demip_ray2_samples", r->ray2_samples);
        json_kv_uint(j, "mip_rays_saturated", r->rays_saturated);
        json_kv_uint(j, "demip_rays_occluded", r->rays_occluded);
        json_kv_uint(j, "mida_rays_terminated", r->rays_terminated);
    }
    json_kv_uint(j, "renderer_exec_cycles_max", r->rn_exec_cycles_max);
    json_kv_uint(j, "ring_bytes", r->ring_bytes_total);
    write_class_bytes(j, "ring_bytes_by_class", r);
    json_key(j, "ring_utilization_by_class");
    json_begin_object(j);
    for (unsigned k = 0; k < RING_CLASS_COUNT; k++)
        json_kv_double(j, stats_class_name(k), r->ring_util[k]);
    json_end_object(j);
    json_kv_double(j, "ring_utilization", r->ring_util_total);
    json_kv_double(j, "gp_utilization_mean", r->gp_util_mean);
    json_kv_double(j, "gp_utilization_max", r->gp_util_max);
    json_kv_double(j, "gp_imbalance_max_over_mean", r->gp_imbalance);
    json_kv_double(j, "renderer_utilization_mean", r->rn_util_mean);
    json_kv_double(j, "renderer_utilization_max", r->rn_util_max);
    json_key(j, "gp");
    json_begin_array(j);
    for (unsigned g = 0; g < s->m.n_gp; g++)
        write_gp(j, &s->last_gp[g], g);
    json_end_array(j);
}

/* Every frame of the sequence, one line each: time and ring traffic. */
static void write_frames(json_writer_t *j, const fw_frame_record_t *frames, int n)
{
    json_key(j, "frames");
    json_begin_array(j);
    for (int i = 0; i < n; i++) {
        const fw_frame_result_t *r = &frames[i].result;
        json_begin_object(j);
        json_kv_int(j, "index", i);
        json_kv_double(j, "gaze_x", frames[i].gaze_x);
        json_kv_double(j, "gaze_y", frames[i].gaze_y);
        json_kv_double(j, "frame_time_s", r->frame_time_s);
        json_kv_string(j, "bottleneck", r->bottleneck);
        json_kv_uint(j, "ring_bytes", r->ring_bytes_total);
        write_class_bytes(j, "ring_bytes_by_class", r);
        json_kv_uint(j, "bricks_fetched", r->bricks_fetched);
        json_kv_uint(j, "rays", r->rays);
        json_kv_uint(j, "samples_3d", r->samples);
        json_end_object(j);
    }
    json_end_array(j);
}

static void write_compare(json_writer_t *j, const fw_compare_t *cmp, const fw_frame_result_t *r)
{
    json_key(j, "image_vs_native");
    json_begin_object(j);
    json_kv_double(j, "psnr_db", isfinite(cmp->psnr_native_db) ? cmp->psnr_native_db : 999.0);
    json_kv_double(j, "max_abs_diff", cmp->max_diff_native);
    json_kv_double(j, "psnr_like_for_like_db", isfinite(cmp->psnr_like_db) ? cmp->psnr_like_db : 999.0);
    json_kv_double(j, "max_abs_diff_like_for_like", cmp->max_diff_like);
    json_kv_uint(j, "native_rays", cmp->native_rays);
    json_kv_uint(j, "native_samples_3d", cmp->native_samples);
    json_kv_uint(j, "machine_rays", r->rays);
    json_kv_uint(j, "machine_samples_3d", r->samples);
    json_end_object(j);
}

pp5_status_t fw_report_write(const char *path, const fw_session_t *s, const fw_frame_record_t *frames,
                             int n_frames, const char *volume_name, const fw_compare_t *cmp)
{
    outfile_t o;
    pp5_status_t st = outfile_open(&o, path, false);
    if (st != PP5_OK)
        return st;
    FILE *f = o.f;
    char opts[160];
    fw_options_format(&s->opts, opts, sizeof opts);
    json_writer_t j;
    json_init(&j, f, true);
    json_begin_object(&j);
    json_kv_string(&j, "workload", "gaze-directed volume rendering (firmware/)");
    json_kv_string(&j, "volume", volume_name);
    json_kv_string(&j, "division", fw_division_name(s->opts.division));
    json_kv_string(&j, "firmware_settings", opts);
    json_key(&j, "blend_settings");
    json_begin_object(&j);
    blend_report_json(&j, &s->rs.blend);
    json_end_object(&j);
    json_kv_string(&j, "lighting", s->cfg.lighting == VR_LIGHT_DIFFUSE ? "diffuse"
                                   : s->cfg.lighting == VR_LIGHT_SPECULAR ? "specular" : "moving");
    json_kv_string(&j, "viewpoint_dependent_shading_on",
                   s->cfg.lighting == VR_LIGHT_DIFFUSE ? "none (diffuse: all viewpoint-independent)"
                   : s->cfg.split == VR_SPLIT_PP ? "pp" : "gp");
    json_kv_int(&j, "width", s->cfg.width);
    json_kv_int(&j, "height", s->cfg.height);
    json_kv_double(&j, "setup_time_s", s->setup_s);
    json_kv_uint(&j, "setup_ring_bytes", s->setup_ring_bytes);
    json_kv_string(&j, "machine_report", "FILE.machine.json: emu's report of the same run");
    write_frames(&j, frames, n_frames);
    json_key(&j, "frame");
    json_begin_object(&j);
    write_frame(&j, s, &frames[n_frames - 1].result);
    json_end_object(&j);
    if (cmp && cmp->have)
        write_compare(&j, cmp, &frames[n_frames - 1].result);
    json_key(&j, "machine");
    pp5_params_write_json(&s->params, &j);
    json_end_object(&j);
    fputc('\n', f);
    return outfile_commit(&o);
}
