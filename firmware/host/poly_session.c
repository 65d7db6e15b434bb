/* poly_session.c: loading and running the polygon GP program (poly_session.h). */
#include "poly_session.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "stats.h"

void poly_options_default(poly_options_t *o)
{
    memset(o, 0, sizeof *o);
    o->shading = POLY_GOURAUD;
    o->level_tables = true;
    o->background[0] = 24, o->background[1] = 26, o->background[2] = 32;
}

const char *poly_shading_name(poly_shading_t s)
{
    return s == POLY_FLAT ? "flat" : s == POLY_GOURAUD ? "gouraud" : "phong";
}

const char *poly_stage_name(poly_stage_t s)
{
    static const char *const names[POLY_STAGE_COUNT] = {"GP (transform, sort, encode)",
                                                       "renderers (PP rasterisation, readout)",
                                                       "ring (channel time / channels)",
                                                       "renderer port (region transfers)"};
    return s < POLY_STAGE_COUNT ? names[s] : "?";
}

static void make_config(poly_session_t *s, int width, int height, const raster_camera_t *cam,
                        const raster_style_t *st)
{
    poly_config_t *c = &s->cfg;
    memset(c, 0, sizeof *c);
    c->width = width, c->height = height;
    c->shading = s->opts.shading;
    c->cull_back = s->opts.cull_back;
    c->colour_per_pixel = s->opts.colour_per_pixel;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            double acc = 0;
            for (int k = 0; k < 4; k++)
                acc += cam->proj[4 * i + k] * cam->view[4 * k + j];
            c->clip_from_world[4 * i + j] = (float)acc;
            c->view[4 * i + j] = (float)cam->view[4 * i + j];
        }
    double l = sqrt(st->light_dir[0] * st->light_dir[0] + st->light_dir[1] * st->light_dir[1] +
                    st->light_dir[2] * st->light_dir[2]);
    for (int k = 0; k < 3; k++) {
        c->light[k] = (float)(l > 0 ? st->light_dir[k] / l : st->light_dir[k]);
        c->front_rgb[k] = st->front_rgb[k];
        c->back_rgb[k] = st->back_rgb[k];
        c->background_rgb[k] = s->opts.background[k];
    }
    c->ambient = (float)st->ambient;
    c->diffuse = (float)st->diffuse;
    const gaze_model_t *g = &s->opts.gaze_model;
    c->gaze = s->opts.gaze;
    c->level_tables = s->opts.level_tables;
    c->levels2d = s->opts.gaze ? g->max_level + 1 : 1;
    if (c->levels2d > POLY_MAX_LEVELS)
        c->levels2d = POLY_MAX_LEVELS;
    c->gaze_x = s->gaze_x, c->gaze_y = s->gaze_y;
    if (s->opts.gaze) {
        c->g_inches_per_px = g->inches_per_px;
        c->g_view_distance_in = g->display.view_distance_in;
        c->g_e_full_deg = g->e_full_deg, c->g_e_edge_deg = g->e_edge_deg;
        c->g_sigma_deg = g->sigma_deg, c->g_rho_min = g->rho_min;
        c->g_r_zero_px = g->r_zero_px, c->g_r_max_px = g->r_max_px;
        c->g_max_level = g->max_level;
        c->g_level_far = g->level_edge;
    }
}

static pp5_status_t send_gp(poly_session_t *s, unsigned g, uint32_t sub, const void *payload,
                            size_t bytes)
{
    const uint32_t args[RING_MSG_ARGS] = {sub};
    ring_msg_t msg = ring_msg_make(ring_addr(RING_NODE_HOST, 0), ring_addr(RING_NODE_GP, g),
                                   RING_MSG_GP_USER, RING_CLASS_HOST, args, payload, bytes);
    return machine_send(&s->m, &msg, s->m.sched.now);
}

/* Deals the triangles round-robin to every GP, loading the program first
 * when load_program (else the GPs replace the lists they hold). */
static pp5_status_t load_gps(poly_session_t *s, const poly_tri_in_t *tris, size_t n,
                             bool load_program)
{
    unsigned G = s->m.n_gp;
    poly_tri_in_t *share = malloc(sizeof *share * (n / G + 1));
    if (!share)
        return pp5_fail(PP5_E_NOMEM, "polygons: out of memory for %zu triangles", n);
    pp5_status_t st = PP5_OK;
    for (unsigned g = 0; g < G && st == PP5_OK; g++) {
        size_t m = 0;
        for (size_t i = g; i < n; i += G)
            share[m++] = tris[i];
        poly_config_t c = s->cfg;
        c.n_triangles = (int32_t)m;
        if (load_program)
            st = machine_load_program(&s->m, g, &poly_program, &c, sizeof c);
        if (st == PP5_OK)
            st = send_gp(s, g, POLY_MSG_TRIANGLES, share, m * sizeof *share);
    }
    free(share);
    return st;
}

static pp5_status_t check_triangles(const poly_tri_in_t *tris, size_t n)
{
    if (n > (size_t)INT32_MAX / 2)
        return pp5_fail(PP5_E_RANGE, "polygons: %zu triangles is too many", n);
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++)
            for (int d = 0; d < 3; d++)
                if (!isfinite(tris[i].p[k][d]) || !isfinite(tris[i].n[k][d]))
                    return pp5_fail(PP5_E_RANGE, "polygons: triangle %zu has a coordinate that is "
                                    "not finite", i);
    return PP5_OK;
}

pp5_status_t poly_session_init(poly_session_t *s, const pp5_params_t *p, const poly_tri_in_t *tris,
                               size_t n, int width, int height, const raster_camera_t *cam,
                               const raster_style_t *style, const poly_options_t *o)
{
    memset(s, 0, sizeof *s);
    s->params = *p;
    s->opts = *o;
    if (width < 1 || height < 1 || (unsigned)width > p->fb_width || (unsigned)height > p->fb_height ||
        width > 2048)
        return pp5_fail(PP5_E_RANGE, "polygons: image %dx%d does not fit the %ux%u frame buffer",
                        width, height, p->fb_width, p->fb_height);
    pp5_status_t st = check_triangles(tris, n);
    if (st != PP5_OK)
        return st;
    s->n_tris = (uint32_t)n;
    if (o->gaze && !(isfinite(o->gaze_x) && isfinite(o->gaze_y) && fabs(o->gaze_x) <= 1e6 &&
                     fabs(o->gaze_y) <= 1e6))
        return pp5_fail(PP5_E_RANGE, "polygons: gaze point (%g, %g) is not a place on the screen",
                        o->gaze_x, o->gaze_y);
    s->gaze_x = o->gaze_x, s->gaze_y = o->gaze_y;
    make_config(s, width, height, cam, style);
    st = machine_init(&s->m, p);
    if (st != PP5_OK)
        return st;
    s->m_ok = true;
    st = load_gps(s, tris, n, true);
    sched_stop_t stop = SCHED_STOP_IDLE;
    if (st == PP5_OK)
        st = machine_run_setup(&s->m, &stop);
    if (st == PP5_OK && stop != SCHED_STOP_IDLE)
        st = pp5_fail(PP5_E_FIRMWARE, "polygons: load stopped (%s)", sched_stop_name(stop));
    s->load_s = ticks_to_s(s->m.setup_ps);
    return st;
}

pp5_status_t poly_triangles_from_mesh(const mesh_t *m, poly_tri_in_t **out, size_t *n)
{
    *out = NULL;
    *n = 0;
    pp5_status_t st = mesh_validate(m, m->source);
    if (st != PP5_OK)
        return st;
    double *vn = calloc((size_t)m->n_vertices * 3 + 3, sizeof *vn);
    poly_tri_in_t *t = calloc((size_t)m->n_faces + 1, sizeof *t);   /* rgb 0: the style's colours */
    if (!vn || !t) {
        free(vn);
        free(t);
        return pp5_fail(PP5_E_NOMEM, "polygons: out of memory for %d faces", m->n_faces);
    }
    for (int f = 0; f < m->n_faces; f++) {
        double fn[3];
        mesh_face_normal(m, f, fn);
        for (int c = 0; c < 3; c++)
            for (int k = 0; k < 3; k++)
                vn[3 * m->tri[3 * f + c] + k] += fn[k];
    }
    for (int v = 0; v < m->n_vertices; v++) {
        double *w = vn + 3 * v, l = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        if (l > 0)
            w[0] /= l, w[1] /= l, w[2] /= l;
    }
    for (int f = 0; f < m->n_faces; f++)
        for (int c = 0; c < 3; c++) {
            int v = m->tri[3 * f + c];
            for (int k = 0; k < 3; k++) {
                t[f].p[c][k] = (float)m->pos[3 * v + k];
                t[f].n[c][k] = (float)vn[3 * v + k];
            }
        }
    free(vn);
    *out = t;
    *n = (size_t)m->n_faces;
    return PP5_OK;
}

pp5_status_t poly_session_init_mesh(poly_session_t *s, const pp5_params_t *p, const mesh_t *m,
                                    int width, int height, const raster_camera_t *cam,
                                    const raster_style_t *style, const poly_options_t *o)
{
    poly_tri_in_t *t;
    size_t n;
    pp5_status_t st = poly_triangles_from_mesh(m, &t, &n);
    if (st != PP5_OK) {
        memset(s, 0, sizeof *s);
        return st;
    }
    st = poly_session_init(s, p, t, n, width, height, cam, style, o);
    free(t);
    return st;
}

pp5_status_t poly_session_set_camera(poly_session_t *s, const raster_camera_t *cam)
{
    raster_style_t keep;
    memset(&keep, 0, sizeof keep);
    poly_config_t old = s->cfg;
    for (int k = 0; k < 3; k++) {
        keep.light_dir[k] = old.light[k];
        keep.front_rgb[k] = (uint8_t)old.front_rgb[k];
        keep.back_rgb[k] = (uint8_t)old.back_rgb[k];
    }
    keep.ambient = old.ambient, keep.diffuse = old.diffuse;
    make_config(s, old.width, old.height, cam, &keep);
    pp5_status_t st = PP5_OK;
    for (unsigned g = 0; g < s->m.n_gp && st == PP5_OK; g++)
        st = send_gp(s, g, POLY_MSG_CONFIG, &s->cfg, sizeof s->cfg);
    return st;
}

pp5_status_t poly_session_set_gaze(poly_session_t *s, double gaze_x, double gaze_y)
{
    if (!isfinite(gaze_x) || !isfinite(gaze_y) || fabs(gaze_x) > 1e6 || fabs(gaze_y) > 1e6)
        return pp5_fail(PP5_E_RANGE, "polygons: gaze point (%g, %g) is not a place on the screen",
                        gaze_x, gaze_y);
    s->gaze_x = gaze_x, s->gaze_y = gaze_y;
    s->cfg.gaze_x = gaze_x, s->cfg.gaze_y = gaze_y;
    pp5_status_t st = PP5_OK;
    for (unsigned g = 0; g < s->m.n_gp && st == PP5_OK; g++) {
        poly_config_t c = s->cfg;
        c.n_triangles = 0;      /* not read after the start */
        st = send_gp(s, g, POLY_MSG_CONFIG, &c, sizeof c);
    }
    return st;
}

pp5_status_t poly_session_set_triangles(poly_session_t *s, const poly_tri_in_t *tris, size_t n)
{
    pp5_status_t st = check_triangles(tris, n);
    if (st != PP5_OK)
        return st;
    /* The host's messages are counted when they are queued (emu/ring.c), so
     * the bytes are taken here; their transfer happens in the next frame. */
    uint64_t bytes0 = ring_total_bytes_sent(&s->m.ring);
    st = load_gps(s, tris, n, false);
    s->upload_ring_bytes = ring_total_bytes_sent(&s->m.ring) - bytes0;
    if (st == PP5_OK)
        s->n_tris = (uint32_t)n;
    return st;
}

void poly_session_free(poly_session_t *s)
{
    if (s->m_ok)
        machine_free(&s->m);
    memset(s, 0, sizeof *s);
}

/* ---- one frame ---- */

static double prog(const stats_t *f, unsigned g, const char *name)
{
    return stats_valuef(f, "gp.%u.prog.%s", g, name);
}

static void gather_gps(const poly_session_t *s, const stats_t *f, pp5_tick_t t0, poly_frame_result_t *r)
{
    double hz = s->params.gp_clock_hz, sum = 0;
    for (unsigned g = 0; g < s->m.n_gp; g++) {
        r->tris_in += (uint64_t)prog(f, g, "tris_in");
        r->tris_setup += (uint64_t)prog(f, g, "tris_setup");
        r->pairs_binned += (uint64_t)prog(f, g, "pairs_binned");
        r->pairs_sent += (uint64_t)prog(f, g, "pairs_sent");
        r->edges_sent += (uint64_t)prog(f, g, "edges_sent");
        r->stream_words += (uint64_t)prog(f, g, "stream_words");
        r->regions += (uint64_t)prog(f, g, "regions");
        r->texels_in += (uint64_t)prog(f, g, "texels_in");
        r->cycles_levels += (uint64_t)prog(f, g, "cycles_levels");
        r->cycles_resample += (uint64_t)prog(f, g, "cycles_resample");
        uint64_t ct = (uint64_t)prog(f, g, "cycles_transform"), cs = (uint64_t)prog(f, g, "cycles_sort"),
                 ce = (uint64_t)prog(f, g, "cycles_encode");
        r->cycles_transform += ct, r->cycles_sort += cs, r->cycles_encode += ce;
        r->gp_transform_sort_s_max = fmax(r->gp_transform_sort_s_max, (double)(ct + cs) / hz);
        r->gp_encode_s_max = fmax(r->gp_encode_s_max, (double)ce / hz);
        double busy = stats_valuef(f, "gp.%u.busy_s", g);
        if (busy > r->gp_busy_s_max)
            r->gp_fdiv_busiest = (uint64_t)stats_valuef(f, "gp.%u.ops.fdiv", g);
        r->gp_busy_s_max = fmax(r->gp_busy_s_max, busy);
        sum += busy;
        /* the phase times are values (the last frame's), not differences */
        double sorted = prog(f, g, "t_sorted_ps") - (double)t0;
        r->gp_sorted_s_max = fmax(r->gp_sorted_s_max, sorted * 1e-12);
    }
    r->gp_busy_s_mean = s->m.n_gp ? sum / s->m.n_gp : 0;
    r->regions_drawn = s->m.n_gp ? r->regions / s->m.n_gp : 0;   /* every GP streams every region */
}

static void gather_units(const poly_session_t *s, const stats_t *f, poly_frame_result_t *r)
{
    double sum = 0;
    for (unsigned j = 0; j < s->m.n_rn; j++) {
        uint64_t ex = (uint64_t)stats_valuef(f, "renderer.%u.exec_cycles", j);
        r->rn_exec_cycles_total += ex;
        r->rn_exec_cycles_max = ex > r->rn_exec_cycles_max ? ex : r->rn_exec_cycles_max;
        r->rn_port_cycles_total += (uint64_t)stats_valuef(f, "renderer.%u.port_cycles", j);
        r->rn_qee_cycles_total += (uint64_t)stats_valuef(f, "renderer.%u.pp.cycles_by_class.qee", j);
        r->rn_qee_count += (uint64_t)stats_valuef(f, "renderer.%u.pp.instructions_by_class.qee", j);
        double busy = stats_valuef(f, "renderer.%u.busy_s", j);
        r->rn_busy_s_max = fmax(r->rn_busy_s_max, busy);
        sum += busy;
    }
    r->rn_busy_s_mean = s->m.n_rn ? sum / s->m.n_rn : 0;
    double ch_sum = 0;
    for (unsigned c = 0; c < s->params.ring_channels; c++)
        ch_sum += stats_valuef(f, "ring.by_channel.%u.busy_s", c);
    for (unsigned k = 0; k < RING_CLASS_COUNT; k++) {
        r->ring_bytes[k] = (uint64_t)stats_valuef(f, "ring.by_class.%s.bytes_sent", stats_class_name(k));
        r->ring_bytes_total += r->ring_bytes[k];
        r->ring_class_busy_s[k] = stats_valuef(f, "ring.by_class.%s.busy_s", stats_class_name(k));
    }
    double T = r->frame_time_s;
    r->ring_util_total = T > 0 ? ch_sum / (s->params.ring_channels * T) : 0;
    r->stage_s[POLY_STAGE_GP] = r->gp_busy_s_max;
    r->stage_s[POLY_STAGE_RENDERER] = r->rn_busy_s_max;
    /* Channels are taken lowest-free first, so with sparse traffic one
     * channel carries most of it: the ring's capacity is the sum over the
     * channels.  A node sends one message at a time (emu/ring.h), so a
     * renderer's regions leave one after another: regions x wire time. */
    r->stage_s[POLY_STAGE_RING] = ch_sum / s->params.ring_channels;
    int regions = (int)(s->m.n_gp ? r->regions / s->m.n_gp : 0);
    int per_rn = (regions + (int)s->m.n_rn - 1) / (int)s->m.n_rn;
    double wire_bytes = 128.0 * 128 * 3 + s->params.ring_header_bytes;
    double cycles = ceil(wire_bytes / (s->params.ring_width_bits / 8));
    r->stage_s[POLY_STAGE_RN_PORT] = per_rn * cycles / s->params.ring_clock_hz;
    if (s->cfg.gaze) {
        /* the texel boxes leave the renderers instead of whole regions */
        double box_cycles = ceil((double)r->ring_bytes[RING_CLASS_DATA] /
                                 (s->params.ring_width_bits / 8));
        r->stage_s[POLY_STAGE_RN_PORT] = box_cycles / s->m.n_rn / s->params.ring_clock_hz;
    }
    int b = 0;
    for (int k = 1; k < POLY_STAGE_COUNT; k++)
        if (r->stage_s[k] > r->stage_s[b])
            b = k;
    r->bottleneck = poly_stage_name((poly_stage_t)b);
    r->tris_per_s_pipelined = r->stage_s[b] > 0 ? (double)r->tris_in / r->stage_s[b] : 0;
    r->tris_per_s_frame = T > 0 ? (double)r->tris_in / T : 0;
}

static pp5_status_t copy_image(const poly_session_t *s, image8_t *img)
{
    const image8_t *fb = fb_front(&s->m.fb);
    pp5_status_t st = image8_alloc(img, s->cfg.width, s->cfg.height, 3);
    if (st != PP5_OK)
        return st;
    for (int y = 0; y < s->cfg.height; y++)
        memcpy(img->pixels + (size_t)y * (size_t)s->cfg.width * 3,
               fb->pixels + (size_t)y * fb->width * 3, (size_t)s->cfg.width * 3);
    return PP5_OK;
}

pp5_status_t poly_session_frame(poly_session_t *s, image8_t *img, poly_frame_result_t *r)
{
    memset(r, 0, sizeof *r);
    machine_t *m = &s->m;
    stats_t before, after, f;
    pp5_status_t st = stats_collect(&before, m);
    if (st != PP5_OK)
        return st;
    pp5_tick_t t0 = m->sched.now;
    sched_stop_t stop = SCHED_STOP_IDLE;
    st = machine_run_frame(m, &stop);
    if (st == PP5_OK && stop != SCHED_STOP_IDLE)
        st = pp5_fail(PP5_E_FIRMWARE, "polygons: frame stopped (%s)", sched_stop_name(stop));
    if (st == PP5_OK && (st = stats_collect(&after, m)) == PP5_OK) {
        st = stats_diff(&f, &before, &after);
        stats_free(&after);
    }
    stats_free(&before);
    if (st != PP5_OK)
        return st;
    /* the machine keeps MACHINE_MAX_FRAMES frame records; the scheduler's
     * clock (left at the frame's last activity) serves any number of frames */
    r->frame_time_s = ticks_to_s(m->sched.now - t0);
    gather_gps(s, &f, t0, r);
    gather_units(s, &f, r);
    stats_free(&f);
    s->frames++;
    s->last = *r;
    return img ? copy_image(s, img) : PP5_OK;
}
