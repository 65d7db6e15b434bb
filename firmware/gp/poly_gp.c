/* poly_gp.c: the polygon GP program: per frame, transform and sort this GP's triangles into screen regions, then feed the renderers region by region as a token passes from GP to GP.
 *
 * Sort-middle (facts §2 [I/S]): every GP may hold triangles of every
 * region, and a renderer works on one region at a time (facts §3.5: it is
 * moved between regions by software), so the GPs take turns per renderer.
 * Renderer j renders regions j, j + n_r, j + 2 n_r, ... (row-major).  For
 * region k a token visits GP 0, 1, ..., n_gp - 1 in ring order: GP 0 moves
 * the renderer (RENDERER_SET_REGION) and sends a stream that clears the
 * region and draws its own triangles there; each next GP sends its
 * triangles; the last sends the Phong shading (Phong only) and
 * RENDERER_SEND_PIXELS (the region to the frame buffer over the ring), then
 * hands the token for j's next region back to GP 0.  A GP's stream leaves
 * its transmit FIFO before its token does and travels no farther to the
 * renderer than the token's path through the next GP, so streams reach the
 * renderer in GP order (emu/ARCHITECTURE.md, "Ring model").  Different
 * renderers' tokens circulate at the same time. */
#include <math.h>
#include <string.h>

#include "common/poly_phong_pp.h"
#include "poly_vrz_kernels.h"
#include "ring_msg.h"


static void declare_stats(gp_t *gp, poly_state_t *s)
{
#define POLY_STAT_DECLARE(id, name, kind, unit, meaning) \
    s->stat[POLY_STAT_##id] = fw_stat_declare(gp, name, kind, unit, meaning);
    POLY_STATS(POLY_STAT_DECLARE)
#undef POLY_STAT_DECLARE
}

void poly_charge(gp_t *gp, poly_state_t *s, int id)
{
    fw_ops_t ops = {0};
    poly_spans_charge(&ops, &s->sp);
    vr_spans_charge(&ops, &s->vsp);
    memset(&s->vsp, 0, sizeof s->vsp);
    uint64_t c0 = fw_cycles(gp);
    fw_charge(gp, &ops);
    fw_stat_add(gp, s->stat[id], fw_cycles(gp) - c0);
}

static fw_status_t set_config(gp_t *gp, poly_state_t *s, const poly_config_t *c)
{
    const fw_machine_info_t *mi = fw_machine_info(gp);
    if (c->width < 1 || c->height < 1 || (unsigned)c->width > mi->screen_width ||
        (unsigned)c->height > mi->screen_height || c->width > 2048 || c->shading < POLY_FLAT ||
        c->shading > POLY_PHONG || c->n_triangles < 0)
        return fw_fail(gp, "polygons: bad configuration (image %dx%d on a %ux%u screen, shading %d)",
                       c->width, c->height, mi->screen_width, mi->screen_height, c->shading);
    if (c->levels2d < 1 || c->levels2d > POLY_MAX_LEVELS || (c->gaze && !(isfinite(c->gaze_x) &&
        isfinite(c->gaze_y) && fabs(c->gaze_x) < 1e9 && fabs(c->gaze_y) < 1e9)))
        return fw_fail(gp, "polygons: bad gaze configuration (%d levels, gaze %g, %g)", c->levels2d,
                       c->gaze_x, c->gaze_y);
    int rx = (c->width + 127) / 128, ry = (c->height + 127) / 128;
    if (s->count && (c->width != s->cfg.width || c->height != s->cfg.height ||
                     c->levels2d != s->cfg.levels2d))
        return fw_fail(gp, "polygons: the image size and the 2D levels are fixed per sequence");
    s->cfg = *c;
    s->regions_x = rx, s->regions_y = ry;
    s->levels = c->gaze ? c->levels2d : 1;
    poly_levels_setup(s);
    /* full resolution: every level-0 tile, row-major */
    s->n_regions = rx * ry;
    for (int k = 0; s->reg && k < s->n_regions; k++)
        s->reg[k] = (poly_region_t){0, (k % rx) * 128, (k / rx) * 128};
    return FW_OK;
}

static fw_status_t poly_start(gp_t *gp)
{
    size_t bytes = 0;
    const poly_config_t *c = fw_host_data(gp, &bytes);
    if (!c || bytes != sizeof *c)
        return fw_fail(gp, "polygons: HOST_LOAD data of %zu bytes, expected a configuration of %zu",
                       bytes, sizeof *c);
    poly_state_t *s = fw_alloc(gp, sizeof *s);
    if (!s)
        return FW_ERROR;
    fw_set_state(gp, s);
    declare_stats(gp, s);
    if (set_config(gp, s, c) != FW_OK)
        return FW_ERROR;
    /* room for every tile of every level: gaze-directed frames plan their
     * regions among them */
    size_t n = (size_t)s->n_tiles;
    s->count = fw_alloc(gp, n * sizeof *s->count);
    s->start = fw_alloc(gp, n * sizeof *s->start);
    s->fill = fw_alloc(gp, n * sizeof *s->fill);
    s->reg = fw_alloc(gp, n * sizeof *s->reg);
    if (!s->count || !s->start || !s->fill || !s->reg || set_config(gp, s, c) != FW_OK)
        return FW_ERROR;
    /* gaze-directed from the start: the band and the 2DLevel tables with
     * the load (a later switch to gaze builds them in its first frame) */
    return c->gaze ? poly_vrz_start(gp, s) : FW_OK;
}

static fw_status_t take_triangles(gp_t *gp, poly_state_t *s, const ring_msg_t *msg)
{
    if (msg->payload_bytes % sizeof(poly_tri_in_t) != 0)
        return fw_fail(gp, "polygons: a triangle message of %zu bytes", msg->payload_bytes);
    /* A later message replaces the list between frames (the host changed the
     * levels of detail): the old list and its screen-triangle table go back
     * to the memory pool before the new ones are taken. */
    fw_free(gp, s->in);
    fw_free(gp, s->tri);
    s->in = NULL;
    s->tri = NULL;
    s->n_tri = 0;
    s->n_in = (uint32_t)(msg->payload_bytes / sizeof(poly_tri_in_t));
    s->in = fw_alloc(gp, msg->payload_bytes + 1);
    if (!s->in)
        return FW_ERROR;
    if (msg->payload_bytes)
        memcpy(s->in, msg->payload, msg->payload_bytes);
    fw_ops_t ops = {0};
    fw_rx_deposit(gp, &ops, s->in, 0, msg->payload_bytes);
    fw_charge(gp, &ops);
    /* room for every triangle unclipped and a few pieces of clipped ones */
    s->cap_tri = s->n_in + 64;
    s->tri = fw_alloc(gp, (size_t)s->cap_tri * sizeof *s->tri);
    return s->tri ? FW_OK : FW_ERROR;
}

/* A triangle table twice as large, the set-up triangles moved (counted). */
static fw_status_t grow_triangles(gp_t *gp, poly_state_t *s)
{
    uint32_t cap = 2 * s->cap_tri;
    poly_tri_t *t = fw_alloc(gp, (size_t)cap * sizeof *t);
    if (!t)
        return FW_ERROR;
    memcpy(t, s->tri, (size_t)s->n_tri * sizeof *t);
    poly_grow_moved((uint64_t)s->n_tri * (sizeof *t / 4), &s->sp, NULL);
    fw_free(gp, s->tri);
    s->tri = t;
    s->cap_tri = cap;
    return FW_OK;
}

fw_status_t poly_reserve_list(gp_t *gp, poly_state_t *s, uint32_t pairs)
{
    if (pairs <= s->list_cap)
        return FW_OK;
    fw_free(gp, s->list);
    s->list_cap = pairs + pairs / 4 + 16;
    s->list = fw_alloc(gp, (size_t)s->list_cap * sizeof *s->list);
    return s->list ? FW_OK : FW_ERROR;
}

/* Transform and set up every triangle, then sort them into regions (of the
 * populated levels, gaze-directed). */
static fw_status_t transform_and_sort(gp_t *gp, poly_state_t *s)
{
    s->n_tri = 0;
    for (uint32_t i = 0; i < s->n_in; i++) {
        if (s->n_tri + POLY_CLIP_MAX > s->cap_tri && grow_triangles(gp, s) != FW_OK)
            return FW_ERROR;
        s->n_tri += (uint32_t)poly_triangle(&s->cfg, &s->in[i], &s->tri[s->n_tri], &s->sp, NULL);
    }
    fw_stat_add(gp, s->stat[POLY_STAT_TRIS_IN], s->n_in);
    fw_stat_add(gp, s->stat[POLY_STAT_TRIS_SETUP], s->n_tri);
    poly_charge(gp, s, POLY_STAT_CYC_TRANSFORM);
    if (s->cfg.gaze) {
        if (!s->slot_of && poly_vrz_start(gp, s) != FW_OK)
            return FW_ERROR;
        return poly_vrz_plan(gp, s) == FW_OK ? poly_vrz_sort(gp, s) : FW_ERROR;
    }
    for (uint32_t i = 0; i < s->n_tri; i++)
        poly_bin_count(&s->tri[i], s->regions_x, s->count, &s->sp, NULL);
    uint32_t pairs = poly_bin_prefix(s->count, s->start, s->fill, s->n_regions, &s->sp, NULL);
    if (poly_reserve_list(gp, s, pairs) != FW_OK)
        return FW_ERROR;
    for (uint32_t i = 0; i < s->n_tri; i++)
        poly_bin_fill(&s->tri[i], i, s->regions_x, s->start, s->fill, s->list, &s->sp, NULL);
    fw_stat_add(gp, s->stat[POLY_STAT_PAIRS_BINNED], pairs);
    poly_charge(gp, s, POLY_STAT_CYC_SORT);
    return FW_OK;
}

/* Sends n stream words (a copy in local memory while they are sent; the
 * encoder's stores were charged as ENC_WORD). */
static fw_status_t send_words(gp_t *gp, poly_state_t *s, unsigned renderer, const uint32_t *words,
                              size_t n)
{
    if (n == 0)
        return FW_OK;
    size_t bytes = n * sizeof *words;
    uint32_t *local = fw_alloc(gp, bytes);
    if (!local)
        return FW_ERROR;
    memcpy(local, words, bytes);
    fw_status_t rc = fw_send(gp, ring_addr(RING_NODE_RENDERER, renderer), RING_MSG_RENDERER_EXEC,
                             NULL, local, bytes);
    fw_free(gp, local);
    fw_stat_add(gp, s->stat[POLY_STAT_STREAM_WORDS], n);
    return rc;
}

/* The stream of this GP's triangles in region k (the first GP's also
 * clears the region), charged. */
static fw_status_t build_region(gp_t *gp, poly_state_t *s, int k, pp_stream_t *st)
{
    const poly_config_t *c = &s->cfg;
    int level = s->reg[k].level;
    int32_t rx = s->reg[k].x, ry = s->reg[k].y;
    poly_region_start(c, fw_gp_index(gp) == 0, st, &s->sp, NULL);
    uint64_t edges0 = s->sp.n[POLY_ROW_ENC_EDGE_EMIT], sent = 0;
    const uint32_t *bin = s->list + s->start[k];
    int n_planes = c->shading == POLY_FLAT ? 1 : 4;
    for (uint32_t i = 0; i < s->fill[k]; i++) {  /* fill[k]: the bin's size after the sort */
        const poly_tri_t *t = &s->tri[bin[i]];
        poly_tri_t on_level;
        if (level > 0) {
            poly_tri_on_level(t, level, n_planes, &on_level, &s->sp, NULL);
            t = &on_level;
        }
        sent += poly_encode(c, t, level, rx, ry, st, &s->sp, NULL);
    }
    fw_stat_add(gp, s->stat[POLY_STAT_EDGES_SENT], s->sp.n[POLY_ROW_ENC_EDGE_EMIT] - edges0);
    fw_stat_add(gp, s->stat[POLY_STAT_PAIRS_SENT], sent);
    fw_stat_add(gp, s->stat[POLY_STAT_REGIONS], 1);
    poly_charge(gp, s, POLY_STAT_CYC_ENCODE);
    if (!pp_stream_ok(st))
        return fw_fail(gp, "polygons: region (%d,%d): %s", rx, ry, pp_stream_error(st));
    return FW_OK;
}

/* This GP's part of region k, renderer j's round r (see the file comment). */
static fw_status_t region_part(gp_t *gp, poly_state_t *s, unsigned j, unsigned r, int k)
{
    unsigned g = fw_gp_index(gp);
    ring_addr_t rn = ring_addr(RING_NODE_RENDERER, j);
    if (g == 0) {
        uint32_t args[RING_MSG_ARGS] = {(uint32_t)s->reg[k].x, (uint32_t)s->reg[k].y, 0, 0, 0, 0};
        if (fw_send(gp, rn, RING_MSG_RENDERER_SET_REGION, args, NULL, 0) != FW_OK)
            return FW_ERROR;
    }
    pp_stream_t st;
    pp_stream_init(&st);
    fw_status_t rc = build_region(gp, s, k, &st);
    if (rc == FW_OK)
        rc = send_words(gp, s, j, st.words, st.n_words);
    pp_stream_free(&st);
    if (rc != FW_OK || g + 1 < fw_machine_info(gp)->n_gp)
        return rc;
    if (send_words(gp, s, j, s->phong, s->phong_words) != FW_OK)
        return FW_ERROR;
    if (s->cfg.gaze)
        return poly_vrz_store_region(gp, s, j, r, k);
    uint32_t px[RING_MSG_ARGS] = {POLY_PP_R, POLY_PP_G, POLY_PP_B,
                                  ring_addr_pack(ring_addr(RING_NODE_FB, 0)), 0, 0};
    return fw_send(gp, rn, RING_MSG_RENDERER_SEND_PIXELS, px, NULL, 0);
}

/* The token of renderer j's round r reached this GP: its part of the
 * region, then the token onward (or, one GP, the next round at once). */
static fw_status_t take_token(gp_t *gp, poly_state_t *s, unsigned j, unsigned r)
{
    const fw_machine_info_t *mi = fw_machine_info(gp);
    unsigned g = fw_gp_index(gp);
    for (;;) {
        int k = (int)(j + r * mi->n_renderers);
        if (region_part(gp, s, j, r, k) != FW_OK)
            return FW_ERROR;
        fw_stat_set(gp, s->stat[POLY_STAT_T_DONE], fw_time_ps(gp));
        bool last = g + 1 == mi->n_gp;
        unsigned next_r = last ? r + 1 : r;
        if (last && (int)(j + next_r * mi->n_renderers) >= s->n_regions)
            return FW_OK;
        if (last && mi->n_gp == 1) {
            r = next_r;
            continue;
        }
        uint32_t args[RING_MSG_ARGS] = {POLY_MSG_TOKEN, j, next_r, s->frame, 0, 0};
        return fw_send(gp, ring_addr(RING_NODE_GP, last ? 0 : g + 1), RING_MSG_GP_USER, args, NULL, 0);
    }
}

/* The last GP builds the Phong stream once per frame (its words charged). */
static fw_status_t build_phong(gp_t *gp, poly_state_t *s)
{
    fw_free(gp, s->phong);
    s->phong = NULL;
    s->phong_words = 0;
    if (s->cfg.shading != POLY_PHONG || fw_gp_index(gp) + 1 != fw_machine_info(gp)->n_gp)
        return FW_OK;
    pp_stream_t st;
    pp_stream_init(&st);
    poly_phong_stream(&st, s->cfg.light, s->cfg.ambient, s->cfg.diffuse, s->cfg.front_rgb,
                      s->cfg.back_rgb, s->cfg.colour_per_pixel != 0);
    fw_status_t rc = pp_stream_ok(&st) ? FW_OK
                     : fw_fail(gp, "polygons: Phong stream: %s", pp_stream_error(&st));
    if (rc == FW_OK && !(s->phong = fw_alloc(gp, st.n_words * sizeof *s->phong)))
        rc = FW_ERROR;
    if (rc == FW_OK) {
        memcpy(s->phong, st.words, st.n_words * sizeof *s->phong);
        s->phong_words = st.n_words;
    }
    pp_stream_free(&st);
    if (rc != FW_OK)
        return rc;
    poly_words(s->phong_words, &s->sp, NULL);
    poly_charge(gp, s, POLY_STAT_CYC_ENCODE);
    return FW_OK;
}

static fw_status_t frame_start(gp_t *gp, poly_state_t *s, uint32_t frame)
{
    const fw_machine_info_t *mi = fw_machine_info(gp);
    s->frame = frame;
    fw_stat_set(gp, s->stat[POLY_STAT_T_START], fw_time_ps(gp));
    if (transform_and_sort(gp, s) != FW_OK || build_phong(gp, s) != FW_OK)
        return FW_ERROR;
    fw_stat_set(gp, s->stat[POLY_STAT_T_SORTED], fw_time_ps(gp));
    fw_stat_set(gp, s->stat[POLY_STAT_T_DONE], fw_time_ps(gp));
    if (fw_gp_index(gp) != 0)
        return FW_OK;
    for (unsigned j = 0; j < mi->n_renderers && (int)j < s->n_regions; j++)
        if (take_token(gp, s, j, 0) != FW_OK)
            return FW_ERROR;
    return FW_OK;
}

static fw_status_t poly_message(gp_t *gp, const ring_msg_t *msg)
{
    poly_state_t *s = fw_state(gp);
    if (msg->kind == RING_MSG_FRAME_START)
        return frame_start(gp, s, msg->args[0]);
    if (msg->kind == RING_MSG_RENDERER_DATA)
        return poly_vrz_take_texels(gp, s, msg);
    if (msg->kind != RING_MSG_GP_USER)
        return fw_fail(gp, "polygons: unexpected message kind %u", msg->kind);
    switch (msg->args[0]) {
    case POLY_MSG_TRIANGLES:
        return take_triangles(gp, s, msg);
    case POLY_MSG_CONFIG:
        if (msg->payload_bytes != sizeof(poly_config_t))
            return fw_fail(gp, "polygons: a configuration of %zu bytes", msg->payload_bytes);
        return set_config(gp, s, msg->payload);
    case POLY_MSG_TOKEN:
        /* A token is sent only after its sender handled FRAME_START, which
         * the host sent this GP earlier on the same ring. */
        if (msg->args[3] != s->frame)
            return fw_fail(gp, "polygons: a token of frame %u in frame %u", msg->args[3], s->frame);
        if (msg->args[1] >= fw_machine_info(gp)->n_renderers)
            return fw_fail(gp, "polygons: a token for renderer %u", msg->args[1]);
        return take_token(gp, s, msg->args[1], msg->args[2]);
    default:
        return fw_fail(gp, "polygons: unknown message %u", msg->args[0]);
    }
}

const fw_program_t poly_program = {
    .name = "polygons",
    .image_bytes = 24576,         /* [U] stand-in size of the i860 binary */
    .on_start = poly_start,
    .on_message = poly_message,
};
