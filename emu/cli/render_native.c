/* render_native.c: `pp5 render` on the native renderer: the frames (one, or a progressive sequence), the PNG, figures 5 and 6, the comparison with full resolution and the JSON report. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"
#include "outfile.h"
#include "render/quality.h"
#include "render/render_figures.h"
#include "render_cmd.h"

/* What a run produced, for the report. */
typedef struct {
    render_stats_t *stats;        /* one per frame */
    int frames, frames_to_full;
    bool have_quality;
    quality_t quality;
    render_stats_t full_stats;
} native_run_t;

static void report_stats(json_writer_t *j, const char *key, const render_stats_t *s)
{
    json_key(j, key);
    json_begin_object(j);
    json_kv_uint(j, "rays", s->rays);
    json_kv_uint(j, "samples_3d", s->samples);
    json_kv_uint(j, "samples_skipped_by_octree", s->samples_skipped);
    if (s->samples_retraced)
        json_kv_uint(j, "samples_retraced", s->samples_retraced);
    json_kv_int(j, "frame_index", s->frame_index);
    json_kv_bool(j, "full_resolution_everywhere", s->full_resolution_everywhere);
    json_end_object(j);
}

/* Host wall-clock times, in ms: they vary from run to run. */
static void report_ms(json_writer_t *j, const char *key, const render_stats_t *s)
{
    json_key(j, key);
    json_begin_object(j);
    json_kv_double(j, "ms_levels", s->ms_levels);
    json_kv_double(j, "ms_cast", s->ms_cast);
    json_kv_double(j, "ms_reconstruct", s->ms_reconstruct);
    json_kv_double(j, "ms_total", s->ms_total);
    json_end_object(j);
}

static void report_settings(json_writer_t *j, const render_job_t *job, const native_renderer_t *r)
{
    const render_settings_t *s = &job->settings;
    json_key(j, "settings");
    json_begin_object(j);
    json_kv_string(j, "mode", render_mode_name(s->mode));
    json_kv_int(j, "width", s->width);
    json_kv_int(j, "height", s->height);
    json_kv_double(j, "gaze_x", s->gaze_x);
    json_kv_double(j, "gaze_y", s->gaze_y);
    json_kv_string(j, "projection", projection_name(s->view.projection));
    json_kv_double(j, "rot_x_deg", s->view.rot_x_deg);
    json_kv_double(j, "rot_y_deg", s->view.rot_y_deg);
    json_kv_double(j, "rot_z_deg", s->view.rot_z_deg);
    json_kv_double(j, "zoom", s->view.zoom);
    json_kv_double(j, "sample_step", s->view.sample_step);
    json_kv_double(j, "early_termination", s->view.early_termination);
    json_kv_bool(j, "octree", s->view.use_octree);
    blend_report_json(j, &s->blend);
    json_kv_string(j, "transfer_function", job->tf.name);
    json_kv_string(j, "lighting", shade_case_name(job->shade.lighting));
    json_kv_double(j, "monitor_diag_in", s->display.monitor_diag_in);
    json_kv_double(j, "view_distance_in", s->display.view_distance_in);
    json_kv_double(j, "image_subtense_deg", s->display.image_subtense_deg);
    json_kv_double(j, "inches_per_px", r->gaze.inches_per_px);
    json_kv_double(j, "sigma_deg", r->gaze.sigma_deg);
    json_kv_double(j, "full_res_radius_px", gaze_radius_px(&r->gaze, r->gaze.e_full_deg));
    json_kv_double(j, "periphery_radius_px", gaze_radius_px(&r->gaze, r->gaze.e_edge_deg));
    json_end_object(j);
}

static void report_results(json_writer_t *j, const render_job_t *job, const native_renderer_t *r,
                           const native_run_t *run)
{
    json_key(j, "preprocessing");
    json_begin_object(j);
    json_kv_int(j, "mip3d_levels", r->mip.levels);
    json_kv_int(j, "mip3d_floats_per_voxel", r->mip.stride);
    json_kv_string(j, "mip3d_voxel_format", mip3d_format_name(r->mip.format));
    json_kv_int(j, "mip3d_bytes", (long long)r->mip.bytes);
    json_kv_uint(j, "mip3d_bytes", r->mip.bytes);
    json_end_object(j);
    json_key(j, "frames");
    json_begin_array(j);
    for (int f = 0; f < run->frames; f++) {
        json_begin_object(j);
        report_stats(j, "stats", &run->stats[f]);
        json_end_object(j);
    }
    json_end_array(j);
    report_stats(j, "last_frame", &run->stats[run->frames - 1]);
    if (job->settings.progressive)
        json_kv_int(j, "frames_to_full_resolution", run->frames_to_full);
    if (run->have_quality) {
        report_stats(j, "full_resolution_reference", &run->full_stats);
        json_key(j, "quality");
        json_begin_object(j);
        json_kv_double(j, "psnr_db", run->quality.psnr_db);
        json_kv_double(j, "acuity_weighted_psnr_db", run->quality.aw_psnr_db);
        json_kv_double(j, "mse", run->quality.mse);
        json_kv_double(j, "acuity_weighted_mse", run->quality.aw_mse);
        json_kv_double(j, "max_channel_error", run->quality.max_abs);
        json_end_object(j);
    }
}

/* Everything that depends on the host rather than the inputs (thread count,
 * wall-clock times) lives under this one key, so that two reports of the
 * same render compare equal once it is removed. */
static void report_host_timing(json_writer_t *j, const render_job_t *job,
                               const native_renderer_t *r, const native_run_t *run)
{
    json_key(j, "host_timing");
    json_begin_object(j);
    json_kv_int(j, "threads", job->settings.threads > 0 ? job->settings.threads : r->threads);
    json_kv_double(j, "ms_mip3d", r->ms_build_mip);
    json_kv_double(j, "ms_octree", r->ms_build_octree);
    json_key(j, "frames");
    json_begin_array(j);
    for (int f = 0; f < run->frames; f++) {
        json_begin_object(j);
        report_ms(j, "ms", &run->stats[f]);
        json_end_object(j);
    }
    json_end_array(j);
    report_ms(j, "last_frame", &run->stats[run->frames - 1]);
    if (run->have_quality)
        report_ms(j, "full_resolution_reference", &run->full_stats);
    json_end_object(j);
}

static pp5_status_t write_report(const char *path, const render_job_t *job, const scene_t *sc,
                                 const native_renderer_t *r, const native_run_t *run)
{
    outfile_t o;
    pp5_status_t st = outfile_open(&o, path, false);
    if (st != PP5_OK)
        return st;
    FILE *f = o.f;
    json_writer_t j;
    json_init(&j, f, true);
    json_begin_object(&j);
    json_kv_string(&j, "renderer", "native gaze-directed (Levoy & Whitaker 1990)");
    json_key(&j, "volume");
    json_begin_object(&j);
    json_kv_string(&j, "source", sc->volume.source);
    json_kv_int(&j, "nx", sc->volume.nx);
    json_kv_int(&j, "ny", sc->volume.ny);
    json_kv_int(&j, "nz", sc->volume.nz);
    json_kv_bool(&j, "fell_back_to_phantom", sc->fell_back);
    json_end_object(&j);
    report_settings(&j, job, r);
    report_results(&j, job, r, run);
    report_host_timing(&j, job, r, run);
    json_end_object(&j);
    fputc('\n', f);
    return outfile_commit(&o);
}

/* A renderer for the job: the 3D mip map and octree, plus the value pyramid
 * that MIP, DEMIP and MIDA rays sample. */
static pp5_status_t renderer_for(native_renderer_t *r, const render_job_t *job, int threads)
{
    pp5_status_t st = native_renderer_init_format(r, job->volume, &job->tf, &job->shade,
                                                  job->settings.voxel_format, threads);
    if (st == PP5_OK && job->settings.blend.mode != BLEND_COMPOSITE) {
        st = native_renderer_build_scalar(r, job->volume, job->settings.blend.pyramid);
        if (st != PP5_OK)
            native_renderer_free(r);
    }
    return st;
}

static pp5_status_t run_frames(native_renderer_t *r, const render_job_t *job, image8_t *img,
                               native_run_t *run, FILE *log)
{
    const render_settings_t *s = &job->settings;
    pp5_status_t st = PP5_OK;
    run->frames_to_full = -1;
    for (int f = 0; st == PP5_OK && f < run->frames; f++) {
        image8_free(img);
        render_stats_t *fs = &run->stats[f];
        st = native_renderer_frame(r, s, img, fs);
        if (st != PP5_OK)
            break;
        fprintf(log, "frame %d (%s %dx%d, %s): %llu rays, %llu 3D samples (%llu skipped), "
                "%.1f ms (levels %.1f, cast %.1f, reconstruct %.1f)\n", f,
                render_mode_name(s->mode), s->width, s->height, projection_name(s->view.projection),
                (unsigned long long)fs->rays, (unsigned long long)fs->samples,
                (unsigned long long)fs->samples_skipped, fs->ms_total, fs->ms_levels, fs->ms_cast,
                fs->ms_reconstruct);
        if (run->frames_to_full < 0 && fs->full_resolution_everywhere)
            run->frames_to_full = f + 1;
    }
    if (st == PP5_OK && s->progressive) {
        fprintf(log, "progressive: %s\n", run->frames_to_full > 0 ? "full resolution everywhere"
                                                                  : "not yet full resolution");
        if (run->frames_to_full > 0)
            fprintf(log, "progressive: frames to full resolution everywhere: %d\n",
                    run->frames_to_full);
    }
    return st;
}

/* --compare: the same view at full resolution, and the quality of ours. */
static pp5_status_t compare_full(const render_job_t *job, const native_renderer_t *r,
                                 const image8_t *img, native_run_t *run, FILE *log)
{
    render_settings_t fs = job->settings;
    fs.mode = RENDER_MODE_FULL;
    fs.progressive = false;
    image8_t ref = {0};
    native_renderer_t r2;
    pp5_status_t st = renderer_for(&r2, job, fs.threads);
    if (st == PP5_OK) {
        st = native_renderer_frame(&r2, &fs, &ref, &run->full_stats);
        native_renderer_free(&r2);
    }
    const render_settings_t *s = &job->settings;
    if (st == PP5_OK)
        st = quality_compare(img, &ref, &r->gaze, s->gaze_x, s->gaze_y, &run->quality);
    if (st == PP5_OK) {
        run->have_quality = true;
        fprintf(log, "full resolution: %llu rays, %llu 3D samples, %.1f ms\n",
                (unsigned long long)run->full_stats.rays,
                (unsigned long long)run->full_stats.samples, run->full_stats.ms_total);
        fprintf(log, "quality vs full resolution: PSNR %.2f dB, acuity-weighted PSNR %.2f dB, "
                "max channel error %.0f\n", run->quality.psnr_db, run->quality.aw_psnr_db,
                run->quality.max_abs);
    }
    image8_free(&ref);
    return st;
}

pp5_status_t render_native_run(const render_cmd_t *c, const render_job_t *job, const scene_t *sc,
                               FILE *log)
{
    native_renderer_t r;
    pp5_status_t st = renderer_for(&r, job, job->settings.threads);
    if (st != PP5_OK)
        return st;
    fprintf(log, "volume: %s (%dx%dx%d, values %g..%g), tf %s, lighting %s\n", sc->volume.source,
            sc->volume.nx, sc->volume.ny, sc->volume.nz, sc->volume.min_value,
            sc->volume.max_value, job->tf.name, shade_case_name(job->shade.lighting));
    fprintf(log, "3D mip map: %d levels, %d %s components/voxel, %.1f MB, built in %.0f ms; "
            "octree %.1f MB in %.0f ms\n", r.mip.levels, r.mip.stride,
            mip3d_format_name(r.mip.format), r.mip.bytes / 1e6, r.ms_build_mip,
            r.octree.bytes / 1e6, r.ms_build_octree);
    const blend_settings_t *b = &job->settings.blend;
    if (b->mode != BLEND_COMPOSITE)
        fprintf(log, "blend %s: %s value pyramid %.1f MB in %.0f ms\n", blend_mode_name(b->mode),
                scalar_pyramid_kind_name(b->pyramid), r.scalar.bytes / 1e6, r.ms_build_scalar);
    native_run_t run = {.frames = job->frames};
    run.stats = calloc((size_t)run.frames, sizeof *run.stats);
    image8_t img = {0};
    st = run.stats ? run_frames(&r, job, &img, &run, log)
                   : pp5_fail(PP5_E_NOMEM, "render: out of memory");
    if (st == PP5_OK && c->out_png)
        st = png_write(c->out_png, &img);
    if (st == PP5_OK && c->levels_prefix)
        st = render_write_mip_levels(&r.mip2d, c->levels_prefix);
    if (st == PP5_OK && c->fig5_png)
        st = render_write_fig5(&r.gaze, c->fig5_png);
    if (st == PP5_OK && c->compare)
        st = compare_full(job, &r, &img, &run, log);
    if (st == PP5_OK && c->report_json)
        st = write_report(c->report_json, job, sc, &r, &run);
    image8_free(&img);
    free(run.stats);
    native_renderer_free(&r);
    return st;
}
