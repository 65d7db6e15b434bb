/* meshopt_peer.c: the meshoptimizer peer of `pp5 bench mesh --peers`.
 *   meshopt_peer IN.off TARGET_FACES REPS OUT.off
 * Reads a triangle OFF file (as pp5 writes them), runs meshopt_simplify to
 * TARGET_FACES faces REPS times (no error limit, borders free to slide along
 * themselves: the library's default), writes the result, and prints
 *   meshopt_faces N
 *   meshopt_cpu_ms MIN MEDIAN      (thread CPU time over the runs)
 *   meshopt_wall_ms MIN MEDIAN
 * Built and run only by render/peers/mesh_peers.sh (never by `make`). */
#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <meshoptimizer.h>

static double clock_ms(clockid_t id)
{
    struct timespec t;
    clock_gettime(id, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec / 1e6;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* A triangle OFF: "OFF", counts, positions, "3 a b c" faces. */
static int read_off(const char *path, float **pos, size_t *nv, unsigned **idx, size_t *nf)
{
    FILE *f = fopen(path, "r");
    char magic[8] = "";
    long v = 0, t = 0, e = 0;
    if (!f || fscanf(f, "%7s %ld %ld %ld", magic, &v, &t, &e) != 4 || strcmp(magic, "OFF") ||
        v <= 0 || t <= 0 || v > 50000000 || t > 50000000) {
        fprintf(stderr, "meshopt_peer: %s: not a triangle OFF file\n", path);
        if (f)
            fclose(f);
        return 1;
    }
    *pos = malloc(sizeof **pos * 3 * (size_t)v);
    *idx = malloc(sizeof **idx * 3 * (size_t)t);
    int ok = *pos && *idx;
    for (long i = 0; ok && i < v; i++) {
        double x, y, z;
        ok = fscanf(f, "%lf %lf %lf", &x, &y, &z) == 3;
        (*pos)[3 * i] = (float)x, (*pos)[3 * i + 1] = (float)y, (*pos)[3 * i + 2] = (float)z;
    }
    for (long i = 0; ok && i < t; i++) {
        long n, a, b, c;
        ok = fscanf(f, "%ld %ld %ld %ld", &n, &a, &b, &c) == 4 && n == 3 && a >= 0 && b >= 0 &&
             c >= 0 && a < v && b < v && c < v;
        (*idx)[3 * i] = (unsigned)a, (*idx)[3 * i + 1] = (unsigned)b;
        (*idx)[3 * i + 2] = (unsigned)c;
    }
    fclose(f);
    if (!ok) {
        fprintf(stderr, "meshopt_peer: %s: bad vertex or face line\n", path);
        return 1;
    }
    *nv = (size_t)v, *nf = (size_t)t;
    return 0;
}

/* Writes the used vertices only, renumbered in order of first use. */
static int write_off(const char *path, const float *pos, size_t nv, const unsigned *idx,
                     size_t nf)
{
    long *map = malloc(sizeof *map * nv);
    FILE *f = fopen(path, "w");
    if (!map || !f) {
        free(map);
        if (f)
            fclose(f);
        return 1;
    }
    size_t used = 0;
    for (size_t i = 0; i < nv; i++)
        map[i] = -1;
    for (size_t i = 0; i < 3 * nf; i++)
        if (map[idx[i]] < 0)
            map[idx[i]] = (long)used++;
    fprintf(f, "OFF\n%zu %zu 0\n", used, nf);
    long next = 0;
    for (size_t i = 0; i < 3 * nf; i++)
        if (map[idx[i]] == next) {
            const float *p = pos + 3 * idx[i];
            fprintf(f, "%.9g %.9g %.9g\n", p[0], p[1], p[2]);
            next++;
        }
    for (size_t i = 0; i < nf; i++)
        fprintf(f, "3 %ld %ld %ld\n", map[idx[3 * i]], map[idx[3 * i + 1]], map[idx[3 * i + 2]]);
    free(map);
    return fclose(f) != 0;
}

int main(int argc, char **argv)
{
    if (argc != 5) {
        fprintf(stderr, "usage: meshopt_peer IN.off TARGET_FACES REPS OUT.off\n");
        return 2;
    }
    float *pos;
    unsigned *idx;
    size_t nv, nf;
    if (read_off(argv[1], &pos, &nv, &idx, &nf))
        return 1;
    size_t target = (size_t)strtoul(argv[2], NULL, 10);
    int reps = atoi(argv[3]);
    if (reps < 1 || reps > 100)
        reps = 1;
    unsigned *out = malloc(sizeof *out * 3 * nf);
    double cpu[100], wall[100];
    size_t n_out = 0;
    for (int r = 0; r < reps && out; r++) {
        double c0 = clock_ms(CLOCK_THREAD_CPUTIME_ID), w0 = clock_ms(CLOCK_MONOTONIC);
        n_out = meshopt_simplify(out, idx, 3 * nf, pos, nv, 3 * sizeof(float), 3 * target,
                                 FLT_MAX, 0, NULL);
        cpu[r] = clock_ms(CLOCK_THREAD_CPUTIME_ID) - c0;
        wall[r] = clock_ms(CLOCK_MONOTONIC) - w0;
    }
    if (!out || write_off(argv[4], pos, nv, out, n_out / 3)) {
        fprintf(stderr, "meshopt_peer: cannot write %s\n", argv[4]);
        return 1;
    }
    qsort(cpu, (size_t)reps, sizeof *cpu, cmp_double);
    qsort(wall, (size_t)reps, sizeof *wall, cmp_double);
    printf("meshopt_faces %zu\n", n_out / 3);
    printf("meshopt_cpu_ms %.3f %.3f\n", cpu[0], cpu[reps / 2]);
    printf("meshopt_wall_ms %.3f %.3f\n", wall[0], wall[reps / 2]);
    free(pos), free(idx), free(out);
    return 0;
}
