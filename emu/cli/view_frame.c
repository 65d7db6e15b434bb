/* view_frame.c: one frame of the viewer: the gaze the latency model gives, the native frame, the emulated machine's cost (or pixels) of the same frame, and the window's picture with its overlays and heads-up display, drawn with cairo (view.h). */
#include <cairo.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "plot.h"
#include "view.h"

static double host_now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

pp5_status_t viewer_init(viewer_t *v, const view_options_t *opt, const render_job_t *job)
{
    memset(v, 0, sizeof *v);
    v->opt = opt;
    v->job = job;
    v->settings = job->settings;
    v->home = job->settings.view;
    v->progressive = false;
    v->settings.progressive = false;
    v->circles = opt->circles;
    v->levels = opt->levels;
    v->hud = opt->hud;
    v->mouse_x = job->settings.gaze_x;
    v->mouse_y = job->settings.gaze_y;
    int n;
    const view_mode_t *m = view_modes(&n);
    for (int i = 0; i < n; i++)
        if (m[i].mode == job->settings.mode)
            v->mode_index = i;
    replay_defaults(&v->latency);
    plot_text_setup();   /* the HUD's text */
    size_t px = (size_t)job->settings.width * (size_t)job->settings.height;
    v->argb = calloc(px, sizeof *v->argb);
    if (!v->argb)
        return pp5_fail(PP5_E_NOMEM, "view: out of memory");
    pp5_status_t st = native_renderer_init(&v->native, job->volume, &job->tf, &job->shade,
                                           job->settings.threads);
    if (st != PP5_OK)
        return st;
    double distance_px = job->settings.display.view_distance_in / v->native.gaze.inches_per_px;
    st = view_gaze_open(&v->gaze, opt->gaze_from, job->settings.width, job->settings.height,
                        distance_px);
    if (st == PP5_OK && (opt->machine_cost || opt->cmd.machine))
        st = view_machine_start(&v->machine, job, &opt->cmd, opt->cmd.machine);
    return st;
}

void viewer_free(viewer_t *v)
{
    view_machine_stop(&v->machine);
    view_gaze_close(&v->gaze);
    native_renderer_free(&v->native);
    image8_free(&v->image);
    free(v->argb);
    v->argb = NULL;
}

/* The gaze for a frame at now_s: the replay's rule over the gaze history
 * (its tracker latency for the mouse and traces; a live tracker has its own). */
static void frame_gaze(viewer_t *v, double now_s)
{
    bool have_rot = false;
    float rot[3];
    if (v->gaze.kind == VIEW_GAZE_MOUSE)
        view_gaze_history_add(&v->history, now_s, v->mouse_x, v->mouse_y);
    view_gaze_poll(&v->gaze, now_s, &v->history, &have_rot, rot);
    if (have_rot) {
        v->settings.view.rot_x_deg = v->home.rot_x_deg + rot[0];
        v->settings.view.rot_y_deg = v->home.rot_y_deg + rot[1];
        v->settings.view.rot_z_deg = v->home.rot_z_deg + rot[2];
    }
    bool live = v->gaze.kind == VIEW_GAZE_HID || v->gaze.kind == VIEW_GAZE_POLHEMUS;
    double lat = v->opt->latency && !live ? v->latency.tracker_latency_s : 0.0;
    double x, y;
    if (view_gaze_history_at(&v->history, now_s, lat, &x, &y)) {
        v->settings.gaze_x = x;
        v->settings.gaze_y = y;
    }
}

/* ---- drawing ---- */

static void draw_image(cairo_surface_t *s, const image8_t *img)
{
    unsigned char *data = cairo_image_surface_get_data(s);
    int stride = cairo_image_surface_get_stride(s);
    int w = cairo_image_surface_get_width(s), h = cairo_image_surface_get_height(s);
    for (int y = 0; y < h && y < img->height; y++)
        for (int x = 0; x < w && x < img->width; x++) {
            const uint8_t *p = img->pixels + ((size_t)y * img->width + x) * 3;
            uint32_t v = 0xff000000u | (uint32_t)p[0] << 16 | (uint32_t)p[1] << 8 | p[2];
            memcpy(data + (size_t)y * stride + 4 * (size_t)x, &v, 4);
        }
    cairo_surface_mark_dirty(s);
}

/* The 12-degree circle (full resolution inside) in yellow and the 20-degree
 * one (periphery resolution outside) in cyan, paper section 5. */
static void draw_circles(cairo_t *cr, const viewer_t *v)
{
    const gaze_model_t *g = &v->native.gaze;
    double gx = v->settings.gaze_x + 0.5, gy = v->settings.gaze_y + 0.5;
    cairo_set_line_width(cr, 3.0);
    cairo_set_source_rgb(cr, 1, 1, 0);
    cairo_new_sub_path(cr);
    cairo_arc(cr, gx, gy, gaze_radius_px(g, g->e_full_deg), 0, 2 * M_PI);
    cairo_stroke(cr);
    static const double dash[2] = {8, 6};
    cairo_set_dash(cr, dash, 2, 0);
    cairo_set_source_rgb(cr, 0, 1, 1);
    cairo_new_sub_path(cr);
    cairo_arc(cr, gx, gy, gaze_radius_px(g, g->e_edge_deg), 0, 2 * M_PI);
    cairo_stroke(cr);
    cairo_set_dash(cr, NULL, 0, 0);
}

/* Figure 6 as an overlay: each level of the 2D mip map along the bottom,
 * texels whose ray was cast in colour, the others dark gray. */
static void draw_levels(cairo_t *cr, const viewer_t *v, double font)
{
    const mip2d_t *m = &v->native.mip2d;
    int W = v->settings.width, H = v->settings.height;
    double box = fmin(H / 5.0, (W - 8.0) / (m->levels > 0 ? m->levels : 1) - 6), x = 4;
    for (int l = 0; l < m->levels && box > 8; l++) {
        double sx = box / m->w[l], sy = box / m->h[l], sc = fmin(sx, sy);
        double y0 = H - 4 - m->h[l] * sc;
        for (int j = 0; j < m->h[l]; j++)
            for (int i = 0; i < m->w[l]; i++) {
                size_t k = (size_t)j * m->w[l] + i;
                if (m->cast[l][k])
                    cairo_set_source_rgb(cr, m->rgb[l][3 * k], m->rgb[l][3 * k + 1],
                                         m->rgb[l][3 * k + 2]);
                else
                    cairo_set_source_rgb(cr, 40 / 255.0, 40 / 255.0, 40 / 255.0);
                cairo_rectangle(cr, x + i * sc, y0 + j * sc, sc + 0.02, sc + 0.02);
                cairo_fill(cr);
            }
        cairo_set_source_rgb(cr, 1, 1, 1);
        cairo_move_to(cr, x + 2, y0 - 3);
        char label[32];
        snprintf(label, sizeof label, "level %d", l);
        cairo_set_font_size(cr, font);
        cairo_show_text(cr, label);
        x += m->w[l] * sc + 6;
    }
}

/* The emulated machine's two lines: its figure for this frame, the last one
 * it managed (and how far behind), or why there is none.  Two lines, so that
 * a 512-pixel window shows all of it. */
static void machine_lines(viewer_t *v, char *buf, char *buf2, char *buf3, size_t n,
                          double *frame_s)
{
    *frame_s = NAN;
    buf2[0] = buf3[0] = '\0';
    if (!v->machine.started) {
        snprintf(buf, n, "emulated Pixel-Planes 5: off (--no-machine-cost)");
        return;
    }
    view_machine_answer_t a;
    char status[256];
    bool busy;
    view_machine_peek(&v->machine, &a, status, sizeof status, &busy);
    if (!a.valid) {
        snprintf(buf, n, "emulated Pixel-Planes 5: %s", status[0] ? status : "starting");
        return;
    }
    const fw_frame_result_t *r = &a.result;
    *frame_s = r->frame_time_s;
    snprintf(buf, n, "emulated Pixel-Planes 5: %.1f ms (%.2f frames/s), ring %.1f %%",
             r->frame_time_s * 1e3, r->frame_time_s > 0 ? 1 / r->frame_time_s : 0.0,
             100 * r->ring_util_total);
    snprintf(buf2, n, "  %llu rays, %.3g samples; %s", (unsigned long long)r->rays,
             (double)r->samples, r->bottleneck);
    long behind = v->frame - a.frame;
    int len = 0;
    if (behind > 0)
        len = snprintf(buf3, n, "  cannot keep up: the figure of frame %ld, %ld behind", a.frame,
                       behind);
    if (status[0] && len >= 0 && (size_t)len < n)
        snprintf(buf3 + len, n - (size_t)len, "  [%s]", status);
}

static void draw_hud(cairo_t *cr, viewer_t *v, double font)
{
    char lines[VIEW_HUD_LINES][400];
    int n;
    const view_mode_t *m = view_modes(&n);
    snprintf(lines[0], sizeof lines[0], "pixels: %s | mode: %s | progressive %s | frame %ld",
             v->pixels_from, m[v->mode_index].name, v->progressive ? "on" : "off", v->frame);
    snprintf(lines[1], sizeof lines[1], "host: %.1f ms this frame, %.1f frames/s; %llu rays, "
             "%.3g samples", v->host_frame_s * 1e3, v->host_fps,
             (unsigned long long)v->stats.rays, (double)v->stats.samples);
    double emu_s;
    machine_lines(v, lines[2], lines[3], lines[4], sizeof lines[2], &emu_s);
    const replay_params_t *L = &v->latency;
    if (isnan(emu_s))
        snprintf(lines[5], sizeof lines[5], "latency (replay's model): tracker %.0f ms + frame ? + "
                 "display %.0f ms", L->tracker_latency_s * 1e3, L->display_latency_s * 1e3);
    else
        snprintf(lines[5], sizeof lines[5], "latency (replay's model): tracker %.0f + frame %.0f + "
                 "display %.0f = %.0f ms", L->tracker_latency_s * 1e3, emu_s * 1e3,
                 L->display_latency_s * 1e3,
                 (L->tracker_latency_s + emu_s + L->display_latency_s) * 1e3);
    view_gaze_describe(&v->gaze, lines[6], sizeof lines[6]);
    size_t used = strlen(lines[6]);
    snprintf(lines[6] + used, sizeof lines[6] - used, " (%.0f, %.0f)", v->settings.gaze_x,
             v->settings.gaze_y);
    snprintf(lines[7], sizeof lines[7], "keys: f/g/m mode  p progressive  c circles  l levels  "
             "h HUD  s shot  q quit");
    memcpy(v->hud_text, lines, sizeof v->hud_text);
    cairo_select_font_face(cr, "DejaVu Sans Mono", CAIRO_FONT_SLANT_NORMAL,
                           CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, font);
    double wmax = 0;
    int shown = 0;
    for (int i = 0; i < VIEW_HUD_LINES; i++) {
        cairo_text_extents_t e;
        cairo_text_extents(cr, lines[i], &e);
        wmax = fmax(wmax, e.x_advance);
    }
    for (int i = 0; i < VIEW_HUD_LINES; i++)
        shown += lines[i][0] != '\0';
    cairo_set_source_rgba(cr, 0, 0, 0, 0.6);
    cairo_rectangle(cr, 0, 0, wmax + 12, shown * font * 1.3 + 8);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 1, 1, 1);
    for (int i = 0, row = 0; i < VIEW_HUD_LINES; i++) {
        if (lines[i][0] == '\0')
            continue;
        cairo_move_to(cr, 6, 4 + font * (1.3 * row++ + 1.0));
        cairo_show_text(cr, lines[i]);
    }
}

void viewer_recompose(viewer_t *v)
{
    int W = v->settings.width, H = v->settings.height;
    cairo_surface_t *s = cairo_image_surface_create_for_data((unsigned char *)v->argb,
                                                             CAIRO_FORMAT_RGB24, W, H, W * 4);
    draw_image(s, &v->image);
    cairo_t *cr = cairo_create(s);
    double font = W >= 700 ? 12 : W >= 400 ? 10 : 8;
    if (v->circles && v->settings.mode == RENDER_MODE_GAZE)
        draw_circles(cr, v);
    if (v->levels)
        draw_levels(cr, v, font);
    if (v->hud)
        draw_hud(cr, v, font);
    cairo_destroy(cr);
    cairo_surface_flush(s);
    cairo_surface_destroy(s);
}

static void ask_machine(viewer_t *v)
{
    if (!v->machine.started)
        return;
    view_machine_request_t r = {v->settings.gaze_x, v->settings.gaze_y, v->settings.view,
                                v->settings.mode, v->settings.progressive, v->frame};
    view_machine_request(&v->machine, &r);
    if (v->opt->frames > 0)
        view_machine_wait(&v->machine, v->frame);   /* scripts: each frame's own figure */
}

pp5_status_t viewer_frame(viewer_t *v, double now_s)
{
    v->frame++;
    frame_gaze(v, now_s);
    double t0 = host_now_s();
    image8_t img = {0};
    pp5_status_t st = native_renderer_frame(&v->native, &v->settings, &img, &v->stats);
    if (st != PP5_OK)
        return st;
    v->host_frame_s = host_now_s() - t0;
    v->host_fps = v->host_fps > 0 ? 0.8 * v->host_fps + 0.2 / fmax(v->host_frame_s, 1e-6)
                                  : 1 / fmax(v->host_frame_s, 1e-6);
    ask_machine(v);
    image8_t mimg;
    long mframe;
    if (v->opt->cmd.machine && view_machine_take_image(&v->machine, &mimg, &mframe)) {
        image8_free(&v->image);
        v->image = mimg;
        v->machine_image_frame = mframe;
    }
    if (v->opt->cmd.machine && v->machine_image_frame > 0) {
        v->pixels_from = "emulated Pixel-Planes 5 (firmware/, --machine)";
        image8_free(&img);
    } else {
        v->pixels_from = v->opt->cmd.machine ? "native renderer until the emulator's first frame"
                                             : "native renderer (render/)";
        image8_free(&v->image);
        v->image = img;
    }
    viewer_recompose(v);
    return PP5_OK;
}

pp5_status_t viewer_screenshot(const viewer_t *v, const char *path)
{
    int W = v->settings.width, H = v->settings.height;
    image8_t img;
    pp5_status_t st = image8_alloc(&img, W, H, 3);
    if (st != PP5_OK)
        return st;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        img.pixels[3 * i] = (uint8_t)(v->argb[i] >> 16);
        img.pixels[3 * i + 1] = (uint8_t)(v->argb[i] >> 8);
        img.pixels[3 * i + 2] = (uint8_t)v->argb[i];
    }
    st = png_write(path, &img);
    image8_free(&img);
    return st;
}
