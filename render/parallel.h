/* parallel.h: a tiny pthreads "for each item" used by the native renderer.
 *
 * Items are handed out through an atomic counter, so which thread runs an
 * item varies from run to run; callers make every item write only its own
 * outputs (and keep per-thread integer counters), which is what makes the
 * renderer's image and counts identical for any thread count. */
#ifndef PP5_PARALLEL_H
#define PP5_PARALLEL_H

#include "status.h"

#define PARALLEL_MAX_THREADS 64

/* fn(ctx, item, thread_index) for item in [0, count).  threads <= 1 runs
 * inline on the caller.  Fails only if no thread could be started. */
typedef void (*parallel_fn)(void *ctx, int item, int thread_index);
pp5_status_t parallel_for(int threads, int count, parallel_fn fn, void *ctx);

/* Host threads to use when the user asked for 0 ("all"): online CPUs, 1..64. */
int parallel_default_threads(void);

#endif
