/* cmd_demo.c: `pp5 demo`, the main demo (`make demo`): a short tour that runs
 * the other subcommands in-process on generated data only, writing every
 * picture and report into one folder and saying what each shows. */
#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "cliopt.h"
#include "outfile.h"
#include "registry.h"

#define DEMO_MAX_ARGS 32

typedef struct {
    const char *title;     /* what the step shows */
    const char *argv[DEMO_MAX_ARGS];  /* a pp5 command line; "@" is replaced by the folder */
} demo_step_t;

/* The tour.  Every step uses generated data (phantoms, synthetic gaze), so the
 * demo needs nothing from ../shared. */
static const demo_step_t demo_steps[] = {
    {"The machine: every parameter with its value, unit and source",
     {"machine", NULL}},
    {"Whole-machine test pattern: GPs send QEE streams to all 16 renderers, 80 regions go to the frame buffer",
     {"test-pattern", "--out", "@/test-pattern.png", "--report", "@/test-pattern.json",
      "--timeline", "@/test-pattern-timeline.json", NULL}},
    {"The same frame with the ring the gaze paper literally describes (640 Mb/s = 80 MB/s, 8x slower)",
     {"test-pattern", "--preset", "gaze1990-literal", "--report", "@/test-pattern-literal.json",
      NULL}},
    {"Native renderer, full resolution (Shepp-Logan head phantom, 512x512)",
     {"render", "--phantom", "shepp-logan", "--mode", "full", "--size", "512x512",
      "--out", "@/native-full.png", "--report", "@/native-full.json", NULL}},
    {"Native renderer, gaze-directed (sweet spot at 300,200; figure 5 and figure 6 images)",
     {"render", "--phantom", "shepp-logan", "--mode", "gaze", "--gaze", "300,200", "--size",
      "512x512", "--out", "@/native-gaze.png", "--report", "@/native-gaze.json", "--compare",
      "--fig5", "@/fig5-sweet-spot.png", "--mip-levels-out", "@/fig6-mip2d", NULL}},
    {"The same gaze-directed frame on the emulated Pixel-Planes 5 (frame time, ring traffic, bottleneck)",
     {"render", "--machine", "--phantom", "shepp-logan", "--mode", "gaze", "--gaze", "300,200",
      "--size", "512x512", "--out", "@/machine-gaze.png", "--report", "@/machine-gaze.json",
      "--timeline", "@/machine-gaze-timeline.json", NULL}},
    {"A synthetic gaze trace: smooth pursuit of a moving cursor (the paper's tracking mode)",
     {"trace", "synth", "--mode", "pursuit", "--seconds", "5", "--seed", "1", "--out",
      "@/pursuit.trace", NULL}},
    {"Replaying it through the emulated machine with the paper's 100-150 ms latency",
     {"replay", "@/pursuit.trace", "--report", "@/replay.json", "--csv", "@/replay-frames.csv",
      "--plot", "@/replay.png", NULL}},
};

static int run_step(const demo_step_t *step, const char *dir, int index, int total)
{
    char storage[DEMO_MAX_ARGS][512];
    char *argv[DEMO_MAX_ARGS + 1];
    int argc = 0;
    for (; step->argv[argc] && argc < DEMO_MAX_ARGS; argc++) {
        const char *a = step->argv[argc];
        if (a[0] == '@')
            snprintf(storage[argc], sizeof storage[argc], "%s%s", dir, a + 1);
        else
            snprintf(storage[argc], sizeof storage[argc], "%s", a);
        argv[argc] = storage[argc];
    }
    argv[argc] = NULL;
    printf("\n[%d/%d] %s\n   $ pp5", index, total, step->title);
    for (int i = 0; i < argc; i++)
        printf(" %s", argv[i]);
    printf("\n");
    fflush(stdout);
    const pp5_command_t *cmd = pp5_find_command(argv[0]);
    if (!cmd) {
        printf("   (this build has no '%s' command yet: step skipped)\n", argv[0]);
        return 1;
    }
    int rc = cmd->fn(argc, argv);
    fflush(stdout);
    if (rc != 0)
        printf("   step failed with exit code %d\n", rc);
    return rc;
}

/* mkdir -p: creates every missing folder of `path`. */
static int make_dirs(const char *path)
{
    char partial[512];
    snprintf(partial, sizeof partial, "%s", path);
    for (char *p = partial + 1; *p; p++) {
        if (*p != '/')
            continue;
        *p = '\0';
        if (mkdir(partial, 0755) != 0 && errno != EEXIST)
            return -1;
        *p = '/';
    }
    return mkdir(partial, 0755) != 0 && errno != EEXIST ? -1 : 0;
}

static int cmd_demo(int argc, char **argv)
{
    const char *dir = "build/demo";
    static const struct option longopts[] = {
        {"out-dir", required_argument, NULL, 'o'},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    int c;
    optind = 1;
    while ((c = getopt_long(argc, argv, "o:h", longopts, NULL)) != -1) {
        switch (c) {
        case 'o': dir = optarg; break;
        case 'h':
            printf("usage: pp5 demo [--out-dir DIR]\n\n"
                   "A tour of pp5 on generated data (no external files needed): the machine's\n"
                   "parameters, a whole-machine test pattern, native full-resolution and\n"
                   "gaze-directed renders of a head phantom, the same frame on the emulated\n"
                   "Pixel-Planes 5 with its frame time and ring traffic, and a synthetic gaze\n"
                   "trace replayed through the machine. Pictures and reports go to DIR\n"
                   "(default build/demo/).\n\n"
                   "Example:\n"
                   "  pp5 demo --out-dir /tmp/tour   then open /tmp/tour/*.png\n");
            return 0;
        default:
            return 2;
        }
    }
    pp5_status_t st = make_dirs(dir) == 0 ? outpath_check_dir("--out-dir", dir)
                                          : pp5_fail(PP5_E_IO, "--out-dir: cannot create %s: %s",
                                                     dir, strerror(errno));
    if (st != PP5_OK)
        return cliopt_report("demo", st);
    int total = (int)(sizeof demo_steps / sizeof demo_steps[0]);
    int failed = 0;
    for (int i = 0; i < total; i++) {
        /* Optind is global: each command resets it, but getopt's internal
         * state must also start afresh for the next argv. */
        optind = 0;
        if (run_step(&demo_steps[i], dir, i + 1, total) != 0)
            failed++;
        optind = 1;
    }
    printf("\n%d of %d demo steps ran; pictures and reports are in %s/\n", total - failed, total,
           dir);
    return failed ? 1 : 0;
}

PP5_COMMAND(demo, "the main demo: a tour of pp5 on generated data (make demo)", cmd_demo)
