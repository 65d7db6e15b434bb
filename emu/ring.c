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
    r->tx_free_at = calloc(cfg->n_nodes, sizeof *r->tx_free_at);
    if (!r->ch || !r->tx_free_at) {
        ring_free(r);
        return pp5_fail(PP5_E_NOMEM, "ring: out of memory");
    }
    return PP5_OK;
}

void ring_free(ring_t *r)
{
    for (size_t i = 0; i < r->n_flights; i++) {
        free(r->flights[i].payload_copy);
    }
    free(r->flights);
    free(r->free_slots);
    free(r->ch);
    free(r->tx_free_at);
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
    pp5_status_t st = r->deliver ? r->deliver(r->deliver_ctx, &msg, now) : PP5_OK;
    free(payload);
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

pp5_status_t ring_send(ring_t *r, const ring_msg_t *msg, unsigned src_pos, unsigned dst_pos,
                       pp5_tick_t t, pp5_tick_t *arrival_out)
{
    PP5_ASSERT(src_pos < r->n_nodes && dst_pos < r->n_nodes, "ring position out of range");
    PP5_ASSERT(msg->cls < RING_CLASS_COUNT, "bad traffic class");
    /* Channel that frees up first; ties to the lowest index. */
    unsigned best = 0;
    for (unsigned c = 1; c < r->n_channels; c++) {
        if (r->ch[c].free_at < r->ch[best].free_at) {
            best = c;
        }
    }
    uint32_t slot = 0;
    pp5_status_t st = ring_take_slot(r, &slot);
    if (st != PP5_OK) {
        return st;
    }
    ring_flight_t *f = &r->flights[slot];
    f->msg = *msg;
    f->payload_copy = NULL;
    if (msg->payload_bytes > 0) {
        f->payload_copy = malloc(msg->payload_bytes);
        if (!f->payload_copy) {
            r->free_slots[r->n_free++] = slot;
            return pp5_fail(PP5_E_NOMEM, "ring: out of memory copying a %zu-byte payload",
                            msg->payload_bytes);
        }
        memcpy(f->payload_copy, msg->payload, msg->payload_bytes);
    }
    f->msg.payload = f->payload_copy;
    f->in_use = 1;

    ring_channel_t *ch = &r->ch[best];
    uint64_t wire = ring_wire_bytes(r, msg);
    pp5_tick_t ser = ring_serialise_ps(r, wire);
    pp5_tick_t start = tick_max(t, tick_max(ch->free_at, r->tx_free_at[src_pos]));
    pp5_tick_t end = start + ser;
    pp5_tick_t arrival = end + (pp5_tick_t)ring_hops(r, src_pos, dst_pos) * r->hop_ps;
    ch->free_at = end;
    ch->busy_ticks += ser;
    ch->bytes += wire;
    ch->messages++;
    ch->bytes_by_class[msg->cls] += wire;
    r->tx_free_at[src_pos] = end;
    r->bytes_sent[msg->cls] += wire;
    r->msgs_sent[msg->cls]++;
    if (r->trace) {
        r->trace(r->trace_ctx, best, &f->msg, start, end, arrival);
    }
    if (arrival_out) {
        *arrival_out = arrival;
    }
    return sched_at(r->sched, arrival, SCHED_PRIO_DELIVER, ring_arrive, r, slot);
}

uint64_t ring_total_bytes_sent(const ring_t *r)
{
    uint64_t sum = 0;
    for (unsigned c = 0; c < RING_CLASS_COUNT; c++) {
        sum += r->bytes_sent[c];
    }
    return sum;
}

pp5_tick_t ring_total_busy_ticks(const ring_t *r)
{
    pp5_tick_t sum = 0;
    for (unsigned c = 0; c < r->n_channels; c++) {
        sum += r->ch[c].busy_ticks;
    }
    return sum;
}

size_t ring_in_flight(const ring_t *r)
{
    return r->n_flights - r->n_free;
}
