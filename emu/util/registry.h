/* registry.h: how modules add subcommands to `pp5` and entries to `pp5 bench`
 * without editing a central list.
 *
 *   PP5_COMMAND(render, "render one frame with the native renderer", cmd_render)
 *   PP5_BENCH(pp_array, "PP-array emulation throughput", bench_pp_array)
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

typedef struct {
    const char *name;
    const char *summary;
    pp5_command_fn fn;
} pp5_command_t;

typedef struct {
    const char *name;
    const char *summary;
    pp5_bench_fn fn;
} pp5_bench_t;

void pp5_register_command(const char *name, const char *summary, pp5_command_fn fn);
void pp5_register_bench(const char *name, const char *summary, pp5_bench_fn fn);
/* Sorted by name; *count receives the number of entries. */
const pp5_command_t *pp5_commands(int *count);
const pp5_bench_t *pp5_benches(int *count);
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
#define PP5_BENCH(name, summary, fn)                                          \
    __attribute__((constructor)) static void pp5_bench_reg_##name(void)       \
    {                                                                         \
        pp5_register_bench(#name, summary, fn);                               \
    }

#endif
