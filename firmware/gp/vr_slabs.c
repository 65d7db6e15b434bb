/* vr_slabs.c: the object-slabs work division (sort-last): every GP casts the segment of each needed ray that lies in its own slab of the volume, ships the segments' colours and opacities to the owner of the ray's image band, and the owner composites them front to back and resamples its band.
 *
 * Per frame (firmware/ARCHITECTURE.md "Work divisions"):
 *   1. each band owner computes 2DLevel and the texels its band needs and
 *      sends that set to every GP (VR_MSG_NEED, a bit per texel);
 *   2. each GP fetches the units of its slab it does not hold (kept across
 *      frames as under resident) and, for every band whose set has arrived,
 *      casts those texels' segments through its slab and sends the non-empty
 *      ones to the band's owner (VR_MSG_PARTIAL);
 *   3. each owner composites the partials of its texels in slab order along
 *      the view direction, then resamples as under image-bands (boundary
 *      rows from the next band, RenderPixel, sections to the frame buffer).
 * Early ray termination acts within a segment only: a segment does not know
 * the opacity in front of it.  Parallel projection only. */
#include <limits.h>
#include <string.h>

#include "vr_slab_kernels.h"

/* Band h's texel rows per 2D level, as frame_texels computes a band's own. */
static void band_geom(const vr_state_t *s, int h, vr_band_geom_t *bg)
{
    int W = s->cfg.width, H = s->cfg.height;
    int y0 = s->fr.band_y0[h], y1 = s->fr.band_y0[h + 1];
    bool last = h + 1 >= s->n_gp || s->fr.band_y0[h + 2] == s->fr.band_y0[h + 1] || y1 >= H;
    bg->base[0] = 0;
    for (int m = 0; m < s->levels2d; m++) {
        int th = ((H - 1) >> m) + 2;
        bg->tw[m] = ((W - 1) >> m) + 2;
        bg->jlo[m] = (y0 + (1 << m) - 1) >> m;
        bg->jhi[m] = last ? th - 1 : ((y1 + (1 << m) - 1) >> m) - 1;
        int rows = bg->jhi[m] >= bg->jlo[m] ? bg->jhi[m] - bg->jlo[m] + 1 : 0;
        bg->base[m + 1] = bg->base[m] + (uint32_t)rows * (uint32_t)bg->tw[m];
    }
}

static bool band_has_rows(const vr_state_t *s, int h)
{
    return s->fr.band_y0[h] < s->fr.band_y0[h + 1];
}

/* Band h's needed texels, from its bit set. */
static fw_status_t unpack_need(gp_t *gp, vr_state_t *s, int h, const uint8_t *bits, size_t bytes)
{
    vr_band_geom_t bg;
    band_geom(s, h, &bg);
    uint32_t total = bg.base[s->levels2d];
    if (bytes != (total + 7) / 8)
        return fw_fail(gp, "vr: need set of band %d has %zu bytes, expected %u", h, bytes,
                       (total + 7) / 8);
    vr_spans_t sp;
    memset(&sp, 0, sizeof sp);
    size_t n = vr_need_count(bits, total, &sp, NULL);
    vr_texel_list_t *tl = &s->band_need[h];
    tl->t = fw_alloc(gp, (n ? n : 1) * sizeof *tl->t);
    if (!tl->t)
        return FW_ERROR;
    tl->n = vr_need_unpack(bits, &bg, s->levels2d, tl->t, &sp, NULL);
    fw_ops_t ops = {0};
    fw_dcache_access(gp, &ops, tl->t, 0, tl->n * sizeof *tl->t, 1);
    vr_spans_charge(&ops, &sp);
    fw_charge(gp, &ops);
    s->need_in[h] = true;
    s->needs_pending--;
    return FW_OK;
}

/* Our band's needed texels as a bit set, to every GP (and to ourselves). */
static fw_status_t send_need(gp_t *gp, vr_state_t *s)
{
    vr_band_geom_t bg;
    band_geom(s, s->g, &bg);
    uint32_t total = bg.base[s->levels2d];
    size_t bytes = (total + 7) / 8;
    uint8_t *bits = fw_alloc(gp, bytes ? bytes : 1);
    if (!bits)
        return FW_ERROR;
    vr_spans_t sp;
    memset(&sp, 0, sizeof sp);
    vr_need_pack(s->need, s->jlo, s->tw, &bg, s->levels2d, bits, &sp, NULL);
    fw_ops_t ops = {0};
    vr_spans_charge(&ops, &sp);
    fw_charge(gp, &ops);
    fw_status_t rc = FW_OK;
    for (int h = 0; h < s->n_gp && rc == FW_OK; h++)
        if (h != s->g)
            rc = vr_send_gp(gp, (unsigned)h, VR_MSG_NEED, (uint32_t)s->g, (uint32_t)s->frame, bits,
                            bytes);
    if (rc == FW_OK)
        rc = unpack_need(gp, s, s->g, bits, bytes);
    fw_free(gp, bits);
    return rc;
}

/* The units of our slab, at every 3D level the frame's rays sample (3D
 * level m for 2D level m under parallel projection): those holding the
 * voxels that trilinear lookups at sample slices [zlo, zhi) can touch. */
static bool unit_in_slab(const vr_state_t *s, int id)
{
    int n, ijk[3];
    vr_unit_locate(s, id, &n, ijk);
    if (n > s->maxm || n >= s->cfg.levels)
        return false;
    const vr_unit_geom_t *u = &s->unit[n];
    long sc = 1L << n;
    /* level-n z coordinate of level-0 slice z: (z + 0.5) / 2^n - 0.5 */
    long lo = s->zslab_lo == LONG_MIN ? LONG_MIN : (2 * s->zslab_lo + 1 - sc) / (2 * sc) - 1;
    long hi = s->zslab_hi == LONG_MAX ? LONG_MAX : (2 * s->zslab_hi + 1 - sc) / (2 * sc) + 1;
    long z0 = (long)ijk[2] * u->uz, z1 = z0 + u->uz - 1;
    return z1 >= lo && z0 <= hi;
}

static fw_status_t request_slab_units(gp_t *gp, vr_state_t *s)
{
    uint32_t *want = fw_alloc(gp, (size_t)s->n_units * sizeof *want);
    if (!want)
        return FW_ERROR;
    size_t n = 0;
    fw_ops_t ops = {0};
    for (int id = 0; id < s->n_units; id++) {
        ops.loads += 2;
        ops.int_ops += 8;
        ops.branches += 2;
        if (!s->unit_nonempty[id] || !unit_in_slab(s, id))
            continue;
        s->unit_stamp[id] = (uint32_t)s->frame + 1u;
        s->unit_tiles[id] = 1;       /* needed by this frame: not to be evicted */
        if (s->unit_state[id] == 2)
            continue;
        if (vr_units_request(gp, s, id) != FW_OK)
            return FW_ERROR;
        want[n++] = (uint32_t)id;
    }
    fw_charge(gp, &ops);
    s->bricks_pending = (int)n * vr_unit_reads(s);
    fw_status_t rc = vr_fetch_send_requests(gp, s, want, n);
    fw_free(gp, want);
    vr_stat_add(gp, s, VR_STAT_BRICKS_FETCHED, n);
    return rc;
}

/* Deferred messages: [kind word, src, args[0..2], payload bytes, payload]. */
fw_status_t vr_slabs_defer(gp_t *gp, vr_state_t *s, const ring_msg_t *m)
{
    size_t rec = 6 * sizeof(uint32_t) + m->payload_bytes, old = s->deferred_bytes;
    uint8_t *buf = fw_alloc(gp, old + rec);
    if (!buf)
        return FW_ERROR;
    if (s->deferred) {
        memcpy(buf, s->deferred, old);
        fw_free(gp, s->deferred);
    }
    uint32_t head[6] = {m->kind, m->src.index, m->args[0], m->args[1], m->args[2],
                        (uint32_t)m->payload_bytes};
    memcpy(buf + old, head, sizeof head);
    memcpy(buf + old + sizeof head, m->payload, m->payload_bytes);
    s->deferred = buf;
    s->deferred_bytes = old + rec;
    return FW_OK;
}

/* Handles the messages of this frame that arrived before it started (in
 * their order of arrival); later frames' ones stay. */
static fw_status_t replay_deferred(gp_t *gp, vr_state_t *s)
{
    uint8_t *buf = s->deferred;
    size_t bytes = s->deferred_bytes;
    s->deferred = NULL;
    s->deferred_bytes = 0;
    fw_status_t rc = FW_OK;
    for (size_t off = 0; off < bytes && rc == FW_OK;) {
        uint32_t head[6];
        memcpy(head, buf + off, sizeof head);
        ring_msg_t m = {.kind = head[0], .src = ring_addr(RING_NODE_GP, head[1]),
                        .args = {head[2], head[3], head[4]}, .payload = buf + off + sizeof head,
                        .payload_bytes = head[5]};
        off += sizeof head + head[5];
        if (vr_slabs_early(s, &m))
            rc = vr_slabs_defer(gp, s, &m);
        else
            rc = m.args[0] == VR_MSG_NEED ? vr_slabs_on_need(gp, s, &m) : vr_slabs_on_partial(gp, s, &m);
    }
    if (buf)
        fw_free(gp, buf);
    return rc;
}

fw_status_t vr_slabs_frame(gp_t *gp, vr_state_t *s)
{
    if (s->fr.projection != 0)
        return fw_fail(gp, "vr: object slabs cast parallel projections only");
    int g = s->g, n = s->n_gp;
    s->zslab_lo = g == 0 ? LONG_MIN : s->fr.slab_z0[g];
    s->zslab_hi = g + 1 == n ? LONG_MAX : s->fr.slab_z0[g + 1];
    s->needs_pending = 0;
    s->bands_cast = 0;
    s->slab_cast_over = false;
    for (int h = 0; h < n; h++) {
        s->need_in[h] = s->band_cast[h] = false;
        s->needs_pending += band_has_rows(s, h);
    }
    s->bands_with_rows = s->needs_pending;
    s->partials_pending = band_has_rows(s, g) ? n : 0;
    /* The memory left for cached units: all but a reserve for the frame's
     * texel lists and partials. */
    uint64_t cap = fw_machine_info(gp)->local_mem_bytes, reserve = 1024u * 1024u;
    uint64_t used = fw_mem_used_bytes(gp) - s->cache_bytes;
    s->cache_budget = cap > used + reserve ? cap - used - reserve : 0;
    if (band_has_rows(s, g) && send_need(gp, s) != FW_OK)
        return FW_ERROR;
    if (request_slab_units(gp, s) != FW_OK)
        return FW_ERROR;
    s->slab_frame = s->frame + 1;
    if (replay_deferred(gp, s) != FW_OK)
        return FW_ERROR;
    vr_stat_set(gp, s, VR_STAT_T_PREP_DONE, fw_time_ps(gp));
    s->t_pass_req = fw_time_ps(gp);
    s->blocked = true;
    s->t_blocked = s->t_pass_req;
    return vr_slabs_progress(gp, s);
}

/* Band h's partials: sent to its owner, or kept when the owner is us. */
static fw_status_t deliver_partials(gp_t *gp, vr_state_t *s, int h, vr_partial_t *p, size_t n)
{
    if (h != s->g) {
        fw_status_t rc = vr_send_gp(gp, (unsigned)h, VR_MSG_PARTIAL, (uint32_t)s->g,
                                    (uint32_t)s->frame, p, n * sizeof *p);
        fw_free(gp, p);
        return rc;
    }
    s->partials[s->g] = p;
    s->n_partials[s->g] = n;
    s->partials_pending--;
    return FW_OK;
}

/* Composites our band's partials front to back (slab order along the view
 * direction's z), then resamples when the boundary rows are in. */
static fw_status_t composite_band(gp_t *gp, vr_state_t *s)
{
    vr_band_geom_t bg;
    band_geom(s, s->g, &bg);
    uint32_t total = bg.base[s->levels2d];
    float *acc = fw_alloc(gp, (size_t)(total ? total : 1) * 4 * sizeof *acc);
    if (!acc)
        return FW_ERROR;
    vr_spans_t sp;
    memset(&sp, 0, sizeof sp);
    fw_ops_t ops = {0};
    const vr_mem_t mem = {gp, &ops};
    bool up = s->fr.forward[2] >= 0.0f;
    for (int k = 0; k < s->n_gp; k++) {
        int src = up ? k : s->n_gp - 1 - k;
        for (size_t r = 0; r < s->n_partials[src]; r++)
            if (!vr_merge_partial(acc, total, s->partials[src], r, &mem, &sp, NULL))
                return fw_fail(gp, "vr: partial for texel %u of a band of %u",
                               s->partials[src][r].code, total);
    }
    for (int m = 0; m < s->levels2d; m++)
        for (uint32_t c = bg.base[m]; c < bg.base[m + 1]; c++) {
            uint32_t off = c - bg.base[m];
            float *tx = s->texel[m] + ((size_t)(off / (uint32_t)bg.tw[m]) * s->tw[m] +
                                       off % (uint32_t)bg.tw[m]) * 3;
            memcpy(tx, acc + (size_t)c * 4, 3 * sizeof *tx);
        }
    vr_spans_charge(&ops, &sp);
    /* the accumulators' colours into the texel rows: a copy loop */
    ops.loads += 3 * (uint64_t)total;
    ops.stores += 3 * (uint64_t)total;
    fw_charge(gp, &ops);
    fw_free(gp, acc);
    s->cast_done = true;
    if (s->g > 0 && vr_cast_send_boundary(gp, s) != FW_OK)
        return FW_ERROR;
    bool last = s->g + 1 >= s->n_gp || s->fr.band_y0[s->g + 2] == s->fr.band_y0[s->g + 1] ||
                s->y1 >= s->cfg.height;
    if (last)
        s->boundary_ok = true;
    return vr_resample_if_ready(gp, s);
}

fw_status_t vr_slabs_progress(gp_t *gp, vr_state_t *s)
{
    if (s->bricks_pending > 0)
        return FW_OK;
    for (int h = 0; h < s->n_gp; h++) {
        if (!s->need_in[h] || s->band_cast[h])
            continue;
        if (s->blocked) {
            vr_stat_add(gp, s, VR_STAT_WAIT_PS, fw_time_ps(gp) - s->t_blocked);
            s->blocked = false;
        }
        const vr_texel_list_t *tl = &s->band_need[h];
        vr_partial_t *out = fw_alloc(gp, (tl->n ? tl->n : 1) * sizeof *out);
        if (!out)
            return FW_ERROR;
        size_t n = vr_cast_slab_segments(gp, s, tl, s->zslab_lo, s->zslab_hi, out);
        if (h == s->g)
            vr_stat_add(gp, s, VR_STAT_RAYS, tl->n);
        s->band_cast[h] = true;
        s->bands_cast++;
        if (deliver_partials(gp, s, h, out, n) != FW_OK)
            return FW_ERROR;
    }
    if (s->bands_cast == s->bands_with_rows && !s->slab_cast_over) {
        vr_stat_set(gp, s, VR_STAT_T_CAST_DONE, fw_time_ps(gp));
        s->slab_cast_over = true;
        if (!band_has_rows(s, s->g)) {
            /* A GP without a band (too few image rows for every GP to own
             * one) is done when its segments are sent: it has nothing to
             * composite or show. */
            vr_stat_set(gp, s, VR_STAT_T_BOUNDARY, fw_time_ps(gp));
            vr_stat_set(gp, s, VR_STAT_T_DONE, fw_time_ps(gp));
            vr_stat_set(gp, s, VR_STAT_ALL_LEVEL0, 1);
            s->frame_done = true;
        }
    }
    if (!s->blocked && s->needs_pending > 0) {
        s->blocked = true;
        s->t_blocked = fw_time_ps(gp);
    }
    if (band_has_rows(s, s->g) && s->partials_pending == 0 && !s->cast_done)
        return composite_band(gp, s);
    return FW_OK;
}

fw_status_t vr_slabs_on_need(gp_t *gp, vr_state_t *s, const ring_msg_t *m)
{
    int h = (int)m->args[1];
    if (h < 0 || h >= s->n_gp || s->need_in[h])
        return fw_fail(gp, "vr: need set from band %d", h);
    if (unpack_need(gp, s, h, m->payload, m->payload_bytes) != FW_OK)
        return FW_ERROR;
    return vr_slabs_progress(gp, s);
}

fw_status_t vr_slabs_on_partial(gp_t *gp, vr_state_t *s, const ring_msg_t *m)
{
    int src = (int)m->args[1];
    if (src < 0 || src >= s->n_gp || s->partials[src] || s->partials_pending <= 0 ||
        m->payload_bytes % sizeof(vr_partial_t) != 0)
        return fw_fail(gp, "vr: partials from GP %d (%zu bytes)", src, m->payload_bytes);
    size_t n = m->payload_bytes / sizeof(vr_partial_t);
    s->partials[src] = fw_alloc(gp, (n ? n : 1) * sizeof(vr_partial_t));
    if (!s->partials[src])
        return FW_ERROR;
    if (n)                        /* an empty set has no payload (memcpy of NULL: UB) */
        memcpy(s->partials[src], m->payload, m->payload_bytes);
    s->n_partials[src] = n;
    fw_ops_t ops = {0};
    fw_rx_deposit(gp, &ops, s->partials[src], 0, m->payload_bytes);   /* gp.rx_dma (fw_api.h) */
    fw_charge(gp, &ops);
    s->partials_pending--;
    return vr_slabs_progress(gp, s);
}

void vr_slabs_free(gp_t *gp, vr_state_t *s)
{
    for (int h = 0; h < VR_MAX_GPS; h++) {
        if (s->band_need[h].t)
            fw_free(gp, s->band_need[h].t);
        s->band_need[h].t = NULL;
        s->band_need[h].n = 0;
        if (s->partials[h])
            fw_free(gp, s->partials[h]);
        s->partials[h] = NULL;
        s->n_partials[h] = 0;
    }
}
