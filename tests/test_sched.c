/* test_sched.c: event order (when, priority, seq), bounded runs and stop reasons. */
#include <string.h>
#include "harness.h"
#include "pp5_sched.h"

typedef struct {
    int order[64];
    int n;
    sched_t *s;
} log_t;

static pp5_status_t record(void *ctx, uint64_t arg, pp5_tick_t now)
{
    log_t *l = ctx;
    l->order[l->n++] = (int)arg;
    return PP5_OK;
}

TEST(sched_orders_by_time_priority_then_insertion)
{
    sched_t s;
    sched_init(&s);
    log_t l = { .n = 0 };
    /* Inserted out of order; expected order by (when, prio, seq). */
    sched_at(&s, 300, 5, record, &l, 0);
    sched_at(&s, 100, 9, record, &l, 1);
    sched_at(&s, 100, 1, record, &l, 2);
    sched_at(&s, 200, 5, record, &l, 3);
    sched_at(&s, 100, 9, record, &l, 4);   /* same (when, prio) as 1: after it */
    sched_at(&s, 0, 5, record, &l, 5);
    sched_stop_t why;
    pp5_status_t st = sched_run_until(&s, 1000, &why);
    CHECK_EQ(st, PP5_OK);
    CHECK_EQ(why, SCHED_STOP_IDLE);
    int want[] = { 5, 2, 1, 4, 3, 0 };
    CHECK_EQ(l.n, 6);
    for (int i = 0; i < 6; i++) {
        CHECK_EQ(l.order[i], want[i]);
    }
    CHECK_EQ(s.now, 300);
    sched_free(&s);
}

TEST(sched_many_events_come_out_sorted)
{
    sched_t s;
    sched_init(&s);
    log_t l = { .n = 0 };
    /* 60 events with times from a fixed permutation (i*37 mod 60). */
    for (int i = 0; i < 60; i++) {
        sched_at(&s, (pp5_tick_t)((i * 37) % 60) * 10, 0, record, &l, (uint64_t)((i * 37) % 60));
    }
    sched_stop_t why;
    sched_run_until(&s, PP5_TICK_MAX, &why);
    CHECK_EQ(l.n, 60);
    /* Event k was scheduled at time 10 k, so it must be the k-th to run. */
    for (int i = 0; i < 60; i++) {
        CHECK_MSG(l.order[i] == i, "run %d was the event at t = %d, want t = %d", i,
                  10 * l.order[i], 10 * i);
    }
    sched_free(&s);
}

TEST(sched_run_until_stops_at_the_limit)
{
    sched_t s;
    sched_init(&s);
    log_t l = { .n = 0 };
    sched_at(&s, 100, 0, record, &l, 1);
    sched_at(&s, 500, 0, record, &l, 2);
    sched_stop_t why;
    pp5_status_t st = sched_run_until(&s, 499, &why);
    CHECK_EQ(st, PP5_OK);
    CHECK_EQ(why, SCHED_STOP_REACHED);
    CHECK_EQ(l.n, 1);
    CHECK_EQ(s.now, 499);
    CHECK_EQ(sched_next_time(&s), 500);
    sched_free(&s);
}

static pp5_status_t fail_fw(void *ctx, uint64_t arg, pp5_tick_t now)
{
    return pp5_fail(PP5_E_FIRMWARE, "test firmware error at %llu", (unsigned long long)now);
}

TEST(sched_firmware_error_stops_the_run)
{
    sched_t s;
    sched_init(&s);
    log_t l = { .n = 0 };
    sched_at(&s, 10, 0, fail_fw, NULL, 0);
    sched_at(&s, 20, 0, record, &l, 1);
    sched_stop_t why;
    pp5_status_t st = sched_run_until(&s, 100, &why);   /* not inside CHECK_EQ: it evaluates twice */
    CHECK_EQ(st, PP5_E_FIRMWARE);
    CHECK_EQ(why, SCHED_STOP_FIRMWARE_ERROR);
    CHECK_EQ(l.n, 0);
    CHECK(strstr(pp5_error_text(), "test firmware error at 10") != NULL);
    sched_free(&s);
}

static void busy_names(void *ctx, char *buf, size_t n)
{
    snprintf(buf, n, "renderer 3");
}

TEST(sched_budget_exceeded_names_busy_units)
{
    sched_t s;
    sched_init(&s);
    s.describe_busy = busy_names;
    log_t l = { .n = 0 };
    sched_at(&s, 2000, 0, record, &l, 1);
    sched_stop_t why;
    pp5_status_t st = sched_run_budget(&s, 1000, &why);
    CHECK_EQ(st, PP5_E_MACHINE);
    CHECK_EQ(why, SCHED_STOP_BUDGET_EXCEEDED);
    CHECK(strstr(pp5_error_text(), "renderer 3") != NULL);
    sched_free(&s);
}
