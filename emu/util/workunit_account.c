/* workunit_account.c: what a batch cost: ranks, units per rank, emulated
 * frames, core-seconds, parallel efficiency and the slowest unit.  Host
 * times are noisy and differ from run to run, so they go to stderr and to
 * the --accounting file, never into the outputs that must be identical. */
#include <inttypes.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"
#include "workunit_internal.h"

typedef struct {
    size_t units;
    double host_s;
} rank_account_t;

typedef struct {
    double wall_s, unit_s, unit_cpu_s, slowest_s;
    uint64_t frames;
    size_t slowest;                /* index, or SIZE_MAX */
    rank_account_t *per_rank;      /* ranks entries */
} account_t;

static pp5_status_t account_sum(const workunit_job_t *j, account_t *a)
{
    memset(a, 0, sizeof *a);
    a->slowest = SIZE_MAX;
    a->wall_s = workunit_now_s() - j->t_start;
    a->per_rank = calloc((size_t)j->out->ranks, sizeof *a->per_rank);
    if (!a->per_rank)
        return pp5_fail(PP5_E_NOMEM, "accounting: out of memory");
    for (size_t i = 0; i < j->out->count; i++) {
        const workunit_result_t *r = &j->out->results[i];
        if (!r->done || r->resumed)
            continue;
        a->unit_s += r->host_s;
        a->unit_cpu_s += r->cpu_s;
        a->frames += r->frames;
        if (r->rank >= 0 && r->rank < j->out->ranks) {
            a->per_rank[r->rank].units++;
            a->per_rank[r->rank].host_s += r->host_s;
        }
        if (a->slowest == SIZE_MAX || r->host_s > a->slowest_s) {
            a->slowest = i;
            a->slowest_s = r->host_s;
        }
    }
    return PP5_OK;
}

static double efficiency(const workunit_job_t *j, const account_t *a)
{
    double allocated = j->out->ranks * a->wall_s;
    return allocated > 0 ? a->unit_s / allocated : 0;
}

static void account_print(const workunit_job_t *j, const account_t *a)
{
    const workunit_run_t *o = j->out;
    fprintf(stderr, "%s: %zu units run, %zu resumed, %zu failed, on %d rank%s in %.2f s "
            "(%" PRIu64 " emulated frames)\n", j->opts->command, o->ran, o->resumed, o->failed,
            o->ranks, o->ranks == 1 ? "" : "s", a->wall_s, a->frames);
    fprintf(stderr, "  units per rank:");
    for (int r = 0; r < o->ranks && r < 16; r++)
        fprintf(stderr, " %zu", a->per_rank[r].units);
    fprintf(stderr, "%s\n", o->ranks > 16 ? " ..." : "");
    fprintf(stderr, "  unit time %.2f core-s of %.2f allocated (%d x %.2f s): parallel "
            "efficiency %.3f; the units' own CPU time %.2f s\n", a->unit_s, o->ranks * a->wall_s,
            o->ranks, a->wall_s, efficiency(j, a), a->unit_cpu_s);
    if (a->slowest != SIZE_MAX)
        fprintf(stderr, "  slowest unit %016" PRIx64 " (%s): %.3f s\n",
                j->list->units[a->slowest].id, j->list->units[a->slowest].key, a->slowest_s);
}

typedef struct {
    const workunit_job_t *j;
    const account_t *a;
} account_file_t;

static void json_units(json_writer_t *w, const workunit_job_t *j)
{
    char id[24];
    json_key(w, "units");
    json_begin_array(w);
    for (size_t i = 0; i < j->out->count; i++) {
        const workunit_result_t *r = &j->out->results[i];
        if (!r->done || r->resumed)
            continue;
        json_begin_object(w);
        json_kv_uint(w, "index", i);
        snprintf(id, sizeof id, "%016" PRIx64, j->list->units[i].id);
        json_kv_string(w, "id", id);
        json_kv_int(w, "rank", r->rank);
        json_kv_double(w, "host_s", r->host_s);
        json_kv_double(w, "cpu_s", r->cpu_s);
        json_kv_uint(w, "frames", r->frames);
        json_kv_bool(w, "failed", r->failed);
        json_end_object(w);
    }
    json_end_array(w);
}

static pp5_status_t account_body(FILE *f, void *arg)
{
    const account_file_t *af = arg;
    const workunit_job_t *j = af->j;
    const account_t *a = af->a;
    json_writer_t w;
    json_init(&w, f, true);
    json_begin_object(&w);
    json_kv_string(&w, "command", j->opts->command);
    json_kv_int(&w, "ranks", j->out->ranks);
    json_kv_double(&w, "wall_s", a->wall_s);
    json_kv_double(&w, "mpi_init_s", j->mpi_init_s);
    json_kv_uint(&w, "units_in_batch", j->out->count);
    json_kv_uint(&w, "units_in_shard", j->out->in_shard);
    json_kv_uint(&w, "units_run", j->out->ran);
    json_kv_uint(&w, "units_resumed", j->out->resumed);
    json_kv_uint(&w, "units_failed", j->out->failed);
    json_kv_uint(&w, "emulated_frames", a->frames);
    json_kv_double(&w, "unit_core_s", a->unit_s);
    json_kv_double(&w, "unit_cpu_s", a->unit_cpu_s);
    json_kv_double(&w, "allocated_core_s", j->out->ranks * a->wall_s);
    json_kv_double(&w, "parallel_efficiency", efficiency(j, a));
    json_key(&w, "per_rank");
    json_begin_array(&w);
    for (int r = 0; r < j->out->ranks; r++) {
        json_begin_object(&w);
        json_kv_int(&w, "rank", r);
        json_kv_uint(&w, "units", a->per_rank[r].units);
        json_kv_double(&w, "host_s", a->per_rank[r].host_s);
        json_end_object(&w);
    }
    json_end_array(&w);
    json_units(&w, j);
    json_end_object(&w);
    return ferror(f) ? pp5_fail(PP5_E_IO, "write failed") : PP5_OK;
}

pp5_status_t workunit_job_finish(workunit_job_t *j)
{
    if (!j->log)
        return PP5_OK;
    progress_end(&j->progress);
    pp5_status_t st = fclose(j->log) == 0 ? PP5_OK
                                          : pp5_fail(PP5_E_IO, "%s: write failed",
                                                     j->opts->log_path);
    j->log = NULL;
    account_t a;
    pp5_status_t ast = account_sum(j, &a);
    if (ast == PP5_OK) {
        if (!j->opts->quiet)
            account_print(j, &a);
        if (j->opts->accounting_path) {
            account_file_t af = {j, &a};
            ast = workunit_write_atomic(j->opts->accounting_path, account_body, &af);
            if (ast != PP5_OK)
                ast = pp5_fail(ast, "--accounting %s: %s", j->opts->accounting_path,
                               pp5_error_text());
        }
    }
    free(a.per_rank);
    return st == PP5_OK ? ast : st;
}
