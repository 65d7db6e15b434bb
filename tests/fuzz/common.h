/* common.h: what the libFuzzer targets in tests/fuzz share.
 *
 * Loaders that take a path are fuzzed through their production entry point:
 * the input is written to a file in a private scratch folder (on /dev/shm
 * when it exists, so each run costs no disk I/O) and the loader reads it. */
#ifndef PP5_FUZZ_COMMON_H
#define PP5_FUZZ_COMMON_H

#include <stddef.h>
#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
/* In common.c for every target: lowers PP5_MAX_VOXELS to 2^20 (unless set),
 * so a header the loaders accept cannot make one run allocate gigabytes
 * (libFuzzer's -rss_limit_mb would report it as a crash).  The limit code is
 * the one production runs; only its value is smaller. */
int LLVMFuzzerInitialize(int *argc, char ***argv);

/* The scratch folder of this process (created on first use; removed at exit). */
const char *fuzz_dir(void);
/* Writes `size` bytes to fuzz_dir()/name and returns the path (a static
 * buffer per call site is not needed: the path is copied into `path`). */
void fuzz_write(const char *name, const uint8_t *data, size_t size, char *path, size_t path_size);
/* A malloc'd NUL-terminated copy of the input, as the slurping readers give
 * their parsers. */
char *fuzz_text(const uint8_t *data, size_t size);

#endif
