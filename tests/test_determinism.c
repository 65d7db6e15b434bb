/* test_determinism.c: the same command twice, and with 1, 2 and 3 host
 * threads, gives bit-identical images, reports and CSVs (tests/determinism.h).
 *
 * Covered here: the native renderer (gaze-directed, and progressive with
 * perspective and specular lighting), test-pattern and the gaze-directed
 * firmware on the emulated machine, a sweep (whose rows for 1, 2 and 3 host
 * threads must agree), replay through the emulated machine, trace synth and
 * import, mesh simplification with its level record, and the images of
 * reproduce demip.  Replay's machine cost
 * source runs one host thread (firmware/host/replay_machine.c), and synth and
 * import run none, so those are compared run against run. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "determinism.h"
#include "harness.h"

static const int one_two_three[] = {1, 2, 3};
static const int just_one[] = {1};

TEST(determinism_json_drop_removes_members_at_any_depth)
{
    char json[] = "{\n  \"a\": 1,\n  \"host_timing\": {\"ms\": [1.5, {\"x\": \"}\"}]},\n"
                  "  \"b\": {\"host_timing\": 2, \"c\": \"host_timing\"},\n"
                  "  \"host_timing\": 3\n}\n";
    size_t n = pp5_det_json_drop(json, strlen(json), "host_timing");
    /* Worked out by hand: both members and the nested one go with their commas;
     * the string value "host_timing" stays. */
    CHECK_MSG(strcmp(json, "{\n  \"a\": 1,\n  \"b\": { \"c\": \"host_timing\"}\n}\n") == 0,
              "got '%s'", json);
    CHECK_EQ(n, strlen(json));
}

TEST(determinism_threads_native_render_gaze)
{
    static const char *const outs[] = {"g.png", "g.json", NULL};
    int n = pp5_det_runs(pp5_test_outdir(), "render gaze",
                         "render --phantom sphere-shell --mode gaze --size 96x96 --gaze 30,60 "
                         "--compare --out @/g.png --report @/g.json --threads {T}",
                         outs, one_two_three, 3, NULL);
    CHECK_EQ(n, 2 * 3);
}

TEST(determinism_threads_native_render_progressive_perspective_specular)
{
    static const char *const outs[] = {"f.png", "f.json", NULL};
    int n = pp5_det_runs(pp5_test_outdir(), "render progressive",
                         "render --phantom marschner-lobb --mode gaze --progressive 2 --size 64x64 "
                         "--projection perspective --lighting specular --out @/f.png "
                         "--report @/f.json --threads {T}",
                         outs, one_two_three, 3, NULL);
    CHECK_EQ(n, 2 * 3);
}

TEST(determinism_threads_test_pattern_host_threads)
{
    /* The machine report records its command line and every parameter,
     * sim.host_threads included: those two members name the thread count. */
    static const char *const outs[] = {"tp.png", "tp.json", "tl.json", NULL};
    static const char *const thread_keys[] = {"command_line", "sim.host_threads", NULL};
    int n = pp5_det_runs(pp5_test_outdir(), "test-pattern",
                         "test-pattern --out @/tp.png --report @/tp.json --timeline @/tl.json "
                         "--set sim.host_threads={T}",
                         outs, one_two_three, 3, thread_keys);
    CHECK_EQ(n, 3 * 3);
}

TEST(determinism_twice_replay_through_the_machine)
{
    static const char *const outs[] = {"r.json", "f.csv", "p.png", "frame_00000.png",
                                       "frame_00002.png", NULL};
    int n = pp5_det_runs(pp5_test_outdir(), "replay",
                         "replay traces/saccades_10s_250hz.trace --cost machine:size=48x48 "
                         "--max-frames 3 --predict kalman --report @/r.json --csv @/f.csv "
                         "--plot @/p.png --frames-dir @",
                         outs, just_one, 1, NULL);
    CHECK_EQ(n, 5);
}

TEST(determinism_twice_trace_synth_and_import)
{
    const char *dir = pp5_test_outdir();
    static const char *const synth_outs[] = {"s.trace", NULL};
    CHECK_EQ(pp5_det_runs(dir, "synth",
                          "trace synth --mode mixed --seconds 2 --seed 7 --out @/s.trace",
                          synth_outs, just_one, 1, NULL), 1);
    char asc[1200];
    snprintf(asc, sizeof asc, "%s/in.asc", dir);
    FILE *f = fopen(asc, "w");
    REQUIRE(f != NULL);
    fputs("** CONVERTED FROM x.edf\nMSG\t1 DISPLAY_COORDS 0 0 1023 767\n"
          "START\t10 \tLEFT\tRIGHT\tSAMPLES\tEVENTS\nSAMPLES\tGAZE\tLEFT\tRIGHT\tRATE\t500.00\n"
          "10\t512.0\t384.0\t900.0\t520.0\t380.0\t910.0\t.....\n"
          "12\t513.5\t385.0\t900.0\t521.0\t381.0\t905.0\t.....\n"
          "14\t   .\t   .\t0.0\t522.0\t382.0\t905.0\t.....\n"
          "EFIX L 10 14 4 513 384 900\nEND\t16 \tSAMPLES\tEVENTS\tRES\t 35.0\t 36.0\n", f);
    REQUIRE(fclose(f) == 0);
    char args[3000];
    snprintf(args, sizeof args, "trace import %s --out @/e.trace --to paper", asc);
    static const char *const import_outs[] = {"e.trace", NULL};
    CHECK_EQ(pp5_det_runs(dir, "import", args, import_outs, just_one, 1, NULL), 1);
}

TEST(determinism_threads_machine_render_gaze)
{
    /* The gaze-directed firmware on the emulated machine: image, frame
     * breakdown and machine report the same for 1, 2 and 3 host threads. */
    static const char *const outs[] = {"m.png", "m.json", "m.json.machine.json", NULL};
    static const char *const thread_keys[] = {"command_line", "sim.host_threads", NULL};
    int n = pp5_det_runs(pp5_test_outdir(), "render machine",
                         "render --machine --phantom marschner-lobb --mode gaze --size 32x32 "
                         "--gaze 12,20 --out @/m.png --report @/m.json --set sim.host_threads={T}",
                         outs, one_two_three, 3, thread_keys);
    CHECK_EQ(n, 3 * 3);
}

TEST(determinism_twice_sweep_and_its_rows_equal_across_host_threads)
{
    static const char *const outs[] = {"s.csv", "s.json", "s.png", NULL};
    char dir[1024];   /* pp5_test_outdir() empties the folder on every call */
    snprintf(dir, sizeof dir, "%s", pp5_test_outdir());
    int n = pp5_det_runs(dir, "sweep",
                         "sweep --phantom marschner-lobb --size 16x16 --set gp.count=4 "
                         "--set sim.host_threads=1,2,3 --out @/s.csv --report @/s.json "
                         "--plot @/s.png",
                         outs, just_one, 1, NULL);
    CHECK_EQ(n, 3);
    /* Within one CSV the three rows differ only in the host-thread column
     * (the second): every emulated figure is the same. */
    char path[1200];
    snprintf(path, sizeof path, "%s/sweep/run1/s.csv", dir);
    char *text = pp5_test_read_file(path);
    REQUIRE(text != NULL);
    char *rows[4] = {NULL};
    int n_rows = 0;
    for (char *line = strtok(text, "\n"); line && n_rows < 4; line = strtok(NULL, "\n"))
        rows[n_rows++] = line;
    REQUIRE(n_rows == 4);
    for (int r = 1; r <= 3; r++) {
        char *c1 = strchr(rows[r], ','), *c2 = c1 ? strchr(c1 + 1, ',') : NULL;
        REQUIRE(c1 && c2);
        CHECK_EQ(c2 - c1, 2);                     /* a one-digit thread count */
        CHECK_EQ(c1[1], '0' + r);
        CHECK_MSG(strcmp(c2, strchr(strchr(rows[1], ',') + 1, ',')) == 0,
                  "row %d differs from row 1 beyond the thread column", r);
    }
    free(text);
}

TEST(determinism_twice_mesh_simplify_with_levels)
{
    static const char *const outs[] = {"s.obj", "s.pmr", NULL};
    int n = pp5_det_runs(pp5_test_outdir(), "mesh",
                         "mesh simplify gen:torus --method seed003 --ratio 0.25 --out @/s.obj "
                         "--levels @/s.pmr",
                         outs, just_one, 1, NULL);
    CHECK_EQ(n, 2);
}

TEST(determinism_threads_reproduce_demip_images)
{
    /* A reproduction's images (its tables carry host times, which differ
     * from run to run by nature); --machine-size 0 leaves out the machine's
     * columns, whose frames the machine determinism test above covers and
     * which take minutes under ThreadSanitizer. */
    static const char *const outs[] = {"demip_sphere-shell.png", "demip_sphere-shell_eps.png",
                                       "demip_sphere-shell_pyramid.png", NULL};
    int n = pp5_det_runs(pp5_test_outdir(), "reproduce demip",
                         "reproduce demip --size 32 --machine-size 0 --datasets sphere-shell --repeats 1 "
                         "--threads {T} --out-dir @",
                         outs, one_two_three, 3, NULL);
    CHECK_EQ(n, 3 * 3);
}

/* reproduce projections runs its machines side by side on --threads host
 * threads and prints them in their order: the whole text (the table and
 * the sensitivity block, emulated figures only) is the same for 1 and 2. */
TEST(determinism_threads_reproduce_projections_quick)
{
    char out[2][1024], err[1024];
    const int threads[2] = {1, 2};
    const char *dir = pp5_test_outdir();     /* (each call empties the folder) */
    for (int k = 0; k < 2; k++) {
        char args[128];
        snprintf(out[k], sizeof out[k], "%s/projections_t%d.txt", dir, threads[k]);
        snprintf(err, sizeof err, "%s/projections_t%d.err", dir, threads[k]);
        snprintf(args, sizeof args, "reproduce projections --quick --threads %d", threads[k]);
        REQUIRE_MSG(pp5_test_run_cli(args, out[k], err) == 0, "pp5 %s failed", args);
    }
    char *a = pp5_test_read_file(out[0]), *b = pp5_test_read_file(out[1]);
    REQUIRE(a && b);
    CHECK(strstr(a, "| B | object-slabs |") != NULL);   /* the table is there */
    CHECK(strstr(a, "Sensitivity of the headline") != NULL);
    CHECK_MSG(strcmp(a, b) == 0, "output differs between 1 and 2 threads");
    free(a);
    free(b);
}
