/* render_mesh.c: `pp5 render --mesh FILE | --scene FILE`, natively: one frame
 * of a polygon scene, at full resolution or gaze-directed (levels of detail
 * by eccentricity and the variable-resolution Z-buffer), with the savings
 * table against full detail at full resolution (--compare). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"
#include "outfile.h"
#include "render/mesh/mesh_lod.h"
#include "render/mesh/mesh_render.h"
#include "render/quality.h"
#include "render_cmd.h"

/* One variant of the frame: its image, counts, and quality against full. */
typedef struct {
    const char *name, *what;
    image8_t img;
    mesh_render_stats_t st;
    quality_t q;
    bool done;
} variant_t;

enum { V_FULL, V_LOD, V_VRZ, V_BOTH, N_VARIANTS };

typedef struct {
    const render_cmd_t *c;
    mesh_scene_t scene;
    raster_camera_t cam;
    mesh_render_opts_t opts;
    gaze_model_t g;
    int width, height;
    double gaze_x, gaze_y;
    long faces_full, faces_lod;
    double records_ms, lod_ms;    /* building the records (once); choosing and extracting levels */
    double flatten_ms;            /* making the full-detail triangle list */
    variant_t v[N_VARIANTS];
} mesh_run_t;

static const char *shading_name(raster_shading_t s)
{
    return s == RASTER_PHONG ? "phong" : s == RASTER_GOURAUD ? "gouraud" : "flat";
}

static pp5_status_t load(const render_cmd_t *c, mesh_scene_t *s)
{
    return c->scene_file ? mesh_scene_load(c->scene_file, s)
                         : mesh_scene_load_mesh(c->mesh_file, s);
}

/* Renders variant k: full or LOD triangles, full or variable-resolution Z. */
static pp5_status_t render_variant(mesh_run_t *r, int k, const mesh_soup_t *full,
                                   const mesh_soup_t *lod)
{
    variant_t *v = &r->v[k];
    const mesh_soup_t *soup = k == V_LOD || k == V_BOTH ? lod : full;
    pp5_status_t st = k == V_VRZ || k == V_BOTH
                          ? mesh_render_vrz(soup, &r->cam, &r->opts, &r->g, r->gaze_x, r->gaze_y,
                                            &v->img, &v->st)
                          : mesh_render_full(soup, &r->cam, &r->opts, r->width, r->height, &v->img,
                                             &v->st);
    v->done = st == PP5_OK;
    return st;
}

static pp5_status_t run_gaze(mesh_run_t *r, const mesh_soup_t *full, mesh_soup_t *lod)
{
    /* the collapse records are built once per mesh, before any frame */
    double t0 = mesh_render_cpu_ms();
    pp5_status_t st = mesh_scene_build_records(&r->scene);
    r->records_ms = mesh_render_cpu_ms() - t0;
    t0 = mesh_render_cpu_ms();
    int *levels = st == PP5_OK ? calloc((size_t)r->scene.n_objects + 1, sizeof *levels) : NULL;
    if (st == PP5_OK && !levels)
        st = pp5_fail(PP5_E_NOMEM, "render: out of memory for levels");
    if (st == PP5_OK) {
        mesh_lod_choose(&r->scene, &r->cam, &r->g, r->gaze_x, r->gaze_y, levels, &r->faces_lod);
        bool coarser = false;
        for (int o = 0; o < r->scene.n_objects; o++)
            coarser |= levels[o] > 0;
        /* every object at full detail: the LOD frames draw the full list */
        st = coarser ? mesh_scene_flatten(&r->scene, levels, lod) : PP5_OK;
        if (!coarser)
            lod = NULL;
    }
    free(levels);
    const mesh_soup_t *lod_list = lod ? lod : full;
    /* the LOD frames pay for their list: extraction, or the full list's flattening */
    r->lod_ms = mesh_render_cpu_ms() - t0 + (lod ? 0 : r->flatten_ms);
    for (int k = r->c->compare ? 0 : V_BOTH; k < N_VARIANTS && st == PP5_OK; k++)
        st = render_variant(r, k, full, lod_list);
    if (st == PP5_OK && r->c->compare)
        for (int k = 0; k < N_VARIANTS && st == PP5_OK; k++)
            st = quality_compare(&r->v[k].img, &r->v[V_FULL].img, &r->g, r->gaze_x, r->gaze_y,
                                 &r->v[k].q);
    /* the level choice and extraction belong to the LOD variants' time */
    r->v[V_LOD].st.cpu_ms += r->lod_ms;
    r->v[V_BOTH].st.cpu_ms += r->lod_ms;
    return st;
}

/* How many times fewer: base / x (1 when both are zero). */
static double times_fewer(double base, double x)
{
    return x > 0 ? base / x : base > 0 ? INFINITY : 1;
}

static void print_table(const mesh_run_t *r, FILE *log)
{
    const variant_t *f = &r->v[V_FULL];
    fprintf(log, "%-26s %10s %10s %11s %10s %9s %9s %8s %9s\n", "variant", "triangles", "drawn",
            "fragments", "shaded", "CPU ms", "(tri ms)", "PSNR dB", "AW-PSNR");
    for (int k = 0; k < N_VARIANTS; k++) {
        const variant_t *v = &r->v[k];
        if (!v->done)
            continue;
        fprintf(log, "%-26s %10llu %10llu %11llu %10llu %9.1f %9.1f", v->what,
                (unsigned long long)v->st.triangles_in, (unsigned long long)v->st.triangles_drawn,
                (unsigned long long)v->st.fragments, (unsigned long long)v->st.pixels_shaded,
                v->st.cpu_ms, v->st.cpu_ms_triangles);
        if (r->c->compare && k != V_FULL)
            fprintf(log, " %8.2f %9.2f\n", v->q.psnr_db, v->q.aw_psnr_db);
        else
            fprintf(log, " %8s %9s\n", "-", "-");
    }
    fprintf(log, "(CPU ms: the frame, its triangle list included; tri ms: of which transform, "
            "set-up, scan conversion and Z)\n");
    if (r->faces_lod > 0)
        fprintf(log, "levels of detail: records built once in %.1f ms CPU (not in the frame times); "
                "choosing and extracting levels %.1f ms (in the LOD frames' times)\n",
                r->records_ms, r->lod_ms);
    if (!r->c->compare || !f->done)
        return;
    fprintf(log, "saving against full detail at full resolution (triangles / fragments / shaded / "
            "CPU time):\n");
    for (int k = V_LOD; k < N_VARIANTS; k++) {
        const mesh_render_stats_t *s = &r->v[k].st;
        fprintf(log, "  %-24s %5.2fx %5.2fx %5.2fx %5.2fx\n", r->v[k].what,
                times_fewer((double)f->st.triangles_in, (double)s->triangles_in),
                times_fewer((double)f->st.fragments, (double)s->fragments),
                times_fewer((double)f->st.pixels_shaded, (double)s->pixels_shaded),
                times_fewer(f->st.cpu_ms, s->cpu_ms));
    }
}

static void json_variant(json_writer_t *j, const variant_t *v, bool quality)
{
    json_key(j, v->name);
    json_begin_object(j);
    json_kv_string(j, "what", v->what);
    json_kv_uint(j, "triangles", v->st.triangles_in);
    json_kv_uint(j, "triangles_drawn", v->st.triangles_drawn);
    json_kv_uint(j, "fragments", v->st.fragments);
    json_kv_uint(j, "pixels_shaded", v->st.pixels_shaded);
    json_kv_uint(j, "zbuffer_samples", v->st.samples);
    json_kv_double(j, "host_cpu_ms", v->st.cpu_ms);
    json_kv_double(j, "host_wall_ms_render_only", v->st.ms);
    json_kv_double(j, "host_cpu_ms_triangles", v->st.cpu_ms_triangles);
    if (quality) {
        json_kv_double(j, "psnr_db", v->q.psnr_db);
        json_kv_double(j, "aw_psnr_db", v->q.aw_psnr_db);
        json_kv_double(j, "max_abs", v->q.max_abs);
    }
    json_end_object(j);
}

static pp5_status_t write_report(const mesh_run_t *r, const char *path, int shown)
{
    outfile_t o;
    pp5_status_t st = outfile_open(&o, path, false);
    if (st != PP5_OK)
        return st;
    json_writer_t j;
    json_init(&j, o.f, true);
    json_begin_object(&j);
    json_kv_string(&j, "renderer", "native polygon renderer (render/mesh/mesh_render.h)");
    json_kv_string(&j, "input", r->scene.source);
    json_kv_int(&j, "objects", r->scene.n_objects);
    json_kv_int(&j, "meshes", r->scene.n_meshes);
    json_kv_string(&j, "shading", shading_name(r->opts.shading));
    json_kv_string(&j, "mode", r->c->choices.settings.mode == RENDER_MODE_FULL ? "full" : "gaze");
    json_kv_int(&j, "width", r->width);
    json_kv_int(&j, "height", r->height);
    json_kv_double(&j, "gaze_x", r->gaze_x);
    json_kv_double(&j, "gaze_y", r->gaze_y);
    json_kv_bool(&j, "cull_back_faces", r->opts.cull_back);
    json_kv_int(&j, "faces_full_detail", r->faces_full);
    if (shown != V_FULL) {
        json_kv_int(&j, "faces_at_chosen_levels", r->faces_lod);
        json_kv_double(&j, "host_cpu_ms_records_once", r->records_ms);
        json_kv_double(&j, "host_cpu_ms_choose_and_extract_levels", r->lod_ms);
    }
    json_variant(&j, &r->v[shown], false);
    if (r->c->compare && shown != V_FULL) {
        json_key(&j, "comparison");
        json_begin_object(&j);
        for (int k = 0; k < N_VARIANTS; k++)
            json_variant(&j, &r->v[k], true);
        json_end_object(&j);
    }
    json_end_object(&j);
    fputc('\n', o.f);
    return outfile_commit(&o);
}

static pp5_status_t setup(mesh_run_t *r, const render_cmd_t *c)
{
    static const char *const what[N_VARIANTS] = {
        "full detail, full res", "LOD, full res", "full detail, VRZ", "LOD + VRZ"};
    static const char *const names[N_VARIANTS] = {"full", "lod", "vrz", "both"};
    memset(r, 0, sizeof *r);
    r->c = c;
    for (int k = 0; k < N_VARIANTS; k++)
        r->v[k].name = names[k], r->v[k].what = what[k];
    const render_settings_t *s = &c->choices.settings;
    r->width = s->width, r->height = s->height;
    r->gaze_x = c->choices.have_gaze ? s->gaze_x : 0.5 * (s->width - 1);
    r->gaze_y = c->choices.have_gaze ? s->gaze_y : 0.5 * (s->height - 1);
    if (!isfinite(r->gaze_x) || !isfinite(r->gaze_y))
        return pp5_fail(PP5_E_CONFIG, "--gaze: the point must be finite");
    pp5_status_t st = gaze_model_init(&r->g, &s->display, r->width, r->height);
    if (st == PP5_OK)
        st = load(c, &r->scene);
    if (st != PP5_OK)
        return st;
    mesh_scene_camera(&r->scene, (double)r->width / r->height, &r->cam);
    mesh_render_opts_from_scene(&r->scene, &r->cam, c->shading, &r->opts);
    return PP5_OK;
}

/* --machine: the frame again on the emulated machine (gaze-directed: the
 * levels of detail into its variable-resolution Z-buffer), against the
 * native frame of the same list. */
static pp5_status_t run_machine(mesh_run_t *r, bool gaze, const mesh_soup_t *full,
                                const mesh_soup_t *lod, FILE *log)
{
    const mesh_soup_t *list = gaze && lod->n_tris > 0 ? lod : full;
    int k = gaze ? V_BOTH : V_FULL;
    pp5_status_t st = r->v[k].done ? PP5_OK : render_variant(r, k, full, list);
    if (st != PP5_OK)
        return st;
    fprintf(log, "on the emulated machine: %s (%d triangles)\n", r->v[k].what, list->n_tris);
    render_mesh_frame_t f = {r->scene.source, full, list, &r->cam, &r->opts, &r->g,
                             r->gaze_x, r->gaze_y, r->width, r->height, gaze, &r->v[k].img};
    return render_mesh_machine(r->c, &f, log);
}

pp5_status_t render_mesh_run(const render_cmd_t *c, FILE *log)
{
    if (c->mesh_file && c->scene_file)
        return pp5_fail(PP5_E_CONFIG, "--mesh and --scene: give one of them");
    pp5_status_t st = outpath_check_all("--out", c->out_png, "--report", c->report_json, NULL);
    mesh_run_t r;
    mesh_soup_t full = {0}, lod = {0};
    if (st == PP5_OK)
        st = setup(&r, c);
    if (st != PP5_OK)
        return st;
    bool gaze = c->choices.settings.mode == RENDER_MODE_GAZE;
    double t0 = mesh_render_cpu_ms();
    st = mesh_scene_flatten(&r.scene, NULL, &full);
    r.flatten_ms = mesh_render_cpu_ms() - t0;
    r.faces_full = full.n_tris;
    if (st == PP5_OK)
        st = gaze ? run_gaze(&r, &full, &lod) : render_variant(&r, V_FULL, &full, NULL);
    /* every frame's time includes making its triangle list (flattening at
     * full detail, or choosing and extracting the levels) */
    r.v[V_FULL].st.cpu_ms += r.flatten_ms;
    r.v[V_VRZ].st.cpu_ms += r.flatten_ms;
    int shown = gaze ? V_BOTH : V_FULL;
    if (st == PP5_OK) {
        fprintf(log, "%s: %d objects, %ld triangles, %dx%d, %s, %s (gaze %.1f,%.1f)\n",
                r.scene.source, r.scene.n_objects, r.faces_full, r.width, r.height,
                shading_name(r.opts.shading), gaze ? "gaze-directed" : "full resolution",
                r.gaze_x, r.gaze_y);
        print_table(&r, log);
    }
    if (st == PP5_OK && c->machine)
        st = run_machine(&r, gaze, &full, &lod, log);
    else if (st == PP5_OK && c->out_png)
        st = png_write(c->out_png, &r.v[shown].img);
    if (st == PP5_OK && c->report_json && !c->machine)
        st = write_report(&r, c->report_json, shown);
    for (int k = 0; k < N_VARIANTS; k++)
        image8_free(&r.v[k].img);
    mesh_soup_free(&full);
    mesh_soup_free(&lod);
    mesh_scene_free(&r.scene);
    return st;
}
