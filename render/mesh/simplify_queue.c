/* simplify_queue.c: the simplifiers' candidate queue, a 4-ary min-heap on
 * (cost, tie) that holds each id at most once and knows where it is, so a
 * re-costed candidate moves in place (no stale copies to pop and skip).
 *
 * Why this shape: the simplifiers spend much of their time moving
 * re-costed candidates, and each level of a move reads one node's children.
 * Four children per node halve the depth a (usually dearer) candidate sinks
 * through; with 16-byte slots and e[1] on a 64-byte boundary, the children
 * 4i+1 .. 4i+4 of every node share one cache line.  Ties (equal costs) are
 * rare, so their keys live in a side array read only then. */
#include "simplify_work.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { LINE = 64, SLOTS_PER_LINE = LINE / sizeof(sw_qslot_t) };

pp5_status_t sw_queue_init(sw_queue_t *q, int n_ids)
{
    memset(q, 0, sizeof *q);
    size_t n = (size_t)(n_ids > 0 ? n_ids : 0) + 1;
    /* room for the slots plus one line, rounded to whole lines (aligned_alloc) */
    size_t bytes = ((n + 2 * SLOTS_PER_LINE) * sizeof(sw_qslot_t) + LINE - 1) / LINE * LINE;
    q->block = aligned_alloc(LINE, bytes);
    q->tie = malloc(sizeof *q->tie * n);
    q->where = malloc(sizeof *q->where * n);
    if (!q->block || !q->tie || !q->where) {
        sw_queue_free(q);
        return pp5_fail(PP5_E_NOMEM, "simplify: out of memory for the queue");
    }
    /* e[1] starts a line, so each group of four children does too */
    q->e = (sw_qslot_t *)q->block + SLOTS_PER_LINE - 1;
    for (size_t i = 0; i < n; i++)
        q->where[i] = -1;
    q->n_ids = n_ids > 0 ? n_ids : 0;
    return PP5_OK;
}

void sw_queue_free(sw_queue_t *q)
{
    free(q->block);
    free(q->tie);
    free(q->where);
    memset(q, 0, sizeof *q);
}

static inline bool slot_less(const sw_queue_t *q, sw_qslot_t x, sw_qslot_t y)
{
    return x.cost < y.cost || (x.cost == y.cost && q->tie[x.id] < q->tie[y.id]);
}

static void sift_up(sw_queue_t *q, int i, sw_qslot_t e)
{
    while (i > 0) {
        int up = (i - 1) / 4;
        if (!slot_less(q, e, q->e[up]))
            break;
        q->e[i] = q->e[up];
        q->where[q->e[i].id] = i;
        i = up;
    }
    q->e[i] = e;
    q->where[e.id] = i;
}

static void sift_down(sw_queue_t *q, int i, sw_qslot_t e)
{
    for (;;) {
        int c = 4 * i + 1, end = c + 4 < q->n ? c + 4 : q->n;
        if (c >= q->n)
            break;
        /* The heap outgrows the cache, so each level's line of children is
         * a miss: ask for the four lines a level further down (the
         * children's children) before choosing among the children. */
        for (int g = 16 * i + 5; g < q->n && g < 16 * i + 21; g += 4)
            __builtin_prefetch(q->e + g);
        for (int j = c + 1; j < end; j++)
            if (slot_less(q, q->e[j], q->e[c]))
                c = j;
        if (!slot_less(q, q->e[c], e))
            break;
        q->e[i] = q->e[c];
        q->where[q->e[i].id] = i;
        i = c;
    }
    q->e[i] = e;
    q->where[e.id] = i;
}

/* NaN sorts last */
static inline sw_qslot_t make_slot(sw_queue_t *q, int id, double cost, uint64_t tie)
{
    q->tie[id] = tie;
    return (sw_qslot_t){cost == cost ? cost : INFINITY, id, 0};
}

void sw_queue_append(sw_queue_t *q, int id, double cost, uint64_t tie)
{
    q->where[id] = q->n;
    q->e[q->n++] = make_slot(q, id, cost, tie);
}

void sw_queue_heapify(sw_queue_t *q)
{
    for (int i = (q->n - 2) / 4; i >= 0 && q->n > 1; i--)
        sift_down(q, i, q->e[i]);
}

void sw_queue_set(sw_queue_t *q, int id, double cost, uint64_t tie)
{
    int i = q->where[id];
    if (i < 0) {
        sift_up(q, q->n++, make_slot(q, id, cost, tie));
        return;
    }
    /* the old key is compared before the tie is overwritten */
    sw_qslot_t e = {cost == cost ? cost : INFINITY, id, 0};
    bool up = e.cost < q->e[i].cost || (e.cost == q->e[i].cost && tie < q->tie[id]);
    q->tie[id] = tie;
    if (up)
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
    sw_qslot_t last = q->e[--q->n];
    if (i == q->n)
        return;
    if (slot_less(q, last, q->e[i]))
        sift_up(q, i, last);
    else
        sift_down(q, i, last);
}

bool sw_queue_pop(sw_queue_t *q, sw_qentry_t *out)
{
    if (q->n == 0)
        return false;
    *out = sw_queue_top(q);
    sw_queue_remove(q, out->id);
    return true;
}
