/* bench_ring.c: `pp5 bench ring`: ring + scheduler events per host second, and the test-pattern frame cost. */
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "firmware/host/testpattern_session.h"
#include "machine.h"
#include "registry.h"
#include "ring.h"
#include "stats.h"

static double wall_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

/* Closed loop: every delivery makes its receiver send a 64-byte message to
 * another node (deterministic pattern), until `limit` deliveries. */
typedef struct {
    ring_t *ring;
    uint64_t delivered, limit;
    unsigned n_nodes;
    uint8_t payload[64];
} bench_loop_t;

static pp5_status_t bench_deliver(void *ctx, const ring_msg_t *msg, pp5_tick_t now)
{
    bench_loop_t *b = ctx;
    b->delivered++;
    if (b->delivered + b->n_nodes > b->limit) {
        return PP5_OK;
    }
    unsigned src = msg->dst.index;
    unsigned dst = (src * 7 + 3 + (unsigned)(b->delivered % 5)) % b->n_nodes;
    ring_msg_t m = *msg;
    m.src = msg->dst;
    m.dst = ring_addr(RING_NODE_GP, dst);
    m.payload = b->payload;
    m.payload_bytes = sizeof b->payload;
    return ring_send(b->ring, &m, src, dst, now);
}

static int bench_ring(const pp5_bench_opts_t *o)
{
    const unsigned n_nodes = 34;   /* 16 GPs + 16 renderers + host + FB */
    sched_t s;
    sched_init(&s);
    ring_t r;
    bench_loop_t b;
    memset(&b, 0, sizeof b);
    b.limit = o->quick ? 200000 : 4000000;
    b.n_nodes = n_nodes;
    ring_config_t cfg = { .channels = 8, .width_bits = 32, .n_nodes = n_nodes, .clock_hz = 20e6,
                          .hop_cycles = 1, .header_bytes = 8 };
    if (ring_init(&r, &cfg, &s, bench_deliver, &b) != PP5_OK) {
        printf("   ring_init failed: %s\n", pp5_error_text());
        return 1;
    }
    b.ring = &r;
    for (unsigned i = 0; i < n_nodes; i++) {
        ring_msg_t m = ring_msg_make(ring_addr(RING_NODE_GP, i),
                                     ring_addr(RING_NODE_GP, (i + 1) % n_nodes), RING_MSG_GP_USER,
                                     RING_CLASS_GP, NULL, b.payload, sizeof b.payload);
        ring_send(&r, &m, i, (i + 1) % n_nodes, 0);
    }
    double t0 = wall_s();
    sched_stop_t why;
    pp5_status_t st = sched_run_until(&s, PP5_TICK_MAX, &why);
    double dt = wall_s() - t0;
    if (st != PP5_OK) {
        printf("   run failed: %s\n", pp5_error_text());
    } else {
        printf("   ring messages:        %llu delivered (64-byte payloads, 34 nodes, 8 channels)\n",
               (unsigned long long)b.delivered);
        printf("   scheduler events:     %llu (arbitration + delivery per message)\n",
               (unsigned long long)s.events_run);
        printf("   ring messages/host s: %.3g\n", (double)b.delivered / dt);
        printf("   sched events/host s:  %.3g\n", (double)s.events_run / dt);
        printf("   emulated time:        %.6f s; host time %.3f s\n", ticks_to_s(s.now), dt);
    }
    ring_free(&r);
    sched_free(&s);

    /* Whole machine: one default test-pattern frame. */
    pp5_params_t p;
    pp5_params_default(&p);
    machine_t m;
    t0 = wall_s();
    st = machine_init(&m, &p);
    if (st == PP5_OK) {
        st = testpattern_session_load(&m, &why);
    }
    double t1 = wall_s();
    if (st == PP5_OK) {
        st = machine_run_frame(&m, &why);
    }
    double t2 = wall_s();
    if (st == PP5_OK) {
        printf("   test-pattern frame:   %.3f ms emulated in %.3f s host (%llu events; machine build+load %.3f s)\n",
               stats_frame_time_s(&m) * 1e3, t2 - t1, (unsigned long long)m.sched.events_run, t1 - t0);
    } else {
        printf("   test-pattern failed: %s\n", pp5_error_text());
    }
    machine_free(&m);
    return st == PP5_OK ? 0 : 1;
}

PP5_BENCH(ring, "ring network + scheduler: events per host second; one test-pattern frame", bench_ring)
