/* workunit.h: batches of self-contained work units (a sweep's grid points, a
 * batch of trace replays), run in one process, across the ranks of an MPI job,
 * or as independent shards, always with the same outputs.
 *
 *   workunit_list_t l;  workunit_list_init(&l);
 *   workunit_list_add(&l, "gp.count=4 ring.channels=8");   (one per unit, in output order)
 *   workunit_run_t r;
 *   workunit_run(&l, &opts, run_one_unit, ctx, &r);        (on every rank)
 *   if (r.root) workunit_write_csv(...), ...;               (rank 0 writes)
 *
 * A unit's id is the FNV-1a-64 hash of its key, the canonical text of its
 * parameters, so it is the same in every run, rank and shard.  The unit
 * function gets the unit's index and key and returns its result as text: a
 * CSV row and a JSON object (and the emulated frames it ran, for the
 * accounting).  Results are kept by index and written in unit order, so
 * the outputs do not depend on which rank ran what, or when.  Host times go
 * only to the accounting (stderr, --accounting FILE), never into the outputs.
 *
 * Three ways to run, one result:
 *   - plainly: units run in order in this process;
 *   - under mpirun/srun (an MPI build, launched by an MPI launcher): rank 0
 *     hands out units one at a time to whichever rank asks (units differ a
 *     lot in cost), runs units itself in a second thread, and gathers the
 *     results;
 *   - shards: opts.shard_n > 1 runs only the units whose id mod shard_n is
 *     shard_k, into a unit log that workunit_merge combines with the others.
 *
 * The unit log (opts.log_path) records each result as it arrives (a header
 * naming the batch, then one checksummed record per unit), so a killed run
 * resumes (opts.resume) without redoing finished units; a torn last record
 * is dropped.  The log is also a shard's output. */
#ifndef PP5_WORKUNIT_H
#define PP5_WORKUNIT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "status.h"

/* Exit code of a command whose batch finished but some of whose units failed
 * (their failure records are in the outputs). */
#define WORKUNIT_EXIT_UNITS_FAILED PP5_EXIT_UNITS_FAILED

typedef struct {
    uint64_t id;      /* FNV-1a-64 of key */
    char *key;        /* canonical parameters, one line */
} workunit_t;

typedef struct {
    workunit_t *units;
    size_t count, capacity;
} workunit_list_t;

void workunit_list_init(workunit_list_t *l);
/* Appends a unit; PP5_E_CONFIG when another unit has the same id (the same
 * parameters twice), naming both. */
pp5_status_t workunit_list_add(workunit_list_t *l, const char *key);
void workunit_list_free(workunit_list_t *l);
uint64_t workunit_hash(const char *text, uint64_t h);
#define WORKUNIT_HASH_START 14695981039346656037ull   /* the FNV-1a 64 offset basis */

/* What a unit function returns (malloc'd texts, one line each; the runner
 * frees them).  A failed unit returns its failure status with
 * pp5_error_text() set, and may still fill row and json (a sweep writes a
 * row of NaNs with the error). */
typedef struct {
    char *row;        /* the CSV row, without newline */
    char *json;       /* a JSON object, or NULL */
    uint64_t frames;  /* emulated frames it ran (accounting) */
} workunit_output_t;

typedef pp5_status_t (*workunit_fn)(void *ctx, size_t index, const workunit_t *unit,
                                    workunit_output_t *out);

typedef struct {
    bool done;        /* a result is present (run now or read from the log) */
    bool failed;
    bool resumed;     /* read back from the unit log */
    uint64_t frames;
    double host_s;    /* host seconds on its rank: accounting only */
    double cpu_s;     /* CPU seconds of the thread that ran it (accounting only) */
    int rank;
    char *error, *row, *json;   /* never NULL once done ("" when empty) */
} workunit_result_t;

typedef struct {
    const char *command;      /* "sweep", "replay-batch": names the log and messages */
    const char *plan;         /* the settings all units share, one line per setting */
    const char *csv_header;   /* kept in the log, so that a merge can write the CSV */
    const char *log_path;     /* the unit log (required) */
    bool resume;              /* keep the log's finished units; failed ones run again */
    unsigned shard_k, shard_n;   /* shard_n 0 or 1: every unit */
    const char *accounting_path; /* JSON accounting, or NULL */
    bool quiet;               /* no accounting summary or failure lines on stderr (tests) */
} workunit_opts_t;

typedef struct {
    workunit_result_t *results;   /* by unit index; only the shard's units are done */
    size_t count;
    bool root;                /* false on the MPI ranks that only computed */
    int ranks;
    size_t ran, resumed, failed, in_shard;
    uint64_t plan_hash;
} workunit_run_t;

pp5_status_t workunit_run(const workunit_list_t *l, const workunit_opts_t *o, workunit_fn fn,
                          void *ctx, workunit_run_t *out);
void workunit_run_free(workunit_run_t *r);

/* Before workunit_run: this process's rank as the MPI launcher numbered it
 * (0 when not launched by one), so that only rank 0 prints. */
int workunit_launcher_rank(void);
/* Whether an MPI launcher (mpirun, srun with PMI/PMIx) started this process
 * as one of a job; PP5_MPI=0 or 1 overrides. */
bool workunit_launched_by_mpi(void);
/* Whether this build has MPI. */
bool workunit_have_mpi(void);

/* "K/N" with 0 <= K < N <= 1000000. */
pp5_status_t workunit_parse_shard(const char *text, unsigned *k, unsigned *n);

/* Outputs, in unit order, written to a temporary file and renamed into place.
 * CSV: the header, then each done unit's row.  JSON: {"command", "plan_hash",
 * "units": [{"index", "id", "key", "status", "error", "result"}, ...]}. */
pp5_status_t workunit_write_csv(const char *path, const char *header, const workunit_run_t *r);
pp5_status_t workunit_write_json(const char *path, const char *command, const workunit_list_t *l,
                                 const workunit_run_t *r);

/* Combines the unit logs of a batch's shards: they must come from the same
 * batch (command, plan, units, pp5 version) and together hold every unit.
 * Fills *l (the batch's units), *r (root, all results) and the command name
 * and CSV header (malloc'd). */
pp5_status_t workunit_merge(const char *const *paths, int n, workunit_list_t *l,
                            workunit_run_t *r, char **command, char **csv_header);

#endif
