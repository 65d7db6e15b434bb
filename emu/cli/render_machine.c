/* render_machine.c: `pp5 render --machine`: the job on the emulated Pixel-Planes 5 (one frame or a gaze sequence), its frame report, and the comparison of its image with the native renderer's on the same job. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "firmware/host/fw_reference.h"
#include "firmware/host/fw_report.h"
#include "render/quality.h"
#include "render_cmd.h"
#include "report.h"

static void print_frame(FILE *log, const fw_frame_result_t *r)
{
    fprintf(log, "machine frame: %.3f ms (%.1f frames/s), bottleneck: %s (critical GP %d)\n",
            r->frame_time_s * 1e3, r->frame_time_s > 0 ? 1.0 / r->frame_time_s : 0, r->bottleneck,
            r->critical_gp);
    for (int k = 0; k < FW_PHASE_COUNT; k++)
        fprintf(log, "  %-40s %9.3f ms\n", fw_phase_name((fw_phase_t)k), r->phase_s[k] * 1e3);
    fprintf(log, "  rays %llu, 3D samples %llu (%llu skipped), bricks fetched %llu (%.1f MB), "
            "up to %llu passes per GP (column ranges x depth segments, local memory)\n",
            (unsigned long long)r->rays, (unsigned long long)r->samples,
            (unsigned long long)r->samples_skipped, (unsigned long long)r->bricks_fetched,
            r->bytes_fetched / 1e6, (unsigned long long)r->passes_max);
    fprintf(log, "  ring bytes: command %llu, data %llu, pixels %llu, gp %llu, host %llu; "
            "utilisation %.1f %%\n",
            (unsigned long long)r->ring_bytes[RING_CLASS_COMMAND],
            (unsigned long long)r->ring_bytes[RING_CLASS_DATA],
            (unsigned long long)r->ring_bytes[RING_CLASS_PIXELS],
            (unsigned long long)r->ring_bytes[RING_CLASS_GP],
            (unsigned long long)r->ring_bytes[RING_CLASS_HOST], 100.0 * r->ring_util_total);
    if (r->ray2_samples || r->rays_saturated || r->rays_occluded || r->rays_terminated)
        fprintf(log, "  blend: DEMIP ray-2 samples %llu (of the samples above), rays saturated "
                "(ray 1 at material 1) %llu, occluded (reading B) %llu, MIDA rays stopped early "
                "%llu\n", (unsigned long long)r->ray2_samples,
                (unsigned long long)r->rays_saturated, (unsigned long long)r->rays_occluded,
                (unsigned long long)r->rays_terminated);
    fprintf(log, "  GP utilisation mean %.1f %% max %.1f %% (imbalance max/mean %.2f); renderer "
            "mean %.1f %% max %.1f %% (shading exec %llu cycles max)\n",
            100 * r->gp_util_mean, 100 * r->gp_util_max, r->gp_imbalance, 100 * r->rn_util_mean,
            100 * r->rn_util_max, (unsigned long long)r->rn_exec_cycles_max);
}

/* Gaze of frame f: frames after the first move it along a horizontal line
 * (a progressive sequence keeps it still while the sweet spot grows). */
static double frame_gaze_x(const render_job_t *job, int f, int frames)
{
    const render_settings_t *s = &job->settings;
    if (frames < 2 || s->progressive)
        return s->gaze_x;
    return s->gaze_x + (s->width * 0.5) * ((double)f / (frames - 1) - 0.5);
}

static pp5_status_t run_frames(fw_session_t *s, const render_job_t *job, int frames,
                               fw_frame_record_t *rec, image8_t *img, FILE *log)
{
    pp5_status_t st = PP5_OK;
    double sum_t = 0;
    for (int f = 0; st == PP5_OK && f < frames; f++) {
        rec[f].gaze_x = frame_gaze_x(job, f, frames);
        rec[f].gaze_y = job->settings.gaze_y;
        image8_free(img);
        st = fw_session_frame(s, rec[f].gaze_x, rec[f].gaze_y, img, &rec[f].result);
        if (st == PP5_OK && frames > 1)
            fprintf(log, "frame %d gaze (%.1f, %.1f): %.3f ms, %llu rays, ring %.2f MB%s\n", f,
                    rec[f].gaze_x, rec[f].gaze_y, rec[f].result.frame_time_s * 1e3,
                    (unsigned long long)rec[f].result.rays, rec[f].result.ring_bytes_total / 1e6,
                    rec[f].result.full_resolution_everywhere ? " (full resolution everywhere)" : "");
        sum_t += rec[f].result.frame_time_s;
    }
    if (st == PP5_OK) {
        print_frame(log, &rec[frames - 1].result);
        if (frames > 1)
            fprintf(log, "mean frame time over %d frames: %.3f ms\n", frames, 1e3 * sum_t / frames);
    }
    return st;
}

/* render/ on the same job and frames: plain, or the like-for-like reference
 * (kind 1: the machine's quantised formats, 2: per-voxel shading in float). */
static pp5_status_t native_image(const render_job_t *job, int kind, int frames, image8_t *out,
                                 render_stats_t *stats)
{
    native_renderer_t nr;
    pp5_status_t st = kind == 0 ? native_renderer_init(&nr, job->volume, &job->tf, &job->shade,
                                                       job->settings.threads)
                                : fw_reference_init(&nr, job, kind == 1);
    if (st == PP5_OK && job->settings.blend.mode != BLEND_COMPOSITE)
        st = native_renderer_build_scalar(&nr, job->volume, job->settings.blend.pyramid);
    if (st != PP5_OK) {
        native_renderer_free(&nr);
        return st;
    }
    for (int f = 0; st == PP5_OK && f < frames; f++) {
        image8_free(out);
        st = native_renderer_frame(&nr, &job->settings, out, stats);
    }
    native_renderer_free(&nr);
    return st;
}

/* A blend's image against render/'s: the machine holds the value
 * pyramid's floats as they are, so render/ itself is like for like. */
static pp5_status_t compare_blend(const image8_t *img, image8_t *ref, const gaze_model_t *gm,
                                  double gx, double gy, const render_stats_t *ns,
                                  fw_compare_t *cmp, FILE *log)
{
    quality_t q;
    pp5_status_t st = quality_compare(img, ref, gm, gx, gy, &q);
    if (st == PP5_OK) {
        *cmp = (fw_compare_t){true, q.psnr_db, q.max_abs, q.psnr_db, q.max_abs, ns->rays,
                              ns->samples};
        fprintf(log, "vs native renderer (same value pyramid floats: like for like): PSNR %.2f dB, "
                "max diff %g; native rays %llu samples %llu (its tracer also skips by the "
                "running maximum)\n", q.psnr_db, q.max_abs, (unsigned long long)ns->rays,
                (unsigned long long)ns->samples);
    }
    image8_free(ref);
    return st;
}

/* The image against render/ on the same inputs (the last gaze point; a
 * progressive sequence against render/'s same sequence). */
static pp5_status_t compare(const fw_session_t *s, const render_job_t *job, double gx,
                            const image8_t *img, fw_compare_t *cmp, FILE *log)
{
    render_job_t last = *job;
    last.settings.gaze_x = gx;
    /* 2DLevel the machine's way (the paper's tables or exact), like for like. */
    last.settings.level_tables = s->opts.level_tables;
    int frames = job->settings.progressive ? job->frames : 1;
    image8_t ref = {0}, ref_q = {0}, ref_f = {0};
    render_stats_t ns1, ns2, ns3;
    quality_t q1, q2, q3, q4;
    double gy = job->settings.gaze_y;
    pp5_status_t st = native_image(&last, 0, frames, &ref, &ns1);
    if (st == PP5_OK && job->settings.blend.mode != BLEND_COMPOSITE)
        return compare_blend(img, &ref, &s->gaze, gx, gy, &ns1, cmp, log);
    if (st == PP5_OK)
        st = native_image(&last, 1, frames, &ref_q, &ns2);
    if (st == PP5_OK)
        st = quality_compare(img, &ref, &s->gaze, gx, gy, &q1);
    if (st == PP5_OK)
        st = quality_compare(img, &ref_q, &s->gaze, gx, gy, &q2);
    if (st == PP5_OK) {
        *cmp = (fw_compare_t){true, q1.psnr_db, q1.max_abs, q2.psnr_db, q2.max_abs, ns1.rays,
                              ns1.samples};
        fprintf(log, "vs native renderer (per-sample float shading): PSNR %.2f dB, max diff %g; "
                "native rays %llu samples %llu\n", q1.psnr_db, q1.max_abs,
                (unsigned long long)ns1.rays, (unsigned long long)ns1.samples);
        fprintf(log, "vs native on the machine's fixed-point per-voxel mip map (like for like): "
                "PSNR %.2f dB, max diff %g; rays %llu samples %llu\n", q2.psnr_db, q2.max_abs,
                (unsigned long long)ns2.rays, (unsigned long long)ns2.samples);
    }
    /* Per-voxel shading in float separates the fixed-point error of the PP
     * formats from the per-voxel-versus-per-sample difference. */
    if (st == PP5_OK && job->shade.lighting != SHADE_DIFFUSE_FIXED_LIGHT) {
        st = native_image(&last, 2, frames, &ref_f, &ns3);
        if (st == PP5_OK)
            st = quality_compare(img, &ref_f, &s->gaze, gx, gy, &q3);
        if (st == PP5_OK)
            st = quality_compare(&ref_f, &ref, &s->gaze, gx, gy, &q4);
        if (st == PP5_OK) {
            fprintf(log, "vs native with float per-voxel viewpoint-dependent shading: PSNR %.2f dB "
                    "(fixed-point error of the PP formats); samples %llu\n", q3.psnr_db,
                    (unsigned long long)ns3.samples);
            fprintf(log, "native float per-voxel vs native per-sample shading: PSNR %.2f dB "
                    "(shading before interpolation, paper §5 'Sampling issues')\n", q4.psnr_db);
        }
    }
    image8_free(&ref);
    image8_free(&ref_q);
    image8_free(&ref_f);
    return st;
}

static pp5_status_t write_outputs(const render_cmd_t *c, const fw_session_t *s, const render_job_t *job,
                                  const fw_frame_record_t *rec, int frames, const image8_t *img,
                                  const fw_compare_t *cmp, FILE *log)
{
    pp5_status_t st = PP5_OK;
    if (c->out_png)
        st = png_write(c->out_png, img);
    if (st == PP5_OK && c->report_json)
        st = fw_report_write(c->report_json, s, rec, frames, job->volume_name, cmp);
    if (st == PP5_OK && c->report_json) {
        /* emu's own run report (every unit's statistics) beside ours. */
        char path[1200];
        snprintf(path, sizeof path, "%s.machine.json", c->report_json);
        report_meta_t meta;
        memset(&meta, 0, sizeof meta);
        meta.workload = "gaze-volume (firmware/)";
        st = report_write(&s->m, &meta, path);
        if (st == PP5_OK)
            fprintf(log, "reports: %s (frame breakdown) and %s (emu's machine report)\n",
                    c->report_json, path);
    }
    if (st == PP5_OK && c->timeline && s->m.tl)
        st = timeline_write(s->m.tl, c->timeline);
    return st;
}

pp5_status_t render_machine_run(const render_cmd_t *c, const render_job_t *job, FILE *log)
{
    if (c->compare || c->levels_prefix || c->fig5_png)
        return pp5_fail(PP5_E_UNSUPPORTED, "--machine does not support --compare, "
                        "--mip-levels-out or --fig5 (use the native renderer for those)");
    pp5_params_t p;
    pp5_status_t st = pp5_params_build(&c->params, &p);
    if (st != PP5_OK)
        return st;
    fw_options_t fo = c->fw;
    fo.timeline = c->timeline != NULL;
    int frames = job->settings.progressive ? job->frames : c->frames;
    fw_frame_record_t *rec = calloc((size_t)frames, sizeof *rec);
    if (!rec)
        return pp5_fail(PP5_E_NOMEM, "render: out of memory");
    fw_session_t s;
    st = fw_session_init(&s, job, &p, &fo);
    if (st == PP5_OK) {
        fprintf(log, "volume: %s (%dx%dx%d), tf %s, lighting %s, viewpoint-dependent shading on %s, "
                "division %s\n", job->volume_name, job->volume->nx, job->volume->ny, job->volume->nz,
                job->tf.name, shade_case_name(job->shade.lighting),
                job->shade.lighting == SHADE_DIFFUSE_FIXED_LIGHT ? "(none needed)"
                : fo.split == VR_SPLIT_PP ? "the PPs" : "the GPs", fw_division_name(fo.division));
        fprintf(log, "machine: %u GPs, %u renderers, ring %.0f MB/s; setup (load, GP mip-map build, "
                "backing-store writes) %.3f s emulated, %.1f MB on the ring\n", s.m.n_gp, s.m.n_rn,
                pp5_params_ring_aggregate_bytes_per_s(&p) / 1e6, s.setup_s, s.setup_ring_bytes / 1e6);
    }
    image8_t img = {0};
    fw_compare_t cmp = {0};
    if (st == PP5_OK)
        st = run_frames(&s, job, frames, rec, &img, log);
    if (st == PP5_OK)
        st = compare(&s, job, rec[frames - 1].gaze_x, &img, &cmp, log);
    if (st == PP5_OK)
        st = write_outputs(c, &s, job, rec, frames, &img, &cmp, log);
    image8_free(&img);
    fw_session_free(&s);
    free(rec);
    return st;
}
