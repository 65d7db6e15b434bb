/* test_soak.c: the long replay soak (`make soak`; hidden unless PP5_SOAK=1).
 *
 * Replays PP5_SOAK_REPLAY_S seconds (default 1800: 30 minutes) of synthetic
 * gaze trace in timing-only mode through the emulated machine, with the pp5
 * that $PP5_BIN names (`make soak` uses the AddressSanitizer build, so a leak
 * also fails the run at exit), and samples its resident memory every two
 * seconds.  Peak RSS over the first and the last tenth of the run must agree
 * within 5 % + 2 MB: memory that keeps rising frame after frame is a leak.
 * The live-recording soak is in test_track_umockdev_run.c (it needs the
 * emulated devices of umockdev_bed.c). */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "harness.h"
#include "soak.h"

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double env_seconds(const char *name, double fallback)
{
    const char *v = getenv(name);
    double s = v ? atof(v) : 0;
    return s > 0 ? s : fallback;
}

/* Runs `sh -c CMD` in the background, sampling memory until it exits;
 * returns its exit code (128 + signal when killed). */
static int run_watched(const char *cmd, soak_series_t *ser, double *elapsed_s)
{
    pid_t pid = fork();
    if (pid < 0)
        return -1;
    if (pid == 0) {
        execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
        _exit(127);
    }
    double t0 = now_s();
    int status = 0;
    for (;;) {
        pid_t r = waitpid(pid, &status, WNOHANG);
        if (r == pid)
            break;
        long rss, hwm;
        if (soak_read_memory(pid, &rss, &hwm))
            soak_series_add(ser, now_s() - t0, rss, hwm);
        usleep(2000 * 1000);
    }
    *elapsed_s = now_s() - t0;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

TEST(soak_replay_30_minutes_of_trace_through_the_machine)
{
    const char *dir = pp5_test_outdir();
    double trace_s = env_seconds("PP5_SOAK_REPLAY_S", 1800);
    char args[2000];
    snprintf(args, sizeof args, "trace synth --mode mixed --seconds %.0f --rate 250 --seed 14 "
             "--out %s/long.trace", trace_s, dir);
    REQUIRE(pp5_test_run_cli(args, NULL, NULL) == 0);
    const char *bin = getenv("PP5_BIN");
    char cmd[4000];
    /* exec: the shell becomes pp5, so the watched pid is pp5's own. */
    snprintf(cmd, sizeof cmd, "exec %s replay %s/long.trace --cost machine:size=64x64 "
             "--timing-only --report %s/replay.json --csv %s/frames.csv >%s/stdout.txt "
             "2>%s/stderr.txt </dev/null", bin && *bin ? bin : "./pp5", dir, dir, dir, dir, dir);
    soak_series_t ser = {0};
    double wall_s = 0;
    int rc = run_watched(cmd, &ser, &wall_s);
    CHECK_MSG(rc == 0, "replay exited %d (see %s/stderr.txt)", rc, dir);
    REQUIRE(ser.n >= 10);
    char csv[1200];
    snprintf(csv, sizeof csv, "%s/rss.csv", dir);
    CHECK(soak_series_write_csv(&ser, csv));
    long first = soak_peak_rss(&ser, 0, 0.1 * wall_s);
    long last = soak_peak_rss(&ser, 0.9 * wall_s, wall_s + 1);
    long hwm_end = ser.s[ser.n - 1].hwm_kb;
    char *report = pp5_test_read_file(csv);
    free(report);
    printf("    soak replay: %.0f s of trace in %.0f s wall; peak RSS %ld kB over the first "
           "tenth, %ld kB over the last tenth; VmHWM at the end %ld kB (%zu samples in %s)\n",
           trace_s, wall_s, first, last, hwm_end, ser.n, csv);
    CHECK_MSG((double)last <= 1.05 * (double)first + 2048, "RSS rose from %ld kB to %ld kB",
              first, last);
    soak_series_free(&ser);
}
