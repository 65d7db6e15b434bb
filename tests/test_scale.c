/* test_scale.c: `pp5 sweep` and `pp5 replay --batch` as work units: the same
 * bytes from a plain run, from mpirun with 1, 2 and 3 ranks, and from shards
 * merged; a failed unit reported by id while the rest finish; --resume after
 * a kill.  The MPI cases run only in a build with MPI (and SKIP loudly
 * otherwise); the rest run in both builds, which is how CI checks that the
 * serial build's commands behave the same.
 *
 * mpirun refuses to run as root unless told: the tests pass
 * --allow-run-as-root only when they are root (CI and containers are), and
 * --oversubscribe so that 3 ranks run on a 2-core machine. */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "harness.h"
#include "pp5_features.h"
#include "workunit.h"

/* Cheap units: a small phantom and image; half the points fail at once
 * (65536 bytes of GP memory cannot hold the program's data). */
#define GRID "sweep --phantom marschner-lobb --size 16x16 --lighting diffuse " \
             "--set gp.count=2,4 --set gp.local_mem_bytes=65536,8388608"

static const char *bin(void)
{
    const char *b = getenv("PP5_BIN");
    return b && *b ? b : "./pp5";
}

/* Runs a shell command line with output to files; the exit code. */
static int run_shell(const char *line)
{
    int rc = system(line);
    if (rc == -1)
        return -1;
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : 128 + (WIFSIGNALED(rc) ? WTERMSIG(rc) : 0);
}

/* Under AddressSanitizer (make SAN=1), LeakSanitizer would report what Open
 * MPI keeps until exit: its frames are suppressed (tests/fixtures/
 * lsan-openmpi.supp), with full stacks and its plugins kept loaded so that
 * the frames have names; pp5's own leaks are still reported. */
#if defined(__SANITIZE_ADDRESS__)
#define MPI_TEST_ENV "OMPI_MCA_mca_base_component_disable_dlclose=1 " \
    "LSAN_OPTIONS=suppressions=tests/fixtures/lsan-openmpi.supp:fast_unwind_on_malloc=0:" \
    "print_suppressions=0 "
#else
#define MPI_TEST_ENV ""
#endif

/* `mpirun -n N pp5 ARGS`, stdout and stderr into files. */
static int run_mpi(int n, const char *args, const char *out, const char *err)
{
    char line[4096];
    snprintf(line, sizeof line, MPI_TEST_ENV "mpirun --oversubscribe %s -n %d %s %s >%s 2>%s "
             "</dev/null", geteuid() == 0 ? "--allow-run-as-root" : "", n, bin(), args, out, err);
    return run_shell(line);
}

static void need_mpi(void)
{
    if (!PP5_HAVE_MPI)
        SKIP("this build has no MPI (built with MPI=0, or without libopenmpi-dev): the "
             "mpirun cases are not checked here");
    if (run_shell("command -v mpirun >/dev/null 2>&1") != 0)
        SKIP("mpirun is not on PATH (Debian: openmpi-bin)");
    /* A launcher that cannot start even `true` here (a sandbox without the
     * mounts or name resolution it wants) says nothing about pp5. */
    static int probe = -1;
    if (probe < 0) {
        char line[512];
        snprintf(line, sizeof line, "mpirun --oversubscribe %s -n 2 true >/dev/null 2>&1 "
                 "</dev/null", geteuid() == 0 ? "--allow-run-as-root" : "");
        probe = run_shell(line);
    }
    if (probe != 0)
        SKIP("`mpirun -n 2 true` fails on this machine (exit %d): the mpirun cases cannot "
             "run here", probe);
}

static bool same_file(const char *a, const char *b)
{
    char *x = pp5_test_read_file(a), *y = pp5_test_read_file(b);
    bool same = x && y && strcmp(x, y) == 0;
    if (!same)
        fprintf(stderr, "    %s and %s differ (or one is missing)\n", a, b);
    free(x);
    free(y);
    return same;
}

static int count_lines(const char *path)
{
    char *t = pp5_test_read_file(path);
    int n = 0;
    for (const char *p = t; p && *p; p++)
        n += *p == '\n';
    free(t);
    return t ? n : -1;
}

/* The plain run of GRID (made once, by the first test that needs it): its
 * CSV, report and stderr, and the checks every run shares. */
static void plain_grid(char *csv, char *json, char *err, size_t cap)
{
    static bool made;
    const char *dir = "build/test-out/scale-plain-grid";
    snprintf(csv, cap, "%s/plain.csv", dir);
    snprintf(json, cap, "%s/plain.json", dir);
    snprintf(err, cap, "%s/plain.err", dir);
    if (made)
        return;
    char args[2048];
    snprintf(args, sizeof args, "rm -rf %s && mkdir -p %s", dir, dir);
    REQUIRE(run_shell(args) == 0);
    snprintf(args, sizeof args, GRID " --out %s --report %s --plot %s/plain.png", csv, json, dir);
    REQUIRE(pp5_test_run_cli(args, NULL, err) == WORKUNIT_EXIT_UNITS_FAILED);
    made = true;
    CHECK_EQ(count_lines(csv), 5);
    char *text = pp5_test_read_file(csv);
    int errors = 0;
    for (const char *p = text; p && (p = strstr(p, "exceeds local memory")); p++)
        errors++;
    CHECK_EQ(errors, 2);
    free(text);
}

TEST(scale_sweep_mpirun_1_2_3_ranks_write_the_plain_runs_bytes)
{
    need_mpi();
    const char *dir = pp5_test_outdir();
    char csv[600], json[600], perr[600];
    plain_grid(csv, json, perr, sizeof csv);
    for (int n = 1; n <= 3; n++) {
        char args[2048], out[600], err[600], mcsv[600], mjson[600];
        snprintf(mcsv, sizeof mcsv, "%s/n%d.csv", dir, n);
        snprintf(mjson, sizeof mjson, "%s/n%d.json", dir, n);
        snprintf(out, sizeof out, "%s/n%d.out", dir, n);
        snprintf(err, sizeof err, "%s/n%d.err", dir, n);
        snprintf(args, sizeof args, GRID " --out %s --report %s --plot %s/n%d.png", mcsv, mjson,
                 dir, n);
        int rc = run_mpi(n, args, out, err);
        /* mpirun passes on the non-zero exit of rank 0 (3: failed units). */
        CHECK_MSG(rc == WORKUNIT_EXIT_UNITS_FAILED, "%d ranks: exit %d (see %s)", n, rc, err);
        CHECK_MSG(same_file(csv, mcsv), "%d ranks: CSV differs", n);
        CHECK_MSG(same_file(json, mjson), "%d ranks: report differs", n);
        char *e = pp5_test_read_file(err);
        char want[64];
        snprintf(want, sizeof want, "on %d rank%s", n, n == 1 ? "" : "s");
        CHECK_MSG(e && strstr(e, want), "%d ranks: the accounting does not say '%s'", n, want);
        free(e);
    }
}

/* Unit ids are the FNV-1a-64 of the key (checked against published vectors
 * in test_workunit.c): the message names the failed point by it. */
TEST(scale_sweep_failed_point_is_reported_by_id_and_the_rest_finish)
{
    char csv[600], json[600], err[600];
    plain_grid(csv, json, err, sizeof csv);
    char *e = pp5_test_read_file(err), want[160];
    const char *key = "gp.count=4 gp.local_mem_bytes=65536";
    snprintf(want, sizeof want, "unit %016" PRIx64 " (%s) failed: ",
             workunit_hash(key, WORKUNIT_HASH_START), key);
    CHECK_MSG(e && strstr(e, want), "stderr lacks '%s'", want);
    free(e);
    char *text = pp5_test_read_file(csv);
    CHECK(text && strstr(text, "\n2,8388608,0.") && strstr(text, "\n4,8388608,0."));
    free(text);
    char *report = pp5_test_read_file(json);
    CHECK(report && strstr(report, "\"status\":\"failed\"") &&
          strstr(report, "\"bottleneck\":"));
    free(report);
}

/* The part of shard K holds exactly the units whose id mod N is K: their
 * number, from the ids the test works out from the keys. */
static int check_part_ids(const char *part, unsigned k, unsigned n)
{
    static const char *const keys[] = {
        "gp.count=2 gp.local_mem_bytes=65536", "gp.count=2 gp.local_mem_bytes=8388608",
        "gp.count=4 gp.local_mem_bytes=65536", "gp.count=4 gp.local_mem_bytes=8388608"};
    int want = 0, records = 0;
    for (int i = 0; i < 4; i++)
        want += workunit_hash(keys[i], WORKUNIT_HASH_START) % n == k;
    char *t = pp5_test_read_file(part);
    REQUIRE(t != NULL);
    for (const char *p = strstr(t, "\nr "); p; p = strstr(p + 1, "\nr ")) {
        size_t index;
        uint64_t id;
        REQUIRE(sscanf(p, "\nr %zu %" SCNx64, &index, &id) == 2);
        CHECK_MSG(id % n == k, "%s holds unit %016" PRIx64, part, id);
        records++;
    }
    CHECK_EQ(records, want);
    free(t);
    return records;
}

TEST(scale_sweep_shards_merged_equal_the_single_run)
{
    const char *dir = pp5_test_outdir();
    char csv[600], json[600], err[600], args[4096], parts[1300] = "";
    plain_grid(csv, json, err, sizeof csv);
    int held[2];
    for (unsigned k = 0; k < 2; k++) {
        char part[600];
        snprintf(part, sizeof part, "%s/part%u.units", dir, k);
        snprintf(args, sizeof args, GRID " --shard %u/2 --out %s", k, part);
        int rc = pp5_test_run_cli(args, NULL, NULL);
        CHECK(rc == 0 || rc == WORKUNIT_EXIT_UNITS_FAILED);
        held[k] = check_part_ids(part, k, 2);
        strcat(parts, part);
        strcat(parts, " ");
    }
    CHECK_EQ(held[0] + held[1], 4);
    char mcsv[600], mjson[600];
    snprintf(mcsv, sizeof mcsv, "%s/merged.csv", dir);
    snprintf(mjson, sizeof mjson, "%s/merged.json", dir);
    snprintf(args, sizeof args, "merge %s --out %s --report %s", parts, mcsv, mjson);
    CHECK_EQ(pp5_test_run_cli(args, NULL, NULL), WORKUNIT_EXIT_UNITS_FAILED);
    CHECK(same_file(csv, mcsv));
    CHECK(same_file(json, mjson));
    /* A part that lacks units alone is not the whole grid: an error, and no output. */
    snprintf(args, sizeof args, "merge %s/part%d.units --out %s/half.csv", dir,
             held[0] < 4 ? 0 : 1, dir);
    CHECK_EQ(pp5_test_run_cli(args, NULL, NULL), PP5_EXIT_INPUT);
    snprintf(args, sizeof args, "%s/half.csv", dir);
    CHECK(access(args, F_OK) != 0);
}

TEST(scale_sweep_resume_after_a_kill_completes_with_identical_output)
{
    const char *dir = pp5_test_outdir();
    char csv[600], json[600], args[2048], rcsv[600], rjson[600], err[600];
    plain_grid(csv, json, err, sizeof csv);
    snprintf(rcsv, sizeof rcsv, "%s/r.csv", dir);
    snprintf(rjson, sizeof rjson, "%s/r.json", dir);
    snprintf(err, sizeof err, "%s/r.err", dir);
    snprintf(args, sizeof args, "PP5_WORKUNIT_KILL_AFTER=2 %s " GRID " --out %s --report %s "
             "--plot %s/r.png >/dev/null 2>%s", bin(), rcsv, rjson, dir, err);
    CHECK_EQ(run_shell(args), 128 + 9);
    CHECK(access(rcsv, F_OK) != 0);
    /* A record cut short, as a kill in mid-write leaves. */
    snprintf(args, sizeof args, "printf 'r 3 00ff 0' >> %s.units", rcsv);
    REQUIRE(run_shell(args) == 0);
    snprintf(args, sizeof args, GRID " --resume --out %s --report %s --plot %s/r.png", rcsv,
             rjson, dir);
    /* Of the two units done before the kill, the failed one runs again. */
    bool mpi = PP5_HAVE_MPI && run_shell("command -v mpirun >/dev/null 2>&1") == 0;
    char out[600];
    snprintf(out, sizeof out, "%s/r2.out", dir);
    int rc = mpi ? run_mpi(2, args, out, err) : pp5_test_run_cli(args, out, err);
    CHECK_EQ(rc, WORKUNIT_EXIT_UNITS_FAILED);
    char *e = pp5_test_read_file(err);
    CHECK_MSG(e && strstr(e, "1 of 4 units done, 3 to run") && strstr(e, "ignoring what follows"),
              "resume did not say what it kept (see %s)", err);
    free(e);
    CHECK(same_file(csv, rcsv));
    CHECK(same_file(json, rjson));
}

/* A list of cheap replays (constant frame cost), one of them broken. */
static void write_list(const char *path)
{
    FILE *f = fopen(path, "w");
    REQUIRE(f != NULL);
    fprintf(f, "# trace and options\n"
               "traces/saccades_10s_250hz.trace --predict kalman --latency-ms 40\n"
               "traces/saccades_10s_250hz.trace --predict none\n"
               "traces/pursuit_10s_250hz.trace --predict linear --frame-time-ms 50\n"
               "\n"
               "traces/no-such.trace\n"
               "traces/mixed_10s_250hz.trace --predict alphabeta --refresh-hz 60\n"
               "traces/pursuit_4s_1000hz.trace --tracker-latency-ms 8 --display-latency-ms 8\n");
    fclose(f);
}

TEST(scale_replay_batch_shards_merged_equal_the_single_run)
{
    const char *dir = pp5_test_outdir();
    char list[600], csv[600], json[600], args[4096];
    snprintf(list, sizeof list, "%s/runs.list", dir);
    write_list(list);
    snprintf(csv, sizeof csv, "%s/plain.csv", dir);
    snprintf(json, sizeof json, "%s/plain.json", dir);
    snprintf(args, sizeof args, "replay --batch %s --cost constant:66 --out %s --report %s",
             list, csv, json);
    CHECK_EQ(pp5_test_run_cli(args, NULL, NULL), WORKUNIT_EXIT_UNITS_FAILED);
    CHECK_EQ(count_lines(csv), 7);
    char *text = pp5_test_read_file(csv);
    CHECK(text && strstr(text, "no-such.trace: cannot open"));
    free(text);
    char parts[1300] = "", part[600];
    for (unsigned k = 0; k < 3; k++) {
        snprintf(part, sizeof part, "%s/part%u.units", dir, k);
        snprintf(args, sizeof args, "replay --batch %s --cost constant:66 --shard %u/3 --out %s",
                 list, k, part);
        int rc = pp5_test_run_cli(args, NULL, NULL);
        CHECK(rc == 0 || rc == WORKUNIT_EXIT_UNITS_FAILED);
        strcat(parts, part);
        strcat(parts, " ");
    }
    char mcsv[600];
    snprintf(mcsv, sizeof mcsv, "%s/merged.csv", dir);
    snprintf(args, sizeof args, "merge %s --out %s", parts, mcsv);
    CHECK_EQ(pp5_test_run_cli(args, NULL, NULL), WORKUNIT_EXIT_UNITS_FAILED);
    CHECK(same_file(csv, mcsv));
}

TEST(scale_replay_batch_is_identical_for_1_2_3_ranks)
{
    need_mpi();
    const char *dir = pp5_test_outdir();
    char list[600], csv[600], json[600], args[4096];
    snprintf(list, sizeof list, "%s/runs.list", dir);
    write_list(list);
    snprintf(csv, sizeof csv, "%s/plain.csv", dir);
    snprintf(json, sizeof json, "%s/plain.json", dir);
    snprintf(args, sizeof args, "replay --batch %s --cost constant:66 --out %s --report %s",
             list, csv, json);
    CHECK_EQ(pp5_test_run_cli(args, NULL, NULL), WORKUNIT_EXIT_UNITS_FAILED);
    for (int n = 1; n <= 3; n++) {
        char ncsv[600], njson[600], out[600], err[600];
        snprintf(ncsv, sizeof ncsv, "%s/n%d.csv", dir, n);
        snprintf(njson, sizeof njson, "%s/n%d.json", dir, n);
        snprintf(out, sizeof out, "%s/n%d.out", dir, n);
        snprintf(err, sizeof err, "%s/n%d.err", dir, n);
        snprintf(args, sizeof args, "replay --batch %s --cost constant:66 --out %s --report %s",
                 list, ncsv, njson);
        CHECK_EQ(run_mpi(n, args, out, err), WORKUNIT_EXIT_UNITS_FAILED);
        CHECK_MSG(same_file(csv, ncsv) && same_file(json, njson), "%d ranks differ", n);
    }
}

TEST(scale_replay_batch_rejects_bad_lines_naming_the_line)
{
    const char *dir = pp5_test_outdir();
    const char *bad[] = {"traces/pursuit_10s_250hz.trace --predict nope\n",
                         "traces/pursuit_10s_250hz.trace --csv x.csv\n",
                         "traces/pursuit_10s_250hz.trace --predict none\n"
                         "traces/pursuit_10s_250hz.trace  --predict  none\n",
                         "traces/pursuit_10s_250hz.trace \"unbalanced\n"};
    const char *want[] = {"runs.list:1:", "runs.list:1: a line sets", "same id",
                          "runs.list:1: unbalanced"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char list[600], args[1400], err[600];
        snprintf(list, sizeof list, "%s/runs.list", dir);
        snprintf(err, sizeof err, "%s/err%zu.txt", dir, i);
        FILE *f = fopen(list, "w");
        REQUIRE(f != NULL);
        fputs(bad[i], f);
        fclose(f);
        snprintf(args, sizeof args, "replay --batch %s --out %s/b.csv", list, dir);
        CHECK_EQ(pp5_test_run_cli(args, NULL, err), 2);
        char *e = pp5_test_read_file(err);
        CHECK_MSG(e && strstr(e, want[i]), "case %zu: stderr lacks '%s'", i, want[i]);
        free(e);
    }
}

/* Under an MPI launcher's variables (set by hand here: no mpirun needed) a
 * build without MPI refuses instead of running the whole batch once per
 * rank; PP5_MPI=0 makes any build run plainly, with the plain run's bytes. */
TEST(scale_launcher_variables_without_mpi_refuse_and_pp5_mpi_0_runs_plainly)
{
    const char *dir = pp5_test_outdir();
    char csv[600], json[600], args[2048], err[600], pcsv[600];
    plain_grid(csv, json, err, sizeof csv);
    snprintf(err, sizeof err, "%s/e.txt", dir);
    snprintf(pcsv, sizeof pcsv, "%s/p.csv", dir);
    if (!PP5_HAVE_MPI) {
        snprintf(args, sizeof args, "OMPI_COMM_WORLD_RANK=0 %s " GRID " --out %s 2>%s",
                 bin(), pcsv, err);
        CHECK_EQ(run_shell(args), PP5_EXIT_UNSUPPORTED);   /* not built in */
        char *e = pp5_test_read_file(err);
        CHECK(e && strstr(e, "built without MPI"));
        free(e);
        CHECK(access(pcsv, F_OK) != 0);
    }
    snprintf(args, sizeof args, "OMPI_COMM_WORLD_RANK=0 PP5_MPI=0 %s " GRID " --out %s "
             "--plot %s/p.png >/dev/null 2>%s", bin(), pcsv, dir, err);
    CHECK_EQ(run_shell(args), WORKUNIT_EXIT_UNITS_FAILED);
    CHECK(same_file(csv, pcsv));
}
