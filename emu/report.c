/* report.c: writes the JSON run report. */
#include "report.h"

#include <stdio.h>
#include <string.h>
#include "stats.h"
#include "util/json.h"
#include "util/outfile.h"
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

static void write_meta(json_writer_t *j, const machine_t *m, const report_meta_t *meta)
{
    json_kv_string(j, "pp5_version", pp5_version);
    json_kv_string(j, "workload", meta->workload ? meta->workload : "");
    json_key(j, "command_line");
    json_begin_array(j);
    for (int i = 0; i < meta->argc; i++)
        json_string(j, meta->argv[i]);
    json_end_array(j);
    json_key(j, "inputs");
    json_begin_array(j);
    for (int i = 0; i < meta->n_inputs; i++) {
        char hex[20];
        snprintf(hex, sizeof hex, "%016llx", (unsigned long long)meta->inputs[i].fnv1a64);
        json_begin_object(j);
        json_kv_string(j, "name", meta->inputs[i].name);
        json_kv_string(j, "fnv1a64", hex);
        json_kv_uint(j, "bytes", meta->inputs[i].bytes);
        json_end_object(j);
    }
    json_end_array(j);
    /* What the run was, besides its figures: each frame's stop reason and
     * each GP's program. */
    json_key(j, "frame_stops");
    json_begin_array(j);
    for (unsigned i = 0; i < m->n_frames; i++)
        json_string(j, sched_stop_name(m->frames[i].stop));
    json_end_array(j);
    json_key(j, "gp_programs");
    json_begin_array(j);
    for (unsigned i = 0; i < m->n_gp; i++)
        json_string(j, m->gp[i].prog ? m->gp[i].prog->name : "");
    json_end_array(j);
}

pp5_status_t report_write(const machine_t *m, const report_meta_t *meta, const char *path)
{
    stats_t st;
    pp5_status_t rc = stats_collect(&st, m);
    if (rc != PP5_OK)
        return rc;
    outfile_t o;
    rc = outfile_open(&o, path, false);
    if (rc != PP5_OK) {
        stats_free(&st);
        return rc;
    }
    FILE *f = o.f;
    json_writer_t j;
    json_init(&j, f, true);
    json_begin_object(&j);
    write_meta(&j, m, meta);
    json_key(&j, "machine");
    pp5_params_write_json(&m->params, &j);
    stats_write_json(&st, &j);
    json_end_object(&j);
    fputc('\n', f);
    stats_free(&st);
    return outfile_commit(&o);
}
