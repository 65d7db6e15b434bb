/* simplify_queue.c: the simplifiers' candidate queue, a 4-ary min-heap on
 * (cost, tie) that holds each id at most once and knows where it is, so a
 * re-costed candidate moves in place (no stale copies to pop and skip).
 * Four children per node halve the depth a re-costed (usually dearer)
 * candidate sinks through; their keys share a cache line or two. */
#include "simplify_work.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

pp5_status_t sw_queue_init(sw_queue_t *q, int n_ids)
{
    memset(q, 0, sizeof *q);
    size_t n = (size_t)(n_ids > 0 ? n_ids : 0) + 1;
    q->e = malloc(sizeof *q->e * n);
    q->where = malloc(sizeof *q->where * n);
    if (!q->e || !q->where) {
        sw_queue_free(q);
        return pp5_fail(PP5_E_NOMEM, "simplify: out of memory for the queue");
    }
    for (size_t i = 0; i < n; i++)
        q->where[i] = -1;
    q->n_ids = n_ids > 0 ? n_ids : 0;
    return PP5_OK;
}

void sw_queue_free(sw_queue_t *q)
{
    free(q->e);
    free(q->where);
    memset(q, 0, sizeof *q);
}

static inline bool entry_less(const sw_qentry_t *x, const sw_qentry_t *y)
{
    return x->cost < y->cost || (x->cost == y->cost && x->tie < y->tie);
}

static void sift_up(sw_queue_t *q, int i, sw_qentry_t e)
{
    while (i > 0) {
        int up = (i - 1) / 4;
        if (!entry_less(&e, &q->e[up]))
            break;
        q->e[i] = q->e[up];
        q->where[q->e[i].id] = i;
        i = up;
    }
    q->e[i] = e;
    q->where[e.id] = i;
}

static void sift_down(sw_queue_t *q, int i, sw_qentry_t e)
{
    for (;;) {
        int c = 4 * i + 1, end = c + 4 < q->n ? c + 4 : q->n;
        if (c >= q->n)
            break;
        for (int j = c + 1; j < end; j++)
            if (entry_less(&q->e[j], &q->e[c]))
                c = j;
        if (!entry_less(&q->e[c], &e))
            break;
        q->e[i] = q->e[c];
        q->where[q->e[i].id] = i;
        i = c;
    }
    q->e[i] = e;
    q->where[e.id] = i;
}

void sw_queue_append(sw_queue_t *q, int id, double cost, uint64_t tie)
{
    sw_qentry_t e = {cost == cost ? cost : INFINITY, tie, id};
    q->where[id] = q->n;
    q->e[q->n++] = e;
}

void sw_queue_heapify(sw_queue_t *q)
{
    for (int i = (q->n - 2) / 4; i >= 0 && q->n > 1; i--)
        sift_down(q, i, q->e[i]);
}

void sw_queue_set(sw_queue_t *q, int id, double cost, uint64_t tie)
{
    sw_qentry_t e = {cost == cost ? cost : INFINITY, tie, id}; /* NaN sorts last */
    int i = q->where[id];
    if (i < 0) {
        sift_up(q, q->n++, e);
        return;
    }
    if (entry_less(&e, &q->e[i]))
        sift_up(q, i, e);
    else
        sift_down(q, i, e);
}

void sw_queue_remove(sw_queue_t *q, int id)
{
    int i = q->where[id];
    if (i < 0)
        return;
    q->where[id] = -1;
    sw_qentry_t last = q->e[--q->n];
    if (i == q->n)
        return;
    if (entry_less(&last, &q->e[i]))
        sift_up(q, i, last);
    else
        sift_down(q, i, last);
}

bool sw_queue_pop(sw_queue_t *q, sw_qentry_t *out)
{
    if (q->n == 0)
        return false;
    *out = q->e[0];
    sw_queue_remove(q, out->id);
    return true;
}
