/* cmd_replay_batch.c: `pp5 replay --batch LIST`: a collection of replays as
 * work units (emu/util/workunit.h), run here, across MPI ranks or as shards,
 * with one summary row per replay in list order.
 *
 * LIST holds one replay per line, a trace and its replay options exactly as
 * `pp5 replay TRACE ...` takes them (the options given on the command line
 * apply to every line, and a line's own options win):
 *
 *   # trace                          options
 *   traces/saccades_10s_250hz.trace --predict kalman --latency-ms 40
 *   traces/saccades_10s_250hz.trace --predict none --cost machine:division=resident
 *
 * A unit's key is the canonical text of what the line chose (trace, frame
 * source, prediction, latencies, ...), not the line as written, so the same
 * replay spelt twice is caught.  Each rank reads every trace once and keeps
 * it for all the units that replay it; the machine frame source keeps its
 * loaded volume the same way (firmware/host/replay_machine.c).  The
 * machine's setup runs in each unit: the emulated machine carries state from
 * frame to frame (resident units, band balance), so a unit never inherits
 * another's. */
#include <getopt.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cliopt.h"
#include "emu/cli/cmd_replay.h"
#include "tracker/trace_file.h"
#include "workunit.h"

#define BATCH_MAX_TOKENS 64

typedef struct {
    char *trace;
    replay_params_t p;
    char cost_spec[256];
} batch_line_t;

typedef struct {
    char *path;
    trace_t trace;
} cached_trace_t;

typedef struct {
    batch_line_t *lines;
    size_t n_lines;
    cached_trace_t *traces;      /* this process's traces, read once each */
    size_t n_traces, cap_traces;
} batch_t;

/* Splits a line at blanks, with "..." for a token holding blanks; '#' outside
 * quotes starts a comment.  Writes into line. */
static int tokenize(char *line, char **tok, int max)
{
    int n = 0;
    char *p = line;
    while (*p) {
        while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n')
            p++;
        if (!*p || *p == '#')
            break;
        if (n == max)
            return -1;
        bool quoted = *p == '"';
        tok[n++] = quoted ? ++p : p;
        while (*p && (quoted ? *p != '"' : !strchr(" \t\r\n", *p)))
            p++;
        if (quoted && *p != '"')
            return -1;
        if (*p)
            *p++ = '\0';
    }
    return n;
}

/* What a line's options chose, as text: the unit's key. */
static void line_key(const batch_line_t *b, char *key, size_t cap)
{
    const replay_params_t *p = &b->p;
    snprintf(key, cap, "%s cost=%s predict=%s%s%s tracker_latency_ms=%.10g "
             "display_latency_ms=%.10g radius_deg=%.10g refresh_hz=%.10g gap_s=%.10g "
             "timing_only=%d max_frames=%zu", b->trace, b->cost_spec,
             predict_kind_name(p->predict.kind), p->predict.kind == PREDICT_LANDING ? ":" : "",
             p->predict.kind == PREDICT_LANDING ? predict_kind_name(p->predict.landing_fallback)
                                                : "",
             p->tracker_latency_s * 1e3, p->display_latency_s * 1e3, p->fullres_radius_deg,
             p->refresh_hz, p->gap_s, p->timing_only ? 1 : 0, p->max_frames);
}

/* One line of LIST into b: PP5_E_CONFIG naming LIST:N on a bad line. */
static pp5_status_t parse_line(const replay_cli_t *base, char *text, const char *list, long no,
                               batch_line_t *b, bool *empty)
{
    char *tok[BATCH_MAX_TOKENS + 1];
    int n = tokenize(text, tok + 1, BATCH_MAX_TOKENS);
    *empty = n == 0;
    if (n <= 0)
        return n == 0 ? PP5_OK : pp5_fail(PP5_E_CONFIG, "%s:%ld: unbalanced quote or more than "
                                          "%d words", list, no, BATCH_MAX_TOKENS);
    tok[0] = "replay";
    replay_cli_t o = *base;
    o.in_list = true;
    bool done;
    int rc;
    pp5_status_t st = replay_cli_parse(&o, n + 1, tok, &done, &rc);
    if (st == PP5_OK && done)
        st = pp5_fail(PP5_E_CONFIG, "--help or an unknown option");
    if (st == PP5_OK && optind != n)
        st = pp5_fail(PP5_E_CONFIG, "expected one TRACE, then options");
    if (st == PP5_OK && (o.batch != base->batch || o.out != base->out || o.report != base->report ||
                         o.csv || o.plot || o.frames_dir || o.live || o.sweep ||
                         o.resume != base->resume || o.shard_n != base->shard_n ||
                         o.accounting != base->accounting))
        st = pp5_fail(PP5_E_CONFIG, "a line sets a replay's inputs only (no --batch, --out, "
                      "--report, --csv, --plot, --frames-dir, --live, --sweep-latency, --resume, "
                      "--shard or --accounting)");
    if (st != PP5_OK)
        return pp5_fail(st, "%s:%ld: %s", list, no, pp5_error_text());
    b->trace = strdup(tok[optind]);
    b->p = o.p;
    snprintf(b->cost_spec, sizeof b->cost_spec, "%s", o.cost_spec);
    return b->trace ? PP5_OK : pp5_fail(PP5_E_NOMEM, "out of memory");
}

static pp5_status_t read_list(const replay_cli_t *base, batch_t *bt, workunit_list_t *l)
{
    FILE *f = fopen(base->batch, "r");
    if (!f)
        return pp5_fail(PP5_E_IO, "--batch %s: cannot open", base->batch);
    char *buf = NULL;
    size_t cap = 0, cap_lines = 0;
    long no = 0;
    pp5_status_t st = PP5_OK;
    while (st == PP5_OK && getline(&buf, &cap, f) > 0) {
        no++;
        bool empty;
        batch_line_t b = {0};
        st = parse_line(base, buf, base->batch, no, &b, &empty);
        if (st != PP5_OK || empty)
            continue;
        char key[2048];
        line_key(&b, key, sizeof key);
        st = pp5_grow((void **)&bt->lines, &cap_lines, bt->n_lines, sizeof *bt->lines, "lines");
        if (st == PP5_OK)
            bt->lines[bt->n_lines++] = b;
        else
            free(b.trace);
        if (st == PP5_OK && (st = workunit_list_add(l, key)) != PP5_OK)
            st = pp5_fail(st, "%s:%ld: %s", base->batch, no, pp5_error_text());
    }
    free(buf);
    fclose(f);
    if (st == PP5_OK && bt->n_lines == 0)
        st = pp5_fail(PP5_E_CONFIG, "--batch %s: no replays in it", base->batch);
    return st;
}

/* The trace at path, read on first use by this process. */
static pp5_status_t batch_trace(batch_t *bt, const char *path, const trace_t **t)
{
    for (size_t i = 0; i < bt->n_traces; i++)
        if (strcmp(bt->traces[i].path, path) == 0) {
            *t = &bt->traces[i].trace;
            return PP5_OK;
        }
    pp5_status_t st = pp5_grow((void **)&bt->traces, &bt->cap_traces, bt->n_traces,
                               sizeof *bt->traces, "traces");
    cached_trace_t *c = st == PP5_OK ? &bt->traces[bt->n_traces] : NULL;
    if (c && (st = trace_read_file(path, &c->trace)) == PP5_OK) {
        if (!(c->path = strdup(path))) {
            trace_free(&c->trace);
            return pp5_fail(PP5_E_NOMEM, "out of memory");
        }
        bt->n_traces++;
        *t = &c->trace;
    }
    return st;
}

/* One replay of line b: its summary. */
static pp5_status_t batch_replay(batch_t *bt, const batch_line_t *b, replay_summary_t *s)
{
    char name[256];
    snprintf(name, sizeof name, "%s", b->cost_spec);
    char *colon = strchr(name, ':');
    const char *options = colon ? colon + 1 : "";
    if (colon)
        *colon = '\0';
    const replay_cost_source_t *cs = replay_find_cost_source(name);
    if (!cs)
        return pp5_fail(PP5_E_CONFIG, "--cost: no frame-cost source '%s' in this build", name);
    const trace_t *t = NULL;
    pp5_status_t st = batch_trace(bt, b->trace, &t);
    void *ctx = NULL;
    if (st == PP5_OK)
        st = cs->open(options, &b->p.display, &ctx);
    if (st != PP5_OK)
        return st;
    replay_params_t p = b->p;
    p.timing_only = true;        /* a batch keeps no frame images */
    replay_result_t r;
    st = replay_run(t, &p, cs->cost, ctx, NULL, NULL, &r);
    if (st == PP5_OK) {
        *s = r.summary;
        replay_result_free(&r);
    }
    if (cs->close)
        cs->close(ctx);
    return st;
}

#define BATCH_CSV_HEADER                                                                       \
    "unit,trace,cost,predict,tracker_latency_ms,display_latency_ms,frames,frames_with_error,"  \
    "frames_after_gap,trace_s,valid_display_s,inside_fraction,mean_error_deg,p95_error_deg,"   \
    "max_error_deg,frames_per_s,mean_frame_ms,mean_latency_ms,rays,ring_bytes,error"

/* A CSV field in double quotes (inner quotes doubled). */
static void csv_quoted(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; s++) {
        if (*s == '"')
            fputc('"', f);
        fputc(*s, f);
    }
    fputc('"', f);
}

static void batch_row(FILE *f, const workunit_t *u, const batch_line_t *b, pp5_status_t st,
                      const replay_summary_t *s)
{
    csv_quoted(f, u->key);
    fputc(',', f);
    csv_quoted(f, b->trace);
    fputc(',', f);
    csv_quoted(f, b->cost_spec);
    fprintf(f, ",%s,%.10g,%.10g,", predict_kind_name(b->p.predict.kind),
            b->p.tracker_latency_s * 1e3, b->p.display_latency_s * 1e3);
    if (st != PP5_OK) {
        fputs(",,,,,,,,,,,,,,", f);
        csv_quoted(f, pp5_error_text());
        return;
    }
    fprintf(f, "%zu,%zu,%zu,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%" PRIu64 ",%" PRIu64
               ",", s->frames, s->frames_with_error, s->frames_after_gap, s->trace_s,
            s->valid_display_s, s->inside_fraction, s->mean_error_deg, s->p95_error_deg,
            s->max_error_deg, s->frames_per_s, s->mean_frame_s * 1e3, s->mean_latency_s * 1e3,
            s->rays, s->ring_bytes);
}

static void batch_json(FILE *f, const batch_line_t *b, pp5_status_t st, const replay_summary_t *s)
{
    json_writer_t j;
    json_init(&j, f, false);
    json_begin_object(&j);
    json_kv_string(&j, "trace", b->trace);
    json_kv_string(&j, "frame_cost", b->cost_spec);
    json_kv_string(&j, "predict", predict_kind_name(b->p.predict.kind));
    json_kv_double(&j, "tracker_latency_ms", b->p.tracker_latency_s * 1e3);
    json_kv_double(&j, "display_latency_ms", b->p.display_latency_s * 1e3);
    json_kv_double(&j, "fullres_radius_deg", b->p.fullres_radius_deg);
    json_kv_double(&j, "refresh_hz", b->p.refresh_hz);
    json_kv_uint(&j, "max_frames", b->p.max_frames);
    if (st == PP5_OK)
        replay_summary_json(&j, s);
    json_end_object(&j);
}

/* The text an open_memstream stream made, once closed (NULL on failure). */
static char *memory_text(FILE *f, char **buf)
{
    if (!f)
        return NULL;
    if (fclose(f) != 0) {
        free(*buf);
        return NULL;
    }
    return *buf;
}

static pp5_status_t batch_unit(void *ctx, size_t index, const workunit_t *unit,
                               workunit_output_t *out)
{
    batch_t *bt = ctx;
    const batch_line_t *b = &bt->lines[index];
    replay_summary_t s;
    memset(&s, 0, sizeof s);
    pp5_status_t st = batch_replay(bt, b, &s);
    char *row = NULL, *json = NULL;
    size_t row_len = 0, json_len = 0;
    FILE *rf = open_memstream(&row, &row_len), *jf = open_memstream(&json, &json_len);
    if (rf)
        batch_row(rf, unit, b, st, &s);
    if (jf)
        batch_json(jf, b, st, &s);
    out->row = memory_text(rf, &row);
    out->json = memory_text(jf, &json);
    out->frames = st == PP5_OK ? s.frames : 0;
    return st;
}

/* Rank 0: one line per replay, in list order. */
static void batch_print(const workunit_list_t *l, const workunit_run_t *run)
{
    for (size_t i = 0; i < run->count; i++) {
        const workunit_result_t *r = &run->results[i];
        if (!r->done)
            continue;
        printf("  %s\n", l->units[i].key);
        if (r->failed)
            printf("      error: %s\n", r->error);
    }
}

static void batch_free(batch_t *bt)
{
    for (size_t i = 0; i < bt->n_lines; i++)
        free(bt->lines[i].trace);
    for (size_t i = 0; i < bt->n_traces; i++) {
        free(bt->traces[i].path);
        trace_free(&bt->traces[i].trace);
    }
    free(bt->lines);
    free(bt->traces);
}

static pp5_status_t batch_outputs(const replay_cli_t *o, const char *out,
                                  const workunit_list_t *l, const workunit_run_t *run,
                                  const char *log_path)
{
    pp5_status_t st = workunit_write_csv(out, BATCH_CSV_HEADER, run);
    if (st == PP5_OK && o->report)
        st = workunit_write_json(o->report, "replay-batch", l, run);
    if (st != PP5_OK)
        return st;
    batch_print(l, run);
    printf("wrote %s%s%s: %zu replays\n", out, o->report ? " and " : "",
           o->report ? o->report : "", run->count);
    if (run->failed)
        printf("%zu of %zu replays failed (see their rows); the unit log %s stays: --resume "
               "runs them again\n", run->failed, run->count, log_path);
    else
        remove(log_path);
    return PP5_OK;
}

int replay_batch_main(const replay_cli_t *o)
{
    const char *out = o->out ? o->out : "batch.csv";
    char log_path[1100];
    bool shard = o->shard_n > 1;
    snprintf(log_path, sizeof log_path, shard ? "%s" : "%s.units", out);
    batch_t bt = {0};
    workunit_list_t l;
    workunit_list_init(&l);
    workunit_run_t run = {0};
    pp5_status_t st = read_list(o, &bt, &l);
    workunit_opts_t wo = {.command = "replay-batch", .plan = "replay batch 1",
                          .csv_header = BATCH_CSV_HEADER, .log_path = log_path,
                          .resume = o->resume, .shard_k = o->shard_k, .shard_n = o->shard_n,
                          .accounting_path = o->accounting};
    if (st == PP5_OK) {
        if (workunit_launcher_rank() == 0)
            printf("replay batch %s: %zu replays\n", o->batch, l.count);
        st = workunit_run(&l, &wo, batch_unit, &bt, &run);
    }
    int rc = 0;
    if (st == PP5_OK && run.root && shard)
        printf("wrote the part %s: shard %u/%u, %zu of the %zu replays (combine the parts with "
               "pp5 merge)\n", log_path, o->shard_k, o->shard_n, run.in_shard, l.count);
    else if (st == PP5_OK && run.root)
        st = batch_outputs(o, out, &l, &run, log_path);
    if (st != PP5_OK && (run.root || !run.results))
        rc = cliopt_report("replay", st);
    else if (st != PP5_OK)
        rc = 1;
    else if (run.root && run.failed)
        rc = WORKUNIT_EXIT_UNITS_FAILED;
    workunit_run_free(&run);
    workunit_list_free(&l);
    batch_free(&bt);
    return rc;
}
