/* harness.h: pp5's small test harness.
 *
 *   TEST(ring_one_message_takes_bytes_over_bandwidth) {
 *       CHECK_EQ(ring_busy, expected);
 *   }
 *
 * Tests register themselves (constructor), run in name order, and the runner
 * ends with the line "N passed, N failed, N skipped".  A test that makes no
 * check and does not SKIP counts as failed: a test must assert something. */
#ifndef PP5_HARNESS_H
#define PP5_HARNESS_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

typedef void (*pp5_test_fn)(void);
void pp5_test_register(const char *name, const char *file, pp5_test_fn fn);

#define TEST(name)                                                            \
    static void test_##name(void);                                            \
    __attribute__((constructor)) static void test_reg_##name(void)            \
    {                                                                         \
        pp5_test_register(#name, __FILE__, test_##name);                      \
    }                                                                         \
    static void test_##name(void)

/* Internal: record one check; returns `ok`. */
bool pp5_test_check(bool ok, const char *file, int line, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
/* Abandon the current test (after a failed REQUIRE) or skip it. */
void pp5_test_abort(void) __attribute__((noreturn));
void pp5_test_skip(const char *fmt, ...) __attribute__((noreturn, format(printf, 1, 2)));

#define CHECK(cond) pp5_test_check((cond), __FILE__, __LINE__, "%s", #cond)
#define CHECK_MSG(cond, ...) pp5_test_check((cond), __FILE__, __LINE__, __VA_ARGS__)
#define REQUIRE(cond)                                                         \
    do { if (!CHECK(cond)) pp5_test_abort(); } while (0)
#define REQUIRE_MSG(cond, ...)                                                \
    do { if (!CHECK_MSG(cond, __VA_ARGS__)) pp5_test_abort(); } while (0)
/* Each operand is evaluated exactly once (a call with side effects is safe). */
bool pp5_test_check_eq(long long a, long long b, const char *sa, const char *sb,
                       const char *file, int line);
bool pp5_test_check_near(double a, double b, double tol, const char *sa, const char *sb,
                         const char *file, int line);
#define CHECK_EQ(a, b) \
    pp5_test_check_eq((long long)(a), (long long)(b), #a, #b, __FILE__, __LINE__)
#define CHECK_NEAR(a, b, tol) \
    pp5_test_check_near((double)(a), (double)(b), (double)(tol), #a, #b, __FILE__, __LINE__)
#define SKIP(...) pp5_test_skip(__VA_ARGS__)

/* Path of a file under ../shared/data (or $PP5_SHARED_DATA), or NULL when
 * absent; tests that need real data SKIP loudly when this is NULL.  The path
 * lives in a static buffer that the next call overwrites: copy it to keep it. */
const char *pp5_test_shared_data(const char *relative_path);
/* A fresh, empty directory for this test's output files (under build/). */
const char *pp5_test_outdir(void);
/* Runs `pp5 ARGS` (the built binary, $PP5_BIN) through the shell with stdout
 * and stderr sent to the named files (NULL: /dev/null); returns the exit code. */
int pp5_test_run_cli(const char *args, const char *stdout_path, const char *stderr_path);
/* Reads a whole small text file into a malloc'd NUL-terminated buffer. */
char *pp5_test_read_file(const char *path);

#endif
