/* fw_render.c: `pp5 render --machine`: one frame (or a gaze sequence) on the emulated machine, compared with the native renderer, with report and timeline. */
#include "fw_render.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cliopt.h"
#include "json.h"
#include "render/quality.h"
#include "report.h"
#include "stats.h"
#include "firmware/common/vr_gp.h"

const char *fw_render_help(void)
{
    return "Machine (emulated Pixel-Planes 5, firmware/):\n"
           "  --machine             render on the emulated machine (GPs + renderers + ring);\n"
           "                        prints the emulated frame time and compares the image\n"
           "                        with the native renderer on the same inputs\n"
           "  --split pp|gp         where viewpoint-dependent shading runs (pp: the paper)\n"
           "  --frames N            N frames with the gaze moving (setup reused)\n"
           "  --timeline FILE.json  Chrome trace of the emulated frame (ui.perfetto.dev)\n"
           "  --preset NAME --config FILE --set NAME=VALUE   machine parameters (pp5 machine)\n";
}

int fw_render_filter_args(int argc, char **argv, fw_render_opts_t *o, pp5_status_t *st)
{
    memset(o, 0, sizeof *o);
    o->split = VR_SPLIT_PP;
    o->frames = 1;
    *st = PP5_OK;
    int out = 1;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(a, "--machine") == 0) {
            o->machine = true;
            continue;
        }
        bool takes = strcmp(a, "--split") == 0 || strcmp(a, "--timeline") == 0 ||
                     strcmp(a, "--preset") == 0 || strcmp(a, "--config") == 0 ||
                     strcmp(a, "--set") == 0 || strcmp(a, "--frames") == 0;
        if (!takes) {
            argv[out++] = argv[i];
            continue;
        }
        if (!val) {
            *st = pp5_fail(PP5_E_CONFIG, "%s needs a value", a);
            return out;
        }
        i++;
        if (strcmp(a, "--split") == 0) {
            if (strcmp(val, "pp") == 0)
                o->split = VR_SPLIT_PP;
            else if (strcmp(val, "gp") == 0)
                o->split = VR_SPLIT_GP;
            else
                *st = pp5_fail(PP5_E_CONFIG, "--split: expected pp or gp, got '%s'", val);
        } else if (strcmp(a, "--timeline") == 0) {
            o->timeline = val;
        } else if (strcmp(a, "--preset") == 0) {
            o->params.preset = val;
        } else if (strcmp(a, "--config") == 0) {
            o->params.config = val;
        } else if (strcmp(a, "--frames") == 0) {
            long n;
            if (cliopt_long("--frames", val, 1, 100000, &n) != PP5_OK)
                *st = PP5_E_CONFIG;
            o->frames = (int)n;
        } else if (pp5_params_cli_add_set(&o->params, val) != PP5_OK) {
            *st = PP5_E_CONFIG;
        }
    }
    argv[out] = NULL;
    return out;
}

static void write_frame_json(json_writer_t *j, const fw_session_t *s, const fw_frame_result_t *r)
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
    json_kv_uint(j, "renderer_exec_cycles_max", r->rn_exec_cycles_max);
    json_key(j, "ring_bytes_by_class");
    json_begin_object(j);
    for (unsigned k = 0; k < RING_CLASS_COUNT; k++)
        json_kv_uint(j, stats_class_name(k), r->ring_bytes[k]);
    json_end_object(j);
    json_key(j, "ring_utilization_by_class");
    json_begin_object(j);
    for (unsigned k = 0; k < RING_CLASS_COUNT; k++)
        json_kv_double(j, stats_class_name(k), r->ring_util[k]);
    json_end_object(j);
    json_kv_double(j, "ring_utilization", r->ring_util_total);
    json_kv_double(j, "gp_utilization_mean", r->gp_util_mean);
    json_kv_double(j, "gp_utilization_max", r->gp_util_max);
    json_kv_double(j, "renderer_utilization_mean", r->rn_util_mean);
    json_kv_double(j, "renderer_utilization_max", r->rn_util_max);
    json_key(j, "gp");
    json_begin_array(j);
    for (unsigned g = 0; g < s->m.n_gp; g++) {
        const vr_probe_t *p = vr_probe(s->m.gp[g].state);
        json_begin_object(j);
        json_kv_int(j, "index", g);
        if (p) {
            json_kv_int(j, "band_y0", s->last_bands[g]);
            json_kv_int(j, "band_y1", s->last_bands[g + 1]);
            json_kv_uint(j, "rays", p->rays);
            json_kv_uint(j, "samples_3d", p->samples);
            json_kv_uint(j, "bricks_fetched", p->bricks_fetched);
            json_kv_uint(j, "cycles_prep", p->cyc_prep);
            json_kv_uint(j, "cycles_pp_stream_build", p->cyc_exec_build);
            json_kv_uint(j, "cycles_forward", p->cyc_forward);
            json_kv_uint(j, "cycles_receive", p->cyc_unpack);
            json_kv_uint(j, "cycles_shade", p->cyc_shade);
            json_kv_uint(j, "cycles_cast", p->cyc_cast);
            json_kv_uint(j, "cycles_resample", p->cyc_pixels);
            json_kv_double(j, "done_s", ticks_to_s(p->t_done - p->t_start));
        }
        json_kv_uint(j, "mem_peak_bytes", s->m.gp[g].mem_peak_bytes);
        json_end_object(j);
    }
    json_end_array(j);
}

pp5_status_t fw_write_report(const char *path, const fw_session_t *s, const fw_frame_result_t *r,
                             const char *volume_name, const fw_compare_t *cmp)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return pp5_fail(PP5_E_IO, "cannot write %s", path);
    json_writer_t j;
    json_init(&j, f, true);
    json_begin_object(&j);
    json_kv_string(&j, "workload", "gaze-directed volume rendering (firmware/)");
    json_kv_string(&j, "volume", volume_name);
    json_kv_string(&j, "lighting", s->cfg.lighting == VR_LIGHT_DIFFUSE ? "diffuse" : "specular");
    json_kv_string(&j, "viewpoint_dependent_shading_on",
                   s->cfg.lighting == VR_LIGHT_DIFFUSE ? "none (diffuse: all viewpoint-independent)"
                   : s->cfg.split == VR_SPLIT_PP ? "pp" : "gp");
    json_kv_int(&j, "width", s->cfg.width);
    json_kv_int(&j, "height", s->cfg.height);
    json_kv_double(&j, "setup_time_s", s->setup_s);
    json_kv_uint(&j, "setup_ring_bytes", s->setup_ring_bytes);
    json_kv_string(&j, "machine_report", "FILE.machine.json: emu's report of the same run");
    json_key(&j, "frame");
    json_begin_object(&j);
    write_frame_json(&j, s, r);
    json_end_object(&j);
    if (cmp && cmp->have) {
        json_key(&j, "image_vs_native");
        json_begin_object(&j);
        json_kv_double(&j, "psnr_db", isfinite(cmp->psnr_native_db) ? cmp->psnr_native_db : 999.0);
        json_kv_double(&j, "max_abs_diff", cmp->max_diff_native);
        json_kv_double(&j, "psnr_like_for_like_db", isfinite(cmp->psnr_like_db) ? cmp->psnr_like_db : 999.0);
        json_kv_double(&j, "max_abs_diff_like_for_like", cmp->max_diff_like);
        json_kv_uint(&j, "native_rays", cmp->native_rays);
        json_kv_uint(&j, "native_samples_3d", cmp->native_samples);
        json_kv_uint(&j, "machine_rays", r->rays);
        json_kv_uint(&j, "machine_samples_3d", r->samples);
        json_end_object(&j);
    }
    json_key(&j, "machine");
    pp5_params_write_json(&s->params, &j);
    json_end_object(&j);
    fputc('\n', f);
    if (fclose(f) != 0)
        return pp5_fail(PP5_E_IO, "cannot write %s", path);
    return PP5_OK;
}

static void print_frame(FILE *log, const fw_session_t *s, const fw_frame_result_t *r)
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
    fprintf(log, "  GP utilisation mean %.1f %% max %.1f %%; renderer mean %.1f %% max %.1f %% "
            "(shading exec %llu cycles max)\n",
            100 * r->gp_util_mean, 100 * r->gp_util_max, 100 * r->rn_util_mean,
            100 * r->rn_util_max, (unsigned long long)r->rn_exec_cycles_max);
    (void)s;
}

pp5_status_t fw_render_cli_run(render_cli_t *c, const fw_render_opts_t *o, FILE *log)
{
    scene_t sc;
    pp5_status_t st = render_cli_load_input(c, &sc, log);
    if (st != PP5_OK)
        return st;
    render_settings_t rs = c->settings;
    if (!c->have_tf)
        c->tf = sc.tf;
    if (!c->have_rot) {
        rs.view.rot_x_deg = sc.rot_x_deg;
        rs.view.rot_y_deg = sc.rot_y_deg;
        rs.view.rot_z_deg = sc.rot_z_deg;
    }
    if (!c->have_gaze) {
        rs.gaze_x = 0.5 * (rs.width - 1);
        rs.gaze_y = 0.5 * (rs.height - 1);
    }
    if (c->compare || c->levels_prefix || c->fig5_png) {
        scene_free(&sc);
        return pp5_fail(PP5_E_UNSUPPORTED, "--machine does not support --compare, "
                        "--mip-levels-out or --fig5 (use the native renderer for those)");
    }
    fw_render_opts_t oo = *o;
    if (c->progressive_frames > 0) {
        rs.progressive = true;
        oo.frames = c->progressive_frames;
    }
    o = &oo;
    pp5_params_t p;
    st = pp5_params_build(&o->params, &p);
    if (st != PP5_OK) {
        scene_free(&sc);
        return st;
    }
    fw_options_t fo;
    fw_options_default(&fo);
    fo.split = o->split;
    fo.timeline = o->timeline != NULL;
    fw_session_t s;
    st = fw_session_init(&s, &sc.volume, &c->tf, &c->shade, &rs, &p, &fo);
    if (st != PP5_OK) {
        fw_session_free(&s);
        scene_free(&sc);
        return st;
    }
    fprintf(log, "volume: %s (%dx%dx%d), tf %s, lighting %s, viewpoint-dependent shading on %s\n",
            sc.volume.source, sc.volume.nx, sc.volume.ny, sc.volume.nz, c->tf.name,
            shade_case_name(c->shade.lighting),
            c->shade.lighting == SHADE_DIFFUSE_FIXED_LIGHT ? "(none needed)"
            : o->split == VR_SPLIT_PP ? "the PPs" : "the GPs");
    fprintf(log, "machine: %u GPs, %u renderers, ring %.0f MB/s; setup (load, GP mip-map build, "
            "backing-store writes) %.3f s emulated, %.1f MB on the ring\n",
            s.m.n_gp, s.m.n_rn, pp5_params_ring_aggregate_bytes_per_s(&p) / 1e6, s.setup_s,
            s.setup_ring_bytes / 1e6);
    image8_t img = {0};
    fw_frame_result_t r;
    memset(&r, 0, sizeof r);
    fw_compare_t cmp;
    memset(&cmp, 0, sizeof cmp);
    double sum_t = 0;
    for (int f = 0; st == PP5_OK && f < o->frames; f++) {
        /* Frames after the first move the gaze along a horizontal line
         * (progressive: the gaze stays put and the sweet spot grows). */
        double gx = rs.gaze_x + (o->frames > 1 && !rs.progressive
                                     ? (rs.width * 0.5) * ((double)f / (o->frames - 1) - 0.5) : 0);
        image8_free(&img);
        st = fw_session_frame(&s, gx, rs.gaze_y, &img, &r);
        if (st == PP5_OK && o->frames > 1)
            fprintf(log, "frame %d gaze (%.1f, %.1f): %.3f ms, %llu rays%s\n", f, gx, rs.gaze_y,
                    r.frame_time_s * 1e3, (unsigned long long)r.rays,
                    r.full_resolution_everywhere ? " (full resolution everywhere)" : "");
        sum_t += r.frame_time_s;
    }
    if (st == PP5_OK) {
        print_frame(log, &s, &r);
        if (o->frames > 1)
            fprintf(log, "mean frame time over %d frames: %.3f ms\n", o->frames, 1e3 * sum_t / o->frames);
        /* Compare with the native renderer on the same inputs (last gaze). */
        double gx = rs.gaze_x + (o->frames > 1 && !rs.progressive ? rs.width * 0.25 : 0);
        render_settings_t ns = rs;
        ns.gaze_x = gx;
        /* Compared with render/ on the same frame (progressive: the same sequence). */
        int nframes = rs.progressive ? o->frames : 1;
        native_renderer_t nr;
        image8_t ref = {0}, ref_q = {0};
        render_stats_t ns1, ns2;
        st = native_renderer_init(&nr, &sc.volume, &c->tf, &c->shade, rs.threads);
        if (st == PP5_OK) {
            for (int f = 0; st == PP5_OK && f < nframes; f++) {
                image8_free(&ref);
                st = native_renderer_frame(&nr, &ns, &ref, &ns1);
            }
            native_renderer_free(&nr);
        }
        if (st == PP5_OK)
            st = fw_reference_init(&nr, &sc.volume, &c->tf, &c->shade, &rs, true);
        if (st == PP5_OK) {
            for (int f = 0; st == PP5_OK && f < nframes; f++) {
                image8_free(&ref_q);
                st = native_renderer_frame(&nr, &ns, &ref_q, &ns2);
            }
            native_renderer_free(&nr);
        }
        quality_t q1, q2;
        if (st == PP5_OK)
            st = quality_compare(&img, &ref, &s.gaze, gx, rs.gaze_y, &q1);
        if (st == PP5_OK)
            st = quality_compare(&img, &ref_q, &s.gaze, gx, rs.gaze_y, &q2);
        if (st == PP5_OK) {
            cmp.have = true;
            cmp.psnr_native_db = q1.psnr_db;
            cmp.max_diff_native = q1.max_abs;
            cmp.psnr_like_db = q2.psnr_db;
            cmp.max_diff_like = q2.max_abs;
            cmp.native_rays = ns1.rays;
            cmp.native_samples = ns1.samples;
            fprintf(log, "vs native renderer (per-sample float shading): PSNR %.2f dB, max diff %g; "
                    "native rays %llu samples %llu\n", q1.psnr_db, q1.max_abs,
                    (unsigned long long)ns1.rays, (unsigned long long)ns1.samples);
            fprintf(log, "vs native on the machine's fixed-point per-voxel mip map (like for like): "
                    "PSNR %.2f dB, max diff %g; rays %llu samples %llu\n", q2.psnr_db, q2.max_abs,
                    (unsigned long long)ns2.rays, (unsigned long long)ns2.samples);
        }
        if (st == PP5_OK && c->shade.lighting != SHADE_DIFFUSE_FIXED_LIGHT) {
            /* Per-voxel shading in float: separates the fixed-point error of
             * the PP formats from the per-voxel-versus-per-sample difference. */
            image8_t ref_f = {0};
            render_stats_t ns3;
            quality_t q3, q4;
            st = fw_reference_init(&nr, &sc.volume, &c->tf, &c->shade, &rs, false);
            if (st == PP5_OK) {
                for (int f = 0; st == PP5_OK && f < nframes; f++) {
                    image8_free(&ref_f);
                    st = native_renderer_frame(&nr, &ns, &ref_f, &ns3);
                }
                native_renderer_free(&nr);
            }
            if (st == PP5_OK)
                st = quality_compare(&img, &ref_f, &s.gaze, gx, rs.gaze_y, &q3);
            if (st == PP5_OK)
                st = quality_compare(&ref_f, &ref, &s.gaze, gx, rs.gaze_y, &q4);
            if (st == PP5_OK) {
                fprintf(log, "vs native with float per-voxel viewpoint-dependent shading: PSNR %.2f dB "
                        "(fixed-point error of the PP formats); samples %llu\n", q3.psnr_db,
                        (unsigned long long)ns3.samples);
                fprintf(log, "native float per-voxel vs native per-sample shading: PSNR %.2f dB "
                        "(shading before interpolation, paper §5 'Sampling issues')\n", q4.psnr_db);
            }
            image8_free(&ref_f);
        }
        image8_free(&ref);
        image8_free(&ref_q);
    }
    if (st == PP5_OK && c->out_png)
        st = png_write(c->out_png, &img);
    if (st == PP5_OK && c->report_json)
        st = fw_write_report(c->report_json, &s, &r, sc.volume.source, &cmp);
    if (st == PP5_OK && c->report_json) {
        /* emu's own run report (every unit's busy time, ring counters, parameters)
         * beside ours: FILE.machine.json. */
        char path[1200];
        snprintf(path, sizeof path, "%s.machine.json", c->report_json);
        report_meta_t meta;
        memset(&meta, 0, sizeof meta);
        meta.argc = 0;
        meta.argv = NULL;
        meta.workload = "gaze-volume (firmware/)";
        st = report_write(&s.m, &meta, path);
        if (st == PP5_OK)
            fprintf(log, "reports: %s (frame breakdown) and %s (emu's machine report)\n",
                    c->report_json, path);
    }
    if (st == PP5_OK && o->timeline && s.m.tl)
        st = timeline_write(s.m.tl, o->timeline);
    image8_free(&img);
    fw_session_free(&s);
    scene_free(&sc);
    return st;
}
