/* bench_fw.c: PP5_BENCH fw_frame: host time to emulate one frame against the native renderer's time for the same frame, and emulated frames per host second. */
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "firmware/host/fw_session.h"
#include "registry.h"
#include "render/scene.h"

/* Host wall clock: benchmark figures only, never part of any result. */
static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static int bench_case(const volume_t *v, const classify_tf_t *tf, const float rot[3], int size,
                      shade_case_t lighting, int frames)
{
    shade_params_t sh;
    shade_defaults(&sh);
    sh.lighting = lighting;
    if (lighting == SHADE_SPECULAR_FIXED_LIGHT)
        sh.specular = 0.4f;
    render_settings_t rs;
    render_settings_defaults(&rs);
    rs.width = rs.height = size;
    rs.mode = RENDER_MODE_GAZE;
    rs.view.rot_x_deg = rot[0];
    rs.view.rot_y_deg = rot[1];
    rs.view.rot_z_deg = rot[2];
    rs.threads = 1;
    pp5_params_t p;
    pp5_params_default(&p);
    fw_options_t o;
    fw_options_default(&o);
    fw_session_t s;
    double t0 = now_s();
    render_job_t job = {.volume = v, .volume_name = v->source, .tf = *tf, .shade = sh,
                        .settings = rs, .frames = 1};
    pp5_status_t st = fw_session_init(&s, &job, &p, &o);
    double t_setup = now_s() - t0;
    if (st != PP5_OK) {
        printf("   machine setup failed: %s\n", pp5_error_text());
        fw_session_free(&s);
        return 1;
    }
    double emu_host = 0, emu_frames = 0, first_host = 0;
    fw_frame_result_t r;
    for (int f = 0; f < frames && st == PP5_OK; f++) {
        double gx = 0.5 * (size - 1) + (f % 3 - 1) * size * 0.15;
        double a = now_s();
        st = fw_session_frame(&s, gx, 0.5 * (size - 1), NULL, &r);
        emu_host += now_s() - a;
        if (f == 0)
            first_host = emu_host;
        emu_frames += r.frame_time_s;
    }
    fw_session_free(&s);
    if (st != PP5_OK) {
        printf("   frame failed: %s\n", pp5_error_text());
        return 1;
    }
    /* Native: same inputs, one thread (the emulator is single-threaded). */
    native_renderer_t nr;
    double n0 = now_s();
    st = native_renderer_init(&nr, v, tf, &sh, 1);
    double n_setup = now_s() - n0;
    double nat = 0;
    for (int f = 0; f < frames && st == PP5_OK; f++) {
        render_settings_t ns = rs;
        ns.gaze_x = 0.5 * (size - 1) + (f % 3 - 1) * size * 0.15;
        ns.gaze_y = 0.5 * (size - 1);
        image8_t img = {0};
        render_stats_t rst;
        double a = now_s();
        st = native_renderer_frame(&nr, &ns, &img, &rst);
        nat += now_s() - a;
        image8_free(&img);
    }
    native_renderer_free(&nr);
    if (st != PP5_OK)
        return 1;
    double per_emu = emu_host / frames, per_nat = nat / frames;
    printf("   %dx%d gaze, %s: emulate %.1f ms/frame (setup %.2f s), native %.1f ms/frame "
           "(setup %.2f s): ratio %.2fx (goal <= 3x)\n",
           size, size, shade_case_name(lighting), per_emu * 1e3, t_setup, per_nat * 1e3, n_setup,
           per_emu / per_nat);
    printf("      emulated frame %.1f ms; %.2f emulated frames per host second; host %.1f ms for "
           "the first frame, %.1f ms for each later one\n", 1e3 * emu_frames / frames,
           1.0 / per_emu, first_host * 1e3,
           frames > 1 ? (emu_host - first_host) * 1e3 / (frames - 1) : 0.0);
    return 0;
}

static int bench_fw_frame(const pp5_bench_opts_t *opts)
{
    printf("fw_frame: host cost of emulating one frame of the gaze-directed renderer on the\n"
           "machine (GPs, renderers, ring: single host thread) vs the native renderer (1 thread)\n");
    scene_t sc;
    pp5_status_t st = scene_load("mrbrain", true, &sc);
    if (st != PP5_OK) {
        printf("   cannot load a volume: %s\n", pp5_error_text());
        return 1;
    }
    volume_t v;
    st = scene_paper_volume(&sc, &v);
    if (st != PP5_OK) {
        scene_free(&sc);
        return 1;
    }
    printf("   volume %s resampled to 128x128x109 (the projection scenario), 16 GPs, 16 renderers\n",
           sc.volume.source);
    float rot[3] = {sc.rot_x_deg, sc.rot_y_deg, sc.rot_z_deg};
    int frames = opts->quick ? 1 : 3;
    int rc = bench_case(&v, &sc.tf, rot, opts->quick ? 96 : 210, SHADE_SPECULAR_FIXED_LIGHT, frames);
    if (rc == 0 && !opts->quick)
        rc = bench_case(&v, &sc.tf, rot, 210, SHADE_DIFFUSE_FIXED_LIGHT, frames);
    if (rc == 0 && !opts->quick)
        rc = bench_case(&v, &sc.tf, rot, 512, SHADE_DIFFUSE_FIXED_LIGHT, 2);
    volume_free(&v);
    scene_free(&sc);
    return rc;
}

PP5_BENCH(fw_frame, "host time to emulate a frame on the machine vs the native renderer", bench_fw_frame)
