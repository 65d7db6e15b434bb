/* workunit_internal.h: what the unit runner's files share (workunit.c, the
 * log, the serial runner and the MPI transport); not for its users. */
#ifndef PP5_WORKUNIT_INTERNAL_H
#define PP5_WORKUNIT_INTERNAL_H

#include <stdio.h>

#include "progress.h"
#include "workunit.h"

/* The header of a unit log: which batch it belongs to. */
typedef struct {
    char *command, *version, *csv_header;
    uint64_t plan_hash;
    unsigned shard_k, shard_n;
    size_t count;
} workunit_log_header_t;

/* One run of a batch in this process. */
typedef struct {
    const workunit_list_t *list;
    const workunit_opts_t *opts;
    workunit_fn fn;
    void *ctx;
    workunit_run_t *out;
    size_t *todo;             /* unit indices still to run, in unit order */
    size_t n_todo;
    FILE *log;                /* rank 0: the unit log, open for appending */
    progress_t progress;
    double t_start, mpi_init_s;
    size_t recorded;          /* results recorded by this run */
    long kill_after;          /* PP5_WORKUNIT_KILL_AFTER (tests): 0 = off */
} workunit_job_t;

double workunit_now_s(void);
double workunit_thread_cpu_s(void);
uint64_t workunit_plan_hash(const char *command, const char *plan, const workunit_list_t *l);
void workunit_result_clear(workunit_result_t *r);
pp5_status_t workunit_write_atomic(const char *path, pp5_status_t (*body)(FILE *f, void *arg),
                                   void *arg);

/* Runs unit `index` here and fills *r (never fails: a failure is a result). */
void workunit_run_one(workunit_job_t *j, size_t index, int rank, workunit_result_t *r);
/* Rank 0: results[index] has arrived: log it, report a failure, step the progress. */
pp5_status_t workunit_record(workunit_job_t *j, size_t index);
/* Rank 0: opens or resumes the log and makes the to-do list. */
pp5_status_t workunit_job_prepare(workunit_job_t *j);
/* Rank 0: closes the log and prints (and writes) the accounting. */
pp5_status_t workunit_job_finish(workunit_job_t *j);
/* Runs the to-do list in this process. */
pp5_status_t workunit_run_serial(workunit_job_t *j);
/* The MPI transport (workunit_mpi.c): PP5_E_UNSUPPORTED in a build without MPI. */
pp5_status_t workunit_run_mpi(workunit_job_t *j);

/* The unit log (workunit_log.c). */
pp5_status_t workunit_log_write_header(FILE *f, const workunit_log_header_t *h,
                                       const workunit_list_t *l);
pp5_status_t workunit_log_append(FILE *f, size_t index, uint64_t id, const workunit_result_t *r);
/* Reads a whole log.  With `expect` (a resume), its header must match (else
 * an error naming the field) and record ids are checked against *batch, the
 * batch's units; without (a merge), *fill receives the log's units.  *got, when
 * given, receives the header.  *results (allocated when NULL) gets the valid
 * records (a later record of a unit replaces an earlier one); *valid_bytes is
 * where the first torn or bad record starts (the end of the file when there
 * is none). */
pp5_status_t workunit_log_read(const char *path, const workunit_log_header_t *expect,
                               const workunit_list_t *batch, workunit_log_header_t *got,
                               workunit_list_t *fill, workunit_result_t **results,
                               long *valid_bytes);
void workunit_log_header_free(workunit_log_header_t *h);

#endif
