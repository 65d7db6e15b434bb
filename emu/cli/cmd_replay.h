/* cmd_replay.h: the parts of `pp5 replay` that live in their own files
 * (cmd_replay_*.c), called by cmd_replay.c. */
#ifndef PP5_CMD_REPLAY_H
#define PP5_CMD_REPLAY_H

#include "json.h"
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

/* Everything the command line chose (cmd_replay.c); the batch
 * (cmd_replay_batch.c) parses each line of its list into a copy. */
typedef struct {
    replay_params_t p;
    char cost_spec[256];          /* NAME[:OPTIONS] */
    bool cost_given;              /* --cost or --frame-time-ms was given */
    const char *scene, *mesh;     /* --scene / --mesh: folded into cost_spec after parsing */
    const char *report, *csv, *plot, *frames_dir, *live, *live_seconds;
    bool sweep;
    replay_sweep_t sw;
    /* --batch LIST and how it runs (emu/util/workunit.h). */
    const char *batch, *out, *accounting;
    bool resume;
    unsigned shard_k, shard_n;
    bool in_list;                 /* parsing a line of LIST: no usage text on errors */
} replay_cli_t;

void replay_cli_defaults(replay_cli_t *o);
/* getopt over argv (argv[0] is skipped) into *o; *done (with *rc) after
 * --help or an unknown option.  optind is left after the last option. */
pp5_status_t replay_cli_parse(replay_cli_t *o, int argc, char **argv, bool *done, int *rc);
pp5_status_t replay_cli_option(int c, const char *arg, replay_cli_t *o, bool *done, int *rc);

/* The "summary" object of a replay's JSON report (cmd_replay.c). */
void replay_summary_json(json_writer_t *j, const replay_summary_t *s);

/* --batch LIST (cmd_replay_batch.c): returns the exit code. */
int replay_batch_main(const replay_cli_t *o);

#endif
