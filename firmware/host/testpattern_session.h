/* testpattern_session.h: the host's side of the test pattern: load the test-pattern GP program on every GP, run the loads, then the frames.
 *
 * The test pattern needs no data: every GP gets the same program
 * (firmware/gp/testpattern_gp.c, scene in firmware/common/testpattern_gp.h)
 * with an empty HOST_LOAD, the loads run to completion (machine_run_setup,
 * not a frame), and each frame is one machine_run_frame (FRAME_START to
 * every GP).  `pp5 test-pattern` and `pp5 bench ring` both run it; the
 * frame-time hand calculation is in emu/ARCHITECTURE.md. */
#ifndef PP5_TESTPATTERN_SESSION_H
#define PP5_TESTPATTERN_SESSION_H

#include "machine.h"

/* Load the program on every GP of the initialised machine m and run the
 * loads; *stop tells how the setup ended. */
pp5_status_t testpattern_session_load(machine_t *m, sched_stop_t *stop);

/* testpattern_session_load, then `frames` frames (1..MACHINE_MAX_FRAMES);
 * stops at the first error, *stop telling how the last run ended. */
pp5_status_t testpattern_session_run(machine_t *m, long frames, sched_stop_t *stop);

#endif
