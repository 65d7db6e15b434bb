/* renderer_node.c: renderer ring port: FIFO of commands, cycle charging, replies over the ring. */
#include "renderer_node.h"

#include <stdlib.h>
#include <string.h>

pp5_status_t rnode_init(renderer_node_t *n, unsigned index, const pp5_params_t *p, sched_t *sched,
                        rnode_send_fn send, void *send_ctx)
{
    memset(n, 0, sizeof *n);
    n->index = index;
    n->period_ps = clock_period_ps(p->renderer_clock_hz);
    n->cycles_per_bit = p->rport_cycles_per_bit;
    n->msg_cycles = p->rport_msg_cycles;
    n->sched = sched;
    n->send = send;
    n->send_ctx = send_ctx;
    n->scratch = malloc(3 * (size_t)PP_COUNT * sizeof *n->scratch);
    if (!n->scratch) {
        return pp5_fail(PP5_E_NOMEM, "renderer %u: out of memory", index);
    }
    pp5_status_t st = renderer_init(&n->r, (int)index, &p->pp);
    if (st != PP5_OK) {
        free(n->scratch);
        n->scratch = NULL;
    }
    return st;
}

void rnode_free(renderer_node_t *n)
{
    while (n->count > 0) {
        free(n->fifo[n->head].payload_copy);
        n->head = (n->head + 1) % n->cap;
        n->count--;
    }
    free(n->fifo);
    free(n->scratch);
    if (n->r.array) {
        renderer_free(&n->r);
    }
    memset(n, 0, sizeof *n);
}

bool rnode_busy(const renderer_node_t *n, pp5_tick_t now)
{
    return n->busy_until > now || n->count > 0;
}

static pp5_status_t rnode_fw_error(const renderer_node_t *n, const ring_msg_t *m, const char *what)
{
    char text[400];
    snprintf(text, sizeof text, "%s", pp5_error_text());
    return pp5_fail(PP5_E_FIRMWARE, "renderer %u: %s from node %u.%u: %s", n->index, what, m->src.type,
                    m->src.index, text);
}

static pp5_status_t rnode_expect_payload(const renderer_node_t *n, const ring_msg_t *m, size_t bytes,
                                         const char *what)
{
    if (m->payload_bytes != bytes) {
        return pp5_fail(PP5_E_FIRMWARE, "renderer %u: %s from node %u.%u carries %zu bytes, expected %zu",
                        n->index, what, m->src.type, m->src.index, m->payload_bytes, bytes);
    }
    return PP5_OK;
}

/* Reply with 16384 words of data (RENDERER_DATA) to the packed address. */
static pp5_status_t rnode_reply_data(renderer_node_t *n, uint32_t reply_to, uint32_t tag, uint32_t bits,
                                     pp5_tick_t t)
{
    ring_msg_t r;
    memset(&r, 0, sizeof r);
    r.src = ring_addr(RING_NODE_RENDERER, n->index);
    r.dst = ring_addr_unpack(reply_to);
    r.kind = RING_MSG_RENDERER_DATA;
    r.cls = RING_CLASS_DATA;
    r.args[0] = tag;
    r.args[1] = bits;
    r.payload = n->scratch;
    r.payload_bytes = (size_t)PP_COUNT * 4;
    return n->send(n->send_ctx, &r, t);
}

/* Execute one message starting at t; sets *cycles; posts replies at t + cycles. */
static pp5_status_t rnode_execute(renderer_node_t *n, const ring_msg_t *m, pp5_tick_t t, uint64_t *cycles,
                                  const char **what)
{
    uint64_t c = n->msg_cycles;
    pp5_status_t st = PP5_OK;
    const uint32_t *words = m->payload;
    switch (m->kind) {
    case RING_MSG_RENDERER_EXEC: {
        *what = "exec";
        if (m->payload_bytes % 4 != 0) {
            return rnode_expect_payload(n, m, m->payload_bytes / 4 * 4, "RENDERER_EXEC");
        }
        renderer_exec_result_t res;
        st = renderer_execute(&n->r, words, m->payload_bytes / 4, &res);
        if (st != PP5_OK) {
            return rnode_fw_error(n, m, "RENDERER_EXEC");
        }
        c += res.total_cycles;
        n->exec_cycles += res.total_cycles;
        break;
    }
    case RING_MSG_RENDERER_SET_REGION:
        *what = "set_region";
        renderer_set_region(&n->r, (int)(int32_t)m->args[0], (int)(int32_t)m->args[1]);
        break;
    case RING_MSG_RENDERER_WRITE_FIELD:
        *what = "write_field";
        if ((st = rnode_expect_payload(n, m, (size_t)PP_COUNT * 4, "RENDERER_WRITE_FIELD")) != PP5_OK) {
            return st;
        }
        if (renderer_write_field(&n->r, m->args[0], m->args[1], words) != PP5_OK) {
            return rnode_fw_error(n, m, "RENDERER_WRITE_FIELD");
        }
        c += (uint64_t)m->args[1] * n->cycles_per_bit;
        n->port_cycles += (uint64_t)m->args[1] * n->cycles_per_bit;
        break;
    case RING_MSG_RENDERER_WRITE_BS:
        *what = "write_bs";
        if ((st = rnode_expect_payload(n, m, (size_t)PP_COUNT * 4, "RENDERER_WRITE_BS")) != PP5_OK) {
            return st;
        }
        if (renderer_bs_write(&n->r, m->args[0], words) != PP5_OK) {
            return rnode_fw_error(n, m, "RENDERER_WRITE_BS");
        }
        c += 32ull * n->cycles_per_bit;
        n->port_cycles += 32ull * n->cycles_per_bit;
        break;
    case RING_MSG_RENDERER_READ_FIELD:
        *what = "read_field";
        if (renderer_read_field(&n->r, m->args[0], m->args[1], n->scratch) != PP5_OK) {
            return rnode_fw_error(n, m, "RENDERER_READ_FIELD");
        }
        c += (uint64_t)m->args[1] * n->cycles_per_bit;
        n->port_cycles += (uint64_t)m->args[1] * n->cycles_per_bit;
        st = rnode_reply_data(n, m->args[2], m->args[3], m->args[1], t + c * n->period_ps);
        break;
    case RING_MSG_RENDERER_READ_BS:
        *what = "read_bs";
        if (renderer_bs_read(&n->r, m->args[0], n->scratch) != PP5_OK) {
            return rnode_fw_error(n, m, "RENDERER_READ_BS");
        }
        c += 32ull * n->cycles_per_bit;
        n->port_cycles += 32ull * n->cycles_per_bit;
        st = rnode_reply_data(n, m->args[2], m->args[3], 32, t + c * n->period_ps);
        break;
    case RING_MSG_RENDERER_SEND_PIXELS: {
        *what = "send_pixels";
        for (int k = 0; k < 3; k++) {
            if (renderer_read_field(&n->r, m->args[k], 8, n->scratch + (size_t)k * PP_COUNT) != PP5_OK) {
                return rnode_fw_error(n, m, "RENDERER_SEND_PIXELS");
            }
        }
        c += 24ull * n->cycles_per_bit;
        n->port_cycles += 24ull * n->cycles_per_bit;
        /* Pack RGB8 row-major into the tail of scratch viewed as bytes is
         * unsafe (aliasing the source); use a separate buffer. */
        uint8_t *rgb = malloc((size_t)PP_COUNT * 3);
        if (!rgb) {
            return pp5_fail(PP5_E_NOMEM, "renderer %u: out of memory", n->index);
        }
        for (size_t i = 0; i < PP_COUNT; i++) {
            rgb[3 * i + 0] = (uint8_t)n->scratch[i];
            rgb[3 * i + 1] = (uint8_t)n->scratch[PP_COUNT + i];
            rgb[3 * i + 2] = (uint8_t)n->scratch[2 * PP_COUNT + i];
        }
        ring_msg_t r;
        memset(&r, 0, sizeof r);
        r.src = ring_addr(RING_NODE_RENDERER, n->index);
        r.dst = ring_addr_unpack(m->args[3]);
        r.kind = RING_MSG_FB_PIXELS;
        r.cls = RING_CLASS_PIXELS;
        r.args[0] = (uint32_t)n->r.x0;
        r.args[1] = (uint32_t)n->r.y0;
        r.args[2] = PP_ARRAY_DIM;
        r.args[3] = PP_ARRAY_DIM;
        r.payload = rgb;
        r.payload_bytes = (size_t)PP_COUNT * 3;
        st = n->send(n->send_ctx, &r, t + c * n->period_ps);
        free(rgb);
        break;
    }
    default:
        return pp5_fail(PP5_E_FIRMWARE, "renderer %u: message kind %u from node %u.%u is not a renderer command",
                        n->index, m->kind, m->src.type, m->src.index);
    }
    *cycles = c;
    return st;
}

static pp5_status_t rnode_run_event(void *ctx, uint64_t arg, pp5_tick_t now)
{
    renderer_node_t *n = ctx;
    n->scheduled = false;
    if (n->count == 0) {
        return PP5_OK;
    }
    rnode_item_t item = n->fifo[n->head];
    n->head = (n->head + 1) % n->cap;
    n->count--;
    pp5_tick_t start = tick_max(now, n->busy_until);
    uint64_t cycles = 0;
    const char *what = "?";
    pp5_status_t st = rnode_execute(n, &item.msg, start, &cycles, &what);
    free(item.payload_copy);
    if (st != PP5_OK) {
        return st;
    }
    pp5_tick_t dur = clock_cycles_ps(cycles, n->period_ps);
    n->busy_until = start + dur;
    n->busy_ps += dur;
    n->cycles += cycles;
    n->messages++;
    if (n->trace && dur > 0) {
        n->trace(n->trace_ctx, n->index, what, start, start + dur);
    }
    if (n->count > 0) {
        n->scheduled = true;
        return sched_at(n->sched, n->busy_until, SCHED_PRIO_UNIT, rnode_run_event, n, 0);
    }
    return PP5_OK;
}

pp5_status_t rnode_deliver(renderer_node_t *n, const ring_msg_t *msg, pp5_tick_t now)
{
    if (n->count == n->cap) {
        size_t cap = n->cap ? n->cap * 2 : 16;
        rnode_item_t *q = malloc(cap * sizeof *q);
        if (!q) {
            return pp5_fail(PP5_E_NOMEM, "renderer %u: out of memory for the FIFO", n->index);
        }
        for (size_t i = 0; i < n->count; i++) {
            q[i] = n->fifo[(n->head + i) % n->cap];
        }
        free(n->fifo);
        n->fifo = q;
        n->head = 0;
        n->cap = cap;
    }
    rnode_item_t *it = &n->fifo[(n->head + n->count) % n->cap];
    it->msg = *msg;
    it->payload_copy = NULL;
    if (msg->payload_bytes > 0) {
        it->payload_copy = malloc(msg->payload_bytes);
        if (!it->payload_copy) {
            return pp5_fail(PP5_E_NOMEM, "renderer %u: out of memory for a message", n->index);
        }
        memcpy(it->payload_copy, msg->payload, msg->payload_bytes);
    }
    it->msg.payload = it->payload_copy;
    n->count++;
    if (!n->scheduled) {
        n->scheduled = true;
        return sched_at(n->sched, tick_max(now, n->busy_until), SCHED_PRIO_UNIT, rnode_run_event, n, 0);
    }
    return PP5_OK;
}
