/* vr_fetch.c: per frame, the bricks a pass needs: the PP shading stream, backing-store reads (direct or through the driver GP), received bricks and GP-side shading.
 *
 * Paper: seed 004 §4 last paragraph (division of work), §5 (octree), §6.
 * Partitioning, PP memory layout and the per-frame message sequence are in
 * firmware/ARCHITECTURE.md. */
#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "vr_gp_internal.h"

void vr_frame_free(gp_t *gp, vr_state_t *s, bool keep_view)
{
    for (int i = 0; i < s->n_bricks; i++) {
        if (s->cache[i]) {
            fw_free(gp, s->cache[i]);
            s->cache[i] = NULL;
        }
        if (s->cache_n[i]) {
            fw_free(gp, s->cache_n[i]);
            s->cache_n[i] = NULL;
        }
    }
    for (int m = 0; m < VR_MAX_2D_LEVELS; m++) {
        if (s->ray_state[m])
            fw_free(gp, s->ray_state[m]);
        if (s->ray_a[m])
            fw_free(gp, s->ray_a[m]);
        if (s->ray_t[m])
            fw_free(gp, s->ray_t[m]);
        if (s->ray_k[m])
            fw_free(gp, s->ray_k[m]);
        s->ray_state[m] = NULL;
        s->ray_a[m] = s->ray_t[m] = NULL;
        s->ray_k[m] = NULL;
    }
    if (keep_view)
        return;
    for (int m = 0; m < VR_MAX_2D_LEVELS; m++) {
        if (s->texel[m])
            fw_free(gp, s->texel[m]);
        if (s->need[m])
            fw_free(gp, s->need[m]);
        if (s->castf[m])
            fw_free(gp, s->castf[m]);
        s->texel[m] = NULL;
        s->need[m] = NULL;
        s->castf[m] = NULL;
    }
    if (s->level)
        fw_free(gp, s->level);
    s->level = NULL;
}

/* Backing-store block a GP reads for brick id (and the N block, GP split). */
static unsigned brick_block(const vr_state_t *s, int id, int which)
{
    unsigned slot = (unsigned)id / (unsigned)s->n_r;
    unsigned base = slot * (unsigned)s->blocks_per_slot;
    if (s->cfg.lighting == VR_LIGHT_DIFFUSE)
        return base;
    if (s->cfg.split == VR_SPLIT_PP)
        return base + 2;
    return base + (unsigned)which;
}

static fw_status_t send_read(gp_t *gp, vr_state_t *s, int id, unsigned requester)
{
    unsigned r = (unsigned)id % (unsigned)s->n_r;
    int reads = (s->cfg.lighting != VR_LIGHT_DIFFUSE && s->cfg.split == VR_SPLIT_GP) ? 2 : 1;
    for (int w = 0; w < reads; w++) {
        uint32_t args[RING_MSG_ARGS] = {brick_block(s, id, w), 0,
                                        ring_addr_pack(ring_addr(RING_NODE_GP, requester)),
                                        (uint32_t)id * 2u + (uint32_t)w, 0, 0};
        if (fw_send(gp, ring_addr(RING_NODE_RENDERER, r), RING_MSG_RENDERER_READ_BS, args, NULL, 0) != FW_OK)
            return FW_ERROR;
    }
    return FW_OK;
}

fw_status_t vr_fetch_forward(gp_t *gp, vr_state_t *s, const uint32_t *ids, size_t n,
                                    unsigned requester)
{
    fw_ops_t ops = {0};
    uint64_t c0 = fw_cycles(gp);
    for (size_t i = 0; i < n; i++) {
        if ((int)ids[i] >= s->n_bricks)
            return fw_fail(gp, "vr: request for brick %u", ids[i]);
        ops.loads++;
        ops.int_ops += 4;
        if (send_read(gp, s, (int)ids[i], requester) != FW_OK)
            return FW_ERROR;
    }
    fw_charge(gp, &ops);
    vr_stat_add(gp, s, VR_STAT_CYC_FORWARD, fw_cycles(gp) - c0);
    return FW_OK;
}

/* Driver GP of renderer r. */
static unsigned driver_of(const vr_state_t *s, unsigned r)
{
    return r % (unsigned)s->n_gp;
}

fw_status_t vr_fetch_send_exec(gp_t *gp, vr_state_t *s)
{
    uint64_t c0 = fw_cycles(gp);
    fw_ops_t ops = {0};
    ops.fadd += 8;
    ops.fmul += 10;
    ops.fsqrt += 1;
    ops.fdiv += 3;
    pp_stream_t st;
    pp_stream_init(&st);
    uint32_t *slots = fw_alloc(gp, fw_machine_info(gp)->pp_bs_blocks * sizeof(uint32_t));
    if (!slots)
        return FW_ERROR;
    fw_status_t rc = FW_OK;
    for (int r = s->g; r < s->n_r && rc == FW_OK; r += s->n_gp) {
        size_t n = 0;
        for (int id = r; id < s->n_bricks; id += s->n_r) {
            /* non-empty? */
            int n3 = 0;
            while (n3 + 1 < s->cfg.levels && id >= s->brick_base[n3 + 1])
                n3++;
            ops.int_ops += 4;
            ops.branches += 2;
            if (s->brick_nonempty[n3][id - s->brick_base[n3]])
                slots[n++] = (uint32_t)(id / s->n_r);
        }
        pp_stream_clear(&st);
        vr_pp_shade_stream(&st, &s->shade_consts, slots, n);
        ops.int_ops += 2 * st.n_words;
        ops.stores += st.n_words;
        fw_charge(gp, &ops);
        memset(&ops, 0, sizeof ops);
        if (!pp_stream_ok(&st)) {
            rc = fw_fail(gp, "vr: shading stream: %s", pp_stream_error(&st));
            break;
        }
        vr_stat_add(gp, s, VR_STAT_PP_STREAM_WORDS, st.n_words);
        size_t bytes = st.n_words * 4;
        uint32_t *local = fw_alloc(gp, bytes);
        if (!local) {
            rc = FW_ERROR;
            break;
        }
        memcpy(local, st.words, bytes);
        rc = fw_send(gp, ring_addr(RING_NODE_RENDERER, (unsigned)r), RING_MSG_RENDERER_EXEC, NULL,
                     local, bytes);
        fw_free(gp, local);
    }
    fw_free(gp, slots);
    pp_stream_free(&st);
    vr_stat_add(gp, s, VR_STAT_CYC_EXEC_BUILD, fw_cycles(gp) - c0);
    return rc;
}

fw_status_t vr_fetch_request_pass(gp_t *gp, vr_state_t *s)
{
    const vr_config_t *c = &s->cfg;
    uint64_t c0 = fw_cycles(gp);
    uint32_t *want = fw_alloc(gp, (size_t)s->n_bricks * sizeof(uint32_t));
    if (!want)
        return FW_ERROR;
    size_t n_want = 0;
    if (vr_plan_footprint(gp, s, want, &n_want) != FW_OK)
        return FW_ERROR;
    vr_stat_add(gp, s, VR_STAT_CYC_PREP, fw_cycles(gp) - c0);
    uint32_t frame = (uint32_t)s->frame;
    /* Requests: via the renderer's driver GP when the PPs shade this frame
     * (its READ_BS then follows its EXEC in the same FIFO), else direct. */
    s->bricks_pending = (int)n_want * ((c->lighting != VR_LIGHT_DIFFUSE && c->split == VR_SPLIT_GP) ? 2 : 1);
    if (vr_uses_exec(s)) {
        uint32_t *list = fw_alloc(gp, (n_want + 1) * sizeof(uint32_t));
        if (!list)
            return FW_ERROR;
        for (int d = 0; d < s->n_gp && d < s->n_r; d++) {
            size_t k = 0;
            for (size_t i = 0; i < n_want; i++)
                if (driver_of(s, want[i] % (unsigned)s->n_r) == (unsigned)d)
                    list[k++] = want[i];
            if (k == 0)
                continue;
            if (d == s->g) {
                if (vr_fetch_forward(gp, s, list, k, (unsigned)s->g) != FW_OK)
                    return FW_ERROR;
            } else if (vr_send_gp(gp, (unsigned)d, VR_MSG_REQUEST, (uint32_t)frame, 0, list,
                               k * sizeof(uint32_t)) != FW_OK) {
                return FW_ERROR;
            }
        }
        fw_free(gp, list);
    } else {
        for (size_t i = 0; i < n_want; i++)
            if (send_read(gp, s, (int)want[i], (unsigned)s->g) != FW_OK)
                return FW_ERROR;
    }
    fw_free(gp, want);
    vr_stat_add(gp, s, VR_STAT_BRICKS_FETCHED, n_want);
    s->t_pass_req = fw_time_ps(gp);
    return vr_fetch_start_cast_if_ready(gp, s);
}

fw_status_t vr_fetch_start_cast_if_ready(gp_t *gp, vr_state_t *s)
{
    if (s->bricks_pending > 0 || s->cast_done)
        return FW_OK;
    s->t_data_done = fw_time_ps(gp);
    vr_stat_add(gp, s, VR_STAT_WAIT_PS, s->t_data_done - s->t_pass_req);
    return vr_cast_pass(gp, s);
}

fw_status_t vr_fetch_on_data(gp_t *gp, vr_state_t *s, const ring_msg_t *m)
{
    uint32_t tag = m->args[0];
    int id = (int)(tag / 2u), which = (int)(tag & 1u);
    if (id >= s->n_bricks || m->payload_bytes != VR_BRICK_VOXELS * 4u)
        return fw_fail(gp, "vr: unexpected data message (tag %u, %zu bytes)", tag, m->payload_bytes);
    uint64_t c0 = fw_cycles(gp);
    uint32_t *dst = fw_alloc(gp, VR_BRICK_VOXELS * 4u);
    if (!dst)
        return fw_fail(gp, "vr: GP %d local memory (%llu bytes) cannot hold brick %d of this "
                           "frame's vr_plan_footprint: partition does not fit",
                       s->g, (unsigned long long)fw_machine_info(gp)->local_mem_bytes, id);
    memcpy(dst, m->payload, VR_BRICK_VOXELS * 4u);
    /* The ring port deposits the brick in local memory over the i860's
     * external bus (DMA-like, [I]); the GP pays the bus time, not a copy loop. */
    fw_ops_t ops = {0};
    ops.ext_bytes = VR_BRICK_VOXELS * 4u;
    ops.int_ops = 8;
    fw_charge(gp, &ops);
    vr_stat_add(gp, s, VR_STAT_CYC_RECEIVE, fw_cycles(gp) - c0);
    vr_stat_add(gp, s, VR_STAT_BYTES_FETCHED, m->payload_bytes);
    bool gp_shade = s->cfg.lighting != VR_LIGHT_DIFFUSE && s->cfg.split == VR_SPLIT_GP;
    if (!gp_shade) {
        s->cache[id] = dst;
    } else {
        if (which == 0)
            s->cache[id] = dst;
        else
            s->cache_n[id] = dst;
        if (s->cache[id] && s->cache_n[id]) {
            /* Viewpoint-dependent shading on the GP: same integer function
             * as the PP stream (vr_shade_fixed.h). */
            uint64_t c1 = fw_cycles(gp);
            uint32_t *a = s->cache[id];
            const uint32_t *nb = s->cache_n[id];
            for (unsigned i = 0; i < VR_BRICK_VOXELS; i++)
                a[i] = vr_shade_voxel(&s->shade_consts, a[i], nb[i]);
            fw_ops_t o2 = {0};
            vr_cost_add(&o2, &VR_COST_SHADE_VOXEL, VR_BRICK_VOXELS);
            fw_charge(gp, &o2);
            fw_free(gp, s->cache_n[id]);
            s->cache_n[id] = NULL;
            vr_stat_add(gp, s, VR_STAT_CYC_SHADE, fw_cycles(gp) - c1);
        }
    }
    s->bricks_pending--;
    return vr_fetch_start_cast_if_ready(gp, s);
}
