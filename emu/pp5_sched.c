/* pp5_sched.c: binary-heap event queue ordered by (when, priority, seq). */
#include "pp5_sched.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void sched_init(sched_t *s)
{
    memset(s, 0, sizeof *s);
}

void sched_free(sched_t *s)
{
    free(s->heap);
    memset(s, 0, sizeof *s);
}

const char *sched_stop_name(sched_stop_t r)
{
    switch (r) {
    case SCHED_STOP_REACHED: return "REACHED";
    case SCHED_STOP_IDLE: return "IDLE";
    case SCHED_STOP_BUDGET_EXCEEDED: return "BUDGET_EXCEEDED";
    case SCHED_STOP_FIRMWARE_ERROR: return "FIRMWARE_ERROR";
    case SCHED_STOP_ERROR: return "ERROR";
    }
    return "?";
}

static int sched_before(const sched_event_t *a, const sched_event_t *b)
{
    if (a->when != b->when) {
        return a->when < b->when;
    }
    if (a->priority != b->priority) {
        return a->priority < b->priority;
    }
    return a->seq < b->seq;
}

pp5_status_t sched_at(sched_t *s, pp5_tick_t when, uint32_t priority, sched_fn fn, void *ctx,
                      uint64_t arg)
{
    PP5_ASSERT(when >= s->now, "event scheduled in the past");
    if (s->count == s->capacity) {
        size_t cap = s->capacity ? s->capacity * 2 : 64;
        size_t bytes;
        if (!pp5_mul_size(cap, sizeof *s->heap, &bytes)) {
            return pp5_fail(PP5_E_NOMEM, "event queue too large");
        }
        sched_event_t *h = realloc(s->heap, bytes);
        if (!h) {
            return pp5_fail(PP5_E_NOMEM, "out of memory growing the event queue to %zu events", cap);
        }
        s->heap = h;
        s->capacity = cap;
    }
    sched_event_t ev = { when, priority, s->next_seq++, fn, ctx, arg };
    size_t i = s->count++;
    while (i > 0) {
        size_t parent = (i - 1) / 2;
        if (!sched_before(&ev, &s->heap[parent])) {
            break;
        }
        s->heap[i] = s->heap[parent];
        i = parent;
    }
    s->heap[i] = ev;
    return PP5_OK;
}

pp5_tick_t sched_next_time(const sched_t *s)
{
    return s->count ? s->heap[0].when : PP5_TICK_MAX;
}

static sched_event_t sched_pop(sched_t *s)
{
    sched_event_t top = s->heap[0];
    sched_event_t last = s->heap[--s->count];
    size_t i = 0;
    for (;;) {
        size_t c = 2 * i + 1;
        if (c >= s->count) {
            break;
        }
        if (c + 1 < s->count && sched_before(&s->heap[c + 1], &s->heap[c])) {
            c++;
        }
        if (!sched_before(&s->heap[c], &last)) {
            break;
        }
        s->heap[i] = s->heap[c];
        i = c;
    }
    if (s->count > 0) {
        s->heap[i] = last;
    }
    return top;
}

pp5_status_t sched_run_until(sched_t *s, pp5_tick_t t_end, sched_stop_t *reason)
{
    while (s->count > 0 && s->heap[0].when <= t_end) {
        sched_event_t ev = sched_pop(s);
        s->now = ev.when;
        s->events_run++;
        pp5_status_t st = ev.fn(ev.ctx, ev.arg, ev.when);
        if (st != PP5_OK) {
            *reason = st == PP5_E_FIRMWARE ? SCHED_STOP_FIRMWARE_ERROR : SCHED_STOP_ERROR;
            return st;
        }
    }
    if (s->count == 0) {
        *reason = SCHED_STOP_IDLE;
    } else {
        s->now = t_end;
        *reason = SCHED_STOP_REACHED;
    }
    return PP5_OK;
}

pp5_status_t sched_run_budget(sched_t *s, pp5_tick_t budget_end, sched_stop_t *reason)
{
    pp5_tick_t started = s->now;
    pp5_status_t st = sched_run_until(s, budget_end, reason);
    if (st != PP5_OK || *reason != SCHED_STOP_REACHED) {
        return st;
    }
    *reason = SCHED_STOP_BUDGET_EXCEEDED;
    char busy[512] = "";
    if (s->describe_busy) {
        s->describe_busy(s->describe_ctx, busy, sizeof busy);
    }
    return pp5_fail(PP5_E_MACHINE, "emulated-time budget of %.6g s (run from %.6g s to %.6g s) "
                    "exceeded with %zu events pending; busy: %s",
                    ticks_to_s(budget_end - started), ticks_to_s(started), ticks_to_s(budget_end),
                    s->count, busy[0] ? busy : "(no unit description)");
}
