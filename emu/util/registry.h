/* registry.h: how modules add subcommands to `pp5`, entries to `pp5 bench`
 * and experiments to `pp5 reproduce` without editing a central list.
 *
 *   PP5_COMMAND(render, "render one frame with the native renderer", cmd_render)
 *   PP5_BENCH(pp_array, "PP-array emulation throughput", bench_pp_array)
 *   PP5_REPRODUCE(table1, "Levoy & Whitaker 1990 Table I", reproduce_table1)
 *
 * Registration runs before main() (a constructor); entries are listed sorted by
 * name, so the order never depends on link order. */
#ifndef PP5_REGISTRY_H
#define PP5_REGISTRY_H

#include <stdbool.h>

typedef int (*pp5_command_fn)(int argc, char **argv);

typedef struct {
    bool peers;      /* --peers: also run the optional peer comparisons */
    bool quick;      /* --quick: smaller sizes (used by the tests) */
} pp5_bench_opts_t;
typedef int (*pp5_bench_fn)(const pp5_bench_opts_t *opts);

/* Options every `pp5 reproduce NAME` experiment receives; argv holds the
 * experiment's own options after its name (argv[0] = NAME), for getopt. */
typedef struct {
    int threads;              /* host threads (default 1, like the paper's workstation) */
    int repeats;              /* timing: median of this many runs */
    const char *out_dir;      /* write every image into this folder, or NULL */
    int argc;
    char **argv;
} pp5_reproduce_opts_t;
typedef int (*pp5_reproduce_fn)(const pp5_reproduce_opts_t *opts);

typedef struct {
    const char *name;
    const char *summary;
    pp5_command_fn fn;
} pp5_command_t;

typedef struct {
    const char *name;
    const char *summary;
    pp5_reproduce_fn fn;
} pp5_reproduce_t;

typedef struct {
    const char *name;
    const char *summary;
    pp5_bench_fn fn;
} pp5_bench_t;

void pp5_register_command(const char *name, const char *summary, pp5_command_fn fn);
void pp5_register_bench(const char *name, const char *summary, pp5_bench_fn fn);
void pp5_register_reproduce(const char *name, const char *summary, pp5_reproduce_fn fn);
/* Sorted by name; *count receives the number of entries. */
const pp5_command_t *pp5_commands(int *count);
const pp5_bench_t *pp5_benches(int *count);
const pp5_reproduce_t *pp5_reproductions(int *count);
const pp5_command_t *pp5_find_command(const char *name);

#define PP5_COMMAND(name, summary, fn)                                        \
    __attribute__((constructor)) static void pp5_cmd_reg_##name(void)         \
    {                                                                         \
        pp5_register_command(#name, summary, fn);                             \
    }
/* For command names that are not C identifiers (e.g. "test-pattern"). */
#define PP5_COMMAND_NAMED(id, name, summary, fn)                              \
    __attribute__((constructor)) static void pp5_cmd_reg_##id(void)           \
    {                                                                         \
        pp5_register_command(name, summary, fn);                              \
    }
#define PP5_REPRODUCE(name, summary, fn)                                      \
    __attribute__((constructor)) static void pp5_repro_reg_##name(void)       \
    {                                                                         \
        pp5_register_reproduce(#name, summary, fn);                           \
    }
#define PP5_BENCH(name, summary, fn)                                          \
    __attribute__((constructor)) static void pp5_bench_reg_##name(void)       \
    {                                                                         \
        pp5_register_bench(#name, summary, fn);                               \
    }

#endif
