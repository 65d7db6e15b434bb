/* registry.c: the subcommand and benchmark tables filled by PP5_COMMAND and
 * PP5_BENCH constructors (see registry.h). */
#include "registry.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_ENTRIES 128

static pp5_command_t commands[MAX_ENTRIES];
static int n_commands;
static bool commands_sorted;
static pp5_bench_t benches[MAX_ENTRIES];
static int n_benches;
static bool benches_sorted;

void pp5_register_command(const char *name, const char *summary, pp5_command_fn fn)
{
    if (n_commands == MAX_ENTRIES) {
        fprintf(stderr, "pp5: too many subcommands (raise MAX_ENTRIES)\n");
        abort();
    }
    commands[n_commands++] = (pp5_command_t){name, summary, fn};
    commands_sorted = false;
}

void pp5_register_bench(const char *name, const char *summary, pp5_bench_fn fn)
{
    if (n_benches == MAX_ENTRIES) {
        fprintf(stderr, "pp5: too many benchmarks (raise MAX_ENTRIES)\n");
        abort();
    }
    benches[n_benches++] = (pp5_bench_t){name, summary, fn};
    benches_sorted = false;
}

static int by_command_name(const void *a, const void *b)
{
    return strcmp(((const pp5_command_t *)a)->name, ((const pp5_command_t *)b)->name);
}

static int by_bench_name(const void *a, const void *b)
{
    return strcmp(((const pp5_bench_t *)a)->name, ((const pp5_bench_t *)b)->name);
}

const pp5_command_t *pp5_commands(int *count)
{
    if (!commands_sorted) {
        qsort(commands, (size_t)n_commands, sizeof commands[0], by_command_name);
        commands_sorted = true;
    }
    *count = n_commands;
    return commands;
}

const pp5_bench_t *pp5_benches(int *count)
{
    if (!benches_sorted) {
        qsort(benches, (size_t)n_benches, sizeof benches[0], by_bench_name);
        benches_sorted = true;
    }
    *count = n_benches;
    return benches;
}

const pp5_command_t *pp5_find_command(const char *name)
{
    int n;
    const pp5_command_t *c = pp5_commands(&n);
    for (int i = 0; i < n; i++)
        if (strcmp(c[i].name, name) == 0)
            return &c[i];
    return NULL;
}
