/* test_reproduce_help.c: every `pp5 reproduce NAME --help` prints its usage
 * with an example and returns at once (it does not run the experiment), and an
 * unknown option is a usage error, not an experiment run with it ignored. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "emu/util/registry.h"
#include "emu/util/status.h"
#include "harness.h"

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

TEST(reproduce_every_experiment_has_help_and_refuses_unknown_options)
{
    int n;
    const pp5_reproduce_t *r = pp5_reproductions(&n);
    REQUIRE(n >= 5);   /* table1, projections, demip, events, meshes at least */
    char out[1200], err[1200], args[256];
    snprintf(out, sizeof out, "%s/out.txt", pp5_test_outdir());
    snprintf(err, sizeof err, "%s/err.txt", pp5_test_outdir());
    for (int i = 0; i < n; i++) {
        snprintf(args, sizeof args, "reproduce %s --help", r[i].name);
        double t0 = now_s();
        int rc = pp5_test_run_cli(args, out, err);
        double dt = now_s() - t0;
        CHECK_MSG(rc == 0, "%s exited %d", args, rc);
        /* Help is printed, not computed: even a slow shared machine answers
         * in well under the seconds an experiment takes. */
        CHECK_MSG(dt < 5.0, "%s took %.1f s: did it run the experiment?", args, dt);
        char *text = pp5_test_read_file(out);
        REQUIRE(text != NULL);
        CHECK_MSG(strstr(text, "usage: pp5 reproduce") != NULL, "%s: no usage line", args);
        CHECK_MSG(strstr(text, "Example: pp5 reproduce") != NULL, "%s: no example", args);
        free(text);
        snprintf(args, sizeof args, "reproduce %s --no-such-option", r[i].name);
        rc = pp5_test_run_cli(args, out, err);
        CHECK_MSG(rc == PP5_EXIT_USAGE, "%s exited %d, not %d", args, rc, PP5_EXIT_USAGE);
    }
}
