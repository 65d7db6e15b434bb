/* workunit_mpi.c: the MPI transport of the unit runner.  The only file of pp5
 * that includes <mpi.h>.
 *
 * Rank 0 keeps the to-do list and hands out one unit at a time to whichever
 * rank asks, so that a rank that drew cheap units simply draws more (a
 * sweep's points differ in cost by 10x and more).  Rank 0 also runs units,
 * in a second thread that takes from the same list; its main thread only
 * talks MPI (MPI_THREAD_FUNNELED), polling with MPI_Iprobe and sleeping 1 ms
 * when idle rather than spinning in a blocking receive, which would take a
 * core from the units.  Results travel as bytes (index, id, status, frames,
 * host seconds, then the error, row and JSON texts); rank 0 keeps them by
 * index and writes the outputs in unit order after the last one, so the
 * outputs do not depend on the number of ranks.  The binary layout assumes
 * that all ranks run the same build on the same architecture.
 *
 * Protocol (tags): a worker sends READY, then gets UNIT {index, id} or STOP;
 * after each unit it sends RESULT, which is also its request for the next. */
#include <inttypes.h>
#include <stdlib.h>
#include <string.h>

#include "pp5_features.h"
#include "workunit_internal.h"

#if PP5_HAVE_MPI
#include <mpi.h>
#include <pthread.h>
#include <time.h>

bool workunit_have_mpi(void)
{
    return true;
}

enum { TAG_READY = 11, TAG_UNIT, TAG_STOP, TAG_RESULT };

typedef struct {
    uint64_t index, id, frames;
    double host_s, cpu_s;
    uint32_t failed, len_error, len_row, len_json;
} wire_head_t;

static unsigned char *pack_result(size_t index, uint64_t id, const workunit_result_t *r,
                                  size_t *bytes)
{
    wire_head_t h = {index, id, r->frames, r->host_s, r->cpu_s, r->failed,
                     (uint32_t)strlen(r->error),
                     (uint32_t)strlen(r->row), (uint32_t)strlen(r->json)};
    *bytes = sizeof h + h.len_error + h.len_row + h.len_json;
    unsigned char *buf = malloc(*bytes);
    if (!buf)
        return NULL;
    memcpy(buf, &h, sizeof h);
    memcpy(buf + sizeof h, r->error, h.len_error);
    memcpy(buf + sizeof h + h.len_error, r->row, h.len_row);
    memcpy(buf + sizeof h + h.len_error + h.len_row, r->json, h.len_json);
    return buf;
}

static char *copy_text(const unsigned char *p, uint32_t n)
{
    char *s = malloc((size_t)n + 1);
    if (s) {
        memcpy(s, p, n);
        s[n] = '\0';
    }
    return s;
}

static pp5_status_t unpack_result(const workunit_job_t *j, const unsigned char *buf,
                                  size_t bytes, int rank, size_t *index)
{
    wire_head_t h;
    if (bytes < sizeof h)
        return pp5_fail(PP5_E_FORMAT, "rank %d sent a short result", rank);
    memcpy(&h, buf, sizeof h);
    if (h.index >= j->list->count || j->list->units[h.index].id != h.id ||
        sizeof h + (size_t)h.len_error + h.len_row + h.len_json != bytes)
        return pp5_fail(PP5_E_FORMAT, "rank %d sent a malformed result", rank);
    workunit_result_t *r = &j->out->results[h.index];
    workunit_result_clear(r);
    const unsigned char *p = buf + sizeof h;
    *r = (workunit_result_t){.done = true, .failed = h.failed != 0, .frames = h.frames,
                             .host_s = h.host_s, .cpu_s = h.cpu_s, .rank = rank};
    r->error = copy_text(p, h.len_error);
    r->row = copy_text(p + h.len_error, h.len_row);
    r->json = copy_text(p + h.len_error + h.len_row, h.len_json);
    *index = (size_t)h.index;
    return r->error && r->row && r->json ? PP5_OK : pp5_fail(PP5_E_NOMEM, "out of memory");
}

/* Waits for a request, sleeping 1 ms between tests: a blocking MPI call
 * spins (Open MPI polls), which takes a core from the ranks still working,
 * and on an oversubscribed node (tests: 3 ranks on 2 cores) slows them all. */
static void wait_sleeping(MPI_Request *req)
{
    int done = 0;
    MPI_Test(req, &done, MPI_STATUS_IGNORE);
    while (!done) {
        nanosleep(&(struct timespec){0, 1000000}, NULL);
        MPI_Test(req, &done, MPI_STATUS_IGNORE);
    }
}

/* ---- rank 0 ---- */

typedef struct {
    workunit_job_t *job;
    pthread_mutex_t lock;
    size_t next;            /* into job->todo */
    size_t *finished;       /* rank 0's own results not yet recorded */
    size_t n_finished;
    bool local_done;
} coordinator_t;

static bool take_next(coordinator_t *c, size_t *index)
{
    pthread_mutex_lock(&c->lock);
    bool ok = c->next < c->job->n_todo;
    if (ok)
        *index = c->job->todo[c->next++];
    pthread_mutex_unlock(&c->lock);
    return ok;
}

static void *local_worker(void *arg)
{
    coordinator_t *c = arg;
    size_t index;
    while (take_next(c, &index)) {
        workunit_run_one(c->job, index, 0, &c->job->out->results[index]);
        pthread_mutex_lock(&c->lock);
        c->finished[c->n_finished++] = index;
        pthread_mutex_unlock(&c->lock);
    }
    pthread_mutex_lock(&c->lock);
    c->local_done = true;
    pthread_mutex_unlock(&c->lock);
    return NULL;
}

/* A message from a worker: record its result, if any, and give it the next
 * unit or tell it to stop. */
static pp5_status_t serve(coordinator_t *c, const MPI_Status *probe, int *active)
{
    int src = probe->MPI_SOURCE, bytes = 0;
    MPI_Get_count(probe, MPI_BYTE, &bytes);
    unsigned char *buf = malloc(bytes > 0 ? (size_t)bytes : 1);
    if (!buf)
        return pp5_fail(PP5_E_NOMEM, "out of memory");
    MPI_Recv(buf, bytes, MPI_BYTE, src, probe->MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    pp5_status_t st = PP5_OK;
    size_t index = 0;
    if (probe->MPI_TAG == TAG_RESULT && (st = unpack_result(c->job, buf, (size_t)bytes, src,
                                                            &index)) == PP5_OK)
        st = workunit_record(c->job, index);
    free(buf);
    uint64_t msg[2] = {0, 0};
    if (take_next(c, &index)) {
        msg[0] = index;
        msg[1] = c->job->list->units[index].id;
        MPI_Send(msg, 2, MPI_UINT64_T, src, TAG_UNIT, MPI_COMM_WORLD);
    } else {
        MPI_Send(msg, 2, MPI_UINT64_T, src, TAG_STOP, MPI_COMM_WORLD);
        (*active)--;
    }
    return st;
}

/* Records what rank 0's own thread finished; true when it did anything. */
static pp5_status_t drain_local(coordinator_t *c, bool *busy, bool *local_done)
{
    size_t done[64], n = 0;
    pthread_mutex_lock(&c->lock);
    while (c->n_finished > 0 && n < 64)
        done[n++] = c->finished[--c->n_finished];
    *local_done = c->local_done && c->n_finished == 0;
    pthread_mutex_unlock(&c->lock);
    pp5_status_t st = PP5_OK;
    for (size_t k = 0; k < n && st == PP5_OK; k++)
        st = workunit_record(c->job, done[k]);
    *busy |= n > 0;
    return st;
}

static pp5_status_t coordinate(workunit_job_t *j, int size, bool threads)
{
    coordinator_t c = {.job = j, .local_done = !threads};
    pthread_mutex_init(&c.lock, NULL);
    pthread_t worker;
    c.finished = malloc((j->n_todo ? j->n_todo : 1) * sizeof *c.finished);
    if (!c.finished)
        return pp5_fail(PP5_E_NOMEM, "out of memory");
    if (threads && pthread_create(&worker, NULL, local_worker, &c) != 0) {
        threads = false;
        c.local_done = true;
    }
    int active = size - 1;
    bool local_done = !threads;
    pp5_status_t st = PP5_OK;
    while (st == PP5_OK && (active > 0 || !local_done)) {
        bool busy = false;
        int flag = 0;
        MPI_Status probe;
        MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &probe);
        if (flag) {
            busy = true;
            st = serve(&c, &probe, &active);
        }
        if (st == PP5_OK)
            st = drain_local(&c, &busy, &local_done);
        if (!busy)
            nanosleep(&(struct timespec){0, 1000000}, NULL);
    }
    if (st != PP5_OK) {
        fprintf(stderr, "pp5 %s: %s\n", j->opts->command, pp5_error_text());
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
    if (threads)
        pthread_join(worker, NULL);
    pthread_mutex_destroy(&c.lock);
    free(c.finished);
    return st;
}

/* ---- the other ranks ---- */

static void work(workunit_job_t *j, int rank)
{
    MPI_Send(NULL, 0, MPI_BYTE, 0, TAG_READY, MPI_COMM_WORLD);
    for (;;) {
        uint64_t msg[2];
        MPI_Status s;
        MPI_Request req;
        MPI_Irecv(msg, 2, MPI_UINT64_T, 0, MPI_ANY_TAG, MPI_COMM_WORLD, &req);
        int done = 0;
        while (MPI_Test(&req, &done, &s), !done)
            nanosleep(&(struct timespec){0, 1000000}, NULL);
        if (s.MPI_TAG == TAG_STOP)
            return;
        if (msg[0] >= j->list->count || j->list->units[msg[0]].id != msg[1]) {
            fprintf(stderr, "pp5 %s: rank %d was handed unit %" PRIu64 ", which its list does "
                    "not hold\n", j->opts->command, rank, msg[0]);
            MPI_Abort(MPI_COMM_WORLD, 1);
        }
        workunit_result_t r = {0};
        workunit_run_one(j, (size_t)msg[0], rank, &r);
        size_t bytes = 0;
        unsigned char *buf = r.error ? pack_result((size_t)msg[0], msg[1], &r, &bytes) : NULL;
        if (!buf) {
            fprintf(stderr, "pp5 %s: rank %d: out of memory\n", j->opts->command, rank);
            MPI_Abort(MPI_COMM_WORLD, 1);
        }
        MPI_Send(buf, (int)bytes, MPI_BYTE, 0, TAG_RESULT, MPI_COMM_WORLD);
        free(buf);
        workunit_result_clear(&r);
    }
}

/* Every rank must have built the same batch from its arguments and files. */
static bool plans_agree(uint64_t hash)
{
    unsigned long long mine = hash, lo = 0, hi = 0;
    MPI_Allreduce(&mine, &lo, 1, MPI_UNSIGNED_LONG_LONG, MPI_MIN, MPI_COMM_WORLD);
    MPI_Allreduce(&mine, &hi, 1, MPI_UNSIGNED_LONG_LONG, MPI_MAX, MPI_COMM_WORLD);
    return lo == hi;
}

pp5_status_t workunit_run_mpi(workunit_job_t *j)
{
    int provided = 0, rank = 0, size = 1;
    double t0 = workunit_now_s();
    MPI_Init_thread(NULL, NULL, MPI_THREAD_FUNNELED, &provided);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    j->mpi_init_s = workunit_now_s() - t0;
    j->out->root = rank == 0;
    j->out->ranks = size;
    pp5_status_t st = PP5_OK;
    if (!plans_agree(j->out->plan_hash))
        st = pp5_fail(PP5_E_CONFIG, "the %d ranks built different batches (their plan hashes "
                      "differ): every rank must get the same arguments and see the same files",
                      size);
    if (st == PP5_OK && rank == 0)
        st = workunit_job_prepare(j);
    int ok = st == PP5_OK;
    MPI_Bcast(&ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (ok && rank == 0 && size == 1)
        st = workunit_run_serial(j);
    else if (ok && rank == 0)
        st = coordinate(j, size, provided >= MPI_THREAD_FUNNELED);
    else if (ok)
        work(j, rank);
    /* Ranks that ran out of units wait here for the last ones without
     * spinning (MPI_Finalize's own synchronisation would). */
    MPI_Request barrier;
    MPI_Ibarrier(MPI_COMM_WORLD, &barrier);
    wait_sleeping(&barrier);
    MPI_Finalize();
    if (rank != 0)
        return PP5_OK;
    pp5_status_t fst = workunit_job_finish(j);
    return st == PP5_OK ? fst : st;
}

#else

bool workunit_have_mpi(void)
{
    return false;
}

pp5_status_t workunit_run_mpi(workunit_job_t *j)
{
    j->out->root = workunit_launcher_rank() == 0;
    return pp5_fail(PP5_E_UNSUPPORTED, "an MPI launcher started this process, but this pp5 was "
                    "built without MPI (no usable mpicc when it was built): install "
                    "libopenmpi-dev and run make again, or run %s without mpirun",
                    j->opts->command);
}

#endif
