/* fw_session.c: host side of the machine renderer: the configuration block, slabs and program to the GPs, setup, and one frame at a time. */
#include "fw_session.h"
#include "progress.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "firmware/common/vr_gp.h"
#include "fw_internal.h"
#include "render/blend_ray.h"

static const char *const phase_names[FW_PHASE_COUNT] = {
    "host frame start", "GP prep (2DLevel, marks, footprint)", "PP shading (wait)",
    "ring fetch of shaded bricks (wait)", "GP receive/forward/shade", "GP ray casting",
    "GP load imbalance", "GP boundary exchange (wait)", "GP 2D resampling + sections",
    "frame-buffer transfer",
};

const char *fw_phase_name(fw_phase_t p)
{
    return p < FW_PHASE_COUNT ? phase_names[p] : "?";
}

static const char *const phase_keys[FW_PHASE_COUNT] = {
    "host_start_s", "gp_prep_s", "pp_shade_s", "ring_fetch_s", "gp_receive_s", "gp_cast_s",
    "gp_imbalance_s", "gp_exchange_s", "gp_resample_s", "fb_transfer_s",
};

const char *fw_phase_key(fw_phase_t p)
{
    return p < FW_PHASE_COUNT ? phase_keys[p] : "?";
}

/* ---- the configuration block (vr_config_t) ---- */

static pp5_status_t config_volume(fw_session_t *s, const volume_t *v)
{
    vr_config_t *c = &s->cfg;
    c->nx = v->nx;
    c->ny = v->ny;
    c->nz = v->nz;
    /* The shape of render/'s pyramid, so that both sides sample the same. */
    mip3d_geometry(&s->dims, v);
    if (s->dims.levels >= VR_MAX_LEVELS)
        return pp5_fail(PP5_E_RANGE, "machine renderer: volume too large for %d mip levels",
                        VR_MAX_LEVELS);
    memcpy(c->spacing, s->dims.spacing, sizeof c->spacing);
    memcpy(c->inv_spacing, s->dims.inv_spacing, sizeof c->inv_spacing);
    c->levels = s->dims.levels;
    unsigned n_gp = s->params.n_gp;
    if (n_gp > VR_MAX_GPS)
        return pp5_fail(PP5_E_CONFIG, "machine renderer: at most %d GPs", VR_MAX_GPS);
    /* Slabs of a multiple of 2^K slices (K = 3 levels built on the slab GPs). */
    int K = c->levels - 1 < 3 ? c->levels - 1 : 3;
    int unit = 1 << K;
    c->slab_k = K;
    c->slab_t = unit * (int)((v->nz + unit * (int)n_gp - 1) / (unit * (int)n_gp));
    c->n_slab_gps = (v->nz + c->slab_t - 1) / c->slab_t;
    return PP5_OK;
}

static pp5_status_t config_shading(vr_config_t *c, const classify_tf_t *tf, const shade_params_t *sh)
{
    c->lighting = sh->lighting == SHADE_DIFFUSE_FIXED_LIGHT ? VR_LIGHT_DIFFUSE
                  : sh->lighting == SHADE_SPECULAR_FIXED_LIGHT ? VR_LIGHT_SPECULAR
                                                                : VR_LIGHT_MOVING;
    if (c->lighting != VR_LIGHT_DIFFUSE) {
        float e = sh->specular_exponent;
        if (!(e >= 1.0f && e <= 255.0f) || e != floorf(e))
            return pp5_fail(PP5_E_UNSUPPORTED, "machine renderer: the PPs raise N.H to an "
                            "integer power 1..255 (square and multiply); exponent %g", e);
        if (!(sh->specular >= 0.0f && sh->specular < 4.0f))
            return pp5_fail(PP5_E_RANGE, "machine renderer: specular coefficient must lie in "
                            "[0, 4) for the Q8 PP immediate");
        if (c->lighting == VR_LIGHT_MOVING &&
            !(sh->ambient >= 0.0f && sh->diffuse >= 0.0f && sh->ambient + sh->diffuse <= 4.0f))
            return pp5_fail(PP5_E_RANGE, "machine renderer: ambient and diffuse must be >= 0 "
                            "with a sum <= 4 for the Q15 PP shade");
    }
    /* The GP firmware classifies by Levoy's iso-value contours (vr_kernels.h);
     * a table would silently classify every voxel as empty. */
    if (classify_tf_is_table(tf))
        return pp5_fail(PP5_E_UNSUPPORTED, "machine renderer: transfer function '%s' is a table "
                        "of control points; the machine's firmware classifies by iso-value "
                        "contours only (use a contour function, or the native renderer)", tf->name);
    c->tf_count = tf->count;
    for (int i = 0; i < tf->count && i < VR_MAX_CONTOURS; i++) {
        c->tf[i].value = tf->contour[i].value;
        c->tf[i].opacity = tf->contour[i].opacity;
        c->tf[i].width_vox = tf->contour[i].width_vox;
        memcpy(c->tf[i].rgb, tf->contour[i].rgb, sizeof c->tf[i].rgb);
    }
    c->ambient = sh->ambient;
    c->diffuse = sh->diffuse;
    c->specular = sh->specular;
    c->specular_exponent = sh->specular_exponent;
    memcpy(c->light_dir, sh->light_dir, sizeof c->light_dir);
    c->two_sided = sh->two_sided;
    return PP5_OK;
}

static pp5_status_t config_image(fw_session_t *s, const render_settings_t *rs)
{
    vr_config_t *c = &s->cfg;
    c->width = rs->width;
    c->height = rs->height;
    if ((unsigned)rs->width > s->params.fb_width || (unsigned)rs->height > s->params.fb_height)
        return pp5_fail(PP5_E_RANGE, "machine renderer: image %dx%d larger than the %ux%u frame "
                        "buffer", rs->width, rs->height, s->params.fb_width, s->params.fb_height);
    pp5_status_t st = gaze_model_init(&s->gaze, &rs->display, rs->width, rs->height);
    if (st != PP5_OK)
        return st;
    c->levels2d = rs->mode == RENDER_MODE_GAZE ? s->gaze.max_level + 1 : 1;
    if (c->levels2d > VR_MAX_2D_LEVELS)
        return pp5_fail(PP5_E_CONFIG, "machine renderer: too many 2D levels");
    fw_bands_equal(rs->height, (int)s->params.n_gp, c->levels2d, c->band_y0);
    c->sample_step = rs->view.sample_step;
    c->early_termination = rs->view.early_termination;
    c->use_octree = rs->view.use_octree;
    c->perspective = rs->view.projection == PROJECTION_PERSPECTIVE;
    c->g_inches_per_px = s->gaze.inches_per_px;
    c->g_view_distance_in = s->gaze.display.view_distance_in;
    c->g_e_full_deg = s->gaze.e_full_deg;
    c->g_e_edge_deg = s->gaze.e_edge_deg;
    c->g_sigma_deg = s->gaze.sigma_deg;
    c->g_rho_min = s->gaze.rho_min;
    c->g_r_zero_px = s->gaze.r_zero_px;
    c->g_r_max_px = s->gaze.r_max_px;
    c->g_max_level = s->gaze.max_level;
    c->fb_x0 = 0;
    c->fb_y0 = 0;
    return PP5_OK;
}

/* Whether a blend may skip cold cells exactly: parallel projection and
 * every 2D level's rays sampling one integer 3D level (vr_ray_consts's
 * float expressions), since the octree grids hold one level each. */
static bool blend_can_skip(const fw_session_t *s)
{
    const vr_config_t *c = &s->cfg;
    const view_params_t *v = &s->rs.view;
    if (!v->use_octree || v->projection != PROJECTION_PARALLEL)
        return false;
    float step = c->sample_step > 0.0f ? c->sample_step : 1.0f, offset = log2f(step);
    for (int m = 0; m < c->levels2d; m++) {
        float level3d = log2f(step * (float)(1 << m)) - offset;
        if (level3d != floorf(level3d))
            return false;
    }
    return true;
}

/* MIP, DEMIP and MIDA: the sequence's part of render/'s blend_frame_t,
 * computed by render/'s own code (blend_ray.c) so that the GPs use the same
 * floats, and the cold limit of skipping (firmware/ARCHITECTURE.md
 * "Blends"). */
static pp5_status_t config_blend(fw_session_t *s, const render_job_t *job)
{
    vr_config_t *c = &s->cfg;
    const blend_settings_t *b = &job->settings.blend;
    pp5_status_t st = blend_settings_check(b);
    if (st != PP5_OK || b->mode == BLEND_COMPOSITE)
        return st;
    if (s->opts.division == FW_DIVISION_OBJECT_SLABS)
        return pp5_fail(PP5_E_UNSUPPORTED, "machine renderer: --blend %s is not cast in object "
                        "slabs (DEMIP's ray 2 needs the whole ray's maximum before any slab can "
                        "stop it, MIDA's colour depends on the maximum in front of each slab, "
                        "and MIP's merge by maximum is not written yet; firmware/ARCHITECTURE.md "
                        "\"Blends\"): use division=image-bands or division=resident", blend_mode_name(b->mode));
    c->blend = b->mode == BLEND_MIP ? VR_BLEND_MIP : b->mode == BLEND_DEMIP ? VR_BLEND_DEMIP
                                                                          : VR_BLEND_MIDA;
    c->pyramid = b->pyramid == SCALAR_PYRAMID_BOX ? VR_PYRAMID_BOX : VR_PYRAMID_MAX;
    c->reading = b->reading == DEMIP_READING_B ? VR_READING_B : VR_READING_A;
    c->depth = b->depth == DEMIP_DEPTH_EXACT ? VR_DEPTH_EXACT : VR_DEPTH_ENTRY_PLUS_LENGTH;
    /* The value pyramid carries no shading. */
    c->lighting = VR_LIGHT_DIFFUSE;
    camera_t cam;
    camera_setup(&cam, &job->settings.view, &s->dims, job->settings.width, job->settings.height);
    /* The rays into voxel space with the camera's 1 / spacing (render/'s
     * blend_geom_begin), not the mip map's (smin / spacing in double): the
     * two may differ in the last bit, and a blend's image is bit for bit. */
    memcpy(c->inv_spacing, cam.inv_spacing, sizeof c->inv_spacing);
    const volume_t *v = job->volume;
    blend_frame_t f;
    blend_frame_init(&f, b, &cam, v->min_value, v->max_value, job->settings.view.early_termination);
    c->window_lo = f.window.lo;
    c->window_inv_width = f.window.inv_width;
    c->eps = f.eps;
    c->dw = f.dw;
    c->sw = f.sw;
    memcpy(c->sphere_pole, f.sphere.pole, sizeof c->sphere_pole);
    memcpy(c->sphere_front, f.sphere.front, sizeof c->sphere_front);
    memcpy(c->sphere_back, f.sphere.back, sizeof c->sphere_back);
    /* Trilinear samples of values <= M stay below M + 21 roundings of the
     * largest magnitude (7 nested lerps, 3 roundings each: < 1.3e-6 of it);
     * the margin, 2^-16 of it, is ten times that, so a cell whose corners
     * are all at or below cold_below samples below window_lo: material 0. */
    float mag = fmaxf(fmaxf(fabsf(v->min_value), fabsf(v->max_value)), fabsf(f.window.lo));
    c->cold_below = f.window.lo - mag * (1.0f / 65536.0f);
    if (!blend_can_skip(s)) {
        c->cold_below = -INFINITY;
        c->use_octree = 0;
    }
    return PP5_OK;
}

static pp5_status_t make_config(fw_session_t *s, const render_job_t *job)
{
    vr_config_t *c = &s->cfg;
    memset(c, 0, sizeof *c);
    c->magic = VR_MAGIC;
    pp5_status_t st = config_volume(s, job->volume);
    if (st == PP5_OK)
        st = config_shading(c, &job->tf, &job->shade);
    if (st == PP5_OK)
        st = config_image(s, &job->settings);
    c->split = s->opts.split;
    c->max_pass_bricks = s->opts.max_pass_bricks;
    c->division = s->opts.division == FW_DIVISION_RESIDENT ? VR_DIVISION_RESIDENT
                  : s->opts.division == FW_DIVISION_OBJECT_SLABS ? VR_DIVISION_OBJECT_SLABS
                                                                 : VR_DIVISION_IMAGE_BANDS;
    c->level_tables = s->opts.level_tables;
    c->unit_edge = s->opts.unit_edge;
    c->tiles = s->opts.tiles;
    if (st == PP5_OK)
        st = config_blend(s, job);
    return st;
}

/* ---- loading and setup ---- */

/* A host message to GP g: the frame parameters or a slab (host class). */
static pp5_status_t send_to_gp(fw_session_t *s, unsigned g, uint32_t sub, const void *payload,
                               size_t bytes, pp5_tick_t t)
{
    const uint32_t args[RING_MSG_ARGS] = {sub};
    ring_msg_t msg = ring_msg_make(ring_addr(RING_NODE_HOST, 0), ring_addr(RING_NODE_GP, g),
                                   RING_MSG_GP_USER, RING_CLASS_HOST, args, payload, bytes);
    return machine_send(&s->m, &msg, t);
}

/* Each GP: the configuration, then its slab's slices with one halo slice on
 * each side (central differences). */
static pp5_status_t load_gps(fw_session_t *s, const volume_t *v)
{
    pp5_status_t st = PP5_OK;
    for (unsigned g = 0; g < s->m.n_gp && st == PP5_OK; g++) {
        vr_config_t c = s->cfg;
        int z0 = 0, z1 = 0;
        if ((int)g < c.n_slab_gps) {
            z0 = (int)g * c.slab_t - 1;
            z1 = ((int)g + 1) * c.slab_t + 1;
            z0 = z0 < 0 ? 0 : z0;
            z1 = z1 > v->nz ? v->nz : z1;
        }
        c.data_z0 = z0;
        c.data_z1 = z1;
        size_t plane = (size_t)v->nx * (size_t)v->ny;
        size_t slab_bytes = plane * (size_t)(z1 - z0) * sizeof(float);
        st = machine_load_program(&s->m, g, &vr_program, &c, sizeof c);
        if (st == PP5_OK && slab_bytes)
            st = send_to_gp(s, g, VR_MSG_SLAB, v->data + plane * (size_t)z0, slab_bytes,
                            s->m.sched.now);
    }
    return st;
}

pp5_status_t fw_session_init(fw_session_t *s, const render_job_t *job, const pp5_params_t *p,
                             const fw_options_t *o)
{
    memset(s, 0, sizeof *s);
    s->params = *p;
    s->opts = *o;
    s->rs = job->settings;
    s->shade = job->shade;
    const volume_t *v = job->volume;
    s->value_min = v ? v->min_value : 0.0f;
    s->value_max = v ? v->max_value : 0.0f;
    if (!v || !v->data || v->nx < 2 || v->ny < 2 || v->nz < 2)
        return pp5_fail(PP5_E_RANGE, "machine renderer: volume must be at least 2x2x2");
    if (o->division == FW_DIVISION_OBJECT_SLABS &&
        (job->settings.view.projection != PROJECTION_PARALLEL || job->settings.progressive))
        return pp5_fail(PP5_E_UNSUPPORTED, "machine renderer: the object-slabs division casts "
                        "parallel projections and single frames of a view only (no perspective, "
                        "no progressive refinement)");
    pp5_status_t st = make_config(s, job);
    if (st != PP5_OK)
        return st;
    int unit = 1 << (s->cfg.levels2d - 1);
    s->n_units = (s->rs.height + unit - 1) / unit;
    s->unit_factor = calloc((size_t)s->n_units, sizeof *s->unit_factor);
    s->unit_weight = calloc((size_t)s->n_units, sizeof *s->unit_weight);
    if (!s->unit_factor || !s->unit_weight)
        return pp5_fail(PP5_E_NOMEM, "machine renderer: out of memory");
    if (o->plan == FW_PLAN_SAMPLES && (st = fw_estimate_init(s, job)) != PP5_OK)
        return st;
    if ((st = machine_init(&s->m, p)) != PP5_OK)
        return st;
    s->m_ok = true;
    if (o->timeline && (st = machine_enable_timeline(&s->m)) != PP5_OK)
        return st;
    progress_t pr;
    progress_begin(&pr, "machine setup", 1);
    progress_note(&pr, "loading the volume's slabs; the GPs build the 3D mip map into the "
                  "backing store");
    st = load_gps(s, v);
    sched_stop_t stop = SCHED_STOP_IDLE;
    /* The once-per-sequence mip-map build is minutes of work on the paper's
     * workstation (§6: 5 minutes); machine_run_setup bounds it by
     * sim.setup_budget_s, while sim.budget_s bounds each frame. */
    if (st == PP5_OK)
        st = machine_run_setup(&s->m, &stop);
    progress_end(&pr);
    if (st == PP5_OK && stop != SCHED_STOP_IDLE)
        st = pp5_fail(PP5_E_FIRMWARE, "machine renderer: setup stopped (%s)", sched_stop_name(stop));
    s->setup_s = ticks_to_s(s->m.setup_ps);
    s->setup_ring_bytes = ring_total_bytes_sent(&s->m.ring);
    return st;
}

void fw_session_free(fw_session_t *s)
{
    if (s->m_ok)
        machine_free(&s->m);
    free(s->unit_factor);
    free(s->unit_weight);
    free(s->coarse_alpha);
    for (int k = 0; k < 8; k++)
        free(s->coarse_occ[k]);
    free(s->work_memo);
    free(s->work_known);
    memset(s, 0, sizeof *s);
}

/* ---- one frame ---- */

/* DEMIP's depth normalisation for the frame's view (render/'s
 * blend_frame_init), and the colour sphere the legend shows. */
static void frame_blend(const fw_session_t *s, const camera_t *cam, vr_frame_t *f,
                        blend_frame_t *bf)
{
    blend_frame_init(bf, &s->rs.blend, cam, s->value_min, s->value_max,
                     s->rs.view.early_termination);
    f->exact_near = bf->exact_near;
    f->exact_inv_range = bf->exact_inv_range;
    f->axis_near = bf->axis_near;
    f->axis_inv_range = bf->axis_inv_range;
}

static void fill_frame(fw_session_t *s, double gx, double gy, vr_frame_t *f, blend_frame_t *bf)
{
    camera_t cam;
    camera_setup(&cam, &s->rs.view, &s->dims, s->rs.width, s->rs.height);
    memset(f, 0, sizeof *f);
    frame_blend(s, &cam, f, bf);
    f->frame = (int32_t)s->frames;
    f->mode = s->rs.mode == RENDER_MODE_GAZE ? VR_MODE_GAZE : VR_MODE_FULL;
    f->projection = cam.projection == PROJECTION_PERSPECTIVE;
    f->gaze_x = gx;
    f->gaze_y = gy;
    f->gaze_scale = 1.0;
    memcpy(f->right, cam.right, sizeof f->right);
    memcpy(f->down, cam.down, sizeof f->down);
    memcpy(f->forward, cam.forward, sizeof f->forward);
    memcpy(f->centre, cam.centre, sizeof f->centre);
    memcpy(f->eye, cam.eye, sizeof f->eye);
    memcpy(f->box_hi, cam.box_hi, sizeof f->box_hi);
    f->pixel_size = cam.pixel_size;
    f->eye_distance = cam.eye_distance;
    f->radius = cam.radius;
    memcpy(f->light_dir, s->shade.light_dir, sizeof f->light_dir);
    if (s->rs.progressive) {
        /* Progressive refinement keeps each GP's texel rows between frames,
         * so the bands stay fixed (equal) for the whole sequence. */
        fw_bands_equal(s->rs.height, (int)s->m.n_gp, s->cfg.levels2d, f->band_y0);
        f->progressive_keep = 1 | (s->prog_index > 0 ? 2 : 0);
        double growth = s->rs.progressive_growth > 1.0 ? s->rs.progressive_growth : 1.0;
        f->gaze_scale = pow(growth, (double)s->prog_index);
    } else if (s->opts.division == FW_DIVISION_OBJECT_SLABS) {
        /* Bands only resample (the same work per row); slabs cast. */
        fw_bands_equal(s->rs.height, (int)s->m.n_gp, s->cfg.levels2d, f->band_y0);
        fw_slabs_plan(s, f->slab_z0);
    } else {
        fw_bands_plan(s, gx, gy, f->band_y0);
    }
}

static pp5_status_t copy_image(const fw_session_t *s, image8_t *img)
{
    const image8_t *fb = fb_front(&s->m.fb);
    pp5_status_t st = image8_alloc(img, s->rs.width, s->rs.height, 3);
    if (st != PP5_OK)
        return st;
    for (int y = 0; y < s->rs.height; y++)
        memcpy(img->pixels + (size_t)y * s->rs.width * 3,
               fb->pixels + ((size_t)(y + s->cfg.fb_y0) * fb->width + (size_t)s->cfg.fb_x0) * 3,
               (size_t)s->rs.width * 3);
    return PP5_OK;
}

/* Sends the frame parameters, runs the frame, and leaves the statistics of
 * the frame (a difference of two snapshots) in *frame. */
static pp5_status_t run_frame(fw_session_t *s, const vr_frame_t *f, stats_t *frame, pp5_tick_t *t1)
{
    machine_t *m = &s->m;
    stats_t before, after;
    pp5_status_t st = stats_collect(&before, m);
    if (st != PP5_OK)
        return st;
    for (unsigned g = 0; g < m->n_gp && st == PP5_OK; g++)
        st = send_to_gp(s, g, VR_MSG_FRAME_PARAMS, f, sizeof *f, m->sched.now);
    sched_stop_t stop = SCHED_STOP_IDLE;
    if (st == PP5_OK)
        st = machine_run_frame(m, &stop);
    if (st == PP5_OK && stop != SCHED_STOP_IDLE)
        st = pp5_fail(PP5_E_FIRMWARE, "machine renderer: frame stopped (%s)", sched_stop_name(stop));
    *t1 = m->sched.now;
    if (st == PP5_OK && (st = stats_collect(&after, m)) == PP5_OK) {
        st = stats_diff(frame, &before, &after);
        stats_free(&after);
    }
    stats_free(&before);
    return st;
}

pp5_status_t fw_session_frame(fw_session_t *s, double gx, double gy, image8_t *img,
                              fw_frame_result_t *r)
{
    memset(r, 0, sizeof *r);
    if (!isfinite(gx) || !isfinite(gy))
        return pp5_fail(PP5_E_RANGE, "machine renderer: gaze point must be finite");
    vr_frame_t f;
    blend_frame_t bf;
    fill_frame(s, gx, gy, &f, &bf);
    memcpy(s->last_bands, f.band_y0, sizeof s->last_bands);
    pp5_tick_t t0 = s->m.sched.now, t1 = t0;
    stats_t frame;
    pp5_status_t st = run_frame(s, &f, &frame, &t1);
    s->frames++;
    s->prog_index++;
    if (st == PP5_OK && (st = fw_frame_check_finished(s, &frame)) != PP5_OK)
        stats_free(&frame);
    if (st != PP5_OK)
        return st;
    fw_frame_analyse(s, &frame, t0, t1, r);
    if (!s->rs.progressive)
        fw_bands_learn(s, &frame);
    stats_free(&frame);
    s->last = *r;
    if (!img)
        return PP5_OK;
    st = copy_image(s, img);
    /* The colour sphere's legend (seed 002 figure 1) is the host's overlay
     * on the image it shows, as render/ draws it over its own image (host
     * work, not the machine's). */
    const blend_settings_t *b = &s->rs.blend;
    if (st == PP5_OK && b->mode == BLEND_DEMIP && b->sphere_weight > 0.0f && b->legend) {
        camera_t cam;
        camera_setup(&cam, &s->rs.view, &s->dims, s->rs.width, s->rs.height);
        colour_sphere_draw_legend(&bf.sphere, cam.right, cam.down, cam.forward, img);
    }
    return st;
}

pp5_status_t fw_session_set_view(fw_session_t *s, const view_params_t *view)
{
    if (view->projection != s->rs.view.projection)
        return pp5_fail(PP5_E_CONFIG, "machine renderer: the projection is fixed per sequence "
                        "(the GPs' octree grids)");
    s->rs.view = *view;
    fw_estimate_forget(s);
    return PP5_OK;
}

pp5_status_t fw_session_set_light(fw_session_t *s, const float light_dir[3])
{
    /* A fixed light's diffuse term is in the 3D mip map the GPs built once
     * (viewpoint-independent shading, paper §5). */
    if (s->shade.lighting != SHADE_MOVING_OBJECT)
        return pp5_fail(PP5_E_UNSUPPORTED, "machine renderer: a fixed light is shaded into the "
                        "3D mip map at setup; only a moving object's light can change between "
                        "frames (start a new session for another fixed light)");
    memcpy(s->shade.light_dir, light_dir, sizeof s->shade.light_dir);
    return PP5_OK;
}

pp5_status_t fw_replay_frame_cost(void *ctx, double gaze_x, double gaze_y, fw_replay_cost_t *out)
{
    fw_session_t *s = ctx;
    fw_frame_result_t r;
    pp5_status_t st = fw_session_frame(s, gaze_x, gaze_y, out->image, &r);
    if (st != PP5_OK)
        return st;
    out->frame_time_s = r.frame_time_s;
    out->rays = r.rays;
    out->samples = r.samples;
    out->ring_bytes = r.ring_bytes_total;
    return PP5_OK;
}
