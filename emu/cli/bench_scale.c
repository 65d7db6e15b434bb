/* bench_scale.c: `pp5 bench scale`: a 200-point `pp5 sweep` on 1 and 2 MPI
 * ranks (wall time, parallel efficiency T1 / (2 T2)), and a measured model
 * of the per-unit overheads that predicts the efficiency on a bigger node.
 *
 * Wall times on a shared 2-core host are as noisy as the other work on it
 * (the load average is printed beside them), so the model is built from CPU
 * times, which that work does not inflate:
 *   c_i       each unit's CPU time (the thread that ran it), from the 1-rank run;
 *   t_start   CPU per rank outside the units: process start, MPI_Init, the
 *             volume load and resample (once per rank: what the units share),
 *             the launcher; from the job's CPU (getrusage of the children);
 *   h         the wait between units (request, rank 0's 1 ms polls): 2 ms,
 *             the polling bound of emu/util/workunit_mpi.c (the measured
 *             idle time per unit is printed beside it);
 *   setup     the machine's own setup in every unit (machine init, the GPs'
 *             mip-map build) and the cost of one frame: a line through replay
 *             units of 1 and 9 frames.
 * T_P = t_start + the makespan of handing the units, in order, each to the
 * first free of P ranks (each unit costing c_i + h); E_P = sum c_i / (P T_P).
 * Runs `mpirun` on this binary; needs an MPI build. */
#include <math.h>
#include <sys/resource.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "registry.h"
#include "workunit.h"

static double wall_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* The first number after "KEY": in a JSON file of ours, or NAN. */
static double json_number(const char *text, const char *key, const char **after)
{
    char pat[80];
    snprintf(pat, sizeof pat, "\"%s\": ", key);
    const char *p = text ? strstr(text, pat) : NULL;
    if (!p)
        return NAN;
    p += strlen(pat);
    char *end;
    double v = strtod(p, &end);
    if (after)
        *after = end;
    return v;
}

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = n >= 0 ? malloc((size_t)n + 1) : NULL;
    if (buf && fread(buf, 1, (size_t)n, f) == (size_t)n)
        buf[n] = '\0';
    else {
        free(buf);
        buf = NULL;
    }
    fclose(f);
    return buf;
}

#define SCALE_MAX_UNITS 256

typedef struct {
    double wall, runner_wall, unit_wall, unit_cpu, job_cpu;
    double cpu[SCALE_MAX_UNITS];    /* each unit's CPU seconds, by index */
    int units;
} scale_run_t;

static double children_cpu_s(void)
{
    struct rusage ru;
    getrusage(RUSAGE_CHILDREN, &ru);
    return ru.ru_utime.tv_sec + ru.ru_stime.tv_sec +
           1e-6 * (ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

/* The accounting's "units" array: each unit's CPU seconds, by index. */
static void unit_cpus(const char *a, scale_run_t *r)
{
    const char *p = strstr(a, "\"units\": [");
    while (p && (p = strstr(p, "\"index\": ")) != NULL) {
        const char *after;
        double index = json_number(p, "index", &after);
        double cpu = json_number(after, "cpu_s", NULL);
        if (index >= 0 && index < SCALE_MAX_UNITS)
            r->cpu[(int)index] = cpu;
        p = after;
    }
}

/* One command under mpirun -n ranks with --accounting; false when it did not run. */
static bool run_counted(const char *self, int ranks, const char *args, const char *dir,
                        scale_run_t *r)
{
    char acc[600], line[4096];
    snprintf(acc, sizeof acc, "%s/acc.json", dir);
    remove(acc);
    snprintf(line, sizeof line, "mpirun --oversubscribe %s -n %d %s %s --accounting %s "
             ">%s/out.txt 2>%s/err.txt </dev/null", geteuid() == 0 ? "--allow-run-as-root" : "",
             ranks, self, args, acc, dir, dir);
    double t0 = wall_s(), c0 = children_cpu_s();
    int rc = system(line);
    r->wall = wall_s() - t0;
    r->job_cpu = children_cpu_s() - c0;
    char *a = slurp(acc);
    if (!a || rc == -1) {
        printf("   the run did not finish (exit %d): see %s/err.txt\n", rc, dir);
        free(a);
        return false;
    }
    r->runner_wall = json_number(a, "wall_s", NULL);
    r->unit_wall = json_number(a, "unit_core_s", NULL);
    r->unit_cpu = json_number(a, "unit_cpu_s", NULL);
    r->units = (int)json_number(a, "units_run", NULL);
    memset(r->cpu, 0, sizeof r->cpu);
    unit_cpus(a, r);
    free(a);
    return true;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The mean CPU seconds of the units of a replay batch whose lines all ask
 * for `frames` machine frames. */
static double replay_unit_cpu(const char *self, const char *dir, int frames, int units)
{
    char list[600], args[1400];
    snprintf(list, sizeof list, "%s/f%d.list", dir, frames);
    FILE *f = fopen(list, "w");
    if (!f)
        return NAN;
    for (int i = 0; i < units; i++)
        fprintf(f, "traces/mixed_10s_250hz.trace --cost machine:set=gp.count=%d "
                   "--max-frames %d\n", 4 << (i % 3), frames);
    fclose(f);
    snprintf(args, sizeof args, "replay --batch %s --out %s/f%d.csv", list, dir, frames);
    scale_run_t r;
    return run_counted(self, 1, args, dir, &r) && r.units > 0 ? r.unit_cpu / r.units : NAN;
}

/* Rank 0 hands the units out in order, each to the first rank that is free. */
static double makespan(const double *cost, int n, int P, double h)
{
    double free_at[64] = {0}, end = 0;
    for (int i = 0; i < n; i++) {
        int best = 0;
        for (int r = 1; r < P; r++)
            best = free_at[r] < free_at[best] ? r : best;
        free_at[best] += cost[i] + h;
        end = free_at[best] > end ? free_at[best] : end;
    }
    return end;
}

/* useful: the work that counts (all of the units' time, or their frames'
 * time only, when a unit's setup is overhead that bigger units would share). */
static double model_efficiency(const double *cost, int n, int P, double t_start, double h,
                               double useful)
{
    return useful / (P * (t_start + makespan(cost, n, P, h)));
}

static double sum_of(const double *v, int n)
{
    double s = 0;
    for (int i = 0; i < n; i++)
        s += v[i];
    return s;
}

static void print_model(const scale_run_t *one, const scale_run_t *two, double setup,
                        double frame)
{
    const double h = 0.002;
    int U = one->units;
    double t_start = (one->job_cpu - one->unit_cpu), c_max = 0;
    for (int i = 0; i < U; i++)
        c_max = one->cpu[i] > c_max ? one->cpu[i] : c_max;
    double idle = U > 0 ? (2 * two->runner_wall - two->unit_wall) / U : 0;
    printf("   CPU: 1 rank %.2f s in all (%.2f s in units), 2 ranks %.2f s (%.2f s in units): "
           "the second rank adds %.2f s\n", one->job_cpu, one->unit_cpu, two->job_cpu,
           two->unit_cpu, two->job_cpu - one->job_cpu - (two->unit_cpu - one->unit_cpu));
    printf("   overheads: t_start %.2f s CPU per rank; units %.3f s CPU mean, %.3f s largest; "
           "idle between units measured %.1f ms (wall, 2 ranks; the model uses h = %.0f ms)\n",
           t_start, one->unit_cpu / (U ? U : 1), c_max, idle * 1e3, h * 1e3);
    printf("   a machine unit: %.3f s of setup (machine init, GP mip-map build) + %.4f s per "
           "frame (CPU; through 1- and 9-frame replays): a unit of F frames spends %.0f %% "
           "(F=1), %.0f %% (F=50), %.0f %% (F=200) of its time in setup\n", setup, frame,
           100 * setup / (setup + frame), 100 * setup / (setup + 50 * frame),
           100 * setup / (setup + 200 * frame));
    printf("   model E_P (greedy hand-out of the measured unit costs, + t_start, + h per unit):\n");
    double all = sum_of(one->cpu, U);
    printf("     this sweep (%d units, each its own machine): P=2 %.3f, P=16 %.3f, P=64 %.3f\n",
           U, model_efficiency(one->cpu, U, 2, t_start, h, all),
           model_efficiency(one->cpu, U, 16, t_start, h, all),
           model_efficiency(one->cpu, U, 64, t_start, h, all));
    printf("     10,000 replayed frames on one machine configuration, the units' setup counted "
           "as overhead:\n");
    static double batch[10000];
    const int sizes[] = {1, 50, 100, 200};
    for (int k = 0; k < 4; k++) {
        int F = sizes[k], n = 10000 / F;
        for (int i = 0; i < n; i++)
            batch[i] = setup + F * frame;
        printf("       %5d units of %3d frame%s: P=2 %.3f, P=64 %.3f\n", n, F, F == 1 ? " " : "s",
               model_efficiency(batch, n, 2, t_start, h, 10000 * frame),
               model_efficiency(batch, n, 64, t_start, h, 10000 * frame));
    }
}

static int bench_scale(const pp5_bench_opts_t *o)
{
    if (!workunit_have_mpi() || system("command -v mpirun >/dev/null 2>&1") != 0) {
        printf("   skipped: this build has no MPI, or mpirun is missing (Debian: "
               "libopenmpi-dev, openmpi-bin)\n");
        return 0;
    }
    char self[1024];
    ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    if (n <= 0)
        return 1;
    self[n] = '\0';
    const char *dir = "build/bench-scale";
    if (system("mkdir -p build/bench-scale") != 0)
        return 1;
    /* 200 points: 5 GP counts x 5 ring widths x 4 GP clocks x 2 shading splits. */
    char args[1400];
    snprintf(args, sizeof args, "sweep %s --set split=pp,gp --out %s/s.csv --plot %s/s.png",
             o->quick ? "--set gp.count=2,4,8 --set ring.channels=1,8 --size 16x16 --phantom "
                        "marschner-lobb"
                      : "--set gp.count=2,4,8,16,32 --set ring.channels=1,2,4,8,16 "
                        "--set gp.clock_hz=25000000,33000000,40000000,50000000", dir, dir);
    int repeats = o->quick ? 1 : 3;
    double w1[3], w2[3], load[3];
    static scale_run_t one, two, r;
    printf("   %-6s %-8s %9s %9s %12s %11s %9s\n", "ranks", "repeat", "wall s", "units s",
           "unit CPU s", "job CPU s", "load avg");
    for (int k = 0; k < repeats; k++) {
        for (int ranks = 1; ranks <= 2; ranks++) {
            if (!run_counted(self, ranks, args, dir, &r))
                return 1;
            FILE *la = fopen("/proc/loadavg", "r");
            load[k] = 0;
            if (la && fscanf(la, "%lf", &load[k]) != 1)
                load[k] = 0;
            if (la)
                fclose(la);
            printf("   %-6d %-8d %9.2f %9.2f %12.2f %11.2f %9.2f\n", ranks, k + 1, r.wall,
                   r.unit_wall, r.unit_cpu, r.job_cpu, load[k]);
            fflush(stdout);
            (ranks == 1 ? w1 : w2)[k] = r.wall;
            if (ranks == 1 && (k == 0 || r.wall < one.wall))
                one = r;
            if (ranks == 2 && (k == 0 || r.wall < two.wall))
                two = r;
        }
    }
    qsort(w1, (size_t)repeats, sizeof *w1, cmp_double);
    qsort(w2, (size_t)repeats, sizeof *w2, cmp_double);
    printf("   %d units: 1 rank min %.2f s median %.2f s; 2 ranks min %.2f s median %.2f s; "
           "parallel efficiency T1/(2 T2) %.3f (min) %.3f (median)\n", one.units, w1[0],
           w1[repeats / 2], w2[0], w2[repeats / 2], w1[0] / (2 * w2[0]),
           w1[repeats / 2] / (2 * w2[repeats / 2]));
    double c1 = replay_unit_cpu(self, dir, 1, 3), c9 = replay_unit_cpu(self, dir, 9, 3);
    double frame = (c9 - c1) / 8, setup = c1 - frame;
    print_model(&one, &two, setup, frame);
    return 0;
}

PP5_BENCH(scale, "200-unit sweep on 1 and 2 MPI ranks: parallel efficiency, per-unit overheads",
          bench_scale)
