/* cmd_reproduce.c: `pp5 reproduce NAME`, re-running a published experiment and
 * printing the paper's figures beside ours.  Each experiment is its own file
 * (reproduce_*.c) that registers itself with PP5_REPRODUCE (registry.h). */
#include <stdbool.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "cliopt.h"
#include "registry.h"

static void reproduce_usage(void)
{
    int n;
    const pp5_reproduce_t *r = pp5_reproductions(&n);
    printf("usage: pp5 reproduce NAME [--threads N] [--repeats N] [--out-dir DIR] [options of NAME]\n\n"
           "Re-runs a published experiment and prints the paper's figures beside ours,\n"
           "with the reasons where they differ.  Experiments:\n");
    for (int i = 0; i < n; i++)
        printf("  %-12s %s\n", r[i].name, r[i].summary);
    printf("Options:\n"
           "  --threads N   host threads (default 1, like the paper's single workstation)\n"
           "  --repeats N   frames per timing, median reported (default 3)\n"
           "  --out-dir D   also write every rendered image as PNG into D\n"
           "  pp5 reproduce NAME --help   an experiment's own options, if it has any\n"
           "Data: ../shared/data or $PP5_SHARED_DATA; missing data falls back to the\n"
           "Shepp-Logan phantom and the output says so.\n"
           "Example: pp5 reproduce table1 --repeats 5\n");
}

/* Takes the common options out of argv (into o); what is left, starting with
 * NAME, goes to the experiment. */
static pp5_status_t take_common_options(int argc, char **argv, pp5_reproduce_opts_t *o)
{
    int out = 0;
    long l;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        bool common = strcmp(a, "--threads") == 0 || strcmp(a, "--repeats") == 0 ||
                      strcmp(a, "--out-dir") == 0;
        if (!common) {
            argv[out++] = argv[i];
            continue;
        }
        if (!v)
            return pp5_fail(PP5_E_CONFIG, "%s needs a value", a);
        i++;
        pp5_status_t st = PP5_OK;
        if (strcmp(a, "--threads") == 0) {
            st = cliopt_long("--threads", v, 0, 64, &l);
            o->threads = (int)l;
        } else if (strcmp(a, "--repeats") == 0) {
            st = cliopt_long("--repeats", v, 1, 16, &l);
            o->repeats = (int)l;
        } else {
            o->out_dir = v;
        }
        if (st != PP5_OK)
            return st;
    }
    argv[out] = NULL;
    o->argc = out;
    o->argv = argv;
    return PP5_OK;
}

static pp5_status_t make_out_dir(const char *dir)
{
    struct stat sb;
    if (!dir || mkdir(dir, 0777) == 0 || (stat(dir, &sb) == 0 && S_ISDIR(sb.st_mode)))
        return PP5_OK;
    return pp5_fail(PP5_E_IO, "--out-dir %s: cannot create the folder", dir);
}

static int reproduce_main(int argc, char **argv)
{
    if (argc < 2 || strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
        reproduce_usage();
        return argc < 2 ? 2 : 0;
    }
    pp5_reproduce_opts_t o = {.threads = 1, .repeats = 3};
    pp5_status_t st = take_common_options(argc, argv, &o);
    if (st == PP5_OK && (o.argc < 1 || o.argv[0][0] == '-'))
        st = pp5_fail(PP5_E_CONFIG, "the experiment's name comes first (see pp5 reproduce --help)");
    if (st == PP5_OK)
        st = make_out_dir(o.out_dir);
    if (st != PP5_OK)
        return cliopt_report("reproduce", st);
    int n;
    const pp5_reproduce_t *r = pp5_reproductions(&n);
    for (int i = 0; i < n; i++)
        if (strcmp(r[i].name, o.argv[0]) == 0)
            return r[i].fn(&o);
    return cliopt_report("reproduce", pp5_fail(PP5_E_CONFIG, "unknown experiment '%s' (see pp5 "
                                               "reproduce --help)", o.argv[0]));
}

PP5_COMMAND(reproduce, "re-run a paper's experiment beside its published figures",
            reproduce_main)
