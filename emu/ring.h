/* ring.h: the Pixel-Planes 5 ring network: channels, hops, serialisation, contention, counters.
 *
 * Model.  The ring has `channels` independent channels, each `width_bits`
 * wide and clocked at `clock_hz` (parameters ring.*; default 8 x 32 bit x
 * 20 MHz = 640 MB/s, facts §5.2).  Nodes sit at positions 0..n_nodes-1 of a
 * 1-D unidirectional ring (facts §5.1 S10); a message from position s to d
 * passes hops = (d - s) mod n_nodes nodes.  A message of W = header_bytes +
 * payload_bytes bytes
 *   - waits in its sender's output FIFO: a node injects one message at a
 *     time, so messages between one pair of nodes arrive in send order;
 *   - when it reaches the head of that FIFO and its send time has come
 *     (arbitration happens in emulated-time order, as scheduler events),
 *     picks a channel: the lowest-numbered channel free at that instant, or
 *     if none is free the one that frees first (ties to the lowest index);
 *     deterministic;
 *   - starts at max(that instant, channel free);
 *   - occupies the channel for ceil(W / (width_bits/8)) ring cycles
 *     (serialisation), then arrives hops x hop_cycles ring cycles later.
 * Contention: a busy channel delays later messages (queueing in send order).
 *
 * Modelled: serialisation, per-hop latency, channel contention, one
 * transmitter per node, bytes/messages/busy time per channel and per traffic
 * class, conservation (bytes sent == bytes delivered per class).
 * Not modelled: the hardware arbitration / token protocol and the packet
 * format, which no source describes ([U], facts §5 and open question 1);
 * spatial reuse of one channel by messages on disjoint ring segments (a
 * message holds its whole channel: conservative); maximum message size.
 * Receivers accept on all channels at once unless ring_set_rx_ports limits a
 * node (used for the frame buffer, parameter fb.rx_ports [U]): then a
 * message starts only when it will find a free receive port on arrival,
 * holding its channel while it waits. */
#ifndef PP5_RING_H
#define PP5_RING_H

#include <stdint.h>
#include "pp5_time.h"
#include "ring_msg.h"
#include "ring_payload.h"
#include "pp5_sched.h"

/* Arbitration runs after deliveries and before unit work at one instant. */
#define RING_PRIO_ARBITRATE 15
#include "util/status.h"

typedef struct {
    pp5_tick_t free_at;
    pp5_tick_t busy_ps;                           /* time the channel carried data */
    uint64_t bytes;                               /* wire bytes incl. headers */
    uint64_t messages;
    uint64_t bytes_by_class[RING_CLASS_COUNT];
} ring_channel_t;

/* Called at arrival time; msg (and its payload) is valid during the call. */
typedef pp5_status_t (*ring_deliver_fn)(void *ctx, const ring_msg_t *msg, pp5_tick_t now);
/* Optional observer of each transfer (timeline): channel busy [start, end). */
typedef void (*ring_trace_fn)(void *ctx, unsigned channel, const ring_msg_t *msg,
                              pp5_tick_t start, pp5_tick_t end, pp5_tick_t arrival);

typedef struct {
    ring_msg_t msg;
    void *payload_copy;
    int in_use;
    unsigned src_pos, dst_pos;
    pp5_tick_t ready;               /* send time */
} ring_flight_t;

/* A node's output FIFO of flight slots. */
typedef struct {
    uint32_t *slot;
    size_t head, count, cap;
    pp5_tick_t tx_free_at;
    int pump_scheduled;
    /* Receive side: 0 = unlimited (a node accepts on every channel at
     * once); otherwise at most n_rx messages arrive at the same time. */
    unsigned n_rx;
    pp5_tick_t *rx_free_at;
} ring_port_t;

typedef struct {
    unsigned n_channels, n_nodes;
    pp5_tick_t period_ps;          /* one ring clock */
    pp5_tick_t hop_ps;             /* latency per hop */
    uint32_t width_bytes, header_bytes;
    ring_channel_t *ch;
    ring_port_t *port;             /* per node position */
    sched_t *sched;
    ring_deliver_fn deliver;
    void *deliver_ctx;
    ring_trace_fn trace;
    void *trace_ctx;
    void *arriving_payload;        /* during a deliver callback: the payload's buffer (ring_take_payload) */
    ring_flight_t *flights;        /* in-flight messages, index = event arg */
    uint32_t *free_slots;
    size_t n_flights, n_free;
    /* counters */
    uint64_t bytes_sent[RING_CLASS_COUNT], bytes_delivered[RING_CLASS_COUNT];
    uint64_t msgs_sent[RING_CLASS_COUNT], msgs_delivered[RING_CLASS_COUNT];
    pp5_tick_t busy_by_class[RING_CLASS_COUNT];   /* channel time, summed over channels */
    pp5_tick_t last_arrival;
} ring_t;

typedef struct {
    unsigned channels, width_bits, n_nodes;
    double clock_hz;
    uint32_t hop_cycles, header_bytes;
} ring_config_t;

pp5_status_t ring_init(ring_t *r, const ring_config_t *cfg, sched_t *sched,
                       ring_deliver_fn deliver, void *deliver_ctx);
void ring_free(ring_t *r);

/* Only inside the deliver callback: hands the delivered message's payload
 * buffer (the ring's own, msg->payload) to the caller, who must give it
 * back to ring_payload_free; NULL when there is none or it was taken.
 * Saves the receiver a copy. */
void *ring_take_payload(ring_t *r);

/* Wire bytes of a message (header + payload). */
uint64_t ring_wire_bytes(const ring_t *r, const ring_msg_t *msg);
/* Serialisation time of `wire_bytes` on one channel. */
pp5_tick_t ring_serialise_ps(const ring_t *r, uint64_t wire_bytes);
unsigned ring_hops(const ring_t *r, unsigned src_pos, unsigned dst_pos);

/* Send msg (payload copied) from src_pos to dst_pos at time t (>= now):
 * it joins the sender's FIFO; channel arbitration and arrival are
 * scheduler events on r->sched. */
pp5_status_t ring_send(ring_t *r, const ring_msg_t *msg, unsigned src_pos, unsigned dst_pos,
                       pp5_tick_t t);
/* ring_send for a payload the sender gives away: `owned` is msg->payload,
 * from ring_payload_alloc, and the ring keeps it instead of copying it
 * (freed with the flight, or here on failure).  Host speed only: nothing else differs. */
pp5_status_t ring_send_owned(ring_t *r, const ring_msg_t *msg, void *owned, unsigned src_pos,
                             unsigned dst_pos, pp5_tick_t t);

/* Limit node `pos` to `ports` simultaneous incoming messages (0 = unlimited). */
pp5_status_t ring_set_rx_ports(ring_t *r, unsigned pos, unsigned ports);

uint64_t ring_total_bytes_sent(const ring_t *r);
/* Messages still in flight. */
size_t ring_in_flight(const ring_t *r);

#endif
