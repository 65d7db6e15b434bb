/* stats.c: collects the named counters of a machine after a run. */
#include "stats.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *stats_class_name(unsigned cls)
{
    static const char *names[RING_CLASS_COUNT] = { "host", "command", "data", "pixels", "gp" };
    return cls < RING_CLASS_COUNT ? names[cls] : "?";
}

double stats_frames_total_s(const machine_t *m)
{
    pp5_tick_t sum = 0;
    for (unsigned i = 0; i < m->n_frames; i++) {
        sum += m->frames[i].end_ps - m->frames[i].start_ps;
    }
    return ticks_to_s(sum);
}

double stats_frame_time_s(const machine_t *m)
{
    return m->n_frames ? stats_frames_total_s(m) / m->n_frames : 0.0;
}

static pp5_tick_t frames_ticks(const machine_t *m)
{
    pp5_tick_t sum = 0;
    for (unsigned i = 0; i < m->n_frames; i++) {
        sum += m->frames[i].end_ps - m->frames[i].start_ps;
    }
    return sum;
}

static pp5_tick_t frames_channel_busy(const machine_t *m, unsigned c)
{
    pp5_tick_t sum = 0;
    for (unsigned i = 0; i < m->n_frames; i++) {
        sum += m->frames[i].ch_busy_ps[c];
    }
    return sum;
}

double stats_ring_channel_utilization(const machine_t *m, unsigned c)
{
    pp5_tick_t t = frames_ticks(m);
    return t ? (double)frames_channel_busy(m, c) / (double)t : 0.0;
}

double stats_ring_class_utilization(const machine_t *m, unsigned cls)
{
    pp5_tick_t t = frames_ticks(m), busy = 0;
    for (unsigned i = 0; i < m->n_frames; i++) {
        busy += m->frames[i].busy_by_class[cls];
    }
    return t ? (double)busy / ((double)t * m->ring.n_channels) : 0.0;
}

double stats_ring_utilization(const machine_t *m)
{
    pp5_tick_t t = frames_ticks(m);
    if (t == 0) {
        return 0.0;
    }
    double busy = 0;
    for (unsigned c = 0; c < m->ring.n_channels; c++) {
        busy += (double)frames_channel_busy(m, c);
    }
    return busy / ((double)t * m->ring.n_channels);
}

static pp5_status_t add(stats_t *s, double v, const char *unit, const char *meaning, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));
static pp5_status_t add(stats_t *s, double v, const char *unit, const char *meaning, const char *fmt, ...)
{
    if (s->n == s->cap) {
        size_t cap = s->cap ? s->cap * 2 : 128;
        stats_entry_t *e = realloc(s->e, cap * sizeof *e);
        if (!e) {
            return pp5_fail(PP5_E_NOMEM, "out of memory collecting statistics");
        }
        s->e = e;
        s->cap = cap;
    }
    stats_entry_t *e = &s->e[s->n++];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(e->name, sizeof e->name, fmt, ap);
    va_end(ap);
    e->value = v;
    e->unit = unit;
    e->meaning = meaning;
    return PP5_OK;
}

pp5_status_t stats_collect(stats_t *s, const machine_t *m)
{
    memset(s, 0, sizeof *s);
    pp5_status_t st = PP5_OK;
#define ADD(...) do { if (st == PP5_OK) st = add(s, __VA_ARGS__); } while (0)
    ADD(stats_frame_time_s(m), "s", "mean frame time (frame start to last unit activity)", "sim.frame_time_s");
    ADD(stats_frames_total_s(m), "s", "sum of all frame times", "sim.frames_total_s");
    ADD((double)m->n_frames, "count", "frames run", "sim.frames");
    ADD((double)m->sched.events_run, "count", "scheduler events executed", "sim.events");
    for (unsigned i = 0; i < m->n_gp; i++) {
        const gp_t *g = &m->gp[i];
        ADD((double)g->busy_cycles, "i860 cycles", "cycles charged by firmware (ops + sends)", "gp%u.busy_cycles", i);
        ADD(ticks_to_s(g->busy_ps), "s", "time running callbacks", "gp%u.busy_s", i);
        ADD((double)g->msgs_sent, "count", "ring messages sent", "gp%u.msgs_sent", i);
        ADD((double)g->mem_peak_bytes, "bytes", "peak local memory in use", "gp%u.mem_peak_bytes", i);
    }
    for (unsigned i = 0; i < m->n_rn; i++) {
        const renderer_node_t *r = &m->rn[i];
        ADD((double)r->cycles, "renderer cycles", "all cycles (exec + port + decode)", "renderer%u.cycles", i);
        ADD((double)r->exec_cycles, "renderer cycles", "instruction-stream cycles (renderer_execute total)", "renderer%u.exec_cycles", i);
        ADD((double)r->port_cycles, "renderer cycles", "ring-port readout/write cycles", "renderer%u.port_cycles", i);
        ADD((double)r->r.stats.instructions, "count", "PP instructions executed", "renderer%u.instructions", i);
        ADD(ticks_to_s(r->busy_ps), "s", "busy time", "renderer%u.busy_s", i);
    }
    for (unsigned c = 0; c < m->ring.n_channels; c++) {
        const ring_channel_t *ch = &m->ring.ch[c];
        ADD((double)ch->bytes, "bytes", "wire bytes (headers included)", "ring.ch%u.bytes", c);
        ADD((double)ch->messages, "count", "messages", "ring.ch%u.messages", c);
        ADD(ticks_to_s(ch->busy_ticks), "s", "time carrying data (whole run, load included)", "ring.ch%u.busy_s", c);
        ADD(stats_ring_channel_utilization(m, c), "fraction", "busy time inside frames / frame time",
            "ring.ch%u.utilization", c);
    }
    for (unsigned k = 0; k < RING_CLASS_COUNT; k++) {
        ADD((double)m->ring.bytes_sent[k], "bytes", "wire bytes sent in this class", "ring.class.%s.bytes_sent", stats_class_name(k));
        ADD((double)m->ring.bytes_delivered[k], "bytes", "wire bytes delivered in this class", "ring.class.%s.bytes_delivered", stats_class_name(k));
        ADD((double)m->ring.msgs_sent[k], "count", "messages sent in this class", "ring.class.%s.messages", stats_class_name(k));
        ADD(ticks_to_s(m->ring.busy_by_class[k]), "s", "channel time used by this class (all channels)", "ring.class.%s.busy_s", stats_class_name(k));
        ADD(stats_ring_class_utilization(m, k), "fraction", "class busy time inside frames / (channels x frame time)",
            "ring.class.%s.utilization", stats_class_name(k));
    }
    ADD(stats_ring_utilization(m), "fraction", "channel busy time inside frames / (channels x frame time)", "ring.utilization");
    ADD((double)m->fb.blocks_received, "count", "pixel blocks received", "fb.blocks");
    ADD((double)m->fb.pixels_received, "count", "pixels received", "fb.pixels");
    ADD((double)m->fb.swaps, "count", "buffer swaps", "fb.swaps");
    ADD((double)m->host.bytes_loaded, "bytes", "payload bytes loaded into GPs", "host.bytes_loaded");
#undef ADD
    return st;
}

void stats_free(stats_t *s)
{
    free(s->e);
    memset(s, 0, sizeof *s);
}

const stats_entry_t *stats_find(const stats_t *s, const char *name)
{
    for (size_t i = 0; i < s->n; i++) {
        if (strcmp(s->e[i].name, name) == 0) {
            return &s->e[i];
        }
    }
    return NULL;
}
