/* bench_fw.c: PP5_BENCH fw_frame: host time to emulate one frame against the native renderer's time for the same frame, and emulated frames per host second. */
#include <stdbool.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "bench_render.h"
#include "firmware/host/fw_session.h"
#include "registry.h"
#include "render/scene.h"

/* Host clocks: benchmark figures only, never part of any result. */
static double clock_s(clockid_t id)
{
    struct timespec ts;
    clock_gettime(id, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* One frame's host time: wall and this thread's CPU (both sides run on the
 * calling thread, so the CPU time is the steadier figure on a shared host). */
typedef struct {
    double wall, cpu;
} host_time_t;

/* A case: the machine's session and the native renderer on the same
 * inputs, both kept for the whole measurement. */
typedef struct {
    render_settings_t rs;
    shade_params_t sh;
    fw_session_t s;
    native_renderer_t nr;
    double setup_emu_s, setup_native_s;
    double emulated_s;            /* the emulated frames' times, summed */
    int emulated_frames;
} fw_case_t;

static double gaze_x(const fw_case_t *c, int f)
{
    return 0.5 * (c->rs.width - 1) + (f % 3 - 1) * c->rs.width * 0.15;
}

static pp5_status_t emulate_frame(fw_case_t *c, int f, host_time_t *t)
{
    fw_frame_result_t r;
    double w = clock_s(CLOCK_MONOTONIC), u = clock_s(CLOCK_THREAD_CPUTIME_ID);
    pp5_status_t st = fw_session_frame(&c->s, gaze_x(c, f), 0.5 * (c->rs.height - 1), NULL, &r);
    t->cpu = clock_s(CLOCK_THREAD_CPUTIME_ID) - u, t->wall = clock_s(CLOCK_MONOTONIC) - w;
    if (st == PP5_OK) {
        c->emulated_s += r.frame_time_s;
        c->emulated_frames++;
    }
    return st;
}

static pp5_status_t native_frame(fw_case_t *c, int f, host_time_t *t)
{
    render_settings_t ns = c->rs;
    ns.gaze_x = gaze_x(c, f);
    ns.gaze_y = 0.5 * (c->rs.height - 1);
    image8_t img = {0};
    render_stats_t rst;
    double w = clock_s(CLOCK_MONOTONIC), u = clock_s(CLOCK_THREAD_CPUTIME_ID);
    pp5_status_t st = native_renderer_frame(&c->nr, &ns, &img, &rst);
    t->cpu = clock_s(CLOCK_THREAD_CPUTIME_ID) - u, t->wall = clock_s(CLOCK_MONOTONIC) - w;
    image8_free(&img);
    return st;
}

static pp5_status_t case_init(fw_case_t *c, const volume_t *v, const classify_tf_t *tf,
                              const float rot[3], int size, shade_case_t lighting)
{
    memset(c, 0, sizeof *c);
    shade_defaults(&c->sh);
    c->sh.lighting = lighting;
    if (lighting == SHADE_SPECULAR_FIXED_LIGHT)
        c->sh.specular = 0.4f;
    render_settings_defaults(&c->rs);
    c->rs.width = c->rs.height = size;
    c->rs.mode = RENDER_MODE_GAZE;
    c->rs.view.rot_x_deg = rot[0], c->rs.view.rot_y_deg = rot[1], c->rs.view.rot_z_deg = rot[2];
    c->rs.threads = 1;   /* the emulator is single-threaded: so is the native side */
    pp5_params_t p;
    pp5_params_default(&p);
    fw_options_t o;
    fw_options_default(&o);
    render_job_t job = {.volume = v, .volume_name = v->source, .tf = *tf, .shade = c->sh,
                        .settings = c->rs, .frames = 1};
    double t0 = clock_s(CLOCK_MONOTONIC);
    pp5_status_t st = fw_session_init(&c->s, &job, &p, &o);
    c->setup_emu_s = clock_s(CLOCK_MONOTONIC) - t0;
    if (st != PP5_OK)
        return st;
    t0 = clock_s(CLOCK_MONOTONIC);
    st = native_renderer_init(&c->nr, v, tf, &c->sh, 1);
    c->setup_native_s = clock_s(CLOCK_MONOTONIC) - t0;
    return st;
}

static void case_free(fw_case_t *c)
{
    fw_session_free(&c->s);
    native_renderer_free(&c->nr);
}

/* Round 0 is each side's first frame (reported on its own); rounds 1..
 * alternate which side goes first, and each ratio is the median of the
 * rounds' own ratios, so a busy spell on the host weighs on both sides. */
static int bench_case(const volume_t *v, const classify_tf_t *tf, const float rot[3], int size,
                      shade_case_t lighting, int rounds)
{
    fw_case_t c;
    pp5_status_t st = case_init(&c, v, tf, rot, size, lighting);
    host_time_t first_emu = {0}, first_nat = {0}, e = {0}, n = {0};
    double emu_ms[BENCH_MAX_REPS], nat_ms[BENCH_MAX_REPS], wall_q[BENCH_MAX_REPS],
        cpu_q[BENCH_MAX_REPS];
    if (st == PP5_OK)
        st = emulate_frame(&c, 0, &first_emu);
    if (st == PP5_OK)
        st = native_frame(&c, 0, &first_nat);
    for (int i = 0; i < rounds && st == PP5_OK; i++) {
        bool emu_first = i % 2 == 0;
        st = emu_first ? emulate_frame(&c, i + 1, &e) : native_frame(&c, i + 1, &n);
        if (st == PP5_OK)
            st = emu_first ? native_frame(&c, i + 1, &n) : emulate_frame(&c, i + 1, &e);
        if (st != PP5_OK)
            break;
        emu_ms[i] = e.cpu * 1e3, nat_ms[i] = n.cpu * 1e3;
        wall_q[i] = e.wall / n.wall, cpu_q[i] = e.cpu / n.cpu;
    }
    if (st != PP5_OK) {
        printf("   %dx%d %s: %s\n", size, size, shade_case_name(lighting), pp5_error_text());
        case_free(&c);
        return 1;
    }
    double per_emu = bench_median(emu_ms, rounds), per_nat = bench_median(nat_ms, rounds);
    printf("   %dx%d gaze, %s: emulate %.1f ms/frame (setup %.2f s), native %.1f ms/frame "
           "(setup %.2f s): ratio %.2fx (goal <= 3x)\n",
           size, size, shade_case_name(lighting), per_emu, c.setup_emu_s, per_nat,
           c.setup_native_s, bench_median(cpu_q, rounds));
    printf("      CPU ms, medians of %d alternated rounds; the ratio is the rounds' median (wall "
           "clock: %.2fx); first frames %.1f and %.1f ms\n", rounds, bench_median(wall_q, rounds),
           first_emu.cpu * 1e3, first_nat.cpu * 1e3);
    printf("      emulated frame %.1f ms (mean of the %d); %.2f emulated frames per host second\n",
           1e3 * c.emulated_s / c.emulated_frames, c.emulated_frames, 1e3 / per_emu);
    case_free(&c);
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
    int rounds = opts->quick ? 1 : 7;
    int rc = bench_case(&v, &sc.tf, rot, opts->quick ? 96 : 210, SHADE_SPECULAR_FIXED_LIGHT, rounds);
    if (rc == 0 && !opts->quick)
        rc = bench_case(&v, &sc.tf, rot, 210, SHADE_DIFFUSE_FIXED_LIGHT, rounds);
    if (rc == 0 && !opts->quick)
        rc = bench_case(&v, &sc.tf, rot, 512, SHADE_DIFFUSE_FIXED_LIGHT, 5);
    volume_free(&v);
    scene_free(&sc);
    return rc;
}

PP5_BENCH(fw_frame, "host time to emulate a frame on the machine vs the native renderer", bench_fw_frame)
