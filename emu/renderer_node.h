/* renderer_node.h: a renderer's ring port and controller around the PP array's renderer_t (renderer.h).
 *
 * Incoming RENDERER_* messages queue in an instruction FIFO (unbounded [U]:
 * facts §3.4, the controller design is unknown) and execute one after another
 * at the renderer clock (renderer.clock_hz).  Cost of each message, in
 * renderer cycles:
 *   every message        rport.msg_cycles (decode, [U])
 *   EXEC                 renderer_execute's total_cycles (compute and
 *                        backing-store transfers overlapped, see renderer.h)
 *   SET_REGION           nothing more (the QEE origin is a register)
 *   WRITE/READ_FIELD     bits x rport.cycles_per_bit  ([U], facts §3.5)
 *   WRITE/READ_BS        32 x rport.cycles_per_bit
 *   READ_BS_BOX          32 x rport.cycles_per_bit (the whole block is read out)
 *   SEND_PIXELS          24 x rport.cycles_per_bit (three 8-bit fields)
 * A reply (RENDERER_DATA, FB_PIXELS) is posted to the ring when its readout
 * is done; the renderer does not wait for the ring (the port buffers it,
 * [U]).  Busy time = sum of those costs; the renderer is idle when its FIFO is
 * empty.
 *
 * Host threads.  Each command is handled in two steps: a FUNCTIONAL step
 * (rnode_apply: changes the PP memories, computes the cycle count, builds the
 * reply) and a TIMING step (the scheduler event: charges the cycles, posts the
 * reply at the right emulated time).  The functional result of a command
 * depends only on the commands before it in the same FIFO, so with
 * sim.host_threads > 1 a pool of worker threads runs the functional steps of
 * different renderers in parallel as soon as commands arrive, while the
 * scheduler (one thread) consumes the results in event order.  Cycle counts,
 * images and event order are therefore identical for any thread count
 * (tests/test_machine.c checks 1 vs 2 vs 4). */
#ifndef PP5_RENDERER_NODE_H
#define PP5_RENDERER_NODE_H

#include <pthread.h>
#include <stdbool.h>
#include <stdint.h>
#include "params.h"
#include "pp5_time.h"
#include "renderer.h"
#include "ring_msg.h"
#include "pp5_sched.h"

/* Sends msg at t; `owned` (NULL, or msg->payload from ring_payload_alloc)
 * passes the payload buffer on to the ring, which frees it. */
typedef pp5_status_t (*rnode_send_fn)(void *ctx, const ring_msg_t *msg, void *owned, pp5_tick_t t);
typedef void (*rnode_trace_fn)(void *ctx, unsigned index, const char *what, pp5_tick_t start,
                               pp5_tick_t end);

/* One queued command and, once `done`, the result of its functional step. */
typedef struct {
    ring_msg_t msg;
    void *payload_copy;
    bool done;
    pp5_status_t st;
    char err[400];
    const char *what;
    uint64_t cycles, exec_cycles, port_cycles;
    bool has_reply;
    ring_msg_t reply;            /* payload = reply_payload */
    void *reply_payload;
} rnode_item_t;

struct rpool;

typedef struct {
    unsigned index;
    renderer_t r;
    pp5_tick_t period_ps;
    uint32_t cycles_per_bit, msg_cycles;
    pp5_tick_t busy_until;
    pp5_tick_t busy_ps;
    pp5_tick_t setup_busy_ps;        /* part of busy_ps spent in machine_run_setup */
    uint64_t cycles;                 /* all renderer cycles charged (exec + port + decode) */
    uint64_t exec_cycles, port_cycles, messages;
    rnode_item_t **fifo;             /* items are individually allocated (stable for workers) */
    size_t head, count, cap;
    size_t claimed;                  /* items from the head whose functional step started */
    bool in_progress;                /* a functional step of this node is running */
    bool scheduled;
    uint32_t *scratch;               /* 3 x 16384 words for readouts (functional step only) */
    struct rpool *pool;              /* NULL: functional steps run inline */
    sched_t *sched;
    rnode_send_fn send;
    void *send_ctx;
    rnode_trace_fn trace;
    void *trace_ctx;
} renderer_node_t;

pp5_status_t rnode_init(renderer_node_t *n, unsigned index, const pp5_params_t *p, sched_t *sched,
                        rnode_send_fn send, void *send_ctx);
void rnode_free(renderer_node_t *n);
/* Queues a delivered command.  payload_buf: the ring's buffer of
 * msg->payload (ring_take_payload), kept instead of copied; NULL: copied. */
pp5_status_t rnode_deliver(renderer_node_t *n, const ring_msg_t *msg, void *payload_buf,
                           pp5_tick_t now);
bool rnode_busy(const renderer_node_t *n, pp5_tick_t now);

/* Worker pool for the functional steps of several renderer nodes. */
typedef struct rpool {
    pthread_mutex_t mu;
    pthread_cond_t work, done;
    renderer_node_t *nodes;
    unsigned n_nodes;
    pthread_t *threads;
    unsigned n_threads;
    bool stop;
} rpool_t;

/* Start n_threads workers (>= 1) over nodes[0..n_nodes); attaches the pool
 * to every node.  Call before any command is delivered. */
pp5_status_t rpool_start(rpool_t *p, renderer_node_t *nodes, unsigned n_nodes, unsigned n_threads);
/* Join the workers (waits for running steps) and detach the nodes. */
void rpool_stop(rpool_t *p);

#endif
