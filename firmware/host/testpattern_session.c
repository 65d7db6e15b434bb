/* testpattern_session.c: loads and runs the test-pattern program (see testpattern_session.h). */
#include "testpattern_session.h"

#include "firmware/common/testpattern_gp.h"

pp5_status_t testpattern_session_load(machine_t *m, sched_stop_t *stop)
{
    pp5_status_t st = machine_load_all(m, &testpattern_program);
    if (st == PP5_OK) {
        st = machine_run_setup(m, stop);
    }
    return st;
}

pp5_status_t testpattern_session_run(machine_t *m, long frames, sched_stop_t *stop)
{
    if (frames < 1 || frames > MACHINE_MAX_FRAMES) {
        return pp5_fail(PP5_E_RANGE, "test pattern: %ld frames (allowed 1..%d)", frames,
                        MACHINE_MAX_FRAMES);
    }
    pp5_status_t st = testpattern_session_load(m, stop);
    for (long f = 0; st == PP5_OK && f < frames; f++) {
        st = machine_run_frame(m, stop);
    }
    return st;
}
