/* seed003_queue.h: seed 003's candidate queue.  It yields the least
 * (cost, tie) first and holds each id at most once, like the shared queue
 * (simplify_queue.c), but is shaped for lazy costing (ARCHITECTURE.md,
 * "Seed 003 ... decisions"): most edges are queued under a lower bound,
 * costed when they reach the top and queued again far from it, and most
 * leave the queue (frozen, re-costed) long before they come back up.
 *
 * So only the lowest keys are kept in order, in a small heap; the others
 * wait unsorted in buckets by cost (a fixed partition of the doubles: 512
 * per octave from 2^-20 to 2^20, one bucket below and one above).  Putting
 * a key in a bucket or taking it out costs O(1); a bucket is sorted
 * (heapified) only when the heap runs dry and it is the lowest left.
 * Every key of a bucket is above every key of the buckets below it, so
 * the heap's least entry is the least of all.  Buckets are chains of fixed
 * chunks from one array on huge pages (huge_alloc.h): appends to
 * hundreds of buckets at once touch few pages.
 *
 * Where an id is queued (a heap slot or a bucket entry) is kept in a field
 * of the caller's per-id record (pos_base + id * pos_stride), so the
 * record that re-costing reads anyway says it: one cache line per id
 * touched instead of two. */
#ifndef PP5_SEED003_QUEUE_H
#define PP5_SEED003_QUEUE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "status.h"

typedef struct {
    double cost;
    uint64_t tie;          /* equal costs break on this (lower vertex ids first) */
    int32_t id;
    int32_t data;          /* the caller's, carried with the key */
} s003_qentry_t;

/* A bucket: its newest chunk (-1: none) holding n entries; the chunks
 * before it (chunk_next) are full. */
typedef struct {
    int32_t chunk, n;
} s003_bucket_t;

typedef struct {
    s003_qentry_t *heap;   /* a 4-ary min-heap: heap[0] is the least */
    int heap_n, heap_cap;
    s003_bucket_t *bucket;
    uint64_t *filled;      /* one bit per bucket that may hold entries */
    s003_qentry_t *entry;  /* the chunks' entries, S003_CHUNK per chunk */
    int32_t *chunk_next;
    int n_chunks, chunk_cap, free_chunk;
    int n_buckets;
    int front;             /* buckets below it have been emptied into the heap */
    int live;              /* ids queued */
    char *pos_base;        /* id's position: *(int64_t *)(pos_base + id * pos_stride) */
    size_t pos_stride;
} s003_queue_t;

enum { S003_CHUNK = 16 };   /* entries per chunk: six cache lines */

/* Not queued (the value every position field must start with). */
#define S003_QPOS_NONE ((int64_t)-1)

/* Ids 0 .. n_ids-1, each with its position field at pos_base + id * pos_stride. */
pp5_status_t s003_queue_init(s003_queue_t *q, int n_ids, void *pos_base, size_t pos_stride);
void s003_queue_free(s003_queue_t *q);
/* Queues id under (cost, tie) with data, or moves it there; NaN sorts last. */
pp5_status_t s003_queue_set(s003_queue_t *q, int id, double cost, uint64_t tie, int32_t data);
void s003_queue_remove(s003_queue_t *q, int id);
/* The least entry, left in place; false if the queue is empty. */
bool s003_queue_top(s003_queue_t *q, s003_qentry_t *top);
/* Every id leaves the queue. */
void s003_queue_clear(s003_queue_t *q);

static inline int64_t *s003_queue_pos(const s003_queue_t *q, int id)
{
    return (int64_t *)(q->pos_base + (size_t)id * q->pos_stride);
}
static inline bool s003_queue_has(const s003_queue_t *q, int id)
{
    return *s003_queue_pos(q, id) != S003_QPOS_NONE;
}
/* The key id is queued under (the queue must hold it). */
s003_qentry_t s003_queue_key(const s003_queue_t *q, int id);

#endif
