/* renderer_node.c: renderer ring port: command FIFO, functional step (maybe on a worker), cycle charging, replies. */
#include "renderer_node.h"
#include "ring_payload.h"

#include <stdio.h>
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

static void rnode_item_free(rnode_item_t *it)
{
    if (it) {
        ring_payload_free(it->payload_copy);
        ring_payload_free(it->reply_payload);
        free(it);
    }
}

void rnode_free(renderer_node_t *n)
{
    while (n->count > 0) {
        rnode_item_free(n->fifo[n->head]);
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

/* ---- functional step: touches only this node's renderer and scratch ---- */

static pp5_status_t item_fail(rnode_item_t *it, const renderer_node_t *n, const char *what)
{
    snprintf(it->err, sizeof it->err, "renderer %u: %s from node %u.%u: %s", n->index, what,
             it->msg.src.type, it->msg.src.index, pp5_error_text());
    return PP5_E_FIRMWARE;
}

static pp5_status_t item_payload(rnode_item_t *it, const renderer_node_t *n, size_t bytes, const char *what)
{
    if (it->msg.payload_bytes != bytes) {
        snprintf(it->err, sizeof it->err, "renderer %u: %s from node %u.%u carries %zu bytes, expected %zu",
                 n->index, what, it->msg.src.type, it->msg.src.index, it->msg.payload_bytes, bytes);
        return PP5_E_FIRMWARE;
    }
    return PP5_OK;
}

/* Prepare a reply message whose payload is a copy of `bytes` of `data`
 * (data NULL: the caller fills it->reply_payload itself). */
static pp5_status_t item_reply(rnode_item_t *it, const renderer_node_t *n, uint32_t reply_to, uint32_t kind,
                               uint32_t cls, const void *data, size_t bytes)
{
    it->reply_payload = ring_payload_alloc(bytes);
    if (!it->reply_payload) {
        snprintf(it->err, sizeof it->err, "renderer %u: out of memory for a %zu-byte reply", n->index, bytes);
        return PP5_E_NOMEM;
    }
    if (data) {
        memcpy(it->reply_payload, data, bytes);
    }
    it->reply = ring_msg_make(ring_addr(RING_NODE_RENDERER, n->index), ring_addr_unpack(reply_to),
                              kind, cls, NULL, it->reply_payload, bytes);
    it->has_reply = true;
    return PP5_OK;
}

/* RENDERER_READ_BS_BOX (ring_msg.h): the words of a box of the block's PPs.
 * The port reads the block's 32 bit planes as for READ_BS and ships only the
 * box's words ([U]: facts §3.5, the readout path is unknown; a subset costs
 * the renderer a whole readout). */
static pp5_status_t read_bs_box(renderer_node_t *n, rnode_item_t *it)
{
    const ring_msg_t *m = &it->msg;
    unsigned bx = m->args[1] & 0xffu, bz = (m->args[1] >> 8) & 0xffu, by = m->args[1] >> 16;
    unsigned x0 = m->args[4] & 0xffu, z0 = (m->args[4] >> 8) & 0xffu, y0 = m->args[4] >> 16;
    unsigned sx = m->args[5] & 0xffu, sy = (m->args[5] >> 8) & 0xffu, sz = (m->args[5] >> 16) & 0xffu;
    if (!bx || !by || !bz || (uint64_t)bx * by * bz > PP_COUNT || !sx || !sy || !sz ||
        x0 + sx > bx || y0 + sy > by || z0 + sz > bz) {
        snprintf(it->err, sizeof it->err, "renderer %u: RENDERER_READ_BS_BOX of %ux%ux%u at "
                 "(%u, %u, %u) does not fit a %ux%ux%u block", n->index, sx, sy, sz, x0, y0, z0,
                 bx, by, bz);
        return PP5_E_FIRMWARE;
    }
    if (renderer_bs_read(&n->r, m->args[0], n->scratch) != PP5_OK)
        return item_fail(it, n, "RENDERER_READ_BS_BOX");
    size_t words = (size_t)sx * sy * sz;
    pp5_status_t st = item_reply(it, n, m->args[2], RING_MSG_RENDERER_DATA, RING_CLASS_DATA, NULL,
                                 words * 4);
    if (st != PP5_OK)
        return st;
    uint32_t *out = it->reply_payload;
    for (unsigned z = 0; z < sz; z++)
        for (unsigned y = 0; y < sy; y++)
            memcpy(out + ((size_t)z * sy + y) * sx,
                   n->scratch + ((size_t)(z0 + z) * by + y0 + y) * bx + x0, sx * sizeof *out);
    it->reply.args[0] = m->args[3];
    it->reply.args[1] = 32;
    return PP5_OK;
}

static pp5_status_t rnode_apply_inner(renderer_node_t *n, rnode_item_t *it)
{
    const ring_msg_t *m = &it->msg;
    const uint32_t *words = m->payload;
    uint64_t port = 0;
    pp5_status_t st = PP5_OK;
    switch (m->kind) {
    case RING_MSG_RENDERER_EXEC: {
        it->what = "exec";
        if (m->payload_bytes % 4 != 0) {
            return item_payload(it, n, m->payload_bytes / 4 * 4, "RENDERER_EXEC");
        }
        renderer_exec_result_t res;
        if (renderer_execute(&n->r, words, m->payload_bytes / 4, &res) != PP5_OK) {
            return item_fail(it, n, "RENDERER_EXEC");
        }
        it->exec_cycles = res.total_cycles;
        break;
    }
    case RING_MSG_RENDERER_SET_REGION:
        it->what = "set_region";
        renderer_set_region(&n->r, (int)(int32_t)m->args[0], (int)(int32_t)m->args[1]);
        break;
    case RING_MSG_RENDERER_WRITE_FIELD:
        it->what = "write_field";
        if ((st = item_payload(it, n, (size_t)PP_COUNT * 4, "RENDERER_WRITE_FIELD")) != PP5_OK) {
            return st;
        }
        if (renderer_write_field(&n->r, m->args[0], m->args[1], words) != PP5_OK) {
            return item_fail(it, n, "RENDERER_WRITE_FIELD");
        }
        port = (uint64_t)m->args[1] * n->cycles_per_bit;
        break;
    case RING_MSG_RENDERER_WRITE_BS:
        it->what = "write_bs";
        if ((st = item_payload(it, n, (size_t)PP_COUNT * 4, "RENDERER_WRITE_BS")) != PP5_OK) {
            return st;
        }
        if (renderer_bs_write(&n->r, m->args[0], words) != PP5_OK) {
            return item_fail(it, n, "RENDERER_WRITE_BS");
        }
        port = 32ull * n->cycles_per_bit;
        break;
    case RING_MSG_RENDERER_READ_FIELD:
        it->what = "read_field";
        /* Read straight into the reply (host speed: no 64 KB copy via scratch). */
        st = item_reply(it, n, m->args[2], RING_MSG_RENDERER_DATA, RING_CLASS_DATA, NULL,
                        (size_t)PP_COUNT * 4);
        if (st != PP5_OK) {
            return st;
        }
        if (renderer_read_field(&n->r, m->args[0], m->args[1], it->reply_payload) != PP5_OK) {
            it->has_reply = false;
            return item_fail(it, n, "RENDERER_READ_FIELD");
        }
        port = (uint64_t)m->args[1] * n->cycles_per_bit;
        it->reply.args[0] = m->args[3];
        it->reply.args[1] = m->args[1];
        break;
    case RING_MSG_RENDERER_READ_BS:
        it->what = "read_bs";
        st = item_reply(it, n, m->args[2], RING_MSG_RENDERER_DATA, RING_CLASS_DATA, NULL,
                        (size_t)PP_COUNT * 4);
        if (st != PP5_OK) {
            return st;
        }
        if (renderer_bs_read(&n->r, m->args[0], it->reply_payload) != PP5_OK) {
            it->has_reply = false;
            return item_fail(it, n, "RENDERER_READ_BS");
        }
        port = 32ull * n->cycles_per_bit;
        it->reply.args[0] = m->args[3];
        it->reply.args[1] = 32;
        break;
    case RING_MSG_RENDERER_READ_BS_BOX:
        it->what = "read_bs_box";
        if ((st = read_bs_box(n, it)) != PP5_OK)
            return st;
        port = 32ull * n->cycles_per_bit;
        break;
    case RING_MSG_RENDERER_SEND_PIXELS: {
        it->what = "send_pixels";
        for (int k = 0; k < 3; k++) {
            if (renderer_read_field(&n->r, m->args[k], 8, n->scratch + (size_t)k * PP_COUNT) != PP5_OK) {
                return item_fail(it, n, "RENDERER_SEND_PIXELS");
            }
        }
        port = 24ull * n->cycles_per_bit;
        /* Interleave R, G, B row-major into the reply (FB_PIXELS format). */
        st = item_reply(it, n, m->args[3], RING_MSG_FB_PIXELS, RING_CLASS_PIXELS, n->scratch, (size_t)PP_COUNT * 3);
        if (st != PP5_OK) {
            return st;
        }
        uint8_t *rgb = it->reply_payload;
        for (size_t i = 0; i < PP_COUNT; i++) {
            rgb[3 * i + 0] = (uint8_t)n->scratch[i];
            rgb[3 * i + 1] = (uint8_t)n->scratch[PP_COUNT + i];
            rgb[3 * i + 2] = (uint8_t)n->scratch[2 * PP_COUNT + i];
        }
        it->reply.args[0] = (uint32_t)n->r.x0;
        it->reply.args[1] = (uint32_t)n->r.y0;
        it->reply.args[2] = PP_ARRAY_DIM;
        it->reply.args[3] = PP_ARRAY_DIM;
        break;
    }
    default:
        snprintf(it->err, sizeof it->err, "renderer %u: message kind %u from node %u.%u is not a renderer command",
                 n->index, m->kind, m->src.type, m->src.index);
        return PP5_E_FIRMWARE;
    }
    it->port_cycles = port;
    it->cycles = n->msg_cycles + it->exec_cycles + port;
    return st;
}

static void rnode_apply(renderer_node_t *n, rnode_item_t *it)
{
    it->what = "?";
    it->st = rnode_apply_inner(n, it);
}

/* ---- worker pool ---- */

/* Claim the next unstarted item of some node (caller holds the lock). */
static rnode_item_t *rpool_claim(rpool_t *p, renderer_node_t **node_out)
{
    for (unsigned i = 0; i < p->n_nodes; i++) {
        renderer_node_t *n = &p->nodes[i];
        if (!n->in_progress && n->claimed < n->count) {
            rnode_item_t *it = n->fifo[(n->head + n->claimed) % n->cap];
            n->claimed++;
            n->in_progress = true;
            *node_out = n;
            return it;
        }
    }
    return NULL;
}

static void *rpool_worker(void *arg)
{
    rpool_t *p = arg;
    pthread_mutex_lock(&p->mu);
    for (;;) {
        renderer_node_t *n = NULL;
        rnode_item_t *it = NULL;
        while (!p->stop && !(it = rpool_claim(p, &n))) {
            pthread_cond_wait(&p->work, &p->mu);
        }
        if (!it) {
            break;
        }
        pthread_mutex_unlock(&p->mu);
        rnode_apply(n, it);
        pthread_mutex_lock(&p->mu);
        it->done = true;
        n->in_progress = false;
        pthread_cond_broadcast(&p->done);
        pthread_cond_broadcast(&p->work);     /* this node's next item is claimable */
    }
    pthread_mutex_unlock(&p->mu);
    return NULL;
}

pp5_status_t rpool_start(rpool_t *p, renderer_node_t *nodes, unsigned n_nodes, unsigned n_threads)
{
    memset(p, 0, sizeof *p);
    p->nodes = nodes;
    p->n_nodes = n_nodes;
    p->threads = calloc(n_threads, sizeof *p->threads);
    if (!p->threads) {
        return pp5_fail(PP5_E_NOMEM, "out of memory for %u worker threads", n_threads);
    }
    pthread_mutex_init(&p->mu, NULL);
    pthread_cond_init(&p->work, NULL);
    pthread_cond_init(&p->done, NULL);
    for (unsigned i = 0; i < n_nodes; i++) {
        nodes[i].pool = p;
    }
    for (unsigned i = 0; i < n_threads; i++) {
        if (pthread_create(&p->threads[i], NULL, rpool_worker, p) != 0) {
            rpool_stop(p);
            return pp5_fail(PP5_E_NOMEM, "cannot start worker thread %u", i);
        }
        p->n_threads++;
    }
    return PP5_OK;
}

void rpool_stop(rpool_t *p)
{
    if (!p->threads) {
        return;
    }
    pthread_mutex_lock(&p->mu);
    p->stop = true;
    pthread_cond_broadcast(&p->work);
    pthread_mutex_unlock(&p->mu);
    for (unsigned i = 0; i < p->n_threads; i++) {
        pthread_join(p->threads[i], NULL);
    }
    for (unsigned i = 0; i < p->n_nodes; i++) {
        p->nodes[i].pool = NULL;
        p->nodes[i].claimed = 0;
    }
    pthread_cond_destroy(&p->work);
    pthread_cond_destroy(&p->done);
    pthread_mutex_destroy(&p->mu);
    free(p->threads);
    memset(p, 0, sizeof *p);
}

/* Make sure the head item's functional step is done (run it here if no
 * worker has started it), then pop it. */
static rnode_item_t *rnode_pop_done(renderer_node_t *n)
{
    rnode_item_t *it = n->fifo[n->head];
    rpool_t *p = n->pool;
    if (!p) {
        if (!it->done) {          /* may have been done by a pool stopped since */
            rnode_apply(n, it);
            it->done = true;
        }
    } else {
        pthread_mutex_lock(&p->mu);
        while (!it->done) {
            if (n->claimed == 0 && !n->in_progress) {
                n->claimed = 1;
                n->in_progress = true;
                pthread_mutex_unlock(&p->mu);
                rnode_apply(n, it);
                pthread_mutex_lock(&p->mu);
                it->done = true;
                n->in_progress = false;
                pthread_cond_broadcast(&p->work);
            } else {
                pthread_cond_wait(&p->done, &p->mu);
            }
        }
        n->claimed--;
    }
    n->head = (n->head + 1) % n->cap;
    n->count--;
    if (p) {
        pthread_mutex_unlock(&p->mu);
    }
    return it;
}

/* ---- timing step (scheduler thread) ---- */

static pp5_status_t rnode_run_event(void *ctx, uint64_t arg, pp5_tick_t now)
{
    renderer_node_t *n = ctx;
    n->scheduled = false;
    if (n->count == 0) {
        return PP5_OK;
    }
    rnode_item_t *it = rnode_pop_done(n);
    if (it->st != PP5_OK) {
        pp5_status_t st = pp5_fail(it->st, "%s", it->err);
        rnode_item_free(it);
        return st;
    }
    pp5_tick_t start = tick_max(now, n->busy_until);
    pp5_tick_t dur = clock_cycles_ps(it->cycles, n->period_ps);
    n->busy_until = start + dur;
    n->busy_ps += dur;
    n->cycles += it->cycles;
    n->exec_cycles += it->exec_cycles;
    n->port_cycles += it->port_cycles;
    n->messages++;
    if (n->trace && dur > 0) {
        n->trace(n->trace_ctx, n->index, it->what, start, start + dur);
    }
    pp5_status_t st = PP5_OK;
    if (it->has_reply) {
        void *owned = it->reply_payload;   /* the ring frees it from now on */
        it->reply_payload = NULL;
        st = n->send(n->send_ctx, &it->reply, owned, n->busy_until);
    }
    rnode_item_free(it);
    if (st == PP5_OK && n->count > 0) {
        n->scheduled = true;
        st = sched_at(n->sched, n->busy_until, SCHED_PRIO_UNIT, rnode_run_event, n, 0);
    }
    return st;
}

pp5_status_t rnode_deliver(renderer_node_t *n, const ring_msg_t *msg, void *payload_buf,
                           pp5_tick_t now)
{
    rnode_item_t *it = calloc(1, sizeof *it);
    if (!it) {
        ring_payload_free(payload_buf);
        return pp5_fail(PP5_E_NOMEM, "renderer %u: out of memory for a command", n->index);
    }
    it->msg = *msg;
    if (payload_buf) {
        it->payload_copy = payload_buf;
    } else if (msg->payload_bytes > 0) {
        it->payload_copy = ring_payload_alloc(msg->payload_bytes);
        if (!it->payload_copy) {
            free(it);
            return pp5_fail(PP5_E_NOMEM, "renderer %u: out of memory for a message", n->index);
        }
        memcpy(it->payload_copy, msg->payload, msg->payload_bytes);
    }
    it->msg.payload = it->payload_copy;

    rpool_t *p = n->pool;
    if (p) {
        pthread_mutex_lock(&p->mu);
    }
    pp5_status_t st = PP5_OK;
    if (n->count == n->cap) {
        size_t cap = n->cap ? n->cap * 2 : 16;
        rnode_item_t **q = malloc(cap * sizeof *q);
        if (!q) {
            st = pp5_fail(PP5_E_NOMEM, "renderer %u: out of memory for the FIFO", n->index);
        } else {
            for (size_t i = 0; i < n->count; i++) {
                q[i] = n->fifo[(n->head + i) % n->cap];
            }
            free(n->fifo);
            n->fifo = q;
            n->head = 0;
            n->cap = cap;
        }
    }
    if (st == PP5_OK) {
        n->fifo[(n->head + n->count) % n->cap] = it;
        n->count++;
    }
    if (p) {
        pthread_cond_signal(&p->work);
        pthread_mutex_unlock(&p->mu);
    }
    if (st != PP5_OK) {
        rnode_item_free(it);
        return st;
    }
    if (!n->scheduled) {
        n->scheduled = true;
        return sched_at(n->sched, tick_max(now, n->busy_until), SCHED_PRIO_UNIT, rnode_run_event, n, 0);
    }
    return PP5_OK;
}
