/* test_docs.c: the documentation a new user reads: every command that `pp5
 * help` lists answers --help with a usage line and a worked example, and the
 * manual page emu/cli/pp5.1 has a section for each of them (and is clean roff when
 * groff is there to say so). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"

#define MAX_COMMANDS 64

/* The command names of `pp5 help`: the indented first words after
 * "commands:", up to the first line that is not indented (the exit codes and
 * the limits follow). */
static int help_commands(char names[][32])
{
    const char *dir = pp5_test_outdir();
    char out[1200];
    snprintf(out, sizeof out, "%s/help.txt", dir);
    if (pp5_test_run_cli("help", out, NULL) != 0)
        return -1;
    char *text = pp5_test_read_file(out);
    if (!text)
        return -1;
    int n = 0;
    char *list = strstr(text, "\ncommands:\n");
    for (char *line = list ? strtok(list + 11, "\n") : NULL; line && line[0] == ' ' &&
         n < MAX_COMMANDS; line = strtok(NULL, "\n"))
        if (sscanf(line, " %31s", names[n]) == 1)
            n++;
    free(text);
    return n;
}

/* The names the manual's COMMANDS section gives (".TP" then ".B NAME"),
 * with roff's \- read as -. */
static bool man_has(const char *man, const char *name)
{
    const char *p = strstr(man, "\n.SH COMMANDS\n");
    const char *end = p ? strstr(p + 1, "\n.SH ") : NULL;
    for (; p && (!end || p < end); p = strstr(p + 1, "\n.TP\n.B ")) {
        const char *s = strstr(p, "\n.TP\n.B ");
        if (!s || (end && s > end))
            break;
        s += 8;
        char word[64];
        size_t k = 0;
        for (; *s && *s != '\n' && *s != ' ' && k + 1 < sizeof word; s++) {
            if (s[0] == '\\' && s[1] == '-')
                s++;
            word[k++] = *s;
        }
        word[k] = '\0';
        if (strcmp(word, name) == 0)
            return true;
        p = s - 1;
    }
    return false;
}

TEST(docs_every_command_has_help_with_an_example_and_a_man_section)
{
    char names[MAX_COMMANDS][32];
    int n = help_commands(names);
    REQUIRE_MSG(n >= 12, "pp5 help lists %d commands", n);
    char *man = pp5_test_read_file("emu/cli/pp5.1");
    REQUIRE_MSG(man != NULL, "pp5.1 not found (the tests run from the repository's top)");
    const char *dir = pp5_test_outdir();
    for (int i = 0; i < n; i++) {
        CHECK_MSG(man_has(man, names[i]), "pp5.1 has no section for '%s'", names[i]);
        if (strcmp(names[i], "help") == 0)
            continue;
        char args[128], out[1200];
        snprintf(args, sizeof args, "%.31s --help", names[i]);
        snprintf(out, sizeof out, "%.1100s/%.31s.txt", dir, names[i]);
        int rc = pp5_test_run_cli(args, out, NULL);
        char *text = pp5_test_read_file(out);
        CHECK_MSG(rc == 0 && text && strstr(text, "usage: pp5 ") &&
                      (strstr(text, "Example") || strstr(text, "example")),
                  "pp5 %s --help: exit %d, %s", names[i], rc,
                  text && strstr(text, "usage: pp5 ") ? "no worked example" : "no usage line");
        free(text);
    }
    /* A made-up name is not found, so the check above can fail. */
    CHECK(!man_has(man, "no-such-command"));
    free(man);
}

TEST(docs_man_page_is_clean_roff)
{
    if (system("command -v groff >/dev/null 2>&1") != 0)
        SKIP("groff is not installed (Debian groff-base): cannot check pp5.1's roff");
    const char *dir = pp5_test_outdir();
    char cmd[1400], path[1200];
    snprintf(path, sizeof path, "%s/groff.txt", dir);
    snprintf(cmd, sizeof cmd, "groff -man -Tutf8 -ww -z emu/cli/pp5.1 >%s 2>&1", path);
    int rc = system(cmd);
    char *text = pp5_test_read_file(path);
    CHECK_MSG(rc == 0 && text && text[0] == '\0', "groff says: %s", text ? text : "(none)");
    free(text);
}
