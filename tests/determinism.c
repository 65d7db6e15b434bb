/* determinism.c: run-it-again comparisons for the determinism tests (see
 * determinism.h). */
#include "determinism.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "harness.h"

/* End of the JSON value starting at p (object, array, string or scalar). */
static const char *skip_value(const char *p, const char *end)
{
    int depth = 0;
    bool in_string = false;
    for (; p < end; p++) {
        char c = *p;
        if (in_string) {
            if (c == '\\')
                p++;
            else if (c == '"')
                in_string = false;
            if (!in_string && depth == 0)
                return p + 1;
            continue;
        }
        if (c == '"')
            in_string = true;
        else if (c == '{' || c == '[')
            depth++;
        else if (c == '}' || c == ']') {
            if (depth == 0)
                return p;          /* end of the enclosing container */
            if (--depth == 0)
                return p + 1;
        } else if (depth == 0 && (c == ',' || c == '\n'))
            return p;
    }
    return end;
}

size_t pp5_det_json_drop(char *json, size_t len, const char *key)
{
    char quoted[256];
    snprintf(quoted, sizeof quoted, "\"%s\"", key);
    size_t qlen = strlen(quoted);
    char *p = json, *end = json + len;
    while ((p = memmem(p, (size_t)(end - p), quoted, qlen)) != NULL) {
        char *colon = p + qlen;
        while (colon < end && (*colon == ' ' || *colon == '\n'))
            colon++;
        if (colon >= end || *colon != ':') {
            p += qlen;             /* the key text as a value, not a member */
            continue;
        }
        const char *v = colon + 1;
        while (v < end && (*v == ' ' || *v == '\n'))
            v++;
        char *stop = (char *)skip_value(v, end);
        /* Take the comma before the member (or the one after, for a first member). */
        char *start = p;
        char *back = p;
        while (back > json && (back[-1] == ' ' || back[-1] == '\n'))
            back--;
        if (back > json && back[-1] == ',')
            start = back - 1;
        else {
            while (stop < end && (*stop == ' ' || *stop == '\n'))
                stop++;
            if (stop < end && *stop == ',')
                stop++;
        }
        memmove(start, stop, (size_t)(end - stop));
        end -= stop - start;
        p = start;
    }
    *end = '\0';
    return (size_t)(end - json);
}

static char *read_whole(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    size_t cap = 1 << 16, n = 0, got;
    char *buf = malloc(cap + 1);
    while (buf && (got = fread(buf + n, 1, cap - n, f)) > 0) {
        n += got;
        if (n == cap) {
            cap *= 2;
            char *b = realloc(buf, cap + 1);
            if (!b) {
                free(buf);
                buf = NULL;
            }
            buf = b;
        }
    }
    fclose(f);
    if (buf)
        buf[n] = '\0';
    *len = n;
    return buf;
}

static bool ends_with(const char *s, const char *suffix)
{
    size_t a = strlen(s), b = strlen(suffix);
    return a >= b && strcmp(s + a - b, suffix) == 0;
}

/* Reads an output of run `k`, with the ignored members removed from JSON. */
static char *load_output(const char *dir, int k, const char *out, bool other_threads,
                         const char *const *thread_keys, size_t *len)
{
    char path[1400];
    snprintf(path, sizeof path, "%s/run%d/%s", dir, k, out);
    char *text = read_whole(path, len);
    if (!text || !ends_with(out, ".json"))
        return text;
    *len = pp5_det_json_drop(text, *len, "host_timing");
    for (int i = 0; other_threads && thread_keys && thread_keys[i]; i++)
        *len = pp5_det_json_drop(text, *len, thread_keys[i]);
    return text;
}

/* Runs one instance of the command in dir/work and moves its outputs to dir/runK. */
static bool run_once(const char *dir, const char *args, int threads, int k,
                     const char *const *outputs)
{
    char work[1400], cmd[4096], err[1400];
    snprintf(work, sizeof work, "%s/work", dir);
    mkdir(work, 0755);
    size_t n = 0;
    for (const char *a = args; *a && n + 1300 < sizeof cmd; a++) {
        if (*a == '@')
            n += (size_t)snprintf(cmd + n, sizeof cmd - n, "%s", work);
        else if (strncmp(a, "{T}", 3) == 0) {
            n += (size_t)snprintf(cmd + n, sizeof cmd - n, "%d", threads);
            a += 2;
        } else
            cmd[n++] = *a;
    }
    cmd[n] = '\0';
    snprintf(err, sizeof err, "%s/stderr%d.txt", dir, k);
    int rc = pp5_test_run_cli(cmd, NULL, err);
    CHECK_MSG(rc == 0, "pp5 %s exited %d (see %s)", cmd, rc, err);
    if (rc != 0)
        return false;
    char moved[1400];
    snprintf(moved, sizeof moved, "%s/run%d", dir, k);
    bool ok = rename(work, moved) == 0;
    CHECK_MSG(ok, "cannot move %s to %s", work, moved);
    return ok;
}

int pp5_det_runs(const char *dir, const char *name, const char *args,
                 const char *const *outputs, const int *threads, int n_threads,
                 const char *const *thread_keys)
{
    /* Each call gets its own folder: dir/NAME (spaces become '_'). */
    char own[1000];
    snprintf(own, sizeof own, "%s/%s", dir, name);
    for (char *c = own + strlen(dir) + 1; *c; c++)
        if (*c == ' ' || *c == '/')
            *c = '_';
    mkdir(own, 0755);
    dir = own;
    int runs = n_threads + 1, compared = 0;
    for (int k = 0; k < runs; k++)
        if (!run_once(dir, args, threads[k == 0 ? 0 : k - 1], k, outputs))
            return compared;
    for (int o = 0; outputs[o]; o++) {
        for (int k = 1; k < runs; k++) {
            int t = threads[k - 1];
            bool other = t != threads[0];    /* then thread_keys are dropped from both */
            size_t len0, len;
            char *first = load_output(dir, 0, outputs[o], other, thread_keys, &len0);
            char *again = load_output(dir, k, outputs[o], other, thread_keys, &len);
            CHECK_MSG(first && again, "%s: run 0 or run %d wrote no %s", name, k, outputs[o]);
            size_t at = 0;
            while (first && again && at < len && at < len0 && again[at] == first[at])
                at++;
            bool same = first && again && len == len0 && at == len;
            CHECK_MSG(same, "%s: %s differs between run 0 (%d threads) and run %d (%d threads) "
                      "at byte %zu of %zu", name, outputs[o], threads[0], k, t, at, len0);
            compared += same;
            free(first);
            free(again);
        }
    }
    return compared;
}
