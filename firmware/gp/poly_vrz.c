/* poly_vrz.c: gaze-directed polygon frames on the machine: the variable-resolution Z-buffer of the gaze paper's §7 (seed 004), its coarse levels rasterised by the renderers as smaller screens.
 *
 * Per frame every GP plans the same regions: the 128x128 tiles of each 2D
 * level that some pixel may read (poly_tile_populated), level 0 first,
 * row-major.  Triangles are sorted into the tiles their box reaches on each
 * level, and the regions go round the renderers and the GP token exactly as
 * full-resolution regions do (poly_gp.c).  A finished region is not sent
 * to the frame buffer: the last GP has the renderer store its colour plane
 * in the backing store (block = the renderer's round) and asks for one box
 * of texel rows per GP whose image rows read them (RENDERER_READ_BS_BOX
 * with reply_to that GP).  Each GP resamples its own band of image rows
 * (RenderPixel, render/gaze2d.c mip2d_pixel) once every box it expects is
 * in, and sends the band to the frame buffer.  firmware/ARCHITECTURE.md
 * "Polygons" has the message sequence. */
#include <string.h>

#include "poly_vrz_kernels.h"
#include "ring_msg.h"

fw_status_t poly_vrz_start(gp_t *gp, poly_state_t *s)
{
    const fw_machine_info_t *mi = fw_machine_info(gp);
    s->slot_of = fw_alloc(gp, (size_t)s->n_tiles * sizeof *s->slot_of);
    if (!s->slot_of)
        return FW_ERROR;
    poly_band_rows(s, fw_gp_index(gp), mi->n_gp, &s->y0, &s->y1);
    if (s->cfg.level_tables &&
        vr_level_tables_build(gp, &s->gaze_model, s->cfg.width, s->cfg.height, &s->tables) != FW_OK)
        return FW_ERROR;
    if (s->y1 > s->y0) {
        s->level = fw_alloc(gp, (size_t)(s->y1 - s->y0) * (size_t)s->cfg.width * sizeof *s->level);
        if (!s->level)
            return FW_ERROR;
    }
    for (int l = 0; l < s->levels && s->y1 > s->y0; l++) {
        poly_band_texel_rows(s, s->y0, s->y1, l, &s->jlo[l], &s->jhi[l]);
        size_t n = (size_t)(s->jhi[l] - s->jlo[l] + 1) * (size_t)s->tw[l];
        if (!(s->texel[l] = fw_alloc(gp, n * sizeof *s->texel[l])))
            return FW_ERROR;
    }
    return FW_OK;
}

/* The frame's regions: the populated tiles, level by level, row-major; and
 * how many texel boxes this GP will receive. */
fw_status_t poly_vrz_plan(gp_t *gp, poly_state_t *s)
{
    s->n_regions = 0;
    for (int l = 0; l < s->levels; l++)
        for (int ty = 0; ty < s->tiles_y[l]; ty++)
            for (int tx = 0; tx < s->tiles_x[l]; tx++)
                poly_plan_tile(s, l, tx, ty, POLY_NO_COUNT);
    s->expected = s->arrived = 0;
    for (int k = 0; k < s->n_regions && s->y1 > s->y0; k++)
        s->expected += poly_expect_region(s, k, POLY_NO_COUNT);
    for (int y = s->y0; y < s->y1; y++)
        for (int x = 0; x < s->cfg.width; x++)
            poly_band_level(s, x, y, POLY_NO_COUNT);
    poly_charge(gp, s, POLY_STAT_CYC_LEVELS);
    fw_stat_add(gp, s->stat[POLY_STAT_REGIONS_PLANNED], (uint64_t)s->n_regions);
    return FW_OK;
}

/* Counts (fill = false) or stores (true) triangle i in its populated tiles
 * on every level. */
static void sort_levels(poly_state_t *s, uint32_t i, bool fill)
{
    poly_box_t box = poly_tri_box(&s->tri[i], &s->sp, NULL);
    for (int l = 0; l < s->levels; l++) {
        int t[4];
        if (!poly_level_tiles(s, &box, l, t, &s->sp, NULL))
            continue;
        for (int ty = t[2]; ty <= t[3]; ty++)
            for (int tx = t[0]; tx <= t[1]; tx++)
                poly_sort_tile(s, l, tx, ty, i, fill, POLY_NO_COUNT);
    }
}

fw_status_t poly_vrz_sort(gp_t *gp, poly_state_t *s)
{
    for (uint32_t i = 0; i < s->n_tri; i++)
        sort_levels(s, i, false);
    uint32_t pairs = poly_bin_prefix(s->count, s->start, s->fill, s->n_regions, &s->sp, NULL);
    if (poly_reserve_list(gp, s, pairs) != FW_OK)
        return FW_ERROR;
    for (uint32_t i = 0; i < s->n_tri; i++)
        sort_levels(s, i, true);
    fw_stat_add(gp, s->stat[POLY_STAT_PAIRS_BINNED], pairs);
    poly_charge(gp, s, POLY_STAT_CYC_SORT);
    return FW_OK;
}

/* The last GP's end of region k on renderer j in round r: the colour plane
 * to backing-store block r, then each GP's texel box of it. */
fw_status_t poly_vrz_store_region(gp_t *gp, poly_state_t *s, unsigned j, unsigned r, int k)
{
    const fw_machine_info_t *mi = fw_machine_info(gp);
    if (r >= mi->pp_bs_blocks)
        return fw_fail(gp, "polygons: renderer %u's round %u has no backing-store block (%u)", j, r,
                       mi->pp_bs_blocks);
    pp_stream_t st;
    pp_stream_init(&st);
    pp_emit_en_all(&st);                 /* the store is masked by Enable */
    pp_emit_bsstore(&st, r, POLY_PP_R);
    pp_emit_bswait(&st);
    poly_words(st.n_words, &s->sp, NULL);
    fw_status_t rc = pp_stream_ok(&st) ? FW_OK : fw_fail(gp, "polygons: %s", pp_stream_error(&st));
    if (rc == FW_OK)
        rc = fw_send(gp, ring_addr(RING_NODE_RENDERER, j), RING_MSG_RENDERER_EXEC, NULL, st.words,
                     st.n_words * sizeof *st.words);
    pp_stream_free(&st);
    for (unsigned h = 0; h < mi->n_gp && rc == FW_OK; h++) {
        uint32_t args[RING_MSG_ARGS];
        if (poly_box_request(s, h, mi->n_gp, k, r, args, POLY_NO_COUNT))
            rc = fw_send(gp, ring_addr(RING_NODE_RENDERER, j), RING_MSG_RENDERER_READ_BS_BOX, args,
                         NULL, 0);
    }
    poly_charge(gp, s, POLY_STAT_CYC_ENCODE);
    return rc;
}

/* RenderPixel of the band, in sections of at most 128 columns to the frame
 * buffer. */
static fw_status_t resample(gp_t *gp, poly_state_t *s)
{
    int W = s->cfg.width, rows = s->y1 - s->y0;
    for (int sx = 0; sx < W; sx += 128) {
        int sw = W - sx < 128 ? W - sx : 128;
        size_t bytes = (size_t)sw * (size_t)rows * 3;
        uint8_t *px = fw_alloc(gp, bytes);
        if (!px)
            return FW_ERROR;
        for (int y = s->y0; y < s->y1; y++)
            for (int x = sx; x < sx + sw; x++)
                poly_render_pixel(s, x, y, px + ((size_t)(y - s->y0) * sw + (size_t)(x - sx)) * 3,
                                  &s->sp, NULL);
        poly_section_sent(&s->sp, POLY_NO_COUNT);
        poly_charge(gp, s, POLY_STAT_CYC_RESAMPLE);
        uint32_t args[RING_MSG_ARGS] = {(uint32_t)sx, (uint32_t)s->y0, (uint32_t)sw, (uint32_t)rows,
                                        0, 0};
        fw_status_t rc = fw_send(gp, ring_addr(RING_NODE_FB, 0), RING_MSG_FB_PIXELS, args, px, bytes);
        fw_free(gp, px);
        if (rc != FW_OK)
            return rc;
    }
    fw_stat_set(gp, s->stat[POLY_STAT_T_DONE], fw_time_ps(gp));
    return FW_OK;
}

/* A texel box of region args[0] (RENDERER_DATA from READ_BS_BOX). */
fw_status_t poly_vrz_take_texels(gp_t *gp, poly_state_t *s, const ring_msg_t *msg)
{
    int k = (int)msg->args[0], a, b;
    if (!s->cfg.gaze || k < 0 || k >= s->n_regions || s->y1 <= s->y0 ||
        !poly_region_rows(s, k, s->jlo[s->reg[k].level], s->jhi[s->reg[k].level], &a, &b))
        return fw_fail(gp, "polygons: texels of region %d that this GP did not ask for", k);
    int l = s->reg[k].level, sx = poly_region_columns(s, k);
    size_t row_bytes = (size_t)sx * 4;
    if (msg->payload_bytes != (size_t)(b - a + 1) * row_bytes)
        return fw_fail(gp, "polygons: region %d's texels: %zu bytes, expected %zu", k,
                       msg->payload_bytes, (size_t)(b - a + 1) * row_bytes);
    fw_ops_t ops = {0};
    const uint32_t *src = msg->payload;
    for (int j = a; j <= b; j++) {
        size_t at = poly_texel_row_at(s, k, j, POLY_NO_COUNT);
        memcpy(s->texel[l] + at, src + (size_t)(j - a) * (size_t)sx, row_bytes);
        fw_rx_deposit(gp, &ops, s->texel[l], at * 4, row_bytes);
    }
    fw_charge(gp, &ops);
    fw_stat_add(gp, s->stat[POLY_STAT_TEXELS_IN], (uint64_t)(b - a + 1) * (uint64_t)sx);
    poly_charge(gp, s, POLY_STAT_CYC_RESAMPLE);
    return ++s->arrived == s->expected ? resample(gp, s) : FW_OK;
}
