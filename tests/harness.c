/* harness.c: the test runner (main) behind harness.h.
 *
 * usage: pp5-tests [--list] [SUBSTRING...]
 * Runs every registered test whose name contains one of the substrings.
 *
 * Each test runs in its own child process (fork), so a test that crashes,
 * aborts or hangs is reported as that test's failure, with its signal, and
 * the rest still run; the child sends its check counts back through a pipe.
 * PP5_TEST_TIMEOUT_S (default 600) bounds one test; PP5_TEST_NO_FORK=1 runs
 * tests in the runner itself (for a debugger).  Tests named harness_selftest_*
 * run only when PP5_TEST_SELFTEST=1: they crash on purpose, and the test
 * harness_isolates_crashing_tests runs them in a child runner.  Tests named
 * soak_* run only when PP5_SOAK=1 (`make soak`). */
#include "harness.h"

#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define MAX_TESTS 2048

typedef struct {
    const char *name;
    const char *file;
    pp5_test_fn fn;
} test_entry_t;

static test_entry_t tests[MAX_TESTS];
static int n_tests;

static jmp_buf test_exit;
static int checks_made, checks_failed;
static char skip_reason[512];
static const char *current_name;
static char outdir[1024];
static char shared_path[2048];

void pp5_test_register(const char *name, const char *file, pp5_test_fn fn)
{
    if (n_tests == MAX_TESTS) {
        fprintf(stderr, "too many tests\n");
        abort();
    }
    tests[n_tests++] = (test_entry_t){name, file, fn};
}

bool pp5_test_check(bool ok, const char *file, int line, const char *fmt, ...)
{
    checks_made++;
    if (!ok) {
        checks_failed++;
        /* Cap the noise from one test: the first failures explain the rest. */
        if (checks_failed <= 10) {
            va_list ap;
            va_start(ap, fmt);
            fprintf(stdout, "    %s:%d: check failed: ", file, line);
            vfprintf(stdout, fmt, ap);
            fputc('\n', stdout);
            va_end(ap);
        }
    }
    return ok;
}

bool pp5_test_check_eq(long long a, long long b, const char *sa, const char *sb,
                       const char *file, int line)
{
    return pp5_test_check(a == b, file, line, "%s == %s (%lld vs %lld)", sa, sb, a, b);
}

bool pp5_test_check_near(double a, double b, double tol, const char *sa, const char *sb,
                         const char *file, int line)
{
    /* NaN on either side fails: fabs(NaN) <= tol is false. */
    return pp5_test_check(fabs(a - b) <= tol, file, line, "%s ~= %s (%.9g vs %.9g, tol %g)", sa,
                          sb, a, b, tol);
}

void pp5_test_abort(void)
{
    longjmp(test_exit, 1);
}

void pp5_test_skip(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(skip_reason, sizeof skip_reason, fmt, ap);
    va_end(ap);
    longjmp(test_exit, 2);
}

const char *pp5_test_shared_data(const char *relative_path)
{
    const char *root = getenv("PP5_SHARED_DATA");
    if (!root || !*root)
        root = "../shared/data";
    snprintf(shared_path, sizeof shared_path, "%s/%s", root, relative_path);
    return access(shared_path, R_OK) == 0 ? shared_path : NULL;
}

static void make_dirs(const char *path)
{
    char tmp[1024];
    snprintf(tmp, sizeof tmp, "%s", path);
    for (char *p = tmp + 1; *p; p++) {
        if (*p == '/') {
            *p = '\0';
            mkdir(tmp, 0755);
            *p = '/';
        }
    }
    mkdir(tmp, 0755);
}

const char *pp5_test_outdir(void)
{
    snprintf(outdir, sizeof outdir, "build/test-out/%s", current_name);
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", outdir);
    if (system(cmd) != 0)
        fprintf(stderr, "warning: could not clear %s\n", outdir);
    make_dirs(outdir);
    return outdir;
}

int pp5_test_run_cli(const char *args, const char *stdout_path, const char *stderr_path)
{
    const char *bin = getenv("PP5_BIN");
    if (!bin || !*bin)
        bin = "./pp5";
    size_t len = strlen(bin) + strlen(args) + 2200;
    char *cmd = malloc(len);
    snprintf(cmd, len, "%s %s >%s 2>%s </dev/null", bin, args,
             stdout_path ? stdout_path : "/dev/null", stderr_path ? stderr_path : "/dev/null");
    int rc = system(cmd);
    free(cmd);
    if (rc == -1)
        return -1;
    if (WIFEXITED(rc))
        return WEXITSTATUS(rc);
    return 128 + (WIFSIGNALED(rc) ? WTERMSIG(rc) : 0);
}

char *pp5_test_read_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    size_t cap = 4096, len = 0;
    char *buf = malloc(cap);
    size_t got;
    while ((got = fread(buf + len, 1, cap - len - 1, f)) > 0) {
        len += got;
        if (cap - len - 1 == 0) {
            cap *= 2;
            buf = realloc(buf, cap);
        }
    }
    fclose(f);
    buf[len] = '\0';
    return buf;
}

static int by_name(const void *a, const void *b)
{
    return strcmp(((const test_entry_t *)a)->name, ((const test_entry_t *)b)->name);
}

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef enum { OUTCOME_PASS, OUTCOME_FAIL, OUTCOME_SKIP } outcome_t;

/* What a test's process reports back: how it ended (0 returned, 1 a failed
 * REQUIRE, 2 SKIP) and its checks. */
typedef struct {
    int how;
    int checks_made, checks_failed;
    char skip_reason[sizeof skip_reason];
} test_result_t;

/* Runs the test in this process.  Kept apart from main() so that
 * setjmp/longjmp cannot clobber the runner's own locals. */
static void run_here(const test_entry_t *t, test_result_t *r)
{
    current_name = t->name;
    checks_made = checks_failed = 0;
    skip_reason[0] = '\0';
    int how = setjmp(test_exit);
    if (how == 0)
        t->fn();
    r->how = how;
    r->checks_made = checks_made;
    r->checks_failed = checks_failed;
    snprintf(r->skip_reason, sizeof r->skip_reason, "%s", skip_reason);
}

static bool write_all(int fd, const void *buf, size_t n)
{
    const char *p = buf;
    while (n > 0) {
        ssize_t w = write(fd, p, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return false;
        p += w;
        n -= (size_t)w;
    }
    return true;
}

static size_t read_all(int fd, void *buf, size_t n)
{
    char *p = buf;
    size_t got = 0;
    while (got < n) {
        ssize_t r = read(fd, p + got, n - got);
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0)
            break;
        got += (size_t)r;
    }
    return got;
}

static int test_timeout_s(void)
{
    const char *v = getenv("PP5_TEST_TIMEOUT_S");
    int s = v ? atoi(v) : 0;
    return s > 0 ? s : 600;
}

/* Runs the test in a child; false (and *why filled) when the child died
 * before reporting: a signal, an exit() from the code under test, a timeout. */
static bool run_in_child(const test_entry_t *t, test_result_t *r, char *why, size_t why_size)
{
    int fds[2];
    fflush(stdout);
    fflush(stderr);
    if (pipe(fds) != 0) {
        snprintf(why, why_size, "cannot create a pipe: %s", strerror(errno));
        return false;
    }
    pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]);
        close(fds[1]);
        snprintf(why, why_size, "cannot fork: %s", strerror(errno));
        return false;
    }
    if (pid == 0) {
        close(fds[0]);
        alarm((unsigned)test_timeout_s());   /* SIGALRM ends a hung test */
        test_result_t mine;
        run_here(t, &mine);
        fflush(stdout);
        fflush(stderr);
        _exit(write_all(fds[1], &mine, sizeof mine) ? 0 : 3);
    }
    close(fds[1]);
    size_t got = read_all(fds[0], r, sizeof *r);
    close(fds[0]);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        continue;
    if (got == sizeof *r && WIFEXITED(status) && WEXITSTATUS(status) == 0)
        return true;
    if (WIFSIGNALED(status)) {
        int sig = WTERMSIG(status);
        snprintf(why, why_size, "killed by signal %d (%s)%s", sig, strsignal(sig),
                 sig == SIGALRM ? ": it ran longer than PP5_TEST_TIMEOUT_S" : "");
    } else {
        snprintf(why, why_size, "its process exited with status %d before the test returned",
                 WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    }
    return false;
}

static outcome_t run_one(const test_entry_t *t)
{
    test_result_t r = {0};
    char why[256];
    double t0 = now_seconds();
    bool no_fork = getenv("PP5_TEST_NO_FORK") && strcmp(getenv("PP5_TEST_NO_FORK"), "1") == 0;
    if (no_fork) {
        run_here(t, &r);
    } else if (!run_in_child(t, &r, why, sizeof why)) {
        printf("FAIL %s (crashed: %s)\n", t->name, why);
        return OUTCOME_FAIL;
    }
    double ms = 1000.0 * (now_seconds() - t0);
    if (r.how == 2) {
        printf("SKIP %s: %s\n", t->name, r.skip_reason);
        return OUTCOME_SKIP;
    }
    if (r.checks_failed > 0 || r.how == 1) {
        printf("FAIL %s (%d of %d checks failed)\n", t->name, r.checks_failed, r.checks_made);
        return OUTCOME_FAIL;
    }
    if (r.checks_made == 0) {
        printf("FAIL %s (made no check: a test must assert something)\n", t->name);
        return OUTCOME_FAIL;
    }
    printf("ok   %s (%d checks, %.0f ms)\n", t->name, r.checks_made, ms);
    return OUTCOME_PASS;
}

static bool env_is_1(const char *name)
{
    const char *v = getenv(name);
    return v && strcmp(v, "1") == 0;
}

/* Tests that crash on purpose run only inside harness_isolates_crashing_tests;
 * the long soak runs (soak_*) only under `make soak` (PP5_SOAK=1). */
static bool hidden(const char *name)
{
    if (strncmp(name, "harness_selftest_", 17) == 0)
        return !env_is_1("PP5_TEST_SELFTEST");
    if (strncmp(name, "soak_", 5) == 0)
        return !env_is_1("PP5_SOAK");
    return false;
}

int main(int argc, char **argv)
{
    /* volatile: both live across the setjmp below (-Wclobbered under -Werror). */
    volatile bool list = false;
    volatile int first_filter = 1;
    if (argc > 1 && strcmp(argv[1], "--list") == 0) {
        list = true;
        first_filter = 2;
    }
    qsort(tests, (size_t)n_tests, sizeof tests[0], by_name);
    int passed = 0, failed = 0, skipped = 0;
    for (int i = 0; i < n_tests; i++) {
        if (hidden(tests[i].name))
            continue;
        bool selected = first_filter >= argc;
        for (int a = first_filter; a < argc; a++)
            if (strstr(tests[i].name, argv[a]))
                selected = true;
        if (!selected)
            continue;
        if (list) {
            printf("%s (%s)\n", tests[i].name, tests[i].file);
            continue;
        }
        switch (run_one(&tests[i])) {
        case OUTCOME_PASS: passed++; break;
        case OUTCOME_FAIL: failed++; break;
        case OUTCOME_SKIP: skipped++; break;
        }
        fflush(stdout);
    }
    if (list)
        return 0;
    printf("%d passed, %d failed, %d skipped\n", passed, failed, skipped);
    return failed ? 1 : 0;
}
