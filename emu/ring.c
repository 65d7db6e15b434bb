/* ring.c: the Pixel-Planes 5 ring network (channels, hops, message serialisation, counters). */
#include "ring.h"

#include <stdlib.h>
#include <string.h>

pp5_status_t ring_init(ring_t *r, const ring_config_t *cfg, sched_t *sched,
                       ring_deliver_fn deliver, void *deliver_ctx)
{
    memset(r, 0, sizeof *r);
    if (cfg->channels == 0 || cfg->n_nodes == 0 || cfg->width_bits < 8 || cfg->width_bits % 8 != 0 ||
        !(cfg->clock_hz > 0)) {
        return pp5_fail(PP5_E_CONFIG, "ring: bad configuration (%u channels, %u bits, %u nodes)",
                        cfg->channels, cfg->width_bits, cfg->n_nodes);
    }
    r->n_channels = cfg->channels;
    r->n_nodes = cfg->n_nodes;
    r->period_ps = clock_period_ps(cfg->clock_hz);
    r->hop_ps = (pp5_tick_t)cfg->hop_cycles * r->period_ps;
    r->width_bytes = cfg->width_bits / 8;
    r->header_bytes = cfg->header_bytes;
    r->sched = sched;
    r->deliver = deliver;
    r->deliver_ctx = deliver_ctx;
    r->ch = calloc(cfg->channels, sizeof *r->ch);
    r->port = calloc(cfg->n_nodes, sizeof *r->port);
    if (!r->ch || !r->port) {
        ring_free(r);
        return pp5_fail(PP5_E_NOMEM, "ring: out of memory");
    }
    return PP5_OK;
}

void ring_free(ring_t *r)
{
    for (size_t i = 0; i < r->n_flights; i++) {
        ring_payload_free(r->flights[i].payload_copy);
    }
    free(r->flights);
    free(r->free_slots);
    free(r->ch);
    if (r->port) {
        for (unsigned i = 0; i < r->n_nodes; i++) {
            free(r->port[i].slot);
            free(r->port[i].rx_free_at);
        }
    }
    free(r->port);
    memset(r, 0, sizeof *r);
}

uint64_t ring_wire_bytes(const ring_t *r, const ring_msg_t *msg)
{
    return (uint64_t)r->header_bytes + msg->payload_bytes;
}

pp5_tick_t ring_serialise_ps(const ring_t *r, uint64_t wire_bytes)
{
    uint64_t words = (wire_bytes + r->width_bytes - 1) / r->width_bytes;
    return words * r->period_ps;
}

unsigned ring_hops(const ring_t *r, unsigned src_pos, unsigned dst_pos)
{
    return (dst_pos + r->n_nodes - src_pos) % r->n_nodes;
}

void *ring_take_payload(ring_t *r)
{
    void *p = r->arriving_payload;
    r->arriving_payload = NULL;
    return p;
}

static pp5_status_t ring_arrive(void *ctx, uint64_t slot, pp5_tick_t now)
{
    ring_t *r = ctx;
    PP5_ASSERT(r->flights[slot].in_use, "ring delivery of a free slot");
    /* Copy out: the receiver may send, which can grow (move) the pool; the
     * slot itself stays reserved until after the callback. */
    ring_msg_t msg = r->flights[slot].msg;
    void *payload = r->flights[slot].payload_copy;
    r->bytes_delivered[msg.cls] += ring_wire_bytes(r, &msg);
    r->msgs_delivered[msg.cls]++;
    if (now > r->last_arrival) {
        r->last_arrival = now;
    }
    r->arriving_payload = payload;
    pp5_status_t st = r->deliver ? r->deliver(r->deliver_ctx, &msg, now) : PP5_OK;
    ring_payload_free(r->arriving_payload);   /* unless the receiver took it */
    r->arriving_payload = NULL;
    r->flights[slot].payload_copy = NULL;
    r->flights[slot].in_use = 0;
    r->free_slots[r->n_free++] = (uint32_t)slot;
    return st;
}

static pp5_status_t ring_take_slot(ring_t *r, uint32_t *slot)
{
    if (r->n_free == 0) {
        size_t cap = r->n_flights ? r->n_flights * 2 : 64;
        ring_flight_t *fl = realloc(r->flights, cap * sizeof *fl);
        if (!fl) {
            return pp5_fail(PP5_E_NOMEM, "ring: out of memory for in-flight messages");
        }
        r->flights = fl;
        uint32_t *fs = realloc(r->free_slots, cap * sizeof *fs);
        if (!fs) {
            return pp5_fail(PP5_E_NOMEM, "ring: out of memory for in-flight messages");
        }
        r->free_slots = fs;
        for (size_t i = cap; i > r->n_flights; i--) {
            memset(&r->flights[i - 1], 0, sizeof r->flights[i - 1]);
            r->free_slots[r->n_free++] = (uint32_t)(i - 1);
        }
        r->n_flights = cap;
    }
    *slot = r->free_slots[--r->n_free];
    return PP5_OK;
}

static pp5_status_t ring_pump(void *ctx, uint64_t pos, pp5_tick_t now);

static pp5_status_t ring_schedule_pump(ring_t *r, unsigned pos)
{
    ring_port_t *p = &r->port[pos];
    if (p->pump_scheduled || p->count == 0) {
        return PP5_OK;
    }
    pp5_tick_t when = tick_max(r->flights[p->slot[p->head]].ready, p->tx_free_at);
    when = tick_max(when, r->sched->now);
    p->pump_scheduled = 1;
    return sched_at(r->sched, when, RING_PRIO_ARBITRATE, ring_pump, r, pos);
}

/* The head of node `pos`'s FIFO is ready and its transmitter free: pick a
 * channel, occupy it, schedule the arrival. */
static pp5_status_t ring_pump(void *ctx, uint64_t pos, pp5_tick_t now)
{
    ring_t *r = ctx;
    ring_port_t *p = &r->port[pos];
    p->pump_scheduled = 0;
    PP5_ASSERT(p->count > 0, "ring pump with an empty FIFO");
    uint32_t slot = p->slot[p->head];
    p->head = (p->head + 1) % p->cap;
    p->count--;
    ring_flight_t *f = &r->flights[slot];

    unsigned best = 0;
    int found_free = 0;
    for (unsigned c = 0; c < r->n_channels; c++) {
        if (r->ch[c].free_at <= now) {
            best = c;
            found_free = 1;
            break;
        }
    }
    if (!found_free) {
        for (unsigned c = 1; c < r->n_channels; c++) {
            if (r->ch[c].free_at < r->ch[best].free_at) {
                best = c;
            }
        }
    }
    ring_channel_t *ch = &r->ch[best];
    uint64_t wire = ring_wire_bytes(r, &f->msg);
    pp5_tick_t ser = ring_serialise_ps(r, wire);
    pp5_tick_t latency = (pp5_tick_t)ring_hops(r, f->src_pos, f->dst_pos) * r->hop_ps;
    pp5_tick_t start = tick_max(now, ch->free_at);
    ring_port_t *dp = &r->port[f->dst_pos];
    unsigned rx = 0;
    if (dp->n_rx > 0) {
        /* The receiver takes the message over [start + latency, arrival]:
         * wait for its earliest free port (ties: lowest index). */
        for (unsigned k = 1; k < dp->n_rx; k++) {
            if (dp->rx_free_at[k] < dp->rx_free_at[rx]) {
                rx = k;
            }
        }
        if (dp->rx_free_at[rx] > start + latency) {
            start = dp->rx_free_at[rx] - latency;
        }
    }
    pp5_tick_t end = start + ser;
    pp5_tick_t arrival = end + latency;
    if (dp->n_rx > 0) {
        dp->rx_free_at[rx] = arrival;
    }
    ch->free_at = end;
    ch->busy_ps += ser;
    ch->bytes += wire;
    ch->messages++;
    ch->bytes_by_class[f->msg.cls] += wire;
    r->busy_by_class[f->msg.cls] += ser;
    p->tx_free_at = end;
    if (r->trace) {
        r->trace(r->trace_ctx, best, &f->msg, start, end, arrival);
    }
    pp5_status_t st = sched_at(r->sched, arrival, SCHED_PRIO_DELIVER, ring_arrive, r, slot);
    if (st == PP5_OK) {
        st = ring_schedule_pump(r, (unsigned)pos);
    }
    return st;
}

pp5_status_t ring_send(ring_t *r, const ring_msg_t *msg, unsigned src_pos, unsigned dst_pos, pp5_tick_t t)
{
    void *copy = NULL;
    if (msg->payload_bytes > 0) {
        if (!(copy = ring_payload_alloc(msg->payload_bytes)))
            return pp5_fail(PP5_E_NOMEM, "ring: out of memory copying a %zu-byte payload",
                            msg->payload_bytes);
        memcpy(copy, msg->payload, msg->payload_bytes);
    }
    return ring_send_owned(r, msg, copy, src_pos, dst_pos, t);
}

pp5_status_t ring_send_owned(ring_t *r, const ring_msg_t *msg, void *owned, unsigned src_pos,
                             unsigned dst_pos, pp5_tick_t t)
{
    PP5_ASSERT(src_pos < r->n_nodes && dst_pos < r->n_nodes, "ring position out of range");
    PP5_ASSERT(msg->cls < RING_CLASS_COUNT, "bad traffic class");
    PP5_ASSERT(t >= r->sched->now, "ring send in the past");
    ring_port_t *p = &r->port[src_pos];
    if (p->count == p->cap) {
        size_t cap = p->cap ? p->cap * 2 : 16;
        uint32_t *q = malloc(cap * sizeof *q);
        if (!q) {
            ring_payload_free(owned);
            return pp5_fail(PP5_E_NOMEM, "ring: out of memory for a node FIFO");
        }
        for (size_t i = 0; i < p->count; i++) {
            q[i] = p->slot[(p->head + i) % p->cap];
        }
        free(p->slot);
        p->slot = q;
        p->head = 0;
        p->cap = cap;
    }
    if (p->count > 0) {
        /* Send times of one node never decrease (units send at their own
         * advancing clocks); keep FIFO order meaningful. */
        uint32_t last = p->slot[(p->head + p->count - 1) % p->cap];
        if (t < r->flights[last].ready) {
            t = r->flights[last].ready;
        }
    }
    uint32_t slot = 0;
    pp5_status_t st = ring_take_slot(r, &slot);
    if (st != PP5_OK) {
        ring_payload_free(owned);
        return st;
    }
    ring_flight_t *f = &r->flights[slot];
    f->msg = *msg;
    f->payload_copy = msg->payload_bytes > 0 ? owned : NULL;
    if (msg->payload_bytes == 0)
        ring_payload_free(owned);
    f->msg.payload = f->payload_copy;
    f->in_use = 1;
    f->src_pos = src_pos;
    f->dst_pos = dst_pos;
    f->ready = t;
    uint64_t wire = ring_wire_bytes(r, msg);
    r->bytes_sent[msg->cls] += wire;
    r->msgs_sent[msg->cls]++;
    p->slot[(p->head + p->count) % p->cap] = slot;
    p->count++;
    return ring_schedule_pump(r, src_pos);
}

pp5_status_t ring_set_rx_ports(ring_t *r, unsigned pos, unsigned ports)
{
    PP5_ASSERT(pos < r->n_nodes, "ring position out of range");
    ring_port_t *p = &r->port[pos];
    free(p->rx_free_at);
    p->rx_free_at = NULL;
    p->n_rx = 0;
    if (ports == 0) {
        return PP5_OK;
    }
    p->rx_free_at = calloc(ports, sizeof *p->rx_free_at);
    if (!p->rx_free_at) {
        return pp5_fail(PP5_E_NOMEM, "ring: out of memory for %u receive ports", ports);
    }
    p->n_rx = ports;
    return PP5_OK;
}

uint64_t ring_total_bytes_sent(const ring_t *r)
{
    uint64_t sum = 0;
    for (unsigned c = 0; c < RING_CLASS_COUNT; c++) {
        sum += r->bytes_sent[c];
    }
    return sum;
}

size_t ring_in_flight(const ring_t *r)
{
    return r->n_flights - r->n_free;
}
