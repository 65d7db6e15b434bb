/* test_workunit.c: the work-unit runner in this process (emu/util/workunit.h):
 * ids, shards, the unit log with resume and torn records, failed units, and
 * merging shards.  A toy unit whose result is known in closed form stands in
 * for a real one; the commands are tested in test_scale.c. */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "harness.h"
#include "workunit.h"

/* Published FNV-1a 64-bit test vectors (Fowler/Noll/Vo): "" and "a" from
 * the reference code's test suite, "foobar" from the same table. */
TEST(workunit_hash_matches_published_fnv1a_64_vectors)
{
    CHECK(workunit_hash("", WORKUNIT_HASH_START) == 0xcbf29ce484222325ull);
    CHECK(workunit_hash("a", WORKUNIT_HASH_START) == 0xaf63dc4c8601ec8cull);
    CHECK(workunit_hash("foobar", WORKUNIT_HASH_START) == 0x85944171f73967e8ull);
}

TEST(workunit_list_rejects_a_unit_given_twice_and_multiline_keys)
{
    workunit_list_t l;
    workunit_list_init(&l);
    CHECK_EQ(workunit_list_add(&l, "gp.count=4"), PP5_OK);
    CHECK_EQ(workunit_list_add(&l, "gp.count=8"), PP5_OK);
    CHECK_EQ(workunit_list_add(&l, "gp.count=4"), PP5_E_CONFIG);
    CHECK(strstr(pp5_error_text(), "units 1 and 3") != NULL);
    CHECK_EQ(workunit_list_add(&l, "a\nb"), PP5_E_CONFIG);
    CHECK_EQ(l.count, 2);
    workunit_list_free(&l);
}

TEST(workunit_shard_syntax_is_strict)
{
    unsigned k = 99, n = 99;
    CHECK_EQ(workunit_parse_shard("3/8", &k, &n), PP5_OK);
    CHECK(k == 3 && n == 8);
    const char *bad[] = {"8/8", "1/0", "a/b", "-1/2", "1/-2", "1", "1/2x", "/2", ""};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        CHECK_MSG(workunit_parse_shard(bad[i], &k, &n) == PP5_E_CONFIG, "'%s' accepted", bad[i]);
}

/* The toy unit: unit i's row is "KEY,i*i" (i*i worked out by the test, not
 * read back); unit `fail_at` fails; calls counts the units actually run. */
typedef struct {
    int calls;
    size_t fail_at;
} toy_t;

static pp5_status_t toy_unit(void *ctx, size_t index, const workunit_t *u, workunit_output_t *out)
{
    toy_t *t = ctx;
    t->calls++;
    char row[128], json[64];
    snprintf(row, sizeof row, "%s,%zu", u->key, index * index);
    snprintf(json, sizeof json, "{\"square\":%zu}", index * index);
    out->row = strdup(row);
    out->json = strdup(json);
    out->frames = 1;
    return index == t->fail_at ? pp5_fail(PP5_E_RANGE, "unit %zu does not fit", index) : PP5_OK;
}

static void toy_list(workunit_list_t *l, int n)
{
    workunit_list_init(l);
    for (int i = 0; i < n; i++) {
        char key[32];
        snprintf(key, sizeof key, "u%d", i);
        REQUIRE(workunit_list_add(l, key) == PP5_OK);
    }
}

static workunit_opts_t toy_opts(const char *log)
{
    return (workunit_opts_t){.command = "toy", .plan = "toy plan", .csv_header = "key,square",
                             .log_path = log, .quiet = true};
}

/* Runs the batch and returns its CSV text (malloc'd). */
static char *toy_csv(const workunit_list_t *l, const workunit_opts_t *o, toy_t *t,
                     workunit_run_t *r, const char *csv)
{
    REQUIRE(workunit_run(l, o, toy_unit, t, r) == PP5_OK);
    REQUIRE(workunit_write_csv(csv, o->csv_header, r) == PP5_OK);
    return pp5_test_read_file(csv);
}

TEST(workunit_serial_run_writes_rows_in_unit_order_and_resume_skips_done_units)
{
    const char *dir = pp5_test_outdir();
    char log[600], csv[600];
    snprintf(log, sizeof log, "%s/b.units", dir);
    snprintf(csv, sizeof csv, "%s/b.csv", dir);
    workunit_list_t l;
    toy_list(&l, 5);
    workunit_opts_t o = toy_opts(log);
    toy_t t = {0, (size_t)-1};
    workunit_run_t r;
    char *first = toy_csv(&l, &o, &t, &r, csv);
    CHECK_EQ(t.calls, 5);
    CHECK(first && strcmp(first, "key,square\nu0,0\nu1,1\nu2,4\nu3,9\nu4,16\n") == 0);
    workunit_run_free(&r);
    /* A complete log: a resumed run has nothing left to do. */
    o.resume = true;
    t.calls = 0;
    char *again = toy_csv(&l, &o, &t, &r, csv);
    CHECK_EQ(t.calls, 0);
    CHECK_EQ(r.resumed, 5);
    CHECK(first && again && strcmp(first, again) == 0);
    workunit_run_free(&r);
    free(again);
    /* Cut the log inside the last record, as a kill while writing does. */
    char *text = pp5_test_read_file(log);
    REQUIRE(text != NULL);
    REQUIRE(truncate(log, (off_t)strlen(text) - 7) == 0);
    free(text);
    t.calls = 0;
    again = toy_csv(&l, &o, &t, &r, csv);
    CHECK_EQ(t.calls, 1);
    CHECK(first && again && strcmp(first, again) == 0);
    workunit_run_free(&r);
    free(again);
    free(first);
    workunit_list_free(&l);
}

TEST(workunit_failed_unit_is_recorded_the_rest_finish_and_resume_retries_it)
{
    const char *dir = pp5_test_outdir();
    char log[600], csv[600];
    snprintf(log, sizeof log, "%s/f.units", dir);
    snprintf(csv, sizeof csv, "%s/f.csv", dir);
    workunit_list_t l;
    toy_list(&l, 4);
    workunit_opts_t o = toy_opts(log);
    toy_t t = {0, 2};
    workunit_run_t r;
    char *csv_text = toy_csv(&l, &o, &t, &r, csv);
    CHECK_EQ(t.calls, 4);
    CHECK_EQ(r.failed, 1);
    CHECK(r.results[2].failed && strcmp(r.results[2].error, "unit 2 does not fit") == 0);
    CHECK(r.results[3].done && !r.results[3].failed);
    /* The failed unit's row is kept: a result like any other. */
    CHECK(csv_text && strstr(csv_text, "\nu2,4\n") != NULL);
    workunit_run_free(&r);
    free(csv_text);
    o.resume = true;
    t = (toy_t){0, (size_t)-1};
    REQUIRE(workunit_run(&l, &o, toy_unit, &t, &r) == PP5_OK);
    CHECK_EQ(t.calls, 1);
    CHECK_EQ(r.failed, 0);
    CHECK_EQ(r.resumed, 3);
    workunit_run_free(&r);
    workunit_list_free(&l);
}

TEST(workunit_shards_hold_id_mod_n_and_merge_to_the_single_run)
{
    const char *dir = pp5_test_outdir();
    char single_log[600], single_csv[600], merged_csv[600], parts[3][600];
    snprintf(single_log, sizeof single_log, "%s/all.units", dir);
    snprintf(single_csv, sizeof single_csv, "%s/all.csv", dir);
    snprintf(merged_csv, sizeof merged_csv, "%s/merged.csv", dir);
    workunit_list_t l;
    toy_list(&l, 12);
    workunit_opts_t o = toy_opts(single_log);
    toy_t t = {0, 5};
    workunit_run_t r;
    char *single = toy_csv(&l, &o, &t, &r, single_csv);
    workunit_run_free(&r);
    const char *paths[3];
    size_t total = 0;
    for (unsigned k = 0; k < 3; k++) {
        snprintf(parts[k], sizeof parts[k], "%s/part%u.units", dir, k);
        paths[k] = parts[k];
        workunit_opts_t so = toy_opts(parts[k]);
        so.shard_k = k;
        so.shard_n = 3;
        t.calls = 0;
        REQUIRE(workunit_run(&l, &so, toy_unit, &t, &r) == PP5_OK);
        for (size_t i = 0; i < l.count; i++)
            CHECK(r.results[i].done == (l.units[i].id % 3 == k));
        total += (size_t)t.calls;
        workunit_run_free(&r);
    }
    CHECK_EQ(total, 12);
    workunit_list_t ml;
    char *command = NULL, *header = NULL;
    REQUIRE(workunit_merge(paths, 3, &ml, &r, &command, &header) == PP5_OK);
    CHECK(strcmp(command, "toy") == 0 && strcmp(header, "key,square") == 0);
    CHECK_EQ(r.failed, 1);
    REQUIRE(workunit_write_csv(merged_csv, header, &r) == PP5_OK);
    char *merged = pp5_test_read_file(merged_csv);
    CHECK(single && merged && strcmp(single, merged) == 0);
    workunit_run_free(&r);
    workunit_list_free(&ml);
    free(command);
    free(header);
    /* A part left out: no output, and the message says which shard. */
    CHECK_EQ(workunit_merge(paths, 2, &ml, &r, &command, &header), PP5_E_FORMAT);
    CHECK(strstr(pp5_error_text(), "which shard 2/3 runs") != NULL);
    workunit_run_free(&r);
    workunit_list_free(&ml);
    free(single);
    free(merged);
    workunit_list_free(&l);
}

TEST(workunit_resume_and_merge_refuse_a_log_of_another_batch)
{
    const char *dir = pp5_test_outdir();
    char log[600], csv[600];
    snprintf(log, sizeof log, "%s/x.units", dir);
    snprintf(csv, sizeof csv, "%s/x.csv", dir);
    workunit_list_t l, other;
    toy_list(&l, 3);
    toy_list(&other, 4);
    workunit_opts_t o = toy_opts(log);
    toy_t t = {0, (size_t)-1};
    workunit_run_t r;
    REQUIRE(workunit_run(&l, &o, toy_unit, &t, &r) == PP5_OK);
    workunit_run_free(&r);
    o.resume = true;
    CHECK_EQ(workunit_run(&other, &o, toy_unit, &t, &r), PP5_E_CONFIG);
    CHECK(strstr(pp5_error_text(), "written for another batch") != NULL);
    workunit_run_free(&r);
    /* A file that is not a unit log at all. */
    FILE *f = fopen(csv, "w");
    REQUIRE(f != NULL);
    fputs("key,square\nu0,0\n", f);
    fclose(f);
    const char *paths[] = {log, csv};
    workunit_list_t ml;
    char *command = NULL, *header = NULL;
    CHECK_EQ(workunit_merge(paths, 2, &ml, &r, &command, &header), PP5_E_FORMAT);
    CHECK(strstr(pp5_error_text(), "not a pp5 unit log") != NULL);
    workunit_run_free(&r);
    workunit_list_free(&ml);
    workunit_list_free(&l);
    workunit_list_free(&other);
}
