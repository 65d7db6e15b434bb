/* bench_peers.c: the optional peer comparisons of `pp5 bench --peers`
 * (VTK's CPU ray caster and VolPack's shear-warp).  The helper programs
 * live in render/peers/ and are built and run here, not by the Makefile. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bench_render.h"

int render_peers_run(const char *dataset_path, int size, double ours_full_ms,
                     double ours_gaze_ms, double ours_mip_ms, float window_lo, float window_hi)
{
    if (!dataset_path) {
        printf("   peers: skipped (CThead absent; peers need the real data)\n");
        return 0;
    }
    if (access("render/peers/run_peers.sh", R_OK) != 0) {
        printf("   peers: render/peers/run_peers.sh not found (run from the repository root)\n");
        return 0;
    }
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "sh render/peers/run_peers.sh '%s' %d %.1f %.1f %.1f %g %g",
             dataset_path, size, ours_full_ms, ours_gaze_ms, ours_mip_ms, window_lo, window_hi);
    fflush(stdout);
    int rc = system(cmd);
    if (rc != 0)
        printf("   peers: helper exited with status %d (see above)\n", rc);
    return 0;
}
