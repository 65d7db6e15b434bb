/* test_gp_alloc.c: fw_alloc / fw_free with reuse of freed large blocks: memory
 * comes back zeroed, local-memory accounting is by requested bytes, and the
 * capacity limit is unchanged. */
#include <stdint.h>
#include <string.h>

#include "harness.h"
#include "machine.h"

static int g_checks_failed, g_checks_run;

static void expect(int ok)
{
    g_checks_run++;
    g_checks_failed += !ok;
}

static int all_zero(const uint8_t *p, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (p[i])
            return 0;
    return 1;
}

/* Runs on GP 0 at setup: allocation patterns of a frame loop. */
static fw_status_t churn_start(gp_t *gp)
{
    const size_t big = 300000, image = 1024;
    for (int round = 0; round < 3; round++) {
        uint8_t *a = fw_alloc(gp, big);
        uint8_t *b = fw_alloc(gp, big - 1000 * (size_t)round);   /* slightly smaller each round */
        expect(a && b);
        if (!a || !b)
            return FW_OK;
        expect(all_zero(a, big) && all_zero(b, big - 1000 * (size_t)round));
        expect(fw_mem_used_bytes(gp) == image + 2 * big - 1000 * (uint64_t)round);
        memset(a, 0xa5, big);
        memset(b, 0x5a, big - 1000 * (size_t)round);
        fw_free(gp, b);
        fw_free(gp, a);
        expect(fw_mem_used_bytes(gp) == image);
    }
    /* A much smaller request must not be served from (and dirty) a big block,
     * and still comes back zeroed. */
    uint8_t *small = fw_alloc(gp, 70000);
    expect(small && all_zero(small, 70000));
    /* The capacity limit counts live bytes only, never the kept spare blocks:
     * 1024 + 70000 + 900000 <= 1000000. */
    uint8_t *large = fw_alloc(gp, 900000);
    expect(large && all_zero(large, 900000));
    expect(fw_mem_used_bytes(gp) == image + 70000 + 900000);
    fw_free(gp, large);
    fw_free(gp, small);
    return FW_OK;
}

static const fw_program_t churn_prog = {"churn", 1024, churn_start, NULL};

TEST(gp_alloc_reuse_zeroed_and_accounted)
{
    pp5_params_t p;
    pp5_params_default(&p);
    p.n_gp = 1;
    p.n_renderers = 1;
    p.fb_width = 128;
    p.fb_height = 128;
    p.gp_local_mem_bytes = 1000000;
    machine_t m;
    REQUIRE(machine_init(&m, &p) == PP5_OK);
    REQUIRE(machine_load_program(&m, 0, &churn_prog, NULL, 0) == PP5_OK);
    g_checks_failed = g_checks_run = 0;
    sched_stop_t why;
    CHECK_EQ(machine_run_setup(&m, &why), PP5_OK);
    CHECK_EQ(why, SCHED_STOP_IDLE);
    CHECK_EQ(g_checks_run, 3 * 4 + 3);
    CHECK_EQ(g_checks_failed, 0);
    CHECK_EQ(m.gp[0].mem_peak_bytes, 1024 + 70000 + 900000);
    machine_free(&m);
}
