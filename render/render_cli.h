/* render_cli.h: what `pp5 render` does once its options are parsed (load,
 * render, write image/figures/report), kept apart from option parsing. */
#ifndef PP5_RENDER_CLI_H
#define PP5_RENDER_CLI_H

#include <stdbool.h>
#include <stdio.h>
#include "renderer_native.h"
#include "scene.h"

typedef enum { RENDER_INPUT_PHANTOM, RENDER_INPUT_DATASET, RENDER_INPUT_FILE } render_input_t;

typedef struct {
    render_input_t input;
    const char *input_name;
    volume_raw_spec_t raw;
    bool have_raw, have_spacing, have_tf, have_rot, have_gaze;
    classify_tf_t tf;
    shade_params_t shade;
    render_settings_t settings;
    int progressive_frames;       /* 0 = a single ordinary frame */
    const char *out_png, *report_json, *levels_prefix, *fig5_png;
    bool compare;
} render_cli_t;

void render_cli_defaults(render_cli_t *c);
pp5_status_t render_cli_run(render_cli_t *c, FILE *log);
/* Loads the command's input (phantom, shared dataset or file) into a scene,
 * noting a fallback on `log`; used by the machine path too. */
pp5_status_t render_cli_load_input(const render_cli_t *c, scene_t *sc, FILE *log);

/* Figure 5: target and quantized resolution against distance from the gaze
 * point, for the display model of `g`. */
pp5_status_t render_write_fig5(const gaze_model_t *g, const char *path);
/* Figure 6: each level of the 2D mip map as PREFIX<level>.png, texels whose
 * ray was cast in colour, unpopulated texels dark grey. */
pp5_status_t render_write_mip_levels(const mip2d_t *m, const char *prefix);

#endif
