/* fw_render.h: `pp5 render --machine`: the native render command's options, run on the emulated machine, with the frame report. */
#ifndef PP5_FW_RENDER_H
#define PP5_FW_RENDER_H

#include <stdbool.h>
#include <stdio.h>
#include "fw_session.h"
#include "params.h"
#include "render/render_cli.h"
#include "render/scene.h"

#define FW_RENDER_MAX_ARGS 256

typedef struct {
    bool machine;                 /* --machine given */
    int split;                    /* --split pp|gp */
    const char *timeline;         /* --timeline FILE */
    int frames;                   /* --frames N (gaze moves across the image) */
    pp5_params_cli_t params;      /* --preset, --config, --set */
} fw_render_opts_t;

/* Removes the machine-only options from argv (into o) so the native parser
 * sees only its own; returns the new argc (argv is rewritten in place). */
int fw_render_filter_args(int argc, char **argv, fw_render_opts_t *o, pp5_status_t *st);
/* Runs the parsed render command on the machine. */
pp5_status_t fw_render_cli_run(render_cli_t *c, const fw_render_opts_t *o, FILE *log);
const char *fw_render_help(void);

/* The image comparison printed by `pp5 render --machine` (also in the report). */
typedef struct {
    bool have;
    double psnr_native_db, max_diff_native;       /* vs render/ itself */
    double psnr_like_db, max_diff_like;           /* vs render/ on the machine's formats */
    uint64_t native_rays, native_samples;
} fw_compare_t;

/* Writes the frame report JSON (cmp may be NULL). */
pp5_status_t fw_write_report(const char *path, const fw_session_t *s, const fw_frame_result_t *r,
                             const char *volume_name, const fw_compare_t *cmp);

#endif
