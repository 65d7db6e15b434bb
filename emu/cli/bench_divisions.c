/* bench_divisions.c: PP5_BENCH divisions: each work division's emulated frames per second and ring megabytes per frame, cold and steady, on the projections' workload B, with the host time the four frames took. */
#include <stdio.h>
#include <time.h>

#include "registry.h"
#include "reproduce_projections.h"

/* Host wall clock: the last column only, never part of a result. */
static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static int bench_one(const proj_workload_t *w, const pp5_params_t *p, int size,
                     fw_division_t division, int lighting)
{
    proj_row_t row;
    double t0 = now_s();
    pp5_status_t st = proj_run(w, lighting, division, p, size, &row);
    double host = now_s() - t0;
    if (st != PP5_OK) {
        printf("   %s: failed: %s\n", fw_division_name(division), pp5_error_text());
        return 1;
    }
    printf("   %-12s %-8s  cold %7.1f ms %6.2f MB | steady %7.1f ms = %6.2f f/s %6.2f MB"
           "  GP busy %3.0f/%3.0f %% | host %.2f s for 4 frames\n",
           fw_division_name(division), lighting ? "specular" : "diffuse",
           row.cold.frame_time_s * 1e3, (double)row.cold.ring_bytes_total / 1e6,
           row.steady_s * 1e3, 1.0 / row.steady_s, row.steady_ring_bytes / 1e6,
           100 * row.steady_gp_mean, 100 * row.steady_gp_max, host);
    return 0;
}

static int bench_divisions(const pp5_bench_opts_t *opts)
{
    proj_workload_t w[2];
    int n = 0;
    pp5_status_t st = proj_load_workloads(w, &n, opts->quick);
    if (st != PP5_OK) {
        printf("   cannot load the workloads: %s\n", pp5_error_text());
        return 1;
    }
    const proj_workload_t *b = &w[n - 1];
    int size = opts->quick ? 48 : 210;
    pp5_params_t p;
    st = proj_machine("default", NULL, 0, &p);
    printf("divisions: the emulated machine (16 GPs, 16 renderers, 640 MB/s ring) per work\n"
           "division on workload %c (%s), %dx%d image; cold = frame 1, steady = mean of frames\n"
           "3-4 (the view held for diffuse, turned 2 degrees a frame for specular; the gaze\n"
           "moving 12 px a frame)\n", b->tag, b->volume.source, size, size);
    int rc = st == PP5_OK ? 0 : 1;
    static const fw_division_t divisions[] = {FW_DIVISION_IMAGE_BANDS, FW_DIVISION_RESIDENT,
                                              FW_DIVISION_OBJECT_SLABS};
    for (int lighting = 0; lighting < 2 && rc == 0; lighting++)
        for (size_t d = 0; d < sizeof divisions / sizeof divisions[0] && rc == 0; d++)
            rc = bench_one(b, &p, size, divisions[d], lighting);
    for (int i = 0; i < n; i++)
        proj_workload_free(&w[i]);
    return rc;
}

PP5_BENCH(divisions, "emulated frames/s and ring MB/frame of each work division", bench_divisions)
