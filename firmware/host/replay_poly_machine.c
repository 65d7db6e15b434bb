/* replay_poly_machine.c: the emulated Pixel-Planes 5 drawing a polygon scene
 * with levels of detail chosen by the gaze, as the frame-cost source
 * "polygons" of `pp5 replay` (--cost polygons:scene=FILE, or --scene FILE).
 *
 * Every replayed frame is a real frame of the polygon GP program
 * (firmware/gp/poly_gp.c) on the machine model (poly_session_frame): its
 * emulated time and ring bytes come from the emulator.  Per frame the host
 * picks each object's level of detail for the gaze (mesh_lod_choose, the
 * rule of render/mesh/mesh_lod.h, as `pp5 render --scene --mode gaze` does)
 * and, when the levels differ from the previous frame's, flattens the scene
 * at the new levels and gives the GPs the new triangle list
 * (poly_session_set_triangles).  lod=off draws full detail every frame.
 *
 * The cost of a new list is counted inside the frame that needs it: the
 * GP program holds one list, so the frame cannot start transforming before
 * the list has crossed the ring from the host and been stored (the GPs'
 * receive deposits are charged); the host queues it just before that
 * frame's start, so the frame's emulated time includes the transfer, and
 * its ring bytes include the list's wire bytes.  The replay's summary and
 * JSON report say how many frames carried a change, the bytes, and the mean
 * frame time with and without one.  The first list is loaded with the
 * program, before the first frame (setup, as the volume source's mip-map
 * build); host time spent choosing levels and flattening is not emulated
 * time.
 *
 * Geometry as replay_machine.c: the rendered image is shown magnified across
 * the replay's display, so a display gaze point maps to image coordinates by
 * one uniform scale about the display centre, and the acuity model
 * (render/gaze2d.h, its default 37 degrees across the image width) places
 * the eccentricities; mesh_lod_choose takes pixel indices (pixel x spans x
 * .. x + 1), hence the half-pixel shift.
 *
 * vrz=on also draws each frame into the machine's variable-resolution
 * Z-buffer (firmware/gp/poly_vrz.c) with the sweet spot at the gaze (the new
 * gaze point goes to the GPs before the frame, inside its time); off by
 * default, as it makes a frame on Pixel-Planes 5 slower, not faster
 * (firmware/ARCHITECTURE.md "Variable-resolution Z-buffer").
 *
 * Each object keeps its own colour (poly_soup.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cliopt.h"
#include "firmware/host/poly_soup.h"
#include "firmware/host/replay_options.h"
#include "firmware/host/replay_poly_machine.h"
#include "render/mesh/mesh_lod.h"
#include "tracker/replay.h"

#define SOURCE "--cost polygons"

typedef struct {
    char path[512];
    bool is_mesh;                 /* mesh= (a mesh file or gen:NAME), else scene= */
    int width, height;
    raster_shading_t shading;
    bool lod;
    bool vrz;             /* the variable-resolution Z-buffer (firmware/gp/poly_vrz.c) */
    bool level_tables;    /* its 2DLevel by the paper's tables (default), else exact */
    replay_machine_params_t mp;
} poly_cost_opts_t;

typedef struct {
    poly_cost_opts_t o;
    pp5_params_t params;
    mesh_scene_t scene;
    bool scene_ok;
    raster_camera_t cam;
    mesh_render_opts_t ropts;
    gaze_model_t g;
    mesh_soup_t full;             /* the scene at full detail (style, lod=off) */
    int *levels, *prev_levels;
    poly_session_t session;
    bool session_ok;
    image8_t image;
    double display_cx, display_cy, image_per_display_px;
    replay_poly_frame_info_t last;
    /* over the frames so far */
    size_t changes, tris_min, tris_max;
    uint64_t upload_bytes;
    double frames_s, changed_frames_s;
} poly_cost_t;

static pp5_status_t parse_on_off(const char *key, const char *value, bool *out)
{
    if (strcmp(value, "on") == 0 || strcmp(value, "off") == 0) {
        *out = strcmp(value, "on") == 0;
        return PP5_OK;
    }
    return pp5_fail(PP5_E_CONFIG, SOURCE ": %s=%s: expected on or off", key, value);
}

static pp5_status_t parse_shading(const char *value, raster_shading_t *out)
{
    static const char *const names[] = {"flat", "gouraud", "phong"};
    for (int i = 0; i < 3; i++)
        if (strcmp(value, names[i]) == 0) {
            *out = (raster_shading_t)i;
            return PP5_OK;
        }
    return pp5_fail(PP5_E_CONFIG, SOURCE ": shading=%s: expected flat, gouraud or phong", value);
}

/* One KEY=VALUE item: the source's own keys, preset=, or a machine parameter. */
static pp5_status_t parse_item(void *ctx, const char *item)
{
    poly_cost_opts_t *o = ctx;
    const char *eq = strchr(item, '=');
    if (!eq || eq == item)
        return pp5_fail(PP5_E_CONFIG, SOURCE ": expected KEY=VALUE, got '%s' (keys: scene, mesh, "
                        "size, shading, lod, vrz, level_tables, preset, or a machine parameter)", item);
    size_t klen = (size_t)(eq - item);
    const char *value = eq + 1;
    char key[32];
    snprintf(key, sizeof key, "%.*s", klen < sizeof key ? (int)klen : (int)sizeof key - 1, item);
    if (strcmp(key, "scene") == 0 || strcmp(key, "mesh") == 0) {
        if (!value[0] || strlen(value) >= sizeof o->path)
            return pp5_fail(PP5_E_CONFIG, SOURCE ": %s= wants a file name", key);
        snprintf(o->path, sizeof o->path, "%s", value);
        o->is_mesh = strcmp(key, "mesh") == 0;
        return PP5_OK;
    }
    if (strcmp(key, "size") == 0)
        return cliopt_size2(SOURCE ": size", value, 16, 1280, &o->width, &o->height);
    if (strcmp(key, "shading") == 0)
        return parse_shading(value, &o->shading);
    if (strcmp(key, "lod") == 0)
        return parse_on_off(key, value, &o->lod);
    if (strcmp(key, "vrz") == 0)
        return parse_on_off(key, value, &o->vrz);
    if (strcmp(key, "level_tables") == 0)
        return parse_on_off(key, value, &o->level_tables);
    if (strcmp(key, "preset") == 0) {
        snprintf(o->mp.preset, sizeof o->mp.preset, "%s", value);
        return PP5_OK;
    }
    pp5_status_t st = replay_machine_params_unwrap(SOURCE, &item);
    if (st != PP5_OK || replay_machine_params_add(&o->mp, item))
        return st;
    return pp5_fail(PP5_E_CONFIG, SOURCE ": too many machine parameters (at %s)", item);
}

static pp5_status_t parse_options(const char *text, poly_cost_opts_t *o)
{
    memset(o, 0, sizeof *o);
    o->width = o->height = 256;
    o->shading = RASTER_GOURAUD;
    o->lod = true;
    o->level_tables = true;
    replay_machine_params_init(&o->mp);
    pp5_status_t st = replay_options_each(SOURCE, text, parse_item, o);
    if (st == PP5_OK && !o->path[0])
        st = pp5_fail(PP5_E_CONFIG, SOURCE ": give scene=FILE (a scene file or gen:spheres100k) "
                      "or mesh=FILE (a mesh file or gen:NAME)");
    return st;
}

static void poly_cost_close(void *ctx)
{
    poly_cost_t *c = ctx;
    if (!c)
        return;
    if (c->session_ok)
        poly_session_free(&c->session);
    if (c->scene_ok)
        mesh_scene_free(&c->scene);
    mesh_soup_free(&c->full);
    image8_free(&c->image);
    free(c->levels);
    free(c->prev_levels);
    free(c);
}

/* The scene, its camera, light and acuity model, and its full-detail list. */
static pp5_status_t load_scene(poly_cost_t *c)
{
    const poly_cost_opts_t *o = &c->o;
    pp5_status_t st = o->is_mesh ? mesh_scene_load_mesh(o->path, &c->scene)
                                 : mesh_scene_load(o->path, &c->scene);
    if (st != PP5_OK)
        return st;
    c->scene_ok = true;
    mesh_scene_camera(&c->scene, (double)o->width / o->height, &c->cam);
    mesh_render_opts_from_scene(&c->scene, &c->cam, o->shading, &c->ropts);
    gaze_display_t d;
    gaze_display_defaults(&d);
    st = gaze_model_init(&c->g, &d, o->width, o->height);
    if (st == PP5_OK)
        st = mesh_scene_flatten(&c->scene, NULL, &c->full);
    if (st == PP5_OK && c->full.n_tris == 0)
        st = pp5_fail(PP5_E_FORMAT, "%s: the scene has no triangles", o->path);
    if (st == PP5_OK && o->lod)
        st = mesh_scene_build_records(&c->scene);
    size_t n = (size_t)c->scene.n_objects + 1;
    if (st == PP5_OK && (!(c->levels = calloc(n, sizeof *c->levels)) ||
                         !(c->prev_levels = calloc(n, sizeof *c->prev_levels))))
        st = pp5_fail(PP5_E_NOMEM, SOURCE ": out of memory for %zu levels", n);
    return st;
}

static pp5_status_t poly_cost_open(const char *options, const gaze_geometry_t *display,
                                   void **ctx)
{
    poly_cost_t *c = calloc(1, sizeof *c);
    if (!c)
        return pp5_fail(PP5_E_NOMEM, SOURCE ": out of memory");
    pp5_status_t st = parse_options(options, &c->o);
    if (st == PP5_OK && (display->width_px <= 0 || display->height_px <= 0))
        st = pp5_fail(PP5_E_CONFIG, SOURCE ": the display has no size in pixels");
    if (st == PP5_OK)
        st = replay_machine_params_build(&c->o.mp, &c->params);
    if (st == PP5_OK)
        st = load_scene(c);
    if (st != PP5_OK) {
        poly_cost_close(c);
        return st;
    }
    c->display_cx = 0.5 * display->width_px;
    c->display_cy = 0.5 * display->height_px;
    c->image_per_display_px = (double)c->o.width / display->width_px;
    fprintf(stderr, "polygons: %s, %d objects, %d triangles at full detail, %dx%d image, %s, "
            "levels of detail %s, variable-resolution Z-buffer %s\n", c->scene.source,
            c->scene.n_objects, c->full.n_tris, c->o.width, c->o.height,
            poly_shading_name((poly_shading_t)c->o.shading), c->o.lod ? "on" : "off",
            c->o.vrz ? "on" : "off");
    *ctx = c;
    return PP5_OK;
}

/* The list for this frame's levels to the machine: with the program before
 * the first frame, as a replacement later. */
static pp5_status_t send_list(poly_cost_t *c, const int *levels)
{
    mesh_soup_t lod = {0};
    const mesh_soup_t *list = &c->full;
    pp5_status_t st = PP5_OK;
    if (levels) {
        st = mesh_scene_flatten(&c->scene, levels, &lod);
        list = &lod;
    }
    poly_tri_in_t *tris = NULL;
    if (st == PP5_OK)
        st = poly_triangles_from_soup(list, &tris);
    if (st == PP5_OK && !c->session_ok) {
        raster_style_t style;
        poly_options_t po;
        poly_style_from_render_opts(&c->ropts, &c->full, &style, &po);
        po.gaze = c->o.vrz;
        po.level_tables = c->o.level_tables;
        po.gaze_model = c->g;
        po.gaze_x = 0.5 * (c->o.width - 1), po.gaze_y = 0.5 * (c->o.height - 1);
        st = poly_session_init(&c->session, &c->params, tris, (size_t)list->n_tris, c->o.width,
                               c->o.height, &c->cam, &style, &po);
        c->session_ok = true;   /* poly_session_free undoes a partial init */
    } else if (st == PP5_OK) {
        st = poly_session_set_triangles(&c->session, tris, (size_t)list->n_tris);
        c->last.list_changed = true;
        c->last.upload_ring_bytes = c->session.upload_ring_bytes;
    }
    c->last.triangles = (size_t)list->n_tris;
    free(tris);
    mesh_soup_free(&lod);
    return st;
}

/* Chooses the levels for the gaze (image pixel indices) and sends a new
 * list when they changed (or before the first frame). */
static pp5_status_t update_list(poly_cost_t *c, double ix, double iy)
{
    bool first = !c->session_ok;
    c->last.list_changed = false;
    c->last.upload_ring_bytes = 0;
    if (!c->o.lod)
        return first ? send_list(c, NULL) : PP5_OK;
    long faces = 0;
    mesh_lod_choose(&c->scene, &c->cam, &c->g, ix, iy, c->levels, &faces);
    size_t bytes = (size_t)c->scene.n_objects * sizeof *c->levels;
    if (!first && memcmp(c->levels, c->prev_levels, bytes) == 0)
        return PP5_OK;
    memcpy(c->prev_levels, c->levels, bytes);
    return send_list(c, c->levels);
}

static void count_frame(poly_cost_t *c, double frame_s)
{
    replay_poly_frame_info_t *l = &c->last;
    l->frames++;
    l->frame_s = frame_s;
    l->triangles_full = c->full.n_tris;
    c->tris_min = l->frames == 1 || l->triangles < c->tris_min ? l->triangles : c->tris_min;
    c->tris_max = l->triangles > c->tris_max ? l->triangles : c->tris_max;
    c->frames_s += frame_s;
    if (l->list_changed) {
        c->changes++;
        c->upload_bytes += l->upload_ring_bytes;
        c->changed_frames_s += frame_s;
    }
    /* Long traces take minutes of host time: say how far we are (on a
     * terminal only, so logs and tests stay clean). */
    if (l->frames % 25 == 0 && isatty(STDERR_FILENO))
        fprintf(stderr, "polygons: %zu frames emulated (%.1f s of trace time)\r", l->frames,
                c->frames_s);
}

static pp5_status_t poly_cost_frame(void *ctx, double gaze_x, double gaze_y,
                                    replay_frame_cost_t *out)
{
    poly_cost_t *c = ctx;
    double ix = (gaze_x - c->display_cx) * c->image_per_display_px + 0.5 * c->o.width - 0.5;
    double iy = (gaze_y - c->display_cy) * c->image_per_display_px + 0.5 * c->o.height - 0.5;
    pp5_status_t st = update_list(c, ix, iy);
    if (st == PP5_OK && c->o.vrz)
        st = poly_session_set_gaze(&c->session, ix, iy);
    poly_frame_result_t r;
    image8_free(&c->image);
    if (st == PP5_OK)
        st = poly_session_frame(&c->session, out->want_image ? &c->image : NULL, &r);
    if (st != PP5_OK)
        return st;
    out->frame_s = r.frame_time_s;
    out->rays = 0;   /* polygons: no rays */
    out->ring_bytes = r.ring_bytes_total + c->last.upload_ring_bytes;
    out->image = out->want_image ? &c->image : NULL;
    count_frame(c, r.frame_time_s);
    return PP5_OK;
}

pp5_status_t replay_poly_last_frame(const void *ctx, replay_poly_frame_info_t *out)
{
    const poly_cost_t *c = ctx;
    if (!c || c->last.frames == 0)
        return pp5_fail(PP5_E_CONFIG, SOURCE ": no frame yet");
    *out = c->last;
    return PP5_OK;
}

static double mean_or_zero(double sum, size_t n)
{
    return n ? sum / (double)n : 0;
}

static void poly_cost_describe(void *ctx, FILE *out)
{
    const poly_cost_t *c = ctx;
    size_t n = c->last.frames, steady = n - c->changes;
    fprintf(out, "  triangles a frame: %zu..%zu (full detail %d; levels of detail %s)\n",
            c->tris_min, c->tris_max, c->full.n_tris, c->o.lod ? "on" : "off");
    /* the source's own count: the replay may emulate one frame more than it
     * keeps (one that ends past the trace) */
    fprintf(out, "  triangle list changed before %zu of %zu frames emulated: %llu bytes over the "
            "ring, counted inside those frames (time and ring bytes); mean frame %.2f ms with "
            "a change, %.2f ms without\n", c->changes, n, (unsigned long long)c->upload_bytes,
            mean_or_zero(c->changed_frames_s, c->changes) * 1e3,
            mean_or_zero(c->frames_s - c->changed_frames_s, steady) * 1e3);
}

static void poly_cost_json(void *ctx, json_writer_t *j)
{
    const poly_cost_t *c = ctx;
    size_t n = c->last.frames, steady = n - c->changes;
    json_kv_string(j, "scene", c->scene.source);
    json_kv_int(j, "triangles_full_detail", c->full.n_tris);
    json_kv_bool(j, "levels_of_detail", c->o.lod);
    json_kv_bool(j, "variable_resolution_z", c->o.vrz);
    json_kv_uint(j, "triangles_min", c->tris_min);
    json_kv_uint(j, "triangles_max", c->tris_max);
    json_kv_uint(j, "frames_emulated", n);
    json_kv_uint(j, "list_changes", c->changes);
    json_kv_uint(j, "list_change_ring_bytes", c->upload_bytes);
    json_kv_string(j, "list_change_cost", "inside the frame times and ring bytes");
    json_kv_double(j, "mean_frame_ms_with_change", mean_or_zero(c->changed_frames_s, c->changes) * 1e3);
    json_kv_double(j, "mean_frame_ms_without_change",
                   mean_or_zero(c->frames_s - c->changed_frames_s, steady) * 1e3);
}

static const replay_cost_source_t poly_cost_source = {
    .name = "polygons",
    .summary = "the emulated Pixel-Planes 5 drawing a polygon scene, levels of detail chosen "
               "by the gaze; a changed triangle list's transfer is inside its frame's time "
               "(options: scene=FILE|mesh=FILE,size=WxH,shading=flat|gouraud|phong,lod=on|off,"
               "vrz=on|off (default off),level_tables=on|off,preset=NAME, PARAM=VALUE or set=PARAM=VALUE as pp5 machine --set)",
    .open = poly_cost_open,
    .cost = poly_cost_frame,
    .close = poly_cost_close,
    .describe = poly_cost_describe,
    .report_json = poly_cost_json,
};

__attribute__((constructor)) static void poly_cost_register(void)
{
    replay_register_cost_source(&poly_cost_source);
}
