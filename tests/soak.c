/* soak.c: /proc memory sampling for the soak runs (see soak.h). */
#include "soak.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

bool soak_read_memory(pid_t pid, long *rss_kb, long *hwm_kb)
{
    char path[64], line[256];
    snprintf(path, sizeof path, "/proc/%ld/status", (long)pid);
    FILE *f = fopen(path, "r");
    if (!f)
        return false;
    *rss_kb = *hwm_kb = -1;
    while (fgets(line, sizeof line, f)) {
        if (strncmp(line, "VmRSS:", 6) == 0)
            *rss_kb = strtol(line + 6, NULL, 10);
        else if (strncmp(line, "VmHWM:", 6) == 0)
            *hwm_kb = strtol(line + 6, NULL, 10);
    }
    fclose(f);
    return *rss_kb >= 0 && *hwm_kb >= 0;
}

pid_t soak_find_child(pid_t parent)
{
    DIR *d = opendir("/proc");
    if (!d)
        return -1;
    pid_t found = -1;
    struct dirent *e;
    while (found < 0 && (e = readdir(d)) != NULL) {
        char path[300], text[512];
        long pid = strtol(e->d_name, NULL, 10);
        if (pid <= 0)
            continue;
        snprintf(path, sizeof path, "/proc/%ld/stat", pid);
        FILE *f = fopen(path, "r");
        if (!f)
            continue;
        size_t n = fread(text, 1, sizeof text - 1, f);
        fclose(f);
        text[n] = '\0';
        /* "pid (comm) state ppid ...": comm may hold spaces, so parse after ')' */
        char *close = strrchr(text, ')');
        char state;
        long ppid;
        if (close && sscanf(close + 1, " %c %ld", &state, &ppid) == 2 && ppid == (long)parent)
            found = (pid_t)pid;
    }
    closedir(d);
    return found;
}

void soak_series_add(soak_series_t *ser, double t_s, long rss_kb, long hwm_kb)
{
    if (ser->n == ser->cap) {
        size_t cap = ser->cap ? 2 * ser->cap : 256;
        soak_sample_t *p = realloc(ser->s, cap * sizeof *p);
        if (!p)
            return;
        ser->s = p;
        ser->cap = cap;
    }
    ser->s[ser->n++] = (soak_sample_t){t_s, rss_kb, hwm_kb};
}

long soak_peak_rss(const soak_series_t *ser, double start_s, double end_s)
{
    long peak = -1;
    for (size_t i = 0; i < ser->n; i++)
        if (ser->s[i].t_s >= start_s && ser->s[i].t_s < end_s && ser->s[i].rss_kb > peak)
            peak = ser->s[i].rss_kb;
    return peak;
}

bool soak_series_write_csv(const soak_series_t *ser, const char *path)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return false;
    fprintf(f, "t_s,rss_kb,hwm_kb\n");
    for (size_t i = 0; i < ser->n; i++)
        fprintf(f, "%.1f,%ld,%ld\n", ser->s[i].t_s, ser->s[i].rss_kb, ser->s[i].hwm_kb);
    return fclose(f) == 0;
}

void soak_series_free(soak_series_t *ser)
{
    free(ser->s);
    ser->s = NULL;
    ser->n = ser->cap = 0;
}
