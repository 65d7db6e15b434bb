/* test_harness.c: the runner itself.  The harness_selftest_* tests crash,
 * fail and hang on purpose; the runner hides them unless PP5_TEST_SELFTEST=1,
 * and harness_isolates_crashing_tests runs them in a second runner to show
 * that each is reported as its own failure while the others still run. */
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "harness.h"

TEST(harness_selftest_a_aborts)
{
    CHECK(true);
    abort();
}

TEST(harness_selftest_b_require_fails)
{
    REQUIRE(1 + 1 == 3);
    CHECK(false);    /* never reached: REQUIRE ended the test */
}

TEST(harness_selftest_c_hangs)
{
    CHECK(true);
    sleep(30);      /* the child runner sets PP5_TEST_TIMEOUT_S=1 */
}

TEST(harness_selftest_d_passes_after_the_others)
{
    CHECK(true);
}

static char *last_line(char *text)
{
    size_t n = strlen(text);
    while (n > 0 && text[n - 1] == '\n')
        text[--n] = '\0';
    char *nl = strrchr(text, '\n');
    return nl ? nl + 1 : text;
}

TEST(harness_isolates_crashing_tests)
{
    const char *dir = pp5_test_outdir();
    char out[1200], cmd[3000], exe[1024];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    REQUIRE(n > 0);
    exe[n] = '\0';
    snprintf(out, sizeof out, "%s/runner.txt", dir);
    snprintf(cmd, sizeof cmd, "PP5_TEST_SELFTEST=1 PP5_TEST_TIMEOUT_S=1 '%s' harness_selftest_ "
             ">'%s' 2>&1", exe, out);
    int rc = system(cmd);
    CHECK(WIFEXITED(rc) && WEXITSTATUS(rc) == 1);     /* failures make the runner fail */
    char *text = pp5_test_read_file(out);
    REQUIRE(text != NULL);
    CHECK(strstr(text, "FAIL harness_selftest_a_aborts (crashed: killed by signal 6") != NULL);
    CHECK(strstr(text, "FAIL harness_selftest_b_require_fails (1 of 1 checks failed)") != NULL);
    CHECK(strstr(text, "FAIL harness_selftest_c_hangs (crashed: killed by signal 14") != NULL);
    CHECK(strstr(text, "PP5_TEST_TIMEOUT_S") != NULL);
    CHECK(strstr(text, "ok   harness_selftest_d_passes_after_the_others") != NULL);
    CHECK_MSG(strcmp(last_line(text), "1 passed, 3 failed, 0 skipped") == 0, "last line '%s'",
              last_line(text));
    free(text);
}

TEST(harness_hides_the_selftests_by_default)
{
    const char *dir = pp5_test_outdir();
    char out[1200], cmd[3000], exe[1024];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    REQUIRE(n > 0);
    exe[n] = '\0';
    snprintf(out, sizeof out, "%s/list.txt", dir);
    snprintf(cmd, sizeof cmd, "env -u PP5_TEST_SELFTEST '%s' --list harness_ >'%s' 2>&1", exe,
             out);
    CHECK_EQ(system(cmd), 0);
    char *text = pp5_test_read_file(out);
    REQUIRE(text != NULL);
    CHECK(strstr(text, "harness_isolates_crashing_tests") != NULL);
    CHECK(strstr(text, "harness_selftest_") == NULL);
    free(text);
}
