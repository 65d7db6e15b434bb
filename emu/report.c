/* report.c: writes the JSON run report. */
#include "report.h"

#include <stdio.h>
#include <string.h>
#include "stats.h"
#include "util/json.h"
#include "util/version.h"

#define FNV_OFFSET 1469598103934665603ull
#define FNV_PRIME 1099511628211ull

uint64_t report_fnv1a64(const void *data, size_t n, uint64_t h)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++) {
        h = (h ^ p[i]) * FNV_PRIME;
    }
    return h;
}

pp5_status_t report_add_input_file(report_meta_t *meta, const char *path)
{
    if (meta->n_inputs >= REPORT_MAX_INPUTS) {
        return pp5_fail(PP5_E_RANGE, "too many report inputs");
    }
    FILE *f = fopen(path, "rb");
    if (!f) {
        return pp5_fail(PP5_E_IO, "cannot read %s to hash it", path);
    }
    uint64_t h = FNV_OFFSET, bytes = 0;
    unsigned char buf[65536];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, f)) > 0) {
        h = report_fnv1a64(buf, n, h);
        bytes += n;
    }
    int err = ferror(f);
    fclose(f);
    if (err) {
        return pp5_fail(PP5_E_IO, "error reading %s", path);
    }
    meta->inputs[meta->n_inputs++] = (report_input_t){ path, h, bytes };
    return PP5_OK;
}

static const char *stop_name(sched_stop_t s)
{
    return sched_stop_name(s);
}

pp5_status_t report_write(const machine_t *m, const report_meta_t *meta, const char *path)
{
    stats_t st;
    pp5_status_t rc = stats_collect(&st, m);
    if (rc != PP5_OK) {
        return rc;
    }
    FILE *f = fopen(path, "w");
    if (!f) {
        stats_free(&st);
        return pp5_fail(PP5_E_IO, "cannot write report %s", path);
    }
    json_writer_t j;
    json_init(&j, f, true);
    json_begin_object(&j);
    json_kv_string(&j, "pp5_version", pp5_version);
    json_kv_string(&j, "workload", meta->workload ? meta->workload : "");
    json_key(&j, "command_line");
    json_begin_array(&j);
    for (int i = 0; i < meta->argc; i++) {
        json_string(&j, meta->argv[i]);
    }
    json_end_array(&j);
    json_key(&j, "inputs");
    json_begin_array(&j);
    for (int i = 0; i < meta->n_inputs; i++) {
        char hex[20];
        snprintf(hex, sizeof hex, "%016llx", (unsigned long long)meta->inputs[i].fnv1a64);
        json_begin_object(&j);
        json_kv_string(&j, "name", meta->inputs[i].name);
        json_kv_string(&j, "fnv1a64", hex);
        json_kv_uint(&j, "bytes", meta->inputs[i].bytes);
        json_end_object(&j);
    }
    json_end_array(&j);

    /* frame_time_s: mean over frames; busy/idle below cover all frames. */
    double frame_s = stats_frames_total_s(m);
    json_kv_double(&j, "frame_time_s", stats_frame_time_s(m));
    json_kv_double(&j, "frames_total_s", frame_s);
    json_kv_double(&j, "setup_time_s", ticks_to_s(m->setup_ps));
    json_key(&j, "frames");
    json_begin_array(&j);
    for (unsigned i = 0; i < m->n_frames; i++) {
        json_begin_object(&j);
        json_kv_uint(&j, "index", i);
        json_kv_double(&j, "start_s", ticks_to_s(m->frames[i].start_ps));
        json_kv_double(&j, "frame_time_s", ticks_to_s(m->frames[i].end_ps - m->frames[i].start_ps));
        json_kv_uint(&j, "frame_time_ps", m->frames[i].end_ps - m->frames[i].start_ps);
        json_kv_string(&j, "stop", stop_name(m->frames[i].stop));
        json_key(&j, "ring_bytes_by_class");
        json_begin_object(&j);
        for (unsigned k = 0; k < RING_CLASS_COUNT; k++) {
            json_kv_uint(&j, stats_class_name(k), m->frames[i].bytes_by_class[k]);
        }
        json_end_object(&j);
        json_end_object(&j);
    }
    json_end_array(&j);

    json_key(&j, "gp");
    json_begin_array(&j);
    for (unsigned i = 0; i < m->n_gp; i++) {
        const gp_t *g = &m->gp[i];
        json_begin_object(&j);
        json_kv_uint(&j, "index", i);
        json_kv_string(&j, "program", g->prog ? g->prog->name : "");
        /* busy_s/idle_s/cycles cover the frames; setup_* the program load. */
        json_kv_double(&j, "busy_s", ticks_to_s(g->busy_ps - g->setup_busy_ps));
        json_kv_double(&j, "idle_s", frame_s - ticks_to_s(g->busy_ps - g->setup_busy_ps));
        json_kv_uint(&j, "cycles", g->busy_cycles - g->setup_busy_cycles);
        json_kv_double(&j, "setup_busy_s", ticks_to_s(g->setup_busy_ps));
        json_kv_uint(&j, "messages_sent", g->msgs_sent);
        json_kv_uint(&j, "mem_peak_bytes", g->mem_peak_bytes);
        json_key(&j, "ops");
        json_begin_object(&j);
        json_kv_uint(&j, "fadd", g->ops_total.fadd);
        json_kv_uint(&j, "fmul", g->ops_total.fmul);
        json_kv_uint(&j, "fdiv", g->ops_total.fdiv);
        json_kv_uint(&j, "fsqrt", g->ops_total.fsqrt);
        json_kv_uint(&j, "loads", g->ops_total.loads);
        json_kv_uint(&j, "stores", g->ops_total.stores);
        json_kv_uint(&j, "int_ops", g->ops_total.int_ops);
        json_kv_uint(&j, "branches", g->ops_total.branches);
        json_kv_uint(&j, "ext_bytes", g->ops_total.ext_bytes);
        json_end_object(&j);
        json_end_object(&j);
    }
    json_end_array(&j);

    json_key(&j, "renderers");
    json_begin_array(&j);
    for (unsigned i = 0; i < m->n_rn; i++) {
        const renderer_node_t *r = &m->rn[i];
        json_begin_object(&j);
        json_kv_uint(&j, "index", i);
        json_kv_double(&j, "busy_s", ticks_to_s(r->busy_ps - r->setup_busy_ps));
        json_kv_double(&j, "idle_s", frame_s - ticks_to_s(r->busy_ps - r->setup_busy_ps));
        json_kv_uint(&j, "cycles", r->cycles);
        json_kv_uint(&j, "exec_cycles", r->exec_cycles);
        json_kv_uint(&j, "port_cycles", r->port_cycles);
        json_kv_uint(&j, "compute_cycles", r->r.stats.compute_cycles);
        json_kv_uint(&j, "bs_cycles", r->r.stats.bs_cycles);
        json_kv_uint(&j, "instructions", r->r.stats.instructions);
        json_kv_uint(&j, "messages", r->messages);
        /* Cycles and instructions by PP opcode class and opcode (emu-pp). */
        json_key(&j, "pp");
        renderer_stats_write_json(&r->r.stats, &j);
        json_end_object(&j);
    }
    json_end_array(&j);

    const ring_t *rg = &m->ring;
    json_key(&j, "ring");
    json_begin_object(&j);
    json_kv_double(&j, "channel_bytes_per_s", pp5_params_ring_channel_bytes_per_s(&m->params));
    json_kv_double(&j, "aggregate_bytes_per_s", pp5_params_ring_aggregate_bytes_per_s(&m->params));
    json_key(&j, "bytes");
    json_begin_object(&j);
    json_kv_uint(&j, "total", ring_total_bytes_sent(rg));
    json_key(&j, "by_class");
    json_begin_object(&j);
    for (unsigned k = 0; k < RING_CLASS_COUNT; k++) {
        json_kv_uint(&j, stats_class_name(k), rg->bytes_sent[k]);
    }
    json_end_object(&j);
    json_key(&j, "delivered_by_class");
    json_begin_object(&j);
    for (unsigned k = 0; k < RING_CLASS_COUNT; k++) {
        json_kv_uint(&j, stats_class_name(k), rg->bytes_delivered[k]);
    }
    json_end_object(&j);
    json_key(&j, "by_channel");
    json_begin_array(&j);
    for (unsigned c = 0; c < rg->n_channels; c++) {
        json_uint(&j, rg->ch[c].bytes);
    }
    json_end_array(&j);
    json_end_object(&j);
    json_key(&j, "messages_by_class");
    json_begin_object(&j);
    for (unsigned k = 0; k < RING_CLASS_COUNT; k++) {
        json_kv_uint(&j, stats_class_name(k), rg->msgs_sent[k]);
    }
    json_end_object(&j);
    json_key(&j, "busy_s_by_class");
    json_begin_object(&j);
    for (unsigned k = 0; k < RING_CLASS_COUNT; k++) {
        json_kv_double(&j, stats_class_name(k), ticks_to_s(rg->busy_by_class[k]));
    }
    json_end_object(&j);
    json_key(&j, "busy_s_by_channel");
    json_begin_array(&j);
    for (unsigned c = 0; c < rg->n_channels; c++) {
        json_double(&j, ticks_to_s(rg->ch[c].busy_ticks));
    }
    json_end_array(&j);
    json_key(&j, "utilization");
    json_begin_object(&j);
    json_kv_double(&j, "aggregate", stats_ring_utilization(m));
    json_key(&j, "by_channel");
    json_begin_array(&j);
    for (unsigned c = 0; c < rg->n_channels; c++) {
        json_double(&j, stats_ring_channel_utilization(m, c));
    }
    json_end_array(&j);
    json_key(&j, "by_class");
    json_begin_object(&j);
    for (unsigned k = 0; k < RING_CLASS_COUNT; k++) {
        json_kv_double(&j, stats_class_name(k), stats_ring_class_utilization(m, k));
    }
    json_end_object(&j);
    json_end_object(&j);
    json_end_object(&j);

    json_key(&j, "fb");
    json_begin_object(&j);
    json_kv_uint(&j, "blocks", m->fb.blocks_received);
    json_kv_uint(&j, "pixels", m->fb.pixels_received);
    json_kv_uint(&j, "swaps", m->fb.swaps);
    json_kv_double(&j, "last_block_s", ticks_to_s(m->fb.last_block_ps));
    json_end_object(&j);

    json_key(&j, "machine");
    pp5_params_write_json(&m->params, &j);

    json_key(&j, "counters");
    json_begin_object(&j);
    for (size_t i = 0; i < st.n; i++) {
        json_kv_double(&j, st.e[i].name, st.e[i].value);
    }
    json_end_object(&j);
    json_end_object(&j);
    fputc('\n', f);
    stats_free(&st);
    if (fclose(f) != 0) {
        return pp5_fail(PP5_E_IO, "error writing report %s", path);
    }
    return PP5_OK;
}
