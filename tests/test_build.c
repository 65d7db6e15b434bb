/* test_build.c: the build names what it built.  A report and `pp5 version`
 * must carry the commit of the tree that was compiled (the Makefile writes it
 * into a generated file on every build), never a stale one. */
#include "harness.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* `git describe --always --dirty` of the working tree, or false outside git. */
static bool git_describe(char *out, size_t cap)
{
    FILE *p = popen("git describe --always --dirty 2>/dev/null", "r");
    if (!p)
        return false;
    bool ok = fgets(out, (int)cap, p) != NULL;
    if (pclose(p) != 0)
        ok = false;
    if (ok)
        out[strcspn(out, "\n")] = '\0';
    return ok && out[0];
}

TEST(build_version_and_report_name_the_commit_that_was_built)
{
    char commit[128];
    if (!git_describe(commit, sizeof commit))
        SKIP("not a git checkout: the version is \"unknown\" by design");
    const char *dir = pp5_test_outdir();
    char out[512], report[512], args[1200];
    snprintf(out, sizeof out, "%s/version.txt", dir);
    snprintf(report, sizeof report, "%s/r.json", dir);
    REQUIRE(pp5_test_run_cli("version", out, NULL) == 0);
    char *text = pp5_test_read_file(out);
    REQUIRE(text != NULL);
    char want[200];
    snprintf(want, sizeof want, "pp5 %s\n", commit);
    CHECK_MSG(strncmp(text, want, strlen(want)) == 0, "pp5 version says \"%.60s\", git says %s",
              text, commit);
    CHECK_MSG(strstr(text, "built with: NRRD=") != NULL, "pp5 version lists the features");
    free(text);

    snprintf(args, sizeof args, "test-pattern --report %s", report);
    REQUIRE(pp5_test_run_cli(args, NULL, NULL) == 0);
    char *json = pp5_test_read_file(report);
    REQUIRE(json != NULL);
    char key[200];
    snprintf(key, sizeof key, "\"pp5_version\": \"%s\"", commit);
    CHECK_MSG(strstr(json, key) != NULL, "the report names commit %s", commit);
    free(json);
}
