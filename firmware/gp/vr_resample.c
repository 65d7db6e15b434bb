/* vr_resample.c: per frame, the 2D mip map back to pixels: the boundary texel rows from the next GP, RenderPixel, and sections of at most 128 columns to the frame buffer.
 *
 * Paper: seed 004 §4 last paragraph (division of work), §5 (octree), §6.
 * Partitioning, PP memory layout and the per-frame message sequence are in
 * firmware/ARCHITECTURE.md. */
#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "vr_gp_internal.h"
#include "vr_image_kernels.h"

fw_status_t vr_resample_if_ready(gp_t *gp, vr_state_t *s)
{
    if (!s->cast_done || !s->boundary_ok || s->frame_done)
        return FW_OK;
    vr_stat_set(gp, s, VR_STAT_T_BOUNDARY, fw_time_ps(gp));
    uint64_t c0 = fw_cycles(gp);
    const vr_config_t *c = &s->cfg;
    int W = c->width, rows = s->y1 - s->y0;
    /* Sections of at most 128 columns (one renderer region wide). */
    for (int sx = 0; sx < W; sx += 128) {
        int sw = W - sx < 128 ? W - sx : 128;
        size_t bytes = (size_t)sw * rows * 3;
        uint8_t *px = fw_alloc(gp, bytes);
        if (!px)
            return FW_ERROR;
        fw_ops_t ops = {0};
        const vr_mem_t mem = {gp, &ops};
        vr_spans_t sp;
        memset(&sp, 0, sizeof sp);
        for (int y = s->y0; y < s->y1; y++)
            for (int x = sx; x < sx + sw; x++)
                vr_render_pixel(s, x, y, px, ((size_t)(y - s->y0) * sw + (size_t)(x - sx)) * 3, &mem,
                                &sp, NULL);
        vr_spans_charge(&ops, &sp);
        fw_charge(gp, &ops);
        uint32_t args[RING_MSG_ARGS] = {(uint32_t)(c->fb_x0 + sx), (uint32_t)(c->fb_y0 + s->y0),
                                        (uint32_t)sw, (uint32_t)rows, 0, 0};
        fw_status_t rc = fw_send(gp, ring_addr(RING_NODE_FB, 0), RING_MSG_FB_PIXELS, args, px, bytes);
        fw_free(gp, px);
        if (rc != FW_OK)
            return rc;
        vr_stat_add(gp, s, VR_STAT_FB_BYTES, bytes);
    }
    vr_stat_add(gp, s, VR_STAT_CYC_RESAMPLE, fw_cycles(gp) - c0);
    vr_stat_set(gp, s, VR_STAT_T_DONE, fw_time_ps(gp));
    s->frame_done = true;
    /* Free the frame's brick cache now (memory is per frame); keep the 2D
     * mip map when the host runs a progressive sequence. */
    int all0 = 1;
    for (int y = s->y0; y < s->y1 && all0; y++)
        for (int x = 0; x < W; x++)
            if (s->level[(size_t)(y - s->ly0) * W + x] > 0.0f) {
                all0 = 0;
                break;
            }
    vr_stat_set(gp, s, VR_STAT_ALL_LEVEL0, (uint64_t)(all0));
    vr_frame_free(gp, s, (s->fr.progressive_keep & 1) != 0);
    return FW_OK;
}

fw_status_t vr_resample_on_boundary(gp_t *gp, vr_state_t *s, const ring_msg_t *m)
{
    size_t floats = 0;
    for (int mm = 0; mm < s->levels2d; mm++)
        floats += (size_t)s->tw[mm] * 3;
    if (m->payload_bytes != floats * sizeof(float) || !s->texel[0])
        return fw_fail(gp, "vr: boundary message of %zu bytes", m->payload_bytes);
    const float *src = m->payload;
    size_t off = 0;
    fw_ops_t ops = {0};
    for (int mm = 0; mm < s->levels2d; mm++) {
        int rows = s->jhi[mm] - s->jlo[mm] + 1;
        memcpy(s->texel[mm] + (size_t)rows * s->tw[mm] * 3, src + off, (size_t)s->tw[mm] * 3 * sizeof(float));
        /* delivery of the row as gp.rx_dma says (fw_api.h, [U]) */
        fw_rx_deposit(gp, &ops, s->texel[mm], (size_t)rows * s->tw[mm] * 3 * sizeof(float),
                      (size_t)s->tw[mm] * 3 * sizeof(float));
        off += (size_t)s->tw[mm] * 3;
    }
    fw_charge(gp, &ops);
    s->boundary_ok = true;
    return vr_resample_if_ready(gp, s);
}
