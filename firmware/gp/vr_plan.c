/* vr_plan.c: per frame, what a GP casts: 2DLevel of its rows, the texels its pixels need, and passes (column ranges x depth segments) whose brick footprints fit in local memory.
 *
 * Paper: seed 004 §4 last paragraph (division of work), §5 (octree), §6.
 * Partitioning, PP memory layout and the per-frame message sequence are in
 * firmware/ARCHITECTURE.md. */
#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "vr_gp_internal.h"

/* Project object-space point to image coordinates (inverse of camera_ray). */
static void project(const vr_state_t *s, const float P[3], float *px, float *py)
{
    const vr_frame_t *f = &s->fr;
    float d[3];
    if (f->projection == 0) {
        for (int a = 0; a < 3; a++)
            d[a] = P[a] - f->centre[a];
        *px = (d[0] * f->right[0] + d[1] * f->right[1] + d[2] * f->right[2]) / f->pixel_size +
              0.5f * (float)s->cfg.width;
        *py = (d[0] * f->down[0] + d[1] * f->down[1] + d[2] * f->down[2]) / f->pixel_size +
              0.5f * (float)s->cfg.height;
        return;
    }
    for (int a = 0; a < 3; a++)
        d[a] = P[a] - f->eye[a];
    float z = d[0] * f->forward[0] + d[1] * f->forward[1] + d[2] * f->forward[2];
    if (z < 1e-3f)
        z = 1e-3f;
    float k = f->eye_distance / z;
    *px = k * (d[0] * f->right[0] + d[1] * f->right[1] + d[2] * f->right[2]) / f->pixel_size +
          0.5f * (float)s->cfg.width;
    *py = k * (d[0] * f->down[0] + d[1] * f->down[1] + d[2] * f->down[2]) / f->pixel_size +
          0.5f * (float)s->cfg.height;
}

/* Does brick (n, bx, by, bz), padded by one level-n voxel, project onto the
 * rectangle [x0, x1] x [y0, y1] of image points? */
static bool brick_hits(const vr_state_t *s, int n, int bx, int by, int bz, const float rect[4],
                       const float tseg[2], fw_ops_t *ops)
{
    const vr_level_geom_t *g = &s->geom[n];
    float sc = (float)(1 << n);
    int lo[3] = {bx * g->bx, by * g->by, bz * g->bz};
    int hi[3] = {lo[0] + g->bx - 1, lo[1] + g->by - 1, lo[2] + g->bz - 1};
    float plo[3], phi[3];
    for (int a = 0; a < 3; a++) {
        /* level-0 voxel positions, padded by one level-n spacing and a margin */
        plo[a] = (((float)lo[a] + 0.5f) * sc - 0.5f - sc - 1.0f) * s->cfg.spacing[a];
        phi[a] = (((float)hi[a] + 0.5f) * sc - 0.5f + sc + 1.0f) * s->cfg.spacing[a];
    }
    float mnx = INFINITY, mxx = -INFINITY, mny = INFINITY, mxy = -INFINITY;
    float tmin = INFINITY, tmax = -INFINITY;
    const vr_frame_t *f = &s->fr;
    for (int k = 0; k < 8; k++) {
        float P[3] = {(k & 1) ? phi[0] : plo[0], (k & 2) ? phi[1] : plo[1], (k & 4) ? phi[2] : plo[2]};
        float px, py;
        project(s, P, &px, &py);
        /* Ray parameter of the corner: parallel t = depth + radius + 1;
         * perspective: between the depth along the view axis (a lower
         * bound, minimal at a corner) and the distance (maximal at one). */
        float tl, th;
        if (f->projection == 0) {
            tl = th = (P[0] - f->centre[0]) * f->forward[0] + (P[1] - f->centre[1]) * f->forward[1] +
                      (P[2] - f->centre[2]) * f->forward[2] + f->radius + 1.0f;
        } else {
            float d[3] = {P[0] - f->eye[0], P[1] - f->eye[1], P[2] - f->eye[2]};
            tl = d[0] * f->forward[0] + d[1] * f->forward[1] + d[2] * f->forward[2];
            th = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        }
        tmin = tl < tmin ? tl : tmin;
        tmax = th > tmax ? th : tmax;
        mnx = px < mnx ? px : mnx;
        mxx = px > mxx ? px : mxx;
        mny = py < mny ? py : mny;
        mxy = py > mxy ? py : mxy;
    }
    ops->fadd += 8 * 8;
    ops->fmul += 8 * 8;
    ops->fdiv += 8 * 2;
    ops->branches += 8 * 4 + 4;
    if (tmax < tseg[0] - 1.0f || tmin > tseg[1] + 1.0f)
        return false;
    return !(mxx < rect[0] - 2.0f || mnx > rect[1] + 2.0f || mxy < rect[2] - 2.0f || mny > rect[3] + 2.0f);
}

fw_status_t vr_plan_frame_start(gp_t *gp, vr_state_t *s, uint32_t frame)
{
    const vr_config_t *c = &s->cfg;
    /* Progressive refinement (paper §7): keep the 2D mip map, its flags and
     * each pixel's finest level while the bands stay the same. */
    bool reuse = (s->fr.progressive_keep & 2) && s->level &&
                 s->y0 == s->fr.band_y0[s->g] && s->y1 == s->fr.band_y0[s->g + 1];
    vr_frame_free(gp, s, reuse);
    /* The phase-boundary times of this frame (published values). */
    static const int times[] = {VR_STAT_T_PREP_DONE, VR_STAT_T_CAST_DONE, VR_STAT_T_BOUNDARY,
                                VR_STAT_T_DONE};
    for (size_t i = 0; i < sizeof times / sizeof times[0]; i++)
        vr_stat_set(gp, s, times[i], 0);
    vr_stat_set(gp, s, VR_STAT_PASSES, 0);
    vr_stat_set(gp, s, VR_STAT_T_START, fw_time_ps(gp));
    s->frame_done = false;
    s->frame = (int)frame;
    s->cast_done = false;
    s->boundary_ok = false;
    if (!s->have_octree)
        return fw_fail(gp, "vr: frame started before the mip map was distributed");
    if ((s->fr.projection != 0) != (c->perspective != 0))
        return fw_fail(gp, "vr: the projection is fixed per sequence (octree grids)");
    if (c->lighting != VR_LIGHT_DIFFUSE) {
        /* Fixed light: light_dir is in object space.  Moving object: it is in
         * eye space; carry it into object space for this view
         * (raycast_ctx_init). */
        float light[3];
        for (int a = 0; a < 3; a++)
            light[a] = c->lighting == VR_LIGHT_MOVING
                           ? c->light_dir[0] * s->fr.right[a] + c->light_dir[1] * s->fr.down[a] +
                                 c->light_dir[2] * s->fr.forward[a]
                           : c->light_dir[a];
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
    if (vr_uses_exec(s) && vr_fetch_send_exec(gp, s) != FW_OK)
        return FW_ERROR;
    s->exec_sent = true;
    if (s->pending_req_n) {
        /* requests that overtook our FRAME_START: [requester, count, ids...] records */
        size_t i = 0;
        while (i + 2 <= s->pending_req_n) {
            unsigned req = s->pending_req[i], cnt = s->pending_req[i + 1];
            if (vr_fetch_forward(gp, s, s->pending_req + i + 2, cnt, req) != FW_OK)
                return FW_ERROR;
            i += 2 + cnt;
        }
        s->pending_req_n = 0;
    }
    uint64_t c0 = fw_cycles(gp);
    fw_ops_t ops = {0};
    /* Own rows and texel rows. */
    s->levels2d = s->fr.mode == VR_MODE_GAZE ? c->levels2d : 1;
    s->maxm = s->levels2d - 1;
    s->y0 = s->fr.band_y0[s->g];
    s->y1 = s->fr.band_y0[s->g + 1];
    bool last = s->g + 1 >= s->n_gp || s->fr.band_y0[s->g + 2] == s->fr.band_y0[s->g + 1] ||
                s->y1 >= c->height;
    int W = c->width, H = c->height;
    if (s->y0 >= s->y1) {
        /* An empty band: every phase ends now. */
        for (size_t i = 0; i < sizeof times / sizeof times[0]; i++)
            vr_stat_set(gp, s, times[i], fw_time_ps(gp));
        s->t_data_done = fw_time_ps(gp);
        s->frame_done = true;
        vr_stat_set(gp, s, VR_STAT_ALL_LEVEL0, 1);
        return FW_OK;
    }
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
    uint64_t n_level = 0, n_trans = 0;
    for (int y = s->ly0; y < s->ly1; y++) {
        float *row = s->level + (size_t)(y - s->ly0) * W;
        for (int x = 0; x < W; x++) {
            float level = 0.0f;
            if (s->fr.mode == VR_MODE_GAZE) {
                double dx = (double)x - s->fr.gaze_x, dy = (double)y - s->fr.gaze_y;
                int tr = 0;
                level = vr_gaze_level(c, sqrt(dx * dx + dy * dy) / s->fr.gaze_scale, &tr);
                n_trans += (uint64_t)tr;
            }
            if (level < row[x])
                row[x] = level;    /* finest level so far (render/: level_best) */
        }
        n_level += (uint64_t)W;
    }
    if (s->fr.mode == VR_MODE_GAZE) {
        vr_cost_add(&ops, &VR_COST_LEVEL, n_level);
        vr_cost_add(&ops, &VR_COST_LEVEL_TRANS, n_trans);
    }
    /* Texel rows and marks (mip2d_mark_pixel, own rows only). */
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
    uint64_t n_mark = 0;
    for (int y = s->ly0; y < s->ly1; y++) {
        const float *row = s->level + (size_t)(y - s->ly0) * W;
        for (int x = 0; x < W; x++) {
            float level = row[x];
            int lo = (int)level;
            if (lo >= s->levels2d)
                lo = s->levels2d - 1;
            for (int pass = 0; pass < 2; pass++) {
                int l = lo + pass;
                if (pass == 1 && !(level > (float)lo && lo + 1 < s->levels2d))
                    break;
                int i = x >> l, j = y >> l;
                bool fx = (x & ((1 << l) - 1)) != 0, fy = (y & ((1 << l) - 1)) != 0;
                for (int dj = 0; dj <= (fy ? 1 : 0); dj++) {
                    int jj = j + dj;
                    if (jj < s->jlo[l] || jj > s->jhi[l])
                        continue;
                    uint8_t *nd = s->need[l] + (size_t)(jj - s->jlo[l]) * s->tw[l];
                    nd[i] = 1;
                    if (fx)
                        nd[i + 1] = 1;
                }
            }
            n_mark++;
        }
    }
    vr_cost_add(&ops, &VR_COST_MARK, n_mark);
    fw_charge(gp, &ops);
    vr_stat_add(gp, s, VR_STAT_CYC_PREP, fw_cycles(gp) - c0);
    /* Passes (column ranges x depth segments) so that one pass's bricks fit
     * in memory: first try one pass. */
    s->n_passes = s->n_cols = s->n_segs = 1;
    s->pass = 0;
    {
        const vr_frame_t *f = &s->fr;
        if (f->projection == 0) {
            s->seg_t0 = 0.0f;
            s->seg_len = 2.0f * (f->radius + 1.0f);
        } else {
            float lo = f->eye_distance - f->radius - 1.0f;
            s->seg_t0 = lo > 0.0f ? lo : 0.0f;
            s->seg_len = f->eye_distance + f->radius + 1.0f - s->seg_t0;
        }
    }

    size_t n_all = 0;
    if (vr_plan_footprint(gp, s, NULL, &n_all) != FW_OK)
        return FW_ERROR;
    uint64_t cap = fw_machine_info(gp)->local_mem_bytes, used = fw_mem_used_bytes(gp);
    uint64_t reserve = 256u * 1024u;
    uint64_t avail;
    /* GP split: a brick's N block arrives right behind its A block (same
     * renderer FIFO) and is freed once shaded, so one N is live at a time. */
    uint64_t per = VR_BRICK_VOXELS * 4u;
    if (c->lighting != VR_LIGHT_DIFFUSE && c->split == VR_SPLIT_GP)
        reserve += VR_BRICK_VOXELS * 4u;
    avail = cap > used + reserve ? cap - used - reserve : 0;
    /* The host may cap a pass's bricks below what memory allows (studies of
     * the pass machinery; 0 = memory decides). */
    if (c->max_pass_bricks > 0 && avail > (uint64_t)c->max_pass_bricks * per)
        avail = (uint64_t)c->max_pass_bricks * per;
    /* Passes: the fewest (depth segments x column ranges), both powers of
     * two, whose largest vr_plan_footprint fits (each vr_plan_footprint is charged).  Depth
     * segments split rays front to back (a ray resumes where it stopped), so
     * they shrink footprints along the view direction; columns across it. */
    bool fits = (uint64_t)n_all * per <= avail;
    /* Search up to 64 passes (the search itself is charged GP work). */
    for (int total = 2; !fits && total <= 64; total *= 2) {
        for (int segs = total; segs >= 1 && !fits; segs /= 2) {
            int cols = total / segs;
            if (segs > 16)
                continue;
            s->n_segs = segs;
            s->n_cols = cols;
            s->n_passes = segs * cols;
            n_all = 0;
            for (s->pass = 0; s->pass < s->n_passes; s->pass++) {
                size_t n = 0;
                if (vr_plan_footprint(gp, s, NULL, &n) != FW_OK)
                    return FW_ERROR;
                n_all = n > n_all ? n : n_all;
            }
            fits = (uint64_t)n_all * per <= avail;
        }
    }
    if (!fits)
        return fw_fail(gp, "vr: GP %d: the bricks of its partition do not fit in local memory "
                           "(%llu bytes free after a %llu-byte working set; %zu bricks of %llu "
                           "bytes in the largest of %d passes)",
                       s->g, (unsigned long long)avail, (unsigned long long)used, n_all,
                       (unsigned long long)per, s->n_passes);
    s->pass = 0;
    vr_stat_set(gp, s, VR_STAT_T_PREP_DONE, fw_time_ps(gp));
    return vr_fetch_request_pass(gp, s);
}

/* Pixel x range of pass p. */
/* Ray-parameter range [t0, t1) of pass q's depth segment. */
void vr_plan_seg_range(const vr_state_t *s, int q, float *t0, float *t1)
{
    int d = q % s->n_segs;
    *t0 = d == 0 ? -INFINITY : s->seg_t0 + s->seg_len * (float)d / (float)s->n_segs;
    *t1 = d + 1 == s->n_segs ? INFINITY : s->seg_t0 + s->seg_len * (float)(d + 1) / (float)s->n_segs;
}

void vr_plan_pass_range(const vr_state_t *s, int q, float *x0, float *x1)
{
    int W = s->cfg.width;
    int p = q / s->n_segs;
    *x0 = p == 0 ? -INFINITY : (float)((long)W * p / s->n_cols);
    *x1 = p + 1 == s->n_cols ? INFINITY : (float)((long)W * (p + 1) / s->n_cols);
}

/* Footprint of the current pass: bounding rectangle of its marked texel
 * points per 2D level, then the non-empty bricks of the 3D levels those rays
 * read whose padded projection meets the rectangle.  want = NULL: count only. */
fw_status_t vr_plan_footprint(gp_t *gp, vr_state_t *s, uint32_t *want, size_t *n_out)
{
    const vr_config_t *c = &s->cfg;
    fw_ops_t ops = {0};
    float px0, px1, tseg[2];
    vr_plan_pass_range(s, s->pass, &px0, &px1);
    vr_plan_seg_range(s, s->pass, &tseg[0], &tseg[1]);
    float rect[VR_MAX_2D_LEVELS][4];
    bool any_level[VR_MAX_2D_LEVELS] = {false};
    for (int m = 0; m < s->levels2d; m++) {
        rect[m][0] = rect[m][2] = INFINITY;
        rect[m][1] = rect[m][3] = -INFINITY;
        for (int j = s->jlo[m]; j <= s->jhi[m]; j++) {
            const uint8_t *nd = s->need[m] + (size_t)(j - s->jlo[m]) * s->tw[m];
            const uint8_t *cf = s->castf[m] + (size_t)(j - s->jlo[m]) * s->tw[m];
            const uint8_t *rsx = s->ray_state[m] + (size_t)(j - s->jlo[m]) * s->tw[m];
            for (int i = 0; i < s->tw[m]; i++) {
                if (!nd[i] || cf[i] || rsx[i] == 2)
                    continue;
                float px = (float)(i << m) + 0.5f, py = (float)(j << m) + 0.5f;
                if (px < px0 || px >= px1)
                    continue;
                rect[m][0] = px < rect[m][0] ? px : rect[m][0];
                rect[m][1] = px > rect[m][1] ? px : rect[m][1];
                rect[m][2] = py < rect[m][2] ? py : rect[m][2];
                rect[m][3] = py > rect[m][3] ? py : rect[m][3];
                any_level[m] = true;
            }
            ops.loads += (uint64_t)s->tw[m];
            ops.branches += (uint64_t)s->tw[m];
        }
    }
    uint8_t *wanted = fw_alloc(gp, (size_t)s->n_bricks);
    if (!wanted)
        return FW_ERROR;
    size_t n_want = 0;
    float lstep = log2f(c->sample_step);
    for (int m = 0; m < s->levels2d; m++) {
        if (!any_level[m])
            continue;
        /* 3D levels a level-m ray reads: m exactly under parallel projection
         * (raycast.h); perspective spacing varies along the ray, so m-1..m+1
         * (eye distance >= 1 radius keeps the ratio within 2). */
        float base3d = log2f(c->sample_step * (float)(1 << m)) - lstep;
        int n_lo = (int)floorf(base3d), n_hi = n_lo;
        if (s->fr.projection != 0) {
            /* Perspective: spacing t * base / eye_distance for t within the
             * bounding sphere, so levels floor(L(t_near)) .. ceil(L(t_far)). */
            float base = c->sample_step * (float)(1 << m);
            float ed = s->fr.eye_distance, rad = s->fr.radius + 1.0f;
            float t_near = ed - rad > 1e-3f ? ed - rad : 1e-3f, t_far = ed + rad;
            n_lo = (int)floorf(log2f(t_near * base / ed) - lstep);
            n_hi = (int)floorf(log2f(t_far * base / ed) - lstep) + 1;
        }
        for (int n = n_lo; n <= n_hi; n++) {
            int nn = n < 0 ? 0 : (n >= c->levels ? c->levels - 1 : n);
            const vr_level_geom_t *g = &s->geom[nn];
            for (int bz = 0; bz < g->gz; bz++)
                for (int by = 0; by < g->gy; by++)
                    for (int bx = 0; bx < g->gx; bx++) {
                        int local = (bz * g->gy + by) * g->gx + bx;
                        int id = s->brick_base[nn] + local;
                        ops.loads++;
                        ops.branches++;
                        if (wanted[id] || !s->brick_nonempty[nn][local])
                            continue;
                        if (!brick_hits(s, nn, bx, by, bz, rect[m], tseg, &ops))
                            continue;
                        wanted[id] = 1;
                        if (want)
                            want[n_want] = (uint32_t)id;
                        n_want++;
                    }
        }
    }
    fw_charge(gp, &ops);
    fw_free(gp, wanted);
    *n_out = n_want;
    return FW_OK;
}
