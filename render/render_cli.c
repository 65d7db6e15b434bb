/* render_cli.c: the body of `pp5 render`: input, frames, PNG, figures 5 and
 * 6, comparison against full resolution and the JSON report. */
#include "render_cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"
#include "plot.h"
#include "quality.h"
#include "scene.h"

void render_cli_defaults(render_cli_t *c)
{
    memset(c, 0, sizeof *c);
    c->input = RENDER_INPUT_PHANTOM;
    c->input_name = "shepp-logan";
    shade_defaults(&c->shade);
    render_settings_defaults(&c->settings);
}

pp5_status_t render_write_fig5(const gaze_model_t *g, const char *path)
{
    enum { N = 400 };
    double xs[N], target[N], lo[N], hi[N];
    /* Distance in inches on the screen, out to the image's half width. */
    double max_in = 0.5 * g->width * g->inches_per_px;
    for (int i = 0; i < N; i++) {
        double r_in = max_in * i / (N - 1);
        double r_px = r_in / g->inches_per_px;
        float level = gaze_level(g, r_px);
        xs[i] = r_in;
        target[i] = gaze_target_rays_per_px(g, gaze_eccentricity_deg(g, r_px));
        lo[i] = pow(0.25, floor(level));   /* finest populated level: span */
        hi[i] = pow(0.25, ceil(level));    /* coarsest level blended in */
    }
    plot_t p;
    plot_init(&p, "Sweet spot (fig. 5)",
              "distance from gaze (inches on screen)",
              "rays per pixel");
    pp5_status_t st = plot_add_series(&p, "target", xs, target, N);
    if (st == PP5_OK)
        st = plot_add_series(&p, "floor(2DLevel)", xs, lo, N);
    if (st == PP5_OK)
        st = plot_add_series(&p, "ceil(2DLevel)", xs, hi, N);
    /* The paper's circles (diameters): 12 degrees (4.2") and 20 degrees (7"). */
    char label[64];
    snprintf(label, sizeof label, "12deg");
    if (st == PP5_OK)
        st = plot_add_xref(&p, gaze_radius_px(g, g->e_full_deg) * g->inches_per_px, label);
    snprintf(label, sizeof label, "20deg");
    if (st == PP5_OK)
        st = plot_add_xref(&p, gaze_radius_px(g, g->e_edge_deg) * g->inches_per_px, label);
    if (st == PP5_OK) {
        plot_set_style(&p, 1, PLOT_STEPS);
        plot_set_style(&p, 2, PLOT_STEPS);
        plot_set_yrange(&p, 0.0, 1.1);
        st = plot_write_png(&p, path, 1000, 560);
    }
    plot_free(&p);
    return st;
}

pp5_status_t render_write_mip_levels(const mip2d_t *m, const char *prefix)
{
    for (int l = 0; l < m->levels; l++) {
        image8_t img;
        pp5_status_t st = image8_alloc(&img, m->w[l], m->h[l], 3);
        if (st != PP5_OK)
            return st;
        size_t n = (size_t)m->w[l] * m->h[l];
        for (size_t i = 0; i < n; i++)
            for (int k = 0; k < 3; k++)
                img.pixels[i * 3 + k] = m->cast[l][i] ? render_to_u8(m->rgb[l][i * 3 + k]) : 40;
        char path[1100];
        snprintf(path, sizeof path, "%s%d.png", prefix, l);
        st = png_write(path, &img);
        image8_free(&img);
        if (st != PP5_OK)
            return st;
    }
    return PP5_OK;
}

pp5_status_t render_cli_load_input(const render_cli_t *c, scene_t *sc, FILE *log)
{
    memset(sc, 0, sizeof *sc);
    pp5_status_t st;
    if (c->input == RENDER_INPUT_PHANTOM || c->input == RENDER_INPUT_DATASET) {
        st = scene_load(c->input_name, c->input == RENDER_INPUT_DATASET, sc);
        if (st == PP5_OK && sc->fell_back)
            fprintf(log, "note: %s\n", sc->note);
        return st;
    }
    volume_raw_spec_t spec = c->raw;
    const volume_raw_spec_t *raw = NULL;
    if (c->have_raw) {
        raw = &spec;
    } else if (volume_raw_spec_from_name(c->input_name, &spec) == PP5_OK) {
        if (c->have_spacing)
            memcpy(spec.spacing, c->raw.spacing, sizeof spec.spacing);
        raw = &spec;
    }
    st = volume_load(c->input_name, raw, &sc->volume);
    if (st != PP5_OK)
        return st;
    if (c->have_spacing)
        memcpy(sc->volume.spacing, c->raw.spacing, sizeof sc->volume.spacing);
    snprintf(sc->name, sizeof sc->name, "file");
    scene_guess_tf(&sc->volume, &sc->tf);
    return PP5_OK;
}

static void report_stats(json_writer_t *j, const char *key, const render_stats_t *s)
{
    json_key(j, key);
    json_begin_object(j);
    json_kv_uint(j, "rays", s->rays);
    json_kv_uint(j, "samples_3d", s->samples);
    json_kv_uint(j, "samples_skipped_by_octree", s->samples_skipped);
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

/* Everything that depends on the host rather than the inputs (thread count,
 * wall-clock times) lives under this one key, so that two reports of the same
 * render compare equal once it is removed. */
static void report_host_timing(json_writer_t *j, const native_renderer_t *r, int threads,
                               const render_stats_t *stats, int frames,
                               const render_stats_t *full_stats, bool have_full)
{
    json_key(j, "host_timing");
    json_begin_object(j);
    json_kv_int(j, "threads", threads);
    json_kv_double(j, "ms_mip3d", r->ms_build_mip);
    json_kv_double(j, "ms_octree", r->ms_build_octree);
    json_key(j, "frames");
    json_begin_array(j);
    for (int f = 0; f < frames; f++) {
        json_begin_object(j);
        report_ms(j, "ms", &stats[f]);
        json_end_object(j);
    }
    json_end_array(j);
    report_ms(j, "last_frame", &stats[frames - 1]);
    if (have_full)
        report_ms(j, "full_resolution_reference", full_stats);
    json_end_object(j);
}

pp5_status_t render_cli_run(render_cli_t *c, FILE *log)
{
    scene_t sc;
    pp5_status_t st = render_cli_load_input(c, &sc, log);
    if (st != PP5_OK)
        return st;
    render_settings_t s = c->settings;
    if (!c->have_tf)
        c->tf = sc.tf;
    if (!c->have_rot) {
        s.view.rot_x_deg = sc.rot_x_deg;
        s.view.rot_y_deg = sc.rot_y_deg;
        s.view.rot_z_deg = sc.rot_z_deg;
    }
    if (!c->have_gaze) {
        s.gaze_x = 0.5 * (s.width - 1);
        s.gaze_y = 0.5 * (s.height - 1);
    }
    gaze_model_t check;       /* refuse a bad display before the costly build */
    st = gaze_model_init(&check, &s.display, s.width, s.height);
    if (st != PP5_OK) {
        scene_free(&sc);
        return st;
    }
    native_renderer_t r;
    st = native_renderer_init(&r, &sc.volume, &c->tf, &c->shade, s.threads);
    if (st != PP5_OK) {
        scene_free(&sc);
        return st;
    }
    fprintf(log, "volume: %s (%dx%dx%d, values %g..%g), tf %s, lighting %s\n",
            sc.volume.source, sc.volume.nx, sc.volume.ny, sc.volume.nz, sc.volume.min_value,
            sc.volume.max_value, c->tf.name, shade_case_name(c->shade.lighting));
    fprintf(log, "3D mip map: %d levels, %d floats/voxel, %.1f MB, built in %.0f ms; octree "
            "%.1f MB in %.0f ms\n", r.mip.levels, r.mip.stride, r.mip.bytes / 1e6,
            r.ms_build_mip, r.octree.bytes / 1e6, r.ms_build_octree);

    int frames = c->progressive_frames > 0 ? c->progressive_frames : 1;
    s.progressive = c->progressive_frames > 0;
    render_stats_t *stats = calloc((size_t)frames, sizeof *stats);
    image8_t img = {0};
    int frames_to_full = -1;
    for (int f = 0; st == PP5_OK && f < frames; f++) {
        image8_free(&img);
        st = native_renderer_frame(&r, &s, &img, &stats[f]);
        if (st != PP5_OK)
            break;
        fprintf(log, "frame %d (%s %dx%d, %s): %llu rays, %llu 3D samples (%llu skipped), "
                "%.1f ms (levels %.1f, cast %.1f, reconstruct %.1f)\n", f,
                render_mode_name(s.mode), s.width, s.height, projection_name(s.view.projection),
                (unsigned long long)stats[f].rays, (unsigned long long)stats[f].samples,
                (unsigned long long)stats[f].samples_skipped, stats[f].ms_total,
                stats[f].ms_levels, stats[f].ms_cast, stats[f].ms_reconstruct);
        if (frames_to_full < 0 && stats[f].full_resolution_everywhere)
            frames_to_full = f + 1;
    }
    if (st == PP5_OK && s.progressive)
        fprintf(log, "progressive: %s\n", frames_to_full > 0 ? "full resolution everywhere"
                                                              : "not yet full resolution");
    if (st == PP5_OK && s.progressive && frames_to_full > 0)
        fprintf(log, "progressive: frames to full resolution everywhere: %d\n", frames_to_full);
    if (st == PP5_OK && c->out_png)
        st = png_write(c->out_png, &img);
    if (st == PP5_OK && c->levels_prefix)
        st = render_write_mip_levels(&r.mip2d, c->levels_prefix);
    if (st == PP5_OK && c->fig5_png)
        st = render_write_fig5(&r.gaze, c->fig5_png);

    quality_t q;
    render_stats_t full_stats = {0};
    bool have_q = false;
    if (st == PP5_OK && c->compare) {
        render_settings_t fs = s;
        fs.mode = RENDER_MODE_FULL;
        fs.progressive = false;
        image8_t ref = {0};
        native_renderer_t r2;
        st = native_renderer_init(&r2, &sc.volume, &c->tf, &c->shade, s.threads);
        if (st == PP5_OK) {
            st = native_renderer_frame(&r2, &fs, &ref, &full_stats);
            native_renderer_free(&r2);
        }
        if (st == PP5_OK)
            st = quality_compare(&img, &ref, &r.gaze, s.gaze_x, s.gaze_y, &q);
        if (st == PP5_OK) {
            have_q = true;
            fprintf(log, "full resolution: %llu rays, %llu 3D samples, %.1f ms\n",
                    (unsigned long long)full_stats.rays, (unsigned long long)full_stats.samples,
                    full_stats.ms_total);
            fprintf(log, "quality vs full resolution: PSNR %.2f dB, acuity-weighted PSNR "
                    "%.2f dB, max channel error %.0f\n", q.psnr_db, q.aw_psnr_db, q.max_abs);
        }
        image8_free(&ref);
    }
    if (st == PP5_OK && c->report_json) {
        FILE *f = fopen(c->report_json, "w");
        if (!f) {
            st = pp5_fail(PP5_E_IO, "%s: cannot write report", c->report_json);
        } else {
            json_writer_t j;
            json_init(&j, f, true);
            json_begin_object(&j);
            json_kv_string(&j, "renderer", "native gaze-directed (Levoy & Whitaker 1990)");
            json_key(&j, "volume");
            json_begin_object(&j);
            json_kv_string(&j, "source", sc.volume.source);
            json_kv_int(&j, "nx", sc.volume.nx);
            json_kv_int(&j, "ny", sc.volume.ny);
            json_kv_int(&j, "nz", sc.volume.nz);
            json_kv_bool(&j, "fell_back_to_phantom", sc.fell_back);
            json_end_object(&j);
            json_key(&j, "settings");
            json_begin_object(&j);
            json_kv_string(&j, "mode", render_mode_name(s.mode));
            json_kv_int(&j, "width", s.width);
            json_kv_int(&j, "height", s.height);
            json_kv_double(&j, "gaze_x", s.gaze_x);
            json_kv_double(&j, "gaze_y", s.gaze_y);
            json_kv_string(&j, "projection", projection_name(s.view.projection));
            json_kv_double(&j, "rot_x_deg", s.view.rot_x_deg);
            json_kv_double(&j, "rot_y_deg", s.view.rot_y_deg);
            json_kv_double(&j, "rot_z_deg", s.view.rot_z_deg);
            json_kv_double(&j, "zoom", s.view.zoom);
            json_kv_double(&j, "sample_step", s.view.sample_step);
            json_kv_double(&j, "early_termination", s.view.early_termination);
            json_kv_bool(&j, "octree", s.view.use_octree);
            json_kv_string(&j, "transfer_function", c->tf.name);
            json_kv_string(&j, "lighting", shade_case_name(c->shade.lighting));
            json_kv_double(&j, "monitor_diag_in", s.display.monitor_diag_in);
            json_kv_double(&j, "view_distance_in", s.display.view_distance_in);
            json_kv_double(&j, "image_subtense_deg", s.display.image_subtense_deg);
            json_kv_double(&j, "inches_per_px", r.gaze.inches_per_px);
            json_kv_double(&j, "sigma_deg", r.gaze.sigma_deg);
            json_kv_double(&j, "full_res_radius_px", gaze_radius_px(&r.gaze, r.gaze.e_full_deg));
            json_kv_double(&j, "periphery_radius_px", gaze_radius_px(&r.gaze, r.gaze.e_edge_deg));
            json_end_object(&j);
            json_key(&j, "preprocessing");
            json_begin_object(&j);
            json_kv_int(&j, "mip3d_levels", r.mip.levels);
            json_kv_int(&j, "mip3d_floats_per_voxel", r.mip.stride);
            json_kv_uint(&j, "mip3d_bytes", r.mip.bytes);
            json_end_object(&j);
            json_key(&j, "frames");
            json_begin_array(&j);
            for (int f2 = 0; f2 < frames; f2++) {
                json_begin_object(&j);
                report_stats(&j, "stats", &stats[f2]);
                json_end_object(&j);
            }
            json_end_array(&j);
            report_stats(&j, "last_frame", &stats[frames - 1]);
            if (s.progressive)
                json_kv_int(&j, "frames_to_full_resolution", frames_to_full);
            if (have_q) {
                report_stats(&j, "full_resolution_reference", &full_stats);
                json_key(&j, "quality");
                json_begin_object(&j);
                json_kv_double(&j, "psnr_db", q.psnr_db);
                json_kv_double(&j, "acuity_weighted_psnr_db", q.aw_psnr_db);
                json_kv_double(&j, "mse", q.mse);
                json_kv_double(&j, "acuity_weighted_mse", q.aw_mse);
                json_kv_double(&j, "max_channel_error", q.max_abs);
                json_end_object(&j);
            }
            report_host_timing(&j, &r, s.threads > 0 ? s.threads : r.threads, stats, frames,
                               &full_stats, have_q);
            json_end_object(&j);
            fputc('\n', f);
            if (fclose(f) != 0)
                st = pp5_fail(PP5_E_IO, "%s: write failed", c->report_json);
        }
    }
    image8_free(&img);
    free(stats);
    native_renderer_free(&r);
    scene_free(&sc);
    return st;
}
