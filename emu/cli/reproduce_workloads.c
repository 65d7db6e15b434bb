/* reproduce_workloads.c: the volumes of `pp5 reproduce projections`: the MR subject at the paper's two sizes (Table I's 256x256x109 and the 128x128x109 of the 10 frames/s claim), or phantoms when the data is absent. */
#include <stdio.h>
#include <string.h>

#include "reproduce_projections.h"
#include "render/scene.h"

static pp5_status_t resampled(const scene_t *sc, int nx, int ny, int nz, proj_workload_t *w)
{
    const volume_t *v = &sc->volume;
    pp5_status_t st = volume_resample(v, nx, ny, nz, &w->volume);
    if (st != PP5_OK)
        return st;
    /* Keep the object's shape: each axis's spacing grows by n_in / n_out. */
    const int n_in[3] = {v->nx, v->ny, v->nz}, n_out[3] = {nx, ny, nz};
    for (int a = 0; a < 3; a++)
        w->volume.spacing[a] = v->spacing[a] * n_in[a] / n_out[a];
    w->tf = sc->tf;
    w->rot[0] = sc->rot_x_deg;
    w->rot[1] = sc->rot_y_deg;
    w->rot[2] = sc->rot_z_deg;
    snprintf(w->label, sizeof w->label, "%s resampled trilinearly to %dx%dx%d", sc->name, nx, ny, nz);
    return PP5_OK;
}

pp5_status_t proj_load_workloads(proj_workload_t *w, int *n, bool quick)
{
    memset(w, 0, 2 * sizeof *w);
    *n = 0;
    scene_t sc;
    pp5_status_t st = scene_load(quick ? "shepp-logan" : "mrbrain", !quick, &sc);
    if (st != PP5_OK)
        return st;
    if (sc.fell_back)
        printf("note: %s\n", sc.note);
    if (quick) {
        st = resampled(&sc, 48, 48, 40, &w[0]);
        w[0].tag = 'B';
        *n = st == PP5_OK;
    } else {
        st = resampled(&sc, 256, 256, 109, &w[0]);
        w[0].tag = 'A';
        if (st == PP5_OK)
            st = resampled(&sc, 128, 128, 109, &w[1]);
        w[1].tag = 'B';
        *n = st == PP5_OK ? 2 : 0;
    }
    scene_free(&sc);
    return st;
}

void proj_workload_free(proj_workload_t *w)
{
    volume_free(&w->volume);
    memset(w, 0, sizeof *w);
}

void proj_runs_begin(proj_runs_t *r, const char *label, int total)
{
    pthread_mutex_init(&r->lock, NULL);
    progress_begin(&r->pr, label, total);
}

void proj_runs_step(proj_runs_t *r, const char *what)
{
    pthread_mutex_lock(&r->lock);
    progress_step(&r->pr, what);
    pthread_mutex_unlock(&r->lock);
}

void proj_runs_end(proj_runs_t *r)
{
    progress_end(&r->pr);
    pthread_mutex_destroy(&r->lock);
}
