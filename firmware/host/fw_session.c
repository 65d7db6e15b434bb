/* fw_session.c: host side of the machine renderer: slabs and program to the GPs, setup, per-frame parameters, image and phase breakdown. */
#include "fw_session.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "firmware/common/vr_gp.h"
#include "firmware/common/vr_shade_fixed.h"
#include "stats.h"

static const char *const phase_names[FW_PHASE_COUNT] = {
    "host frame start", "GP prep (2DLevel, marks, footprint)", "PP shading (wait)",
    "ring fetch of shaded bricks (wait)", "GP receive/forward/shade", "GP ray casting",
    "GP boundary exchange (wait)", "GP 2D resampling + sections", "frame-buffer transfer",
};

const char *fw_phase_name(fw_phase_t p)
{
    return p < FW_PHASE_COUNT ? phase_names[p] : "?";
}

static const char *const phase_keys[FW_PHASE_COUNT] = {
    "host_start_s", "gp_prep_s", "pp_shade_s", "ring_fetch_s", "gp_receive_s", "gp_cast_s",
    "gp_exchange_s", "gp_resample_s", "fb_transfer_s",
};

const char *fw_phase_key(fw_phase_t p)
{
    return p < FW_PHASE_COUNT ? phase_keys[p] : "?";
}

void fw_options_default(fw_options_t *o)
{
    memset(o, 0, sizeof *o);
    o->split = VR_SPLIT_PP;
}

void fw_bands(int height, int n_gp, int levels2d, int32_t *band_y0)
{
    /* Equal bands whose starts are multiples of 2^(levels2d-1) (so every
     * band's texel rows start on a texel boundary of every 2D level). */
    int unit = 1 << (levels2d - 1);
    int units = (height + unit - 1) / unit;
    /* Fewer units than GPs: one unit each, the empty bands last (a GP's
     * boundary rows always come from the next GP). */
    for (int g = 0; g <= n_gp; g++) {
        int u = units >= n_gp ? (int)(((long long)units * g) / n_gp) : (g < units ? g : units);
        int y = u * unit;
        band_y0[g] = y > height ? height : y;
    }
    band_y0[n_gp] = height;
}

static pp5_status_t make_config(fw_session_t *s, const volume_t *v, const classify_tf_t *tf,
                                const shade_params_t *sh, const render_settings_t *rs)
{
    vr_config_t *c = &s->cfg;
    memset(c, 0, sizeof *c);
    c->magic = VR_MAGIC;
    c->nx = v->nx;
    c->ny = v->ny;
    c->nz = v->nz;
    /* spacing exactly as mip3d_build computes it */
    double sp[3], smin = 0.0;
    for (int a = 0; a < 3; a++) {
        sp[a] = v->spacing[a] > 0.0 && isfinite(v->spacing[a]) ? v->spacing[a] : 1.0;
        if (smin == 0.0 || sp[a] < smin)
            smin = sp[a];
    }
    for (int a = 0; a < 3; a++) {
        c->spacing[a] = (float)(sp[a] / smin);
        c->inv_spacing[a] = (float)(smin / sp[a]);
        s->dims.spacing[a] = c->spacing[a];
        s->dims.inv_spacing[a] = c->inv_spacing[a];
    }
    int nx = v->nx, ny = v->ny, nz = v->nz, levels = 0;
    for (int n = 0; n < VR_MAX_LEVELS; n++) {
        levels = n + 1;
        if (nx == 1 && ny == 1 && nz == 1)
            break;
        nx = (nx + 1) / 2;
        ny = (ny + 1) / 2;
        nz = (nz + 1) / 2;
    }
    if (levels >= VR_MAX_LEVELS)
        return pp5_fail(PP5_E_RANGE, "machine renderer: volume too large for %d mip levels",
                        VR_MAX_LEVELS);
    c->levels = levels;
    s->dims.levels = levels;
    s->dims.level[0].nx = v->nx;
    s->dims.level[0].ny = v->ny;
    s->dims.level[0].nz = v->nz;
    unsigned n_gp = s->params.n_gp;
    if (n_gp > VR_MAX_GPS)
        return pp5_fail(PP5_E_CONFIG, "machine renderer: at most %d GPs", VR_MAX_GPS);
    int K = 3;
    if (K > levels - 1)
        K = levels - 1;
    int unit = 1 << K;
    c->slab_k = K;
    c->slab_t = unit * (int)((v->nz + unit * (int)n_gp - 1) / (unit * (int)n_gp));
    c->n_slab_gps = (v->nz + c->slab_t - 1) / c->slab_t;
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
    fw_bands(rs->height, (int)n_gp, c->levels2d, c->band_y0);
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

pp5_status_t fw_session_init(fw_session_t *s, const volume_t *v, const classify_tf_t *tf,
                             const shade_params_t *shade, const render_settings_t *rs,
                             const pp5_params_t *p, const fw_options_t *o)
{
    memset(s, 0, sizeof *s);
    s->params = *p;
    s->rs = *rs;
    s->shade = *shade;
    if (!v->data || v->nx < 2 || v->ny < 2 || v->nz < 2)
        return pp5_fail(PP5_E_RANGE, "machine renderer: volume must be at least 2x2x2");
    pp5_status_t st = make_config(s, v, tf, shade, rs);
    if (st != PP5_OK)
        return st;
    s->cfg.split = o->split;
    s->cfg.max_pass_bricks = o->max_pass_bricks;
    {
        int unit = 1 << (s->cfg.levels2d - 1);
        s->n_units = (rs->height + unit - 1) / unit;
        s->unit_factor = calloc((size_t)s->n_units, sizeof *s->unit_factor);
        s->unit_weight = calloc((size_t)s->n_units, sizeof *s->unit_weight);
        if (!s->unit_factor || !s->unit_weight)
            return pp5_fail(PP5_E_NOMEM, "machine renderer: out of memory");
    }
    st = machine_init(&s->m, p);
    if (st != PP5_OK)
        return st;
    s->m_ok = true;
    if (o->timeline && (st = machine_enable_timeline(&s->m)) != PP5_OK)
        return st;
    /* Each GP: config + its slab's slices with one halo slice each side. */
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
        if (st == PP5_OK && slab_bytes) {
            ring_msg_t msg;
            memset(&msg, 0, sizeof msg);
            msg.src = ring_addr(RING_NODE_HOST, 0);
            msg.dst = ring_addr(RING_NODE_GP, g);
            msg.kind = RING_MSG_GP_USER;
            msg.cls = RING_CLASS_HOST;
            msg.args[0] = VR_MSG_SLAB;
            msg.payload = v->data + plane * (size_t)z0;
            msg.payload_bytes = slab_bytes;
            st = machine_send(&s->m, &msg, s->m.sched.now);
        }
    }
    sched_stop_t stop = SCHED_STOP_IDLE;
    /* The once-per-sequence mip-map build is minutes of work on the paper's
     * workstation (§6: 5 minutes); machine_run_setup bounds it by
     * sim.setup_budget_s, while sim.budget_s bounds each frame. */
    if (st == PP5_OK)
        st = machine_run_setup(&s->m, &stop);
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
    memset(s, 0, sizeof *s);
}

/* Bands of equal estimated ray count for this gaze point: the host
 * evaluates the acuity model (gaze2d.h) on a 4x4-subsampled grid, one weight
 * per band unit of 2^(levels2d-1) rows, plus a per-row share for the
 * resampling every pixel needs.  Host work, not charged to the machine. */
void fw_bands_balanced(const gaze_model_t *gm, bool gaze, double gx, double gy, int width,
                       int height, int n_gp, int levels2d, const double *unit_factor,
                       double *unit_weight, int32_t *band_y0)
{
    int unit = 1 << (levels2d - 1);
    int units = (height + unit - 1) / unit;
    double *w = calloc((size_t)units, sizeof *w);
    if (!w || units < n_gp) {
        free(w);
        fw_bands(height, n_gp, levels2d, band_y0);
        return;
    }
    double total = 0;
    for (int u = 0; u < units; u++) {
        double y = u * unit + 0.5 * unit, sum = 0;
        for (int x = 2; x < width; x += 4) {
            float level = 0.0f;
            if (gaze) {
                double dx = x - gx, dy = y - gy;
                level = gaze_level(gm, sqrt(dx * dx + dy * dy));
            }
            sum += pow(0.25, level);
        }
        w[u] = sum * 4.0 * unit + 0.02 * width * unit;
        if (unit_weight)
            unit_weight[u] = w[u];
        /* Measured cost per estimated ray of the rows' GP in the previous
         * frame (samples per ray vary with the data). */
        if (unit_factor && unit_factor[u] > 0)
            w[u] *= unit_factor[u];
        total += w[u];
    }
    double acc = 0;
    int g = 1, u = 0;
    band_y0[0] = 0;
    for (; u < units && g < n_gp; u++) {
        acc += w[u];
        /* leave at least one unit for every remaining band */
        if (acc >= total * g / n_gp || units - (u + 1) <= n_gp - g) {
            int y = (u + 1) * unit;
            band_y0[g++] = y > height ? height : y;
        }
    }
    for (; g <= n_gp; g++)
        band_y0[g] = height;
    band_y0[n_gp] = height;
    free(w);
}

static void fill_frame(fw_session_t *s, double gx, double gy, vr_frame_t *f)
{
    camera_t cam;
    camera_setup(&cam, &s->rs.view, &s->dims, s->rs.width, s->rs.height);
    memset(f, 0, sizeof *f);
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
    if (s->rs.progressive) {
        /* Progressive refinement keeps each GP's texel rows between frames,
         * so the bands stay fixed (equal) for the whole sequence. */
        fw_bands(s->rs.height, (int)s->m.n_gp, s->cfg.levels2d, f->band_y0);
        f->progressive_keep = 1 | (s->prog_index > 0 ? 2 : 0);
        double growth = s->rs.progressive_growth > 1.0 ? s->rs.progressive_growth : 1.0;
        f->gaze_scale = pow(growth, (double)s->prog_index);
    } else {
        fw_bands_balanced(&s->gaze, s->rs.mode == RENDER_MODE_GAZE, gx, gy, s->rs.width,
                          s->rs.height, (int)s->m.n_gp, s->cfg.levels2d,
                          s->frames > 0 ? s->unit_factor : NULL, s->unit_weight, f->band_y0);
    }
}

pp5_status_t fw_session_frame(fw_session_t *s, double gx, double gy, image8_t *img,
                              fw_frame_result_t *r)
{
    memset(r, 0, sizeof *r);
    if (!isfinite(gx) || !isfinite(gy))
        return pp5_fail(PP5_E_RANGE, "machine renderer: gaze point must be finite");
    machine_t *m = &s->m;
    vr_frame_t f;
    fill_frame(s, gx, gy, &f);
    memcpy(s->last_bands, f.band_y0, sizeof s->last_bands);
    pp5_tick_t t0 = m->sched.now;
    uint64_t bytes0[RING_CLASS_COUNT];
    memcpy(bytes0, m->ring.bytes_sent, sizeof bytes0);
    pp5_tick_t *gp_busy0 = calloc(m->n_gp + m->n_rn, sizeof *gp_busy0);
    uint64_t *rn_exec0 = calloc(m->n_rn + 1, sizeof *rn_exec0);
    if (!gp_busy0 || !rn_exec0) {
        free(gp_busy0);
        free(rn_exec0);
        return pp5_fail(PP5_E_NOMEM, "machine renderer: out of memory");
    }
    for (unsigned g = 0; g < m->n_gp; g++)
        gp_busy0[g] = m->gp[g].busy_ps;
    for (unsigned j = 0; j < m->n_rn; j++) {
        gp_busy0[m->n_gp + j] = m->rn[j].busy_ps;
        rn_exec0[j] = m->rn[j].exec_cycles;
    }
    pp5_status_t st = PP5_OK;
    for (unsigned g = 0; g < m->n_gp && st == PP5_OK; g++) {
        ring_msg_t msg;
        memset(&msg, 0, sizeof msg);
        msg.src = ring_addr(RING_NODE_HOST, 0);
        msg.dst = ring_addr(RING_NODE_GP, g);
        msg.kind = RING_MSG_GP_USER;
        msg.cls = RING_CLASS_HOST;
        msg.args[0] = VR_MSG_FRAME_PARAMS;
        msg.payload = &f;
        msg.payload_bytes = sizeof f;
        st = machine_send(m, &msg, t0);
    }
    sched_stop_t stop = SCHED_STOP_IDLE;
    if (st == PP5_OK)
        st = machine_run_frame(m, &stop);
    if (st == PP5_OK && stop != SCHED_STOP_IDLE)
        st = pp5_fail(PP5_E_FIRMWARE, "machine renderer: frame stopped (%s)", sched_stop_name(stop));
    pp5_tick_t t1 = m->sched.now;
    s->frames++;
    s->prog_index++;
    if (st != PP5_OK) {
        free(gp_busy0);
        free(rn_exec0);
        return st;
    }
    double T = ticks_to_s(t1 - t0);
    r->frame_time_s = T;
    for (unsigned k = 0; k < RING_CLASS_COUNT; k++) {
        r->ring_bytes[k] = m->ring.bytes_sent[k] - bytes0[k];
        double bw = pp5_params_ring_aggregate_bytes_per_s(&s->params);
        r->ring_util[k] = T > 0 ? (double)r->ring_bytes[k] / (bw * T) : 0.0;
        r->ring_util_total += r->ring_util[k];
    }
    /* Per-GP figures and the critical GP (last to finish its sections). */
    double gp_period = 1.0 / s->params.gp_clock_hz;
    int crit = 0;
    uint64_t crit_done = 0;
    bool all0 = true;
    double gsum = 0, gmax = 0;
    for (unsigned g = 0; g < m->n_gp; g++) {
        const vr_probe_t *p = vr_probe(m->gp[g].state);
        if (!p)
            continue;
        r->rays += p->rays;
        r->samples += p->samples;
        r->samples_skipped += p->skipped;
        r->bricks_fetched += p->bricks_fetched;
        r->bytes_fetched += p->bytes_fetched;
        if (!p->all_level0)
            all0 = false;
        if (p->passes > r->passes_max)
            r->passes_max = p->passes;
        r->pp_stream_words += p->pp_stream_words;
        if (p->t_done >= crit_done) {
            crit_done = p->t_done;
            crit = (int)g;
        }
        double u = T > 0 ? ticks_to_s(m->gp[g].busy_ps - gp_busy0[g]) / T : 0;
        gsum += u;
        gmax = u > gmax ? u : gmax;
    }
    r->full_resolution_everywhere = all0;
    r->gp_util_mean = m->n_gp ? gsum / m->n_gp : 0;
    r->gp_util_max = gmax;
    double rsum = 0, rmax = 0, exec_max_s = 0;
    for (unsigned j = 0; j < m->n_rn; j++) {
        double u = T > 0 ? ticks_to_s(m->rn[j].busy_ps - gp_busy0[m->n_gp + j]) / T : 0;
        rsum += u;
        rmax = u > rmax ? u : rmax;
        uint64_t ex = m->rn[j].exec_cycles - rn_exec0[j];
        if (ex > r->rn_exec_cycles_max)
            r->rn_exec_cycles_max = ex;
    }
    exec_max_s = (double)r->rn_exec_cycles_max / s->params.renderer_clock_hz;
    r->rn_util_mean = m->n_rn ? rsum / m->n_rn : 0;
    r->rn_util_max = rmax;
    free(gp_busy0);
    free(rn_exec0);
    /* Critical-path split (see ARCHITECTURE.md "Frame report"). */
    /* The critical GP finished last.  If it waited for its neighbour's
     * boundary rows, the path runs through the neighbour's work up to the end
     * of its casting, then the boundary transfer, then the critical GP's
     * resampling. */
    const vr_probe_t *pc = vr_probe(m->gp[crit].state);
    const vr_probe_t *p = pc;
    int path = crit;
    if (pc && crit + 1 < (int)m->n_gp) {
        const vr_probe_t *pn = vr_probe(m->gp[crit + 1].state);
        if (pn && pn->rays && pc->t_boundary > pc->t_cast_done && pn->t_cast_done > pc->t_cast_done) {
            p = pn;
            path = crit + 1;
        }
    }
    r->critical_gp = crit;
    r->critical_path_gp = path;
    if (p && pc) {
        double ts = ticks_to_s(p->t_start - t0);
        double tc = ticks_to_s(p->t_cast_done - t0);
        double tb = ticks_to_s(pc->t_boundary - t0), te = ticks_to_s(pc->t_done - t0);
        double wait = ticks_to_s(p->wait_ps), cast = ticks_to_s(p->cast_ps);
        /* prep: before the first requests, plus the footprints of later passes */
        double prep = (tc - ts) - wait - cast;
        double recv = (double)(p->cyc_unpack + p->cyc_forward + p->cyc_shade) * gp_period;
        if (recv > wait)
            recv = wait;
        double pp = exec_max_s < wait - recv ? exec_max_s : wait - recv;
        if (pp < 0)
            pp = 0;
        r->phase_s[FW_PHASE_HOST_START] = ts;
        r->phase_s[FW_PHASE_GP_PREP] = prep;
        r->phase_s[FW_PHASE_GP_RECEIVE] = recv;
        r->phase_s[FW_PHASE_PP_SHADE] = pp;
        r->phase_s[FW_PHASE_RING_FETCH] = wait - recv - pp;
        r->phase_s[FW_PHASE_GP_CAST] = cast;
        r->phase_s[FW_PHASE_GP_EXCHANGE] = tb - tc;
        r->phase_s[FW_PHASE_GP_RESAMPLE] = te - tb;
        r->phase_s[FW_PHASE_FB_TRANSFER] = T - te;
    }
    /* Load balance for the next frame: each band's measured GP cycles per
     * unit of estimated work, normalised (host bookkeeping, deterministic). */
    if (!s->rs.progressive && s->unit_factor) {
        int unit = 1 << (s->cfg.levels2d - 1);
        double fsum = 0;
        int fn = 0;
        for (unsigned g = 0; g < m->n_gp; g++) {
            const vr_probe_t *pg = vr_probe(m->gp[g].state);
            int u0 = s->last_bands[g] / unit, u1 = (s->last_bands[g + 1] + unit - 1) / unit;
            if (!pg || u1 <= u0)
                continue;
            double wsum = 0;
            for (int u = u0; u < u1 && u < s->n_units; u++)
                wsum += s->unit_weight[u];
            double cost = (double)(pg->cyc_prep + pg->cyc_cast + pg->cyc_pixels + pg->cyc_unpack +
                                   pg->cyc_shade);
            double fct = wsum > 0 && cost > 0 ? cost / wsum : 0;
            for (int u = u0; u < u1 && u < s->n_units; u++)
                s->unit_factor[u] = fct;
            if (fct > 0) {
                fsum += fct;
                fn++;
            }
        }
        for (int u = 0; u < s->n_units && fn > 0; u++)
            s->unit_factor[u] = s->unit_factor[u] > 0 ? s->unit_factor[u] / (fsum / fn) : 1.0;
    }
    int best = 0;
    for (int k = 1; k < FW_PHASE_COUNT; k++)
        if (r->phase_s[k] > r->phase_s[best])
            best = k;
    r->bottleneck = fw_phase_name((fw_phase_t)best);
    r->ok = true;
    s->last = *r;
    if (img) {
        const image8_t *fb = fb_front(&m->fb);
        st = image8_alloc(img, s->rs.width, s->rs.height, 3);
        if (st != PP5_OK)
            return st;
        for (int y = 0; y < s->rs.height; y++)
            memcpy(img->pixels + (size_t)y * s->rs.width * 3,
                   fb->pixels + ((size_t)(y + s->cfg.fb_y0) * fb->width + (size_t)s->cfg.fb_x0) * 3,
                   (size_t)s->rs.width * 3);
    }
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
    out->ring_bytes = 0;
    for (unsigned k = 0; k < RING_CLASS_COUNT; k++)
        out->ring_bytes += r.ring_bytes[k];
    return PP5_OK;
}

/* ---- like-for-like native reference ---- */

pp5_status_t fw_reference_init(native_renderer_t *nr, const volume_t *v, const classify_tf_t *tf,
                               const shade_params_t *shade, const render_settings_t *rs,
                               bool quantised)
{
    pp5_status_t st = native_renderer_init(nr, v, tf, shade, rs->threads);
    if (st != PP5_OK)
        return st;
    mip3d_t *mp = &nr->mip;
    float lut[256];
    for (int i = 0; i < 256; i++)
        lut[i] = (float)i / 255.0f;
    vr_shade_consts_t consts;
    memset(&consts, 0, sizeof consts);
    float half[3] = {0, 0, 0};
    float light[3] = {0, 0, 0};
    if (mp->lighting != SHADE_DIFFUSE_FIXED_LIGHT) {
        camera_t cam;
        camera_setup(&cam, &rs->view, mp, rs->width, rs->height);
        for (int a = 0; a < 3; a++)
            light[a] = mp->lighting == SHADE_MOVING_OBJECT
                           ? shade->light_dir[0] * cam.right[a] + shade->light_dir[1] * cam.down[a] +
                                 shade->light_dir[2] * cam.forward[a]
                           : shade->light_dir[a];
        float view[3] = {-cam.forward[0], -cam.forward[1], -cam.forward[2]};
        shade_half_vector(light, view, half);
        vr_shade_consts(&consts, half, shade->specular, (int)shade->specular_exponent,
                        shade->two_sided);
        if (mp->lighting == SHADE_MOVING_OBJECT)
            vr_shade_consts_diffuse(&consts, light, shade->ambient, shade->diffuse);
    }
    for (int n = 0; n < mp->levels; n++) {
        mip3d_level_t *L = &mp->level[n];
        size_t count = (size_t)L->nx * L->ny * L->nz;
        float *out = malloc(count * 4 * sizeof(float));
        if (!out)
            return pp5_fail(PP5_E_NOMEM, "reference: out of memory");
        for (size_t i = 0; i < count; i++) {
            const float *o = L->data + i * (size_t)mp->stride;
            float *d = out + i * 4;
            if (quantised) {
                uint32_t a = vr_q8(o[0]) | vr_q8(o[1]) << 8 | vr_q8(o[2]) << 16 | vr_q8(o[3]) << 24;
                if (mp->stride == 8) {
                    float nn[3] = {o[4], o[5], o[6]};
                    float len = sqrtf(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
                    if (len > 0.0f)
                        for (int k = 0; k < 3; k++)
                            nn[k] /= len;
                    a = vr_shade_voxel(&consts, a, vr_pack_normal(nn));
                }
                for (int k = 0; k < 4; k++)
                    d[k] = lut[(a >> (8 * k)) & 255u];
            } else {
                for (int k = 0; k < 4; k++)
                    d[k] = o[k];
                if (mp->stride == 8 && o[3] > 0.0f) {
                    /* render/'s shade_sample, applied to the voxel */
                    float nn[3] = {o[4], o[5], o[6]};
                    float len = sqrtf(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
                    if (len > 0.0f)
                        for (int k = 0; k < 3; k++)
                            nn[k] /= len;
                    if (mp->lighting == SHADE_MOVING_OBJECT) {
                        float dd = shade_diffuse(shade, nn, light);
                        for (int k = 0; k < 3; k++)
                            d[k] *= dd;
                    }
                    if (len > 0.0f) {
                        float sp = o[3] * shade_specular(shade, nn, half);
                        for (int k = 0; k < 3; k++)
                            d[k] += sp;
                    }
                }
            }
        }
        free(L->data);
        L->data = out;
    }
    mp->stride = 4;
    mp->lighting = SHADE_DIFFUSE_FIXED_LIGHT;
    return PP5_OK;
}
