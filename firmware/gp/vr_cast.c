/* vr_cast.c: per pass, the gaze-directed rays: TraceRay (render/raycast.c) on fetched bricks, with octree skipping, level blending and opacity correction (vr_cast_kernels.h), charged from the spans they ran and the data-cache lookups they declared.
 *
 * Paper: seed 004 §4 last paragraph (division of work), §5 (octree), §6.
 * Partitioning, PP memory layout and the per-frame message sequence are in
 * firmware/ARCHITECTURE.md. */
#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "vr_blend_kernels.h"
#include "vr_slab_kernels.h"
#include "vr_gp_internal.h"

/* Casts the texels of this pass whose pixel rows (row << level) lie in
 * [py0, py1): new rays, and rays parked at the end of the previous depth
 * segment.  Charged from the counted kernel executions. */
void vr_cast_texels(gp_t *gp, vr_state_t *s, int py0, int py1)
{
    uint64_t c0 = fw_cycles(gp), t0 = fw_time_ps(gp);
    vr_spans_t sp;
    memset(&sp, 0, sizeof sp);
    fw_ops_t ops = {0};
    const vr_mem_t mem = {gp, &ops};
    uint64_t rays = 0, skipped = 0;
    bool blend = vr_is_blend(s);
    vr_blend_tally_t tally = {0};
    float px0, px1, tseg[2];
    vr_plan_pass_range(s, s->pass, &px0, &px1);
    vr_plan_seg_range(s, s->pass, &tseg[0], &tseg[1]);
    for (int m = 0; m < s->levels2d; m++) {
        vr_ray_consts_t rc;
        vr_ray_consts(s, m, &rc);
        for (int j = s->jlo[m]; j <= s->jhi[m]; j++) {
            if ((j << m) < py0 || (j << m) >= py1)
                continue;
            size_t row = (size_t)(j - s->jlo[m]) * s->tw[m];
            const uint8_t *nd = s->need[m] + row;
            uint8_t *cf = s->castf[m] + row, *rsx = s->ray_state[m] + row;
            for (int i = 0; i < s->tw[m]; i++) {
                float px = (float)(i << m) + 0.5f;
                if (!nd[i] || cf[i] || rsx[i] == 2 || px < px0 || px >= px1)
                    continue;
                bool resume = rsx[i] == 1;
                if (!resume)
                    rays++;
                vr_ray_slot_t slot = {m, row + (size_t)i};
                bool done = true;
                if (blend)
                    vr_blend_trace(s, &rc, px, (float)(j << m) + 0.5f, slot, &mem, &sp, NULL,
                                   &skipped, &tally);
                else
                    done = vr_trace(s, &rc, px, (float)(j << m) + 0.5f, slot, resume, tseg[1], &mem,
                                    &sp, NULL, &skipped);
                if (done) {
                    rsx[i] = 2;
                    cf[i] = 1;
                } else {
                    rsx[i] = 1;
                }
            }
        }
    }
    vr_spans_charge(&ops, &sp);
    fw_charge(gp, &ops);
    vr_stat_add(gp, s, VR_STAT_CYC_CAST, fw_cycles(gp) - c0);
    vr_stat_add(gp, s, VR_STAT_RAYS, rays);
    vr_stat_add(gp, s, VR_STAT_SAMPLES, sp.n[VR_ROW_POINT] + sp.n[VR_ROW_VALUE_POINT]);
    vr_stat_add(gp, s, VR_STAT_SKIPPED, skipped);
    vr_stat_add(gp, s, VR_STAT_SKIPS, sp.n[VR_ROW_SKIP]);
    vr_stat_add(gp, s, VR_STAT_CAST_PS, fw_time_ps(gp) - t0);
    if (blend) {
        vr_stat_add(gp, s, VR_STAT_RAY2_SAMPLES, tally.ray2_samples);
        vr_stat_add(gp, s, VR_STAT_SATURATED, tally.saturated);
        vr_stat_add(gp, s, VR_STAT_OCCLUDED, tally.occluded);
        vr_stat_add(gp, s, VR_STAT_TERMINATED, tally.terminated);
    }
}

/* After the last pass: our first texel row of each level goes to the GP
 * above, which needs it for its last pixel rows. */
fw_status_t vr_cast_send_boundary(gp_t *gp, vr_state_t *s)
{
    size_t floats = 0;
    for (int m = 0; m < s->levels2d; m++)
        floats += (size_t)s->tw[m] * 3;
    float *buf = fw_alloc(gp, floats * sizeof(float));
    if (!buf)
        return FW_ERROR;
    size_t off = 0;
    fw_ops_t o2 = {0};
    for (int m = 0; m < s->levels2d; m++) {
        size_t bytes = (size_t)s->tw[m] * 3 * sizeof(float);
        memcpy(buf + off, s->texel[m], bytes);
        fw_dcache_access(gp, &o2, s->texel[m], 0, bytes, 0);
        fw_dcache_access(gp, &o2, buf, off * sizeof(float), bytes, 1);
        off += (size_t)s->tw[m] * 3;
    }
    o2.loads = o2.stores = floats;    /* a copy loop: the loads are scheduled */
    fw_charge(gp, &o2);
    fw_status_t rc = vr_send_gp(gp, (unsigned)(s->g - 1), VR_MSG_BOUNDARY, (uint32_t)s->frame, 0,
                                buf, floats * sizeof(float));
    fw_free(gp, buf);
    return rc;
}

/* ---- object slabs: ray segments ---- */

/* The segments through slices [zlo, zhi) of the rays of texel list tl, the
 * non-empty ones into out (as many as tl holds); returns how many. */
size_t vr_cast_slab_segments(gp_t *gp, vr_state_t *s, const vr_texel_list_t *tl, long zlo,
                             long zhi, vr_partial_t *out)
{
    uint64_t c0 = fw_cycles(gp), t0 = fw_time_ps(gp), skipped = 0;
    vr_spans_t sp;
    memset(&sp, 0, sizeof sp);
    fw_ops_t ops = {0};
    const vr_mem_t mem = {gp, &ops};
    vr_ray_consts_t rc[VR_MAX_2D_LEVELS];
    for (int m = 0; m < s->levels2d; m++)
        vr_ray_consts(s, m, &rc[m]);
    size_t n_out = 0;
    for (size_t i = 0; i < tl->n; i++) {
        const vr_texel_ref_t *r = &tl->t[i];
        vr_mem_access(&mem, tl->t, i * sizeof *r, sizeof *r, 0);
        if (vr_slab_segment(s, &rc[r->m], r, zlo, zhi, &out[n_out], &mem, &sp, NULL, &skipped)) {
            vr_mem_access(&mem, out, n_out * sizeof *out, sizeof *out, 1);
            n_out++;
        }
    }
    vr_spans_charge(&ops, &sp);
    fw_charge(gp, &ops);
    vr_stat_add(gp, s, VR_STAT_CYC_CAST, fw_cycles(gp) - c0);
    vr_stat_add(gp, s, VR_STAT_SAMPLES, sp.n[VR_ROW_POINT]);
    vr_stat_add(gp, s, VR_STAT_SKIPPED, skipped);
    vr_stat_add(gp, s, VR_STAT_SKIPS, sp.n[VR_ROW_SKIP]);
    vr_stat_add(gp, s, VR_STAT_CAST_PS, fw_time_ps(gp) - t0);
    return n_out;
}
