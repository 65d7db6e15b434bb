/* workunit_log.c: the unit log: a header naming the batch, then one record
 * per finished unit, appended and flushed as results arrive.  Text, so that
 * a person can read it:
 *
 *   pp5-unit-log 1
 *   command sweep
 *   pp5_version a39f5aa
 *   plan 8c1f0e2d4b6a7980             (workunit_plan_hash: command, plan, keys)
 *   shard 0/1
 *   csv gp.count,frame_time_s,...     (the batch's CSV header)
 *   units 2
 *   u 5d1e0c3b2a190807 gp.count=4     (id and key of every unit, in order)
 *   u 0f1e2d3c4b5a6978 gp.count=8
 *   records
 *   r 1 0f1e2d3c4b5a6978 ok 1 0 87 412 3a2b1c0d9e8f7061
 *   <error line>                      (lengths 0, 87 and 412 bytes; then the
 *   <CSV row>                          FNV-1a-64 of the three lines)
 *   <JSON object>
 *
 * A record that is cut short or fails its lengths or checksum ends the valid
 * part: a run killed while writing leaves exactly that, and a resumed run
 * cuts it off before appending. */
#include <inttypes.h>
#include <stdlib.h>
#include <string.h>

#include "workunit_internal.h"

#define LOG_MAGIC "pp5-unit-log 1"

pp5_status_t workunit_log_write_header(FILE *f, const workunit_log_header_t *h,
                                       const workunit_list_t *l)
{
    fprintf(f, "%s\ncommand %s\npp5_version %s\nplan %016" PRIx64 "\nshard %u/%u\ncsv %s\n"
               "units %zu\n", LOG_MAGIC, h->command, h->version, h->plan_hash, h->shard_k,
            h->shard_n, h->csv_header, l->count);
    for (size_t i = 0; i < l->count; i++)
        fprintf(f, "u %016" PRIx64 " %s\n", l->units[i].id, l->units[i].key);
    fputs("records\n", f);
    return fflush(f) == 0 && !ferror(f) ? PP5_OK : pp5_fail(PP5_E_IO, "unit log: write failed");
}

static uint64_t record_sum(const char *error, const char *row, const char *json)
{
    uint64_t h = workunit_hash(error, WORKUNIT_HASH_START);
    h = workunit_hash(json, workunit_hash("\n", workunit_hash(row, workunit_hash("\n", h))));
    return h;
}

pp5_status_t workunit_log_append(FILE *f, size_t index, uint64_t id, const workunit_result_t *r)
{
    fprintf(f, "r %zu %016" PRIx64 " %s %" PRIu64 " %zu %zu %zu %016" PRIx64 "\n%s\n%s\n%s\n",
            index, id, r->failed ? "failed" : "ok", r->frames, strlen(r->error), strlen(r->row),
            strlen(r->json), record_sum(r->error, r->row, r->json), r->error, r->row, r->json);
    return fflush(f) == 0 && !ferror(f) ? PP5_OK : pp5_fail(PP5_E_IO, "unit log: write failed");
}

void workunit_log_header_free(workunit_log_header_t *h)
{
    free(h->command);
    free(h->version);
    free(h->csv_header);
    memset(h, 0, sizeof *h);
}

typedef struct {
    FILE *f;
    const char *path;
    char *buf;
    size_t cap;
    long line_no;
} log_reader_t;

/* The next whole line without its newline, or NULL at the end of the file
 * or before a line cut short (no newline). */
static char *next_line(log_reader_t *r, size_t *len)
{
    ssize_t n = getline(&r->buf, &r->cap, r->f);
    if (n <= 0 || r->buf[n - 1] != '\n')
        return NULL;
    r->buf[--n] = '\0';
    r->line_no++;
    if (len)
        *len = (size_t)n;
    return r->buf;
}

/* "NAME VALUE": the value (in the reader's buffer). */
static const char *header_field(log_reader_t *r, const char *name, pp5_status_t *st)
{
    char *line = next_line(r, NULL);
    size_t n = strlen(name);
    if (!line || strncmp(line, name, n) != 0 || line[n] != ' ') {
        *st = pp5_fail(PP5_E_FORMAT, "%s:%ld: not a pp5 unit log (expected '%s ...')", r->path,
                       r->line_no + (line == NULL), name);
        return NULL;
    }
    return line + n + 1;
}

static char *dup_field(log_reader_t *r, const char *name, pp5_status_t *st)
{
    const char *v = *st == PP5_OK ? header_field(r, name, st) : NULL;
    char *copy = v ? strdup(v) : NULL;
    if (v && !copy)
        *st = pp5_fail(PP5_E_NOMEM, "%s: out of memory", r->path);
    return copy;
}

static pp5_status_t read_header(log_reader_t *r, workunit_log_header_t *h)
{
    memset(h, 0, sizeof *h);
    char *magic = next_line(r, NULL);
    if (!magic || strcmp(magic, LOG_MAGIC) != 0)
        return pp5_fail(PP5_E_FORMAT, "%s: not a pp5 unit log (first line '%s')", r->path,
                        LOG_MAGIC);
    pp5_status_t st = PP5_OK;
    h->command = dup_field(r, "command", &st);
    h->version = dup_field(r, "pp5_version", &st);
    const char *v = st == PP5_OK ? header_field(r, "plan", &st) : NULL;
    if (v && sscanf(v, "%" SCNx64, &h->plan_hash) != 1)
        st = pp5_fail(PP5_E_FORMAT, "%s:%ld: bad plan hash", r->path, r->line_no);
    v = st == PP5_OK ? header_field(r, "shard", &st) : NULL;
    if (v && (sscanf(v, "%u/%u", &h->shard_k, &h->shard_n) != 2 || h->shard_n == 0 ||
              h->shard_k >= h->shard_n))
        st = pp5_fail(PP5_E_FORMAT, "%s:%ld: bad shard", r->path, r->line_no);
    h->csv_header = dup_field(r, "csv", &st);
    v = st == PP5_OK ? header_field(r, "units", &st) : NULL;
    char *end = NULL;
    if (v) {
        unsigned long long c = strtoull(v, &end, 10);
        h->count = (size_t)c;
        if (end == v || *end || c > 100000000ull)
            st = pp5_fail(PP5_E_FORMAT, "%s:%ld: bad unit count", r->path, r->line_no);
    }
    return st;
}

/* A header field that differs from the batch's: what it means for the user. */
static pp5_status_t header_matches(const char *path, const workunit_log_header_t *got,
                                   const workunit_log_header_t *want)
{
    if (strcmp(got->command, want->command) != 0)
        return pp5_fail(PP5_E_CONFIG, "%s: written by pp5 %s, not pp5 %s", path, got->command,
                        want->command);
    if (strcmp(got->version, want->version) != 0)
        return pp5_fail(PP5_E_CONFIG, "%s: written by pp5 %s, this is pp5 %s: results of two "
                        "builds are not mixed", path, got->version, want->version);
    if (got->plan_hash != want->plan_hash || got->count != want->count ||
        strcmp(got->csv_header, want->csv_header) != 0)
        return pp5_fail(PP5_E_CONFIG, "%s: written for another batch (plan %016" PRIx64 ", %zu "
                        "units; this one is %016" PRIx64 ", %zu units): remove it, or give the "
                        "same arguments", path, got->plan_hash, got->count, want->plan_hash,
                        want->count);
    if (want->shard_n && (got->shard_k != want->shard_k || got->shard_n != want->shard_n))
        return pp5_fail(PP5_E_CONFIG, "%s: holds shard %u/%u, not %u/%u", path, got->shard_k,
                        got->shard_n, want->shard_k, want->shard_n);
    return PP5_OK;
}

/* The "u ID KEY" lines: into l when given (a merge), else only checked for form. */
static pp5_status_t read_units(log_reader_t *r, size_t count, workunit_list_t *l)
{
    for (size_t i = 0; i < count; i++) {
        char *line = next_line(r, NULL);
        uint64_t id;
        int used = 0;
        if (!line || sscanf(line, "u %" SCNx64 " %n", &id, &used) != 1 || used == 0)
            return pp5_fail(PP5_E_FORMAT, "%s:%ld: expected unit %zu of %zu ('u ID KEY')",
                            r->path, r->line_no + (line == NULL), i + 1, count);
        if (!l)
            continue;
        pp5_status_t st = workunit_list_add(l, line + used);
        if (st != PP5_OK)
            return pp5_fail(st, "%s:%ld: %s", r->path, r->line_no, pp5_error_text());
        if (l->units[l->count - 1].id != id)
            return pp5_fail(PP5_E_FORMAT, "%s:%ld: unit id %016" PRIx64 " is not the hash of "
                            "its key", r->path, r->line_no, id);
    }
    char *line = next_line(r, NULL);
    if (!line || strcmp(line, "records") != 0)
        return pp5_fail(PP5_E_FORMAT, "%s:%ld: expected 'records'", r->path, r->line_no);
    return PP5_OK;
}

static char *next_text(log_reader_t *r, size_t want_len)
{
    size_t len;
    char *line = next_line(r, &len);
    return line && len == want_len ? strdup(line) : NULL;
}

/* One record into res (count entries); false at a torn or bad record. */
static bool read_record(log_reader_t *r, const workunit_log_header_t *h, const uint64_t *ids,
                        workunit_result_t *res)
{
    char *line = next_line(r, NULL), status[8];
    size_t index, le, lr, lj;
    uint64_t id, frames, sum;
    if (!line || sscanf(line, "r %zu %" SCNx64 " %7s %" SCNu64 " %zu %zu %zu %" SCNx64, &index,
                        &id, status, &frames, &le, &lr, &lj, &sum) != 8 ||
        index >= h->count || (ids && ids[index] != id) ||
        (strcmp(status, "ok") != 0 && strcmp(status, "failed") != 0))
        return false;
    workunit_result_t got = {.done = true, .resumed = true, .frames = frames,
                             .failed = status[0] == 'f'};
    got.error = next_text(r, le);
    got.row = got.error ? next_text(r, lr) : NULL;
    got.json = got.row ? next_text(r, lj) : NULL;
    if (!got.json || record_sum(got.error, got.row, got.json) != sum) {
        workunit_result_clear(&got);
        return false;
    }
    workunit_result_clear(&res[index]);
    res[index] = got;
    return true;
}

static pp5_status_t read_records(log_reader_t *r, const workunit_log_header_t *h,
                                 const workunit_list_t *l, workunit_result_t *res, long *valid)
{
    uint64_t *ids = NULL;
    if (l && l->count == h->count && (ids = malloc((h->count ? h->count : 1) * sizeof *ids)))
        for (size_t i = 0; i < l->count; i++)
            ids[i] = l->units[i].id;
    *valid = ftell(r->f);
    size_t n = 0;
    while (read_record(r, h, ids, res)) {
        *valid = ftell(r->f);
        n++;
    }
    fseek(r->f, 0, SEEK_END);
    if (ftell(r->f) > *valid)
        fprintf(stderr, "pp5: %s: ignoring what follows record %zu (byte %ld on): a run "
                "stopped while writing it, or the file was damaged\n", r->path, n, *valid);
    free(ids);
    return PP5_OK;
}

pp5_status_t workunit_log_read(const char *path, const workunit_log_header_t *expect,
                               const workunit_list_t *batch, workunit_log_header_t *got,
                               workunit_list_t *fill, workunit_result_t **results,
                               long *valid_bytes)
{
    log_reader_t r = {.f = fopen(path, "r"), .path = path};
    if (!r.f)
        return pp5_fail(PP5_E_IO, "%s: cannot open", path);
    workunit_log_header_t h;
    pp5_status_t st = read_header(&r, &h);
    if (st == PP5_OK && expect)
        st = header_matches(path, &h, expect);
    if (st == PP5_OK)
        st = read_units(&r, h.count, fill);
    if (st == PP5_OK && !*results && !(*results = calloc(h.count ? h.count : 1, sizeof **results)))
        st = pp5_fail(PP5_E_NOMEM, "%s: out of memory", path);
    if (st == PP5_OK)
        st = read_records(&r, &h, expect ? batch : fill, *results, valid_bytes);
    free(r.buf);
    fclose(r.f);
    if (st == PP5_OK && got)
        *got = h;
    else
        workunit_log_header_free(&h);
    return st;
}
