/* seed003_queue.c: seed 003's candidate queue (seed003_queue.h): a small
 * 4-ary heap of the lowest keys over unsorted buckets of the others.
 *
 * Why: to 1 % of the bunny seed 003 re-keys an edge at the top of the
 * queue 166,000 times (a lower bound becomes its cost, usually far from
 * the top) and takes 417,000 frozen or re-costed edges out of the middle.
 * In one heap of 100,000 edges the first sank through eight levels and the
 * second sifted too, each level writing a position to a cold line.  Here
 * both are O(1) for keys above the heap's range, and the heap holds about
 * one bucket of keys. */
#include "seed003_queue.h"

#include "huge_alloc.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The buckets: one for keys below 2^-20 (zero and negative ones too), then
 * 2^BUCKET_STEPS_LOG2 per octave up to 2^20 (a key's bucket is read off
 * its exponent and leading mantissa bits), then one for the rest (INFINITY,
 * where NaN goes).  A bucket's keys are all above those of the buckets
 * before it: positive doubles order as their bit patterns. */
enum { BUCKET_STEPS_LOG2 = 9, OCTAVES = 40, N_BUCKETS = (OCTAVES << BUCKET_STEPS_LOG2) + 2 };
static const double LOWEST_STEPPED = 0x1p-20, ABOVE_STEPPED = 0x1p20;

static int bucket_of(double cost)
{
    if (!(cost >= LOWEST_STEPPED))
        return 0;
    if (!(cost < ABOVE_STEPPED))
        return N_BUCKETS - 1;
    uint64_t bits, low;
    memcpy(&bits, &cost, sizeof bits);
    memcpy(&low, &LOWEST_STEPPED, sizeof low);
    return 1 + (int)((bits - low) >> (52 - BUCKET_STEPS_LOG2));
}

/* A chunk entry's position: below S003_QPOS_NONE, so apart from heap slots. */
static int64_t entry_pos(int64_t entry)
{
    return -2 - entry;
}

pp5_status_t s003_queue_init(s003_queue_t *q, int n_ids, void *pos_base, size_t pos_stride)
{
    memset(q, 0, sizeof *q);
    q->pos_base = pos_base, q->pos_stride = pos_stride;
    q->n_buckets = N_BUCKETS;
    /* every id at most once: the heap never grows (untouched pages cost nothing) */
    q->heap_cap = n_ids > 0 ? n_ids : 1;
    q->heap = malloc(sizeof *q->heap * (size_t)q->heap_cap);
    q->bucket = malloc(sizeof *q->bucket * N_BUCKETS);
    q->filled = calloc((N_BUCKETS + 63) / 64, sizeof *q->filled);
    /* room for about two entries per id; more chunks if needed */
    q->chunk_cap = n_ids / (S003_CHUNK / 2) + 64;
    q->entry = huge_alloc(sizeof *q->entry * S003_CHUNK * (size_t)q->chunk_cap, false);
    q->chunk_next = malloc(sizeof *q->chunk_next * (size_t)q->chunk_cap);
    if (!q->heap || !q->bucket || !q->filled || !q->entry || !q->chunk_next) {
        s003_queue_free(q);
        return pp5_fail(PP5_E_NOMEM, "seed003: out of memory for the queue");
    }
    for (int b = 0; b < N_BUCKETS; b++)
        q->bucket[b] = (s003_bucket_t){-1, 0};
    q->free_chunk = -1;
    return PP5_OK;
}

void s003_queue_free(s003_queue_t *q)
{
    huge_free(q->entry, sizeof *q->entry * S003_CHUNK * (size_t)q->chunk_cap);
    free(q->heap), free(q->bucket), free(q->filled), free(q->chunk_next);
    memset(q, 0, sizeof *q);
}

static inline bool entry_less(const s003_qentry_t *x, const s003_qentry_t *y)
{
    return x->cost < y->cost || (x->cost == y->cost && x->tie < y->tie);
}

static inline void heap_place(s003_queue_t *q, int i, const s003_qentry_t *e)
{
    q->heap[i] = *e;
    *s003_queue_pos(q, e->id) = i;
}

static void sift_up(s003_queue_t *q, int i, s003_qentry_t e)
{
    while (i > 0) {
        int up = (i - 1) / 4;
        if (!entry_less(&e, &q->heap[up]))
            break;
        heap_place(q, i, &q->heap[up]);
        i = up;
    }
    heap_place(q, i, &e);
}

static void sift_down(s003_queue_t *q, int i, s003_qentry_t e)
{
    for (;;) {
        int c = 4 * i + 1, end = c + 4 < q->heap_n ? c + 4 : q->heap_n;
        if (c >= q->heap_n)
            break;
        for (int j = c + 1; j < end; j++)
            if (entry_less(&q->heap[j], &q->heap[c]))
                c = j;
        if (!entry_less(&q->heap[c], &e))
            break;
        heap_place(q, i, &q->heap[c]);
        i = c;
    }
    heap_place(q, i, &e);
}

static void heap_remove_at(s003_queue_t *q, int i)
{
    s003_qentry_t last = q->heap[--q->heap_n];
    if (i == q->heap_n)
        return;
    if (entry_less(&last, &q->heap[i]))
        sift_up(q, i, last);
    else
        sift_down(q, i, last);
}

/* A free chunk, or -1 (out of memory). */
static int chunk_new(s003_queue_t *q)
{
    if (q->free_chunk >= 0) {
        int c = q->free_chunk;
        q->free_chunk = q->chunk_next[c];
        return c;
    }
    if (q->n_chunks == q->chunk_cap) {   /* a copy, so the new array is on huge pages too */
        int cap = 2 * q->chunk_cap;
        int32_t *nn = realloc(q->chunk_next, sizeof *nn * (size_t)cap);
        if (!nn)
            return -1;
        q->chunk_next = nn;
        s003_qentry_t *ne = huge_grow(q->entry, sizeof *ne * S003_CHUNK * (size_t)q->n_chunks,
                                          sizeof *ne * S003_CHUNK * (size_t)q->chunk_cap,
                                          sizeof *ne * S003_CHUNK * (size_t)cap);
        if (!ne)
            return -1;
        q->entry = ne, q->chunk_cap = cap;
    }
    return q->n_chunks++;
}

static pp5_status_t bucket_append(s003_queue_t *q, int b, const s003_qentry_t *e)
{
    s003_bucket_t *bk = &q->bucket[b];
    if (bk->chunk < 0 || bk->n == S003_CHUNK) {
        int c = chunk_new(q);
        if (c < 0)
            return pp5_fail(PP5_E_NOMEM, "seed003: out of memory for the queue");
        q->chunk_next[c] = bk->chunk;
        bk->chunk = c, bk->n = 0;
    }
    int64_t at = (int64_t)bk->chunk * S003_CHUNK + bk->n++;
    *s003_queue_pos(q, e->id) = entry_pos(at);
    q->entry[at] = *e;
    q->filled[b >> 6] |= (uint64_t)1 << (b & 63);
    return PP5_OK;
}

/* An entry left behind in a bucket is marked (id -1), so merging the
 * bucket skips it without looking up where its id is now (a cache line
 * for each; three in four entries merged to 1 % of the bunny were left
 * behind).  A store, not a load to wait for. */
static void entry_leave(s003_queue_t *q, int64_t pos)
{
    q->entry[-2 - pos].id = -1;
}

pp5_status_t s003_queue_set(s003_queue_t *q, int id, double cost, uint64_t tie, int32_t data)
{
    s003_qentry_t e = {cost == cost ? cost : INFINITY, tie, id, data};
    int64_t pos = *s003_queue_pos(q, id);
    int b = bucket_of(e.cost);
    if (pos == S003_QPOS_NONE)
        q->live++;
    else if (pos < 0)
        entry_leave(q, pos);
    if (b < q->front) {   /* the heap's range */
        if (pos >= 0 && entry_less(&e, &q->heap[pos]))
            sift_up(q, (int)pos, e);
        else if (pos >= 0)
            sift_down(q, (int)pos, e);
        else
            sift_up(q, q->heap_n++, e);
        return PP5_OK;
    }
    if (pos >= 0)
        heap_remove_at(q, (int)pos);
    return bucket_append(q, b, &e);
}

void s003_queue_remove(s003_queue_t *q, int id)
{
    int64_t *pos = s003_queue_pos(q, id), at = *pos;
    if (at == S003_QPOS_NONE)
        return;
    *pos = S003_QPOS_NONE;
    q->live--;
    if (at >= 0)
        heap_remove_at(q, (int)at);
    else
        entry_leave(q, at);
}

s003_qentry_t s003_queue_key(const s003_queue_t *q, int id)
{
    int64_t pos = *s003_queue_pos(q, id);
    return pos >= 0 ? q->heap[pos] : q->entry[-2 - pos];
}

/* The first bucket from b on that may hold entries, or -1. */
static int next_filled(const s003_queue_t *q, int b)
{
    for (int w = b >> 6; w < (q->n_buckets + 63) / 64; w++) {
        uint64_t bits = q->filled[w];
        if (w == b >> 6)
            bits &= ~(uint64_t)0 << (b & 63);
        if (bits)
            return 64 * w + __builtin_ctzll(bits);
    }
    return -1;
}

/* Bucket b is emptied; its chunks are free again. */
static void bucket_empty(s003_queue_t *q, int b)
{
    s003_bucket_t *bk = &q->bucket[b];
    for (int c = bk->chunk, next; c >= 0; c = next) {
        next = q->chunk_next[c];
        q->chunk_next[c] = q->free_chunk;
        q->free_chunk = c;
    }
    *bk = (s003_bucket_t){-1, 0};
    q->filled[b >> 6] &= ~((uint64_t)1 << (b & 63));
}

/* Moves bucket b's entries that are still current into the empty heap. */
static void bucket_to_heap(s003_queue_t *q, int b)
{
    const s003_bucket_t *bk = &q->bucket[b];
    for (int c = bk->chunk, n = bk->n; c >= 0; c = q->chunk_next[c], n = S003_CHUNK) {
        const s003_qentry_t *e = q->entry + (int64_t)c * S003_CHUNK;
        for (int i = 0; i < n; i++)
            if (e[i].id >= 0)
                heap_place(q, q->heap_n++, &e[i]);
    }
    bucket_empty(q, b);
    for (int i = (q->heap_n - 2) / 4; i >= 0 && q->heap_n > 1; i--)
        sift_down(q, i, q->heap[i]);
}

bool s003_queue_top(s003_queue_t *q, s003_qentry_t *top)
{
    while (q->heap_n == 0) {
        int b = q->live > 0 ? next_filled(q, q->front) : -1;
        if (b < 0) {   /* empty: the next keys may start anywhere */
            for (b = next_filled(q, 0); b >= 0; b = next_filled(q, b + 1)) {
                q->bucket[b] = (s003_bucket_t){-1, 0};
                q->filled[b >> 6] &= ~((uint64_t)1 << (b & 63));
            }
            q->front = 0, q->n_chunks = 0, q->free_chunk = -1;
            return false;
        }
        q->front = b + 1;
        bucket_to_heap(q, b);
    }
    *top = q->heap[0];
    return true;
}

void s003_queue_clear(s003_queue_t *q)
{
    for (int i = 0; i < q->heap_n; i++)
        *s003_queue_pos(q, q->heap[i].id) = S003_QPOS_NONE;
    for (int b = next_filled(q, 0); b >= 0; b = next_filled(q, b + 1)) {
        const s003_bucket_t *bk = &q->bucket[b];
        for (int c = bk->chunk, n = bk->n; c >= 0; c = q->chunk_next[c], n = S003_CHUNK)
            for (int i = 0; i < n; i++) {
                int64_t at = (int64_t)c * S003_CHUNK + i;
                if (q->entry[at].id >= 0)
                    *s003_queue_pos(q, q->entry[at].id) = S003_QPOS_NONE;
            }
        bucket_empty(q, b);
    }
    q->heap_n = 0, q->front = 0, q->live = 0;
    q->n_chunks = 0, q->free_chunk = -1;
}
