/* cmd_replay.h: the parts of `pp5 replay` that live in their own files
 * (cmd_replay_*.c), called by cmd_replay.c. */
#ifndef PP5_CMD_REPLAY_H
#define PP5_CMD_REPLAY_H

#include "tracker/replay.h"

/* --predict landing: the landing error per amplitude bin against the true
 * landings (the trace's saccade labels, or the adaptive detector's). */
pp5_status_t replay_print_landing(const trace_t *t, const replay_params_t *p);

/* --sweep-latency (cmd_replay_sweep.c). */
#define REPLAY_SWEEP_MAX_MACHINES 16
typedef struct {
    double from_ms, to_ms, step_ms;          /* default 10..200 by 10 */
    const char *machines[REPLAY_SWEEP_MAX_MACHINES];   /* machine settings, each
                                                "KEY=VALUE KEY=VALUE ..." */
    int n_machines;
    size_t machine_frames;                   /* frames emulated per configuration (4) */
} replay_sweep_t;

void replay_sweep_defaults(replay_sweep_t *s);
pp5_status_t replay_sweep_latency(const trace_t *t, const replay_params_t *p,
                                  const replay_sweep_t *s);

#endif
