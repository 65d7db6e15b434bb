/* bench_render_common.c: what the renderer benchmarks share (bench_render.h):
 * the scene, frame settings, timing, host memory and fitting. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "bench_render.h"

pp5_status_t bench_render_scene(scene_t *sc)
{
    pp5_status_t st = scene_load("cthead", true, sc);
    if (st != PP5_OK) {
        printf("   cannot load a volume: %s\n", pp5_error_text());
        return st;
    }
    if (sc->fell_back)
        printf("   note: %s\n", sc->note);
    /* The peers' 1D value ramp (classify.h "ct-skin-ramp") on CThead, so all
     * three renderers classify alike; the phantom keeps its own preset. */
    if (!sc->fell_back)
        classify_preset("ct-skin-ramp", &sc->tf);
    return PP5_OK;
}

void bench_render_settings(const scene_t *sc, int side, render_mode_t mode, render_settings_t *s)
{
    render_settings_defaults(s);
    s->width = s->height = side;
    s->gaze_x = s->gaze_y = 0.5 * (side - 1);
    s->view.rot_x_deg = sc->rot_x_deg;
    s->view.rot_y_deg = sc->rot_y_deg;
    s->view.rot_z_deg = sc->rot_z_deg;
    s->mode = mode;
}

static double process_cpu_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

pp5_status_t bench_render_frames_min(native_renderer_t *r, const render_settings_t *s, int reps,
                                     double *wall_ms, double *cpu_ms, render_stats_t *last)
{
    *wall_ms = *cpu_ms = INFINITY;
    for (int i = 0; i < reps; i++) {
        image8_t img;
        double c0 = process_cpu_ms();
        pp5_status_t st = native_renderer_frame(r, s, &img, last);
        double c = process_cpu_ms() - c0;
        if (st != PP5_OK)
            return st;
        image8_free(&img);
        *wall_ms = last->ms_total < *wall_ms ? last->ms_total : *wall_ms;
        *cpu_ms = c < *cpu_ms ? c : *cpu_ms;
    }
    return PP5_OK;
}

double bench_peak_rss_mb(void)
{
    FILE *f = fopen("/proc/self/status", "r");
    if (!f)
        return -1.0;
    char line[256];
    double kb = -1.0;
    while (fgets(line, sizeof line, f))
        if (strncmp(line, "VmHWM:", 6) == 0 && sscanf(line + 6, "%lf", &kb) == 1)
            break;
    fclose(f);
    return kb < 0.0 ? -1.0 : kb / 1024.0;
}

bool bench_peak_rss_reset(void)
{
    /* "5" resets the peak RSS to the current RSS (Linux 4.0 and later). */
    FILE *f = fopen("/proc/self/clear_refs", "w");
    if (!f)
        return false;
    bool ok = fputs("5", f) >= 0;
    return fclose(f) == 0 && ok;
}

double bench_fit_exponent(const double *x, const double *y, int n)
{
    double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
    for (int i = 0; i < n; i++) {
        double lx = log(x[i]), ly = log(y[i]);
        sx += lx;
        sy += ly;
        sxx += lx * lx;
        sxy += lx * ly;
    }
    double d = n * sxx - sx * sx;
    return d != 0.0 ? (n * sxy - sx * sy) / d : NAN;
}
