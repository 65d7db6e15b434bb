/* render_job.h: one render's inputs with every default decided once: the volume, its transfer function, shading, view and gaze.
 *
 * Both back ends take a render_job_t: the native renderer (renderer_native.h)
 * and the emulated machine's host session (firmware/host/fw_session.h).  The
 * command layer fills it once from what the user chose and the dataset's own
 * defaults (render_job_resolve), so the two back ends can never resolve a
 * default differently. */
#ifndef PP5_RENDER_JOB_H
#define PP5_RENDER_JOB_H

#include <stdbool.h>
#include <stdio.h>
#include "renderer_native.h"
#include "scene.h"

/* Where the volume comes from. */
typedef enum { RENDER_INPUT_PHANTOM, RENDER_INPUT_DATASET, RENDER_INPUT_FILE } render_input_kind_t;

typedef struct {
    render_input_kind_t kind;
    const char *name;             /* phantom, dataset or file name */
    volume_raw_spec_t raw;        /* raw-file layout (--raw-dims ...) */
    bool have_raw, have_spacing;
} render_input_t;

/* What the user chose; a field whose have_* flag is false takes the
 * dataset's default. */
typedef struct {
    classify_tf_t tf;
    shade_params_t shade;
    render_settings_t settings;
    bool have_tf, have_rot, have_gaze;
    int progressive_frames;       /* 0: a single ordinary frame */
} render_choices_t;

typedef struct {
    const volume_t *volume;       /* borrowed; outlives the job's use */
    const char *volume_name;
    classify_tf_t tf;
    shade_params_t shade;
    render_settings_t settings;   /* settings.progressive set for a progressive sequence */
    int frames;                   /* frames of the sequence (>= 1) */
} render_job_t;

void render_input_default(render_input_t *in);
void render_choices_default(render_choices_t *ch);
/* Loads the volume (phantom, shared dataset with its fall-back, or file),
 * noting a fall-back on `log`. */
pp5_status_t render_input_load(const render_input_t *in, scene_t *sc, FILE *log);
/* The job for `sc` under the user's choices: the dataset's transfer function
 * and view unless chosen, the gaze at the image centre unless given; the
 * display model is checked here, before any costly build. */
pp5_status_t render_job_resolve(render_job_t *job, const scene_t *sc, const render_choices_t *ch);

#endif
