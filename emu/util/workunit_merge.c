/* workunit_merge.c: combining the unit logs of a batch's shards into the
 * results of the whole batch, refusing parts of different batches, units
 * that two parts disagree on, and missing units. */
#include <inttypes.h>
#include <stdlib.h>
#include <string.h>

#include "workunit_internal.h"

static bool same_result(const workunit_result_t *a, const workunit_result_t *b)
{
    return a->failed == b->failed && a->frames == b->frames && strcmp(a->row, b->row) == 0 &&
           strcmp(a->json, b->json) == 0 && strcmp(a->error, b->error) == 0;
}

/* Moves part's results into all: a unit done in two parts must agree (a
 * failure gives way to a success, from a retry). */
static pp5_status_t take_part(const char *path, const workunit_list_t *l,
                              workunit_result_t *part, workunit_result_t *all,
                              const char **owner, const char *const *paths)
{
    for (size_t i = 0; i < l->count; i++) {
        workunit_result_t *p = &part[i], *a = &all[i];
        if (!p->done)
            continue;
        if (a->done && !a->failed && !p->failed && !same_result(a, p))
            return pp5_fail(PP5_E_FORMAT, "unit %016" PRIx64 " (%s) has different results in "
                            "%s and %s", l->units[i].id, l->units[i].key, owner[i] ? owner[i]
                            : paths[0], path);
        if (a->done && !a->failed)
            continue;
        workunit_result_clear(a);
        *a = *p;
        memset(p, 0, sizeof *p);
        owner[i] = path;
    }
    return PP5_OK;
}

static pp5_status_t check_complete(const workunit_list_t *l, const workunit_result_t *all,
                                   unsigned shard_n)
{
    size_t missing = 0, first = 0;
    for (size_t i = 0; i < l->count; i++)
        if (!all[i].done && missing++ == 0)
            first = i;
    if (missing == 0)
        return PP5_OK;
    return pp5_fail(PP5_E_FORMAT, "%zu of the batch's %zu units are in none of the parts, "
                    "e.g. unit %016" PRIx64 " (%s), which shard %" PRIu64 "/%u runs: give every "
                    "shard's part, and finish unfinished shards with --resume", missing,
                    l->count, l->units[first].id, l->units[first].key,
                    l->units[first].id % (shard_n ? shard_n : 1), shard_n ? shard_n : 1);
}

static pp5_status_t read_part(const char *path, const workunit_log_header_t *first,
                              const workunit_list_t *l, workunit_result_t **res)
{
    /* The shard may differ between parts; everything else must not. */
    workunit_log_header_t want = *first;
    want.shard_n = 0;
    long valid;
    return workunit_log_read(path, &want, l, NULL, NULL, res, &valid);
}

static pp5_status_t merge_parts(const char *const *paths, int n, workunit_log_header_t *h,
                                workunit_list_t *l, workunit_run_t *r)
{
    workunit_result_t *part = NULL;
    long valid;
    pp5_status_t st = workunit_log_read(paths[0], NULL, NULL, h, l, &part, &valid);
    if (st != PP5_OK)
        return st;
    size_t cells = l->count ? l->count : 1;
    r->count = l->count;
    r->results = calloc(cells, sizeof *r->results);
    const char **owner = calloc(cells, sizeof *owner);   /* the part each unit came from */
    if (!r->results || !owner)
        st = pp5_fail(PP5_E_NOMEM, "merge: out of memory");
    for (int k = 0; st == PP5_OK && k < n; k++) {
        if (k > 0 && (st = read_part(paths[k], h, l, &part)) != PP5_OK)
            break;
        st = take_part(paths[k], l, part, r->results, owner, paths);
        for (size_t i = 0; i < l->count; i++)
            workunit_result_clear(&part[i]);
    }
    free(part);
    free(owner);
    return st;
}

pp5_status_t workunit_merge(const char *const *paths, int n, workunit_list_t *l,
                            workunit_run_t *r, char **command, char **csv_header)
{
    memset(r, 0, sizeof *r);
    workunit_list_init(l);
    *command = *csv_header = NULL;
    if (n < 1)
        return pp5_fail(PP5_E_CONFIG, "merge: no parts given");
    workunit_log_header_t h = {0};
    pp5_status_t st = merge_parts(paths, n, &h, l, r);
    if (st == PP5_OK)
        st = check_complete(l, r->results, h.shard_n);
    if (st == PP5_OK) {
        r->root = true;
        r->ranks = 1;
        r->plan_hash = h.plan_hash;
        for (size_t i = 0; i < r->count; i++)
            r->failed += r->results[i].failed;
        *command = h.command;
        *csv_header = h.csv_header;
        h.command = h.csv_header = NULL;
    }
    workunit_log_header_free(&h);
    return st;
}
