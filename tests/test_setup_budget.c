/* test_setup_budget.c: machine_run_setup is bounded by sim.setup_budget_s, not by
 * the per-frame sim.budget_s (and frames still by sim.budget_s). */
#include <string.h>

#include "harness.h"
#include "firmware/common/testpattern_gp.h"
#include "machine.h"

static void small_params(pp5_params_t *p)
{
    pp5_params_default(p);
    p->n_gp = 2;
    p->n_renderers = 2;
    p->fb_width = 256;
    p->fb_height = 128;
}

/* Emulated length of the test pattern's setup (program loads) with roomy budgets. */
static double setup_seconds(void)
{
    pp5_params_t p;
    small_params(&p);
    machine_t m;
    sched_stop_t why = SCHED_STOP_IDLE;
    double s = -1;
    if (machine_init(&m, &p) != PP5_OK)
        return s;
    if (machine_load_all(&m, &testpattern_program) == PP5_OK &&
        machine_run_setup(&m, &why) == PP5_OK && why == SCHED_STOP_IDLE)
        s = ticks_to_s(m.setup_ps);
    machine_free(&m);
    return s;
}

TEST(machine_setup_budget_default_is_generous)
{
    pp5_params_t p;
    pp5_params_default(&p);
    /* Run control: minutes of emulated setup must fit (the paper's mip-map
     * build took 5 minutes, seed paper §6), unlike one frame. */
    CHECK(p.sim_setup_budget_s >= 300.0);
    CHECK(p.sim_setup_budget_s > p.sim_budget_s);
    REQUIRE(pp5_params_set_kv(&p, "sim.setup_budget_s=42") == PP5_OK);
    CHECK_NEAR(p.sim_setup_budget_s, 42.0, 0);
    CHECK(pp5_params_set_kv(&p, "sim.setup_budget_s=0") == PP5_E_CONFIG);
}

TEST(machine_setup_budget_bounds_setup_not_frame_budget)
{
    double need_s = setup_seconds();
    REQUIRE(need_s > 2e-6);          /* long enough to cut with a 1 us budget */

    /* A frame budget far below the setup's length does not stop the setup. */
    pp5_params_t p;
    small_params(&p);
    p.sim_budget_s = need_s / 2;
    machine_t m;
    sched_stop_t why = SCHED_STOP_IDLE;
    REQUIRE(machine_init(&m, &p) == PP5_OK);
    REQUIRE(machine_load_all(&m, &testpattern_program) == PP5_OK);
    CHECK_EQ(machine_run_setup(&m, &why), PP5_OK);
    CHECK_EQ(why, SCHED_STOP_IDLE);
    CHECK_NEAR(ticks_to_s(m.setup_ps), need_s, 1e-12);
    machine_free(&m);

    /* A setup budget below its length stops it, naming the parameter. */
    small_params(&p);
    p.sim_setup_budget_s = 1e-6;
    REQUIRE(machine_init(&m, &p) == PP5_OK);
    REQUIRE(machine_load_all(&m, &testpattern_program) == PP5_OK);
    CHECK_EQ(machine_run_setup(&m, &why), PP5_E_MACHINE);
    CHECK_EQ(why, SCHED_STOP_BUDGET_EXCEEDED);
    CHECK(strstr(pp5_error_text(), "sim.setup_budget_s") != NULL);
    machine_free(&m);
}
