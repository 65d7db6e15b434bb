/* harness.c: the test runner (main) behind harness.h.
 *
 * usage: pp5-tests [--list] [SUBSTRING...]
 * Runs every registered test whose name contains one of the substrings. */
#include "harness.h"

#include <errno.h>
#include <math.h>
#include <setjmp.h>
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

/* Runs one test.  Kept apart from main() so that setjmp/longjmp cannot
 * clobber the runner's own locals. */
static outcome_t run_one(const test_entry_t *t)
{
    current_name = t->name;
    checks_made = checks_failed = 0;
    skip_reason[0] = '\0';
    double t0 = now_seconds();
    int how = setjmp(test_exit);
    if (how == 0)
        t->fn();
    double ms = 1000.0 * (now_seconds() - t0);
    if (how == 2) {
        printf("SKIP %s: %s\n", t->name, skip_reason);
        return OUTCOME_SKIP;
    }
    if (checks_failed > 0 || how == 1) {
        printf("FAIL %s (%d of %d checks failed)\n", t->name, checks_failed, checks_made);
        return OUTCOME_FAIL;
    }
    if (checks_made == 0) {
        printf("FAIL %s (made no check: a test must assert something)\n", t->name);
        return OUTCOME_FAIL;
    }
    printf("ok   %s (%d checks, %.0f ms)\n", t->name, checks_made, ms);
    return OUTCOME_PASS;
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
