/* bench_mesh.c: `pp5 bench mesh`: the three simplifiers on the bunny to 50 %
 * and 1 % (one thread), their Hausdorff errors, and level extraction from the
 * collapse record per 10,000 faces.  Speed figures only; never fails. */
#include <math.h>
#include <stdio.h>
#include <time.h>

#include "registry.h"
#include "render/mesh/mesh.h"
#include "render/mesh/mesh_gen.h"
#include "render/mesh/mesh_hausdorff.h"
#include "render/mesh/mesh_simplify.h"
#include "render/scene.h"

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec / 1e6;
}

static int bench_mesh(const pp5_bench_opts_t *o)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/meshes/bun_zipper.ply.gz", scene_data_root());
    mesh_t in;
    if (mesh_load(path, &in) != PP5_OK) {
        printf("   bunny absent (%s); using a 200x100 torus\n", pp5_error_text());
        if (mesh_gen_torus(200, 100, 1.0, 0.3, &in) != PP5_OK)
            return 1;
    }
    printf("   %s: %d faces; one thread; min of %d runs (shared host)\n", in.source, in.n_faces,
           o->quick ? 1 : 3);
    static const double ratios[2] = {0.5, 0.01};
    static const mesh_method_t methods[3] = {MESH_QEM, MESH_SEED001, MESH_SEED003};
    double qem_ms[2] = {0, 0};
    for (int r = 0; r < 2; r++)
        for (int k = 0; k < 3; k++) {
            mesh_simplify_opts_t so;
            mesh_simplify_defaults(&so, methods[k]);
            so.target_faces = (int)(ratios[r] * in.n_faces + 0.5);
            double best = INFINITY;
            mesh_t out = {0};
            for (int rep = 0; rep < (o->quick ? 1 : 3); rep++) {
                mesh_simplify_stats_t st;
                mesh_free(&out);
                if (mesh_simplify(&in, &so, &out, NULL, &st) != PP5_OK)
                    return 1;
                best = fmin(best, st.ms);
                if (methods[k] == MESH_SEED003)
                    break;   /* slow: one run */
            }
            if (methods[k] == MESH_QEM)
                qem_ms[r] = best;
            mesh_distance_opts_t d_o;
            mesh_distance_defaults(&d_o);
            d_o.mean_samples = 50000;
            mesh_distance_t d;
            double h = mesh_distance(&in, &out, &d_o, &d) == PP5_OK
                           ? 100 * d.hausdorff / d.diagonal : NAN;
            printf("   to %4.0f %%  %-8s %8.1f ms  %6d faces  Hausdorff %.4f %%", 100 * ratios[r],
                   mesh_method_name(methods[k]), best, out.n_faces, h);
            if (methods[k] != MESH_QEM)
                printf("  %.2fx our QEM (goal <= 3x)", best / qem_ms[r]);
            printf("\n");
            mesh_free(&out);
        }
    mesh_simplify_opts_t so;
    mesh_simplify_defaults(&so, MESH_QEM);
    mesh_record_t rec;
    if (mesh_simplify(&in, &so, NULL, &rec, NULL) == PP5_OK) {
        static const double fr[3] = {0.5, 0.1, 0.01};
        for (int i = 0; i < 3; i++) {
            int level = mesh_record_level_for_faces(&rec, (int)(fr[i] * in.n_faces));
            double best = INFINITY;
            int faces = 0;
            for (int rep = 0; rep < 20; rep++) {
                mesh_t m;
                double t0 = now_ms();
                if (mesh_record_extract(&rec, level, &m) != PP5_OK)
                    break;
                best = fmin(best, now_ms() - t0);
                faces = m.n_faces;
                mesh_free(&m);
            }
            printf("   extract level with %6d faces: %.3f ms = %.3f ms per 10,000 faces "
                   "(goal < 1 ms)\n", faces, best, best * 1e4 / faces);
        }
        mesh_record_free(&rec);
    }
    if (o->peers)
        printf("   peers (meshoptimizer, CGAL): not built yet; see the closing note\n");
    mesh_free(&in);
    return 0;
}

PP5_BENCH(mesh, "mesh simplifiers on the bunny (50 % and 1 %), level extraction", bench_mesh)
