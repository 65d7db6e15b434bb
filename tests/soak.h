/* soak.h: memory watching for the soak runs (`make soak`, PP5_SOAK=1).
 *
 * A soak starts a long pp5 run in the background and samples the process's
 * resident memory from /proc/PID/status (VmRSS, and VmHWM, the peak so far)
 * every few seconds, so that a leak shows as a peak that keeps rising. */
#ifndef PP5_SOAK_H
#define PP5_SOAK_H

#include <stdbool.h>
#include <stddef.h>
#include <sys/types.h>

typedef struct {
    double t_s;            /* since the start of the watch */
    long rss_kb, hwm_kb;   /* VmRSS, VmHWM */
} soak_sample_t;

typedef struct {
    soak_sample_t *s;
    size_t n, cap;
} soak_series_t;

/* VmRSS and VmHWM of `pid` in kB; false when the process is gone. */
bool soak_read_memory(pid_t pid, long *rss_kb, long *hwm_kb);
/* The pid of a child of `parent` (the program umockdev-run or sh started), or -1. */
pid_t soak_find_child(pid_t parent);
void soak_series_add(soak_series_t *ser, double t_s, long rss_kb, long hwm_kb);
/* Peak VmRSS over samples with start_s <= t_s < end_s (-1 when none). */
long soak_peak_rss(const soak_series_t *ser, double start_s, double end_s);
/* Writes t_s,rss_kb,hwm_kb lines. */
bool soak_series_write_csv(const soak_series_t *ser, const char *path);
void soak_series_free(soak_series_t *ser);

#endif
