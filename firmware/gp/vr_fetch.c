/* vr_fetch.c: per frame, the bricks a pass needs: the PP shading stream, backing-store reads (direct or through the driver GP), received bricks and GP-side shading.
 *
 * Paper: seed 004 §4 last paragraph (division of work), §5 (octree), §6.
 * Partitioning, PP memory layout and the per-frame message sequence are in
 * firmware/ARCHITECTURE.md. */
#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "vr_cast_kernels.h"
#include "vr_gp_internal.h"

void vr_frame_free(gp_t *gp, vr_state_t *s, bool keep_view)
{
    /* Resident keeps its units across frames; image-bands drops them after
     * each pass already. */
    if (!vr_keeps_units(s) && s->cache)
        vr_units_drop_all(gp, s);
    if (s->cfg.division == VR_DIVISION_OBJECT_SLABS) {
        vr_slabs_free(gp, s);
        for (int id = 0; id < s->n_units && s->unit_tiles; id++)
            s->unit_tiles[id] = 0;
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

fw_status_t vr_fetch_forward(gp_t *gp, vr_state_t *s, const uint32_t *ids, size_t n,
                                    unsigned requester)
{
    fw_ops_t ops = {0};
    uint64_t c0 = fw_cycles(gp);
    for (size_t i = 0; i < n; i++) {
        if ((int)ids[i] >= s->n_units)
            return fw_fail(gp, "vr: request for unit %u", ids[i]);
        ops.loads++;
        ops.load_use++;              /* the id, bounds-checked at once */
        ops.int_ops += 4;
        if (vr_unit_send_read(gp, s, (int)ids[i], requester) != FW_OK)
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
        uint32_t *local = fw_alloc_copy(gp, st.words, bytes);
        if (!local) {
            rc = FW_ERROR;
            break;
        }
        rc = fw_send(gp, ring_addr(RING_NODE_RENDERER, (unsigned)r), RING_MSG_RENDERER_EXEC, NULL,
                     local, bytes);
        fw_free(gp, local);
    }
    fw_free(gp, slots);
    pp_stream_free(&st);
    vr_stat_add(gp, s, VR_STAT_CYC_EXEC_BUILD, fw_cycles(gp) - c0);
    return rc;
}

/* The requests of this pass: through each renderer's driver GP when the
 * PPs shade this frame (its reads then follow its EXEC in the same FIFO),
 * else straight to the renderers. */
fw_status_t vr_fetch_send_requests(gp_t *gp, vr_state_t *s, const uint32_t *ids, size_t n)
{
    if (!s->exec_this_frame) {
        for (size_t i = 0; i < n; i++)
            if (vr_unit_send_read(gp, s, (int)ids[i], (unsigned)s->g) != FW_OK)
                return FW_ERROR;
        return FW_OK;
    }
    uint32_t *list = fw_alloc(gp, (n + 1) * sizeof(uint32_t));
    if (!list)
        return FW_ERROR;
    fw_status_t rc = FW_OK;
    for (int d = 0; d < s->n_gp && d < s->n_r && rc == FW_OK; d++) {
        size_t k = 0;
        for (size_t i = 0; i < n; i++)
            if (driver_of(s, vr_unit_renderer(s, (int)ids[i])) == (unsigned)d)
                list[k++] = ids[i];
        if (k == 0)
            continue;
        if (d == s->g)
            rc = vr_fetch_forward(gp, s, list, k, (unsigned)s->g);
        else
            rc = vr_send_gp(gp, (unsigned)d, VR_MSG_REQUEST, (uint32_t)s->frame, 0, list,
                            k * sizeof(uint32_t));
    }
    fw_free(gp, list);
    return rc;
}

/* Resident: the wanted units already held need no read; the others get
 * room in the cache (evicting the least recently used) and are requested.
 * Compacts `want` to the units to read. */
static fw_status_t take_cached(gp_t *gp, vr_state_t *s, uint32_t *want, size_t *n)
{
    size_t k = 0;
    for (size_t i = 0; i < *n; i++) {
        int id = (int)want[i];
        s->unit_stamp[id] = (uint32_t)s->frame + 1u;
        if (s->unit_state[id] == 2)
            continue;
        if (vr_units_request(gp, s, id) != FW_OK)
            return FW_ERROR;
        want[k++] = (uint32_t)id;
    }
    *n = k;
    return FW_OK;
}

fw_status_t vr_fetch_request_pass(gp_t *gp, vr_state_t *s)
{
    uint64_t c0 = fw_cycles(gp);
    bool resident = s->cfg.division == VR_DIVISION_RESIDENT;
    size_t cap = (size_t)(resident ? s->n_units : s->n_bricks);
    uint32_t *want = fw_alloc(gp, cap * sizeof(uint32_t));
    if (!want)
        return FW_ERROR;
    size_t n_want = 0;
    fw_status_t rc = resident ? vr_footprint_units(gp, s, want, &n_want, NULL)
                              : vr_footprint_bricks(gp, s, want, &n_want);
    if (rc != FW_OK)
        return rc;
    /* Every tile waits for the wanted units it needs (one tile under
     * image-bands, whose units are the bricks). */
    for (int t = 0; t < s->tiles; t++)
        s->tile_pending[t] = 0;
    for (size_t i = 0; i < n_want; i++) {
        if (!resident)
            s->unit_tiles[want[i]] = 1;
        if (!resident || s->unit_state[want[i]] != 2)
            for (int t = 0; t < s->tiles; t++)
                s->tile_pending[t] += (s->unit_tiles[want[i]] >> t) & 1;
    }
    if (resident && take_cached(gp, s, want, &n_want) != FW_OK)
        return FW_ERROR;
    for (size_t i = 0; i < n_want && !resident; i++) {
        s->cache_bytes += vr_unit_bytes(s, (int)want[i]);   /* counted from the request */
        s->unit_state[want[i]] = 1;
    }
    vr_stat_add(gp, s, VR_STAT_CYC_PREP, fw_cycles(gp) - c0);
    s->bricks_pending = (int)n_want * vr_unit_reads(s);
    rc = vr_fetch_send_requests(gp, s, want, n_want);
    fw_free(gp, want);
    if (rc != FW_OK)
        return rc;
    vr_stat_add(gp, s, VR_STAT_BRICKS_FETCHED, n_want);
    s->t_pass_req = fw_time_ps(gp);
    s->tile = 0;
    s->blocked = true;
    s->t_blocked = s->t_pass_req;
    return vr_fetch_cast_ready(gp, s);
}

/* The pass's casting is over: drop or keep its units, then the next pass or
 * the end of casting (boundary rows to the GP above, resampling). */
static fw_status_t pass_done(gp_t *gp, vr_state_t *s)
{
    bool resident = s->cfg.division == VR_DIVISION_RESIDENT;
    for (int id = 0; id < s->n_units; id++)
        s->unit_tiles[id] = 0;
    if (!resident)
        vr_units_drop_all(gp, s);
    vr_stat_set(gp, s, VR_STAT_PASSES, (uint64_t)s->n_passes);
    if (s->pass + 1 < s->n_passes) {
        s->pass++;
        return vr_fetch_request_pass(gp, s);
    }
    s->cast_done = true;
    vr_stat_set(gp, s, VR_STAT_T_CAST_DONE, fw_time_ps(gp));
    if (s->g > 0 && vr_cast_send_boundary(gp, s) != FW_OK)
        return FW_ERROR;
    bool last = s->g + 1 >= s->n_gp || s->fr.band_y0[s->g + 2] == s->fr.band_y0[s->g + 1] ||
                s->y1 >= s->cfg.height;
    if (last)
        s->boundary_ok = true;
    return vr_resample_if_ready(gp, s);
}

fw_status_t vr_fetch_cast_ready(gp_t *gp, vr_state_t *s)
{
    if (s->cfg.division == VR_DIVISION_OBJECT_SLABS)
        return vr_slabs_progress(gp, s);
    if (s->cast_done)
        return FW_OK;
    while (s->tile < s->tiles && s->tile_pending[s->tile] == 0) {
        if (s->blocked) {
            /* The time spent waiting for this tile's units (receiving
             * included) is the pass's wait. */
            vr_stat_add(gp, s, VR_STAT_WAIT_PS, fw_time_ps(gp) - s->t_blocked);
            s->blocked = false;
        }
        int t = s->tile;
        vr_cast_texels(gp, s, t == 0 ? 0 : s->tile_y0[t], t + 1 == s->tiles ? 1 << 30 : s->tile_y0[t + 1]);
        s->tile++;
    }
    if (s->tile == s->tiles)
        return pass_done(gp, s);
    if (!s->blocked) {
        s->blocked = true;
        s->t_blocked = fw_time_ps(gp);
    }
    return FW_OK;
}

/* GP-side viewpoint-dependent shading of a unit whose A and N words are in:
 * the same integer function as the PP stream (vr_shade_fixed.h). */
static void shade_unit(gp_t *gp, vr_state_t *s, int id)
{
    uint64_t c1 = fw_cycles(gp);
    fw_ops_t o2 = {0};
    const vr_mem_t mem = {gp, &o2};
    vr_spans_t sp;
    memset(&sp, 0, sizeof sp);
    vr_shade_words(&s->shade_consts, s->cache[id], s->cache_n[id], vr_unit_bytes(s, id) / 4, &mem, &sp,
                   NULL);
    vr_spans_charge(&o2, &sp);
    fw_charge(gp, &o2);
    fw_free(gp, s->cache_n[id]);
    s->cache_n[id] = NULL;
    vr_stat_add(gp, s, VR_STAT_CYC_SHADE, fw_cycles(gp) - c1);
}

fw_status_t vr_fetch_on_data(gp_t *gp, vr_state_t *s, const ring_msg_t *m)
{
    uint32_t tag = m->args[0];
    int id = (int)(tag / 2u), which = (int)(tag & 1u);
    if (id >= s->n_units || s->unit_state[id] != 1 || m->payload_bytes != vr_unit_bytes(s, id))
        return fw_fail(gp, "vr: unexpected data message (tag %u, %zu bytes)", tag, m->payload_bytes);
    uint64_t c0 = fw_cycles(gp);
    size_t bytes = vr_unit_bytes(s, id);
    uint32_t *dst = fw_take_payload(gp, m);
    if (!dst)
        return fw_fail(gp, "vr: GP %d local memory (%llu bytes) cannot hold unit %d of this "
                           "frame's footprint: partition does not fit",
                       s->g, (unsigned long long)fw_machine_info(gp)->local_mem_bytes, id);
    /* Delivery as gp.rx_dma says (fw_api.h, [U]): with DMA the port wrote
     * the unit into local memory, without it the GP copies every word. */
    fw_ops_t ops = {0};
    fw_rx_deposit(gp, &ops, dst, 0, bytes);
    ops.int_ops = 8;
    fw_charge(gp, &ops);
    vr_stat_add(gp, s, VR_STAT_CYC_RECEIVE, fw_cycles(gp) - c0);
    vr_stat_add(gp, s, VR_STAT_BYTES_FETCHED, m->payload_bytes);
    if (which == 0)
        s->cache[id] = dst;
    else
        s->cache_n[id] = dst;
    s->bricks_pending--;
    bool gp_shade = vr_unit_reads(s) == 2;
    if (gp_shade && !(s->cache[id] && s->cache_n[id]))
        return FW_OK;
    if (gp_shade)
        shade_unit(gp, s, id);
    s->unit_state[id] = 2;
    for (int t = 0; t < s->tiles; t++)
        s->tile_pending[t] -= (s->unit_tiles[id] >> t) & 1;
    return vr_fetch_cast_ready(gp, s);
}
