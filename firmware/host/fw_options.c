/* fw_options.c: the firmware's own settings (work division, shading split, band planning, 2DLevel method) and their KEY=VALUE form among the --set items. */
#include "fw_session.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const division_names[FW_DIVISION_COUNT] = {"image-bands", "resident",
                                                              "object-slabs"};

void fw_options_default(fw_options_t *o)
{
    memset(o, 0, sizeof *o);
    o->division = FW_DIVISION_IMAGE_BANDS;
    o->split = VR_SPLIT_PP;
    o->plan = FW_PLAN_SAMPLES;
    o->level_tables = true;
    o->unit_edge = 8;
    o->tiles = 4;
}

const char *fw_division_name(fw_division_t d)
{
    return (unsigned)d < FW_DIVISION_COUNT ? division_names[d] : "?";
}

static pp5_status_t choose(const char *key, const char *value, const char *const *names, int n,
                           int *out)
{
    for (int i = 0; i < n; i++)
        if (strcmp(value, names[i]) == 0) {
            *out = i;
            return PP5_OK;
        }
    char list[256] = "";
    for (int i = 0; i < n; i++)
        snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", i ? ", " : "", names[i]);
    return pp5_fail(PP5_E_CONFIG, "%s=%s: expected one of %s", key, value, list);
}

pp5_status_t fw_options_set(fw_options_t *o, const char *kv, bool *taken)
{
    static const char *const splits[] = {"pp", "gp"}, *const plans[] = {"rays", "samples"},
                             *const bools[] = {"0", "1"};
    *taken = false;
    const char *eq = strchr(kv, '=');
    if (!eq)
        return PP5_OK;
    char key[32];
    size_t klen = (size_t)(eq - kv);
    if (klen >= sizeof key)
        return PP5_OK;
    memcpy(key, kv, klen);
    key[klen] = '\0';
    const char *v = eq + 1;
    int i = 0;
    pp5_status_t st = PP5_OK;
    if (strcmp(key, "division") == 0) {
        st = choose(key, v, division_names, FW_DIVISION_COUNT, &i);
        o->division = (fw_division_t)i;
    } else if (strcmp(key, "split") == 0) {
        st = choose(key, v, splits, 2, &i);
        o->split = i == 0 ? VR_SPLIT_PP : VR_SPLIT_GP;
    } else if (strcmp(key, "plan") == 0) {
        st = choose(key, v, plans, 2, &i);
        o->plan = (fw_plan_t)i;
    } else if (strcmp(key, "level_tables") == 0) {
        st = choose(key, v, bools, 2, &i);
        o->level_tables = i == 1;
    } else if (strcmp(key, "unit_edge") == 0 || strcmp(key, "tiles") == 0) {
        bool edge = strcmp(key, "unit_edge") == 0;
        char *end;
        long n = strtol(v, &end, 10);
        if (*v == '\0' || *end || n < 1 || n > (edge ? 64 : VR_TILES_MAX))
            st = pp5_fail(PP5_E_CONFIG, "%s=%s: expected an integer 1..%d", key, v,
                          edge ? 64 : VR_TILES_MAX);
        else if (edge)
            o->unit_edge = (int)n;
        else
            o->tiles = (int)n;
    } else {
        return PP5_OK;
    }
    *taken = true;
    return st;
}

void fw_options_format(const fw_options_t *o, char *buf, size_t n)
{
    snprintf(buf, n, "division=%s split=%s plan=%s level_tables=%d unit_edge=%d tiles=%d",
             fw_division_name(o->division), o->split == VR_SPLIT_PP ? "pp" : "gp",
             o->plan == FW_PLAN_RAYS ? "rays" : "samples", o->level_tables ? 1 : 0, o->unit_edge,
             o->tiles);
}
