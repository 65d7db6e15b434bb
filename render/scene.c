/* scene.c: named datasets with presets, default views and phantom fallback. */
#include "scene.h"

#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static bool is_dir(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

/* $PP5_SHARED_DATA; else ../shared/data from the working directory (the
 * checkout's root, where the README's commands run); else the same folder
 * found from the binary's own place (./pp5 at the checkout's root, or
 * build/<kind>/pp5 below it), so a run from elsewhere still finds the data
 * instead of quietly falling back to a phantom. */
static char data_root[4096];
static pthread_once_t data_root_once = PTHREAD_ONCE_INIT;

static void find_data_root(void)
{
    snprintf(data_root, sizeof data_root, "../shared/data");
    if (is_dir(data_root))
        return;
    char exe[3000];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    char *slash = n > 0 ? (exe[n] = '\0', strrchr(exe, '/')) : NULL;
    if (!slash)
        return;
    *slash = '\0';
    static const char *const up[] = {"/../shared/data", "/../../../shared/data"};
    for (size_t i = 0; i < sizeof up / sizeof up[0]; i++) {
        snprintf(data_root, sizeof data_root, "%s%s", exe, up[i]);
        if (is_dir(data_root))
            return;
    }
    snprintf(data_root, sizeof data_root, "../shared/data");
}

const char *scene_data_root(void)
{
    const char *env = getenv("PP5_SHARED_DATA");
    if (env && *env)
        return env;
    pthread_once(&data_root_once, find_data_root);
    return data_root;
}

void scene_free(scene_t *s)
{
    volume_free(&s->volume);
    memset(s, 0, sizeof *s);
}

void scene_guess_tf(const volume_t *v, classify_tf_t *tf)
{
    /* 12-bit CT numbers exceed 1000; 8-bit MR and the phantoms do not. */
    const char *name = v->max_value > 1000.0f ? "ct-skin" : (v->max_value <= 1.0f
                                                             ? "marschner-lobb" : "mr");
    classify_preset(name, tf);
}

static pp5_status_t load_phantom(const char *name, scene_t *s)
{
    pp5_status_t st = phantom_make(name, 0, 0, 0, &s->volume);
    if (st != PP5_OK)
        return st;
    snprintf(s->name, sizeof s->name, "phantom %s", name);
    if (classify_preset(name, &s->tf) != PP5_OK)
        scene_guess_tf(&s->volume, &s->tf);
    return PP5_OK;
}

pp5_status_t scene_load(const char *dataset, bool allow_fallback, scene_t *s)
{
    memset(s, 0, sizeof *s);
    char path[4200];
    volume_raw_spec_t spec;
    memset(&spec, 0, sizeof spec);
    const char *preset = NULL;
    if (strcmp(dataset, "mrbrain") == 0) {
        snprintf(path, sizeof path, "%s/volumes/mrbrain_brainsmall/"
                 "brainsmall_128x128x84_u8.raw.gz", scene_data_root());
        spec.nx = 128, spec.ny = 128, spec.nz = 84, spec.type = VOXEL_U8;
        preset = "mr";
        /* From its histogram: background below 15, the brightest tissue
         * ends near 165 (a few voxels reach 202). */
        s->window_centre = 90.0f;
        s->window_width = 150.0f;
        /* Sagittal planes, face toward x = 0, top toward y = 0 (README):
         * looking along +z shows the side of the head upright. */
    } else if (strcmp(dataset, "cthead") == 0) {
        snprintf(path, sizeof path, "%s/volumes/cthead/cthead_256x256x113_u16be.raw.gz",
                 scene_data_root());
        spec.nx = 256, spec.ny = 256, spec.nz = 113, spec.type = VOXEL_U16;
        spec.big_endian = true;
        spec.spacing[0] = spec.spacing[1] = 1.0;
        spec.spacing[2] = 2.0;       /* 1:1:2 (data README) */
        preset = "ct-skin";
        /* The radiologists' bone window (level 500 HU, width 2000 HU) in
         * CThead's units, where air is 0 and soft tissue 1000-1100, i.e.
         * value = HU + 1000: material 0 at 500, 1 at 2500 (dense bone and
         * teeth saturate; the bone peak, 1900-2200, does not). */
        s->window_centre = 1500.0f;
        s->window_width = 2000.0f;
        /* Slice 1 above the vertex, table at +y: look along +y from the face
         * side with the vertex up. */
        s->rot_x_deg = 90.0f;
        s->rot_z_deg = 180.0f;
    } else {
        return load_phantom(dataset, s);
    }
    snprintf(s->name, sizeof s->name, "%s", dataset);
    if (access(path, R_OK) != 0) {
        if (!allow_fallback)
            return pp5_fail(PP5_E_IO, "%s: not found (set PP5_SHARED_DATA)", path);
        snprintf(s->note, sizeof s->note, "%s absent: Shepp-Logan phantom 256x256x109 used "
                 "instead", path);
        s->fell_back = true;
        s->rot_x_deg = s->rot_y_deg = s->rot_z_deg = 0.0f;
        s->window_centre = s->window_width = 0.0f;
        return load_phantom("shepp-logan", s);
    }
    pp5_status_t st = volume_load_raw(path, &spec, &s->volume);
    if (st != PP5_OK)
        return st;
    return classify_preset(preset, &s->tf);
}

pp5_status_t scene_paper_volume(const scene_t *s, volume_t *out)
{
    const volume_t *v = &s->volume;
    pp5_status_t st = volume_resample(v, SCENE_PAPER_NX, SCENE_PAPER_NY, SCENE_PAPER_NZ, out);
    if (st != PP5_OK)
        return st;
    const int n_in[3] = {v->nx, v->ny, v->nz}, n_out[3] = {SCENE_PAPER_NX, SCENE_PAPER_NY,
                                                           SCENE_PAPER_NZ};
    for (int a = 0; a < 3; a++)
        out->spacing[a] = v->spacing[a] * n_in[a] / n_out[a];
    return PP5_OK;
}
