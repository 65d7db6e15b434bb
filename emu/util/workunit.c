/* workunit.c: unit lists and their stable ids, the shard syntax, the
 * launcher probe, and the batch outputs (CSV and JSON in unit order). */
#include "workunit.h"
#include "outfile.h"

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "json.h"
#include "workunit_internal.h"

/* FNV-1a 64: short, well known, and the same on every host, which is all an
 * id needs (collisions are caught when the list is built). */
uint64_t workunit_hash(const char *text, uint64_t h)
{
    for (const unsigned char *p = (const unsigned char *)text; *p; p++) {
        h ^= *p;
        h *= 1099511628211ull;
    }
    return h;
}

void workunit_list_init(workunit_list_t *l)
{
    memset(l, 0, sizeof *l);
}

pp5_status_t workunit_list_add(workunit_list_t *l, const char *key)
{
    if (strchr(key, '\n'))
        return pp5_fail(PP5_E_CONFIG, "work unit '%s': a key is one line", key);
    uint64_t id = workunit_hash(key, WORKUNIT_HASH_START);
    for (size_t i = 0; i < l->count; i++)
        if (l->units[i].id == id)
            return pp5_fail(PP5_E_CONFIG, "work units %zu and %zu have the same id %016" PRIx64
                            " ('%s' and '%s'): each unit must be given once", i + 1,
                            l->count + 1, id, l->units[i].key, key);
    pp5_status_t st = pp5_grow((void **)&l->units, &l->capacity, l->count, sizeof *l->units,
                               "work units");
    if (st != PP5_OK)
        return st;
    char *copy = strdup(key);
    if (!copy)
        return pp5_fail(PP5_E_NOMEM, "work units: out of memory");
    l->units[l->count++] = (workunit_t){.id = id, .key = copy};
    return PP5_OK;
}

void workunit_list_free(workunit_list_t *l)
{
    for (size_t i = 0; i < l->count; i++)
        free(l->units[i].key);
    free(l->units);
    memset(l, 0, sizeof *l);
}

uint64_t workunit_plan_hash(const char *command, const char *plan, const workunit_list_t *l)
{
    uint64_t h = workunit_hash(command, WORKUNIT_HASH_START);
    h = workunit_hash("\n", workunit_hash(plan ? plan : "", workunit_hash("\n", h)));
    for (size_t i = 0; i < l->count; i++)
        h = workunit_hash("\n", workunit_hash(l->units[i].key, h));
    return h;
}

pp5_status_t workunit_parse_shard(const char *text, unsigned *k, unsigned *n)
{
    char *end;
    unsigned long a = strtoul(text, &end, 10);
    if (end == text || *end != '/' || text[0] == '-' || end[1] == '-')
        return pp5_fail(PP5_E_CONFIG, "--shard: expected K/N (e.g. 3/8), got '%s'", text);
    const char *second = end + 1;
    unsigned long b = strtoul(second, &end, 10);
    if (end == second || *end != '\0' || b < 1 || b > 1000000 || a >= b)
        return pp5_fail(PP5_E_CONFIG, "--shard %s: need 0 <= K < N <= 1000000", text);
    *k = (unsigned)a;
    *n = (unsigned)b;
    return PP5_OK;
}

/* The variables the common launchers set in each process they start:
 * Open MPI's mpirun, PMIx (Open MPI 5, srun --mpi=pmix), PMI-1/2 (MPICH's
 * hydra, srun --mpi=pmi2). */
static const char *const launcher_rank_vars[] = {"OMPI_COMM_WORLD_RANK", "PMIX_RANK",
                                                 "PMI_RANK"};

bool workunit_launched_by_mpi(void)
{
    const char *force = getenv("PP5_MPI");
    if (force && (strcmp(force, "0") == 0 || strcmp(force, "1") == 0))
        return force[0] == '1';
    for (size_t i = 0; i < sizeof launcher_rank_vars / sizeof launcher_rank_vars[0]; i++)
        if (getenv(launcher_rank_vars[i]))
            return true;
    return false;
}

int workunit_launcher_rank(void)
{
    if (!workunit_launched_by_mpi())
        return 0;
    for (size_t i = 0; i < sizeof launcher_rank_vars / sizeof launcher_rank_vars[0]; i++) {
        const char *v = getenv(launcher_rank_vars[i]);
        if (v)
            return atoi(v);
    }
    return 0;
}

/* The body writes into outfile's temporary beside path, which is renamed
 * into place only when every write succeeded (outfile.h): a reader never
 * sees half an output. */
pp5_status_t workunit_write_atomic(const char *path, pp5_status_t (*body)(FILE *f, void *arg),
                                   void *arg)
{
    outfile_t o;
    pp5_status_t st = outfile_open(&o, path, false);
    if (st != PP5_OK)
        return st;
    st = body(o.f, arg);
    if (st != PP5_OK) {
        outfile_discard(&o);
        return st;
    }
    return outfile_commit(&o);
}

typedef struct {
    const char *header, *command;
    const workunit_list_t *list;
    const workunit_run_t *run;
} outputs_t;

static pp5_status_t csv_body(FILE *f, void *arg)
{
    const outputs_t *o = arg;
    fprintf(f, "%s\n", o->header);
    for (size_t i = 0; i < o->run->count; i++)
        if (o->run->results[i].done)
            fprintf(f, "%s\n", o->run->results[i].row);
    return ferror(f) ? pp5_fail(PP5_E_IO, "CSV: write failed") : PP5_OK;
}

pp5_status_t workunit_write_csv(const char *path, const char *header, const workunit_run_t *r)
{
    outputs_t o = {.header = header, .run = r};
    return workunit_write_atomic(path, csv_body, &o);
}

static pp5_status_t json_body(FILE *f, void *arg)
{
    const outputs_t *o = arg;
    char hash[24];
    snprintf(hash, sizeof hash, "%016" PRIx64, o->run->plan_hash);
    fprintf(f, "{\"command\": \"%s\", \"plan_hash\": \"%s\", \"units\": [", o->command, hash);
    bool first = true;
    for (size_t i = 0; i < o->run->count; i++) {
        const workunit_result_t *r = &o->run->results[i];
        if (!r->done)
            continue;
        json_writer_t j;
        fputs(first ? "\n" : ",\n", f);
        first = false;
        json_init(&j, f, false);
        json_begin_object(&j);
        json_kv_uint(&j, "index", i);
        snprintf(hash, sizeof hash, "%016" PRIx64, o->list->units[i].id);
        json_kv_string(&j, "id", hash);
        json_kv_string(&j, "key", o->list->units[i].key);
        json_kv_string(&j, "status", r->failed ? "failed" : "ok");
        json_kv_string(&j, "error", r->error);
        /* The unit's own JSON, as it made it (one object). */
        json_key(&j, "result");
        fputs(r->json[0] ? r->json : "null", f);
        json_end_object(&j);
    }
    fputs("\n]}\n", f);
    return ferror(f) ? pp5_fail(PP5_E_IO, "JSON: write failed") : PP5_OK;
}

pp5_status_t workunit_write_json(const char *path, const char *command, const workunit_list_t *l,
                                 const workunit_run_t *r)
{
    outputs_t o = {.command = command, .list = l, .run = r};
    return workunit_write_atomic(path, json_body, &o);
}

void workunit_result_clear(workunit_result_t *r)
{
    free(r->error);
    free(r->row);
    free(r->json);
    memset(r, 0, sizeof *r);
}

void workunit_run_free(workunit_run_t *r)
{
    for (size_t i = 0; r->results && i < r->count; i++)
        workunit_result_clear(&r->results[i]);
    free(r->results);
    memset(r, 0, sizeof *r);
}
