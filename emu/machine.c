/* machine.c: builds the machine from the parameters, routes ring messages to units, runs frames. */
#include "machine.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static pp5_status_t machine_deliver(void *ctx, const ring_msg_t *msg, pp5_tick_t now)
{
    machine_t *m = ctx;
    switch (msg->dst.type) {
    case RING_NODE_GP:
        /* GPs and renderers keep the ring's payload buffer instead of
         * copying it (host speed). */
        return gp_deliver_owned(&m->gp[msg->dst.index], msg,
                                msg->kind == RING_MSG_HOST_LOAD ? NULL : ring_take_payload(&m->ring),
                                now);
    case RING_NODE_RENDERER:
        return rnode_deliver(&m->rn[msg->dst.index], msg, ring_take_payload(&m->ring), now);
    case RING_NODE_FB: return fb_deliver(&m->fb, msg, now);
    default: return host_deliver(&m->host, msg, now);
    }
}

pp5_status_t machine_position(const machine_t *m, ring_addr_t a, unsigned *pos)
{
    switch (a.type) {
    case RING_NODE_HOST:
        if (a.index == 0) {
            *pos = 0;
            return PP5_OK;
        }
        break;
    case RING_NODE_GP:
        if (a.index < m->n_gp) {
            *pos = 1 + a.index;
            return PP5_OK;
        }
        break;
    case RING_NODE_RENDERER:
        if (a.index < m->n_rn) {
            *pos = 1 + m->n_gp + a.index;
            return PP5_OK;
        }
        break;
    case RING_NODE_FB:
        if (a.index == 0) {
            *pos = 1 + m->n_gp + m->n_rn;
            return PP5_OK;
        }
        break;
    }
    static const char *names[] = { "host", "GP", "renderer", "frame buffer" };
    return pp5_fail(PP5_E_FIRMWARE, "no ring node %s %u on this machine (%u GPs, %u renderers, 1 host, 1 FB)",
                    a.type < 4 ? names[a.type] : "of unknown type", a.index, m->n_gp, m->n_rn);
}

/* Sends msg, copying its payload, or adopting it when `owned`
 * (ring_payload_alloc'd, msg->payload) is given. */
static pp5_status_t send_on_ring(machine_t *m, const ring_msg_t *msg, void *owned, pp5_tick_t t)
{
    unsigned s, d;
    pp5_status_t st = machine_position(m, msg->src, &s);
    if (st == PP5_OK) {
        st = machine_position(m, msg->dst, &d);
    }
    if (st != PP5_OK) {
        ring_payload_free(owned);
        return st;
    }
    return owned ? ring_send_owned(&m->ring, msg, owned, s, d, t) : ring_send(&m->ring, msg, s, d, t);
}

pp5_status_t machine_send(machine_t *m, const ring_msg_t *msg, pp5_tick_t t)
{
    return send_on_ring(m, msg, NULL, t);
}

static pp5_status_t machine_gp_send(void *ctx, gp_t *gp, const ring_msg_t *msg, pp5_tick_t t)
{
    return machine_send(ctx, msg, t);
}

static pp5_status_t machine_unit_send(void *ctx, const ring_msg_t *msg, pp5_tick_t t)
{
    return machine_send(ctx, msg, t);
}

/* A renderer's reply: its payload buffer goes with it (no copy of 64 KB
 * backing-store blocks on every read). */
static pp5_status_t machine_renderer_send(void *ctx, const ring_msg_t *msg, void *owned,
                                          pp5_tick_t t)
{
    return send_on_ring(ctx, msg, owned, t);
}

/* ---- timeline observers ---- */

static void trace_ring(void *ctx, unsigned channel, const ring_msg_t *msg, pp5_tick_t start,
                       pp5_tick_t end, pp5_tick_t arrival)
{
    machine_t *m = ctx;
    timeline_span(m->tl, m->tid_ch0 + channel, ring_msg_kind_name(msg->kind), start, end,
                  ring_wire_bytes(&m->ring, msg));
    if (msg->src.type == RING_NODE_HOST) {
        /* The host's own track shows what it injects. */
        timeline_span(m->tl, m->tid_host, ring_msg_kind_name(msg->kind), start, end, ring_wire_bytes(&m->ring, msg));
    }
}

static void trace_gp(void *ctx, const gp_t *gp, const char *what, pp5_tick_t start, pp5_tick_t end)
{
    machine_t *m = ctx;
    timeline_span(m->tl, m->tid_gp0 + gp->index, what, start, end, UINT64_MAX);
}

static void trace_rn(void *ctx, unsigned index, const char *what, pp5_tick_t start, pp5_tick_t end)
{
    machine_t *m = ctx;
    timeline_span(m->tl, m->tid_rn0 + index, what, start, end, UINT64_MAX);
}

static void trace_fb(void *ctx, const ring_msg_t *msg, pp5_tick_t now)
{
    machine_t *m = ctx;
    timeline_span(m->tl, m->tid_fb, ring_msg_kind_name(msg->kind), now, now, msg->payload_bytes);
}

pp5_status_t machine_enable_timeline(machine_t *m)
{
    if (m->tl) {
        return PP5_OK;
    }
    m->tl = calloc(1, sizeof *m->tl);
    if (!m->tl) {
        return pp5_fail(PP5_E_NOMEM, "out of memory for the timeline");
    }
    timeline_init(m->tl);
    char name[32];
    m->tid_host = timeline_track(m->tl, "host");
    for (unsigned i = 0; i < m->n_gp; i++) {
        snprintf(name, sizeof name, "GP %u", i);
        uint32_t tid = timeline_track(m->tl, name);
        if (i == 0) {
            m->tid_gp0 = tid;
        }
        m->gp[i].trace = trace_gp;
        m->gp[i].trace_ctx = m;
    }
    for (unsigned i = 0; i < m->n_rn; i++) {
        snprintf(name, sizeof name, "renderer %u", i);
        uint32_t tid = timeline_track(m->tl, name);
        if (i == 0) {
            m->tid_rn0 = tid;
        }
        m->rn[i].trace = trace_rn;
        m->rn[i].trace_ctx = m;
    }
    for (unsigned c = 0; c < m->ring.n_channels; c++) {
        snprintf(name, sizeof name, "ring channel %u", c);
        uint32_t tid = timeline_track(m->tl, name);
        if (c == 0) {
            m->tid_ch0 = tid;
        }
    }
    m->tid_fb = timeline_track(m->tl, "frame buffer");
    if (m->tid_fb == 0) {
        return pp5_fail(PP5_E_NOMEM, "out of memory for the timeline");
    }
    m->ring.trace = trace_ring;
    m->ring.trace_ctx = m;
    m->fb.trace = trace_fb;
    m->fb.trace_ctx = m;
    return PP5_OK;
}

pp5_status_t machine_init(machine_t *m, const pp5_params_t *p)
{
    memset(m, 0, sizeof *m);
    pp5_status_t st = pp5_params_validate(p);
    if (st != PP5_OK) {
        return st;
    }
    m->params = *p;
    m->n_gp = p->n_gp;
    m->n_rn = p->n_renderers;
    m->info.n_gp = p->n_gp;
    m->info.n_renderers = p->n_renderers;
    m->info.screen_width = p->fb_width;
    m->info.screen_height = p->fb_height;
    m->info.region_width = PP_ARRAY_DIM;
    m->info.region_height = PP_ARRAY_DIM;
    m->info.pp_mem_bits = PP_MEM_BITS;
    m->info.pp_bs_blocks = PP_BS_BLOCKS;
    m->info.local_mem_bytes = p->gp_local_mem_bytes;
    sched_init(&m->sched);
    m->sched.describe_busy = machine_describe_busy;
    m->sched.describe_ctx = m;
    ring_config_t rc = { .channels = p->ring_channels, .width_bits = p->ring_width_bits,
                         .n_nodes = m->n_gp + m->n_rn + 2, .clock_hz = p->ring_clock_hz,
                         .hop_cycles = p->ring_hop_cycles, .header_bytes = p->ring_header_bytes };
    st = ring_init(&m->ring, &rc, &m->sched, machine_deliver, m);
    if (st != PP5_OK) {
        return st;
    }
    if (p->fb_rx_ports > 0) {
        st = ring_set_rx_ports(&m->ring, m->n_gp + m->n_rn + 1, p->fb_rx_ports);   /* FB position */
        if (st != PP5_OK) {
            ring_free(&m->ring);
            return st;
        }
    }
    host_init(&m->host, machine_unit_send, m);
    m->gp = calloc(m->n_gp, sizeof *m->gp);
    m->rn = calloc(m->n_rn, sizeof *m->rn);
    if (!m->gp || !m->rn) {
        machine_free(m);
        return pp5_fail(PP5_E_NOMEM, "out of memory for %u GPs and %u renderers", p->n_gp, p->n_renderers);
    }
    for (unsigned i = 0; i < m->n_gp; i++) {
        st = gp_init(&m->gp[i], i, p, &m->info, &m->sched, machine_gp_send, m);
        if (st != PP5_OK) {
            machine_free(m);
            return st;
        }
    }
    for (unsigned i = 0; i < m->n_rn; i++) {
        st = rnode_init(&m->rn[i], i, p, &m->sched, machine_renderer_send, m);
        if (st != PP5_OK) {
            machine_free(m);
            return st;
        }
    }
    st = fb_init(&m->fb, p->fb_width, p->fb_height, p->fb_double_buffered != 0);
    if (st == PP5_OK && p->sim_host_threads > 1 && m->n_rn > 1) {
        /* The scheduler thread also runs functional steps when it has to
         * wait, so host_threads - 1 workers. */
        st = rpool_start(&m->pool, m->rn, m->n_rn, p->sim_host_threads - 1);
        m->pool_running = st == PP5_OK;
    }
    if (st != PP5_OK) {
        machine_free(m);
        return st;
    }
    return PP5_OK;
}

void machine_free(machine_t *m)
{
    if (m->pool_running) {
        rpool_stop(&m->pool);
        m->pool_running = false;
    }
    if (m->gp) {
        for (unsigned i = 0; i < m->n_gp; i++) {
            gp_free(&m->gp[i]);
        }
    }
    if (m->rn) {
        for (unsigned i = 0; i < m->n_rn; i++) {
            rnode_free(&m->rn[i]);
        }
    }
    free(m->gp);
    free(m->rn);
    fb_free(&m->fb);
    ring_free(&m->ring);
    sched_free(&m->sched);
    if (m->tl) {
        timeline_free(m->tl);
        free(m->tl);
    }
    memset(m, 0, sizeof *m);
}

pp5_status_t machine_load_program(machine_t *m, unsigned gp, const fw_program_t *prog, const void *data,
                                  size_t data_bytes)
{
    if (gp >= m->n_gp) {
        return pp5_fail(PP5_E_CONFIG, "no GP %u (machine has %u)", gp, m->n_gp);
    }
    gp_set_program(&m->gp[gp], prog);
    return host_load_gp(&m->host, gp, prog->image_bytes, data, data_bytes, m->sched.now);
}

pp5_status_t machine_load_all(machine_t *m, const fw_program_t *prog)
{
    for (unsigned g = 0; g < m->n_gp; g++) {
        pp5_status_t st = machine_load_program(m, g, prog, NULL, 0);
        if (st != PP5_OK) {
            return st;
        }
    }
    return PP5_OK;
}

void machine_describe_busy(void *ctx, char *buf, size_t n)
{
    machine_t *m = ctx;
    pp5_tick_t now = m->sched.now;
    size_t used = 0;
    buf[0] = '\0';
#define APPEND(...)                                                              \
    do {                                                                         \
        if (used < n) {                                                          \
            int k = snprintf(buf + used, n - used, __VA_ARGS__);                 \
            used += k > 0 ? (size_t)k : 0;                                       \
        }                                                                        \
    } while (0)
    for (unsigned i = 0; i < m->n_gp; i++) {
        if (gp_busy(&m->gp[i], now)) {
            APPEND("%sGP %u (%zu queued)", used ? ", " : "", i, m->gp[i].inbox_count);
        }
    }
    for (unsigned i = 0; i < m->n_rn; i++) {
        if (rnode_busy(&m->rn[i], now)) {
            APPEND("%srenderer %u (%zu queued)", used ? ", " : "", i, m->rn[i].count);
        }
    }
    if (ring_in_flight(&m->ring) > 0) {
        APPEND("%sring (%zu messages in flight)", used ? ", " : "", ring_in_flight(&m->ring));
    }
#undef APPEND
}

/* Latest instant any unit is busy until. */
static pp5_tick_t machine_last_activity(const machine_t *m)
{
    pp5_tick_t end = m->sched.now;
    for (unsigned i = 0; i < m->n_gp; i++) {
        end = tick_max(end, m->gp[i].local_ps);
    }
    for (unsigned i = 0; i < m->n_rn; i++) {
        end = tick_max(end, m->rn[i].busy_until);
    }
    return end;
}

pp5_status_t machine_run_setup(machine_t *m, sched_stop_t *stop)
{
    pp5_tick_t start = m->sched.now;
    /* Setup has its own bound: it is not a frame, and the once-per-sequence
     * work (e.g. building the 3D mip map) can take far longer than one. */
    pp5_tick_t budget_end = start + (pp5_tick_t)(m->params.sim_setup_budget_s * 1e12);
    pp5_status_t st = sched_run_budget(&m->sched, budget_end, stop);
    if (st != PP5_OK && *stop == SCHED_STOP_BUDGET_EXCEEDED) {
        char why[512];
        snprintf(why, sizeof why, "%s", pp5_error_text());
        st = pp5_fail(st, "setup ran past sim.setup_budget_s = %g s: %s",
                      m->params.sim_setup_budget_s, why);
    }
    if (st != PP5_OK && m->pool_running) {
        rpool_stop(&m->pool);
        m->pool_running = false;
    }
    pp5_tick_t end = machine_last_activity(m);
    m->setup_ps += end - start;
    for (unsigned i = 0; i < m->n_gp; i++) {
        m->gp[i].setup_busy_ps = m->gp[i].busy_ps;
        m->gp[i].setup_busy_cycles = m->gp[i].busy_cycles;
        m->gp[i].setup_ops = m->gp[i].ops_total;
    }
    for (unsigned i = 0; i < m->n_rn; i++) {
        m->rn[i].setup_busy_ps = m->rn[i].busy_ps;
    }
    m->sched.now = tick_max(end, m->sched.now);
    return st;
}

pp5_status_t machine_run_frame(machine_t *m, sched_stop_t *stop)
{
    pp5_tick_t start = m->sched.now;
    double budget_ps = m->params.sim_budget_s * 1e12;
    pp5_tick_t budget_end = start + (pp5_tick_t)budget_ps;
    pp5_tick_t busy0[MACHINE_MAX_CHANNELS];
    uint64_t bytes0[RING_CLASS_COUNT];
    pp5_tick_t cbusy0[RING_CLASS_COUNT];
    memcpy(cbusy0, m->ring.busy_by_class, sizeof cbusy0);
    for (unsigned c = 0; c < m->ring.n_channels; c++) {
        busy0[c] = m->ring.ch[c].busy_ps;
    }
    memcpy(bytes0, m->ring.bytes_sent, sizeof bytes0);
    pp5_status_t st = host_start_frame(&m->host, m->n_gp, m->n_frames, start);
    if (st != PP5_OK) {
        *stop = SCHED_STOP_ERROR;
        return st;
    }
    st = sched_run_budget(&m->sched, budget_end, stop);
    if (st != PP5_OK && *stop == SCHED_STOP_BUDGET_EXCEEDED) {
        /* Name the parameter that sets the budget, so the user knows what to raise. */
        char why[900];
        snprintf(why, sizeof why, "%s", pp5_error_text());
        st = pp5_fail(st, "frame ran past sim.budget_s = %g s: %s", m->params.sim_budget_s, why);
    }
    /* Last activity of any unit (events end at deliveries; GPs and renderers
     * may stay busy after their last event). */
    pp5_tick_t end = machine_last_activity(m);
    if (*stop == SCHED_STOP_BUDGET_EXCEEDED) {
        end = budget_end;
    }
    if (m->n_frames < MACHINE_MAX_FRAMES) {
        machine_frame_t *f = &m->frames[m->n_frames++];
        memset(f, 0, sizeof *f);
        f->start_ps = start;
        f->end_ps = end;
        f->stop = *stop;
        for (unsigned c = 0; c < m->ring.n_channels; c++) {
            f->ch_busy_ps[c] = m->ring.ch[c].busy_ps - busy0[c];
        }
        for (unsigned k = 0; k < RING_CLASS_COUNT; k++) {
            f->bytes_by_class[k] = m->ring.bytes_sent[k] - bytes0[k];
            f->busy_by_class[k] = m->ring.busy_by_class[k] - cbusy0[k];
        }
    }
    m->sched.now = end > m->sched.now ? end : m->sched.now;
    fb_end_frame(&m->fb);
    if (st != PP5_OK && m->pool_running) {
        /* Workers may still be running commands of the aborted frame: stop
         * them before anyone reads renderer statistics. */
        rpool_stop(&m->pool);
        m->pool_running = false;
    }
    return st;
}
