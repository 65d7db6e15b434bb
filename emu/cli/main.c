/* main.c: the `pp5` program: git-style dispatch to the subcommands that the
 * modules register with PP5_COMMAND (see emu/util/registry.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "input_limits.h"
#include "registry.h"
#include "status.h"
#include "version.h"

static void print_usage(FILE *out)
{
    int n;
    const pp5_command_t *cmds = pp5_commands(&n);
    fprintf(out,
            "pp5 %s: a Pixel-Planes 5 emulator and its gaze-directed volume renderer\n\n"
            "usage: pp5 COMMAND [options]      (pp5 COMMAND --help for a command's options)\n"
            "       --quiet anywhere: no progress lines (they appear only on a terminal)\n\n"
            "built with: %s\n\n"
            "commands:\n",
            pp5_version, pp5_features);
    for (int i = 0; i < n; i++)
        fprintf(out, "  %-16s %s\n", cmds[i].name, cmds[i].summary);
    fprintf(out, "  %-16s %s\n", "help", "this list, or `pp5 help COMMAND` for one command");
    fprintf(out, "\nexit codes (every command):\n%s", pp5_exit_codes_help());
    fprintf(out, "\ninput limits (raise one with its environment variable, e.g. "
                 "PP5_MAX_VOXELS=2000000000 pp5 ...):\n");
    for (int i = 0; i < PP5_LIMIT_COUNT; i++) {
        pp5_limit_t l = (pp5_limit_t)i;
        fprintf(out, "  %-22s %12llu  %s\n", pp5_limit_name(l), (unsigned long long)pp5_limit(l),
                pp5_limit_what(l));
    }
}

/* --quiet anywhere on the line silences the progress lines of every command
 * (emu/util/progress.h reads PP5_QUIET); it is taken out before dispatch. */
static int take_quiet(int argc, char **argv)
{
    int k = 1;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--quiet") == 0)
            setenv("PP5_QUIET", "1", 1);
        else
            argv[k++] = argv[i];
    }
    argv[k] = NULL;
    return k;
}

int main(int argc, char **argv)
{
    argc = take_quiet(argc, argv);
    if (argc < 2) {
        print_usage(stderr);
        return PP5_EXIT_USAGE;
    }
    const char *name = argv[1];
    if (strcmp(name, "help") == 0 || strcmp(name, "--help") == 0 || strcmp(name, "-h") == 0) {
        if (argc >= 3 && strcmp(name, "help") == 0 && argv[2][0] != '-') {
            const pp5_command_t *c = pp5_find_command(argv[2]);
            if (!c) {
                fprintf(stderr, "pp5: no command '%s' (see pp5 help)\n", argv[2]);
                return PP5_EXIT_USAGE;
            }
            char *help_argv[] = {argv[2], "--help", NULL};
            return c->fn(2, help_argv);
        }
        print_usage(stdout);
        return 0;
    }
    if (strcmp(name, "--version") == 0 || strcmp(name, "version") == 0) {
        printf("pp5 %s\nbuilt with: %s\n", pp5_version, pp5_features);
        return 0;
    }
    const pp5_command_t *c = pp5_find_command(name);
    if (!c) {
        fprintf(stderr, "pp5: no command '%s'\n\n", name);
        print_usage(stderr);
        return PP5_EXIT_USAGE;
    }
    /* The command sees argv[0] = its own name, like a git subcommand. */
    return c->fn(argc - 1, argv + 1);
}
