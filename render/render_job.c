/* render_job.c: the volume of a render loaded once and its defaults resolved once, for both back ends. */
#include "render_job.h"

#include <stdlib.h>
#include <string.h>

#include "classify_io.h"
#include "volume_histogram.h"

void render_input_default(render_input_t *in)
{
    memset(in, 0, sizeof *in);
    in->kind = RENDER_INPUT_PHANTOM;
    in->name = "shepp-logan";
}

void render_choices_default(render_choices_t *ch)
{
    memset(ch, 0, sizeof *ch);
    shade_defaults(&ch->shade);
    render_settings_defaults(&ch->settings);
}

static pp5_status_t load_file(const render_input_t *in, scene_t *sc)
{
    volume_raw_spec_t spec = in->raw;
    const volume_raw_spec_t *raw = NULL;
    if (in->have_raw) {
        raw = &spec;
    } else if (volume_raw_spec_from_name(in->name, &spec) == PP5_OK) {
        if (in->have_spacing)
            memcpy(spec.spacing, in->raw.spacing, sizeof spec.spacing);
        raw = &spec;
    }
    pp5_status_t st = volume_load(in->name, raw, &sc->volume);
    if (st != PP5_OK)
        return st;
    if (in->have_spacing)
        memcpy(sc->volume.spacing, in->raw.spacing, sizeof sc->volume.spacing);
    snprintf(sc->name, sizeof sc->name, "file");
    scene_guess_tf(&sc->volume, &sc->tf);
    sc->tf_from_data = true;
    return PP5_OK;
}

pp5_status_t render_input_load(const render_input_t *in, scene_t *sc, FILE *log)
{
    memset(sc, 0, sizeof *sc);
    if (in->kind == RENDER_INPUT_FILE)
        return load_file(in, sc);
    pp5_status_t st = scene_load(in->name, in->kind == RENDER_INPUT_DATASET, sc);
    if (st == PP5_OK && sc->fell_back && log)
        fprintf(log, "note: %s\n", sc->note);
    return st;
}

pp5_status_t render_choices_set_tf(render_choices_t *ch, const char *spec)
{
    ch->have_tf = true;
    ch->tf_note[0] = '\0';
    if (classify_preset(spec, &ch->tf) == PP5_OK)
        return PP5_OK;
    FILE *f = fopen(spec, "r");
    if (!f)
        return pp5_fail(PP5_E_CONFIG, "--tf %s: neither a preset (%s) nor a readable file", spec,
                        classify_preset_names());
    fclose(f);
    return classify_tf_read(spec, &ch->tf, ch->tf_note, sizeof ch->tf_note);
}

static pp5_status_t resolve_tf(render_job_t *job, const scene_t *sc, const render_choices_t *ch)
{
    if (ch->have_tf) {
        job->tf = ch->tf;
        job->tf_origin = RENDER_TF_CHOSEN;
        return PP5_OK;
    }
    job->tf = sc->tf;
    job->tf_origin = RENDER_TF_DATASET;
    if (!sc->tf_from_data)
        return PP5_OK;
    volume_histogram_t *h = malloc(sizeof *h);
    if (!h)
        return pp5_fail(PP5_E_NOMEM, "render: out of memory");
    volume_histogram_compute(&sc->volume, h);
    pp5_status_t st = classify_tf_auto(h, &job->tf, &job->tf_auto);
    free(h);
    if (st != PP5_OK)
        return pp5_fail(st, "%s: %s", sc->volume.source, pp5_error_text());
    job->tf_origin = RENDER_TF_AUTO;
    return PP5_OK;
}

void render_job_print_tf(const render_job_t *job, FILE *log)
{
    if (job->tf_origin != RENDER_TF_AUTO) {
        fprintf(log, "transfer function: %s (%s)\n", job->tf.name,
                job->tf_origin == RENDER_TF_CHOSEN ? "--tf" : "the data set's preset");
        return;
    }
    char how[512];
    classify_auto_describe(&job->tf_auto, how, sizeof how);
    fprintf(log, "transfer function: automatic, %s; save it with --tf-out FILE, edit it and give "
            "it back with --tf FILE:\n", how);
    char *text = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&text, &len);
    if (m) {
        classify_tf_write_text(m, &job->tf, NULL);
        fclose(m);
        for (char *line = strtok(text, "\n"); line; line = strtok(NULL, "\n"))
            fprintf(log, "    %s\n", line);
    }
    free(text);
}

pp5_status_t render_job_resolve(render_job_t *job, const scene_t *sc, const render_choices_t *ch)
{
    memset(job, 0, sizeof *job);
    job->volume = &sc->volume;
    job->volume_name = sc->volume.source;
    pp5_status_t st = resolve_tf(job, sc, ch);
    if (st != PP5_OK)
        return st;
    job->shade = ch->shade;
    render_settings_t *s = &job->settings;
    *s = ch->settings;
    if (!ch->have_rot) {
        s->view.rot_x_deg = sc->rot_x_deg;
        s->view.rot_y_deg = sc->rot_y_deg;
        s->view.rot_z_deg = sc->rot_z_deg;
    }
    if (!ch->have_gaze) {
        s->gaze_x = 0.5 * (s->width - 1);
        s->gaze_y = 0.5 * (s->height - 1);
    }
    /* The blend's window and the colour sphere's orientation default to the
     * dataset's (its front faces the viewer of the dataset's own view). */
    blend_settings_fill(&s->blend, sc->window_centre, sc->window_width,
                        (const float[3]){sc->rot_x_deg, sc->rot_y_deg, sc->rot_z_deg});
    s->progressive = ch->progressive_frames > 0;
    job->frames = ch->progressive_frames > 0 ? ch->progressive_frames : 1;
    gaze_model_t check;
    return gaze_model_init(&check, &s->display, s->width, s->height);
}
