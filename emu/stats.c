/* stats.c: collects, indexes, differences and writes the named statistics of a machine. */
#include "stats.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *stats_class_name(unsigned cls)
{
    static const char *names[RING_CLASS_COUNT] = { "host", "command", "data", "pixels", "gp" };
    return cls < RING_CLASS_COUNT ? names[cls] : "?";
}

/* ---- figures over the frames ---- */

static pp5_tick_t frames_ticks(const machine_t *m)
{
    pp5_tick_t sum = 0;
    for (unsigned i = 0; i < m->n_frames; i++)
        sum += m->frames[i].end_ps - m->frames[i].start_ps;
    return sum;
}

double stats_frames_total_s(const machine_t *m)
{
    return ticks_to_s(frames_ticks(m));
}

double stats_frame_time_s(const machine_t *m)
{
    return m->n_frames ? stats_frames_total_s(m) / m->n_frames : 0.0;
}

static pp5_tick_t frames_channel_busy(const machine_t *m, unsigned c)
{
    pp5_tick_t sum = 0;
    for (unsigned i = 0; i < m->n_frames; i++)
        sum += m->frames[i].ch_busy_ps[c];
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
    for (unsigned i = 0; i < m->n_frames; i++)
        busy += m->frames[i].busy_by_class[cls];
    return t ? (double)busy / ((double)t * m->ring.n_channels) : 0.0;
}

double stats_ring_utilization(const machine_t *m)
{
    pp5_tick_t t = frames_ticks(m);
    if (t == 0)
        return 0.0;
    double busy = 0;
    for (unsigned c = 0; c < m->ring.n_channels; c++)
        busy += (double)frames_channel_busy(m, c);
    return busy / ((double)t * m->ring.n_channels);
}

/* ---- the collection and its index ---- */

static uint32_t name_hash(const char *s)
{
    uint32_t h = 2166136261u;               /* FNV-1a */
    for (; *s; s++)
        h = (h ^ (uint8_t)*s) * 16777619u;
    return h;
}

static pp5_status_t reindex(stats_t *s)
{
    size_t cap = 64;
    while (cap < 2 * s->cap)
        cap *= 2;
    uint32_t *slot = calloc(cap, sizeof *slot);
    if (!slot)
        return pp5_fail(PP5_E_NOMEM, "out of memory indexing statistics");
    for (size_t i = 0; i < s->n; i++) {
        size_t k = name_hash(s->e[i].name) & (cap - 1);
        while (slot[k])
            k = (k + 1) & (cap - 1);
        slot[k] = (uint32_t)(i + 1);
    }
    free(s->slot);
    s->slot = slot;
    s->slot_cap = cap;
    return PP5_OK;
}

const stats_entry_t *stats_find(const stats_t *s, const char *name)
{
    if (!s->slot_cap)
        return NULL;
    for (size_t k = name_hash(name) & (s->slot_cap - 1); s->slot[k]; k = (k + 1) & (s->slot_cap - 1))
        if (strcmp(s->e[s->slot[k] - 1].name, name) == 0)
            return &s->e[s->slot[k] - 1];
    return NULL;
}

double stats_value(const stats_t *s, const char *name)
{
    const stats_entry_t *e = stats_find(s, name);
    return e ? e->value : 0.0;
}

double stats_valuef(const stats_t *s, const char *fmt, ...)
{
    char name[sizeof s->e[0].name];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(name, sizeof name, fmt, ap);
    va_end(ap);
    return stats_value(s, name);
}

static pp5_status_t push(stats_t *s, const stats_entry_t *entry)
{
    if (s->n == s->cap) {
        size_t cap = s->cap ? s->cap * 2 : 256;
        stats_entry_t *e = realloc(s->e, cap * sizeof *e);
        if (!e)
            return pp5_fail(PP5_E_NOMEM, "out of memory collecting statistics");
        s->e = e;
        s->cap = cap;
    }
    s->e[s->n++] = *entry;
    return PP5_OK;
}

/* Adds one entry; a no-op once an earlier add failed (*st != OK). */
static void add(stats_t *s, pp5_status_t *st, stats_kind_t kind, double v, const char *unit,
                const char *meaning, const char *fmt, ...) __attribute__((format(printf, 7, 8)));
static void add(stats_t *s, pp5_status_t *st, stats_kind_t kind, double v, const char *unit,
                const char *meaning, const char *fmt, ...)
{
    if (*st != PP5_OK)
        return;
    stats_entry_t e = {.value = v, .kind = kind, .unit = unit, .meaning = meaning};
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(e.name, sizeof e.name, fmt, ap);
    va_end(ap);
    *st = push(s, &e);
}

#define COUNTER(...) add(s, &st, STATS_COUNTER, __VA_ARGS__)
#define VALUE(...) add(s, &st, STATS_VALUE, __VA_ARGS__)
#define FORMULA(...) add(s, &st, STATS_FORMULA, __VA_ARGS__)

static pp5_status_t collect_sim(stats_t *s, const machine_t *m)
{
    pp5_status_t st = PP5_OK;
    FORMULA(stats_frame_time_s(m), "s", "mean frame time: sim.frames_total_s / sim.frames", "sim.frame_time_s");
    COUNTER(stats_frames_total_s(m), "s", "sum of the frame times (frame start to last unit activity)", "sim.frames_total_s");
    COUNTER((double)m->n_frames, "count", "frames run", "sim.frames");
    COUNTER((double)m->sched.events_run, "count", "scheduler events executed", "sim.events");
    COUNTER(ticks_to_s(m->setup_ps), "s", "time spent in setup (program loads, per-sequence builds)", "sim.setup_time_s");
    for (unsigned i = 0; i < m->n_frames; i++) {
        const machine_frame_t *f = &m->frames[i];
        VALUE(ticks_to_s(f->start_ps), "s", "frame start", "frame.%u.start_s", i);
        VALUE(ticks_to_s(f->end_ps - f->start_ps), "s", "frame time", "frame.%u.frame_time_s", i);
        VALUE((double)(f->end_ps - f->start_ps), "ps", "frame time", "frame.%u.frame_time_ps", i);
        for (unsigned k = 0; k < RING_CLASS_COUNT; k++)
            VALUE((double)f->bytes_by_class[k], "bytes", "wire bytes of this class sent in the frame",
                  "frame.%u.ring_bytes_by_class.%s", i, stats_class_name(k));
    }
    return st;
}

static pp5_status_t collect_gp(stats_t *s, const gp_t *g, double frames_s)
{
    pp5_status_t st = PP5_OK;
    unsigned i = g->index;
    double frames_busy = ticks_to_s(g->busy_ps - g->setup_busy_ps);
    FORMULA(frames_busy, "s", "busy time inside frames: busy_s - setup_busy_s", "gp.%u.frames_busy_s", i);
    FORMULA(frames_s - frames_busy, "s", "idle time inside frames: sim.frames_total_s - frames_busy_s", "gp.%u.frames_idle_s", i);
    COUNTER((double)g->busy_cycles, "i860 cycles", "cycles charged by firmware (ops + sends)", "gp.%u.busy_cycles", i);
    COUNTER(ticks_to_s(g->busy_ps), "s", "time running callbacks", "gp.%u.busy_s", i);
    COUNTER((double)g->setup_busy_cycles, "i860 cycles", "part of busy_cycles charged during setup", "gp.%u.setup_busy_cycles", i);
    COUNTER(ticks_to_s(g->setup_busy_ps), "s", "part of busy_s spent during setup", "gp.%u.setup_busy_s", i);
    COUNTER((double)g->msgs_sent, "count", "ring messages sent", "gp.%u.messages_sent", i);
    VALUE((double)g->mem_peak_bytes, "bytes", "peak local memory in use", "gp.%u.mem_peak_bytes", i);
    VALUE((double)gp_addr_top_peak(&g->addr), "bytes",
          "highest emulated address of any block (above mem_peak_bytes by alignment and fragmentation)",
          "gp.%u.mem_addr_peak_bytes", i);
    const fw_ops_t *o = &g->ops_total;
    const struct { const char *name; uint64_t v; } ops[] = {
        {"fadd", o->fadd}, {"fmul", o->fmul}, {"fdiv", o->fdiv}, {"fsqrt", o->fsqrt},
        {"loads", o->loads}, {"stores", o->stores}, {"int_ops", o->int_ops},
        {"branches", o->branches}, {"ext_bytes", o->ext_bytes}, {"load_use", o->load_use},
        {"dcache_hits", o->dcache_hits}, {"dcache_misses", o->dcache_misses},
        {"dcache_writebacks", o->dcache_writebacks},
    };
    for (size_t k = 0; k < sizeof ops / sizeof ops[0]; k++)
        COUNTER((double)ops[k].v, "count", "operations charged (fw_ops_t)", "gp.%u.ops.%s", i, ops[k].name);
    /* The data cache inside frames (setup excluded): line lookups. */
    const fw_ops_t *su = &g->setup_ops;
    COUNTER((double)(o->dcache_hits - su->dcache_hits), "count", "data-cache line lookups that hit, inside frames",
            "gp.%u.frames_dcache_hits", i);
    COUNTER((double)(o->dcache_misses - su->dcache_misses), "count", "data-cache line lookups that missed, inside frames",
            "gp.%u.frames_dcache_misses", i);
    COUNTER((double)(o->dcache_writebacks - su->dcache_writebacks), "count",
            "written lines evicted (written back), inside frames", "gp.%u.frames_dcache_writebacks", i);
    for (unsigned k = 0; k < g->n_stats; k++)
        add(s, &st, g->stats[k].kind == FW_STAT_COUNTER ? STATS_COUNTER : STATS_VALUE,
            (double)g->stats[k].value, g->stats[k].unit, g->stats[k].meaning, "gp.%u.prog.%s", i,
            g->stats[k].name);
    return st;
}

static pp5_status_t collect_renderer(stats_t *s, const renderer_node_t *r, unsigned i, double frames_s)
{
    pp5_status_t st = PP5_OK;
    double frames_busy = ticks_to_s(r->busy_ps - r->setup_busy_ps);
    FORMULA(frames_busy, "s", "busy time inside frames: busy_s - setup_busy_s", "renderer.%u.frames_busy_s", i);
    FORMULA(frames_s - frames_busy, "s", "idle time inside frames: sim.frames_total_s - frames_busy_s", "renderer.%u.frames_idle_s", i);
    const renderer_stats_t *p = &r->r.stats;
    COUNTER((double)r->cycles, "renderer cycles", "all cycles (exec + port + decode)", "renderer.%u.cycles", i);
    COUNTER((double)r->exec_cycles, "renderer cycles", "instruction-stream cycles (renderer_execute total)", "renderer.%u.exec_cycles", i);
    COUNTER((double)r->port_cycles, "renderer cycles", "ring-port readout/write cycles", "renderer.%u.port_cycles", i);
    COUNTER(ticks_to_s(r->busy_ps), "s", "busy time", "renderer.%u.busy_s", i);
    COUNTER(ticks_to_s(r->setup_busy_ps), "s", "part of busy_s spent during setup", "renderer.%u.setup_busy_s", i);
    COUNTER((double)r->messages, "count", "ring messages handled", "renderer.%u.messages", i);
    COUNTER((double)p->streams, "count", "instruction streams executed", "renderer.%u.pp.streams", i);
    COUNTER((double)p->instructions, "count", "PP instructions executed", "renderer.%u.pp.instructions", i);
    COUNTER((double)p->compute_cycles, "renderer cycles", "SIMD instruction cycles, stalls included", "renderer.%u.pp.compute_cycles", i);
    COUNTER((double)p->stall_cycles, "renderer cycles", "compute cycles spent waiting for backing-store transfers", "renderer.%u.pp.stall_cycles", i);
    COUNTER((double)p->bs_cycles, "renderer cycles", "backing-store channel busy cycles", "renderer.%u.pp.bs_cycles", i);
    COUNTER((double)p->bs_blocks, "count", "backing-store blocks moved", "renderer.%u.pp.bs_blocks", i);
    for (int c = 0; c < PP_CLASS_COUNT; c++) {
        COUNTER((double)p->class_cycles[c], "renderer cycles", "compute cycles of this instruction class",
                "renderer.%u.pp.cycles_by_class.%s", i, pp_class_name((pp_class_t)c));
        COUNTER((double)p->class_instructions[c], "count", "instructions of this class",
                "renderer.%u.pp.instructions_by_class.%s", i, pp_class_name((pp_class_t)c));
    }
    for (unsigned op = 0; op < PP_OP_LIMIT; op++) {
        const pp_op_info_t *info = pp_isa_info(op);
        if (!info || !p->op_instructions[op])
            continue;
        COUNTER((double)p->op_cycles[op], "renderer cycles", "compute cycles of this opcode",
                "renderer.%u.pp.cycles_by_opcode.%s", i, info->name);
        COUNTER((double)p->op_instructions[op], "count", "instructions of this opcode",
                "renderer.%u.pp.instructions_by_opcode.%s", i, info->name);
    }
    return st;
}

static pp5_status_t collect_ring(stats_t *s, const machine_t *m)
{
    pp5_status_t st = PP5_OK;
    const ring_t *rg = &m->ring;
    FORMULA(pp5_params_ring_channel_bytes_per_s(&m->params), "bytes/s",
            "ring.width_bits / 8 x ring.clock_hz", "ring.channel_bytes_per_s");
    FORMULA(pp5_params_ring_aggregate_bytes_per_s(&m->params), "bytes/s",
            "ring.channel_bytes_per_s x ring.channels", "ring.aggregate_bytes_per_s");
    COUNTER((double)ring_total_bytes_sent(rg), "bytes", "wire bytes sent, all classes", "ring.bytes_total");
    for (unsigned c = 0; c < rg->n_channels; c++) {
        const ring_channel_t *ch = &rg->ch[c];
        COUNTER((double)ch->bytes, "bytes", "wire bytes (headers included)", "ring.by_channel.%u.bytes", c);
        COUNTER((double)ch->messages, "count", "messages", "ring.by_channel.%u.messages", c);
        COUNTER(ticks_to_s(ch->busy_ps), "s", "time carrying data (whole run, load included)", "ring.by_channel.%u.busy_s", c);
        FORMULA(stats_ring_channel_utilization(m, c), "fraction", "busy time inside frames / frame time",
                "ring.by_channel.%u.utilization", c);
    }
    for (unsigned k = 0; k < RING_CLASS_COUNT; k++) {
        const char *cn = stats_class_name(k);
        COUNTER((double)rg->bytes_sent[k], "bytes", "wire bytes sent in this class", "ring.by_class.%s.bytes_sent", cn);
        COUNTER((double)rg->bytes_delivered[k], "bytes", "wire bytes delivered in this class", "ring.by_class.%s.bytes_delivered", cn);
        COUNTER((double)rg->msgs_sent[k], "count", "messages sent in this class", "ring.by_class.%s.messages", cn);
        COUNTER(ticks_to_s(rg->busy_by_class[k]), "s", "channel time used by this class (all channels)", "ring.by_class.%s.busy_s", cn);
        FORMULA(stats_ring_class_utilization(m, k), "fraction", "class busy time inside frames / (channels x frame time)",
                "ring.by_class.%s.utilization", cn);
    }
    FORMULA(stats_ring_utilization(m), "fraction", "channel busy time inside frames / (channels x frame time)",
            "ring.utilization");
    return st;
}

static pp5_status_t collect_fb_host(stats_t *s, const machine_t *m)
{
    pp5_status_t st = PP5_OK;
    COUNTER((double)m->fb.blocks_received, "count", "pixel blocks received", "fb.blocks");
    COUNTER((double)m->fb.pixels_received, "count", "pixels received", "fb.pixels");
    COUNTER((double)m->fb.swaps, "count", "buffer swaps", "fb.swaps");
    VALUE(ticks_to_s(m->fb.last_block_ps), "s", "arrival of the last pixel block", "fb.last_block_s");
    COUNTER((double)m->host.bytes_loaded, "bytes", "payload bytes loaded into GPs", "host.bytes_loaded");
    return st;
}

#undef COUNTER
#undef VALUE
#undef FORMULA

pp5_status_t stats_collect(stats_t *s, const machine_t *m)
{
    memset(s, 0, sizeof *s);
    pp5_status_t st = collect_sim(s, m);
    for (unsigned i = 0; i < m->n_gp && st == PP5_OK; i++)
        st = collect_gp(s, &m->gp[i], stats_frames_total_s(m));
    for (unsigned i = 0; i < m->n_rn && st == PP5_OK; i++)
        st = collect_renderer(s, &m->rn[i], i, stats_frames_total_s(m));
    if (st == PP5_OK)
        st = collect_ring(s, m);
    if (st == PP5_OK)
        st = collect_fb_host(s, m);
    if (st == PP5_OK)
        st = reindex(s);
    if (st != PP5_OK)
        stats_free(s);
    return st;
}

void stats_free(stats_t *s)
{
    free(s->e);
    free(s->slot);
    memset(s, 0, sizeof *s);
}

pp5_status_t stats_diff(stats_t *out, const stats_t *before, const stats_t *after)
{
    memset(out, 0, sizeof *out);
    pp5_status_t st = PP5_OK;
    for (size_t i = 0; i < after->n && st == PP5_OK; i++) {
        stats_entry_t e = after->e[i];
        if (e.kind == STATS_FORMULA)
            continue;
        if (e.kind == STATS_COUNTER)
            e.value -= stats_value(before, e.name);
        st = push(out, &e);
    }
    if (st == PP5_OK)
        st = reindex(out);
    if (st != PP5_OK)
        stats_free(out);
    return st;
}

/* ---- JSON: entries nested by the dots of their names ---- */

typedef struct {
    char key[64];
    int first_child, last_child, next;
    int entry;                /* leaf: index into the collection, else -1 */
} tree_node_t;

typedef struct {
    tree_node_t *node;
    int n, cap;
} tree_t;

static int tree_child(tree_t *t, int parent, const char *key, size_t len)
{
    for (int c = t->node[parent].first_child; c >= 0; c = t->node[c].next)
        if (strlen(t->node[c].key) == len && strncmp(t->node[c].key, key, len) == 0)
            return c;
    if (t->n == t->cap) {
        int cap = t->cap ? 2 * t->cap : 256;
        tree_node_t *nn = realloc(t->node, (size_t)cap * sizeof *nn);
        if (!nn)
            return -1;
        t->node = nn;
        t->cap = cap;
    }
    int c = t->n++;
    tree_node_t *nd = &t->node[c];
    snprintf(nd->key, sizeof nd->key, "%.*s", (int)len, key);
    nd->first_child = nd->last_child = nd->next = nd->entry = -1;
    if (t->node[parent].last_child >= 0)
        t->node[t->node[parent].last_child].next = c;
    else
        t->node[parent].first_child = c;
    t->node[parent].last_child = c;
    return c;
}

/* Children keyed "0", "1", ... in order are written as an array. */
static bool tree_is_array(const tree_t *t, int node)
{
    int k = 0;
    for (int c = t->node[node].first_child; c >= 0; c = t->node[c].next, k++) {
        char want[16];
        snprintf(want, sizeof want, "%d", k);
        if (strcmp(t->node[c].key, want) != 0)
            return false;
    }
    return k > 0;
}

static void write_number(json_writer_t *j, double v)
{
    if (v == floor(v) && fabs(v) < 9007199254740992.0)
        json_int(j, (int64_t)v);
    else
        json_double(j, v);
}

static void tree_write(const tree_t *t, int node, const stats_t *s, json_writer_t *j)
{
    const tree_node_t *nd = &t->node[node];
    if (nd->first_child < 0) {
        write_number(j, nd->entry >= 0 ? s->e[nd->entry].value : 0.0);
        return;
    }
    bool array = tree_is_array(t, node);
    if (array)
        json_begin_array(j);
    else
        json_begin_object(j);
    for (int c = nd->first_child; c >= 0; c = t->node[c].next) {
        if (!array)
            json_key(j, t->node[c].key);
        tree_write(t, c, s, j);
    }
    if (array)
        json_end_array(j);
    else
        json_end_object(j);
}

static const char *kind_name(stats_kind_t k)
{
    return k == STATS_COUNTER ? "counter" : k == STATS_VALUE ? "value" : "formula";
}

void stats_write_json(const stats_t *s, json_writer_t *j)
{
    tree_t t = {0};
    tree_node_t root = {.first_child = -1, .last_child = -1, .next = -1, .entry = -1};
    t.node = malloc(256 * sizeof *t.node);
    t.cap = t.node ? 256 : 0;
    if (t.node) {
        t.node[0] = root;
        t.n = 1;
    }
    for (size_t i = 0; i < s->n && t.node; i++) {
        int at = 0;
        for (const char *p = s->e[i].name; at >= 0;) {
            const char *dot = strchr(p, '.');
            size_t len = dot ? (size_t)(dot - p) : strlen(p);
            at = tree_child(&t, at, p, len);
            if (!dot || at < 0)
                break;
            p = dot + 1;
        }
        if (at >= 0)
            t.node[at].entry = (int)i;
    }
    json_key(j, "statistics");
    if (t.node) {
        tree_write(&t, 0, s, j);
    } else {
        json_begin_object(j);             /* out of memory: an empty tree, the flat list follows */
        json_end_object(j);
    }
    free(t.node);
    json_key(j, "descriptions");
    json_begin_object(j);
    for (size_t i = 0; i < s->n; i++) {
        char text[512];
        snprintf(text, sizeof text, "%s; %s; %s", s->e[i].unit ? s->e[i].unit : "",
                 kind_name(s->e[i].kind), s->e[i].meaning ? s->e[i].meaning : "");
        json_kv_string(j, s->e[i].name, text);
    }
    json_end_object(j);
}
