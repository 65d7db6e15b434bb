/* cmd_trace.h: the `pp5 trace` subcommands that live in their own files
 * (cmd_trace_*.c), dispatched by cmd_trace.c. */
#ifndef PP5_CMD_TRACE_H
#define PP5_CMD_TRACE_H

#include "tracker/trace_file.h"

int cmd_trace_events(int argc, char **argv);
/* pp5 trace info's event statistics and data quality (adaptive detector). */
pp5_status_t trace_info_print_events(const trace_t *t);

#endif
