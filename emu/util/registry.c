/* registry.c: the subcommand, benchmark and experiment tables filled by the
 * PP5_COMMAND, PP5_BENCH and PP5_REPRODUCE constructors (see registry.h). */
#include "registry.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_ENTRIES 128

/* One table of entries whose first member is the name (const char *), so a
 * single comparator sorts all three kinds. */
typedef struct {
    void *entries;
    size_t entry_size;
    int n;
    bool sorted;
    const char *what;
} table_t;

static pp5_command_t commands[MAX_ENTRIES];
static pp5_bench_t benches[MAX_ENTRIES];
static pp5_reproduce_t reproductions[MAX_ENTRIES];
static table_t command_table = {commands, sizeof commands[0], 0, false, "subcommands"};
static table_t bench_table = {benches, sizeof benches[0], 0, false, "benchmarks"};
static table_t reproduce_table = {reproductions, sizeof reproductions[0], 0, false, "experiments"};

static void *table_add(table_t *t)
{
    if (t->n == MAX_ENTRIES) {
        fprintf(stderr, "pp5: too many %s (raise MAX_ENTRIES)\n", t->what);
        abort();
    }
    t->sorted = false;
    return (char *)t->entries + (size_t)t->n++ * t->entry_size;
}

static int by_name(const void *a, const void *b)
{
    return strcmp(*(const char *const *)a, *(const char *const *)b);
}

static const void *table_sorted(table_t *t, int *count)
{
    if (!t->sorted) {
        qsort(t->entries, (size_t)t->n, t->entry_size, by_name);
        t->sorted = true;
    }
    *count = t->n;
    return t->entries;
}

void pp5_register_command(const char *name, const char *summary, pp5_command_fn fn)
{
    *(pp5_command_t *)table_add(&command_table) = (pp5_command_t){name, summary, fn};
}

void pp5_register_bench(const char *name, const char *summary, pp5_bench_fn fn)
{
    *(pp5_bench_t *)table_add(&bench_table) = (pp5_bench_t){name, summary, fn};
}

void pp5_register_reproduce(const char *name, const char *summary, pp5_reproduce_fn fn)
{
    *(pp5_reproduce_t *)table_add(&reproduce_table) = (pp5_reproduce_t){name, summary, fn};
}

const pp5_command_t *pp5_commands(int *count)
{
    return table_sorted(&command_table, count);
}

const pp5_bench_t *pp5_benches(int *count)
{
    return table_sorted(&bench_table, count);
}

const pp5_reproduce_t *pp5_reproductions(int *count)
{
    return table_sorted(&reproduce_table, count);
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
