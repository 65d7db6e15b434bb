/* parallel.c: pthreads work sharing over independent items (see parallel.h). */
#include "parallel.h"

#include <pthread.h>
#include <stdatomic.h>
#include <unistd.h>

typedef struct {
    parallel_fn fn;
    void *ctx;
    int count;
    atomic_int next;
} parallel_job_t;

typedef struct {
    parallel_job_t *job;
    int index;
} parallel_worker_t;

static void *parallel_worker(void *arg)
{
    parallel_worker_t *w = arg;
    for (;;) {
        int item = atomic_fetch_add(&w->job->next, 1);
        if (item >= w->job->count)
            break;
        w->job->fn(w->job->ctx, item, w->index);
    }
    return NULL;
}

pp5_status_t parallel_for(int threads, int count, parallel_fn fn, void *ctx)
{
    if (threads > PARALLEL_MAX_THREADS)
        threads = PARALLEL_MAX_THREADS;
    if (threads > count)
        threads = count;
    if (threads <= 1) {
        for (int i = 0; i < count; i++)
            fn(ctx, i, 0);
        return PP5_OK;
    }
    parallel_job_t job = {fn, ctx, count, 0};
    pthread_t tid[PARALLEL_MAX_THREADS];
    parallel_worker_t w[PARALLEL_MAX_THREADS];
    int started = 0;
    for (int t = 1; t < threads; t++) {
        w[t].job = &job;
        w[t].index = t;
        if (pthread_create(&tid[t], NULL, parallel_worker, &w[t]) != 0)
            break;
        started = t;
    }
    w[0].job = &job;
    w[0].index = 0;
    parallel_worker(&w[0]);
    for (int t = 1; t <= started; t++)
        pthread_join(tid[t], NULL);
    return PP5_OK;
}

int parallel_default_threads(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    if (n < 1)
        n = 1;
    if (n > PARALLEL_MAX_THREADS)
        n = PARALLEL_MAX_THREADS;
    return (int)n;
}
