/* replay_options.c: the frame-cost sources' option strings (replay_options.h). */
#include "replay_options.h"

#include <stdio.h>
#include <string.h>

pp5_status_t replay_options_each(const char *source, const char *text, replay_option_fn item,
                                 void *ctx)
{
    char buf[2048];
    if (strlen(text) >= sizeof buf)
        return pp5_fail(PP5_E_CONFIG, "%s: options too long", source);
    snprintf(buf, sizeof buf, "%s", text);
    for (char *save = NULL, *it = strtok_r(buf, ",", &save); it; it = strtok_r(NULL, ",", &save)) {
        pp5_status_t st = item(ctx, it);
        if (st != PP5_OK)
            return st;
    }
    return PP5_OK;
}

void replay_machine_params_init(replay_machine_params_t *mp)
{
    memset(mp, 0, sizeof *mp);
    snprintf(mp->preset, sizeof mp->preset, "default");
}

pp5_status_t replay_machine_params_unwrap(const char *source, const char **item)
{
    if (strncmp(*item, "set=", 4) != 0)
        return PP5_OK;
    const char *value = *item + 4;
    if (!strchr(value, '='))
        return pp5_fail(PP5_E_CONFIG, "%s: set= wants PARAM=VALUE, got '%s'", source, value);
    *item = value;
    return PP5_OK;
}

bool replay_machine_params_add(replay_machine_params_t *mp, const char *item)
{
    if (mp->params.n_sets >= PP5_PARAMS_MAX_SETS || strlen(item) >= sizeof mp->sets[0])
        return false;
    char *copy = mp->sets[mp->params.n_sets];
    snprintf(copy, sizeof mp->sets[0], "%s", item);
    return pp5_params_cli_add_set(&mp->params, copy) == PP5_OK;
}

pp5_status_t replay_machine_params_build(replay_machine_params_t *mp, pp5_params_t *out)
{
    mp->params.preset = mp->preset;
    pp5_status_t st = pp5_params_build(&mp->params, out);
    return st == PP5_OK ? pp5_params_validate(out) : st;
}
