/* cmd_replay.h: the parts of `pp5 replay` that live in their own files
 * (cmd_replay_*.c), called by cmd_replay.c. */
#ifndef PP5_CMD_REPLAY_H
#define PP5_CMD_REPLAY_H

#include "tracker/replay.h"

/* --predict landing: the landing error per amplitude bin against the true
 * landings (the trace's saccade labels, or the adaptive detector's). */
pp5_status_t replay_print_landing(const trace_t *t, const replay_params_t *p);

#endif
