/* vr_plan.c: per frame, what a GP casts: the frame's shading constants, 2DLevel of its rows (by the paper's tables or exactly), the texels its pixels need, and passes (column ranges x depth segments) whose footprints fit in local memory.
 *
 * Paper: seed 004 §4 (2DLevel, the division of work), §5 (octree), §6, §7
 * (progressive refinement).  Partitioning and the per-frame message sequence
 * are in firmware/ARCHITECTURE.md. */
#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "vr_gp_internal.h"
#include "vr_image_kernels.h"

/* The phase-boundary times of a frame (published values). */
static const int phase_times[] = {VR_STAT_T_PREP_DONE, VR_STAT_T_CAST_DONE, VR_STAT_T_BOUNDARY,
                                  VR_STAT_T_DONE};
#define N_PHASE_TIMES ((int)(sizeof phase_times / sizeof phase_times[0]))

/* The view-dependent shading constants of the frame (raycast_ctx_init):
 * fixed light in object space; a moving object's light carried into object
 * space for this view. */
static void frame_shading(gp_t *gp, vr_state_t *s)
{
    const vr_config_t *c = &s->cfg;
    if (c->lighting == VR_LIGHT_DIFFUSE)
        return;
    const float *ld = s->fr.light_dir;
    float light[3];
    for (int a = 0; a < 3; a++)
        light[a] = c->lighting == VR_LIGHT_MOVING
                       ? ld[0] * s->fr.right[a] + ld[1] * s->fr.down[a] + ld[2] * s->fr.forward[a]
                       : ld[a];
    float view[3] = {-s->fr.forward[0], -s->fr.forward[1], -s->fr.forward[2]}, half[3];
    vr_half_vector(light, view, half);
    vr_shade_consts(&s->shade_consts, half, c->specular, (int)c->specular_exponent, c->two_sided);
    if (c->lighting == VR_LIGHT_MOVING)
        vr_shade_consts_diffuse(&s->shade_consts, light, c->ambient, c->diffuse);
    fw_ops_t lo = {0};
    lo.fmul = 9 + 12;
    lo.fadd = 6 + 8;
    lo.fsqrt = 1;
    lo.fdiv = 3;
    fw_charge(gp, &lo);
}

/* Divisions that keep units: what the cache may keep.  Under specular or
 * moving lighting the shaded values are a function of this frame's shading
 * constants (half vector, light), so a change of view or light invalidates
 * every cached unit and the PPs must shade again; otherwise they are still
 * this frame's values.  The diffuse mip map never changes. */
static void frame_cache(gp_t *gp, vr_state_t *s, bool *shade_pps)
{
    bool keeps = vr_keeps_units(s), diffuse = s->cfg.lighting == VR_LIGHT_DIFFUSE;
    bool same = s->cache_valid_view &&
                memcmp(&s->shade_consts, &s->cache_consts, sizeof s->cache_consts) == 0;
    *shade_pps = vr_uses_exec(s) && !(keeps && same);
    if (keeps && !diffuse && !same)
        vr_units_drop_all(gp, s);
    s->cache_consts = s->shade_consts;
    s->cache_valid_view = true;
}

/* Frame start before any work of the band: reset the published times, the
 * shading constants, the PP shading stream, and the requests of other GPs
 * that overtook our FRAME_START. */
static fw_status_t frame_begin(gp_t *gp, vr_state_t *s, uint32_t frame)
{
    for (int i = 0; i < N_PHASE_TIMES; i++)
        vr_stat_set(gp, s, phase_times[i], 0);
    vr_stat_set(gp, s, VR_STAT_PASSES, 0);
    vr_stat_set(gp, s, VR_STAT_T_START, fw_time_ps(gp));
    s->frame_done = false;
    s->frame = (int)frame;
    s->cast_done = false;
    s->boundary_ok = false;
    if (!s->have_octree)
        return fw_fail(gp, "vr: frame started before the mip map was distributed");
    if ((s->fr.projection != 0) != (s->cfg.perspective != 0))
        return fw_fail(gp, "vr: the projection is fixed per sequence (octree grids)");
    frame_shading(gp, s);
    bool shade_pps;
    frame_cache(gp, s, &shade_pps);
    s->exec_this_frame = shade_pps;
    if (shade_pps && vr_fetch_send_exec(gp, s) != FW_OK)
        return FW_ERROR;
    s->exec_sent = true;
    /* requests that overtook our FRAME_START: [requester, count, ids...] records */
    for (size_t i = 0; i + 2 <= s->pending_req_n;) {
        unsigned req = s->pending_req[i], cnt = s->pending_req[i + 1];
        if (vr_fetch_forward(gp, s, s->pending_req + i + 2, cnt, req) != FW_OK)
            return FW_ERROR;
        i += 2 + cnt;
    }
    s->pending_req_n = 0;
    return FW_OK;
}

/* 2DLevel of rows [ly0, ly1), each pixel keeping the finest level it has
 * had (render/: level_best).  By the paper's two tables (vr_kernels.h) or
 * exactly (atan, exp and log2 where the level is not constant). */
static void frame_levels(vr_state_t *s, vr_spans_t *sp)
{
    int W = s->cfg.width;
    bool gaze = s->fr.mode == VR_MODE_GAZE, tables = gaze && s->cfg.level_tables;
    int gx = (int)floor(s->fr.gaze_x + 0.5), gy = (int)floor(s->fr.gaze_y + 0.5);
    for (int y = s->ly0; y < s->ly1; y++) {
        float *row = s->level + (size_t)(y - s->ly0) * W;
        for (int x = 0; x < W; x++)
            vr_pixel_level(s, x, y, gaze, tables, gx, gy, &row[x], sp, NULL);
    }
}

/* The band's texel rows of each 2D level, and per texel the ray state that
 * lets depth segments resume a ray. */
static fw_status_t frame_texels(gp_t *gp, vr_state_t *s, bool reuse, bool last)
{
    int W = s->cfg.width, H = s->cfg.height;
    for (int m = 0; m < s->levels2d; m++) {
        s->tw[m] = ((W - 1) >> m) + 2;
        s->th[m] = ((H - 1) >> m) + 2;
        s->jlo[m] = (s->y0 + (1 << m) - 1) >> m;
        s->jhi[m] = last ? s->th[m] - 1 : ((s->y1 + (1 << m) - 1) >> m) - 1;
        int rows = s->jhi[m] - s->jlo[m] + 2;
        if (reuse) {
            memset(s->need[m], 0, (size_t)rows * s->tw[m]);
            continue;
        }
        s->texel[m] = fw_alloc(gp, (size_t)rows * s->tw[m] * 3 * sizeof(float));
        s->need[m] = fw_alloc(gp, (size_t)rows * s->tw[m]);
        s->castf[m] = fw_alloc(gp, (size_t)rows * s->tw[m]);
        if (!s->texel[m] || !s->need[m] || !s->castf[m])
            return FW_ERROR;
    }
    for (int m = 0; m < s->levels2d; m++) {
        size_t n = (size_t)(s->jhi[m] - s->jlo[m] + 1) * s->tw[m];
        s->ray_state[m] = fw_alloc(gp, n);
        s->ray_a[m] = fw_alloc(gp, n * sizeof(float));
        s->ray_t[m] = fw_alloc(gp, n * sizeof(float));
        s->ray_k[m] = fw_alloc(gp, n * sizeof(int32_t));
        if (!s->ray_state[m] || !s->ray_a[m] || !s->ray_t[m] || !s->ray_k[m])
            return FW_ERROR;
    }
    return FW_OK;
}

/* Marks the texels the band's pixels need (mip2d_mark_pixel, own rows). */
static void frame_marks(vr_state_t *s, vr_spans_t *sp)
{
    int W = s->cfg.width;
    for (int y = s->ly0; y < s->ly1; y++) {
        const float *row = s->level + (size_t)(y - s->ly0) * W;
        for (int x = 0; x < W; x++)
            vr_mark_pixel(s, x, y, row[x], sp, NULL);
    }
}

/* Tiles of the band: ray groups cast as soon as their units are in
 * (resident), one group otherwise. */
static void frame_tiles(vr_state_t *s)
{
    int rows = s->y1 - s->y0;
    s->tiles = s->cfg.division == VR_DIVISION_RESIDENT && s->cfg.tiles > 1 ? s->cfg.tiles : 1;
    if (s->tiles > VR_MAX_TILES)
        s->tiles = VR_MAX_TILES;
    if (s->tiles > rows)
        s->tiles = rows > 0 ? rows : 1;
    for (int t = 0; t <= s->tiles; t++)
        s->tile_y0[t] = s->y0 + (int)((long)rows * t / s->tiles);
}

/* The footprint of the current pass: units (resident) or bricks, and their
 * bytes in local memory. */
static fw_status_t pass_footprint(gp_t *gp, vr_state_t *s, uint64_t *bytes)
{
    size_t n = 0;
    if (s->cfg.division == VR_DIVISION_RESIDENT)
        return vr_footprint_units(gp, s, NULL, &n, bytes);
    fw_status_t rc = vr_footprint_bricks(gp, s, NULL, &n);
    *bytes = (uint64_t)n * VR_BRICK_VOXELS * 4u;
    return rc;
}

/* The fewest passes (depth segments x column ranges, both powers of two, at
 * most 64) whose largest footprint fits in the memory left; each footprint
 * tried is charged GP work.  Depth segments split rays front to back (a ray
 * resumes where it stopped), columns split across the view. */
static fw_status_t frame_passes(gp_t *gp, vr_state_t *s)
{
    const vr_config_t *c = &s->cfg;
    const vr_frame_t *f = &s->fr;
    s->n_passes = s->n_cols = s->n_segs = 1;
    s->pass = 0;
    float lo = f->eye_distance - f->radius - 1.0f;
    s->seg_t0 = f->projection == 0 ? 0.0f : (lo > 0.0f ? lo : 0.0f);
    s->seg_len = f->projection == 0 ? 2.0f * (f->radius + 1.0f)
                                    : f->eye_distance + f->radius + 1.0f - s->seg_t0;
    uint64_t need = 0;
    if (pass_footprint(gp, s, &need) != FW_OK)
        return FW_ERROR;
    uint64_t cap = fw_machine_info(gp)->local_mem_bytes;
    /* Cached units can be evicted: they do not count against the frame. */
    uint64_t used = fw_mem_used_bytes(gp) - s->cache_bytes, reserve = 256u * 1024u;
    /* GP split: a unit's N words arrive right behind its A words (same
     * renderer FIFO) and are freed once shaded, so one N is live at a time. */
    if (vr_unit_reads(s) == 2)
        reserve += VR_BRICK_VOXELS * 4u;
    uint64_t avail = cap > used + reserve ? cap - used - reserve : 0;
    /* The host may cap a pass's bricks below what memory allows (studies of
     * the pass machinery; 0 = memory decides). */
    if (c->max_pass_bricks > 0 && avail > (uint64_t)c->max_pass_bricks * VR_BRICK_VOXELS * 4u)
        avail = (uint64_t)c->max_pass_bricks * VR_BRICK_VOXELS * 4u;
    bool fits = need <= avail;
    for (int total = 2; !fits && total <= 64; total *= 2)
        for (int segs = total; segs >= 1 && !fits; segs /= 2) {
            /* A blend's ray needs the whole ray in one pass: DEMIP's ray 2
             * restarts at the entry, so it cannot be parked front to back. */
            if (segs > 16 || (vr_is_blend(s) && segs > 1))
                continue;
            s->n_segs = segs;
            s->n_cols = total / segs;
            s->n_passes = total;
            need = 0;
            for (s->pass = 0; s->pass < s->n_passes; s->pass++) {
                uint64_t b = 0;
                if (pass_footprint(gp, s, &b) != FW_OK)
                    return FW_ERROR;
                need = b > need ? b : need;
            }
            fits = need <= avail;
        }
    if (!fits)
        return fw_fail(gp, "vr: GP %d: the bricks of its partition do not fit in local memory "
                           "(%llu bytes free after a %llu-byte working set; %llu bytes in the "
                           "largest of %d passes%s)", s->g, (unsigned long long)avail,
                       (unsigned long long)used, (unsigned long long)need, s->n_passes,
                       vr_is_blend(s) ? "; a blend's rays are cast whole, in column passes only: "
                                        "try division=resident" : "");
    s->pass = 0;
    s->cache_budget = avail;
    return FW_OK;
}

/* A band with no rows: every phase ends now. */
static fw_status_t empty_band(gp_t *gp, vr_state_t *s)
{
    for (int i = 0; i < N_PHASE_TIMES; i++)
        vr_stat_set(gp, s, phase_times[i], fw_time_ps(gp));
    s->frame_done = true;
    vr_stat_set(gp, s, VR_STAT_ALL_LEVEL0, 1);
    return FW_OK;
}

fw_status_t vr_plan_frame_start(gp_t *gp, vr_state_t *s, uint32_t frame)
{
    /* Progressive refinement (paper §7): keep the 2D mip map, its flags and
     * each pixel's finest level while the bands stay the same. */
    bool reuse = (s->fr.progressive_keep & 2) && s->level &&
                 s->y0 == s->fr.band_y0[s->g] && s->y1 == s->fr.band_y0[s->g + 1];
    vr_frame_free(gp, s, reuse);
    if (frame_begin(gp, s, frame) != FW_OK)
        return FW_ERROR;
    uint64_t c0 = fw_cycles(gp);
    fw_ops_t ops = {0};
    int W = s->cfg.width, H = s->cfg.height;
    s->levels2d = s->fr.mode == VR_MODE_GAZE ? s->cfg.levels2d : 1;
    s->maxm = s->levels2d - 1;
    s->y0 = s->fr.band_y0[s->g];
    s->y1 = s->fr.band_y0[s->g + 1];
    bool last = s->g + 1 >= s->n_gp || s->fr.band_y0[s->g + 2] == s->fr.band_y0[s->g + 1] ||
                s->y1 >= H;
    if (s->y0 >= s->y1 && s->cfg.division != VR_DIVISION_OBJECT_SLABS)
        return empty_band(gp, s);
    if (s->y0 >= s->y1)           /* no band, but its slab's segments of every band */
        return vr_slabs_frame(gp, s);
    int span = 1 << s->maxm;
    s->ly0 = s->y0 - span < 0 ? 0 : s->y0 - span;
    s->ly1 = s->y1 + span > H ? H : s->y1 + span;
    if (!reuse) {
        s->level = fw_alloc(gp, (size_t)(s->ly1 - s->ly0) * W * sizeof(float));
        if (!s->level)
            return FW_ERROR;
        for (size_t i = 0; i < (size_t)(s->ly1 - s->ly0) * W; i++)
            s->level[i] = INFINITY;
    }
    vr_spans_t sp;
    memset(&sp, 0, sizeof sp);
    frame_levels(s, &sp);
    if (frame_texels(gp, s, reuse, last) != FW_OK)
        return FW_ERROR;
    frame_marks(s, &sp);
    vr_spans_charge(&ops, &sp);
    fw_charge(gp, &ops);
    vr_stat_add(gp, s, VR_STAT_CYC_PREP, fw_cycles(gp) - c0);
    if (s->cfg.division == VR_DIVISION_OBJECT_SLABS)
        return vr_slabs_frame(gp, s);
    frame_tiles(s);
    if (frame_passes(gp, s) != FW_OK)
        return FW_ERROR;
    vr_stat_set(gp, s, VR_STAT_T_PREP_DONE, fw_time_ps(gp));
    return vr_fetch_request_pass(gp, s);
}

/* Ray-parameter range [t0, t1) of pass q's depth segment. */
void vr_plan_seg_range(const vr_state_t *s, int q, float *t0, float *t1)
{
    int d = q % s->n_segs;
    *t0 = d == 0 ? -INFINITY : s->seg_t0 + s->seg_len * (float)d / (float)s->n_segs;
    *t1 = d + 1 == s->n_segs ? INFINITY : s->seg_t0 + s->seg_len * (float)(d + 1) / (float)s->n_segs;
}

/* Pixel x range [x0, x1) of pass q's column range. */
void vr_plan_pass_range(const vr_state_t *s, int q, float *x0, float *x1)
{
    int W = s->cfg.width;
    int p = q / s->n_segs;
    *x0 = p == 0 ? -INFINITY : (float)((long)W * p / s->n_cols);
    *x1 = p + 1 == s->n_cols ? INFINITY : (float)((long)W * (p + 1) / s->n_cols);
}
