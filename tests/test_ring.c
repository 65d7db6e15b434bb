/* test_ring.c: ring timing (serialisation + hops), contention, channel choice, byte counts. */
#include <string.h>
#include "harness.h"
#include "ring.h"

typedef struct {
    int n;
    pp5_tick_t when[16];
    uint32_t arg0[16];
} sink_t;

static pp5_status_t sink(void *ctx, const ring_msg_t *m, pp5_tick_t now)
{
    sink_t *k = ctx;
    if (k->n < 16) {
        k->when[k->n] = now;
        k->arg0[k->n] = m->args[0];
    }
    k->n++;
    return PP5_OK;
}

static ring_msg_t msg_of(uint32_t cls, size_t bytes, const void *payload, uint32_t tag)
{
    ring_msg_t m;
    memset(&m, 0, sizeof m);
    m.cls = cls;
    m.kind = RING_MSG_GP_USER;
    m.payload = payload;
    m.payload_bytes = bytes;
    m.args[0] = tag;
    return m;
}

/* 32-bit channels at 20 MHz: 4 bytes per 50,000 ps; hop = 3 cycles. */
static void setup(ring_t *r, sched_t *s, sink_t *k, unsigned channels)
{
    sched_init(s);
    memset(k, 0, sizeof *k);
    ring_config_t cfg = { .channels = channels, .width_bits = 32, .n_nodes = 10, .clock_hz = 20e6,
                          .hop_cycles = 3, .header_bytes = 8 };
    REQUIRE(ring_init(r, &cfg, s, sink, k) == PP5_OK);
}

TEST(ring_one_message_takes_bytes_over_bandwidth_plus_latency)
{
    ring_t r;
    sched_t s;
    sink_t k;
    setup(&r, &s, &k, 8);
    static uint8_t payload[4000];
    ring_msg_t m = msg_of(RING_CLASS_PIXELS, sizeof payload, payload, 1);
    REQUIRE(ring_send(&r, &m, 2, 7, 1000) == PP5_OK);
    /* (4000 + 8 header) bytes / (4 bytes per 50 ns) = 1002 cycles; 5 hops x 3 cycles. */
    pp5_tick_t want = 1000 + 1002ull * 50000 + 5ull * 3 * 50000;
    sched_stop_t why;
    sched_run_until(&s, PP5_TICK_MAX, &why);
    CHECK_EQ(k.n, 1);
    CHECK_EQ(k.when[0], want);
    CHECK_EQ(r.bytes_sent[RING_CLASS_PIXELS], 4008);
    CHECK_EQ(r.bytes_delivered[RING_CLASS_PIXELS], 4008);
    CHECK_EQ(r.ch[0].busy_ps, 1002ull * 50000);
    ring_free(&r);
    sched_free(&s);
}

TEST(ring_hops_wrap_around_the_ring)
{
    ring_t r;
    sched_t s;
    sink_t k;
    setup(&r, &s, &k, 1);
    CHECK_EQ(ring_hops(&r, 7, 2), 5);   /* 7->8->9->0->1->2 */
    CHECK_EQ(ring_hops(&r, 2, 7), 5);
    CHECK_EQ(ring_hops(&r, 9, 0), 1);
    CHECK_EQ(ring_hops(&r, 3, 3), 0);
    ring_free(&r);
    sched_free(&s);
}

TEST(ring_two_contending_senders_take_the_sum)
{
    ring_t r;
    sched_t s;
    sink_t k;
    setup(&r, &s, &k, 1);
    static uint8_t payload[992];   /* 1000 wire bytes = 250 cycles */
    ring_msg_t a = msg_of(RING_CLASS_COMMAND, sizeof payload, payload, 1);
    ring_msg_t b = msg_of(RING_CLASS_DATA, sizeof payload, payload, 2);
    REQUIRE(ring_send(&r, &a, 0, 1, 0) == PP5_OK);   /* 1 hop */
    REQUIRE(ring_send(&r, &b, 5, 6, 0) == PP5_OK);   /* 1 hop, waits for a */
    pp5_tick_t ser = 250ull * 50000, hop = 3ull * 50000;
    sched_stop_t why;
    sched_run_until(&s, PP5_TICK_MAX, &why);
    REQUIRE(k.n == 2);
    CHECK_EQ(k.arg0[0], 1);
    CHECK_EQ(k.when[0], ser + hop);
    CHECK_EQ(k.when[1], 2 * ser + hop);
    CHECK_EQ(r.bytes_sent[RING_CLASS_COMMAND], 1000);
    CHECK_EQ(r.bytes_sent[RING_CLASS_DATA], 1000);
    CHECK_EQ(r.bytes_delivered[RING_CLASS_COMMAND], 1000);
    CHECK_EQ(r.bytes_delivered[RING_CLASS_DATA], 1000);
    CHECK_EQ(r.bytes_sent[RING_CLASS_PIXELS], 0);
    CHECK_EQ(r.ch[0].busy_ps, 2 * ser);
    CHECK_EQ(r.busy_by_class[RING_CLASS_COMMAND], ser);
    CHECK_EQ(r.busy_by_class[RING_CLASS_DATA], ser);
    ring_free(&r);
    sched_free(&s);
}

TEST(ring_two_senders_on_two_channels_do_not_wait)
{
    ring_t r;
    sched_t s;
    sink_t k;
    setup(&r, &s, &k, 2);
    static uint8_t payload[992];
    ring_msg_t a = msg_of(RING_CLASS_COMMAND, sizeof payload, payload, 1);
    REQUIRE(ring_send(&r, &a, 0, 1, 0) == PP5_OK);
    REQUIRE(ring_send(&r, &a, 5, 6, 0) == PP5_OK);
    sched_stop_t why;
    sched_run_until(&s, PP5_TICK_MAX, &why);
    REQUIRE(k.n == 2);
    CHECK_EQ(k.when[0], k.when[1]);
    CHECK_EQ(k.when[0], 250ull * 50000 + 3ull * 50000);
    CHECK_EQ(r.ch[0].messages, 1);   /* lowest free channel first */
    CHECK_EQ(r.ch[1].messages, 1);
    ring_free(&r);
    sched_free(&s);
}

TEST(ring_one_sender_keeps_message_order)
{
    ring_t r;
    sched_t s;
    sink_t k;
    setup(&r, &s, &k, 8);
    static uint8_t big[40000];
    ring_msg_t a = msg_of(RING_CLASS_COMMAND, sizeof big, big, 1);
    ring_msg_t b = msg_of(RING_CLASS_COMMAND, 4, big, 2);   /* small, sent after */
    REQUIRE(ring_send(&r, &a, 0, 4, 0) == PP5_OK);
    REQUIRE(ring_send(&r, &b, 0, 4, 0) == PP5_OK);
    sched_stop_t why;
    sched_run_until(&s, PP5_TICK_MAX, &why);
    REQUIRE(k.n == 2);
    CHECK_EQ(k.arg0[0], 1);
    CHECK_EQ(k.arg0[1], 2);
    CHECK(k.when[1] > k.when[0]);
    ring_free(&r);
    sched_free(&s);
}

TEST(ring_payload_is_copied_and_bytes_are_conserved)
{
    ring_t r;
    sched_t s;
    sink_t k;
    setup(&r, &s, &k, 3);
    uint8_t buf[100];
    for (int i = 0; i < 40; i++) {
        memset(buf, i, sizeof buf);
        ring_msg_t m = msg_of((uint32_t)(i % RING_CLASS_COUNT), (size_t)(i % 7) * 10, buf, (uint32_t)i);
        REQUIRE(ring_send(&r, &m, (unsigned)(i % 10), (unsigned)((i * 3) % 10), (pp5_tick_t)i * 1000) == PP5_OK);
    }
    memset(buf, 0xff, sizeof buf);
    sched_stop_t why;
    sched_run_until(&s, PP5_TICK_MAX, &why);
    CHECK_EQ(k.n, 40);
    CHECK_EQ(ring_in_flight(&r), 0);
    uint64_t ch_sum = 0;
    for (unsigned c = 0; c < r.n_channels; c++) {
        ch_sum += r.ch[c].bytes;
    }
    for (unsigned c = 0; c < RING_CLASS_COUNT; c++) {
        CHECK_EQ(r.bytes_sent[c], r.bytes_delivered[c]);
        CHECK_EQ(r.msgs_sent[c], r.msgs_delivered[c]);
    }
    CHECK_EQ(ch_sum, ring_total_bytes_sent(&r));
    ring_free(&r);
    sched_free(&s);
}

TEST(ring_arbitration_follows_emulated_time_not_call_order)
{
    ring_t r;
    sched_t s;
    sink_t k;
    setup(&r, &s, &k, 1);
    static uint8_t payload[992];   /* 1000 wire bytes = 250 cycles */
    ring_msg_t late = msg_of(RING_CLASS_COMMAND, sizeof payload, payload, 1);
    ring_msg_t early = msg_of(RING_CLASS_COMMAND, sizeof payload, payload, 2);
    /* Node 0 posts a message for t = 1 ms first; node 3 then posts one for t = 0. */
    REQUIRE(ring_send(&r, &late, 0, 1, 1000000000ull) == PP5_OK);
    REQUIRE(ring_send(&r, &early, 3, 4, 0) == PP5_OK);
    sched_stop_t why;
    sched_run_until(&s, PP5_TICK_MAX, &why);
    REQUIRE(k.n == 2);
    pp5_tick_t ser = 250ull * 50000, hop = 3ull * 50000;
    CHECK_EQ(k.arg0[0], 2);
    CHECK_EQ(k.when[0], ser + hop);                  /* not delayed by the later one */
    CHECK_EQ(k.when[1], 1000000000ull + ser + hop);
    ring_free(&r);
    sched_free(&s);
}

TEST(ring_receiver_with_one_port_serialises_arrivals)
{
    ring_t r;
    sched_t s;
    sink_t k;
    setup(&r, &s, &k, 8);
    REQUIRE(ring_set_rx_ports(&r, 9, 1) == PP5_OK);
    static uint8_t payload[992];   /* 1000 wire bytes = 250 cycles */
    ring_msg_t a = msg_of(RING_CLASS_PIXELS, sizeof payload, payload, 1);
    ring_msg_t b = msg_of(RING_CLASS_PIXELS, sizeof payload, payload, 2);
    REQUIRE(ring_send(&r, &a, 8, 9, 0) == PP5_OK);   /* 1 hop */
    REQUIRE(ring_send(&r, &b, 6, 9, 0) == PP5_OK);   /* 3 hops, other channel */
    sched_stop_t why;
    sched_run_until(&s, PP5_TICK_MAX, &why);
    REQUIRE(k.n == 2);
    pp5_tick_t ser = 250ull * 50000, hop = 3ull * 50000;
    CHECK_EQ(k.when[0], ser + 1 * hop);
    /* b may only start arriving when a has been received: its arrival is a's
     * arrival plus its own serialisation. */
    CHECK_EQ(k.when[1], (ser + 1 * hop) + ser);
    CHECK_EQ(r.ch[0].messages, 1);
    CHECK_EQ(r.ch[1].messages, 1);
    ring_free(&r);
    sched_free(&s);
}
