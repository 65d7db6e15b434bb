/* bench.c: `pp5 bench`, which runs the speed benchmarks that the modules
 * register with PP5_BENCH.  Benchmarks print figures; they never fail on speed. */
#include <getopt.h>
#include <stdio.h>
#include <string.h>

#include "registry.h"

static int cmd_bench(int argc, char **argv)
{
    pp5_bench_opts_t opts = {0};
    static const struct option longopts[] = {
        {"peers", no_argument, NULL, 'p'},
        {"quick", no_argument, NULL, 'q'},
        {"list", no_argument, NULL, 'l'},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    bool list = false;
    int c;
    optind = 1;
    while ((c = getopt_long(argc, argv, "pqlh", longopts, NULL)) != -1) {
        switch (c) {
        case 'p': opts.peers = true; break;
        case 'q': opts.quick = true; break;
        case 'l': list = true; break;
        case 'h':
            printf("usage: pp5 bench [--peers] [--quick] [--list] [NAME...]\n\n"
                   "Runs the speed benchmarks and prints their figures (it never fails on\n"
                   "speed). NAME selects benchmarks by name prefix; default: all.\n"
                   "  --peers  also run comparisons against other renderers (VTK, VolPack),\n"
                   "           installing them if needed (root)\n"
                   "  --quick  smaller problem sizes\n"
                   "  --list   list the benchmarks and exit\n\n"
                   "Example:\n"
                   "  pp5 bench --quick render     the native renderer's figures, small sizes\n");
            return 0;
        default:
            return 2;
        }
    }
    int n;
    const pp5_bench_t *b = pp5_benches(&n);
    int failures = 0, ran = 0;
    for (int i = 0; i < n; i++) {
        bool selected = optind >= argc;
        for (int a = optind; a < argc; a++)
            if (strncmp(b[i].name, argv[a], strlen(argv[a])) == 0)
                selected = true;
        if (!selected)
            continue;
        if (list) {
            printf("%-20s %s\n", b[i].name, b[i].summary);
            continue;
        }
        printf("== bench %s: %s\n", b[i].name, b[i].summary);
        fflush(stdout);
        if (b[i].fn(&opts) != 0) {
            printf("   (benchmark %s could not run; see above)\n", b[i].name);
            failures++;
        }
        ran++;
    }
    if (!list && ran == 0)
        fprintf(stderr, "pp5 bench: no benchmark matched\n");
    return failures ? 1 : 0;
}

PP5_COMMAND(bench, "run the speed benchmarks and print their figures", cmd_bench)
