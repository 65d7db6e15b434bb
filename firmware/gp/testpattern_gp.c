/* testpattern_gp.c: GP firmware for `pp5 test-pattern`: bins discs per region and sends QEE streams to renderers. */
#include "common/testpattern_gp.h"

#include "pp_encode.h"
#include "ring_msg.h"

typedef struct {
    tp_disc_t disc[TP_DISCS];
    int32_t k[TP_DISCS];          /* shade scale floor(255 * 2^16 / r^2) */
} tp_state_t;

/* Charge the encoder's work for the words it just wrote: each word is
 * assembled (2 integer ops: shift/or of fields) and stored (1 store).  The
 * encoder lives in emu/pp_encode.c and cannot count itself. */
static void charge_words(fw_ops_t *ops, size_t words)
{
    ops->int_ops += 2 * words;
    ops->stores += words;
}

static fw_status_t send_region(gp_t *gp, tp_state_t *s, unsigned renderer, unsigned x0, unsigned y0,
                               pp_stream_t *st)
{
    const fw_machine_info_t *mi = fw_machine_info(gp);
    int64_t w = mi->screen_width, h = mi->screen_height;
    fw_ops_t ops = {0};
    pp_stream_clear(st);

    /* Background: three gradients. */
    int32_t dr = (int32_t)((255ll << 16) / (w - 1));
    int32_t eg = (int32_t)((255ll << 16) / (h - 1));
    int64_t maxd2 = (w / 2) * (w / 2) + (h / 2) * (h / 2);
    int32_t kb = (int32_t)((255ll << 20) / maxd2);
    ops.fdiv += 3;                /* the three scale factors: i860 has no integer divide */
    ops.fmul += 2;
    ops.int_ops += 10;            /* products and sums for the coefficients below */
    pp_emit_en_all(st);
    pp_emit_qee(st, TP_R, 8, 16, 0, 0, 0, dr, 0, 0);
    pp_emit_qee(st, TP_G, 8, 16, 0, 0, 0, 0, eg, 0);
    pp_emit_qee(st, TP_B, 8, 20, kb, 0, kb, (int32_t)(-kb * w), (int32_t)(-kb * h), (int32_t)(kb * maxd2));

    int32_t rx0 = (int32_t)x0, ry0 = (int32_t)y0;
    int32_t rx1 = rx0 + (int32_t)mi->region_width, ry1 = ry0 + (int32_t)mi->region_height;
    for (unsigned i = 0; i < TP_DISCS; i++) {
        const tp_disc_t *d = &s->disc[i];
        /* Bounding-box test: 3 loads (the last compared at once), 4 adds,
         * 4 compares, 4 branches. */
        ops.loads += 3;
        ops.load_use += 1;
        ops.int_ops += 8;
        ops.branches += 4;
        if (d->cx + d->r < rx0 || d->cx - d->r >= rx1 || d->cy + d->r < ry0 || d->cy - d->r >= ry1) {
            continue;
        }
        /* Coefficients: 2 loads (k, colour), 3 multiplies, 4 adds/shifts. */
        ops.loads += 2;
        ops.int_ops += 7;
        int32_t f = d->cx * d->cx + d->cy * d->cy - d->r * d->r;
        pp_emit_qee(st, TP_Q, TP_Q_BITS, 0, 1, 0, 1, -2 * d->cx, -2 * d->cy, f);
        pp_emit_cmpi(st, PP_CMP_LTS, TP_Q, TP_Q_BITS, 0);
        pp_emit_en_flag(st);
        pp_emit_muli(st, TP_P, TP_P_BITS, TP_Q, TP_Q_BITS, true, -s->k[i]);
        static const unsigned chan[3] = { TP_R, TP_G, TP_B };
        for (unsigned c = 0; c < 3; c++) {
            ops.int_ops += 1;
            ops.branches += 1;
            if (d->colour & (1u << c)) {
                pp_emit_copy(st, chan[c], TP_P + 16, 8);
            } else {
                pp_emit_seti(st, chan[c], 8, 0);
            }
        }
        pp_emit_en_all(st);
    }
    charge_words(&ops, st->n_words);
    fw_charge(gp, &ops);
    if (!pp_stream_ok(st)) {
        return fw_fail(gp, "test pattern stream for region (%u,%u): %s", x0, y0, pp_stream_error(st));
    }

    /* The stream lives in this GP's local memory while it is sent (the
     * encoder's own buffer is host scratch; copying it here makes the
     * memory limit apply; the stores were charged above). */
    size_t bytes = st->n_words * sizeof(uint32_t);
    uint32_t *local = fw_alloc(gp, bytes);
    if (!local) {
        return FW_ERROR;
    }
    for (size_t i = 0; i < st->n_words; i++) {
        local[i] = st->words[i];
    }
    ring_addr_t dst = ring_addr(RING_NODE_RENDERER, renderer);
    uint32_t args[RING_MSG_ARGS] = { x0, y0, 0, 0, 0, 0 };
    fw_status_t rc = fw_send(gp, dst, RING_MSG_RENDERER_SET_REGION, args, NULL, 0);
    if (rc == FW_OK) {
        rc = fw_send(gp, dst, RING_MSG_RENDERER_EXEC, NULL, local, bytes);
    }
    fw_free(gp, local);
    if (rc != FW_OK) {
        return FW_ERROR;
    }
    uint32_t px[RING_MSG_ARGS] = { TP_R, TP_G, TP_B, ring_addr_pack(ring_addr(RING_NODE_FB, 0)), 0, 0 };
    return fw_send(gp, dst, RING_MSG_RENDERER_SEND_PIXELS, px, NULL, 0);
}

/* Loaded: build the disc table in local memory. */
static fw_status_t tp_start(gp_t *gp)
{
    const fw_machine_info_t *mi = fw_machine_info(gp);
    tp_state_t *s = fw_alloc(gp, sizeof *s);
    if (!s) {
        return FW_ERROR;
    }
    fw_set_state(gp, s);
    fw_ops_t ops = {0};
    for (unsigned i = 0; i < TP_DISCS; i++) {
        s->disc[i] = tp_disc(i, mi->screen_width, mi->screen_height);
        s->k[i] = (int32_t)((255ll << 16) / ((int64_t)s->disc[i].r * s->disc[i].r));
        ops.int_ops += 12;        /* tp_disc: 3 mul, 3 mod-by-constant (mul+shift), adds */
        ops.fmul += 1;            /* r^2 */
        ops.fdiv += 1;            /* 255 * 2^16 / r^2 */
        ops.stores += 5;
    }
    fw_charge(gp, &ops);
    return FW_OK;
}

/* One frame: every region of this GP's renderers. */
static fw_status_t tp_frame(gp_t *gp)
{
    const fw_machine_info_t *mi = fw_machine_info(gp);
    tp_state_t *s = fw_state(gp);
    unsigned regions_x = mi->screen_width / mi->region_width;
    unsigned n_regions = regions_x * (mi->screen_height / mi->region_height);
    unsigned g = fw_gp_index(gp);
    pp_stream_t st;
    pp_stream_init(&st);
    fw_status_t rc = FW_OK;
    /* Rounds outermost, so that every renderer this GP drives gets its first
     * region before any gets its second. */
    for (unsigned round = 0; rc == FW_OK; round++) {
        int any = 0;
        for (unsigned j = g; j < mi->n_renderers && rc == FW_OK; j += mi->n_gp) {
            unsigned k = j + round * mi->n_renderers;
            if (k >= n_regions) {
                continue;
            }
            any = 1;
            rc = send_region(gp, s, j, (k % regions_x) * mi->region_width, (k / regions_x) * mi->region_height, &st);
        }
        if (!any) {
            break;
        }
    }
    pp_stream_free(&st);
    return rc;
}

static fw_status_t tp_message(gp_t *gp, const ring_msg_t *msg)
{
    if (msg->kind == RING_MSG_FRAME_START) {
        return tp_frame(gp);
    }
    return fw_fail(gp, "test pattern: unexpected message kind %u", msg->kind);
}

const fw_program_t testpattern_program = {
    .name = "testpattern",
    .image_bytes = 16384,         /* [U] stand-in size of the i860 binary */
    .on_start = tp_start,
    .on_message = tp_message,
};
