/* pp5_sched.h: the event queue: a binary heap ordered by (when, priority, seq), bounded runs with stop reasons.
 *
 * Events exist only at interactions between units (a ring message arriving,
 * a renderer finishing a command, a GP ready for its next message); between
 * events units run in batches and charge cycles locally (STYLE L4).  Ties are
 * broken by priority (lower first) then by seq, the insertion number, so
 * the order never depends on pointers or host threads.
 *
 * A callback returning non-OK stops the run: PP5_E_FIRMWARE gives stop
 * reason FIRMWARE_ERROR, anything else ERROR; the callback's pp5_fail text
 * is kept. */
#ifndef PP5_SCHED_H
#define PP5_SCHED_H

#include <stddef.h>
#include <stdint.h>
#include "pp5_time.h"
#include "util/status.h"

typedef pp5_status_t (*sched_fn)(void *ctx, uint64_t arg, pp5_tick_t now);

typedef struct {
    pp5_tick_t when;
    uint32_t priority;
    uint64_t seq;
    sched_fn fn;
    void *ctx;
    uint64_t arg;
} sched_event_t;

typedef enum {
    SCHED_STOP_REACHED = 0,       /* now == t_end, events remain after it */
    SCHED_STOP_IDLE,              /* queue empty (now = time of the last event) */
    SCHED_STOP_BUDGET_EXCEEDED,   /* sched_run_budget: work remains past the budget */
    SCHED_STOP_FIRMWARE_ERROR,    /* a callback returned PP5_E_FIRMWARE */
    SCHED_STOP_ERROR              /* a callback returned another error */
} sched_stop_t;

/* Writes a description of the units still busy (for budget messages). */
typedef void (*sched_busy_fn)(void *ctx, char *buf, size_t n);

typedef struct {
    sched_event_t *heap;
    size_t count, capacity;
    uint64_t next_seq;
    pp5_tick_t now;
    uint64_t events_run;
    sched_busy_fn describe_busy;
    void *describe_ctx;
} sched_t;

/* Event priorities: at the same instant, deliveries happen before the work
 * they enable is started, so a unit sees everything that arrived "now". */
enum {
    SCHED_PRIO_DELIVER = 10,
    SCHED_PRIO_UNIT = 20,
    SCHED_PRIO_LATE = 30
};

void sched_init(sched_t *s);
void sched_free(sched_t *s);
const char *sched_stop_name(sched_stop_t r);

/* Schedule fn(ctx, arg, when) at `when` (>= now; earlier is an invariant
 * violation). */
pp5_status_t sched_at(sched_t *s, pp5_tick_t when, uint32_t priority, sched_fn fn, void *ctx,
                      uint64_t arg);
/* Time of the next event, or PP5_TICK_MAX when empty. */
pp5_tick_t sched_next_time(const sched_t *s);

/* Run every event with when <= t_end.  Returns PP5_OK for REACHED/IDLE or
 * the failing callback's status. */
pp5_status_t sched_run_until(sched_t *s, pp5_tick_t t_end, sched_stop_t *reason);
/* Like run_until(budget_end) but REACHED becomes BUDGET_EXCEEDED with a
 * PP5_E_RANGE message naming the busy units. */
pp5_status_t sched_run_budget(sched_t *s, pp5_tick_t budget_end, sched_stop_t *reason);

#endif
