/* render_cmd.h: `pp5 render` once its options are parsed: what to render, on which back end, and what to write.
 *
 * cmd_render.c parses the command line into a render_cmd_t; the command
 * loads the input and resolves one render job (render/render_job.h), then
 * runs it on the native renderer (render_native.c) or on the emulated
 * machine (render_machine.c), which also compares its image with the native
 * renderer's. */
#ifndef PP5_RENDER_CMD_H
#define PP5_RENDER_CMD_H

#include <stdbool.h>
#include <stdio.h>
#include "firmware/host/fw_session.h"
#include "params.h"
#include "render/mesh/mesh_raster.h"
#include "render/mesh/mesh_render.h"
#include "render/mesh/mesh_scene.h"
#include "render/render_job.h"

typedef struct {
    render_input_t input;
    render_choices_t choices;
    const char *out_png, *report_json, *levels_prefix, *fig5_png, *tf_out;
    bool compare;
    /* The machine back end (--machine). */
    bool machine;
    int frames;                   /* --frames N: the gaze moves across the image */
    const char *timeline;
    fw_options_t fw;              /* --division, --split and firmware --set keys */
    pp5_params_cli_t params;      /* --preset, --config, --set */
    /* Polygons (render_mesh.c): --mesh FILE or --scene FILE, --shading. */
    const char *mesh_file, *scene_file;
    raster_shading_t shading;
} render_cmd_t;

void render_cmd_defaults(render_cmd_t *c);
/* pp5 render's options (getopt_long table, without the terminating entry)
 * and their parser, shared with pp5 view. */
struct option;
const struct option *render_cmd_options(int *count);
pp5_status_t render_cmd_option(render_cmd_t *c, int opt, const char *arg);
/* The native renderer: frames, PNG, figures 5 and 6, --compare, report. */
pp5_status_t render_native_run(const render_cmd_t *c, const render_job_t *job, const scene_t *sc,
                               FILE *log);
/* The emulated machine: frames, PNG, the comparison with render/, reports,
 * timeline. */
pp5_status_t render_machine_run(const render_cmd_t *c, const render_job_t *job, FILE *log);
/* --mesh / --scene natively: full or gaze-directed, PNG, report, and with
 * --compare the savings of LOD, VRZ and both with their image quality. */
pp5_status_t render_mesh_run(const render_cmd_t *c, FILE *log);
/* A polygon frame as render_mesh.c made it natively: the triangle lists at
 * full detail and at the chosen levels of detail (lod == full when every
 * object keeps full detail), the view, and the native image of the frame
 * the machine repeats (gaze-directed: LOD + VRZ; else full, full res). */
typedef struct {
    const char *scene_name;
    const mesh_soup_t *full, *lod;
    const raster_camera_t *cam;
    const mesh_render_opts_t *opts;
    const gaze_model_t *gaze;
    double gaze_x, gaze_y;
    int width, height;
    bool gaze_directed;
    const image8_t *native;
} render_mesh_frame_t;

/* The frame on the emulated machine (render_mesh_machine.c), its report and
 * its agreement with the native image; --compare with --mode gaze adds the
 * machine's savings table. */
pp5_status_t render_mesh_machine(const render_cmd_t *c, const render_mesh_frame_t *f, FILE *log);

#endif
