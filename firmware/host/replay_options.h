/* replay_options.h: the option strings of the emulated machine's frame-cost
 * sources for `pp5 replay --cost NAME:OPTIONS` (replay_machine.c,
 * replay_poly_machine.c): comma-separated KEY=VALUE items, and the machine
 * parameters among them, given as PARAM=VALUE or set=PARAM=VALUE the way
 * `pp5 machine --set` takes them, on top of preset=NAME. */
#ifndef PP5_REPLAY_OPTIONS_H
#define PP5_REPLAY_OPTIONS_H

#include "params.h"

/* Calls item(ctx, ITEM) for each comma-separated item of text, stopping at
 * the first failure; `source` names the option in errors ("--cost machine"). */
typedef pp5_status_t (*replay_option_fn)(void *ctx, const char *item);
pp5_status_t replay_options_each(const char *source, const char *text, replay_option_fn item,
                                 void *ctx);

/* The machine parameters of a cost source's options. */
typedef struct {
    char preset[64];
    pp5_params_cli_t params;
    char sets[PP5_PARAMS_MAX_SETS][128];
} replay_machine_params_t;

void replay_machine_params_init(replay_machine_params_t *mp);
/* set=PARAM=VALUE gives PARAM=VALUE in *item; anything else is left as it is. */
pp5_status_t replay_machine_params_unwrap(const char *source, const char **item);
/* Keeps PARAM=VALUE for the build; false when there is no room (too many or
 * too long), for the caller to name its own options in the error. */
bool replay_machine_params_add(replay_machine_params_t *mp, const char *item);
/* The parameter table: preset, then the settings in order, validated. */
pp5_status_t replay_machine_params_build(replay_machine_params_t *mp, pp5_params_t *out);

#endif
