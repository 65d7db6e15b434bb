/* vr_gp.c: the gaze-directed volume renderer's GP program: its descriptor and the dispatch of ring messages to the phases (setup, plan, fetch, cast, resample).
 *
 * Paper: seed 004 §4 last paragraph (division of work), §5 (octree), §6.
 * Partitioning, PP memory layout and the per-frame message sequence are in
 * firmware/ARCHITECTURE.md. */
#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "vr_gp_internal.h"


static fw_status_t vr_message(gp_t *gp, const ring_msg_t *m)
{
    vr_state_t *s = fw_state(gp);
    if (!s)
        return fw_fail(gp, "vr: message before start");
    switch (m->kind) {
    case RING_MSG_FRAME_START:
        return vr_plan_frame_start(gp, s, m->args[0]);
    case RING_MSG_RENDERER_DATA:
        return vr_fetch_on_data(gp, s, m);
    case RING_MSG_GP_USER:
        switch (m->args[0]) {
        case VR_MSG_FRAME_PARAMS:
            if (m->payload_bytes != sizeof(vr_frame_t))
                return fw_fail(gp, "vr: frame parameters of %zu bytes", m->payload_bytes);
            memcpy(&s->fr, m->payload, sizeof s->fr);
            s->exec_sent = false;
            return FW_OK;
        case VR_MSG_LEVELK:
            return vr_setup_on_levelk(gp, s, m);
        case VR_MSG_SLAB:
            return vr_setup_on_slab(gp, s, m);
        case VR_MSG_OCC:
            return vr_setup_on_occ(gp, s, m);
        case VR_MSG_REQUEST: {
            const uint32_t *ids = m->payload;
            size_t n = m->payload_bytes / 4;
            unsigned req = m->src.index;
            if (s->exec_sent)
                return vr_fetch_forward(gp, s, ids, n, req);
            /* Keep it until our EXEC is out (ordering in the FIFO to the renderer). */
            size_t need = s->pending_req_n + n + 2;
            if (need > s->pending_req_cap) {
                size_t cap = need * 2;
                uint32_t *nb = fw_alloc(gp, cap * 4);
                if (!nb)
                    return FW_ERROR;
                if (s->pending_req) {
                    memcpy(nb, s->pending_req, s->pending_req_n * 4);
                    fw_free(gp, s->pending_req);
                }
                s->pending_req = nb;
                s->pending_req_cap = cap;
            }
            s->pending_req[s->pending_req_n++] = req;
            s->pending_req[s->pending_req_n++] = (uint32_t)n;
            memcpy(s->pending_req + s->pending_req_n, ids, n * 4);
            s->pending_req_n += n;
            return FW_OK;
        }
        case VR_MSG_BOUNDARY:
            return vr_resample_on_boundary(gp, s, m);
        case VR_MSG_NEED:
            return vr_slabs_early(s, m) ? vr_slabs_defer(gp, s, m) : vr_slabs_on_need(gp, s, m);
        case VR_MSG_PARTIAL:
            return vr_slabs_early(s, m) ? vr_slabs_defer(gp, s, m) : vr_slabs_on_partial(gp, s, m);
        default:
            return fw_fail(gp, "vr: unknown GP message %u", m->args[0]);
        }
    default:
        return fw_fail(gp, "vr: unexpected message kind %s", ring_msg_kind_name(m->kind));
    }
}

const fw_program_t vr_program = {
    .name = "gaze-volume",
    .image_bytes = 65536,         /* [U] stand-in size of the i860 binary */
    .on_start = vr_setup_start,
    .on_message = vr_message,
};
