/* workunit_run.c: running a batch: the to-do list (shard, resume), one unit,
 * recording results as they arrive, the serial loop, and the accounting. */
#include <errno.h>
#include <inttypes.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "json.h"
#include "version.h"
#include "workunit_internal.h"

double workunit_now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The calling thread's CPU time: a unit's cost that other work on a shared
 * host does not inflate, as its wall time does. */
double workunit_thread_cpu_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* A text kept in a one-line record: newlines become spaces. */
static char *one_line(char *text, const char *fallback)
{
    if (!text)
        text = strdup(fallback);
    for (char *p = text; p && *p; p++)
        if (*p == '\n' || *p == '\r')
            *p = ' ';
    return text;
}

void workunit_run_one(workunit_job_t *j, size_t index, int rank, workunit_result_t *r)
{
    workunit_output_t out = {0};
    double t0 = workunit_now_s(), c0 = workunit_thread_cpu_s();
    pp5_fail(PP5_OK, "%s", "");
    pp5_status_t st = j->fn(j->ctx, index, &j->list->units[index], &out);
    workunit_result_clear(r);
    r->host_s = workunit_now_s() - t0;
    r->cpu_s = workunit_thread_cpu_s() - c0;
    r->done = true;
    r->failed = st != PP5_OK;
    r->frames = out.frames;
    r->rank = rank;
    r->error = one_line(r->failed ? strdup(pp5_error_text()[0] ? pp5_error_text()
                                                               : pp5_status_name(st))
                                  : NULL, "");
    r->row = one_line(out.row, "");
    r->json = one_line(out.json, "");
    if (!r->error || !r->row || !r->json) {
        /* Out of memory for the texts: keep a result all the same. */
        free(r->error);
        free(r->row);
        free(r->json);
        r->error = r->row = r->json = NULL;
        r->failed = true;
    }
}

pp5_status_t workunit_record(workunit_job_t *j, size_t index)
{
    workunit_result_t *r = &j->out->results[index];
    const workunit_t *u = &j->list->units[index];
    if (!r->error)
        return pp5_fail(PP5_E_NOMEM, "%s: out of memory for the result of unit %016" PRIx64,
                        j->opts->command, u->id);
    pp5_status_t st = workunit_log_append(j->log, index, u->id, r);
    if (st != PP5_OK)
        return pp5_fail(st, "%s: %s", j->opts->log_path, pp5_error_text());
    j->out->ran++;
    if (r->failed) {
        j->out->failed++;
        if (!j->opts->quiet)
                fprintf(stderr, "%s: unit %016" PRIx64 " (%s) failed: %s\n", j->opts->command,
                    u->id, u->key, r->error);
    }
    progress_step(&j->progress, u->key);
    if (j->kill_after > 0 && (long)++j->recorded >= j->kill_after) {
        /* Tests: stop the way a node failure or `kill -9` does, mid-batch. */
        fprintf(stderr, "%s: PP5_WORKUNIT_KILL_AFTER=%ld reached: killing this process\n",
                j->opts->command, j->kill_after);
        raise(SIGKILL);
    }
    return PP5_OK;
}

static void fill_header(const workunit_job_t *j, workunit_log_header_t *h)
{
    *h = (workunit_log_header_t){
        .command = (char *)j->opts->command, .version = (char *)pp5_version,
        .csv_header = (char *)j->opts->csv_header, .plan_hash = j->out->plan_hash,
        .shard_k = j->opts->shard_n > 1 ? j->opts->shard_k : 0,
        .shard_n = j->opts->shard_n > 1 ? j->opts->shard_n : 1, .count = j->list->count};
}

/* --resume: the log's finished units count as done (failed ones run again);
 * a torn tail is cut off so that new records follow the last good one. */
static pp5_status_t resume_log(workunit_job_t *j, const workunit_log_header_t *h)
{
    long valid = 0;
    pp5_status_t st = workunit_log_read(j->opts->log_path, h, j->list, NULL, NULL,
                                        &j->out->results, &valid);
    if (st != PP5_OK)
        return st;
    for (size_t i = 0; i < j->out->count; i++) {
        workunit_result_t *r = &j->out->results[i];
        if (r->done && r->failed)
            workunit_result_clear(r);
        j->out->resumed += r->done;
    }
    if (truncate(j->opts->log_path, valid) != 0)
        return pp5_fail(PP5_E_IO, "%s: cannot cut off its torn end: %s", j->opts->log_path,
                        strerror(errno));
    j->log = fopen(j->opts->log_path, "a");
    return j->log ? PP5_OK : pp5_fail(PP5_E_IO, "%s: cannot append", j->opts->log_path);
}

pp5_status_t workunit_job_prepare(workunit_job_t *j)
{
    workunit_log_header_t h;
    fill_header(j, &h);
    pp5_status_t st;
    if (j->opts->resume && access(j->opts->log_path, F_OK) == 0) {
        st = resume_log(j, &h);
    } else {
        j->log = fopen(j->opts->log_path, "w");
        st = j->log ? workunit_log_write_header(j->log, &h, j->list)
                    : pp5_fail(PP5_E_IO, "%s: cannot create", j->opts->log_path);
    }
    if (st != PP5_OK)
        return st;
    j->todo = malloc((j->list->count ? j->list->count : 1) * sizeof *j->todo);
    if (!j->todo)
        return pp5_fail(PP5_E_NOMEM, "%s: out of memory", j->opts->command);
    for (size_t i = 0; i < j->list->count; i++) {
        if (h.shard_n > 1 && j->list->units[i].id % h.shard_n != h.shard_k)
            continue;
        j->out->in_shard++;
        if (!j->out->results[i].done)
            j->todo[j->n_todo++] = i;
    }
    if (j->out->resumed)
        fprintf(stderr, "%s: resuming from %s: %zu of %zu units done, %zu to run\n",
                j->opts->command, j->opts->log_path, j->out->resumed, j->out->in_shard,
                j->n_todo);
    progress_begin(&j->progress, j->opts->command, (int)j->n_todo);
    return PP5_OK;
}

pp5_status_t workunit_run_serial(workunit_job_t *j)
{
    pp5_status_t st = PP5_OK;
    for (size_t k = 0; k < j->n_todo && st == PP5_OK; k++) {
        workunit_run_one(j, j->todo[k], 0, &j->out->results[j->todo[k]]);
        st = workunit_record(j, j->todo[k]);
    }
    return st;
}

pp5_status_t workunit_run(const workunit_list_t *l, const workunit_opts_t *o, workunit_fn fn,
                          void *ctx, workunit_run_t *out)
{
    memset(out, 0, sizeof *out);
    out->root = true;
    out->ranks = 1;
    out->count = l->count;
    out->plan_hash = workunit_plan_hash(o->command, o->plan, l);
    if (!(out->results = calloc(l->count ? l->count : 1, sizeof *out->results)))
        return pp5_fail(PP5_E_NOMEM, "%s: out of memory", o->command);
    const char *kill = getenv("PP5_WORKUNIT_KILL_AFTER");
    workunit_job_t j = {.list = l, .opts = o, .fn = fn, .ctx = ctx, .out = out,
                        .t_start = workunit_now_s(), .kill_after = kill ? atol(kill) : 0};
    pp5_status_t st;
    if (workunit_launched_by_mpi()) {
        st = workunit_run_mpi(&j);
    } else {
        st = workunit_job_prepare(&j);
        if (st == PP5_OK)
            st = workunit_run_serial(&j);
        pp5_status_t fst = workunit_job_finish(&j);
        st = st == PP5_OK ? fst : st;
    }
    free(j.todo);
    return st;
}
