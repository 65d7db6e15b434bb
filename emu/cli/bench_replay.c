/* bench_replay.c: `pp5 bench replay`: replay speed in timing-only mode, in
 * trace seconds per host second, on a synthetic 60 s, 1000 Hz trace (the goal:
 * faster than real time).  The frame time comes from the
 * built-in constant source first (the replay arithmetic alone), then from the
 * emulated machine (every frame a real frame of the firmware), which is what
 * `pp5 replay` uses by default. */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

#include "registry.h"
#include "tracker/replay.h"
#include "tracker/synth.h"
#include "tracker/trace_file.h"

static double host_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

static int bench_replay(const pp5_bench_opts_t *o)
{
    synth_params_t sp;
    synth_defaults(&sp, SYNTH_MIXED);
    sp.seconds = o->quick ? 10 : 60;
    sp.rate_hz = 1000;
    trace_t t;
    double t0 = host_seconds();
    if (synth_generate(&sp, &t) != PP5_OK) {
        printf("   synth failed: %s\n", pp5_error_text());
        return 1;
    }
    double gen_s = host_seconds() - t0;
    printf("   trace: synth mixed, %.0f s at 1000 Hz (%zu samples), generated in %.3f s\n",
           sp.seconds, t.count, gen_s);
    static const predict_kind_t kinds[] = {PREDICT_NONE, PREDICT_KALMAN};
    static const double frames_ms[] = {66.667, 10.0};
    for (int fi = 0; fi < 2; fi++) {
        for (int k = 0; k < 2; k++) {
            replay_params_t p;
            replay_defaults(&p);
            p.timing_only = true;
            predict_defaults(&p.predict, kinds[k]);
            replay_constant_cost_t c = {frames_ms[fi] / 1e3};
            int reps = o->quick ? 3 : 10;
            double best = 1e30;
            size_t frames = 0;
            for (int r = 0; r < reps; r++) {
                replay_result_t res;
                double a = host_seconds();
                if (replay_run(&t, &p, replay_constant_cost, &c, NULL, NULL, &res) != PP5_OK) {
                    printf("   replay failed: %s\n", pp5_error_text());
                    trace_free(&t);
                    return 1;
                }
                double dt = host_seconds() - a;
                if (dt < best)
                    best = dt;
                frames = res.count;
                replay_result_free(&res);
            }
            printf("   replay timing-only, constant frame %.1f ms, predict %-6s: %zu frames in "
                   "%.4f s host (best of %d) = %.0f trace s per host s\n",
                   frames_ms[fi], predict_kind_name(kinds[k]), frames, best, reps,
                   sp.seconds / best);
        }
    }
    /* Through the emulated machine: the emulation dominates. */
    const replay_cost_source_t *machine = replay_find_cost_source("machine");
    if (machine) {
        replay_params_t p;
        replay_defaults(&p);
        p.timing_only = true;
        void *ctx = NULL;
        double a = host_seconds();
        if (machine->open("", &p.display, &ctx) != PP5_OK) {
            printf("   machine source failed: %s\n", pp5_error_text());
        } else {
            double setup_s = host_seconds() - a;
            replay_result_t res;
            a = host_seconds();
            if (replay_run(&t, &p, machine->cost, ctx, NULL, NULL, &res) == PP5_OK) {
                double dt = host_seconds() - a;
                printf("   replay timing-only through the emulated machine (phantom 128x128x109, "
                       "210x210): setup %.2f s host, %zu frames in %.2f s host = %.2f trace s per "
                       "host s (%s real time)\n", setup_s, res.count, dt, sp.seconds / dt,
                       sp.seconds / dt >= 1 ? "faster than" : "slower than");
                replay_result_free(&res);
            } else {
                printf("   machine replay failed: %s\n", pp5_error_text());
            }
            machine->close(ctx);
        }
    }
    /* And reading the trace from a file, which `pp5 replay` also pays. */
    char path[] = "/tmp/pp5-bench-replay-XXXXXX";
    int fd = mkstemp(path);
    if (fd >= 0) {
        close(fd);
        trace_t back;
        if (trace_write_file(path, &t) == PP5_OK) {
            double a = host_seconds();
            if (trace_read_file(path, &back) == PP5_OK) {
                double dt = host_seconds() - a;
                printf("   reading the trace file back: %.3f s host = %.0f trace s per host s\n",
                       dt, sp.seconds / dt);
                trace_free(&back);
            }
        }
        unlink(path);
    }
    trace_free(&t);
    return 0;
}

PP5_BENCH(replay, "gaze replay speed, timing-only (trace seconds per host second)", bench_replay)
