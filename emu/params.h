/* params.h: THE machine parameter table: defaults, presets, --set/--config, validation, dump.
 *
 * Every hardware constant of the emulator is one row (STYLE L5), with value,
 * unit, description and a certainty tag + citation of
 * ../shared/docs/pxpl5-facts.md.  The machine's rows are in
 * params_machine.def, the renderer/PP rows in pp_params.def (fields of
 * pp_params_t, stored in pp5_params_t.pp).  Parsing is validate-then-commit: a failing --set or
 * --config leaves the parameters unchanged, and the message names the
 * parameter, the bad value and the allowed range. */
#ifndef PP5_PARAMS_H
#define PP5_PARAMS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include "pp_params.h"
#include "util/json.h"
#include "util/status.h"

#define PARAM_CTYPE_U32 uint32_t
#define PARAM_CTYPE_U64 uint64_t
#define PARAM_CTYPE_F64 double

typedef struct {
#define PARAM(KIND, NAME, FIELD, DEF, UNIT, DESC, CITE, MIN, MAX, LO, HI) PARAM_CTYPE_##KIND FIELD;
#include "params_machine.def"
#undef PARAM
    pp_params_t pp;       /* the renderer/PP rows (pp_params.def) */
} pp5_params_t;

typedef enum { PARAM_KIND_U32, PARAM_KIND_U64, PARAM_KIND_F64 } param_kind_t;

typedef struct {
    param_kind_t kind;
    const char *name;
    size_t offset;        /* into pp5_params_t */
    double def, min, max; /* every default/limit fits a double exactly */
    /* Plausible range of the real machine's value (lo <= def <= hi); lo == hi
     * for a row that is known or is not hardware.  The sensitivity study of
     * `reproduce projections` varies each ranged row over it. */
    double plausible_lo, plausible_hi;
    const char *unit;
    const char *description;
    const char *citation;
} param_info_t;

/* The table: machine rows then PP rows, in .def order. */
size_t params_count(void);
const param_info_t *params_info(size_t i);
const param_info_t *params_find(const char *name);
/* Whether the row has a plausible range to vary (plausible_lo < plausible_hi). */
bool params_has_range(const param_info_t *row);

void pp5_params_default(pp5_params_t *p);
/* Presets: "default", "gaze1990-literal" (see params.c). */
pp5_status_t pp5_params_preset(pp5_params_t *p, const char *name);
const char *const *pp5_params_preset_names(size_t *count);
/* key=value or (key, value); strict numbers, range-checked. */
pp5_status_t pp5_params_set(pp5_params_t *p, const char *key, const char *value);
pp5_status_t pp5_params_set_kv(pp5_params_t *p, const char *key_eq_value);
/* "key = value" lines, '#' comments, blank lines; all-or-nothing. */
pp5_status_t pp5_params_load_config(pp5_params_t *p, const char *path);
/* Cross-parameter checks (screen a multiple of the region size, ...). */
pp5_status_t pp5_params_validate(const pp5_params_t *p);

/* Value of a row as double / formatted text (exact for integers). */
double params_get(const pp5_params_t *p, const param_info_t *row);
void params_format(const pp5_params_t *p, const param_info_t *row, char *buf, size_t n);

/* The machine options shared by every command that builds a machine:
 * --preset NAME, --config FILE, --set k=v (repeatable).  Applied in that
 * order (preset, then file, then each --set), all validated. */
#define PP5_PARAMS_MAX_SETS 64
typedef struct {
    const char *preset;
    const char *config;
    const char *sets[PP5_PARAMS_MAX_SETS];
    int n_sets;
} pp5_params_cli_t;
/* Record one option (returns PP5_E_CONFIG when there are too many --set). */
pp5_status_t pp5_params_cli_add_set(pp5_params_cli_t *c, const char *kv);
pp5_status_t pp5_params_build(const pp5_params_cli_t *c, pp5_params_t *out);
#define PP5_PARAMS_CLI_HELP \
    "  --preset NAME     machine preset: default, gaze1990-literal\n" \
    "  --config FILE     parameter file: 'name = value' lines, # comments\n" \
    "  --set NAME=VALUE  override one parameter (repeatable; see pp5 machine)\n"

/* Derived figures. */
double pp5_params_ring_channel_bytes_per_s(const pp5_params_t *p);
double pp5_params_ring_aggregate_bytes_per_s(const pp5_params_t *p);

/* Re-loadable text dump (one "name = value  # unit; description; citation"
 * per row) and a JSON object {name: value}. */
void pp5_params_dump(const pp5_params_t *p, FILE *out);
void pp5_params_write_json(const pp5_params_t *p, json_writer_t *j);

#endif
