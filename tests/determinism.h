/* determinism.h: helpers for tests that run a pp5 command several times and
 * require bit-identical outputs (images, reports, CSVs, traces).
 *
 *   static const char *const outs[] = {"g.png", "g.json", NULL};
 *   pp5_det_runs(pp5_test_outdir(), "render_native",
 *                "render --out @/g.png --report @/g.json --threads {T}",
 *                outs, (int[]){1, 2, 3}, 3, NULL);
 *
 * In ARGS, @ is the run's output folder and {T} the host thread count.  The
 * command runs twice with the first thread count, then once with each other
 * count; every run uses the same folder (so the command line is the same),
 * and its outputs are moved aside before the next run.  Each output must equal
 * the first run's byte for byte, except that in .json files the members named
 * "host_timing" (wall-clock times, thread counts: see render's report) are
 * removed first; runs with another thread count may also drop the members
 * named in `thread_keys` (e.g. "command_line" and "sim.host_threads" of the
 * machine report, which record the thread count by design).  Returns the
 * number of outputs compared; failures are CHECKs naming the output, the run
 * and the first differing byte. */
#ifndef PP5_DETERMINISM_H
#define PP5_DETERMINISM_H

#include <stddef.h>

/* `dir` is the test's folder (pp5_test_outdir()); runs go to dir/NAME/work
 * and dir/NAME/runK, so inputs the test made in dir stay where they are. */
int pp5_det_runs(const char *dir, const char *name, const char *args,
                 const char *const *outputs, const int *threads, int n_threads,
                 const char *const *thread_keys);
/* Removes every member `"key": value` (at any depth) from JSON text, with its
 * comma; returns the new length.  Exposed for its own test. */
size_t pp5_det_json_drop(char *json, size_t len, const char *key);

#endif
