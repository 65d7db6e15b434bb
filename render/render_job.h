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
#include "classify_auto.h"
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

/* Where a job's transfer function came from. */
typedef enum {
    RENDER_TF_DATASET,            /* the dataset's or phantom's preset */
    RENDER_TF_CHOSEN,             /* --tf: a preset or a file */
    RENDER_TF_AUTO                /* a file volume's histogram (classify_auto.h) */
} render_tf_origin_t;

/* What the user chose; a field whose have_* flag is false takes the
 * dataset's default. */
typedef struct {
    classify_tf_t tf;
    char tf_note[256];            /* what reading a --tf file noted ("" when nothing) */
    shade_params_t shade;
    render_settings_t settings;
    bool have_tf, have_rot, have_gaze;
    int progressive_frames;       /* 0: a single ordinary frame */
} render_choices_t;

typedef struct {
    const volume_t *volume;       /* borrowed; outlives the job's use */
    const char *volume_name;
    classify_tf_t tf;
    render_tf_origin_t tf_origin;
    classify_auto_info_t tf_auto; /* how an automatic one was chosen */
    shade_params_t shade;
    render_settings_t settings;   /* settings.progressive set for a progressive sequence */
    int frames;                   /* frames of the sequence (>= 1) */
} render_job_t;

void render_input_default(render_input_t *in);
void render_choices_default(render_choices_t *ch);
/* --tf SPEC: a preset name (classify_preset_names) or a file (classify_io.h). */
pp5_status_t render_choices_set_tf(render_choices_t *ch, const char *spec);
/* Loads the volume (phantom, shared dataset with its fall-back, or file),
 * noting a fall-back on `log`. */
pp5_status_t render_input_load(const render_input_t *in, scene_t *sc, FILE *log);
/* The job for `sc` under the user's choices: the transfer function chosen,
 * else the dataset's, else (a file) one chosen from the volume's histogram;
 * the view unless chosen, the gaze at the image centre unless given; the
 * display model is checked here, before any costly build. */
pp5_status_t render_job_resolve(render_job_t *job, const scene_t *sc, const render_choices_t *ch);
/* Says on `log` which transfer function the job uses and, when it was
 * chosen automatically, how, followed by the function in the text format
 * (classify_io.h) for the user to save (--tf-out) and edit. */
void render_job_print_tf(const render_job_t *job, FILE *log);

#endif
