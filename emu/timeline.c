/* timeline.c: records unit activity and writes Chrome trace-event JSON. */
#include "timeline.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "util/json.h"
#include "util/outfile.h"

void timeline_init(timeline_t *t)
{
    memset(t, 0, sizeof *t);
}

void timeline_free(timeline_t *t)
{
    free(t->track_names);
    free(t->ev);
    memset(t, 0, sizeof *t);
}

uint32_t timeline_track(timeline_t *t, const char *name)
{
    if (t->n_tracks == t->cap_tracks) {
        size_t cap = t->cap_tracks ? t->cap_tracks * 2 : 64;
        char (*names)[32] = realloc(t->track_names, cap * sizeof *names);
        if (!names) {
            return 0;
        }
        t->track_names = names;
        t->cap_tracks = cap;
    }
    snprintf(t->track_names[t->n_tracks], sizeof t->track_names[0], "%s", name);
    return (uint32_t)++t->n_tracks;
}

pp5_status_t timeline_span(timeline_t *t, uint32_t tid, const char *name, pp5_tick_t start,
                           pp5_tick_t end, uint64_t arg)
{
    if (t->n_ev == t->cap_ev) {
        size_t cap = t->cap_ev ? t->cap_ev * 2 : 1024;
        size_t bytes;
        if (!pp5_mul_size(cap, sizeof *t->ev, &bytes)) {
            return pp5_fail(PP5_E_NOMEM, "timeline too large");
        }
        timeline_event_t *ev = realloc(t->ev, bytes);
        if (!ev) {
            return pp5_fail(PP5_E_NOMEM, "out of memory recording the timeline (%zu events)", cap);
        }
        t->ev = ev;
        t->cap_ev = cap;
    }
    t->ev[t->n_ev++] = (timeline_event_t){ tid, name, start, end, arg };
    return PP5_OK;
}

pp5_status_t timeline_write(const timeline_t *t, const char *path)
{
    outfile_t o;     /* a temporary, renamed over `path` once complete */
    if (outfile_open(&o, path, false) != PP5_OK) {
        return pp5_fail(PP5_E_IO, "cannot write timeline %s: %s", path, pp5_error_text());
    }
    FILE *f = o.f;
    json_writer_t j;
    json_init(&j, f, false);
    json_begin_object(&j);
    json_kv_string(&j, "displayTimeUnit", "ns");
    json_key(&j, "otherData");
    json_begin_object(&j);
    json_kv_string(&j, "time_base", "emulated time; ts/dur in microseconds");
    json_end_object(&j);
    json_key(&j, "traceEvents");
    json_begin_array(&j);
    json_begin_object(&j);
    json_kv_string(&j, "name", "process_name");
    json_kv_string(&j, "ph", "M");
    json_kv_int(&j, "pid", 1);
    json_key(&j, "args");
    json_begin_object(&j);
    json_kv_string(&j, "name", "Pixel-Planes 5 (pp5 emulator)");
    json_end_object(&j);
    json_end_object(&j);
    for (size_t i = 0; i < t->n_tracks; i++) {
        json_begin_object(&j);
        json_kv_string(&j, "name", "thread_name");
        json_kv_string(&j, "ph", "M");
        json_kv_int(&j, "pid", 1);
        json_kv_uint(&j, "tid", i + 1);
        json_key(&j, "args");
        json_begin_object(&j);
        json_kv_string(&j, "name", t->track_names[i]);
        json_end_object(&j);
        json_end_object(&j);
        json_begin_object(&j);
        json_kv_string(&j, "name", "thread_sort_index");
        json_kv_string(&j, "ph", "M");
        json_kv_int(&j, "pid", 1);
        json_kv_uint(&j, "tid", i + 1);
        json_key(&j, "args");
        json_begin_object(&j);
        json_kv_uint(&j, "sort_index", i + 1);
        json_end_object(&j);
        json_end_object(&j);
    }
    for (size_t i = 0; i < t->n_ev; i++) {
        const timeline_event_t *e = &t->ev[i];
        json_begin_object(&j);
        json_kv_string(&j, "name", e->name);
        json_kv_string(&j, "ph", e->end > e->start ? "X" : "i");
        json_kv_int(&j, "pid", 1);
        json_kv_uint(&j, "tid", e->tid);
        json_kv_double(&j, "ts", (double)e->start / 1e6);
        if (e->end > e->start) {
            json_kv_double(&j, "dur", (double)(e->end - e->start) / 1e6);
        } else {
            json_kv_string(&j, "s", "t");
        }
        if (e->arg != UINT64_MAX) {
            json_key(&j, "args");
            json_begin_object(&j);
            json_kv_uint(&j, "bytes", e->arg);
            json_end_object(&j);
        }
        json_end_object(&j);
    }
    json_end_array(&j);
    json_end_object(&j);
    fputc('\n', f);
    if (outfile_commit(&o) != PP5_OK) {
        return pp5_fail(PP5_E_IO, "timeline: %s", pp5_error_text());
    }
    return PP5_OK;
}
